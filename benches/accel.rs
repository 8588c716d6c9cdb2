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
//!
//! Environment: `RTLAB_BENCH_RUNS` (rounds, default 5), `EMBREE_BENCH` (the harness binary;
//! otherwise it is built from ../shared/bench/embree with its build.sh when Embree's headers
//! are installed, or skipped with a message), `RTLAB_TERRAIN` (the 1M-triangle terrain OBJ,
//! default /tmp/terrain_1m.obj, generated with gen_mesh.py when missing), `RTLAB_MESHES`
//! (folder of the shared meshes, default ../shared/meshes next to the crate, or
//! /work/shared/meshes).
//!
//! `cargo bench --bench accel -- --only PASS MESH [REPEATS]` runs one pass alone (single,
//! bundle, render, render-bundle, render-rays, render-walk, render-stats, render-bundle-stats, shadow or
//! shadow-bundle), for profilers.
//!
//! Everything runs on 2 threads (rtlab: a rayon pool of 2; Embree: `threads=2`).

use rayon::prelude::*;
use rtlab::math::Ray;
use rtlab::scene::Scene;
use rtlab::shapes::{NoObserver, Shape};
use rtlab::trace::NoRecorder;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

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
            runs,
            &pool,
            embree.as_deref(),
            tmp.path(),
        ));
    }
    print_mesh_table(&rows);
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
    println!(
        "{pass} on {name}: {:.2} Mrays/s (median of {repeats})",
        median(speeds)
    );
}

// ---------------------------------------------------------------- inputs

fn shared_meshes() -> Option<PathBuf> {
    if let Ok(p) = std::env::var("RTLAB_MESHES") {
        return Some(PathBuf::from(p));
    }
    let here = Path::new(env!("CARGO_MANIFEST_DIR"));
    [
        here.join("../shared/meshes"),
        here.join("../../shared/meshes"),
        PathBuf::from("/work/shared/meshes"),
    ]
    .into_iter()
    .find(|p| p.join("bunny_56k.obj").exists())
}

fn meshes() -> Vec<(String, Option<PathBuf>)> {
    let dir = shared_meshes();
    let mut out: Vec<(String, Option<PathBuf>)> =
        ["teapot", "bunny", "bunny_56k", "samurai_monastry"]
            .iter()
            .map(|n| {
                let p = dir.as_ref().map(|d| d.join(format!("{n}.obj")));
                (n.to_string(), p.filter(|p| p.exists()))
            })
            .collect();
    out.push(("terrain_1m".into(), terrain(dir.as_deref())));
    out
}

fn terrain(dir: Option<&Path>) -> Option<PathBuf> {
    let path = PathBuf::from(
        std::env::var("RTLAB_TERRAIN").unwrap_or_else(|_| "/tmp/terrain_1m.obj".into()),
    );
    if path.exists() {
        return Some(path);
    }
    let tool = dir?.join("tools/gen_mesh.py");
    println!(
        "generating the 1M-triangle terrain: python3 {} terrain --tris 1000000 -o {}",
        tool.display(),
        path.display()
    );
    let ok = Command::new("python3")
        .arg(&tool)
        .args(["terrain", "--tris", "1000000", "-o"])
        .arg(&path)
        .status()
        .map(|s| s.success())
        .unwrap_or(false);
    ok.then_some(path)
}

/// The harness binary: $EMBREE_BENCH, or built into the target folder by its build.sh.
fn locate_embree() -> Option<PathBuf> {
    if let Ok(p) = std::env::var("EMBREE_BENCH") {
        return Some(PathBuf::from(p)).filter(|p| p.exists());
    }
    let target = std::env::var("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|_| Path::new(env!("CARGO_MANIFEST_DIR")).join("target"));
    let out = target.join("embree");
    let bin = out.join("embree_bench");
    if bin.exists() {
        return Some(bin);
    }
    let script = shared_meshes()?.join("../bench/embree/build.sh");
    if !script.exists() {
        println!(
            "Embree: no harness at {} (set EMBREE_BENCH)",
            script.display()
        );
        return None;
    }
    if !Path::new("/usr/include/embree3/rtcore.h").exists() {
        println!("Embree: headers missing (apt-get install -y libembree-dev g++), skipping the comparison");
        return None;
    }
    let ok = Command::new("bash")
        .arg(&script)
        .arg(&out)
        .status()
        .map(|s| s.success())
        .unwrap_or(false);
    if !ok {
        println!(
            "Embree: {} failed, skipping the comparison",
            script.display()
        );
    }
    (ok && bin.exists()).then_some(bin)
}

/// A scene holding only this mesh (loaded by rtlab's own scene and OBJ loaders).
fn mesh_scene(obj: &Path, dir: &Path) -> Scene {
    let file = dir.join(format!(
        "{}.json",
        obj.file_stem().unwrap().to_string_lossy()
    ));
    let json = serde_json::json!({
        "camera": {"position": [0, 0, 1]},
        "objects": [{"name": "mesh", "shape": "mesh", "file": obj.to_string_lossy()}]
    });
    std::fs::write(&file, json.to_string()).expect("writable temp folder");
    Scene::load(&file).expect("the mesh loads")
}

// ---------------------------------------------------------------- the harness's camera

/// The harness's pinhole camera, computed in f32 exactly as embree_bench.cpp does (up to
/// the C++ compiler's freedom to fuse multiply-adds), so both trace the same rays.
struct HarnessCamera {
    eye: [f32; 3],
    fwd: [f32; 3],
    right: [f32; 3],
    upv: [f32; 3],
    hw: f32,
    hh: f32,
    light: [f32; 3],
    radius: f32,
}

type V = [f32; 3];
fn add(a: V, b: V) -> V {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn sub(a: V, b: V) -> V {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn mul(a: V, s: f32) -> V {
    [a[0] * s, a[1] * s, a[2] * s]
}
fn dot(a: V, b: V) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: V, b: V) -> V {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn norm(a: V) -> V {
    mul(a, 1.0 / dot(a, a).sqrt())
}

impl HarnessCamera {
    fn new(scene: &Scene) -> HarnessCamera {
        let Shape::Mesh(mesh) = &scene.objects[0].shape else {
            panic!("a mesh scene")
        };
        let (mut lo, mut hi) = ([1e30f32; 3], [-1e30f32; 3]);
        for p in &mesh.positions {
            let p = [p.x as f32, p.y as f32, p.z as f32];
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let c = mul(add(lo, hi), 0.5);
        let radius = 0.5 * dot(sub(hi, lo), sub(hi, lo)).sqrt();
        let eye = add(c, mul(norm([0.6, 0.5, 1.0]), 2.0 * radius));
        let light = add(c, mul([1.0, 2.0, 1.5], radius));
        let fwd = norm(sub(c, eye));
        let right = norm(cross(fwd, [0.0, 1.0, 0.0]));
        let upv = cross(right, fwd);
        let hh = (0.5f32 * 40.0 * std::f32::consts::PI / 180.0).tan();
        let hw = hh * W as f32 / H as f32;
        HarnessCamera {
            eye,
            fwd,
            right,
            upv,
            hw,
            hh,
            light,
            radius,
        }
    }

    fn ray(&self, x: usize, y: usize) -> Ray {
        let u = (2.0 * (x as f32 + 0.5) / W as f32 - 1.0) * self.hw;
        let v = (1.0 - 2.0 * (y as f32 + 0.5) / H as f32) * self.hh;
        let d = norm(add(add(self.fwd, mul(self.right, u)), mul(self.upv, v)));
        let w = |a: V| glam::DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64);
        Ray::new(w(self.eye), w(d))
    }
}

// ---------------------------------------------------------------- rtlab measurements

struct CameraPass {
    seconds: f64,
    hits: u64,
    sum_t: f64,
    /// t per pixel, negative for a miss.
    t: Vec<f64>,
}

/// Runs `f` on every tile the way `rtlab render` hands pixels to threads (its 16×16 tiles,
/// `rtlab::sampling::tiles`, in parallel) and returns its results in tile order.
fn per_tile<T: Send>(
    pool: &rayon::ThreadPool,
    f: impl Fn(&rtlab::sampling::Tile) -> T + Sync,
) -> Vec<T> {
    let tiles = rtlab::sampling::tiles(W as u32, H as u32);
    pool.install(|| tiles.par_iter().map(&f).collect())
}

/// One value per pixel of a tile, in the tile's row-major order.
fn each_pixel<T>(tile: &rtlab::sampling::Tile, mut f: impl FnMut(usize, usize) -> T) -> Vec<T> {
    let mut out = Vec::with_capacity(tile.len());
    for y in tile.y.clone() {
        for x in tile.x.clone() {
            out.push(f(x as usize, y as usize));
        }
    }
    out
}

/// Per-tile results back in row-major order (after the timing: the renderer does the same
/// when it gathers samples for the filter).
fn row_major<T: Copy>(per_tile: &[Vec<T>]) -> Vec<T> {
    rtlab::sampling::row_major_order(W as u32, H as u32)
        .map(|(t, l)| per_tile[t][l])
        .collect()
}

/// The camera rays through the scene (top-level BVH, then the mesh's): t per pixel (−1 for
/// a miss), hits and Σt (summed in row-major order).
fn camera_pass(scene: &Scene, cam: &HarnessCamera, pool: &rayon::ThreadPool) -> CameraPass {
    let start = Instant::now();
    let traced = per_tile(pool, |tile| {
        let mut rec = NoRecorder::default();
        each_pixel(tile, |x, y| {
            let ray = cam.ray(x, y);
            let hit = scene
                .accel
                .closest(&scene.objects, &ray, 0.0, f64::INFINITY, &mut rec);
            hit.map_or(-1.0, |(_, h)| h.t)
        })
    });
    let seconds = start.elapsed().as_secs_f64();
    let t = row_major(&traced);
    CameraPass {
        seconds,
        hits: t.iter().filter(|&&t| t >= 0.0).count() as u64,
        sum_t: t.iter().filter(|&&t| t >= 0.0).sum(),
        t,
    }
}

/// The same camera rays straight into the mesh's own BVH, skipping the scene level, with the
/// same bookkeeping as [`camera_pass`] (t per pixel): the price of the two-level design is
/// the difference.
fn mesh_only_seconds(scene: &Scene, cam: &HarnessCamera, pool: &rayon::ThreadPool) -> f64 {
    let Shape::Mesh(mesh) = &scene.objects[0].shape else {
        unreachable!()
    };
    let start = Instant::now();
    let traced = per_tile(pool, |tile| {
        each_pixel(tile, |x, y| {
            mesh.intersect(&cam.ray(x, y), 0.0, f64::INFINITY, &mut NoObserver)
                .map_or(-1.0, |h| h.t)
        })
    });
    let seconds = start.elapsed().as_secs_f64();
    std::hint::black_box(traced);
    seconds
}

/// The 4×4 blocks of pixels of a tile, one after another: `block(pixels)` gets each
/// block's pixels as (x, y, index in the tile's row-major order).
fn each_block(tile: &rtlab::sampling::Tile, mut block: impl FnMut(&[(usize, usize, usize)])) {
    let tw = tile.x.len();
    let mut pixels = arrayvec::ArrayVec::<_, 16>::new();
    for by in tile.y.clone().step_by(4) {
        for bx in tile.x.clone().step_by(4) {
            pixels.clear();
            for y in by..(by + 4).min(tile.y.end) {
                for x in bx..(bx + 4).min(tile.x.end) {
                    let local = (y - tile.y.start) as usize * tw + (x - tile.x.start) as usize;
                    pixels.push((x as usize, y as usize, local));
                }
            }
            block(&pixels);
        }
    }
}

/// The camera rays in bundles of 4×4 pixels within each tile, through
/// `Accel::closest_bundle_into`: seconds and t per pixel (−1 for a miss), row-major.
fn bundle_pass(scene: &Scene, cam: &HarnessCamera, pool: &rayon::ThreadPool) -> (f64, Vec<f64>) {
    use rtlab::accel::{BundleCost, BUNDLE};
    let start = Instant::now();
    let traced = per_tile(pool, |tile| {
        let mut t = vec![-1.0; tile.len()];
        let mut rays = [Ray::new(glam::DVec3::ZERO, glam::DVec3::X); BUNDLE];
        let mut hits = [None; BUNDLE];
        each_block(tile, |pixels| {
            for (ray, &(x, y, _)) in rays.iter_mut().zip(pixels) {
                *ray = cam.ray(x, y);
            }
            let mut cost = BundleCost::default();
            let rays = &rays[..pixels.len()];
            scene
                .accel
                .closest_bundle_into(&scene.objects, rays, 0.0, &mut cost, &mut hits);
            for (j, &(_, _, l)) in pixels.iter().enumerate() {
                t[l] = hits[j].as_ref().map_or(-1.0, |(_, h)| h.t);
            }
        });
        t
    });
    let seconds = start.elapsed().as_secs_f64();
    (seconds, row_major(&traced))
}

/// The harness's view as an rtlab scene (its eye, centre and 40° vertical field of view,
/// 1280×720, the mesh white diffuse, no lights): what `rtlab render` itself traces.
fn render_view(obj: &Path, cam: &HarnessCamera, dir: &Path) -> Scene {
    let file = dir.join(format!(
        "{}-view.json",
        obj.file_stem().unwrap().to_string_lossy()
    ));
    let at = cam.eye.map(|x| x as f64);
    let look = add(cam.eye, cam.fwd).map(|x| x as f64);
    let json = serde_json::json!({
        "camera": {"position": at, "look_at": look, "up": [0, 1, 0], "fov_y": 40,
                   "width": W, "height": H},
        "objects": [{"shape": "mesh", "file": obj.to_string_lossy()}]
    });
    std::fs::write(&file, json.to_string()).expect("writable temp folder");
    Scene::load(&file).expect("the view loads")
}

/// Camera rays per second of `rtlab render`'s own trace time on the view.
fn render_mrays(view: &Scene, traversal: rtlab::accel::Traversal, pool: &rayon::ThreadPool) -> f64 {
    render_mrays_counting(view, traversal, false, pool)
}

/// [`render_mrays`], with `count`: counting rays, tests and nodes as `render --stats` does.
fn render_mrays_counting(
    view: &Scene,
    traversal: rtlab::accel::Traversal,
    count: bool,
    pool: &rayon::ThreadPool,
) -> f64 {
    let mut settings = view.render.clone();
    settings.traversal = traversal;
    let out = pool.install(|| rtlab::sampling::render(view, &settings, count, None));
    (W * H) as f64 / out.trace_seconds / 1e6
}

/// The bundled render's trace taken apart on its own view, through the functions `render`
/// itself calls, block by block of its tiles: seconds to make every camera ray
/// (`rtlab::trace::camera_rays`, which `render` uses), and to make them and walk them to
/// their hits (`Accel::closest_bundle_into`). What the render adds on top (shading each hit
/// and each miss, keeping its colour for the filter, the tile's plan) is its trace time
/// minus the second.
fn render_parts(view: &Scene, pool: &rayon::ThreadPool, walk: bool) -> f64 {
    use rtlab::accel::{BundleCost, BUNDLE};
    use rtlab::trace::{camera_rays, CameraRay};
    let settings = &view.render;
    let start = Instant::now();
    let traced = per_tile(pool, |tile| {
        let mut cams: [CameraRay; BUNDLE] = std::array::from_fn(|_| CameraRay {
            ray: Ray::new(glam::DVec3::ZERO, glam::DVec3::Z),
            film: glam::DVec2::ZERO,
            lens: None,
            rng: rtlab::math::Rng::keyed([0; 4]),
        });
        let mut rays = [Ray::new(glam::DVec3::ZERO, glam::DVec3::Z); BUNDLE];
        let mut hits = [None; BUNDLE];
        let mut samples = arrayvec::ArrayVec::<_, BUNDLE>::new();
        let mut found = 0u32;
        each_block(tile, |pixels| {
            samples.clear();
            for &(x, y, _) in pixels {
                let centre = glam::DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
                samples.push((x as u32, y as u32, 0, centre));
            }
            camera_rays(view, settings, &samples, &mut cams);
            let n = pixels.len();
            for (ray, cam) in rays.iter_mut().zip(&cams[..n]) {
                *ray = cam.ray;
            }
            if walk {
                let mut cost = BundleCost::default();
                view.accel.closest_bundle_into(
                    &view.objects,
                    &rays[..n],
                    0.0,
                    &mut cost,
                    &mut hits,
                );
                found += hits[..n].iter().filter(|h| h.is_some()).count() as u32;
            } else {
                found += std::hint::black_box(&rays[..n]).len() as u32;
            }
        });
        found
    });
    let seconds = start.elapsed().as_secs_f64();
    std::hint::black_box(traced);
    seconds
}

/// Pixel (x, y)'s shadow ray, as the harness casts it: from its camera hit (None for a miss)
/// towards the light, with the distance to the light as t_max.
fn shadow_ray(cam: &HarnessCamera, camera: &CameraPass, x: usize, y: usize) -> Option<(Ray, f64)> {
    let t = camera.t[y * W + x];
    if t < 0.0 {
        return None;
    }
    let light = glam::DVec3::from_array(cam.light.map(|x| x as f64));
    let p = cam.ray(x, y).at(t);
    let to_light = light - p;
    let dist = to_light.length();
    Some((Ray::new(p, to_light / dist), dist))
}

/// One shadow ray per camera hit, towards the harness's light, from t_min = 1e-4·R as the
/// harness does. Returns (seconds, rays, occluded).
fn shadow_pass(
    scene: &Scene,
    cam: &HarnessCamera,
    camera: &CameraPass,
    pool: &rayon::ThreadPool,
) -> (f64, u64, u64) {
    let eps = 1e-4 * cam.radius as f64;
    let start = Instant::now();
    let traced = per_tile(pool, |tile| {
        let (mut rays, mut occluded) = (0u64, 0u64);
        let mut rec = NoRecorder::default();
        for (x, y) in tile.pixels() {
            let Some((ray, dist)) = shadow_ray(cam, camera, x as usize, y as usize) else {
                continue;
            };
            rays += 1;
            occluded += scene
                .accel
                .occluded(&scene.objects, &ray, eps, dist, &mut rec)
                .is_some() as u64;
        }
        (rays, occluded)
    });
    let seconds = start.elapsed().as_secs_f64();
    let (rays, occluded) = traced.iter().fold((0, 0), |a, b| (a.0 + b.0, a.1 + b.1));
    (seconds, rays, occluded)
}

/// The same shadow rays as [`shadow_pass`], in bundles: per 4×4 block of pixels of a tile,
/// the shadow rays of its pixels that hit, through `Accel::occluded_bundle`. Returns
/// (seconds, blocked or not per pixel that hit, row-major).
fn shadow_bundle_pass(
    scene: &Scene,
    cam: &HarnessCamera,
    camera: &CameraPass,
    pool: &rayon::ThreadPool,
) -> (f64, Vec<bool>) {
    use rtlab::accel::{BundleCost, BUNDLE};
    let eps = 1e-4 * cam.radius as f64;
    let start = Instant::now();
    let traced = per_tile(pool, |tile| {
        let mut blocked = vec![false; tile.len()];
        each_block(tile, |pixels| {
            let mut rays = arrayvec::ArrayVec::<Ray, BUNDLE>::new();
            let mut local = arrayvec::ArrayVec::<usize, BUNDLE>::new();
            let mut t_max = [0.0; BUNDLE];
            for &(x, y, l) in pixels {
                if let Some((ray, dist)) = shadow_ray(cam, camera, x, y) {
                    t_max[rays.len()] = dist;
                    rays.push(ray);
                    local.push(l);
                }
            }
            if rays.is_empty() {
                return;
            }
            let mut cost = BundleCost::default();
            let b = scene
                .accel
                .occluded_bundle(&scene.objects, &rays, eps, &t_max, &mut cost);
            for (j, &l) in local.iter().enumerate() {
                blocked[l] = b >> j & 1 == 1;
            }
        });
        blocked
    });
    let seconds = start.elapsed().as_secs_f64();
    let all = row_major(&traced);
    (
        seconds,
        all.iter()
            .zip(&camera.t)
            .filter(|(_, &t)| t >= 0.0)
            .map(|(&b, _)| b)
            .collect(),
    )
}

/// Blocked or not per pixel that hit, row-major: the single-ray verdicts [`shadow_pass`]
/// counts, for checking the bundles against.
fn shadow_verdicts(scene: &Scene, cam: &HarnessCamera, camera: &CameraPass) -> Vec<bool> {
    let eps = 1e-4 * cam.radius as f64;
    let mut rec = NoRecorder::default();
    (0..W * H)
        .filter_map(|i| shadow_ray(cam, camera, i % W, i / W))
        .map(|(ray, dist)| {
            scene
                .accel
                .occluded(&scene.objects, &ray, eps, dist, &mut rec)
                .is_some()
        })
        .collect()
}

fn build_seconds(scene: &Scene, pool: &rayon::ThreadPool) -> f64 {
    let Shape::Mesh(mesh) = &scene.objects[0].shape else {
        unreachable!()
    };
    let start = Instant::now();
    let built = pool.install(|| rtlab::shapes::Mesh::build_bvh(&mesh.positions, &mesh.faces));
    let s = start.elapsed().as_secs_f64();
    std::hint::black_box(built);
    s
}

/// Child process: load, build and trace the camera rays once, then report the peak
/// resident set (VmHWM) in KiB on stdout: the same work Embree's harness measures.
fn child_memory(obj: &Path) {
    let dir = tempfile::tempdir().expect("temp folder");
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(THREADS)
        .build()
        .expect("pool");
    let scene = pool.install(|| mesh_scene(obj, dir.path()));
    let cam = HarnessCamera::new(&scene);
    let pass = camera_pass(&scene, &cam, &pool);
    std::hint::black_box(pass.hits);
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let kib = status
        .lines()
        .find(|l| l.starts_with("VmHWM:"))
        .and_then(|l| l.split_whitespace().nth(1))
        .unwrap_or("0");
    println!("{kib}");
}

fn peak_memory_mib(obj: &Path) -> Option<f64> {
    let exe = std::env::current_exe().ok()?;
    let out = Command::new(exe)
        .arg("--child-mem")
        .arg(obj)
        .output()
        .ok()?;
    let kib: f64 = String::from_utf8_lossy(&out.stdout).trim().parse().ok()?;
    (kib > 0.0).then_some(kib / 1024.0)
}

// ---------------------------------------------------------------- Embree

#[derive(Default)]
struct EmbreeRun {
    build_ms: f64,
    single: f64,
    packet8: f64,
    packet16: f64,
    hits: u64,
    sum_t: f64,
    shadow: f64,
    shadow_rays: u64,
    occluded: u64,
    peak_mib: f64,
    /// Hit (true) or miss per pixel, from its depth image.
    mask: Vec<bool>,
}

/// One run of the harness over `modes`; its peak memory counts every mode's buffers, so the
/// memory column comes from a run of `single,shadow` alone (the modes it had before the
/// packet modes were added).
fn run_embree(bin: &Path, obj: &Path, ppm: &Path, modes: &str) -> Option<EmbreeRun> {
    let out = Command::new(bin)
        .arg(obj)
        .args(["--size", "1280x720", "--threads", "2", "--runs", "1"])
        .args(["--modes", modes, "--ppm"])
        .arg(ppm)
        .output()
        .ok()?;
    let text = String::from_utf8_lossy(&out.stdout);
    let mut r = EmbreeRun::default();
    let num = |s: &str| s.trim_end_matches(',').parse::<f64>().ok();
    for line in text.lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        let after = |key: &str| w.iter().position(|x| *x == key).and_then(|i| num(w[i + 1]));
        if line.starts_with("build_ms") {
            r.build_ms = after("median")?;
        } else if line.starts_with("single") {
            r.single = after("median")?;
            r.hits = w[w.iter().position(|x| *x == "hits")? + 1]
                .split('/')
                .next()?
                .parse()
                .ok()?;
            r.sum_t = after("sum_t")?;
        } else if line.starts_with("packet8") {
            r.packet8 = after("median")?;
        } else if line.starts_with("packet16") {
            r.packet16 = after("median")?;
        } else if line.starts_with("shadow") {
            r.shadow = after("median")?;
            r.shadow_rays = after("rays")? as u64;
            r.occluded = after("occluded")? as u64;
        } else if line.starts_with("peak_rss_mib") {
            r.peak_mib = after("peak_rss_mib")?;
        }
    }
    let bytes = std::fs::read(ppm).ok()?;
    let header = format!("P5\n{W} {H}\n255\n");
    if !bytes.starts_with(header.as_bytes()) {
        return None;
    }
    r.mask = bytes[header.len()..].iter().map(|&g| g != 0).collect();
    (r.mask.len() == W * H).then_some(r)
}

// ---------------------------------------------------------------- one mesh

struct MeshRow {
    name: String,
    triangles: usize,
    load_s: f64,
    explain_ms: f64,
    build_ms: f64,
    camera: f64,
    bundle: f64,
    /// The renderer's own trace time for the same view (generation, traversal, shading of
    /// a diffuse material without lights, film): single rays and bundles.
    render: f64,
    render_bundle: f64,
    /// The single-ray render again, counting as `--stats` does; and the bundled one.
    render_stats: f64,
    render_bundle_stats: f64,
    /// Seconds of the bundled render's own camera rays: made; made and walked.
    parts: (f64, f64),
    mesh_only: f64,
    shadow: f64,
    /// The same shadow rays in 4×4 bundles (`Accel::occluded_bundle`).
    shadow_bundle: f64,
    peak_mib: Option<f64>,
    bytes_per_tri: f64,
    hits: u64,
    sum_t: f64,
    occluded: (u64, u64),
    embree: Option<EmbreeSummary>,
}

struct EmbreeSummary {
    build_ms: f64,
    camera: f64,
    packet8: f64,
    packet16: f64,
    shadow: f64,
    peak_mib: f64,
    hits: u64,
    sum_t: f64,
    occluded: (u64, u64),
    pixels_differ: usize,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

fn bench_mesh(
    name: &str,
    obj: &Path,
    runs: usize,
    pool: &rayon::ThreadPool,
    embree: Option<&Path>,
    tmp: &Path,
) -> MeshRow {
    println!("== {name} ({})", obj.display());
    let t0 = Instant::now();
    let scene = pool.install(|| mesh_scene(obj, tmp));
    let load_s = t0.elapsed().as_secs_f64();
    let t1 = Instant::now();
    let e = rtlab::cli::explain::explain(&scene, scene.camera.width / 2, scene.camera.height / 2);
    let explain_ms = t1.elapsed().as_secs_f64() * 1e3;
    std::hint::black_box(e);
    let Shape::Mesh(mesh) = &scene.objects[0].shape else {
        unreachable!()
    };
    let triangles = mesh.faces.len();
    let bytes_per_tri = (mesh.accel_bytes()
        + mesh.faces.len() * 12
        + (mesh.positions.len() + mesh.normals.len()) * 24
        + mesh.uvs.len() * 16) as f64
        / triangles as f64;
    let cam = HarnessCamera::new(&scene);
    let ppm = tmp.join(format!("{name}.ppm"));
    let (mut b, mut c, mut m, mut s) = (vec![], vec![], vec![], vec![]);
    let (mut eb, mut ec, mut es, mut em) = (vec![], vec![], vec![], vec![]);
    let (mut e8, mut e16, mut bu, mut rs, mut rb) = (vec![], vec![], vec![], vec![], vec![]);
    let (mut rc, mut rbc, mut sb, mut pr, mut pw) = (vec![], vec![], vec![], vec![], vec![]);
    let view = render_view(obj, &cam, tmp);
    let mut last_embree = None;
    let mut last = None;
    for round in 0..runs {
        if let Some(bin) = embree {
            if let Some(e) = run_embree(bin, obj, &ppm, "single,packet8,packet16,shadow") {
                eb.push(e.build_ms);
                ec.push(e.single);
                e8.push(e.packet8);
                e16.push(e.packet16);
                es.push(e.shadow);
                em.push(
                    run_embree(bin, obj, &ppm, "single,shadow").map_or(e.peak_mib, |s| s.peak_mib),
                );
                last_embree = Some(e);
            } else if round == 0 {
                println!("  Embree harness failed on this mesh");
            }
        }
        b.push(build_seconds(&scene, pool) * 1e3);
        let pass = camera_pass(&scene, &cam, pool);
        c.push((W * H) as f64 / pass.seconds / 1e6);
        let (secs, rays, occ) = shadow_pass(&scene, &cam, &pass, pool);
        s.push(rays as f64 / secs / 1e6);
        let (secs, verdicts) = shadow_bundle_pass(&scene, &cam, &pass, pool);
        if round == 0 {
            assert!(
                verdicts == shadow_verdicts(&scene, &cam, &pass),
                "{name}: the shadow bundles found other verdicts than single rays"
            );
        }
        sb.push(rays as f64 / secs / 1e6);
        m.push((W * H) as f64 / mesh_only_seconds(&scene, &cam, pool) / 1e6);
        let bundled = bundle_pass(&scene, &cam, pool);
        assert!(
            bundled.1 == pass.t,
            "{name}: the bundles found other hits than single rays"
        );
        bu.push((W * H) as f64 / bundled.0 / 1e6);
        rs.push(render_mrays(&view, rtlab::accel::Traversal::Single, pool));
        rb.push(render_mrays(&view, rtlab::accel::Traversal::Bundle, pool));
        pr.push(render_parts(&view, pool, false));
        pw.push(render_parts(&view, pool, true));
        rc.push(render_mrays_counting(
            &view,
            rtlab::accel::Traversal::Single,
            true,
            pool,
        ));
        rbc.push(render_mrays_counting(
            &view,
            rtlab::accel::Traversal::Bundle,
            true,
            pool,
        ));
        println!(
            "  round {}: build {:.1} ms, camera {:.2} Mrays/s (bundles {:.2}, render {:.2} / {:.2}), shadow {:.2} Mrays/s{}",
            round + 1,
            b[round],
            c[round],
            bu[round],
            rs[round],
            rb[round],
            s[round],
            match (ec.last(), es.last()) {
                (Some(x), Some(y)) if ec.len() == round + 1 => format!(
                    "  | Embree build {:.1} ms, camera {x:.2}, shadow {y:.2}",
                    eb[round]
                ),
                _ => String::new(),
            }
        );
        last = Some((pass, rays, occ));
    }
    let (pass, rays, occ) = last.expect("at least one round");
    let embree = last_embree.map(|e| {
        let pixels_differ = e
            .mask
            .iter()
            .zip(&pass.t)
            .filter(|(&hit, &t)| hit != (t >= 0.0))
            .count();
        EmbreeSummary {
            build_ms: median(eb),
            camera: median(ec),
            packet8: median(e8),
            packet16: median(e16),
            shadow: median(es),
            peak_mib: median(em),
            hits: e.hits,
            sum_t: e.sum_t,
            occluded: (e.shadow_rays, e.occluded),
            pixels_differ,
        }
    });
    MeshRow {
        name: name.to_string(),
        triangles,
        load_s,
        explain_ms,
        build_ms: median(b),
        camera: median(c),
        bundle: median(bu),
        render: median(rs),
        render_bundle: median(rb),
        render_stats: median(rc),
        render_bundle_stats: median(rbc),
        parts: (median(pr), median(pw)),
        mesh_only: median(m),
        shadow: median(s),
        shadow_bundle: median(sb),
        peak_mib: peak_memory_mib(obj),
        bytes_per_tri,
        hits: pass.hits,
        sum_t: pass.sum_t,
        occluded: (rays, occ),
        embree,
    }
}

fn print_mesh_table(rows: &[MeshRow]) {
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

// ---------------------------------------------------------------- the Whitted scene

fn bench_whitted(runs: usize, pool: &rayon::ThreadPool, tmp: &Path) {
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
