//! Is `--traversal bundle`, the default, the faster one on the scenes students render?
//!
//! Renders every scene in `scenes/` (their own settings and size) through
//! `rtlab::sampling::render`, as `rtlab render` does, with `--traversal single` and with
//! `--traversal bundle`, alternately (each first in every other run), on 2 threads: each
//! scene's trace time is the median of its renders; two medians within 2 % are a tie. The two images must be equal, pixel for pixel (the tests check the
//! PNGs; here the colours before they are written). `cargo bench --bench traversal`;
//! `RTLAB_BENCH_RUNS` sets the renders each way (default 7).

use rtlab::accel::Traversal;
use rtlab::scene::Scene;
use std::path::Path;

#[path = "shared/median.rs"]
mod shared_median;
use shared_median::median;

/// Two trace times closer than this (as a ratio) are counted as a tie.
const TIE: f64 = 0.02;

fn main() {
    let runs: usize = std::env::var("RTLAB_BENCH_RUNS")
        .ok()
        .and_then(|s| s.parse().ok())
        .filter(|&n| n > 0)
        .unwrap_or(7);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .expect("a thread pool");
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("scenes/ is readable")
        .map(|e| e.expect("a directory entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    println!(
        "trace time of `rtlab render` (2 threads; median of {runs} renders each way, alternating)"
    );
    println!(
        "{:<22} {:>10} {:>10} {:>15}",
        "scene", "single ms", "bundle ms", "single / bundle"
    );
    let (mut faster, mut slower) = (0, 0);
    for file in &files {
        let scene = Scene::load(file).expect("the scenes in scenes/ load");
        let name = file.file_stem().unwrap().to_string_lossy();
        let mut settings = scene.render.clone();
        let (mut single, mut bundle) = (Vec::new(), Vec::new());
        let mut images = (None, None);
        for run in 0..runs {
            let mut order = [
                (Traversal::Single, &mut single, &mut images.0),
                (Traversal::Bundle, &mut bundle, &mut images.1),
            ];
            // Each goes first in every other run, so neither always finds the caches cold.
            if run % 2 == 1 {
                order.reverse();
            }
            for (traversal, times, image) in order {
                settings.traversal = traversal;
                let out = pool.install(|| rtlab::sampling::render(&scene, &settings, false, None));
                times.push(out.trace_seconds);
                *image = Some(out.image);
            }
        }
        assert!(
            images.0 == images.1,
            "{name}: the bundled render is not the single-ray render"
        );
        let (s, b) = (median(single), median(bundle));
        if s / b > 1.0 + TIE {
            faster += 1;
        } else if b / s > 1.0 + TIE {
            slower += 1;
        }
        println!(
            "{name:<22} {:>10.2} {:>10.2} {:>15.2}",
            s * 1e3,
            b * 1e3,
            s / b
        );
    }
    println!(
        "of {} scenes, bundles faster on {faster}, slower on {slower}, within {:.0} % on the rest; every image the same both ways",
        files.len(),
        TIE * 100.0
    );
}
