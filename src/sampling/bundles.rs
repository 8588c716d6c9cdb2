//! Bundles of camera rays: a tile's camera rays grouped into 4×4 blocks of pixels (of
//! traced pixels, under `--subsample`; one sample index at a time), each block's rays walking the BVHs together
//! ([`crate::accel::Accel::closest_bundle_into`]). Only the closest hits are found this way;
//! the tracer then shades each sample as usual, from its hit ([`crate::trace::trace_camera`]).

use super::sampler::{centre, only_centres, planned_films_into, traces_samples};
use super::tiles::{Tile, TILE};
use crate::accel::{BundleCost, BUNDLE};
use crate::math::{Ray, Rng};
use crate::scene::{RenderSettings, Scene};
use crate::trace::{camera_rays, CameraRay, Found};
use arrayvec::ArrayVec;
use glam::{DVec2, DVec3};

/// Side of a bundle's block of pixels (BUNDLE = SIDE²).
pub const SIDE: u32 = 4;
const _: () = assert!((SIDE * SIDE) as usize == BUNDLE);

/// Bundles traced, the nodes they opened (each node once per bundle), the rays they held
/// and the most rays one held (16, or fewer under a coarse `--subsample`), for `--stats`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BundleTally {
    pub bundles: u64,
    pub opened: u64,
    pub rays: u64,
    pub most: u32,
}

impl BundleTally {
    pub fn add(&mut self, o: &BundleTally) {
        self.bundles += o.bundles;
        self.opened += o.opened;
        self.rays += o.rays;
        self.most = self.most.max(o.most);
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
/// Traces every sample of `plan` in bundles: per block of SIDE×SIDE of the tile's traced
/// pixels (`Blocks`) and per sample index, the block's camera rays are made side by side ([`camera_rays`]), walked to
/// their closest hits together ([`crate::accel::Accel::closest_bundle_into`]), and handed
/// one by one, hit found, to
/// `trace(l, (x, y), k, camera)` (the tile's pixel `l`, at (x, y), its sample `k`), which
/// shades them with the one tracer. `block_done(pixels)` follows each block and says whether
/// to go on (`false` stops the tile there); a cancelled render (`settings.cancel`) also stops
/// before the next block, and before the next sample index of a block.
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
    // The block's camera rays, made side by side into `cams[..n]`; the placeholders past
    // them are never read.
    let mut cams: [CameraRay; BUNDLE] = std::array::from_fn(|_| unmade());
    let mut pixels: ArrayVec<(usize, (u32, u32)), BUNDLE> = ArrayVec::new();
    let mut block: ArrayVec<(usize, (u32, u32)), BUNDLE> = ArrayVec::new();
    let mut samples: ArrayVec<(u32, u32, u32, DVec2), BUNDLE> = ArrayVec::new();
    let mut hits = BundleHits::default();
    let blocks = Blocks::of(settings, (scene.camera.width, scene.camera.height), tile);
    for (cols, rows) in blocks.iter() {
        if settings.cancel.is_cancelled() {
            return;
        }
        block_pixels(tile, (cols, rows), &mut block);
        let most = block.iter().map(|&(l, _)| plan.samples_of(l)).max();
        for k in 0..most.unwrap_or(0) {
            // A block holds all its pixels' samples: look again before each sample index.
            if k > 0 && settings.cancel.is_cancelled() {
                return;
            }
            block_samples(plan, &block, k, &mut pixels, &mut samples);
            camera_rays(scene, settings, &samples, &mut cams);
            let cams = &mut cams[..pixels.len()];
            hits.find(scene, cams, tally);
            for (j, (cam, &(l, xy))) in cams.iter_mut().zip(&pixels).enumerate() {
                trace(l, xy, k, cam, hits.found(j));
            }
        }
        if !block_done(cols.span.len() as u64 * rows.span.len() as u64) {
            return;
        }
    }
}
// ANCHOR_END: trace_bundled

/// A placeholder for a camera ray not made yet ([`camera_rays`] overwrites it).
fn unmade() -> CameraRay {
    CameraRay {
        ray: Ray::new(DVec3::ZERO, DVec3::Z),
        film: DVec2::ZERO,
        lens: None,
        rng: Rng::keyed([0; 4]),
    }
}

/// One group of a tile's traced columns (or rows): up to SIDE of them, standing for the
/// tile's lines `span` (from the group's first line to the next group's first; the first
/// group from the tile's edge, the last to its other edge).
struct Lines {
    traced: ArrayVec<u32, { SIDE as usize }>,
    span: std::ops::Range<u32>,
}

/// A tile's blocks: its traced columns and rows ([`traces_samples`]) taken SIDE at a time. A
/// block, columns × rows of one group each, holds up to SIDE×SIDE traced pixels and stands
/// for the tile's pixels of the groups' spans. Without `--subsample` every pixel traces and
/// the blocks are the tile's SIDE×SIDE squares; under `--subsample K` a block of SIDE traced
/// columns and rows stands for about (K·SIDE)² pixels and still holds a full bundle (the
/// progressive preview, `--subsample` 4, would otherwise trace bundles of one ray). A tile
/// with no traced column or row is one empty block, so that its pixels still count as done.
struct Blocks {
    cols: ArrayVec<Lines, { (TILE / SIDE) as usize }>,
    rows: ArrayVec<Lines, { (TILE / SIDE) as usize }>,
}

impl Blocks {
    fn of(settings: &RenderSettings, (width, height): (u32, u32), tile: &Tile) -> Blocks {
        // Row 0 and column 0 always trace: column x traces where pixel (x, 0) does.
        Blocks {
            cols: groups(tile.x.clone(), |x| {
                traces_samples(settings, width, height, x, 0)
            }),
            rows: groups(tile.y.clone(), |y| {
                traces_samples(settings, width, height, 0, y)
            }),
        }
    }

    /// The blocks, row by row: (columns, rows).
    fn iter(&self) -> impl Iterator<Item = (&Lines, &Lines)> {
        self.rows
            .iter()
            .flat_map(move |r| self.cols.iter().map(move |c| (c, r)))
    }
}

/// The traced pixels of the block of columns `cols` and rows `rows` into `block`, row by row:
/// each one's index in the tile and where it is on the image.
#[inline(always)]
fn block_pixels(
    tile: &Tile,
    (cols, rows): (&Lines, &Lines),
    block: &mut ArrayVec<(usize, (u32, u32)), BUNDLE>,
) {
    let tile_w = tile.x.len() as u32;
    block.clear();
    for &y in &rows.traced {
        for &x in &cols.traced {
            let l = ((y - tile.y.start) * tile_w + (x - tile.x.start)) as usize;
            block.push((l, (x, y)));
        }
    }
}

/// The traced lines of `range` (`traced(line)`), SIDE at a time ([`Lines`]); one empty group
/// spanning the whole range when none traces.
fn groups(
    range: std::ops::Range<u32>,
    traced: impl Fn(u32) -> bool,
) -> ArrayVec<Lines, { (TILE / SIDE) as usize }> {
    let mut groups: ArrayVec<Lines, { (TILE / SIDE) as usize }> = ArrayVec::new();
    for line in range.clone().filter(|&l| traced(l)) {
        match groups.last_mut() {
            Some(g) if !g.traced.is_full() => g.traced.push(line),
            last => {
                if let Some(g) = last {
                    g.span.end = line;
                }
                let start = if groups.is_empty() { range.start } else { line };
                let mut traced = ArrayVec::new();
                traced.push(line);
                groups.push(Lines {
                    traced,
                    span: start..range.end,
                });
            }
        }
    }
    if groups.is_empty() {
        groups.push(Lines {
            traced: ArrayVec::new(),
            span: range,
        });
    }
    groups
}

/// The bundle of sample index `k` of `block`: the block's pixels that have a sample `k` in
/// `plan` (those `--subsample` skips have none), into `pixels`, and their samples (pixel x,
/// y, `k`, film position), as [`camera_rays`] takes them, into `samples`.
#[inline(always)]
fn block_samples(
    plan: &TilePlan,
    block: &[(usize, (u32, u32))],
    k: u32,
    pixels: &mut ArrayVec<(usize, (u32, u32)), BUNDLE>,
    samples: &mut ArrayVec<(u32, u32, u32, DVec2), BUNDLE>,
) {
    pixels.clear();
    samples.clear();
    for &(l, (x, y)) in block.iter().filter(|&&(l, _)| k < plan.samples_of(l)) {
        samples.push((x, y, k, plan.sample(l, (x, y), k).0));
        pixels.push((l, (x, y)));
    }
}

/// One bundle of camera rays as a render traces it ([`bundle_of`]): ray `i` is the camera
/// ray (world space) of sample `sample` of pixel `pixels[i]`.
#[derive(Debug, Clone)]
pub struct Bundle {
    pub sample: u32,
    pub pixels: Vec<(u32, u32)>,
    pub rays: Vec<Ray>,
}

/// Why a render traces no bundle holding a given sample ([`bundle_of`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoBundle {
    /// `--traversal single`: every camera ray walks the BVHs alone.
    Single,
    /// `--traversal bundle`, but the camera rays go alone all the same ([`alone_because`]).
    Alone(&'static str),
    /// The pixel has no such sample (`--subsample` skips the pixel, or it has fewer).
    NoSample,
    /// The pixel's tile (its size) would plan more samples than the caller allows
    /// ([`bundle_of_within`]).
    TooMany { tile: (u32, u32), samples: u64 },
}

/// The bundle in which a render with `settings` traces sample `k` of pixel (x, y): the
/// pixel's block of its tile, the block's pixels that have a sample `k`, and their camera
/// rays, found by the code [`trace_bundled`] runs (the tile's plan, its blocks, their
/// samples, [`camera_rays`]). Fails with the reason when the render traces no such bundle.
/// Plans the pixel's whole tile: for one figure, not in a loop.
pub fn bundle_of(
    scene: &Scene,
    settings: &RenderSettings,
    (x, y): (u32, u32),
    k: u32,
) -> Result<Bundle, NoBundle> {
    bundle_of_within(scene, settings, (x, y), k, u64::MAX)
}

/// [`bundle_of`], refused ([`NoBundle::TooMany`]) when the pixel's tile would plan more than
/// `max_plan` samples (a server's bound: the plan is the whole tile's, 16 bytes a sample).
pub fn bundle_of_within(
    scene: &Scene,
    settings: &RenderSettings,
    (x, y): (u32, u32),
    k: u32,
    max_plan: u64,
) -> Result<Bundle, NoBundle> {
    if settings.traversal != crate::accel::Traversal::Bundle {
        return Err(NoBundle::Single);
    }
    if let Some(why) = alone_because(settings) {
        return Err(NoBundle::Alone(why));
    }
    let (w, h) = (scene.camera.width, scene.camera.height);
    if x >= w || y >= h {
        return Err(NoBundle::NoSample);
    }
    let tile = super::tiles::tile_of(w, h, x, y);
    let size = (tile.x.len() as u32, tile.y.len() as u32);
    let samples = super::samples_at_most(size, settings.sampler, settings.spp, 1);
    if samples > max_plan {
        return Err(NoBundle::TooMany {
            tile: size,
            samples,
        });
    }
    let plan = TilePlan::new(settings, w, h, &tile).ok_or(NoBundle::NoSample)?;
    let mut block = ArrayVec::new();
    let (mut pixels, mut samples) = (ArrayVec::new(), ArrayVec::new());
    for b in Blocks::of(settings, (w, h), &tile).iter() {
        block_pixels(&tile, b, &mut block);
        if block.iter().any(|&(_, p)| p == (x, y)) {
            break;
        }
    }
    block_samples(&plan, &block, k, &mut pixels, &mut samples);
    if !pixels.iter().any(|&(_, p)| p == (x, y)) {
        return Err(NoBundle::NoSample);
    }
    let mut cams: Vec<CameraRay> = (0..samples.len()).map(|_| unmade()).collect();
    camera_rays(scene, settings, &samples, &mut cams);
    Ok(Bundle {
        sample: k,
        pixels: pixels.iter().map(|&(_, p)| p).collect(),
        rays: cams.iter().map(|c| c.ray).collect(),
    })
}

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
        tally.rays += n as u64;
        tally.most = tally.most.max(n as u32);
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
