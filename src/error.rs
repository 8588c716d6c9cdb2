//! Typed errors of the library. The binary turns every one of them into one line on stderr and
//! exit status 2 (`main.rs`, the only place that knows about exit codes).

use std::fmt;
use std::path::{Path, PathBuf};

/// Everything that can go wrong, each variant saying *where*.
#[derive(Debug, Clone, PartialEq)]
pub enum Error {
    /// A scene or data file is invalid: `file`, a location inside it (JSON path such as
    /// `objects[2].radius`, or `line 3:14`), and what was expected.
    Input {
        file: PathBuf,
        at: String,
        msg: String,
    },
    /// A command-line argument is invalid (`--pixel`, `--spp`, ...).
    Arg { arg: String, msg: String },
    /// A file could not be read or written.
    Io { path: PathBuf, msg: String },
    /// Anything else worth telling the user in one sentence.
    Other(String),
    /// Standard output was closed by its reader (`rtlab explain … | head`): nothing more
    /// can be said, and nothing is wrong.
    OutputClosed,
}

pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    pub fn input(file: &Path, at: impl Into<String>, msg: impl Into<String>) -> Self {
        Error::Input {
            file: file.to_path_buf(),
            at: at.into(),
            msg: msg.into(),
        }
    }
    pub fn arg(arg: impl Into<String>, msg: impl Into<String>) -> Self {
        Error::Arg {
            arg: arg.into(),
            msg: msg.into(),
        }
    }
    pub fn io(path: &Path, err: impl fmt::Display) -> Self {
        Error::Io {
            path: path.to_path_buf(),
            msg: err.to_string(),
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Input { file, at, msg } if at.is_empty() => {
                write!(f, "{}: {msg}", file.display())
            }
            Error::Input { file, at, msg } => write!(f, "{}: {at}: {msg}", file.display()),
            Error::Arg { arg, msg } => write!(f, "argument {arg}: {msg}"),
            Error::Io { path, msg } => write!(f, "{}: {msg}", path.display()),
            Error::Other(msg) => f.write_str(msg),
            Error::OutputClosed => f.write_str("the output was closed by its reader"),
        }
    }
}

impl std::error::Error for Error {}

/// The closest of `candidates` to `word` (edit distance at most a third of its length, and at
/// least 1), for "did you mean" hints.
pub fn suggest<'a>(word: &str, candidates: &[&'a str]) -> Option<&'a str> {
    let limit = (word.len() / 3).max(2);
    candidates
        .iter()
        .map(|c| (edit_distance(&word.to_lowercase(), &c.to_lowercase()), *c))
        .filter(|(d, _)| *d <= limit)
        .min_by_key(|(d, _)| *d)
        .map(|(_, c)| c)
}

/// Levenshtein distance over chars (for "did you mean" suggestions).
pub(crate) fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let cur = row[j + 1];
            row[j + 1] = (prev + (ca != *cb) as usize).min(row[j] + 1).min(cur + 1);
            prev = cur;
        }
    }
    row[b.len()]
}

/// A number as a message shows it: as written for everyday sizes, in scientific notation
/// for the tiny and the huge (`1e-300`, not three hundred zeros).
pub fn number(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-4..1e15).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// `msg` with its control characters escaped (`\n` as `\\n`, an escape code as `\\u{1b}`):
/// an error is one line, and a value echoed back in it must not break the line or drive the
/// terminal.
pub fn printable(msg: &str) -> String {
    msg.chars()
        .map(|c| {
            if c.is_control() {
                c.escape_default().to_string()
            } else {
                c.to_string()
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn suggests_nearest_key() {
        assert_eq!(
            suggest("radus", &["radius", "center", "material"]),
            Some("radius")
        );
        assert_eq!(suggest("colour", &["color", "position"]), Some("color"));
        assert_eq!(suggest("zzzzzz", &["radius"]), None);
    }
}
