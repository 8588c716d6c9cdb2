//! How fast is the BVH? rtlab against Embree 3 on the same meshes, camera and machine
//! (DESIGN §8). `cargo bench --bench accel [-- MESH ...]` (MESH: teapot, bunny, bunny_56k,
//! samurai_monastry, terrain_1m; default all).
//!
//! For each mesh, in rounds that alternate Embree's harness and rtlab so both see the same
//! machine load: BVH build time, camera-ray Mrays/s (one ray per pixel, 1280×720, the
//! harness's default camera), shadow-ray Mrays/s (one ray per camera hit towards the harness's
//! light), peak memory (VmHWM of a child process that loads, builds and traces), and the
//! camera-ray checksum (hits, Σt) compared with Embree's, pixel by pixel. Then the Whitted
//! scene (`scenes/whitted.json`): whole-render Mrays/s, time to first image (the release
//! binary, process start to PNG written) and explain latency of one pixel.
//! The meshes' last table holds the speed goals of issue 21 (camera bundles against
//! `rtcIntersect1` and `rtcIntersect16`, shadow bundles against `rtcOccluded1`, the bundled
//! render against `rtcIntersect1`), met or not by the ratio of the medians, with each
//! round's own ratio beside it (rtlab and Embree timed in the same round): how far the
//! verdict stands from the machine's noise.
//!
//! Environment: `RTLAB_BENCH_RUNS` (rounds, default 5), `RTLAB_BENCH_PASSES` (passes of
//! each measurement in a round, default 3: each side's number for the round is the median
//! of its passes, the harness's `--runs`), `EMBREE_BENCH` (the harness binary;
//! otherwise it is built from ../shared/bench/embree with its build.sh when Embree's headers
//! are installed, or skipped with a message), `RTLAB_TERRAIN` (the 1M-triangle terrain OBJ,
//! default /tmp/terrain_1m.obj, generated with gen_mesh.py when missing), `RTLAB_MESHES`
//! (folder of the shared meshes, default ../shared/meshes next to the crate, or
//! /work/shared/meshes).
//!
//! `cargo bench --bench accel -- --only PASS MESH [REPEATS]` runs one pass alone (single,
//! bundle, render, render-bundle, render-rays, render-walk, render-stats, render-bundle-stats, shadow or
//! shadow-bundle), for profilers; it prints the median of the repeats, and the lowest and
//! highest.
//!
//! Everything runs on 2 threads (rtlab: a rayon pool of 2; Embree: `threads=2`).

mod camera;
mod embree;
mod inputs;
mod mesh;
mod passes;
mod render;
mod shadow;
mod table;
mod whitted;

use camera::HarnessCamera;
use inputs::{locate_embree, mesh_scene, meshes};
use mesh::bench_mesh;
use passes::{bundle_pass, camera_pass, child_memory};
use render::{render_mrays, render_mrays_counting, render_parts, render_view};
use shadow::{shadow_bundle_pass, shadow_pass};
use std::path::Path;
use table::{print_goals, print_mesh_table};
use whitted::bench_whitted;

/// The rtlab binary's own allocator (src/main.rs), so that the render rows time the render
/// as the binary runs it.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

const W: usize = 1280;
const H: usize = 720;
const THREADS: usize = 2;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if let Some(i) = args.iter().position(|a| a == "--child-mem") {
        child_memory(Path::new(&args[i + 1]));
        return;
    }
    if let Some(i) = args.iter().position(|a| a == "--only") {
        only(&args[i + 1..]);
        return;
    }
    let filters: Vec<&String> = args.iter().filter(|a| !a.starts_with('-')).collect();
    let runs: usize = std::env::var("RTLAB_BENCH_RUNS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(5)
        .max(1);
    let passes: usize = std::env::var("RTLAB_BENCH_PASSES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3)
        .max(1);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(THREADS)
        .build()
        .expect("a thread pool");
    let embree = locate_embree();
    if embree.is_none() {
        println!(
            "Embree harness unavailable: rtlab numbers only, no ratios (see the message above)."
        );
    }
    let tmp = tempfile::tempdir().expect("a temporary folder");

    let mut rows = Vec::new();
    for (name, path) in meshes() {
        if !filters.is_empty() && !filters.iter().any(|f| name.contains(f.as_str())) {
            continue;
        }
        let Some(path) = path else {
            println!("{name}: mesh file not found, skipped");
            continue;
        };
        rows.push(bench_mesh(
            &name,
            &path,
            (runs, passes),
            &pool,
            embree.as_deref(),
            tmp.path(),
        ));
    }
    println!(
        "\n{runs} rounds (RTLAB_BENCH_RUNS), each side's number in a round the median of {passes} passes (RTLAB_BENCH_PASSES; Embree's --runs)"
    );
    print_mesh_table(&rows);
    print_goals(&rows);
    if filters.is_empty() || filters.iter().any(|f| "whitted".contains(f.as_str())) {
        bench_whitted(runs, &pool, tmp.path());
    }
}

/// `--only PASS MESH [REPEATS]`: one pass (single, bundle, render, render-bundle,
/// render-stats, render-bundle-stats, shadow, shadow-bundle)
/// on one mesh, repeated, with nothing else in the process: for profilers (`perf stat`,
/// `perf record`), which then see only that pass.
fn only(args: &[String]) {
    let (pass, name) = (args[0].as_str(), args[1].as_str());
    let repeats: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(20);
    let (_, Some(path)) = meshes()
        .into_iter()
        .find(|(n, _)| n == name)
        .expect("a mesh name")
    else {
        panic!("{name}: mesh file not found")
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(THREADS)
        .build()
        .expect("a thread pool");
    let tmp = tempfile::tempdir().expect("a temporary folder");
    let scene = pool.install(|| mesh_scene(&path, tmp.path()));
    let cam = HarnessCamera::new(&scene);
    let view = render_view(&path, &cam, tmp.path());
    let camera = camera_pass(&scene, &cam, &pool);
    let mut speeds = Vec::new();
    for _ in 0..repeats {
        speeds.push(match pass {
            "single" => (W * H) as f64 / camera_pass(&scene, &cam, &pool).seconds / 1e6,
            "bundle" => (W * H) as f64 / bundle_pass(&scene, &cam, &pool).0 / 1e6,
            "render" => render_mrays(&view, rtlab::accel::Traversal::Single, &pool),
            "render-bundle" => render_mrays(&view, rtlab::accel::Traversal::Bundle, &pool),
            "render-rays" => (W * H) as f64 / render_parts(&view, &pool, false) / 1e6,
            "render-walk" => (W * H) as f64 / render_parts(&view, &pool, true) / 1e6,
            "shadow-bundle" => {
                let (secs, v) = shadow_bundle_pass(&scene, &cam, &camera, &pool);
                v.len() as f64 / secs / 1e6
            }
            "render-stats" => {
                render_mrays_counting(&view, rtlab::accel::Traversal::Single, true, &pool)
            }
            "render-bundle-stats" => {
                render_mrays_counting(&view, rtlab::accel::Traversal::Bundle, true, &pool)
            }
            "shadow" => {
                let (secs, rays, _) = shadow_pass(&scene, &cam, &camera, &pool);
                rays as f64 / secs / 1e6
            }
            _ => {
                panic!("{pass}: not single, bundle, render, render-bundle, render-rays, render-walk, render-stats, render-bundle-stats, shadow or shadow-bundle")
            }
        });
    }
    let lowest = speeds.iter().copied().fold(f64::INFINITY, f64::min);
    let highest = speeds.iter().copied().fold(0.0, f64::max);
    println!(
        "{pass} on {name}: {:.2} Mrays/s (median of {repeats}; lowest {lowest:.2}, highest {highest:.2})",
        median(speeds)
    );
}

#[path = "../shared/median.rs"]
mod shared_median;
use shared_median::median;
