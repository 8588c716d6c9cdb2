//! `rtlab samples`: a figure of where each sampler puts its samples in a 3×3 patch of pixels.

use crate::error::{Error, Result};
use crate::output::check_png;
use crate::scene::SamplerKind;
use std::path::PathBuf;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Samplers to draw, in order (default: all six).
    #[arg(long = "sampler", value_name = "KIND")]
    pub sampler: Vec<String>,
    /// Samples per pixel (grid, jittered, random; the adaptive sampler's finest grid).
    #[arg(long, value_name = "N", default_value_t = 16)]
    pub spp: u32,
    /// Seed of the random samplers.
    #[arg(long, value_name = "S", default_value_t = 0)]
    pub seed: u64,
    /// The figure (PNG).
    #[arg(short, long)]
    pub output: PathBuf,
}

pub fn run(args: Args, out: &mut dyn std::io::Write) -> Result<()> {
    check_png(&args.output, "-o")?;
    let names: Vec<String> = if args.sampler.is_empty() {
        SamplerKind::NAMES.iter().map(|s| s.to_string()).collect()
    } else {
        args.sampler.clone()
    };
    let mut runs = Vec::new();
    for n in &names {
        let kind = SamplerKind::parse(n).ok_or_else(|| {
            Error::arg(
                "--sampler",
                format!(
                    "unknown sampler \"{n}\" (expected one of: {})",
                    SamplerKind::NAMES.join(", ")
                ),
            )
        })?;
        let spp = match kind {
            SamplerKind::Center => 1,
            SamplerKind::Corners => 5,
            _ => args.spp,
        };
        crate::sampling::validate_spp(kind, spp).map_err(|m| Error::arg("--spp", m))?;
        runs.push((kind, spp));
    }
    crate::viz::samples::figure(&runs, args.seed).write_png(&args.output)?;
    super::emit(out, &format!("wrote {}\n", args.output.display()))
}
