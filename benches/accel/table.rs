//! The tables printed after the rounds.

use crate::mesh::{EmbreeSummary, MeshRow, Paired};
use crate::{H, THREADS, W};

pub fn print_mesh_table(rows: &[MeshRow]) {
    if rows.is_empty() {
        return;
    }
    println!();
    println!("1280×720, one ray per pixel, harness camera, {THREADS} threads; medians; ratio = rtlab / Embree (for build and memory, lower is better)");
    println!(
        "{:<17} {:>9} | {:>10} {:>10} {:>6} | {:>8} {:>8} {:>6} | {:>8} {:>8} {:>6} | {:>8} {:>8} {:>6} | {:>7}",
        "mesh", "tris", "build ms", "Embree", "ratio", "camera", "Embree", "ratio", "shadow", "Embree", "ratio",
        "peak MiB", "Embree", "ratio", "2-level"
    );
    for r in rows {
        let e = r.embree.as_ref();
        let f = |x: Option<f64>, p: usize| x.map_or("-".to_string(), |v| format!("{v:.p$}"));
        println!(
            "{:<17} {:>9} | {:>10.1} {:>10} {:>6} | {:>8.2} {:>8} {:>6} | {:>8.2} {:>8} {:>6} | {:>8} {:>8} {:>6} | {:>6.1}%",
            r.name,
            r.triangles,
            r.build_ms,
            f(e.map(|e| e.build_ms), 1),
            f(e.map(|e| r.build_ms / e.build_ms), 2),
            r.camera,
            f(e.map(|e| e.camera), 2),
            f(e.map(|e| r.camera / e.camera), 2),
            r.shadow,
            f(e.map(|e| e.shadow), 2),
            f(e.map(|e| r.shadow / e.shadow), 2),
            f(r.peak_mib, 1),
            f(e.map(|e| e.peak_mib), 1),
            f(r.peak_mib.zip(e.map(|e| e.peak_mib)).map(|(a, b)| a / b), 2),
            100.0 * (r.mesh_only / r.camera - 1.0),
        );
    }
    println!("2-level: how much faster the same camera rays run straight into the mesh's BVH, skipping the scene level");
    println!();
    println!("shadow rays from the camera hits, Mrays/s (medians): single rays, and in 4x4 bundles (Accel::occluded_bundle, same verdicts, checked)");
    println!(
        "{:<17} | {:>8} {:>8} | {:>8} {:>6} {:>6}",
        "mesh", "Embree", "single", "bundle", "x1", "/sgl"
    );
    for r in rows {
        let e = r.embree.as_ref();
        let f = |x: Option<f64>| x.map_or("-".to_string(), |v| format!("{v:.2}"));
        println!(
            "{:<17} | {:>8} {:>8.2} | {:>8.2} {:>6} {:>6.2}",
            r.name,
            f(e.map(|e| e.shadow)),
            r.shadow,
            r.shadow_bundle,
            f(e.map(|e| r.shadow_bundle / e.shadow)),
            r.shadow_bundle / r.shadow,
        );
    }
    println!();
    println!("camera rays, Mrays/s (medians); ratios to Embree's rtcIntersect1 (x1), rtcIntersect8 (x8), rtcIntersect16 (x16) of the same run");
    println!(
        "{:<17} | {:>7} {:>7} {:>7} | {:>7} {:>5} {:>5} | {:>7} {:>5} {:>5} {:>5} | {:>7} {:>5} | {:>7} {:>5} | {:>7} {:>6} | {:>7} {:>6}",
        "mesh", "Embree1", "Embree8", "Emb16", "single", "x1", "x16", "bundle", "x1", "x16", "/sgl", "render", "x1", "r+bndl", "x1", "r+stats", "/rndr", "rb+stat", "/rbndl"
    );
    for r in rows {
        let e = r.embree.as_ref();
        let f = |x: Option<f64>, p: usize| x.map_or("-".to_string(), |v| format!("{v:.p$}"));
        let ratio = |x: f64, by: fn(&EmbreeSummary) -> f64| f(e.map(|e| x / by(e)), 2);
        println!(
            "{:<17} | {:>7} {:>7} {:>7} | {:>7.2} {:>5} {:>5} | {:>7.2} {:>5} {:>5} {:>5.2} | {:>7.2} {:>5} | {:>7.2} {:>5} | {:>7.2} {:>6.2} | {:>7.2} {:>6.2}",
            r.name,
            f(e.map(|e| e.camera), 2),
            f(e.map(|e| e.packet8), 2),
            f(e.map(|e| e.packet16), 2),
            r.camera,
            ratio(r.camera, |e| e.camera),
            ratio(r.camera, |e| e.packet16),
            r.bundle,
            ratio(r.bundle, |e| e.camera),
            ratio(r.bundle, |e| e.packet16),
            r.bundle / r.camera,
            r.render,
            ratio(r.render, |e| e.camera),
            r.render_bundle,
            ratio(r.render_bundle, |e| e.camera),
            r.render_stats,
            r.render_stats / r.render,
            r.render_bundle_stats,
            r.render_bundle_stats / r.render_bundle,
        );
    }
    println!("bundle: the same rays in 4x4 blocks through Accel::closest_bundle (same hits, checked); /sgl: bundle / single");
    println!("render, r+bndl: `rtlab render` of the same view (its own camera, a diffuse mesh, no lights: generation, traversal, shading, film), trace time, --traversal single / bundle");
    println!(
        "r+stats, rb+stat: the single-ray and the bundled render counting as --stats does; /rndr, /rbndl: their speed / the same render's without counting"
    );
    println!();
    println!("the bundled render's trace per camera ray, ns of wall time (2 threads; medians): its rays made, walked, and the rest");
    println!(
        "{:<17} | {:>7} {:>7} {:>7} {:>7} | {:>7} {:>7}",
        "mesh", "rays", "walk", "rest", "render", "Embree1", "0.8x"
    );
    for r in rows {
        let ns = |mrays: f64| 1e3 / mrays;
        let per_ray = |seconds: f64| seconds * 1e9 / (W * H) as f64;
        let (made, walked) = (per_ray(r.parts.0), per_ray(r.parts.1));
        let render = ns(r.render_bundle);
        let e = r.embree.as_ref();
        let f = |x: Option<f64>| x.map_or("-".to_string(), |v| format!("{v:.1}"));
        println!(
            "{:<17} | {:>7.1} {:>7.1} {:>7.1} {:>7.1} | {:>7} {:>7}",
            r.name,
            made,
            walked - made,
            render - walked,
            render,
            f(e.map(|e| ns(e.camera))),
            f(e.map(|e| ns(0.8 * e.camera))),
        );
    }
    println!("rays: rtlab::trace::camera_rays over the view's 4x4 blocks; walk: their closest hits (Accel::closest_bundle_into); rest: the render's trace time minus both (shading, the colours kept for the filter, the tiles' plans)");
    println!("Embree1: rtcIntersect1's time per ray; 0.8x: the render's trace time per ray at 0.8x rtcIntersect1");
    println!();
    println!(
        "checksums (camera rays: hits, Σt; shadow rays: occluded of rays) and memory per triangle"
    );
    for r in rows {
        print!(
            "{:<17} rtlab hits {:>7} Σt {:.6e} occluded {}/{} | load + build {:.2} s, then explain of a pixel {:.2} ms; {:.0} bytes/triangle (mesh + BVH + packed faces)",
            r.name, r.hits, r.sum_t, r.occluded.1, r.occluded.0, r.load_s, r.explain_ms, r.bytes_per_tri
        );
        if let Some(e) = &r.embree {
            print!(
                "\n{:<17} Embree hits {:>7} Σt {:.6e} occluded {}/{} | hits differ by {}, Σt by {:.2e} (relative), {} pixels disagree on hit/miss",
                "",
                e.hits,
                e.sum_t,
                e.occluded.1,
                e.occluded.0,
                r.hits as i64 - e.hits as i64,
                (r.sum_t - e.sum_t) / e.sum_t,
                e.pixels_differ
            );
        }
        println!();
    }
}

/// A speed goal of issue 21: rtlab's speed over one of Embree's, at least `at`.
struct Goal {
    /// What is timed, and against which of Embree's modes.
    what: &'static str,
    against: &'static str,
    at: f64,
    /// The ratio of the medians (the tables' ratio).
    medians: fn(&MeshRow, &EmbreeSummary) -> f64,
    /// One round's own ratio.
    round: fn(&Paired) -> f64,
}

const GOALS: [Goal; 4] = [
    Goal {
        what: "camera bundles",
        against: "rtcIntersect1",
        at: 1.0,
        medians: |r, e| r.bundle / e.camera,
        round: |p| p.bundle_x1,
    },
    Goal {
        what: "camera bundles",
        against: "rtcIntersect16",
        at: 0.5,
        medians: |r, e| r.bundle / e.packet16,
        round: |p| p.bundle_x16,
    },
    Goal {
        what: "shadow bundles",
        against: "rtcOccluded1",
        at: 0.7,
        medians: |r, e| r.shadow_bundle / e.shadow,
        round: |p| p.shadow_x1,
    },
    Goal {
        what: "bundled render",
        against: "rtcIntersect1",
        at: 0.8,
        medians: |r, e| r.render_bundle / e.camera,
        round: |p| p.render_x1,
    },
];

/// Issue 21's speed goals, met or not by the ratio of the medians (the tables' verdict), with
/// the rounds' own ratios beside it: how far the verdict stands from the noise.
pub fn print_goals(rows: &[MeshRow]) {
    if rows.iter().all(|r| r.embree.is_none()) {
        return;
    }
    println!();
    println!("the speed goals of issue 21: the ratio of the medians above, and each round's own ratio (rtlab and Embree timed in the same round): lowest, highest, rounds at the goal");
    println!(
        "{:<38} {:<17} {:>6} {:<8} | {:>7} {:>7} {:>6}",
        "goal", "mesh", "ratio", "", "lowest", "highest", "rounds"
    );
    for goal in &GOALS {
        let label = format!("{} >= {:.1}x {}", goal.what, goal.at, goal.against);
        let mut first = true;
        for r in rows {
            let Some(e) = &r.embree else { continue };
            let ratio = (goal.medians)(r, e);
            let rounds: Vec<f64> = r.paired.iter().map(goal.round).collect();
            let met = rounds.iter().filter(|&&x| x >= goal.at).count();
            let (lowest, highest) = if rounds.is_empty() {
                ("-".to_string(), "-".to_string())
            } else {
                let low = rounds.iter().copied().fold(f64::INFINITY, f64::min);
                let high = rounds.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                (format!("{low:.3}"), format!("{high:.3}"))
            };
            println!(
                "{:<38} {:<17} {:>6.3} {:<8} | {:>7} {:>7} {:>6}",
                if first { label.as_str() } else { "" },
                r.name,
                ratio,
                if ratio >= goal.at { "met" } else { "NOT MET" },
                lowest,
                highest,
                format!("{met}/{}", rounds.len()),
            );
            first = false;
        }
    }
}
