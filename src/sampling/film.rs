//! The render: tiles traced in parallel, sample by sample through the one tracer, then
//! reconstructed into the image; and what the render holds in memory.

use super::bundles::{bundled, trace_bundled, BundleTally, TilePlan};
use super::image::Image;
use super::kept::TileSamples;
use super::reconstruct::{reconstruct_color, Kernel};
use super::sampler::{only_centres, sample_pixel_into};
use super::tiles::{row_major_order, tiles};
use super::{Filter, PixelSample};
use crate::scene::{RenderSettings, Scene};
use crate::trace::{
    camera_ray, trace_camera, Counter, NoRecorder, RayCounts, Recorder, SampleResult,
};
use glam::DVec3;
use rayon::prelude::*;
use std::time::Instant;

/// What the counting recorder saw over a whole render.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RenderStats {
    pub rays: RayCounts,
    pub tests: u64,
    pub nodes: u64,
    /// The same work pixel by pixel, when it was asked for ([`Counting::PerPixel`]).
    pub per_pixel: Option<PixelWork>,
    /// Bundles of camera rays traced (`--traversal bundle`) and the nodes they opened.
    pub bundles: BundleTally,
}

/// Intersection tests (objects, and faces inside meshes) and BVH nodes visited (the scene's
/// and the meshes'), per pixel, row-major: their sum is what the `cost` AOV shows.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PixelWork {
    pub tests: Vec<u64>,
    pub nodes: Vec<u64>,
}

impl PixelWork {
    /// Tests + nodes of pixel `i` (row-major): the `cost` AOV's value.
    pub fn cost(&self, i: usize) -> u64 {
        self.tests[i] + self.nodes[i]
    }
}

/// What a render counts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Counting {
    /// Nothing: the zero-cost recorder runs.
    Off,
    /// Rays, tests and nodes over the whole render (what `render --stats` prints).
    Totals,
    /// The totals, and each pixel's tests and nodes ([`PixelWork`]): 16 bytes a pixel more
    /// while the render runs, and the work of keeping them.
    PerPixel,
}

impl Counting {
    /// [`Counting::Totals`] when `count`, else [`Counting::Off`].
    pub fn totals_if(count: bool) -> Counting {
        if count {
            Counting::Totals
        } else {
            Counting::Off
        }
    }
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

impl RenderOutput {
    /// The output of a render cancelled before its image was complete: no image (black), no
    /// counts, nothing to be written.
    fn cancelled((width, height): (u32, u32), trace_seconds: f64) -> RenderOutput {
        RenderOutput {
            image: Image {
                width,
                height,
                pixels: vec![DVec3::ZERO; width as usize * height as usize],
            },
            stats: None,
            trace_seconds,
            first_nan: None,
            spp_map: None,
            cut_samples: 0,
            first_cut: None,
            cancelled: true,
        }
    }
}

/// Renders the scene. With `count`, a [`Counter`] records rays, tests and nodes over the
/// whole render ([`Counting::Totals`]); otherwise the zero-cost [`NoRecorder`] runs. Tiles
/// ([`tiles`]) are traced in parallel and gathered back into rows, and each sample's
/// randomness depends only on its own key, so the result is the same on any number of
/// threads.
pub fn render(
    scene: &Scene,
    settings: &RenderSettings,
    count: bool,
    progress: Option<&indicatif::ProgressBar>,
) -> RenderOutput {
    render_counting(scene, settings, Counting::totals_if(count), progress)
}

/// [`render`], counting what `counting` asks for (each pixel's work too, with
/// [`Counting::PerPixel`]).
pub fn render_counting(
    scene: &Scene,
    settings: &RenderSettings,
    counting: Counting,
    progress: Option<&indicatif::ProgressBar>,
) -> RenderOutput {
    render_until(scene, settings, counting, progress, &|| false)
        .expect("a render nothing stops runs to the end")
}

/// [`render`], but `stop()` is asked before each tile, inside a tile before each pixel
/// (each 4×4 block, with bundles), and before each row of the image made from the samples:
/// once it says yes, the rest is skipped and there is no
/// image (`None`). (So a pass of many samples per pixel on a small image, a tile or two,
/// still stops soon after it is asked to; `stop` should be cheap.) Progressive rendering
/// ([`super::progressive`]) stops a pass this way when its time is up or its caller cancels.
/// Ctrl-C ([`crate::interrupt`]) skips the tiles as well, but still returns an (empty) output.
pub fn render_until(
    scene: &Scene,
    settings: &RenderSettings,
    counting: Counting,
    progress: Option<&indicatif::ProgressBar>,
    stop: &(dyn Fn() -> bool + Sync),
) -> Option<RenderOutput> {
    match counting {
        Counting::Off => render_with::<NoRecorder>(scene, settings, false, progress, stop),
        Counting::Totals => render_with::<Counter>(scene, settings, false, progress, stop),
        Counting::PerPixel => render_with::<Counter>(scene, settings, true, progress, stop),
    }
}

trait Tally: Recorder + Default + Send {
    /// Does it count anything?
    const COUNTS: bool;
    /// Intersection tests and BVH nodes so far.
    fn work(&self) -> [u64; 2];
    /// Rays so far, by kind.
    fn rays(&self) -> RayCounts;
}
impl Tally for NoRecorder {
    const COUNTS: bool = false;
    fn work(&self) -> [u64; 2] {
        [0; 2]
    }
    fn rays(&self) -> RayCounts {
        RayCounts::default()
    }
}
impl Tally for Counter {
    const COUNTS: bool = true;
    fn work(&self) -> [u64; 2] {
        [self.total_tests(), self.total_nodes()]
    }
    fn rays(&self) -> RayCounts {
        self.rays
    }
}

/// The render, with recorder `R` (counting or not) and, when `per_pixel`, each pixel's work.
fn render_with<R: Tally>(
    scene: &Scene,
    settings: &RenderSettings,
    per_pixel: bool,
    progress: Option<&indicatif::ProgressBar>,
    stop: &(dyn Fn() -> bool + Sync),
) -> Option<RenderOutput> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let stopped = std::sync::atomic::AtomicBool::new(false);
    let start = Instant::now();
    /// One tile's samples (pixel by pixel in the tile's own row-major order) and counts
    /// (per pixel, if kept; its tests and nodes; its rays), its first non-finite sample, and
    /// its samples the ray budget cut (count, first).
    type Traced = (
        TileSamples,
        (Vec<[u64; 2]>, [u64; 2], RayCounts),
        Option<(u32, u32, u32)>,
        (u64, Option<(u32, u32, u32)>),
        BundleTally,
    );
    let bundled = bundled(settings);
    let centres = only_centres(settings);
    let tiles = tiles(w, h);
    let traced: Vec<Traced> = tiles
        .par_iter()
        .map(|tile| {
            // Asked before the tile, and before each pixel or block inside it.
            let halt = || {
                let halt = stopped.load(std::sync::atomic::Ordering::Relaxed) || stop();
                if halt {
                    stopped.store(true, std::sync::atomic::Ordering::Relaxed);
                }
                halt
            };
            // Ctrl-C or a cancelled token too: a tile's plan alone (the bundled render's) can
            // take milliseconds, and a cancelled render has hundreds of tiles left to skip.
            if settings.cancel.is_cancelled() || halt() {
                return Default::default();
            }
            let mut bundles = BundleTally::default();
            // One recorder counts the whole tile. Each pixel's work is kept only when asked
            // for (`per_pixel`): 16 bytes a pixel (its tests and nodes, pixel l's at
            // `stats[l]`, what the recorder grew by while the pixel's samples were traced),
            // memory `--stats` does not need (its totals are the recorder's) and that cost
            // it a tenth of the bundled render's trace time in page faults and bookkeeping.
            let per_pixel = R::COUNTS && per_pixel;
            let mut stats = vec![[0u64; 2]; if per_pixel { tile.len() } else { 0 }];
            let mut rec = R::default();
            let mut firsts = Firsts::default();
            let work = |rec: &R| if per_pixel { rec.work() } else { [0; 2] };
            let tally = |stats: &mut Vec<[u64; 2]>, l: usize, before: [u64; 2], rec: &R| {
                if per_pixel {
                    let after = rec.work();
                    stats[l][0] += after[0] - before[0];
                    stats[l][1] += after[1] - before[1];
                }
            };
            // Bundles: the tile's samples planned, traced block by block.
            let plan = bundled
                .then(|| TilePlan::new(settings, w, h, tile))
                .flatten();
            let kept = if let Some(plan) = plan {
                let mut kept = TileSamples::planned(&plan);
                trace_bundled(
                    scene,
                    settings,
                    tile,
                    &plan,
                    &mut bundles,
                    |l, (x, y), k, camera, found| {
                        let before = work(&rec);
                        let r = trace_camera(scene, settings, camera, Some(found), &mut rec);
                        tally(&mut stats, l, before, &rec);
                        let sample = PixelSample {
                            index: k,
                            film: r.film,
                            area: 1.0,
                            color: firsts.note(&r, (x, y, k)),
                        };
                        kept.set(plan.sample(l, (x, y), k).1, sample);
                    },
                    |pixels| {
                        if let Some(p) = progress {
                            p.inc(pixels);
                        }
                        !halt()
                    },
                );
                kept
            } else {
                // Room for the samples of the pixels the tile traces (every pixel, unless
                // --subsample skips some: memory_needed counts the same).
                let traced = tile
                    .pixels()
                    .filter(|&(x, y)| super::sampler::traces_samples(settings, w, h, x, y))
                    .count();
                let most = traced * (settings.spp as usize).min(16);
                let mut kept = TileSamples::with_capacity(centres, tile.len(), most);
                let mut scratch = Vec::new();
                for (l, (x, y)) in tile.pixels().enumerate() {
                    if settings.cancel.is_cancelled() || halt() {
                        // Ctrl-C or a cancelled token (the caller writes nothing), or stopped.
                        break;
                    }
                    let before = work(&rec);
                    kept.push_pixel_with(&mut scratch, |out| {
                        sample_pixel_into(settings, w, h, x, y, out, |k, film| {
                            // A pixel may hold thousands of samples: a cancelled render (a
                            // spent time budget) traces none of the rest; it is thrown away.
                            if settings.cancel.is_cancelled() {
                                return DVec3::ZERO;
                            }
                            let mut camera = camera_ray(scene, settings, x, y, k, film);
                            let r = trace_camera(scene, settings, &mut camera, None, &mut rec);
                            firsts.note(&r, (x, y, k))
                        })
                    });
                    tally(&mut stats, l, before, &rec);
                    // Pixel by pixel, so the bar moves while a slow tile is still being traced.
                    if let Some(p) = progress {
                        p.inc(1);
                    }
                }
                kept
            };
            let Firsts { nan, cut } = firsts;
            (kept, (stats, rec.work(), rec.rays()), nan, cut, bundles)
        })
        .collect();
    let trace_seconds = start.elapsed().as_secs_f64();
    if stopped.into_inner() {
        return None;
    }
    if settings.cancel.is_cancelled() {
        // Some tiles were skipped: there is no image to reconstruct (and none will be written).
        return Some(RenderOutput::cancelled((w, h), trace_seconds));
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
    let stats = R::COUNTS.then(|| {
        let mut st = RenderStats::default();
        for t in &traced {
            let [tests, nodes] = t.1 .1;
            st.tests += tests;
            st.nodes += nodes;
            st.rays.add(&t.1 .2);
            st.bundles.add(&t.4);
        }
        // Every pixel of every tile has its counts (a short tile was cancelled, and a
        // cancelled render returned above): index them, so that a gap could never shift a
        // pixel's counts onto another.
        st.per_pixel = per_pixel.then(|| {
            let (tests, nodes) = row_major_order(w, h)
                .map(|(t, l)| {
                    let [tests, nodes] = traced[t].1 .0[l];
                    (tests, nodes)
                })
                .unzip();
            PixelWork { tests, nodes }
        });
        st
    });
    // Each pixel's samples: its tile's, and its place in the tile.
    let grid: Vec<(&TileSamples, usize)> = row_major_order(w, h)
        .map(|(t, l)| (&traced[t].0, l))
        .collect();
    let spp_map = Some(grid.iter().map(|&(kept, l)| kept.count(l)).collect());
    let filter = Filter::for_settings(settings);
    let kernel = Kernel::new(&filter, settings.subsample);
    // Stopped or cancelled while reconstructing, the pass is thrown away as above.
    let given_up = || settings.cancel.is_cancelled() || stop();
    let Some(image) = Image::from_fn_until(w, h, &given_up, |x, y| {
        reconstruct_color(&kernel, (x, y), (w, h), |qx, qy| {
            let (kept, l) = grid[(qy * w + qx) as usize];
            kept.of(l, (qx, qy))
        })
    }) else {
        if settings.cancel.is_cancelled() {
            return Some(RenderOutput::cancelled((w, h), trace_seconds));
        }
        return None;
    };
    Some(RenderOutput {
        image,
        stats,
        trace_seconds,
        first_nan,
        spp_map,
        cut_samples,
        first_cut,
        cancelled: false,
    })
}

/// What a tile remembers of its samples besides their colours: the first (in row-major order
/// of pixels, then by sample index) whose colour was not finite, and the samples whose tree
/// the ray budget cut (how many, and the first).
#[derive(Default)]
struct Firsts {
    nan: Option<(u32, u32, u32)>,
    cut: (u64, Option<(u32, u32, u32)>),
}

impl Firsts {
    /// Notes sample (x, y, k)'s result and returns its colour for the film: black when it
    /// was not finite.
    fn note(&mut self, r: &SampleResult, (x, y, k): (u32, u32, u32)) -> DVec3 {
        let first = |old: Option<(u32, u32, u32)>| {
            Some(old.map_or((x, y, k), |o| {
                if (y, x, k) < (o.1, o.0, o.2) {
                    (x, y, k)
                } else {
                    o
                }
            }))
        };
        if r.cut {
            self.cut.0 += 1;
            self.cut.1 = first(self.cut.1);
        }
        // c − c is zero in every channel exactly when every channel is finite (±∞ and NaN
        // give NaN): `is_finite` written this way stays three float operations (the
        // compiler turns `is_finite` into integer tests on each channel's bits).
        #[allow(clippy::eq_op)] // on purpose: c − c is not 0 for ±∞ and NaN
        let zero = r.color - r.color;
        if (zero.x == 0.0) & (zero.y == 0.0) & (zero.z == 0.0) {
            r.color
        } else {
            self.nan = first(self.nan);
            DVec3::ZERO
        }
    }
}

/// Bytes a render of `width`×`height` at `spp` samples per pixel, tracing every
/// `subsample`-th pixel ([`super::sampler::traces_samples`]), holds at its peak: every
/// sample of a traced pixel kept for reconstruction (film position and colour), and for
/// every pixel its sample list, the linear image, the 8-bit image and its PNG encoding.
pub fn memory_needed(width: u32, height: u32, spp: u32, subsample: u32) -> u64 {
    let traced = traced_lines(width, subsample) * traced_lines(height, subsample);
    memory_kept(
        width,
        height,
        traced * spp as u64,
        Kept::of::<PixelSample>(),
    )
}

/// What a render keeps of each sample until its image is made: the bytes of one sample's
/// record and of one pixel's list of them.
#[derive(Clone, Copy)]
pub(crate) struct Kept {
    pub sample: u64,
    pub list: u64,
}

impl Kept {
    /// Records of type `T`, in a `Vec<T>` per pixel.
    pub(crate) fn of<T>() -> Kept {
        Kept {
            sample: std::mem::size_of::<T>() as u64,
            list: std::mem::size_of::<Vec<T>>() as u64,
        }
    }
}

/// [`memory_needed`] for `samples` samples in all, kept as `kept` says.
fn memory_kept(width: u32, height: u32, samples: u64, kept: Kept) -> u64 {
    let per_pixel = kept.list + 2 * std::mem::size_of::<DVec3>() as u64 + 2 * 3;
    width as u64 * height as u64 * per_pixel + samples * kept.sample
}

/// How many of `n` columns (or rows) trace under `--subsample k`: every k-th, and the last.
fn traced_lines(n: u32, k: u32) -> u64 {
    let k = k.max(1);
    (n.div_ceil(k) + u32::from(n > 0 && !(n - 1).is_multiple_of(k))) as u64
}

/// The most samples a render of `width` × `height` pixels traces and keeps with `sampler` at
/// `spp`, tracing every `subsample`-th row and column (and the last):
/// [`super::samples_kept`] of the pixels traced. What [`check_memory`] weighs, and what the
/// server limits one request to.
pub fn samples_at_most(
    (width, height): (u32, u32),
    sampler: crate::scene::SamplerKind,
    spp: u32,
    subsample: u32,
) -> u64 {
    let (cols, rows) = (
        traced_lines(width, subsample),
        traced_lines(height, subsample),
    );
    super::sampler::samples_kept(sampler, spp, cols, rows)
}

/// The most memory a render may take ([`check_memory`]).
pub const MEMORY_BUDGET: u64 = 8 << 30;

/// Refuses, before anything is allocated, a render that would need more than
/// [`MEMORY_BUDGET`], saying how much it would need: `spp` samples per pixel with `sampler`
/// (the adaptive sampler may keep more: [`super::sampler::most_samples`]).
pub fn check_memory(
    width: u32,
    height: u32,
    sampler: crate::scene::SamplerKind,
    spp: u32,
    subsample: u32,
) -> Result<(), String> {
    check_memory_kept(
        (width, height),
        sampler,
        spp,
        subsample,
        Kept::of::<PixelSample>(),
    )
}

/// [`check_memory`] for samples kept as `kept` says (an AOV keeps more of each).
pub(crate) fn check_memory_kept(
    (width, height): (u32, u32),
    sampler: crate::scene::SamplerKind,
    spp: u32,
    subsample: u32,
    kept: Kept,
) -> Result<(), String> {
    let samples = samples_at_most((width, height), sampler, spp, subsample);
    let need = memory_kept(width, height, samples, kept);
    if need > MEMORY_BUDGET {
        let gib = |b: u64| b as f64 / (1u64 << 30) as f64;
        let most = super::sampler::most_samples(sampler, spp);
        let samples = if sampler == crate::scene::SamplerKind::Corners {
            "two samples each (the corners sampler: a centre and a corner)".to_string()
        } else if most == spp {
            format!("{spp} sample(s) per pixel")
        } else {
            format!(
                "up to {most} samples per pixel (the adaptive sampler's every level up to {spp})"
            )
        };
        return Err(format!(
            "{width}×{height} pixels at {samples} would need about {:.1} GiB of memory, more than the {:.0} GiB rtlab allows: render fewer pixels or samples",
            gib(need),
            gib(MEMORY_BUDGET)
        ));
    }
    Ok(())
}
