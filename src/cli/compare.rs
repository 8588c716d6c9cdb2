//! `rtlab compare`: the same scene at several sampling settings, against a high-spp reference.
//!
//! Output format (DESIGN §3, version 1), `--format json`:
//! `{"reference": {"spp": n, "sampler": ".."}, "crop": [x, y, w, h], "runs": [{"label": ..,
//! "spp": n, "sampler": .., "filter": .., "samples": n, "rays": n, "seconds": s, "rmse": x,
//! "psnr": x|null}]}`. RMSE and PSNR are measured on the encoded bytes (/255), the image a
//! student sees; `psnr` is null when a run equals the reference. `samples` counts the samples
//! actually traced (the adaptive sampler decides per pixel); `rays` every ray, shadow rays
//! included. `seconds` is trace time and is the only value that changes from run to run.

use super::render::with_threads;
use super::{parse_list, RenderArgs};
use crate::error::{Error, Result};
use crate::output::{check_not_input, check_png};
use crate::sampling::render;
use crate::scene::{SamplerKind, Scene};
use crate::viz::compare::{error_map, figure, rmse_psnr, worst_crop, Crop, Panel};
use serde_json::json;
use std::path::PathBuf;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Scene file: native rtlab JSON or a CS1230 scenefile.
    pub scene: PathBuf,
    /// Samples per pixel of a run; repeat for several runs (default: --spp 1 --spp 16).
    #[arg(long = "spp", value_name = "N")]
    pub spp: Vec<u32>,
    /// Sampler of the runs: one for all, one per --spp, or several at a single --spp
    /// (default: center at 1 spp, jittered at square counts, random otherwise).
    #[arg(long = "sampler", value_name = "KIND")]
    pub sampler: Vec<String>,
    /// Samples per pixel of the reference (jittered; a square number).
    #[arg(long, value_name = "N", default_value_t = 256)]
    pub reference_spp: u32,
    /// The magnified region, in pixels (default: where the first run differs most from the
    /// reference).
    #[arg(long, value_name = "X,Y,W,H")]
    pub crop: Option<String>,
    /// Write the figure here (PNG).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// text (default) or json.
    #[arg(long, default_value = "text")]
    pub format: String,
    /// Also draw the trace times in the figure (they differ from run to run, so the figure's
    /// bytes do too).
    #[arg(long)]
    pub show_time: bool,
    /// Worker threads (default: all cores). The images are the same for any count.
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// Image width in pixels (overrides the scene).
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height in pixels (overrides the scene).
    #[arg(long)]
    pub height: Option<u32>,
    /// Reconstruction filter of every run and the reference: box, tent, gaussian, mitchell.
    #[arg(long, value_name = "KIND")]
    pub filter: Option<String>,
    /// Maximum recursion depth.
    #[arg(long, value_name = "D")]
    pub max_depth: Option<u32>,
    /// Seed of every random choice.
    #[arg(long, value_name = "S")]
    pub seed: Option<u64>,
    /// Subsample the runs (not the reference) by K.
    #[arg(long, value_name = "K")]
    pub subsample: Option<u32>,
    /// Threshold of the adaptive sampler.
    #[arg(long, value_name = "T")]
    pub adaptive_threshold: Option<f64>,
    /// The course's stage (see `rtlab render --help`); the runs' sampling stays compare's.
    #[arg(long, value_name = "intersect|illuminate")]
    pub course_stage: Option<String>,
    /// Render every run and the reference with a deliberate mistake (`rtlab mistakes`);
    /// repeatable and comma-separated.
    #[arg(long = "mistake", value_name = "NAME")]
    pub mistakes: Vec<String>,
}

/// One run: its sampler and spp.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunSpec {
    pub spp: u32,
    pub sampler: SamplerKind,
}

/// Pairs the `--spp` and `--sampler` lists into runs.
pub fn plan_runs(spp: &[u32], samplers: &[String]) -> Result<Vec<RunSpec>> {
    let spp: Vec<u32> = if spp.is_empty() {
        vec![1, 16]
    } else {
        spp.to_vec()
    };
    let kinds = samplers
        .iter()
        .map(|s| {
            SamplerKind::parse(s).ok_or_else(|| {
                Error::arg(
                    "--sampler",
                    format!(
                        "unknown sampler \"{s}\" (expected one of: {})",
                        SamplerKind::NAMES.join(", ")
                    ),
                )
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let default_kind = |n: u32| {
        let r = (n as f64).sqrt().round() as u32;
        if n == 1 {
            SamplerKind::Center
        } else if r * r == n {
            SamplerKind::Jittered
        } else {
            SamplerKind::Random
        }
    };
    let runs: Vec<RunSpec> = match (kinds.len(), spp.len()) {
        (0, _) => spp
            .iter()
            .map(|&n| RunSpec {
                spp: n,
                sampler: default_kind(n),
            })
            .collect(),
        (1, _) => spp
            .iter()
            .map(|&n| RunSpec {
                spp: n,
                sampler: kinds[0],
            })
            .collect(),
        (k, 1) => (0..k)
            .map(|i| RunSpec {
                spp: spp[0],
                sampler: kinds[i],
            })
            .collect(),
        (k, n) if k == n => spp
            .iter()
            .zip(&kinds)
            .map(|(&n, &s)| RunSpec { spp: n, sampler: s })
            .collect(),
        (k, n) => {
            return Err(Error::arg(
                "--sampler",
                format!(
                    "{k} samplers for {n} --spp values: give one sampler for all, one per --spp, \
                     or a single --spp"
                ),
            ))
        }
    };
    for r in &runs {
        crate::sampling::validate_spp(r.sampler, r.spp).map_err(|m| Error::arg("--spp", m))?;
    }
    Ok(runs)
}

fn parse_crop(s: &str, w: u32, h: u32) -> Result<Crop> {
    let v = parse_list("--crop", s, 4)?;
    let bad = || {
        Error::arg(
            "--crop",
            format!("{s} is not a region inside the {w}×{h} image (X,Y,W,H in whole pixels, W and H ≥ 1)"),
        )
    };
    if v.iter().any(|x| *x < 0.0 || x.fract() != 0.0) {
        return Err(bad());
    }
    let c = (v[0] as u32, v[1] as u32, v[2] as u32, v[3] as u32);
    if c.2 == 0 || c.3 == 0 || c.0 + c.2 > w || c.1 + c.3 > h {
        return Err(bad());
    }
    Ok(c)
}

fn label(r: &RunSpec, subsample: u32) -> String {
    let mut s = format!("{} spp · {}", r.spp, r.sampler.name());
    if r.sampler == SamplerKind::Adaptive {
        s = format!("≤{} spp · adaptive", r.spp);
    }
    if subsample > 1 {
        s += &format!(" · 1/{subsample}²");
    }
    s
}

pub fn run(args: Args, out: &mut dyn std::io::Write) -> Result<()> {
    if args.format != "text" && args.format != "json" {
        return Err(Error::arg(
            "--format",
            format!("unknown format \"{}\" (expected text or json)", args.format),
        ));
    }
    if let Some(o) = &args.output {
        check_png(o, "-o")?;
        check_not_input(o, "-o", &[(&args.scene, "the scene")])?;
    }
    let runs = plan_runs(&args.spp, &args.sampler)?;
    crate::sampling::validate_spp(SamplerKind::Jittered, args.reference_spp)
        .map_err(|m| Error::arg("--reference-spp", m))?;
    let base = RenderArgs {
        width: args.width,
        height: args.height,
        filter: args.filter.clone(),
        max_depth: args.max_depth,
        seed: args.seed,
        adaptive_threshold: args.adaptive_threshold,
        course_stage: args.course_stage.clone(),
        mistakes: args.mistakes.clone(),
        ..RenderArgs::default()
    };
    let scene = base.load(&args.scene)?;
    if let Some(o) = &args.output {
        crate::output::check_not_read(o, "-o")?; // a texture or mesh of the scene
    }
    // The reference is the largest render compare makes.
    let most = args.spp.iter().copied().chain([args.reference_spp]).max();
    base.check_memory(&scene, &args.scene, most.unwrap_or(1))?;
    let (w, h) = (scene.camera.width, scene.camera.height);
    let crop_arg = args
        .crop
        .as_deref()
        .map(|s| parse_crop(s, w, h))
        .transpose()?;
    let subsample = args.subsample.unwrap_or(1);
    if !(1..=64).contains(&subsample) {
        return Err(Error::arg(
            "--subsample",
            format!("{subsample} is out of range (1 to 64)"),
        ));
    }

    let render_with = |spp: u32, sampler: SamplerKind, sub: u32| -> Result<_> {
        let mut s: Scene = scene.clone();
        s.render.spp = spp;
        s.render.sampler = sampler;
        s.render.subsample = sub;
        let o = with_threads(args.threads, || render(&s, &s.render, true, None))?;
        let img = o.image.to_rgb8_for(&s.render);
        let samples: u64 = o.spp_map.iter().flatten().map(|&n| n as u64).sum();
        let rays = o.stats.as_ref().map_or(0, |st| st.rays.total);
        Ok((
            img,
            samples,
            rays,
            o.trace_seconds,
            o.spp_map.unwrap_or_default(),
        ))
    };
    let (reference, _, _, _, _) = render_with(args.reference_spp, SamplerKind::Jittered, 1)?;
    let mut panels = Vec::new();
    for r in &runs {
        let (img, samples, rays, seconds, spp_map) = render_with(r.spp, r.sampler, subsample)?;
        let (rmse, psnr) = rmse_psnr(&img, &reference);
        panels.push(Panel {
            label: label(r, subsample),
            image: img,
            samples,
            rays,
            seconds,
            rmse,
            psnr,
            spp_map,
        });
    }
    let crop = crop_arg.unwrap_or_else(|| {
        let e = error_map(&panels[0].image, &reference);
        worst_crop(&e, w, h, (w / 5).max(4), (h / 5).max(3))
    });
    let ref_label = format!("reference: {} spp · jittered", args.reference_spp);
    if let Some(o) = &args.output {
        let adaptive = runs.iter().any(|r| r.sampler == SamplerKind::Adaptive);
        figure(
            &panels,
            &reference,
            &ref_label,
            crop,
            args.show_time,
            adaptive,
        )
        .write_png(o)?;
    }

    let filter = scene.render.filter.name();
    let text = if args.format == "json" {
        let v = json!({
            "reference": {"spp": args.reference_spp, "sampler": "jittered"},
            "crop": [crop.0, crop.1, crop.2, crop.3],
            "runs": runs.iter().zip(&panels).map(|(r, p)| json!({
                "label": p.label,
                "spp": r.spp,
                "sampler": r.sampler.name(),
                "filter": filter,
                "subsample": subsample,
                "samples": p.samples,
                "rays": p.rays,
                "seconds": p.seconds,
                "rmse": p.rmse,
                "psnr": p.psnr,
            })).collect::<Vec<_>>(),
        });
        serde_json::to_string_pretty(&v).expect("serialisable") + "\n"
    } else {
        let mut t = format!(
            "{:<26} {:>10} {:>12} {:>9} {:>8} {:>10}\n",
            "run", "samples", "rays", "RMSE", "PSNR dB", "time s"
        );
        for p in &panels {
            t += &format!(
                "{:<26} {:>10} {:>12} {:>9.4} {:>8} {:>10.3}\n",
                p.label,
                p.samples,
                p.rays,
                p.rmse,
                p.psnr.map_or("inf".into(), |v| format!("{v:.2}")),
                p.seconds
            );
        }
        t += &format!(
            "against a {}-spp jittered reference ({filter} filter); crop {},{},{},{}\n",
            args.reference_spp, crop.0, crop.1, crop.2, crop.3
        );
        if let Some(o) = &args.output {
            t += &format!("wrote {}\n", o.display());
        }
        t
    };
    super::emit(out, &text)
}
