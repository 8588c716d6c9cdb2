//! The Whitted scene: a whole render, time to first image, and explain's latency.

use crate::{median, THREADS};
use rtlab::scene::Scene;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

pub fn bench_whitted(runs: usize, pool: &rayon::ThreadPool, tmp: &Path) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/whitted.json");
    println!();
    println!(
        "== Whitted scene {} (mirror + glass + shadows, depth 5), {THREADS} threads",
        path.display()
    );
    let (mut mrays, mut ttfi, mut explain_ms, mut load_ms) = (vec![], vec![], vec![], vec![]);
    let exe = env!("CARGO_BIN_EXE_rtlab");
    let png = tmp.join("whitted.png");
    let mut rays = 0;
    for _ in 0..runs {
        let t0 = Instant::now();
        let scene = Scene::load(&path).expect("the Whitted scene loads");
        load_ms.push(t0.elapsed().as_secs_f64() * 1e3);
        let out = pool.install(|| rtlab::sampling::render(&scene, &scene.render, true, None));
        let stats = out.stats.expect("counted");
        rays = stats.rays.total;
        mrays.push(rays as f64 / out.trace_seconds / 1e6);
        let (x, y) = (scene.camera.width / 2, scene.camera.height / 2);
        let t1 = Instant::now();
        let e = rtlab::cli::explain::explain(&scene, x, y);
        explain_ms.push(t1.elapsed().as_secs_f64() * 1e3);
        std::hint::black_box(e);
        let t2 = Instant::now();
        let ok = Command::new(exe)
            .arg("render")
            .arg(&path)
            .arg("-o")
            .arg(&png)
            .args(["--threads", "2", "--quiet"])
            .status()
            .map(|s| s.success())
            .unwrap_or(false);
        if ok && png.exists() {
            ttfi.push(t2.elapsed().as_secs_f64());
        }
        let _ = std::fs::remove_file(&png);
    }
    println!(
        "whole render: {:.2} Mrays/s ({rays} rays: camera, shadow, reflection, refraction)",
        median(mrays)
    );
    if !ttfi.is_empty() {
        println!(
            "time to first image (release binary, process start to PNG written): {:.3} s",
            median(ttfi)
        );
    }
    println!(
        "explain of the centre pixel: {:.2} ms after a load + build of {:.2} ms",
        median(explain_ms),
        median(load_ms)
    );
}
