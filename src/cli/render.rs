//! `rtlab render`: the image.

use super::budget::{aov_fits, budgeted, pass_of, reached_lines};
use super::{default_output, RenderArgs};
use crate::accel::Traversal;
use crate::error::{Error, Result};
use crate::output::{check_not_input, check_png, write_png};
use crate::sampling::aov::{render_aov, Aov};
use crate::sampling::progressive::{colour_pass, pass_settings};
use crate::sampling::render;
use serde_json::json;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Instant;

// The doc comments are `--help` text: `<scene name>` is a placeholder, not an HTML tag.
#[allow(rustdoc::invalid_html_tags)]
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
    /// Print less: no progress bar, no warnings about the scene file, no line per pass, no
    /// AOV legend and no "wrote" line (errors, --stats and the pass a budget reached still
    /// print).
    #[arg(long, short)]
    pub quiet: bool,
    /// Write an arbitrary output variable instead of the colour: depth, normal, albedo,
    /// object-id, ambient, diffuse, specular, reflection, transmission, shadow, ray-depth, cost,
    /// spp.
    #[arg(long, value_name = "NAME")]
    pub aov: Option<String>,
    /// Progressive rendering: write pass K of the sequence (1: subsampled preview, 4 times
    /// the scene's subsampling, at most 64; 2: the scene's settings; k > 2: 4^(k-2) times its
    /// samples per pixel, and under center and corners a grid of 4^(k-2)). Only pass K is
    /// traced. With --time-budget: stop after pass K at the latest.
    #[arg(long, value_name = "K", allow_negative_numbers = true, value_parser = crate::sampling::progressive::parse_pass)]
    pub passes: Option<u32>,
    /// Progressive rendering for about this long: passes 1, 2, 3, ... until the time is
    /// spent (a pass after the first is cut off within a few rays; pass 1 always
    /// completes, however long it takes); writes the last complete pass (the same bytes as
    /// --passes K, K printed).
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true, value_parser = crate::sampling::progressive::parse_seconds)]
    pub time_budget: Option<f64>,
}

/// The most threads `--threads` may ask for: far more than any processor has cores, and few
/// enough to start at once (thousands take seconds to start, a hundred thousand minutes).
const MAX_THREADS: usize = 1024;

/// Runs `f` on a thread pool of `threads` workers (or rayon's default).
pub fn with_threads<T: Send>(threads: Option<usize>, f: impl FnOnce() -> T + Send) -> Result<T> {
    Ok(Threads::start(threads)?.run(f))
}

/// The threads a command runs on, started once: `--threads N` workers, or rayon's own pool.
pub struct Threads(Option<rayon::ThreadPool>);

impl Threads {
    /// Starts the workers now (rayon's own pool too, which otherwise starts with the first
    /// parallel work and would be timed as part of it).
    pub fn start(threads: Option<usize>) -> Result<Threads> {
        match threads {
            None => {
                rayon::current_num_threads();
                Ok(Threads(None))
            }
            Some(0) => Err(Error::arg("--threads", "must be at least 1")),
            Some(n) if n > MAX_THREADS => Err(Error::arg(
                "--threads",
                format!("{n} is more than {MAX_THREADS}, the most a render may start"),
            )),
            Some(n) => rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map(|pool| Threads(Some(pool)))
                .map_err(|e| Error::arg("--threads", format!("cannot start {n} threads: {e}"))),
        }
    }

    /// Runs `f` on these threads.
    pub fn run<T: Send>(&self, f: impl FnOnce() -> T + Send) -> T {
        match &self.0 {
            Some(pool) => pool.install(f),
            None => f(),
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
        Some(name) => Some(Aov::parse_arg(name)?),
    };
    let suffix = aov.map(|a| format!("-{}", a.name())).unwrap_or_default();
    if let Some(o) = &args.output {
        check_png(o, "-o")?;
    }
    if aov.is_some() && stats_format.is_some() {
        return Err(Error::arg(
            "--stats",
            "cannot be combined with --aov (the cost AOV shows the work per pixel)",
        ));
    }
    let threads = Threads::start(args.threads)?;
    let t0 = Instant::now();
    let mut render_args = args.render.clone();
    render_args.quiet = args.quiet;
    // Loading builds the meshes' BVHs: on the render's threads too.
    let loaded = threads.run(|| render_args.load_full(&args.scene))?;
    // A course ini names its output (created with its folders, as the course's program
    // does, and removed again if nothing is written); -o wins.
    let mut folders = None;
    let out = match (&args.output, &loaded.output) {
        (None, Some(o)) => {
            // An AOV goes beside it: unit_cone-normal.png.
            let o = if suffix.is_empty() {
                o.clone()
            } else {
                let stem = o.file_stem().and_then(|s| s.to_str()).unwrap_or("render");
                o.with_file_name(format!("{stem}{suffix}.png"))
            };
            if let Some(dir) = o.parent().filter(|d| !d.as_os_str().is_empty()) {
                folders = Some(crate::output::NewFolders::create(dir)?);
            }
            check_png(&o, "the ini's [IO] output")?;
            o
        }
        _ => default_output(&args.scene, args.output.clone(), &suffix),
    };
    if args.output.is_none() && loaded.output.is_none() {
        check_png(&out, "-o")?;
    }
    let out_arg = match (&args.output, &loaded.output) {
        (None, Some(_)) => "the ini's [IO] output",
        _ => "-o",
    };
    check_not_input(&out, out_arg, &[(&args.scene, "the scene")])?;
    crate::output::check_not_read(&out, out_arg)?; // a texture or mesh of the scene
    render_args.warn(&loaded.warnings);
    let mut scene = loaded.scene;
    // What a budget reached (`reached_lines`), said once the image is written.
    let mut said = Vec::new();
    if let Some(aov) = aov {
        let img = if let Some(budget) = args.time_budget {
            // As for the colour: pass 1 must fit (it always completes), and so must pass K.
            if let Some(k) = args.passes {
                let pass = pass_of(&scene, k)?;
                args.render.check_aov_memory(&scene, &args.scene, &pass)?;
            }
            let (w, h) = (scene.camera.width, scene.camera.height);
            pass_settings(&scene.render, w, h, 1)
                .and_then(|p| aov_fits(&scene, &p).map_err(|m| format!("pass 1: {m}")))
                .map_err(|m| Error::arg("--time-budget", m))?;
            let render = |settings: &crate::scene::RenderSettings,
                          _: &(dyn Fn() -> bool + Sync)| {
                // A pass too big for an AOV's memory ends the sequence, as the colour's does.
                let fits = aov_fits(&scene, settings).is_ok();
                fits.then(|| render_aov(&scene, settings, aov)).flatten()
            };
            let pass =
                threads.run(|| budgeted(&scene, budget, args.passes, args.quiet, None, render));
            crate::interrupt::check()?;
            let pass = pass.ok_or_else(|| Error::Other("no pass was completed".into()))?;
            said = reached_lines(&scene, &pass, args.passes, Some(aov));
            pass.output
        } else {
            let settings = match args.passes {
                Some(k) => pass_of(&scene, k)?,
                None => scene.render.clone(),
            };
            args.render
                .check_aov_memory(&scene, &args.scene, &settings)?;
            let img = threads.run(|| render_aov(&scene, &settings, aov));
            crate::interrupt::check()?; // the only way an AOV here stops before it is complete
            img.ok_or_else(|| Error::Other("the AOV render was stopped".into()))?
        };
        write_png(&out, &img.image)?;
        if let Some(f) = folders {
            f.keep();
        }
        for line in &said {
            eprintln!("{line}");
        }
        if !args.quiet {
            eprintln!("{}", img.legend);
            eprintln!("wrote {}", out.display());
        }
        return Ok(());
    }
    // What is rendered must fit: the scene's settings; or pass K (`pass_of` checks it), which
    // must exist, also as a budget's last pass (a cap it could never reach would be silently
    // the same as no cap); under a budget, pass 1, which always completes (a later pass that
    // would not fit ends the sequence).
    if args.passes.is_none() && args.time_budget.is_none() {
        args.render
            .check_memory(&scene, &args.scene, scene.render.spp)?;
    }
    if args.time_budget.is_some() {
        let (w, h) = (scene.camera.width, scene.camera.height);
        pass_settings(&scene.render, w, h, 1).map_err(|m| Error::arg("--time-budget", m))?;
    }
    if let Some(k) = args.passes {
        let pass = pass_of(&scene, k)?;
        if args.time_budget.is_none() {
            scene.render = pass;
        }
    }
    let load = t0.elapsed().as_secs_f64();
    // The accelerators (scene level and each mesh's) were built, and timed, during load.
    let build = scene.accel.build_seconds(&scene.objects);

    // Said before it happens: on a terminal, the first line warns of trees the budget will cut.
    if !args.quiet && std::io::stderr().is_terminal() {
        if let Some(w) = crate::trace::branching_warning(&scene, &scene.render) {
            let r = &scene.render;
            let worst = crate::trace::worst_case(&scene, r).rays_per_sample;
            let samples = scene.camera.width as f64 * scene.camera.height as f64 * r.spp as f64;
            let rays = samples * worst.min(r.max_rays as f64);
            if args.time_budget.is_some() {
                // The scene's settings are pass 2; each later pass traces four times as many.
                eprintln!(
                    "warning: {w} Pass 2 of this render (the scene's settings, {samples} samples) \
                     can trace up to {rays:.1e} rays under the ray budget, and each later pass \
                     four times as many."
                );
            } else {
                eprintln!(
                    "warning: {w} This render of {samples} samples can trace up to {rays:.1e} \
                     rays under the ray budget."
                );
            }
        }
    }
    let bar = (!args.quiet && std::io::stderr().is_terminal()).then(|| {
        let pixels = scene.camera.width as u64 * scene.camera.height as u64;
        let bar = indicatif::ProgressBar::new(pixels);
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{spinner} {prefix} [{bar:40}] {percent}% of the pixels {elapsed} (eta {eta})",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        bar.set_prefix("rendering");
        // The spinner and the clock move even while a slow pixel is still being traced.
        bar.enable_steady_tick(std::time::Duration::from_millis(200));
        bar
    });
    // The pass written (`--passes K`, or the last a budget completed), for the stats, and
    // its settings when they are not the scene's (under a budget).
    let mut reached = args.passes;
    let mut written = None;
    let result = if let Some(budget) = args.time_budget {
        let counting = crate::sampling::Counting::totals_if(stats_format.is_some());
        let render = |settings: &crate::scene::RenderSettings, stop: &(dyn Fn() -> bool + Sync)| {
            colour_pass(&scene, settings, counting, bar.as_ref(), stop)
        };
        let quiet = args.quiet;
        let pass =
            threads.run(|| budgeted(&scene, budget, args.passes, quiet, bar.as_ref(), render));
        crate::interrupt::check()?;
        let pass = pass.ok_or_else(|| Error::Other("no pass was completed".into()))?;
        said = reached_lines(&scene, &pass, args.passes, None);
        reached = Some(pass.index);
        written = Some(pass.settings.clone());
        pass.output
    } else {
        threads.run(|| render(&scene, &scene.render, stats_format.is_some(), bar.as_ref()))
    };
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    crate::interrupt::check()?;
    let written = written.as_ref().unwrap_or(&scene.render);
    if let Some((x, y, k)) = result.first_nan {
        eprintln!(
            "warning: sample {k} of pixel ({x}, {y}) came out as NaN or infinity and was counted as black \
             (reflective or transparent colours above 1 amplify light at every bounce and can overflow; otherwise this is a bug in rtlab). \
             Reproduce it with: {}",
            explain_command(&args, written, x, y, k)
        );
    }
    if let Some((x, y, k)) = result.first_cut {
        eprintln!(
            "warning: the ray budget ({} rays per sample, render.max_rays or --max-rays) cut {} sample(s): \
             their ray trees were not traced to the end, so their pixels miss part of their light \
             (the first is sample {k} of pixel ({x}, {y})). See where it was cut with: {}",
            scene.render.max_rays,
            result.cut_samples,
            explain_command(&args, written, x, y, k)
        );
    }
    write_png(&out, &result.image.to_rgb8_for(&scene.render))?;
    if let Some(f) = folders {
        f.keep();
    }
    for line in &said {
        eprintln!("{line}");
    }

    let (spp, subsample) = (written.spp, written.subsample);
    let passes = reached.map(|k| json!(k));
    if let (Some(format), Some(stats)) = (stats_format, &result.stats) {
        let trace = result.trace_seconds;
        let mrays = stats.rays.total as f64 / trace.max(1e-9) / 1e6;
        let b = stats.bundles;
        let traversal = match scene.render.traversal {
            Traversal::Single => "single",
            Traversal::Bundle => "bundle",
        };
        let per_bundle = b.opened as f64 / b.bundles.max(1) as f64;
        let bundles = (b.bundles > 0).then(|| {
            json!({
                "count": b.bundles,
                "nodes_opened": b.opened,
                "nodes_opened_per_bundle": per_bundle,
                "rays": b.rays,
                "most_rays": b.most,
                "simd": simd_lanes(),
            })
        });
        // Why the camera rays went alone although bundles were asked for (JSON; the text
        // says it in words below).
        let alone = match scene.render.traversal {
            Traversal::Single => Some("--traversal single sends every ray alone"),
            Traversal::Bundle => crate::sampling::bundles::alone_because(&scene.render),
        };
        if format == "json" {
            let v = json!({
                "rays": stats.rays,
                "tests": stats.tests,
                "bvh_nodes": stats.nodes,
                "bvh_nodes_per_ray": stats.nodes as f64 / stats.rays.total.max(1) as f64,
                "traversal": traversal,
                "bundles": bundles,
                "bundles_alone_because": alone,
                "seconds": {"load": load, "build": build, "trace": trace},
                "mrays_per_s": mrays,
                "width": scene.camera.width,
                "height": scene.camera.height,
                "spp": spp,
                "subsample": subsample,
                "passes": passes,
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
            let bundle_line = if b.bundles > 0 {
                // Fewer than sixteen at the image's edges, and under --subsample (a tile's
                // traced pixels): the average says how full they were.
                let mean = b.rays as f64 / b.bundles as f64;
                let size = if b.rays == b.bundles * b.most as u64 {
                    format!("of {}", b.most)
                } else {
                    format!("of {mean:.1} rays on average (up to {})", b.most)
                };
                format!(
                    "camera rays in {} bundles {size} ({} lanes): {:.1} nodes opened \
                     per bundle (each once for all its rays)\n",
                    b.bundles,
                    simd_lanes(),
                    per_bundle
                )
            } else if let Some(why) =
                alone.filter(|_| scene.render.traversal == Traversal::Bundle && r.camera > 0)
            {
                format!("no bundles: {why}, so every camera ray went alone\n")
            } else {
                String::new()
            };
            // A budgeted render's counts are its last pass's (the image written), not the sum.
            let of_pass = match (args.time_budget, reached) {
                (Some(_), Some(1)) => "pass 1 (the image written): ".to_string(),
                (Some(_), Some(k)) => {
                    format!("pass {k} (the image written; earlier passes not counted): ")
                }
                (None, Some(k)) => format!("pass {k}: "), // --passes K traces pass K only
                _ => String::new(),
            };
            // Bundles asked for and none made (the line after says why): every ray went alone.
            let traversal = match (traversal, b.bundles) {
                ("bundle", 0) if r.camera > 0 => "bundle traversal asked, every ray alone",
                ("bundle", _) => "bundle traversal",
                _ => "single traversal",
            };
            eprintln!(
                "{of_pass}rays: {} camera, {} shadow, {} reflection, {} refraction, {} total\n\
                 intersection tests: {}, BVH nodes visited: {} ({:.1} per ray, {traversal})\n\
                 {bundle_line}\
                 time: load {:.3} s (of which building the BVHs {:.3} s), trace {:.3} s ({:.2} Mrays/s)",
                r.camera,
                r.shadow,
                r.reflection,
                r.refraction,
                r.total,
                stats.tests,
                stats.nodes,
                stats.nodes as f64 / r.total.max(1) as f64,
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
fn explain_command(
    args: &Args,
    written: &crate::scene::RenderSettings,
    x: u32,
    y: u32,
    k: u32,
) -> String {
    // A pass (`--passes`, `--time-budget`) has samples of its own: explain takes them as
    // options, having no passes.
    let mut flags = args.render.clone();
    if args.passes.is_some() || args.time_budget.is_some() {
        flags.spp = Some(written.spp);
        flags.sampler = Some(written.sampler.name().to_string());
        flags.subsample = (written.subsample > 1).then_some(written.subsample);
    }
    format!(
        "rtlab explain {} --pixel {x},{y} --sample {k}{}",
        super::shell_word(&args.scene.display().to_string()),
        flags.to_flags()
    )
}

/// The SIMD lanes bundles ran on (`portable`, `avx2`, `avx512`: [`crate::accel::isa::level`]).
fn simd_lanes() -> &'static str {
    crate::accel::isa::level().name()
}
