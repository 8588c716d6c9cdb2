use super::bundles::{tile_camera_rays, BundleTally};
use super::sampler::sample_pixel_into;
use super::{Filter, PixelSample};
use crate::accel::Traversal;
use crate::mistakes::{Mistake, Mistakes};
use crate::scene::{Encoding, RenderSettings, Scene};
use crate::trace::{camera_ray, trace_camera, Counter, NoRecorder, RayCounts, Recorder};
use glam::{DVec2, DVec3};
use rayon::prelude::*;
use std::time::Instant;

/// A linear-colour image, row-major from the top-left.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<DVec3>,
}

impl Image {
    pub fn get(&self, x: u32, y: u32) -> DVec3 {
        self.pixels[(y * self.width + x) as usize]
    }
    /// The bytes of this image under an encoding (RGB, 3 bytes a pixel).
    pub fn to_rgb8(&self, encoding: Encoding) -> image::RgbImage {
        let mut out = image::RgbImage::new(self.width, self.height);
        for (p, c) in out.pixels_mut().zip(&self.pixels) {
            *p = image::Rgb(encode(*c, encoding));
        }
        out
    }

    /// The bytes of this image as the settings encode them: their encoding, and the
    /// catalogue's byte mistakes (`srgb-gamma`, `round-bytes`) when they are on.
    pub fn to_rgb8_for(&self, settings: &RenderSettings) -> image::RgbImage {
        if settings.mistakes.is_empty() {
            return self.to_rgb8(settings.encoding);
        }
        let mut out = image::RgbImage::new(self.width, self.height);
        for (p, c) in out.pixels_mut().zip(&self.pixels) {
            *p = image::Rgb(encode_as(*c, settings.encoding, settings.mistakes));
        }
        out
    }
}

/// One pixel's bytes. `Clamp`: floor(255·min(max(c, 0), 1)), no gamma, as the course's
/// reference images are made. `Srgb`: the sRGB transfer curve, rounded.
pub fn encode(c: DVec3, encoding: Encoding) -> [u8; 3] {
    encode_as(c, encoding, Mistakes::NONE)
}

// ANCHOR: encode
/// [`encode`] under the catalogue's byte mistakes: `srgb-gamma` applies the sRGB curve to the
/// course's linear encoding, `round-bytes` rounds instead of truncating.
pub fn encode_as(c: DVec3, encoding: Encoding, mistakes: Mistakes) -> [u8; 3] {
    let f = |x: f64| -> u8 {
        let x = if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) };
        let srgb = |x: f64| {
            if x >= 1.0 {
                1.0 // not 1.055 − 0.055, a hair below 1
            } else if x <= 0.003_130_8 {
                12.92 * x
            } else {
                1.055 * x.powf(1.0 / 2.4) - 0.055
            }
        };
        match encoding {
            Encoding::Clamp => {
                let x = if mistakes.has(Mistake::SrgbGamma) {
                    srgb(x)
                } else {
                    x
                };
                if mistakes.has(Mistake::RoundBytes) {
                    (255.0 * x).round() as u8
                } else {
                    (255.0 * x).floor() as u8
                }
            }
            Encoding::Srgb => (255.0 * srgb(x)).round() as u8,
        }
    };
    [f(c.x), f(c.y), f(c.z)]
}
// ANCHOR_END: encode

/// What the counting recorder saw over a whole render.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RenderStats {
    pub rays: RayCounts,
    pub tests: u64,
    pub nodes: u64,
    /// Intersection tests + BVH nodes per pixel (the `cost` AOV), row-major.
    pub cost: Vec<u64>,
    /// BVH nodes visited per pixel (the scene's and the meshes'), row-major.
    pub pixel_nodes: Vec<u64>,
    /// Intersection tests per pixel (objects, and faces inside meshes), row-major.
    pub pixel_tests: Vec<u64>,
    /// Bundles of camera rays traced (`--traversal bundle`) and the nodes they opened.
    pub bundles: BundleTally,
}

pub struct RenderOutput {
    pub image: Image,
    pub stats: Option<RenderStats>,
    pub trace_seconds: f64,
    /// The first sample whose colour was not finite: (x, y, sample index).
    pub first_nan: Option<(u32, u32, u32)>,
    /// Samples each pixel traced, row-major (corner samples count for the pixel that owns
    /// them; 0 for pixels skipped by `--subsample`). Always filled; it is the interesting one
    /// for the adaptive sampler (draw it with [`crate::viz::heatmap::spp_heat_map`]).
    pub spp_map: Option<Vec<u32>>,
    /// Samples whose tree the ray budget (`max_rays`) cut.
    pub cut_samples: u64,
    /// The first cut sample in row-major order of pixels: (x, y, sample index).
    pub first_cut: Option<(u32, u32, u32)>,
    /// `settings.cancel` was cancelled (or Ctrl-C pressed) during the render: some pixels
    /// were skipped or cut short, so the image is not to be used.
    pub cancelled: bool,
}

/// Side of the square tiles a render hands out to threads. Neighbouring rays open the same
/// BVH nodes and test the same faces, so a tile keeps them in the core's cache far better
/// than a row 1280 pixels long does (about 5–10 % more camera rays per second on a
/// million-triangle mesh).
pub const TILE: u32 = 16;

/// A block of pixels: columns `x`, rows `y` (ends excluded).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Tile {
    pub x: std::ops::Range<u32>,
    pub y: std::ops::Range<u32>,
}

impl Tile {
    /// Its pixels, row by row.
    pub fn pixels(&self) -> impl Iterator<Item = (u32, u32)> + '_ {
        self.y
            .clone()
            .flat_map(move |y| self.x.clone().map(move |x| (x, y)))
    }

    pub fn len(&self) -> usize {
        self.x.len() * self.y.len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// The image cut into [`TILE`]×[`TILE`] tiles (narrower at the right and bottom edges),
/// listed row by row of tiles: tile `(y / TILE) · ⌈width / TILE⌉ + x / TILE` holds pixel
/// (x, y).
pub fn tiles(width: u32, height: u32) -> Vec<Tile> {
    (0..height.div_ceil(TILE))
        .flat_map(|ty| {
            (0..width.div_ceil(TILE)).map(move |tx| Tile {
                x: tx * TILE..((tx + 1) * TILE).min(width),
                y: ty * TILE..((ty + 1) * TILE).min(height),
            })
        })
        .collect()
}

/// Where each pixel's result sits among per-tile results (tile by tile, each in its tile's
/// row-major order, as [`tiles`] lists them): for every pixel in row-major order, (tile,
/// index within the tile).
pub fn row_major_order(width: u32, height: u32) -> impl Iterator<Item = (usize, usize)> {
    let across = width.div_ceil(TILE);
    (0..height).flat_map(move |y| {
        (0..width).map(move |x| {
            let t = ((y / TILE) * across + x / TILE) as usize;
            // Tiles are TILE wide except the last of a row of tiles.
            let tile_width = TILE.min(width - (x / TILE) * TILE);
            let local = (y % TILE) * tile_width + x % TILE;
            (t, local as usize)
        })
    })
}

/// Renders the scene. With `count`, a [`Counter`] records rays, tests and nodes per pixel;
/// otherwise the zero-cost [`NoRecorder`] runs. Tiles ([`tiles`]) are traced in parallel and
/// gathered back into rows, and each sample's randomness depends only on its own key, so the result is the
/// same on any number of threads.
pub fn render(
    scene: &Scene,
    settings: &RenderSettings,
    count: bool,
    progress: Option<&indicatif::ProgressBar>,
) -> RenderOutput {
    render_until(scene, settings, count, progress, &|| false)
        .expect("a render nothing stops runs to the end")
}

/// [`render`], but `stop()` is asked before each tile: once it says yes, the remaining tiles
/// are skipped and there is no image (`None`). Progressive rendering
/// ([`super::progressive`]) stops a pass this way when its time is up or its caller cancels.
/// Ctrl-C ([`crate::interrupt`]) skips the tiles as well, but still returns an (empty) output.
pub fn render_until(
    scene: &Scene,
    settings: &RenderSettings,
    count: bool,
    progress: Option<&indicatif::ProgressBar>,
    stop: &(dyn Fn() -> bool + Sync),
) -> Option<RenderOutput> {
    if count {
        render_with::<Counter>(scene, settings, progress, stop)
    } else {
        render_with::<NoRecorder>(scene, settings, progress, stop)
    }
}

/// [`render`] that gives up (`None`) once `cancel` is set, checked before each tile: the
/// server cancels a render that a newer one superseded.
pub fn render_cancellable(
    scene: &Scene,
    settings: &RenderSettings,
    cancel: &std::sync::atomic::AtomicBool,
) -> Option<RenderOutput> {
    let stop = || cancel.load(std::sync::atomic::Ordering::Relaxed);
    render_until(scene, settings, false, None, &stop).filter(|o| !o.cancelled)
}

trait Tally: Recorder + Default + Send {
    /// Does it count anything (does `into_stats` return `Some`)?
    const COUNTS: bool;
    fn into_stats(self) -> Option<(RayCounts, u64, u64)>;
}
impl Tally for NoRecorder {
    const COUNTS: bool = false;
    fn into_stats(self) -> Option<(RayCounts, u64, u64)> {
        None
    }
}
impl Tally for Counter {
    const COUNTS: bool = true;
    fn into_stats(self) -> Option<(RayCounts, u64, u64)> {
        Some((self.rays, self.total_tests(), self.total_nodes()))
    }
}

fn render_with<R: Tally>(
    scene: &Scene,
    settings: &RenderSettings,
    progress: Option<&indicatif::ProgressBar>,
    stop: &(dyn Fn() -> bool + Sync),
) -> Option<RenderOutput> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let stopped = std::sync::atomic::AtomicBool::new(false);
    let start = Instant::now();
    /// One tile's samples (all in one vector, pixel by pixel in the tile's own row-major
    /// order, with where each pixel's start: `ends[l]` is one past pixel l's last) and
    /// counts, its first non-finite sample, and its samples the ray budget cut (count, first).
    type Traced = (
        (Vec<PixelSample>, Vec<u32>),
        (Vec<[u64; 2]>, RayCounts),
        Option<(u32, u32, u32)>,
        (u64, Option<(u32, u32, u32)>),
        BundleTally,
    );
    // Under a mistake that changes hits, every ray takes the mistaken single-ray path.
    let bundled = settings.traversal == Traversal::Bundle && !settings.mistakes.changes_hits();
    let tiles = tiles(w, h);
    let traced: Vec<Traced> = tiles
        .par_iter()
        .map(|tile| {
            if stopped.load(std::sync::atomic::Ordering::Relaxed) || stop() {
                stopped.store(true, std::sync::atomic::Ordering::Relaxed);
                return Default::default();
            }
            let mut tally = BundleTally::default();
            // Bundles: every camera ray of the tile, its closest hit already found.
            let mut cameras = bundled
                .then(|| tile_camera_rays(scene, settings, tile, &mut tally))
                .flatten();
            let mut samples = Vec::with_capacity(tile.len() * (settings.spp as usize).min(16));
            let mut ends = Vec::with_capacity(tile.len());
            // Filled only when counting (`--stats`): a render without it touches no memory
            // for counts (it was 64 bytes a pixel, a tenth of its trace time in page faults).
            // With it, 16 bytes a pixel (its tests and nodes) and the tile's ray counts.
            let mut stats = Vec::with_capacity(if R::COUNTS { tile.len() } else { 0 });
            let mut tile_rays = RayCounts::default();
            let mut nan = None;
            let mut cut = (0, None);
            for (local, (x, y)) in tile.pixels().enumerate() {
                if settings.cancel.is_cancelled() {
                    // Ctrl-C or a cancelled token: skip the rest; the caller writes nothing.
                    break;
                }
                let mut rec = R::default();
                sample_pixel_into(settings, w, h, x, y, &mut samples, |k, film| {
                    let mut own = None;
                    let camera = match cameras.as_mut().and_then(|c| c.get(local, k as usize)) {
                        Some(bundled) => bundled,
                        None => own.insert(camera_ray(scene, settings, x, y, k, film)),
                    };
                    debug_assert_eq!(camera.generation.film, film);
                    let r = trace_camera(scene, settings, camera, &mut rec);
                    if r.cut {
                        cut.0 += 1;
                        cut.1.get_or_insert((x, y, k));
                    }
                    if r.color.is_finite() {
                        r.color
                    } else {
                        nan.get_or_insert((x, y, k));
                        DVec3::ZERO
                    }
                });
                ends.push(samples.len() as u32);
                if let Some((rays, tests, nodes)) = rec.into_stats() {
                    tile_rays.add(&rays);
                    stats.push([tests, nodes]);
                }
                // Pixel by pixel, so the bar moves while a slow tile is still being traced.
                if let Some(p) = progress {
                    p.inc(1);
                }
            }
            ((samples, ends), (stats, tile_rays), nan, cut, tally)
        })
        .collect();
    let trace_seconds = start.elapsed().as_secs_f64();
    if stopped.into_inner() {
        return None;
    }
    if settings.cancel.is_cancelled() {
        // Some tiles were skipped: there is no image to reconstruct (and none will be written).
        return Some(RenderOutput {
            image: Image {
                width: w,
                height: h,
                pixels: vec![DVec3::ZERO; w as usize * h as usize],
            },
            stats: None,
            trace_seconds,
            first_nan: None,
            spp_map: None,
            cut_samples: 0,
            first_cut: None,
            cancelled: true,
        });
    }

    // The first in row-major order (a tile's own first is its first in that order too).
    let first_nan = traced
        .iter()
        .filter_map(|t| t.2)
        .min_by_key(|&(x, y, _)| (y, x));
    let cut_samples = traced.iter().map(|t| t.3 .0).sum();
    let first_cut = traced
        .iter()
        .filter_map(|t| t.3 .1)
        .min_by_key(|&(x, y, _)| (y, x));
    let mut stats: Option<RenderStats> = None;
    // Counting, every pixel of every tile has its counts (a short tile was cancelled, and a
    // cancelled render returned above): index them, so that a gap could never shift a
    // pixel's counts onto another.
    let counted = row_major_order(w, h).filter(|_| R::COUNTS);
    for [tests, nodes] in counted.map(|(t, l)| traced[t].1 .0[l]) {
        let st = stats.get_or_insert_with(RenderStats::default);
        st.tests += tests;
        st.nodes += nodes;
        st.cost.push(tests + nodes);
        st.pixel_tests.push(tests);
        st.pixel_nodes.push(nodes);
    }
    if let Some(st) = stats.as_mut() {
        for t in &traced {
            st.rays.add(&t.1 .1);
            st.bundles.add(&t.4);
        }
    }
    let grid: Vec<&[PixelSample]> = row_major_order(w, h)
        .map(|(t, l)| {
            let (samples, ends) = &traced[t].0;
            let start = if l == 0 { 0 } else { ends[l - 1] as usize };
            &samples[start..ends[l] as usize]
        })
        .collect();
    let spp_map = Some(grid.iter().map(|s| s.len() as u32).collect());
    let filter = Filter::for_settings(settings);
    let pixels = (0..h)
        .into_par_iter()
        .flat_map_iter(|y| {
            let grid = &grid;
            (0..w).map(move |x| {
                reconstruct_color(&filter, (x, y), (w, h), settings.subsample, |qx, qy| {
                    grid[(qy * w + qx) as usize]
                        .iter()
                        .map(|s| (s.film, s.color, s.area))
                })
            })
        })
        .collect();
    Some(RenderOutput {
        image: Image {
            width: w,
            height: h,
            pixels,
        },
        stats,
        trace_seconds,
        first_nan,
        spp_map,
        cut_samples,
        first_cut,
        cancelled: false,
    })
}

// ANCHOR: reconstruct
/// Pixel (x, y) as the filter-weighted mean of every sample within the filter's reach,
/// neighbours' samples included: Σ w(s − centre)·a(s)·c(s) / Σ w·a, where a(s) is the share
/// of the film the sample stands for (1, except for the adaptive sampler's cells).
/// `samples_of(qx, qy)` gives the (film, colour, area) of the samples pixel q owns. Returns the
/// colour and the normalised weight of each sample, pixel by pixel (for `explain`). Pixels are
/// visited in a fixed order, so the sum is the same on any number of threads.
pub fn reconstruct<I: IntoIterator<Item = (DVec2, DVec3, f64)>>(
    filter: &Filter,
    x: u32,
    y: u32,
    width: u32,
    height: u32,
    samples_of: impl Fn(u32, u32) -> I,
) -> (DVec3, Vec<(u32, u32, usize, f64)>) {
    let mut weights = Vec::new();
    let every = Lines(1);
    let (sum, total) = accumulate(
        filter,
        (x, y),
        (width, height),
        every,
        samples_of,
        |qx, qy, k, w| weights.push((qx, qy, k, w)),
    );
    if total.abs() < 1e-12 {
        return (DVec3::ZERO, weights);
    }
    for w in &mut weights {
        w.3 /= total;
    }
    (sum / total, weights)
}

/// The rows (or columns) of pixels that may own samples: under `--subsample K`, the
/// multiples of K and the last one ([`super::traces_samples`]); `Lines(1)`, every one.
#[derive(Clone, Copy)]
struct Lines(u32);

impl Lines {
    /// Those of lo..=hi (within 0..n), in increasing order.
    fn within(self, lo: i64, hi: i64, n: u32) -> impl Iterator<Item = u32> {
        let k = self.0.max(1) as i64;
        let (lo, hi) = (lo.max(0), hi.min(n as i64 - 1));
        let first = (lo + k - 1) / k * k;
        let last = n as i64 - 1;
        // The last line traces too; it is listed after the multiples, which are all below it.
        let tail = (last >= lo && last <= hi && last % k != 0).then_some(last as u32);
        (first..=hi)
            .step_by(k as usize)
            .map(|q| q as u32)
            .chain(tail)
    }
}

/// Σ w·a·c and Σ w·a over the samples within the filter's reach of pixel (x, y), in the fixed
/// order [`reconstruct`] documents, telling `weighed(qx, qy, k, w)` each nonzero weight.
/// Only the pixels on `lines` (both ways) are asked for samples; the others must own none,
/// so skipping them changes no sum.
fn accumulate<I: IntoIterator<Item = (DVec2, DVec3, f64)>>(
    filter: &Filter,
    (x, y): (u32, u32),
    (width, height): (u32, u32),
    lines: Lines,
    samples_of: impl Fn(u32, u32) -> I,
    mut weighed: impl FnMut(u32, u32, usize, f64),
) -> (DVec3, f64) {
    let centre = DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
    let reach = filter.reach();
    let (mut sum, mut total) = (DVec3::ZERO, 0.0);
    let (x, y) = (x as i64, y as i64);
    for qy in lines.within(y - reach, y + reach, height) {
        for qx in lines.within(x - reach, x + reach, width) {
            for (k, (film, color, area)) in samples_of(qx, qy).into_iter().enumerate() {
                let d = film - centre;
                let w = filter.weight(d.x, d.y) * area;
                if w != 0.0 {
                    sum += w * color;
                    total += w;
                    weighed(qx, qy, k, w);
                }
            }
        }
    }
    (sum, total)
}

/// [`reconstruct`]'s colour alone (the same sums, so the same bits), keeping no weights: what
/// the renderer runs for every pixel. Under `--subsample K` it asks only the pixels that
/// trace (one in K×K) for samples, since the others own none: the stretched filter of a
/// preview reaches K times as far each way, and visiting every pixel of it cost more than
/// tracing the preview.
fn reconstruct_color<I: IntoIterator<Item = (DVec2, DVec3, f64)>>(
    filter: &Filter,
    (x, y): (u32, u32),
    (width, height): (u32, u32),
    subsample: u32,
    samples_of: impl Fn(u32, u32) -> I,
) -> DVec3 {
    let (sum, total) = accumulate(
        filter,
        (x, y),
        (width, height),
        Lines(subsample),
        samples_of,
        |_, _, _, _| {},
    );
    if total.abs() < 1e-12 {
        DVec3::ZERO
    } else {
        sum / total
    }
}
// ANCHOR_END: reconstruct

/// Bytes a render of `width`×`height` at `spp` samples per pixel holds at its peak: every
/// sample kept for reconstruction (film position and colour), each pixel's sample list, the
/// linear image, the 8-bit image and its PNG encoding.
pub fn memory_needed(width: u32, height: u32, spp: u32) -> u64 {
    let per_pixel = std::mem::size_of::<PixelSample>() as u64 * spp as u64
        + std::mem::size_of::<Vec<PixelSample>>() as u64
        + 2 * std::mem::size_of::<DVec3>() as u64
        + 2 * 3;
    width as u64 * height as u64 * per_pixel
}

/// The most memory a render may take ([`check_memory`]).
pub const MEMORY_BUDGET: u64 = 8 << 30;

/// Refuses, before anything is allocated, a render that would need more than
/// [`MEMORY_BUDGET`], saying how much it would need.
pub fn check_memory(width: u32, height: u32, spp: u32) -> Result<(), String> {
    let need = memory_needed(width, height, spp);
    if need > MEMORY_BUDGET {
        let gib = |b: u64| b as f64 / (1u64 << 30) as f64;
        return Err(format!(
            "{width}×{height} pixels at {spp} sample(s) per pixel would need about {:.1} GiB of memory, more than the {:.0} GiB rtlab allows: render fewer pixels or samples",
            gib(need),
            gib(MEMORY_BUDGET)
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `Lines(k).within` lists exactly the lines of a range that trace under `--subsample k`
    /// (the multiples of k and the last line), in increasing order.
    #[test]
    fn lines_are_the_traced_ones_in_order() {
        for n in [1u32, 2, 7, 8, 9, 33] {
            for k in 1..=9u32 {
                for lo in -10i64..=n as i64 + 2 {
                    for hi in lo - 1..=lo + 12 {
                        let got: Vec<u32> = Lines(k).within(lo, hi, n).collect();
                        // The renderer's own rule, along one axis (the other at 0).
                        let settings = RenderSettings {
                            subsample: k,
                            ..Default::default()
                        };
                        let want: Vec<u32> = (lo.max(0)..=hi.min(n as i64 - 1))
                            .map(|q| q as u32)
                            .filter(|&q| super::super::traces_samples(&settings, n, 1, q, 0))
                            .collect();
                        assert_eq!(got, want, "n {n}, k {k}, {lo}..={hi}");
                    }
                }
            }
        }
    }

    /// Every pixel is in exactly one tile, the one the index rule names, and edge tiles are
    /// cut to the image.
    #[test]
    fn tiles_cover_every_pixel_once() {
        for (w, h) in [(1, 1), (16, 16), (17, 5), (40, 33), (1280, 720)] {
            let tiles = tiles(w, h);
            let mut seen = vec![0u32; (w * h) as usize];
            for (t, tile) in tiles.iter().enumerate() {
                assert!(!tile.is_empty() && tile.x.len() <= 16 && tile.y.len() <= 16);
                for (x, y) in tile.pixels() {
                    seen[(y * w + x) as usize] += 1;
                    assert_eq!(t as u32, (y / TILE) * w.div_ceil(TILE) + x / TILE);
                }
            }
            assert!(seen.iter().all(|&n| n == 1), "{w}×{h}");
            let order: Vec<_> = row_major_order(w, h).collect();
            for (t, tile) in tiles.iter().enumerate() {
                for (l, (x, y)) in tile.pixels().enumerate() {
                    assert_eq!(order[(y * w + x) as usize], (t, l), "{w}×{h} ({x}, {y})");
                }
            }
        }
    }
}
