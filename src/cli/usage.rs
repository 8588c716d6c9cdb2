//! clap's errors in rtlab's words: a value one of rtlab's parsers refused is one line,
//! "argument --flag: why", like every other bad input ([`refused_value`]); other usage
//! errors keep clap's own ([`usage_line`]).

/// "argument --passes: passes are numbered from 1" for a value that one of rtlab's parsers
/// (`value_parser = …`) refused, which clap would print over three lines around the same
/// words; `None` for every other error clap reports. The binary and `rtlab serve` print it.
pub fn refused_value(e: &clap::Error) -> Option<String> {
    use clap::error::{ContextKind, ContextValue, ErrorKind};
    if e.kind() != ErrorKind::ValueValidation {
        return None;
    }
    let Some(ContextValue::String(arg)) = e.get(ContextKind::InvalidArg) else {
        return None;
    };
    // "--passes <K>": the flag, without its value's name.
    let flag = arg.split(' ').next().unwrap_or(arg);
    let source = std::error::Error::source(e)?;
    let value = match e.get(ContextKind::InvalidValue) {
        Some(ContextValue::String(v)) => v.as_str(),
        _ => "",
    };
    // Rust's own number parsers do not say what they were given; rtlab's parsers do.
    let why = if let Some(int) = source.downcast_ref::<std::num::ParseIntError>() {
        match int.kind() {
            std::num::IntErrorKind::PosOverflow => format!("\"{value}\" is too large"),
            _ => format!("\"{value}\" is not a whole number"),
        }
    } else if source.is::<std::num::ParseFloatError>() {
        format!("\"{value}\" is not a number")
    } else {
        source.to_string()
    };
    Some(format!("argument {flag}: {why}"))
}

/// The line a usage error shows, without its "error: ": [`refused_value`]'s, or clap's
/// message on one line: its first paragraph joined ("the following required arguments were
/// not provided: `<SCENE>`") and its tip in brackets, without the usage and the pointer to
/// `--help` that clap adds around them.
pub fn usage_line(e: &clap::Error) -> String {
    refused_value(e).unwrap_or_else(|| one_line(&e.render().to_string()))
}

/// [`usage_line`] for the command line `words` (the program's arguments, without its name):
/// a word that begins with `-` right after an option that takes a value (`-o -x.png`) is
/// read by clap as more options, and the line says how to give it as the value instead
/// (`-o=-x.png`), unless it is a negative number, which [`usage_line`] already speaks of.
pub fn usage_line_in(e: &clap::Error, command: &clap::Command, words: &[String]) -> String {
    let line = usage_line(e);
    match value_like_an_option(e, command, words) {
        Some((option, word)) => {
            format!("{line} (if {word} is the value of {option}, write {option}={word})")
        }
        None => line,
    }
}

/// The option and the word of [`usage_line_in`]'s case, if the error is one.
fn value_like_an_option<'w>(
    e: &clap::Error,
    command: &clap::Command,
    words: &'w [String],
) -> Option<(&'w str, &'w str)> {
    use clap::error::{ContextKind, ContextValue, ErrorKind};
    if e.kind() != ErrorKind::UnknownArgument {
        return None;
    }
    let Some(ContextValue::String(unknown)) = e.get(ContextKind::InvalidArg) else {
        return None;
    };
    // The subcommand (the first word) names the options that can take the value.
    let sub = words
        .first()
        .and_then(|w| command.find_subcommand(w))
        .unwrap_or(command);
    // An option that takes values starting with '-' (`--origin -1,0,0`) already took it.
    let takes_value = |option: &str| {
        sub.get_arguments().any(|a| {
            let named = match option.strip_prefix("--") {
                Some(long) => a.get_long() == Some(long),
                None => {
                    let mut short = option.strip_prefix('-').unwrap_or("").chars();
                    matches!((short.next(), short.next()), (Some(c), None) if a.get_short() == Some(c))
                }
            };
            named && a.get_action().takes_values() && !a.is_allow_hyphen_values_set()
        })
    };
    // After `--` every word is a value, and clap says nothing of them as options.
    let end = words.iter().position(|w| w == "--").unwrap_or(words.len());
    words[..end].windows(2).find_map(|pair| {
        let (option, word) = (pair[0].as_str(), pair[1].as_str());
        let meant = word.starts_with('-')
            && word.starts_with(unknown.as_str())
            && word.parse::<f64>().is_err()
            && takes_value(option);
        meant.then_some((option, word))
    })
}

/// clap's rendered error on one line ([`usage_line`]).
fn one_line(text: &str) -> String {
    let text = text.trim_start_matches("error: ");
    let message: Vec<&str> = text
        .lines()
        .take_while(|l| !l.trim().is_empty())
        .map(str::trim)
        .collect();
    let message = match message.join(" ") {
        m if m.is_empty() => "bad option".to_string(),
        m => m,
    };
    let tip = text
        .lines()
        .map(str::trim)
        .find_map(|l| l.strip_prefix("tip: "));
    match tip {
        // clap's advice to write `-- -4` would make the value the scene's name: a negative
        // number after an option that takes none is said as such; an unknown `--flag`
        // needs no advice to pass it as a value.
        Some(t) if t.starts_with("to pass '") => match negative_number(t) {
            true => format!("{message}: no option here takes a negative number"),
            false => message,
        },
        Some(t) => format!("{message} (tip: {t})"),
        None => message,
    }
}

/// Does the tip "to pass 'X' as a value, …" name a number?
fn negative_number(tip: &str) -> bool {
    let value = tip
        .trim_start_matches("to pass '")
        .split('\'')
        .next()
        .unwrap_or("");
    value.parse::<f64>().is_ok()
}

#[cfg(test)]
mod tests {
    use super::{one_line, usage_line_in};

    /// A word that starts with '-' after an option taking a value gets the `=` advice; after
    /// a flag, or as a negative number, it does not.
    #[test]
    fn a_value_that_looks_like_an_option() {
        use clap::{Arg, ArgAction, Command};
        let command = Command::new("t").subcommand(
            Command::new("render")
                .arg(Arg::new("scene"))
                .arg(Arg::new("output").short('o').long("output"))
                .arg(Arg::new("quiet").long("quiet").action(ArgAction::SetTrue))
                .arg(Arg::new("spp").long("spp")),
        );
        let line = |words: &[&str]| {
            let words: Vec<String> = words.iter().map(|w| w.to_string()).collect();
            let all = std::iter::once("t".to_string()).chain(words.iter().cloned());
            let e = command.clone().try_get_matches_from(all).unwrap_err();
            usage_line_in(&e, &command, &words)
        };
        assert!(line(&["render", "s.json", "-o", "-x.png"])
            .ends_with("(if -x.png is the value of -o, write -o=-x.png)"));
        assert!(line(&["render", "s.json", "--output", "-x.png"])
            .ends_with("(if -x.png is the value of --output, write --output=-x.png)"));
        assert_eq!(
            line(&["render", "s.json", "--quiet", "-x.png"]),
            "unexpected argument '-x' found"
        );
        assert!(!line(&["render", "s.json", "--spp", "-4"]).contains("write"));
        // A value clap took already (an option that allows a leading '-') gets no advice,
        // nor do words after `--`.
        let command = command.clone().subcommand(
            Command::new("intersect")
                .arg(Arg::new("shape"))
                .arg(Arg::new("dir").long("dir").allow_hyphen_values(true)),
        );
        let words = ["intersect", "sphere", "--dir", "-1,", "-1,", "0"].map(String::from);
        let all = std::iter::once("t".to_string()).chain(words.iter().cloned());
        let e = command.clone().try_get_matches_from(all).unwrap_err();
        assert!(!usage_line_in(&e, &command, &words).contains("write"));
        let words = ["render", "--", "s.json", "-o", "-x.png"].map(String::from);
        let all = std::iter::once("t".to_string()).chain(words.iter().cloned());
        if let Err(e) = command.clone().try_get_matches_from(all) {
            assert!(!usage_line_in(&e, &command, &words).contains("write"));
        }
    }

    #[test]
    fn clap_errors_on_one_line() {
        assert_eq!(
            one_line("error: the following required arguments were not provided:\n  <SCENE>\n\nUsage: rtlab render <SCENE>\n\nFor more information, try '--help'.\n"),
            "the following required arguments were not provided: <SCENE>"
        );
        assert_eq!(
            one_line("error: unexpected argument '--sspp' found\n\n  tip: a similar argument exists: '--spp'\n\nUsage: rtlab render --spp <SPP> <SCENE>\n\nFor more information, try '--help'.\n"),
            "unexpected argument '--sspp' found (tip: a similar argument exists: '--spp')"
        );
        assert_eq!(
            one_line("error: unexpected argument '-4' found\n\n  tip: to pass '-4' as a value, use '-- -4'\n\nUsage: rtlab render [OPTIONS] <SCENE>\n"),
            "unexpected argument '-4' found: no option here takes a negative number"
        );
        assert_eq!(
            one_line("error: unexpected argument '-x' found\n\n  tip: to pass '-x' as a value, use '-- -x'\n"),
            "unexpected argument '-x' found"
        );
    }
}
