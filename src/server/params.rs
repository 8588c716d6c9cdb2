//! A request's query string, split into the server's own parameters (`x`, `y`, `aov`, ...)
//! and the render options, which become command-line words (`spp=4` → `--spp=4`,
//! `no-shadows` → `--no-shadows`) for the CLI's own parser (the [`super::Loader`]).

use crate::error::{Error, Result};
use std::collections::BTreeMap;

/// Longest query string accepted (bytes); longer requests are refused before parsing.
pub const MAX_QUERY: usize = 4096;

#[derive(Debug, Clone, Default, PartialEq)]
pub struct Params {
    /// The endpoint's own parameters.
    pub own: BTreeMap<String, String>,
    /// Render options as command-line words, in the order given.
    pub words: Vec<String>,
}

/// Splits `query` (undecoded) into the endpoint's `own` keys and render-option words.
/// One of the endpoint's keys given twice, or a key that is not an option name, is refused.
pub fn parse(query: Option<&str>, own_keys: &[&str]) -> Result<Params> {
    let q = query.unwrap_or("");
    if q.len() > MAX_QUERY {
        return Err(Error::arg(
            "query",
            format!("{} bytes is too long (at most {MAX_QUERY})", q.len()),
        ));
    }
    let mut p = Params::default();
    let mut seen = std::collections::BTreeSet::new();
    for (k, v) in form_urlencoded::parse(q.as_bytes()) {
        let (k, v) = (k.into_owned(), v.into_owned());
        if !is_option_name(&k) {
            return Err(Error::arg(
                format!("\"{}\"", k.escape_debug()),
                "is not a parameter name (expected lower-case words joined by '-', e.g. spp or no-shadows)",
            ));
        }
        // The endpoint's own keys are given once; a render option given twice goes to the
        // CLI's parser, which refuses it as the command line does (unless it repeats, as
        // `--mistake a --mistake b`).
        if own_keys.contains(&k.as_str()) && !seen.insert(k.clone()) {
            return Err(Error::arg(&k, "is given twice"));
        }
        if own_keys.contains(&k.as_str()) {
            p.own.insert(k, v);
        } else if v.is_empty() {
            p.words.push(format!("--{k}"));
        } else {
            p.words.push(format!("--{k}={v}"));
        }
    }
    Ok(p)
}

fn is_option_name(k: &str) -> bool {
    let b = k.as_bytes();
    !b.is_empty()
        && b.len() <= 40
        && b[0].is_ascii_lowercase()
        && b.iter()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || *c == b'-')
}

impl Params {
    /// A required whole-number parameter of the endpoint.
    pub fn number(&self, key: &str, example: &str) -> Result<u32> {
        let v = self
            .own
            .get(key)
            .ok_or_else(|| Error::arg(key, format!("is missing (e.g. {example})")))?;
        v.parse().map_err(|_| {
            let digits = !v.is_empty() && v.bytes().all(|c| c.is_ascii_digit());
            Error::arg(
                key,
                match digits {
                    true => format!("{v} is not in 0..={}", u32::MAX),
                    false => format!("expected a whole number, found \"{}\"", v.escape_debug()),
                },
            )
        })
    }

    /// The pixel `x`, `y`, checked against the image as `explain --pixel X,Y` checks it.
    pub fn pixel(&self, width: u32, height: u32) -> Result<(u32, u32)> {
        let (x, y) = (
            self.own
                .get("x")
                .ok_or_else(|| Error::arg("x", "is missing (e.g. ?x=160&y=120)"))?,
            self.own
                .get("y")
                .ok_or_else(|| Error::arg("y", "is missing (e.g. ?x=160&y=120)"))?,
        );
        for (key, v) in [("x", x), ("y", y)] {
            if v.is_empty() || !v.bytes().all(|c| c.is_ascii_digit()) {
                return Err(Error::arg(
                    key,
                    format!("expected a whole number, found \"{}\"", v.escape_debug()),
                ));
            }
        }
        crate::report::explain::parse_pixel(&format!("{x},{y}"), width, height)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_and_own_keys() {
        let p = parse(
            Some("x=3&spp=4&no-shadows&sampler=jittered&y=%34"),
            &["x", "y"],
        )
        .unwrap();
        assert_eq!(p.words, ["--spp=4", "--no-shadows", "--sampler=jittered"]);
        assert_eq!(p.own["y"], "4");
        // A render option twice is for the CLI's parser to refuse; an own key twice is not.
        assert_eq!(
            parse(Some("spp=1&spp=2"), &[]).unwrap().words,
            ["--spp=1", "--spp=2"]
        );
        assert!(parse(Some("x=1&x=2"), &["x"]).is_err());
        assert!(parse(Some("=1"), &[]).is_err());
        assert!(parse(Some("--spp=1"), &[]).is_err());
        assert!(parse(Some("a%20b=1"), &[]).is_err());
    }
}
