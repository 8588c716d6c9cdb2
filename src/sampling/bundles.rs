//! Bundles of camera rays: a tile's camera rays grouped into 4×4 blocks of pixels (one
//! sample index at a time), each block's rays walking the BVHs together
//! ([`crate::accel::Accel::closest_bundle`]). Only the closest hits are found this way; the
//! tracer then shades each sample as usual, from its hit ([`crate::trace::trace_camera`]).

use super::film::Tile;
use super::sampler::planned_films;
use crate::accel::{BundleCost, BUNDLE};
use crate::math::Ray;
use crate::scene::{RenderSettings, Scene};
use crate::trace::{camera_ray, CameraRay, Found};
use glam::DVec2;

/// Side of a bundle's block of pixels (BUNDLE = SIDE²).
pub const SIDE: u32 = 4;
const _: () = assert!((SIDE * SIDE) as usize == BUNDLE);

/// Bundles traced and the nodes they opened (each node once per bundle), for `--stats`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BundleTally {
    pub bundles: u64,
    pub opened: u64,
}

impl BundleTally {
    pub fn add(&mut self, o: &BundleTally) {
        self.bundles += o.bundles;
        self.opened += o.opened;
    }
}

/// The camera rays of every sample of `tile`, their closest hits found in bundles: for each
/// pixel of the tile (in its row-major order), its samples' rays by index. `None` when the
/// samples are not known before tracing (the adaptive sampler): those rays go alone.
pub fn tile_camera_rays(
    scene: &Scene,
    settings: &RenderSettings,
    tile: &Tile,
    tally: &mut BundleTally,
) -> Option<Vec<Vec<Option<CameraRay>>>> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let films: Vec<Vec<DVec2>> = tile
        .pixels()
        .map(|(x, y)| planned_films(settings, w, h, x, y))
        .collect::<Option<_>>()?;
    let mut out: Vec<Vec<Option<CameraRay>>> = films
        .iter()
        .map(|f| (0..f.len()).map(|_| None).collect())
        .collect();
    let tile_w = tile.x.len() as u32;
    let most = films.iter().map(Vec::len).max().unwrap_or(0);
    // Per block of SIDE×SIDE pixels and per sample index: one bundle.
    let mut members: Vec<(usize, usize)> = Vec::with_capacity(BUNDLE);
    let mut samples = Vec::with_capacity(BUNDLE);
    for by in (tile.y.start..tile.y.end).step_by(SIDE as usize) {
        for bx in (tile.x.start..tile.x.end).step_by(SIDE as usize) {
            for k in 0..most {
                members.clear();
                samples.clear();
                for y in by..(by + SIDE).min(tile.y.end) {
                    for x in bx..(bx + SIDE).min(tile.x.end) {
                        let local = ((y - tile.y.start) * tile_w + (x - tile.x.start)) as usize;
                        if let Some(&film) = films[local].get(k) {
                            members.push((local, k));
                            samples.push((x, y, k as u32, film));
                        }
                    }
                }
                for (cam, &(local, k)) in camera_rays(scene, settings, &samples, tally)
                    .into_iter()
                    .zip(&members)
                {
                    out[local][k] = Some(cam);
                }
            }
        }
    }
    Some(out)
}

/// The camera rays of `samples` (pixel x, y, sample index, film), each run of [`BUNDLE`]
/// consecutive ones traced together to their closest hits: callers list neighbours next
/// to each other.
pub fn camera_rays(
    scene: &Scene,
    settings: &RenderSettings,
    samples: &[(u32, u32, u32, DVec2)],
    tally: &mut BundleTally,
) -> Vec<CameraRay> {
    let mut out = Vec::with_capacity(samples.len());
    for chunk in samples.chunks(BUNDLE) {
        let cams = chunk
            .iter()
            .map(|&(x, y, k, film)| camera_ray(scene, settings, x, y, k, film));
        let start = out.len();
        out.extend(cams);
        let rays: Vec<Ray> = out[start..].iter().map(|c| c.ray).collect();
        let mut cost = BundleCost::default();
        let hits = scene
            .accel
            .closest_bundle(&scene.objects, &rays, 0.0, &mut cost);
        tally.bundles += 1;
        tally.opened += cost.opened as u64;
        for (j, cam) in out[start..].iter_mut().enumerate() {
            cam.found = Some(Found {
                hit: hits[j],
                tests: cost.tests[j],
                nodes: cost.nodes[j],
            });
        }
    }
    out
}
