//! One module per subcommand, each an args struct and a `run`. Options shared by every
//! command that renders are one flattened group, [`RenderArgs`].

pub mod beam;
mod budget;
pub mod compare;
pub mod convert;
pub mod diff;
pub mod explain;
pub mod explain_text;
pub mod intersect;
mod intersect_args;
pub mod intersect_bundle;
pub mod intersect_solids;
pub mod lessons;
pub mod mistakes;
pub mod render;
mod render_args;
pub mod samples;
pub mod schema;
pub mod serve;
pub mod steps;
mod usage;
pub mod validate;

use crate::error::{Error, Result};
use clap::{Parser, Subcommand};
use glam::DVec3;
use std::io::Write;
use std::path::PathBuf;

pub use render_args::RenderArgs;
pub use usage::{refused_value, usage_line, usage_line_in};

#[derive(Debug, Parser)]
#[command(
    name = "rtlab",
    version,
    about = "A Whitted-style ray tracer that shows its work",
    propagate_version = true
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render a scene to a PNG image.
    Render(render::Args),
    /// Show every ray one pixel spawned, every intersection test and every lighting term.
    Explain(explain::Args),
    /// Intersect one ray with one canonical shape and show the working (and a figure).
    Intersect(intersect::Args),
    /// Heckbert and Hanrahan's beam tracing in the plane: one beam clipped against walls and
    /// mirrors nearest first (and a figure).
    Beam(beam::Args),
    /// Check a scene file and report the first problem (exit 0 when it is valid).
    Validate(validate::Args),
    /// Print the JSON Schema of the native scene format.
    Schema(schema::Args),
    /// Write the native rtlab equivalent of a CS1230 scenefile.
    Convert(convert::Args),
    /// Build or check the book's figures from lessons/*.json.
    Lessons(lessons::Args),
    /// The image built up step by step: visibility, normals, each lighting term, shadows,
    /// reflection depth by depth, refraction (frames, index.json, optional GIF).
    Steps(steps::Args),
    /// Render at several sampling settings side by side, against a high-spp reference.
    Compare(compare::Args),
    /// Draw where each sampler puts its samples in a few pixels.
    Samples(samples::Args),
    /// List the catalogue of deliberate mistakes (`--mistake NAME`): what the wrong code does
    /// and which formula of the lecture it breaks.
    Mistakes(mistakes::Args),
    /// Your image against the expected one: where it differs, which term and which mistake
    /// explain it (exit 0 same, 1 different, 2 error).
    Diff(diff::Args),
    /// The lab in a browser: a local page to click pixels and see their rays (and an API).
    Serve(serve::Args),
}

/// What a command concluded, when it is more than "done": `diff` says whether the images
/// agree. `main.rs` turns it into the exit status (0 same, 1 different), like `diff`/`cmp`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    Same,
    Different,
}

/// Runs a parsed command line, writing what a command prints to `out` (stdout for the
/// binary; a file or a buffer when `rtlab lessons` runs commands in-process).
pub fn run(cli: Cli, out: &mut dyn Write) -> Result<()> {
    run_outcome(cli, out).map(|_| ())
}

/// [`run`], keeping what the command concluded ([`Outcome`]) for the exit status.
pub fn run_outcome(cli: Cli, out: &mut dyn Write) -> Result<Outcome> {
    // A command's outputs are checked against the files it read, not those of the commands
    // run before it in this process.
    crate::input::forget_reads();
    match cli.command {
        Command::Diff(a) => diff::run(a, out),
        other => run_done(other, out).map(|()| Outcome::Same),
    }
}

/// The commands that conclude nothing but "done".
fn run_done(command: Command, out: &mut dyn Write) -> Result<()> {
    match command {
        Command::Render(a) => render::run(a, out),
        Command::Explain(a) => explain::run(a, out),
        Command::Intersect(a) => intersect::run(a, out),
        Command::Beam(a) => beam::run(a, out),
        Command::Validate(a) => validate::run(a, out),
        Command::Schema(a) => schema::run(a, out),
        Command::Convert(a) => convert::run(a, out),
        Command::Lessons(a) => lessons::run(a, out),
        Command::Steps(a) => steps::run(a, out),
        Command::Compare(a) => compare::run(a, out),
        Command::Samples(a) => samples::run(a, out),
        Command::Mistakes(a) => mistakes::run(a, out),
        Command::Diff(a) => diff::run(a, out).map(|_| ()),
        Command::Serve(a) => serve::run(a, out),
    }
}

/// Writes to a command's output, turning a failed write (a closed pipe) into an error.
pub fn emit(out: &mut dyn Write, text: &str) -> Result<()> {
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .map_err(|e| match e.kind() {
            std::io::ErrorKind::BrokenPipe => Error::OutputClosed,
            _ => Error::Other(format!("cannot write to standard output: {e}")),
        })
}

/// Parses "x,y" (or "x,y,z") lists of the command line.
pub fn parse_list(arg: &str, s: &str, n: usize) -> Result<Vec<f64>> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != n {
        return Err(Error::arg(
            arg,
            format!("expected {n} comma-separated numbers, found \"{s}\""),
        ));
    }
    parts
        .iter()
        .map(|p| {
            p.parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| {
                    Error::arg(arg, format!("\"{p}\" is not a finite number (in \"{s}\")"))
                })
        })
        .collect()
}

pub fn parse_vec3(arg: &str, s: &str) -> Result<DVec3> {
    let v = parse_list(arg, s, 3)?;
    Ok(DVec3::new(v[0], v[1], v[2]))
}

/// The output path: `-o` or `<scene stem>.png` in the current directory.
pub fn default_output(scene: &std::path::Path, out: Option<PathBuf>, suffix: &str) -> PathBuf {
    out.unwrap_or_else(|| {
        let stem = scene
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("render");
        PathBuf::from(format!("{stem}{suffix}.png"))
    })
}

pub use crate::report::shell_word;
