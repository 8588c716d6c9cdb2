//! `rtlab diff`: your image against the expected one (rtlab's render of the scene, or
//! `--reference`), region by region, with the term and the mistake that explain each.
//! Exit status 0 when they agree, 1 when they differ, 2 on an error (like `diff` and `cmp`).
//! The output formats are documented where they are produced: [`crate::diff::report`].

use super::render::with_threads;
use super::{emit, Outcome, RenderArgs};
use crate::diff::{self, png, report, Options};
use crate::error::{Error, Result};
use crate::output::{check_not_input, check_png};
use std::path::{Path, PathBuf};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Scene file the image should show: native rtlab JSON or a CS1230 scenefile.
    pub scene: PathBuf,
    /// Your image (an 8-bit RGB PNG).
    pub yours: PathBuf,
    /// The expected image (e.g. the course's published reference) instead of rtlab's render
    /// of the scene; the scene still explains it.
    #[arg(long, value_name = "REF.png")]
    pub reference: Option<PathBuf>,
    #[command(flatten)]
    pub render: RenderArgs,
    /// A channel may differ by this many levels (0-255) and still agree.
    #[arg(long, value_name = "N", default_value_t = 2)]
    pub tolerance: u8,
    /// The images agree when at most this percentage of the pixels differ.
    #[arg(long, value_name = "P", default_value_t = 1.0)]
    pub max_percent: f64,
    /// Write the figure: expected | yours | difference with the regions numbered, and a table.
    #[arg(short, long, value_name = "FIG.png")]
    pub output: Option<PathBuf>,
    /// text (default) or json.
    #[arg(long, default_value = "text")]
    pub format: String,
    /// Worker threads (default: all cores). The result is the same for any count.
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
}

fn size_error(path: &Path, img: &image::RgbImage, what: &str, w: u32, h: u32) -> Error {
    Error::io(
        path,
        format!(
            "is {}×{} pixels, but {what} is {w}×{h}: the images must be the same size",
            img.width(),
            img.height()
        ),
    )
}

pub fn run(args: Args, out: &mut dyn std::io::Write) -> Result<Outcome> {
    if args.format != "text" && args.format != "json" {
        return Err(Error::arg(
            "--format",
            format!("unknown format \"{}\" (expected text or json)", args.format),
        ));
    }
    if !(args.max_percent.is_finite() && (0.0..=100.0).contains(&args.max_percent)) {
        return Err(Error::arg(
            "--max-percent",
            format!(
                "{} is not a percentage (expected 0 to 100)",
                args.max_percent
            ),
        ));
    }
    if let Some(o) = &args.output {
        check_png(o, "-o")?;
        let mut inputs = vec![
            (args.scene.as_path(), "the scene"),
            (&args.yours, "your image"),
        ];
        if let Some(r) = &args.reference {
            inputs.push((r, "the reference image"));
        }
        check_not_input(o, "-o", &inputs)?;
    }
    let yours = png::read_rgb8(&args.yours)?;
    let reference = args.reference.as_deref().map(png::read_rgb8).transpose()?;
    let scene = args.render.load(&args.scene)?;
    if let Some(o) = &args.output {
        crate::output::check_not_read(o, "-o")?; // a texture or mesh of the scene
    }
    let (w, h) = (scene.camera.width, scene.camera.height);
    let expected = match (&reference, &args.reference) {
        (Some(r), Some(path)) => {
            if r.dimensions() != (w, h) {
                return Err(size_error(path, r, "the scene's image", w, h));
            }
            if yours.dimensions() != r.dimensions() {
                return Err(size_error(
                    &args.yours,
                    &yours,
                    &format!("the reference {}", path.display()),
                    w,
                    h,
                ));
            }
            r.clone()
        }
        _ => {
            if yours.dimensions() != (w, h) {
                return Err(size_error(
                    &args.yours,
                    &yours,
                    &format!("the image of {}", args.scene.display()),
                    w,
                    h,
                ));
            }
            args.render
                .check_memory(&scene, &args.scene, scene.render.spp)?;
            let r = with_threads(args.threads, || {
                crate::sampling::render(&scene, &scene.render, false, None)
            })?;
            crate::interrupt::check()?;
            r.image.to_rgb8_for(&scene.render)
        }
    };
    let opts = Options {
        tolerance: args.tolerance,
        max_percent: args.max_percent,
        explain: format!(
            "rtlab explain {}",
            super::shell_word(&args.scene.display().to_string())
        ),
        explain_flags: args.render.to_flags(),
        ..Options::default()
    };
    let rep = with_threads(args.threads, || {
        diff::diff(&scene, &expected, &yours, &opts)
    })??;
    if let Some(o) = &args.output {
        crate::viz::diff::figure(&scene, &expected, &yours, &rep).write_png(o)?;
    }
    let text = if args.format == "json" {
        serde_json::to_string_pretty(&report::to_json(&scene, &rep)).expect("serialisable") + "\n"
    } else {
        let mut t = report::to_text(&scene, &rep, args.max_percent);
        if let Some(o) = &args.output {
            t += &format!("wrote {}\n", o.display());
        }
        t
    };
    emit(out, &text)?;
    Ok(if rep.same {
        Outcome::Same
    } else {
        Outcome::Different
    })
}
