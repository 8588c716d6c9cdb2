//! Shadow rays from the camera hits towards the harness's light: single and in bundles.

use crate::camera::HarnessCamera;
use crate::passes::{each_block, per_tile, row_major, CameraPass};
use crate::{H, W};
use rtlab::math::Ray;
use rtlab::scene::Scene;
use rtlab::trace::NoRecorder;
use std::time::Instant;

/// Pixel (x, y)'s shadow ray, as the harness casts it: from its camera hit (None for a miss)
/// towards the light, with the distance to the light as t_max.
#[inline]
pub fn shadow_ray(
    cam: &HarnessCamera,
    camera: &CameraPass,
    x: usize,
    y: usize,
) -> Option<(Ray, f64)> {
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
pub fn shadow_pass(
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
pub fn shadow_bundle_pass(
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
pub fn shadow_verdicts(scene: &Scene, cam: &HarnessCamera, camera: &CameraPass) -> Vec<bool> {
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
