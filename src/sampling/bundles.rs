//! Bundles of camera rays: a tile's camera rays grouped into 4×4 blocks of pixels (one
//! sample index at a time), each block's rays walking the BVHs together
//! ([`crate::accel::Accel::closest_bundle`]). Only the closest hits are found this way; the
//! tracer then shades each sample as usual, from its hit ([`crate::trace::trace_camera`]).

use super::sampler::planned_films_into;
use super::tiles::Tile;
use crate::accel::{BundleCost, BUNDLE};
use crate::math::Ray;
use crate::scene::{RenderSettings, Scene};
use crate::trace::{camera_ray, CameraRay, Found};
use arrayvec::ArrayVec;
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

/// The camera rays of every sample of a tile, their closest hits already found in bundles
/// ([`tile_camera_rays`]), kept in one vector: pixel `l`'s samples (in the tile's row-major
/// order) are `rays[starts[l]..starts[l + 1]]`, by sample index.
pub struct TileCameras {
    rays: Vec<Option<CameraRay>>,
    starts: Vec<u32>,
}

impl TileCameras {
    /// The camera ray of sample `k` of the tile's pixel `local`, where it lies (tracing
    /// borrows it: [`crate::trace::trace_camera`]).
    pub fn get(&mut self, local: usize, k: usize) -> Option<&mut CameraRay> {
        let i = self.starts[local] as usize + k;
        if i < self.starts[local + 1] as usize {
            self.rays[i].as_mut()
        } else {
            None
        }
    }
}

/// The camera rays of every sample of `tile`, their closest hits found in bundles: a
/// [`TileCameras`]. `None` when the samples are not known before tracing (the adaptive
/// sampler): those rays go alone.
pub fn tile_camera_rays(
    scene: &Scene,
    settings: &RenderSettings,
    tile: &Tile,
    tally: &mut BundleTally,
) -> Option<TileCameras> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let mut films: Vec<DVec2> = Vec::with_capacity(tile.len());
    let mut starts: Vec<u32> = Vec::with_capacity(tile.len() + 1);
    starts.push(0);
    for (x, y) in tile.pixels() {
        if !planned_films_into(settings, w, h, x, y, &mut films) {
            return None;
        }
        starts.push(films.len() as u32);
    }
    let mut rays: Vec<Option<CameraRay>> = (0..films.len()).map(|_| None).collect();
    let tile_w = tile.x.len() as u32;
    let most = (0..tile.len())
        .map(|l| starts[l + 1] - starts[l])
        .max()
        .unwrap_or(0);
    // Per block of SIDE×SIDE pixels and per sample index: one bundle.
    let mut slots: ArrayVec<usize, BUNDLE> = ArrayVec::new();
    let mut samples: ArrayVec<(u32, u32, u32, DVec2), BUNDLE> = ArrayVec::new();
    for by in (tile.y.start..tile.y.end).step_by(SIDE as usize) {
        for bx in (tile.x.start..tile.x.end).step_by(SIDE as usize) {
            for k in 0..most {
                slots.clear();
                samples.clear();
                for y in by..(by + SIDE).min(tile.y.end) {
                    for x in bx..(bx + SIDE).min(tile.x.end) {
                        let local = ((y - tile.y.start) * tile_w + (x - tile.x.start)) as usize;
                        let i = starts[local] + k;
                        if i < starts[local + 1] {
                            slots.push(i as usize);
                            samples.push((x, y, k, films[i as usize]));
                        }
                    }
                }
                bundle_into(scene, settings, &samples, tally, |j, cam| {
                    rays[slots[j]] = Some(cam);
                });
            }
        }
    }
    Some(TileCameras { rays, starts })
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
        bundle_into(scene, settings, chunk, tally, |_, cam| out.push(cam));
    }
    out
}

/// One bundle: the camera rays of at most [`BUNDLE`] samples, made and traced together to
/// their closest hits, handed to `put(j, ray)` in the order of `samples`.
fn bundle_into(
    scene: &Scene,
    settings: &RenderSettings,
    samples: &[(u32, u32, u32, DVec2)],
    tally: &mut BundleTally,
    mut put: impl FnMut(usize, CameraRay),
) {
    if samples.is_empty() {
        return;
    }
    // Pushed one by one rather than collected: whether the compiler inlined `collect` (and
    // so built the 16 rays in place instead of copying them out) changed with how the crate
    // fell into codegen units, 130 instructions a pixel.
    let mut cams: ArrayVec<CameraRay, BUNDLE> = ArrayVec::new();
    for &(x, y, k, film) in samples {
        cams.push(camera_ray(scene, settings, x, y, k, film));
    }
    let rays: ArrayVec<Ray, BUNDLE> = cams.iter().map(|c| c.ray).collect();
    let mut cost = BundleCost::default();
    let hits = scene
        .accel
        .closest_bundle(&scene.objects, &rays, 0.0, &mut cost);
    tally.bundles += 1;
    tally.opened += cost.opened as u64;
    for (j, mut cam) in cams.into_iter().enumerate() {
        cam.found = Some(Found {
            hit: hits[j],
            tests: cost.tests[j],
            nodes: cost.nodes[j],
        });
        put(j, cam);
    }
}
