//! Reports: the documents rtlab's faces show (the CLI prints them, the server serves them, the
//! figures draw them). Library types, so no face depends on another.

pub mod explain;
pub mod intersect;
pub mod mistakes;

/// A word as a shell would need it written: as it is when it is plain, else single-quoted.
pub fn shell_word(s: &str) -> String {
    if !s.is_empty()
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_./,=+:".contains(c))
    {
        s.to_string()
    } else {
        format!("'{}'", s.replace('\'', "'\\''"))
    }
}
