//! Bundles of camera rays: a tile's camera rays grouped into 4×4 blocks of pixels (one
//! sample index at a time), each block's rays walking the BVHs together
//! ([`crate::accel::Accel::closest_bundle_into`]). Only the closest hits are found this way;
//! the tracer then shades each sample as usual, from its hit ([`crate::trace::trace_camera`]).

use super::sampler::{centre, only_centres, planned_films_into};
use super::tiles::Tile;
use crate::accel::{BundleCost, BUNDLE};
use crate::math::{Ray, Rng};
use crate::scene::{RenderSettings, Scene};
use crate::trace::{camera_rays, CameraRay, Found};
use arrayvec::ArrayVec;
use glam::{DVec2, DVec3};

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

/// Do a render's camera rays go in bundles? When asked to (`--traversal bundle`), unless
/// [`alone_because`] gives a reason they cannot.
pub fn bundled(settings: &RenderSettings) -> bool {
    settings.traversal == crate::accel::Traversal::Bundle && alone_because(settings).is_none()
}

/// Why a render's camera rays go alone even with `--traversal bundle` (`--stats` says it): a
/// mistake changes which object a ray hits (every ray then takes the mistaken single-ray
/// path), or the adaptive sampler decides its samples while it traces.
pub fn alone_because(settings: &RenderSettings) -> Option<&'static str> {
    if settings.mistakes.changes_hits() {
        Some("a mistake that changes which object a ray hits is on")
    } else if settings.sampler == crate::scene::SamplerKind::Adaptive {
        Some("the adaptive sampler decides its samples while it traces")
    } else {
        None
    }
}

/// Where a tile's samples go, pixel by pixel in the tile's row-major order, by sample index.
pub enum TilePlan {
    /// One sample at each pixel's centre (the common case): nothing to list, sample l of
    /// the tile is pixel l's.
    Centres { len: usize },
    /// The film positions of every sample of the tile; pixel `l`'s are
    /// `films[starts[l]..starts[l + 1]]`.
    Listed { films: Vec<DVec2>, starts: Vec<u32> },
}

impl TilePlan {
    /// The tile's samples, or `None` when they are not known before tracing (the adaptive
    /// sampler decides from what it sees): those pixels go alone.
    pub fn new(settings: &RenderSettings, width: u32, height: u32, tile: &Tile) -> Option<Self> {
        if only_centres(settings) {
            return Some(TilePlan::Centres { len: tile.len() });
        }
        let mut films: Vec<DVec2> = Vec::with_capacity(tile.len());
        let mut starts: Vec<u32> = Vec::with_capacity(tile.len() + 1);
        starts.push(0);
        for (x, y) in tile.pixels() {
            if !planned_films_into(settings, width, height, x, y, &mut films) {
                return None;
            }
            starts.push(films.len() as u32);
        }
        Some(TilePlan::Listed { films, starts })
    }

    /// A plan of every pixel of `tile`, pixel (x, y)'s samples at `films(x, y)`.
    pub fn of(tile: &Tile, mut films: impl FnMut(u32, u32) -> Vec<DVec2>) -> Self {
        let (mut all, mut starts) = (
            Vec::with_capacity(tile.len()),
            Vec::with_capacity(tile.len() + 1),
        );
        starts.push(0);
        for (x, y) in tile.pixels() {
            all.extend(films(x, y));
            starts.push(all.len() as u32);
        }
        TilePlan::Listed { films: all, starts }
    }

    /// Sample `k` of the tile's pixel `l`, at (x, y): its film position, and its place among
    /// all the tile's samples.
    #[inline]
    pub fn sample(&self, l: usize, (x, y): (u32, u32), k: u32) -> (DVec2, usize) {
        match self {
            TilePlan::Centres { .. } => (centre(x, y), l),
            TilePlan::Listed { films, starts } => {
                let i = (starts[l] + k) as usize;
                (films[i], i)
            }
        }
    }

    /// Samples of the tile's pixel `l`.
    #[inline]
    pub fn samples_of(&self, l: usize) -> u32 {
        match self {
            TilePlan::Centres { .. } => 1,
            TilePlan::Listed { starts, .. } => starts[l + 1] - starts[l],
        }
    }
}

// ANCHOR: trace_bundled
/// Traces every sample of `plan` in bundles: per SIDE×SIDE block of the tile's pixels and per
/// sample index, the block's camera rays are made side by side ([`camera_rays`]), walked to
/// their closest hits together ([`crate::accel::Accel::closest_bundle_into`]), and handed
/// one by one, hit found, to
/// `trace(l, (x, y), k, camera)` (the tile's pixel `l`, at (x, y), its sample `k`), which
/// shades them with the one tracer. `block_done(pixels)` follows each block and says whether
/// to go on (`false` stops the tile there); a cancelled render (`settings.cancel`) also stops
/// before the next block.
#[inline(never)] // once per tile; and a profiler sees it whole
pub fn trace_bundled(
    scene: &Scene,
    settings: &RenderSettings,
    tile: &Tile,
    plan: &TilePlan,
    tally: &mut BundleTally,
    mut trace: impl FnMut(usize, (u32, u32), u32, &mut CameraRay, Found),
    mut block_done: impl FnMut(u64) -> bool,
) {
    let tile_w = tile.x.len() as u32;
    // The block's camera rays, made side by side into `cams[..n]`; the placeholders past
    // them are never read.
    let mut cams: [CameraRay; BUNDLE] = std::array::from_fn(|_| CameraRay {
        ray: Ray::new(DVec3::ZERO, DVec3::Z),
        film: DVec2::ZERO,
        lens: None,
        rng: Rng::keyed([0; 4]),
    });
    let mut pixels: ArrayVec<(usize, (u32, u32)), BUNDLE> = ArrayVec::new();
    let mut block: ArrayVec<(usize, (u32, u32)), BUNDLE> = ArrayVec::new();
    let mut samples: ArrayVec<(u32, u32, u32, DVec2), BUNDLE> = ArrayVec::new();
    let mut hits = BundleHits::default();
    for by in (tile.y.start..tile.y.end).step_by(SIDE as usize) {
        for bx in (tile.x.start..tile.x.end).step_by(SIDE as usize) {
            if settings.cancel.is_cancelled() {
                return;
            }
            // The block's pixels: the tile's pixel index and where it is on the image.
            block.clear();
            for y in by..(by + SIDE).min(tile.y.end) {
                for x in bx..(bx + SIDE).min(tile.x.end) {
                    let l = ((y - tile.y.start) * tile_w + (x - tile.x.start)) as usize;
                    block.push((l, (x, y)));
                }
            }
            let most = block.iter().map(|&(l, _)| plan.samples_of(l)).max();
            for k in 0..most.unwrap_or(0) {
                pixels.clear();
                samples.clear();
                for &(l, (x, y)) in block.iter().filter(|&&(l, _)| k < plan.samples_of(l)) {
                    samples.push((x, y, k, plan.sample(l, (x, y), k).0));
                    pixels.push((l, (x, y)));
                }
                camera_rays(scene, settings, &samples, &mut cams);
                let cams = &mut cams[..pixels.len()];
                hits.find(scene, cams, tally);
                for (j, (cam, &(l, xy))) in cams.iter_mut().zip(&pixels).enumerate() {
                    trace(l, xy, k, cam, hits.found(j));
                }
            }
            if !block_done(block.len() as u64) {
                return;
            }
        }
    }
}
// ANCHOR_END: trace_bundled

/// One bundle's results: each camera ray's closest hit and its share of the work.
struct BundleHits {
    hits: [Option<(usize, crate::shapes::LocalHit)>; BUNDLE],
    cost: BundleCost,
}

impl Default for BundleHits {
    fn default() -> Self {
        BundleHits {
            hits: [None; BUNDLE],
            cost: BundleCost::default(),
        }
    }
}

impl BundleHits {
    /// Walks up to [`BUNDLE`] camera rays to their closest hits together.
    fn find(&mut self, scene: &Scene, cams: &[CameraRay], tally: &mut BundleTally) {
        let n = cams.len();
        if n == 0 {
            return;
        }
        let mut rays = [Ray::new(DVec3::ZERO, DVec3::Z); BUNDLE];
        for (ray, cam) in rays.iter_mut().zip(cams) {
            *ray = cam.ray;
        }
        self.cost = BundleCost::default();
        scene.accel.closest_bundle_into(
            &scene.objects,
            &rays[..n],
            0.0,
            &mut self.cost,
            &mut self.hits,
        );
        tally.bundles += 1;
        tally.opened += self.cost.opened as u64;
    }

    /// Ray j's hit and share of the work.
    fn found(&self, j: usize) -> Found<'_> {
        Found {
            hit: self.hits[j].as_ref(),
            tests: self.cost.tests[j],
            nodes: self.cost.nodes[j],
        }
    }
}
