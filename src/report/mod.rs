//! Reports: the documents rtlab's faces show (the CLI prints them, the server serves them, the
//! figures draw them). Library types, so no face depends on another.

pub mod explain;
pub mod intersect;
pub mod mistakes;
