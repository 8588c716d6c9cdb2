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

/// The line a usage error shows, without its "error: ": [`refused_value`]'s, or the first of
/// clap's.
pub fn usage_line(e: &clap::Error) -> String {
    refused_value(e).unwrap_or_else(|| {
        let text = e.render().to_string();
        let line = text.lines().next().unwrap_or("bad option");
        line.trim_start_matches("error: ").to_string()
    })
}
