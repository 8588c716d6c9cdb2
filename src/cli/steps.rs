//! `rtlab steps`: the image built up frame by frame, from ray casting to the final image.
//!
//! Output (DESIGN §3): in the folder `-o DIR`, frames `NNN-name.png` in order (each with its
//! caption in a strip under the image, or the bare image with `--no-captions`),
//! `index.json` = `[{"file": "001-visibility.png", "caption": "..."}, ...]` (version 1: add
//! keys, never rename), and with `--gif` an animated `steps.gif`. When `-o` names a `.png`
//! file instead, all frames (or those of `--frames`) go on one contact sheet.
//! `--pixel X,Y` makes a storyboard of one pixel instead: frame k adds the k-th ray of its
//! ray tree, drawn on the slice figure of [`crate::viz::slice`].
//! `--forward` draws forward against backward tracing instead (see [`crate::trace::forward`]).

use super::explain::{explain, parse_pixel};
use super::render::with_threads;
use super::RenderArgs;
use crate::error::{Error, Result};
use crate::output::{check_png, check_writable, png_bytes, write_atomic, write_png};
use crate::trace::forward::trace_photons;
use crate::viz::slice::SlicePlane;
use crate::viz::steps::{
    captioned, contact_sheet, file_name, gif, plan, render_frames, storyboard,
};
use std::path::{Path, PathBuf};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Scene file: native rtlab JSON or a CS1230 scenefile.
    pub scene: PathBuf,
    /// Output folder for the frames (created if missing), or a .png file for one contact
    /// sheet of the frames (or, with --forward, the forward/backward figure).
    #[arg(short, long, value_name = "DIR")]
    pub output: PathBuf,
    /// Also write steps.gif, an animation of the captioned frames.
    #[arg(long)]
    pub gif: bool,
    /// Write the bare images, without a caption strip (the final frame is then byte for byte
    /// the PNG `rtlab render` writes with the same options).
    #[arg(long)]
    pub no_captions: bool,
    /// Only these frames on the contact sheet (comma-separated names, e.g. ambient,diffuse).
    #[arg(long, value_name = "NAMES", value_delimiter = ',')]
    pub frames: Vec<String>,
    /// Columns of the contact sheet.
    #[arg(long, value_name = "N", default_value_t = 3)]
    pub columns: usize,
    /// Storyboard of one pixel instead: frame k draws the first k rays of its ray tree (its
    /// first sample) on a 2D slice of the scene.
    #[arg(long, value_name = "X,Y")]
    pub pixel: Option<String>,
    /// The slice of --pixel: camera (the camera ray and the camera's up vector) or bounce
    /// (the camera ray and its first reflection or refraction).
    #[arg(long, value_name = "camera|bounce", default_value = "camera")]
    pub plane: String,
    /// Forward against backward tracing: trace photons from the lights and count how many
    /// ever reach the film, next to the camera rays' image.
    #[arg(long)]
    pub forward: bool,
    /// Photons traced from the lights with --forward.
    #[arg(long, value_name = "N", default_value_t = 1_000_000)]
    pub photons: u64,
    /// Radius of the eye's pupil with --forward, in scene units (a pinhole would catch none).
    #[arg(long, value_name = "R", default_value_t = 0.1)]
    pub pupil: f64,
    #[command(flatten)]
    pub render: RenderArgs,
    /// Worker threads (default: all cores). The frames are the same for any count.
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// Print nothing but errors.
    #[arg(long, short)]
    pub quiet: bool,
}

/// One line of `index.json` (DESIGN §3), in the order of the frames.
#[derive(serde::Serialize)]
struct IndexEntry {
    file: String,
    caption: String,
}

fn is_png(p: &Path) -> bool {
    p.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("png"))
}

/// The most rays a `--pixel` storyboard draws (one frame each).
pub const MAX_STORYBOARD_RAYS: usize = 500;

pub fn run(args: Args, out: &mut dyn std::io::Write) -> Result<()> {
    let sheet = is_png(&args.output);
    if sheet {
        check_png(&args.output, "-o")?;
        if args.gif {
            return Err(Error::arg(
                "--gif",
                "needs -o to be a folder (the GIF is written next to the frames)",
            ));
        }
    } else if !args.frames.is_empty() {
        return Err(Error::arg(
            "--frames",
            "chooses the frames of a contact sheet: give -o a .png file name",
        ));
    } else if args.output.is_file() {
        return Err(Error::arg(
            "-o",
            format!(
                "{} is a file; give a folder for the frames, or a .png name for a contact sheet",
                args.output.display()
            ),
        ));
    }
    if args.columns == 0 {
        return Err(Error::arg("--columns", "must be at least 1"));
    }
    if args.forward && args.pixel.is_some() {
        return Err(Error::arg(
            "--forward",
            "cannot be combined with --pixel (forward tracing has no pixel to follow)",
        ));
    }
    let mut render = args.render.clone();
    render.quiet = args.quiet;
    let scene = render.load(&args.scene)?;
    if sheet {
        crate::output::check_not_read(&args.output, "-o")?; // a texture of the scene
    }
    args.render
        .check_memory(&scene, &args.scene, scene.render.spp)?;
    if args.forward {
        return forward(&args, &scene, out);
    }
    // Its visibility, depth and normal frames are AOVs, which keep more of each sample.
    args.render
        .check_aov_memory(&scene, &args.scene, &scene.render)?;
    let (frames, skipped) = match &args.pixel {
        Some(p) => {
            let (x, y) = parse_pixel(p, scene.camera.width, scene.camera.height)?;
            let plane = SlicePlane::parse(&args.plane).ok_or_else(|| {
                Error::arg(
                    "--plane",
                    format!(
                        "unknown plane \"{}\" (expected camera or bounce)",
                        args.plane
                    ),
                )
            })?;
            let e = explain(&scene, x, y);
            let sample = e
                .samples
                .iter()
                .find(|s| s.pixel == [x, y])
                .ok_or_else(|| Error::Other(format!("pixel ({x}, {y}) has no sample")))?;
            // Frame k redraws the first k rays: a long tree costs its square in drawing.
            let rays = crate::viz::steps::events(&sample.ray).len();
            if rays > MAX_STORYBOARD_RAYS {
                return Err(Error::arg(
                    "--pixel",
                    format!(
                        "pixel ({x}, {y})'s ray tree has {rays} rays, more than the {MAX_STORYBOARD_RAYS} a storyboard draws \
                         (one frame per ray): lower --max-depth, or cut the tree with --max-rays, or read it with rtlab explain"
                    ),
                ));
            }
            let frames = storyboard(&scene, &sample.ray, (x, y), plane, e.color)?;
            (frames, Vec::new())
        }
        None => {
            let (steps, mut skipped) = plan(&scene);
            let frames =
                with_threads(args.threads, || render_frames(&scene, &steps, &mut skipped))?;
            (frames, skipped)
        }
    };
    let mut text = String::new();

    if sheet {
        let img = contact_sheet(&frames, &args.frames, args.columns)?;
        write_png(&args.output, &img)?;
        text += &format!("wrote {}\n", args.output.display());
    } else {
        let dir = &args.output;
        // A folder made here is removed again if no frame is written.
        let folders = crate::output::NewFolders::create(dir)?;
        // Every file made in memory and every name checked before the first is written, so a
        // name that cannot be written (a folder in the way) leaves the folder as it was.
        let mut files = Vec::new();
        let mut index = Vec::new();
        for (i, f) in frames.iter().enumerate() {
            let name = file_name(i, f);
            let img = if args.no_captions {
                f.image.clone()
            } else {
                captioned(f, i + 1, frames.len())
            };
            let path = dir.join(&name);
            files.push((png_bytes(&img).map_err(|e| Error::io(&path, e))?, path));
            text += &format!("{name}  {}\n", f.caption);
            index.push(IndexEntry {
                file: name,
                caption: f.caption.clone(),
            });
        }
        let body = serde_json::to_string_pretty(&index).expect("serialisable") + "\n";
        files.push((body.into_bytes(), dir.join("index.json")));
        if args.gif {
            let path = dir.join("steps.gif");
            files.push((gif(&frames, &path)?, path));
            text += "steps.gif  all frames, animated\n";
        }
        for (_, path) in &files {
            check_writable(path, "-o")?;
        }
        remove_old_frames(dir)?;
        for (bytes, path) in &files {
            write_atomic(path, bytes)?;
        }
        folders.keep();
        text += &format!(
            "wrote {} frame{} to {}\n",
            frames.len(),
            if frames.len() == 1 { "" } else { "s" },
            dir.display()
        );
    }
    for s in &skipped {
        text += &format!("skipped {}: {}\n", s.name, s.reason);
    }
    if !args.quiet {
        super::emit(out, &text)?;
    }
    Ok(())
}

/// Removes the frames of an earlier run: the files its `index.json` lists (frame names only,
/// `NNN-name.png`), so the folder holds one sequence. Files the index does not list are
/// never touched, whatever their names.
fn remove_old_frames(dir: &Path) -> Result<()> {
    #[derive(serde::Deserialize)]
    struct Listed {
        file: String,
    }
    let Ok(text) = std::fs::read_to_string(dir.join("index.json")) else {
        return Ok(()); // no earlier run here (or not one rtlab can read): nothing to remove
    };
    let Ok(listed) = serde_json::from_str::<Vec<Listed>>(&text) else {
        return Ok(());
    };
    for Listed { file } in listed {
        let b = file.as_bytes();
        let frame = file.ends_with(".png")
            && b.len() > 8
            && b[..3].iter().all(u8::is_ascii_digit)
            && b[3] == b'-'
            && file[4..file.len() - 4]
                .bytes()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == b'-');
        let path = dir.join(&file);
        if frame && path.is_file() {
            std::fs::remove_file(&path).map_err(|err| Error::io(&path, err.to_string()))?;
        }
    }
    Ok(())
}

/// `--forward`: photons from the lights against camera rays from the eye.
fn forward(args: &Args, scene: &crate::scene::Scene, out: &mut dyn std::io::Write) -> Result<()> {
    let most = crate::scene::json::MAX_MAGNITUDE;
    if !(args.pupil > 0.0 && args.pupil <= most) {
        return Err(Error::arg(
            "--pupil",
            format!("must be a positive number up to {most:e}, as sizes in a scene"),
        ));
    }
    if args.photons == 0 || args.photons > 100_000_000 {
        return Err(Error::arg("--photons", "must be between 1 and 100000000"));
    }
    // A folder made for the figure is removed again if the figure is not written.
    let (path, folders) = if is_png(&args.output) {
        (args.output.clone(), None)
    } else {
        let folders = crate::output::NewFolders::create(&args.output)?;
        (args.output.join("forward.png"), Some(folders))
    };
    let settings = &scene.render;
    let (fwd, backward) = with_threads(args.threads, || {
        (
            trace_photons(
                scene,
                args.photons,
                args.pupil,
                settings.max_depth.max(1),
                settings.seed,
            ),
            crate::sampling::render(scene, settings, true, None),
        )
    })?;
    let rays = backward.stats.as_ref().map(|s| s.rays).unwrap_or_default();
    let img = backward.image.to_rgb8_for(settings);
    crate::viz::forward::figure(&fwd, &img, rays.camera, rays.total, args.pupil)
        .write_png(&path)?;
    if let Some(f) = folders {
        f.keep();
    }
    let n = &fwd.counts;
    let pct = |k: u64| 100.0 * k as f64 / n.photons.max(1) as f64;
    let text = format!(
        "forward: {} photons from {} light(s), eye pupil radius {}, at most {} bounces\n\
         \x20 hit a surface:            {:>10} ({:.4} %)\n\
         \x20 reached the film:         {:>10} ({:.4} %)\n\
         \x20 through the eye, off view:{:>10} ({:.4} %)\n\
         \x20 escaped to the sky:       {:>10} ({:.4} %)\n\
         \x20 absorbed:                 {:>10} ({:.4} %)\n\
         \x20 ray segments traced:      {:>10}\n\
         backward: {} camera rays ({}×{}, {} per pixel), every one reaches its pixel; {} rays in all\n\
         wrote {}\n",
        n.photons,
        scene.lights.len(),
        crate::error::number(args.pupil),
        settings.max_depth.max(1),
        n.hit_surface,
        pct(n.hit_surface),
        n.reached_film,
        pct(n.reached_film),
        n.outside_view,
        pct(n.outside_view),
        n.escaped,
        pct(n.escaped),
        n.absorbed,
        pct(n.absorbed),
        n.rays,
        rays.camera,
        scene.camera.width,
        scene.camera.height,
        settings.spp,
        rays.total,
        path.display()
    );
    if !args.quiet {
        super::emit(out, &text)?;
    }
    Ok(())
}
