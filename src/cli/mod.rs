//! One module per subcommand, each an args struct and a `run`. Options shared by every
//! command that renders are one flattened group, [`RenderArgs`].

pub mod compare;
pub mod convert;
pub mod explain;
pub mod explain_text;
pub mod intersect;
pub mod intersect_solids;
pub mod lessons;
pub mod render;
pub mod samples;
pub mod schema;
pub mod serve;
pub mod steps;
pub mod validate;

use crate::accel::AccelKind;
use crate::error::{Error, Result};
use crate::scene::{check_size, Encoding, FilterKind, SamplerKind, Scene};
use clap::{Parser, Subcommand};
use glam::DVec3;
use std::io::Write;
use std::path::PathBuf;

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
    /// The lab in a browser: a local page to click pixels and see their rays (and an API).
    Serve(serve::Args),
}

/// Runs a parsed command line, writing what a command prints to `out` (stdout for the
/// binary; a file or a buffer when `rtlab lessons` runs commands in-process).
pub fn run(cli: Cli, out: &mut dyn Write) -> Result<()> {
    match cli.command {
        Command::Render(a) => render::run(a, out),
        Command::Explain(a) => explain::run(a, out),
        Command::Intersect(a) => intersect::run(a, out),
        Command::Validate(a) => validate::run(a, out),
        Command::Schema(a) => schema::run(a, out),
        Command::Convert(a) => convert::run(a, out),
        Command::Lessons(a) => lessons::run(a, out),
        Command::Steps(a) => steps::run(a, out),
        Command::Compare(a) => compare::run(a, out),
        Command::Samples(a) => samples::run(a, out),
        Command::Serve(a) => serve::run(a, out),
    }
}

/// Writes to a command's output, turning a failed write (a closed pipe) into an error.
pub fn emit(out: &mut dyn Write, text: &str) -> Result<()> {
    out.write_all(text.as_bytes())
        .map_err(|e| Error::Other(format!("cannot write the output: {e}")))
}

/// Options that change what a pixel is (shared by render, explain, steps, compare).
#[derive(Debug, Clone, Default, clap::Args)]
pub struct RenderArgs {
    /// Image width in pixels (overrides the scene).
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height in pixels (overrides the scene).
    #[arg(long)]
    pub height: Option<u32>,
    /// Samples per pixel.
    #[arg(long)]
    pub spp: Option<u32>,
    /// Sample placement: center, grid, corners, jittered, random, adaptive.
    #[arg(long, value_name = "KIND")]
    pub sampler: Option<String>,
    /// Reconstruction filter: box, tent, gaussian, mitchell.
    #[arg(long, value_name = "KIND")]
    pub filter: Option<String>,
    /// Subsampling: trace only every K-th pixel in x and y and let the (stretched) filter
    /// fill in the rest.
    #[arg(long, value_name = "K")]
    pub subsample: Option<u32>,
    /// Adaptive sampler: split a cell when its samples differ by more than this (default 0.1).
    #[arg(long, value_name = "T")]
    pub adaptive_threshold: Option<f64>,
    /// Maximum recursion depth (0: ray casting, no reflection or refraction).
    #[arg(long, value_name = "D")]
    pub max_depth: Option<u32>,
    /// Seed of every random choice (same seed, same image).
    #[arg(long, value_name = "S")]
    pub seed: Option<u64>,
    /// How colour becomes bytes: clamp (course reference images) or srgb.
    #[arg(long, value_name = "clamp|srgb")]
    pub encoding: Option<String>,
    /// Acceleration: linear (the lecture's loop over every object) or bvh.
    #[arg(long, value_name = "linear|bvh")]
    pub accel: Option<String>,
    /// Turn off shadow rays.
    #[arg(long)]
    pub no_shadows: bool,
    /// Turn off reflection rays.
    #[arg(long)]
    pub no_reflections: bool,
    /// Turn off refraction and transparency.
    #[arg(long)]
    pub no_refractions: bool,
    /// Ignore textures.
    #[arg(long)]
    pub no_textures: bool,
    /// Use a pinhole even if the camera has an aperture.
    #[arg(long)]
    pub no_depth_of_field: bool,
}

impl RenderArgs {
    /// Refuses, before anything is allocated, a render of `spp` samples per pixel that would
    /// not fit in memory; the message names the arguments when they set the size.
    pub fn check_memory(&self, scene: &Scene, path: &std::path::Path, spp: u32) -> Result<()> {
        let (w, h) = (scene.camera.width, scene.camera.height);
        crate::sampling::check_memory(w, h, spp).map_err(|m| {
            if self.width.is_some() || self.height.is_some() || self.spp.is_some() {
                Error::arg("--width/--height/--spp", m)
            } else {
                Error::input(path, "camera", m)
            }
        })
    }

    /// Loads the scene and applies these options to it.
    pub fn load(&self, path: &std::path::Path) -> Result<Scene> {
        // Cheap argument checks first, so a typo is reported before a long load.
        self.check()?;
        let mut scene = Scene::load(path)?;
        self.apply(&mut scene)?;
        Ok(scene)
    }

    fn check(&self) -> Result<()> {
        if let Some(s) = &self.sampler {
            SamplerKind::parse(s).ok_or_else(|| {
                Error::arg(
                    "--sampler",
                    format!(
                        "unknown sampler \"{s}\" (expected one of: {})",
                        SamplerKind::NAMES.join(", ")
                    ),
                )
            })?;
        }
        if let Some(s) = &self.filter {
            FilterKind::parse(s).ok_or_else(|| {
                Error::arg(
                    "--filter",
                    format!(
                        "unknown filter \"{s}\" (expected one of: {})",
                        FilterKind::NAMES.join(", ")
                    ),
                )
            })?;
        }
        if let Some(k) = self.subsample {
            if !(1..=64).contains(&k) {
                return Err(Error::arg(
                    "--subsample",
                    format!("{k} is out of range (1 traces every pixel; at most 64)"),
                ));
            }
        }
        if let Some(t) = self.adaptive_threshold {
            if !(t.is_finite() && t >= 0.0) {
                return Err(Error::arg(
                    "--adaptive-threshold",
                    format!("{t} is not a colour difference (expected a number ≥ 0, e.g. 0.1)"),
                ));
            }
        }
        if let Some(e) = &self.encoding {
            if e != "clamp" && e != "srgb" {
                return Err(Error::arg(
                    "--encoding",
                    format!("unknown encoding \"{e}\" (expected clamp or srgb)"),
                ));
            }
        }
        if let Some(a) = &self.accel {
            AccelKind::parse(a).ok_or_else(|| {
                Error::arg(
                    "--accel",
                    format!("unknown accelerator \"{a}\" (expected linear or bvh)"),
                )
            })?;
        }
        if let Some(d) = self.max_depth {
            if d > crate::scene::native_max_depth() {
                return Err(Error::arg(
                    "--max-depth",
                    format!(
                        "{d} is too deep (at most {})",
                        crate::scene::native_max_depth()
                    ),
                ));
            }
        }
        if let (Some(w), Some(h)) = (self.width, self.height) {
            check_size(w, h).map_err(|m| Error::arg("--width/--height", m))?;
        }
        Ok(())
    }

    pub fn apply(&self, scene: &mut Scene) -> Result<()> {
        let r = &mut scene.render;
        if let Some(s) = &self.sampler {
            r.sampler = SamplerKind::parse(s).expect("checked");
        }
        if let Some(s) = &self.filter {
            r.filter = FilterKind::parse(s).expect("checked");
        }
        if let Some(n) = self.spp {
            r.spp = n;
        }
        crate::sampling::validate_spp(r.sampler, r.spp).map_err(|m| Error::arg("--spp", m))?;
        if let Some(d) = self.max_depth {
            r.max_depth = d;
        }
        if let Some(k) = self.subsample {
            r.subsample = k;
        }
        if let Some(t) = self.adaptive_threshold {
            r.adaptive_threshold = t;
        }
        if let Some(s) = self.seed {
            r.seed = s;
        }
        if let Some(e) = &self.encoding {
            r.encoding = if e == "srgb" {
                Encoding::Srgb
            } else {
                Encoding::Clamp
            };
        }
        r.shadows &= !self.no_shadows;
        r.reflections &= !self.no_reflections;
        r.refractions &= !self.no_refractions;
        r.textures &= !self.no_textures;
        r.depth_of_field &= !self.no_depth_of_field;
        let (w, h) = (
            self.width.unwrap_or(scene.camera.width),
            self.height.unwrap_or(scene.camera.height),
        );
        check_size(w, h).map_err(|m| Error::arg("--width/--height", m))?;
        if (w, h) != (scene.camera.width, scene.camera.height) {
            scene.camera.update_size(w, h);
        }
        if let Some(a) = &self.accel {
            let kind = AccelKind::parse(a).expect("checked");
            if kind != scene.render.accel {
                scene.render.accel = kind;
                scene.rebuild_accel();
            }
        }
        Ok(())
    }
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
