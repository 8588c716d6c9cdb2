//! `rtlab render`: the image.

use super::{default_output, RenderArgs};
use crate::error::{Error, Result};
use crate::output::{check_png, write_png};
use crate::sampling::aov::{render_aov, Aov};
use crate::sampling::render;
use serde_json::json;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Instant;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Scene file: native rtlab JSON or a CS1230 scenefile.
    pub scene: PathBuf,
    /// Output PNG (default: <scene name>.png in the current folder).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    #[command(flatten)]
    pub render: RenderArgs,
    /// Worker threads (default: all cores). The image is the same for any count.
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// Print ray counts and timings: text (default) on stderr, or json on stdout.
    #[arg(long, value_name = "text|json", num_args = 0..=1, default_missing_value = "text")]
    pub stats: Option<String>,
    /// No progress bar.
    #[arg(long, short)]
    pub quiet: bool,
    /// Write an arbitrary output variable instead of the colour: depth, normal, albedo,
    /// object-id, ambient, diffuse, specular, reflection, transmission, shadow, ray-depth, cost.
    #[arg(long, value_name = "NAME")]
    pub aov: Option<String>,
}

/// Runs `f` on a thread pool of `threads` workers (or rayon's default).
pub fn with_threads<T: Send>(threads: Option<usize>, f: impl FnOnce() -> T + Send) -> Result<T> {
    match threads {
        None => Ok(f()),
        Some(0) => Err(Error::arg("--threads", "must be at least 1")),
        Some(n) => {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| Error::arg("--threads", format!("cannot start {n} threads: {e}")))?;
            Ok(pool.install(f))
        }
    }
}

pub fn run(args: Args, stdout: &mut dyn std::io::Write) -> Result<()> {
    let stats_format = match args.stats.as_deref() {
        None => None,
        Some(f @ ("text" | "json")) => Some(f.to_string()),
        Some(other) => {
            return Err(Error::arg(
                "--stats",
                format!("unknown format \"{other}\" (expected text or json)"),
            ))
        }
    };
    let aov = match args.aov.as_deref() {
        None => None,
        Some(name) => Some(Aov::parse(name).ok_or_else(|| {
            Error::arg(
                "--aov",
                format!(
                    "unknown AOV \"{name}\" (expected one of: {})",
                    Aov::names().join(", ")
                ),
            )
        })?),
    };
    let suffix = aov.map(|a| format!("-{}", a.name())).unwrap_or_default();
    let out = default_output(&args.scene, args.output.clone(), &suffix);
    check_png(&out, "-o")?;
    if let Some(aov) = aov {
        if stats_format.is_some() {
            return Err(Error::arg(
                "--stats",
                "cannot be combined with --aov (the cost AOV shows the work per pixel)",
            ));
        }
        let scene = args.render.load(&args.scene)?;
        let img = with_threads(args.threads, || render_aov(&scene, &scene.render, aov))?;
        write_png(&out, &img.image)?;
        if !args.quiet {
            eprintln!("{}", img.legend);
            eprintln!("wrote {}", out.display());
        }
        return Ok(());
    }
    let t0 = Instant::now();
    let scene = args.render.load(&args.scene)?;
    args.render
        .check_memory(&scene, &args.scene, scene.render.spp)?;
    let load = t0.elapsed().as_secs_f64();
    // The accelerators (scene level and each mesh's) are built during load; build them once
    // more to time them for the stats.
    let build = if stats_format.is_some() {
        with_threads(args.threads, || {
            crate::accel::Accel::time_build(scene.render.accel, &scene.objects)
        })?
    } else {
        0.0
    };

    // Said before it happens: on a terminal, the first line warns of trees the budget will cut.
    if !args.quiet && std::io::stderr().is_terminal() {
        if let Some(w) = crate::trace::branching_warning(&scene, &scene.render) {
            let r = &scene.render;
            let worst = crate::trace::worst_case(&scene, r).rays_per_sample;
            let samples = scene.camera.width as f64 * scene.camera.height as f64 * r.spp as f64;
            eprintln!(
                "warning: {w} This render of {} samples can trace up to {:.1e} rays under the budget.",
                samples,
                samples * worst.min(r.max_rays as f64)
            );
        }
    }
    let bar = (!args.quiet && std::io::stderr().is_terminal()).then(|| {
        let pixels = scene.camera.width as u64 * scene.camera.height as u64;
        let bar = indicatif::ProgressBar::new(pixels);
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{spinner} rendering [{bar:40}] {percent}% of the pixels {elapsed} (eta {eta})",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        // The spinner and the clock move even while a slow pixel is still being traced.
        bar.enable_steady_tick(std::time::Duration::from_millis(200));
        bar
    });
    let result = with_threads(args.threads, || {
        render(&scene, &scene.render, stats_format.is_some(), bar.as_ref())
    })?;
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    crate::interrupt::check()?;
    if let Some((x, y, k)) = result.first_nan {
        eprintln!(
            "warning: sample {k} of pixel ({x}, {y}) came out as NaN or infinity and was counted as black \
             (reflective or transparent colours above 1 amplify light at every bounce and can overflow; otherwise this is a bug in rtlab). \
             Reproduce it with: rtlab explain {} --pixel {x},{y} --sample {k}",
            args.scene.display()
        );
    }
    if let Some((x, y, k)) = result.first_cut {
        eprintln!(
            "warning: the ray budget ({} rays per sample, render.max_rays or --max-rays) cut {} sample(s): \
             their ray trees were not traced to the end, so their pixels miss part of their light \
             (the first is sample {k} of pixel ({x}, {y})). See where it was cut with: {}",
            scene.render.max_rays,
            result.cut_samples,
            explain_command(&args, x, y, k)
        );
    }
    write_png(&out, &result.image.to_rgb8(scene.render.encoding))?;

    if let (Some(format), Some(stats)) = (stats_format, &result.stats) {
        let trace = result.trace_seconds;
        let mrays = stats.rays.total as f64 / trace.max(1e-9) / 1e6;
        if format == "json" {
            let v = json!({
                "rays": stats.rays,
                "tests": stats.tests,
                "bvh_nodes": stats.nodes,
                "seconds": {"load": load, "build": build, "trace": trace},
                "mrays_per_s": mrays,
                "width": scene.camera.width,
                "height": scene.camera.height,
                "spp": scene.render.spp,
                "output": out.display().to_string(),
            });
            super::emit(
                stdout,
                &(serde_json::to_string_pretty(&v).expect("serialisable")
                    + "
"),
            )?;
        } else {
            let r = stats.rays;
            eprintln!(
                "rays: {} camera, {} shadow, {} reflection, {} refraction, {} total\n\
                 intersection tests: {}, BVH nodes visited: {}\n\
                 time: load {:.3} s, build {:.3} s, trace {:.3} s ({:.2} Mrays/s)",
                r.camera,
                r.shadow,
                r.reflection,
                r.refraction,
                r.total,
                stats.tests,
                stats.nodes,
                load,
                build,
                trace,
                mrays
            );
        }
    }
    if !args.quiet {
        eprintln!("wrote {}", out.display());
    }
    Ok(())
}

/// The `rtlab explain` command that traces sample `k` of pixel (x, y) as this render did:
/// the scene and every option given that changes a pixel.
fn explain_command(args: &Args, x: u32, y: u32, k: u32) -> String {
    let r = &args.render;
    let mut c = format!("rtlab explain {} --pixel {x},{y}", args.scene.display());
    let mut opt = |name: &str, v: Option<String>| {
        if let Some(v) = v {
            c += &format!(" --{name} {v}");
        }
    };
    opt("sample", Some(k.to_string()));
    opt("width", r.width.map(|v| v.to_string()));
    opt("height", r.height.map(|v| v.to_string()));
    opt("spp", r.spp.map(|v| v.to_string()));
    opt("sampler", r.sampler.clone());
    opt("subsample", r.subsample.map(|v| v.to_string()));
    opt(
        "adaptive-threshold",
        r.adaptive_threshold.map(|v| v.to_string()),
    );
    opt("max-depth", r.max_depth.map(|v| v.to_string()));
    opt("seed", r.seed.map(|v| v.to_string()));
    opt("max-rays", r.max_rays.map(|v| v.to_string()));
    for (on, flag) in [
        (r.no_shadows, "--no-shadows"),
        (r.no_reflections, "--no-reflections"),
        (r.no_refractions, "--no-refractions"),
        (r.no_textures, "--no-textures"),
        (r.no_depth_of_field, "--no-depth-of-field"),
    ] {
        if on {
            c += " ";
            c += flag;
        }
    }
    c
}
