//! rtlab's camera-ray passes over the harness's view (single rays, bundles, the mesh's own
//! BVH), the build, and the peak memory of a child process.

use crate::camera::HarnessCamera;
use crate::inputs::mesh_scene;
use crate::{H, THREADS, W};
use rayon::prelude::*;
use rtlab::math::Ray;
use rtlab::scene::Scene;
use rtlab::shapes::{NoObserver, Shape};
use rtlab::trace::NoRecorder;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

pub struct CameraPass {
    pub seconds: f64,
    pub hits: u64,
    pub sum_t: f64,
    /// t per pixel, negative for a miss.
    pub t: Vec<f64>,
}

/// Runs `f` on every tile the way `rtlab render` hands pixels to threads (its 16×16 tiles,
/// `rtlab::sampling::tiles`, in parallel) and returns its results in tile order.
pub fn per_tile<T: Send>(
    pool: &rayon::ThreadPool,
    f: impl Fn(&rtlab::sampling::Tile) -> T + Sync,
) -> Vec<T> {
    let tiles = rtlab::sampling::tiles(W as u32, H as u32);
    pool.install(|| tiles.par_iter().map(&f).collect())
}

/// One value per pixel of a tile, in the tile's row-major order.
pub fn each_pixel<T>(tile: &rtlab::sampling::Tile, mut f: impl FnMut(usize, usize) -> T) -> Vec<T> {
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
pub fn row_major<T: Copy>(per_tile: &[Vec<T>]) -> Vec<T> {
    rtlab::sampling::row_major_order(W as u32, H as u32)
        .map(|(t, l)| per_tile[t][l])
        .collect()
}

/// The camera rays through the scene (top-level BVH, then the mesh's): t per pixel (−1 for
/// a miss), hits and Σt (summed in row-major order).
pub fn camera_pass(scene: &Scene, cam: &HarnessCamera, pool: &rayon::ThreadPool) -> CameraPass {
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
pub fn mesh_only_seconds(scene: &Scene, cam: &HarnessCamera, pool: &rayon::ThreadPool) -> f64 {
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
pub fn each_block(tile: &rtlab::sampling::Tile, mut block: impl FnMut(&[(usize, usize, usize)])) {
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
pub fn bundle_pass(
    scene: &Scene,
    cam: &HarnessCamera,
    pool: &rayon::ThreadPool,
) -> (f64, Vec<f64>) {
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

pub fn build_seconds(scene: &Scene, pool: &rayon::ThreadPool) -> f64 {
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
pub fn child_memory(obj: &Path) {
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

pub fn peak_memory_mib(obj: &Path) -> Option<f64> {
    let exe = std::env::current_exe().ok()?;
    let out = Command::new(exe)
        .arg("--child-mem")
        .arg(obj)
        .output()
        .ok()?;
    let kib: f64 = String::from_utf8_lossy(&out.stdout).trim().parse().ok()?;
    (kib > 0.0).then_some(kib / 1024.0)
}
