//! `rtlab schema`: the JSON Schema of the native scene format.

use crate::error::Result;

/// The schema, kept next to the loader whose key lists it must match (a test checks this).
pub const SCHEMA: &str = include_str!("../scene/schema.json");

#[derive(Debug, clap::Args)]
pub struct Args {}

pub fn run(_args: Args, out: &mut dyn std::io::Write) -> Result<()> {
    super::emit(out, SCHEMA)
}
