//! `rtlab diff`: what is wrong with an image, where, and which term of the lighting ledger
//! (and which mistake of the catalogue) makes it so.
//!
//! The expected image is rtlab's own render (or a reference image the scene still explains).
//! Differing pixels are grouped into [`regions`]; each region's pixels are traced again with
//! recorders ([`pixels`]) to fit the difference by ledger [`terms`]. Everything goes through
//! the one tracer: no shading formula is repeated here.

pub mod pixels;
pub mod png;
pub mod regions;
pub mod report;
pub mod suspects;
pub mod terms;

use crate::error::{Error, Result};
use crate::scene::Scene;
use glam::DVec3;
use image::RgbImage;
use terms::{Fit, Term};

/// How `diff` decides and how much it reports.
#[derive(Debug, Clone)]
pub struct Options {
    /// A channel may differ by this many levels (0–255) and still agree (default 2).
    pub tolerance: u8,
    /// The images agree when at most this percentage of pixels differ (default 1).
    pub max_percent: f64,
    /// Regions reported, largest first (the rest are counted).
    pub max_regions: usize,
    /// Pixels of a region traced for the term fit (evenly spread when it has more).
    pub fit_pixels: usize,
    /// Search the mistake catalogue, scoring on at most this many differing pixels of each
    /// region (and half as many agreeing ones near it); 0: no search.
    pub mistake_pixels: usize,
    /// The command that explains a pixel, up to `--pixel` (e.g. `rtlab explain scene.json`),
    /// and the render flags after it.
    pub explain: String,
    pub explain_flags: String,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            tolerance: 2,
            max_percent: 1.0,
            max_regions: 12,
            fit_pixels: 800,
            mistake_pixels: 400,
            explain: "rtlab explain SCENE".into(),
            explain_flags: String::new(),
        }
    }
}

/// The whole-image numbers.
#[derive(Debug, Clone, PartialEq)]
pub struct Metrics {
    /// Pixels with some channel off by more than the tolerance, in percent of all pixels.
    pub diff_percent: f64,
    /// PSNR over every channel (bytes / 255) in dB; `None` when the images are identical.
    pub psnr: Option<f64>,
    /// The largest difference of any channel, in levels.
    pub max: u8,
    pub tolerance: u8,
    pub differing: usize,
}

/// One object under a region.
#[derive(Debug, Clone, PartialEq)]
pub struct RegionObject {
    /// The object's name, or `background`.
    pub name: String,
    /// Surfaces hit (`body`, `cap`, `face`, ...), most pixels first.
    pub surfaces: Vec<String>,
    pub pixels: usize,
}

/// A region of differing pixels and what explains it.
#[derive(Debug, Clone, PartialEq)]
pub struct Region {
    /// [x0, y0, x1, y1], inclusive.
    pub bbox: [u32; 4],
    /// The differing pixels, row-major.
    pub members: Vec<(u32, u32)>,
    pub objects: Vec<RegionObject>,
    /// Mean of yours − expected per channel, in levels (positive: yours is brighter).
    pub mean_difference: [f64; 3],
    /// A typical pixel: its difference is the closest to the region's median difference.
    pub pixel: (u32, u32),
    /// The command showing what that pixel should be.
    pub explain: String,
    pub fit: Fit,
    /// The mistakes that explain most of it, best first (empty when none explains enough).
    pub mistakes: Vec<suspects::MistakeFit>,
}

/// Everything `diff` found.
#[derive(Debug, Clone, PartialEq)]
pub struct Report {
    pub width: u32,
    pub height: u32,
    pub metrics: Metrics,
    /// The course's rule: at most `max_percent` of the pixels differ by more than `tolerance`.
    pub same: bool,
    pub regions: Vec<Region>,
    /// Regions found, including those beyond `max_regions`.
    pub regions_found: usize,
}

/// Compares `yours` with `expected` (both the size of the scene's image) and explains each
/// region of difference with the scene. Fails, saying both sizes, when the sizes differ.
pub fn diff(
    scene: &Scene,
    expected: &RgbImage,
    yours: &RgbImage,
    opts: &Options,
) -> Result<Report> {
    let (w, h) = expected.dimensions();
    if yours.dimensions() != (w, h) {
        return Err(Error::Other(format!(
            "your image is {}×{}, the expected image is {w}×{h}",
            yours.width(),
            yours.height()
        )));
    }
    if (scene.camera.width, scene.camera.height) != (w, h) {
        return Err(Error::Other(format!(
            "the images are {w}×{h}, the scene renders {}×{} (set --width and --height)",
            scene.camera.width, scene.camera.height
        )));
    }
    let mask = regions::mask(expected, yours, opts.tolerance);
    let differing = mask.iter().filter(|m| **m).count();
    let (_, psnr) = crate::viz::compare::rmse_psnr(yours, expected);
    let max = expected
        .pixels()
        .zip(yours.pixels())
        .flat_map(|(a, b)| (0..3).map(move |c| a[c].abs_diff(b[c])))
        .max()
        .unwrap_or(0);
    let diff_percent = 100.0 * differing as f64 / (w as f64 * h as f64);
    let metrics = Metrics {
        diff_percent,
        psnr,
        max,
        tolerance: opts.tolerance,
        differing,
    };

    // The object under every differing pixel (ray casting, cheap), to split regions by.
    let diff_pixels: Vec<(u32, u32)> = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| mask[(y * w + x) as usize])
        .collect();
    let hits = pixels::hits(scene, &scene.render, &diff_pixels);
    let mut under = vec![None; (w * h) as usize];
    for (&(x, y), hit) in diff_pixels.iter().zip(&hits) {
        under[(y * w + x) as usize] = *hit;
    }
    let groups = regions::group(
        &mask,
        w,
        h,
        |x, y| under[(y * w + x) as usize].map(|h| h.0),
        4,
    );
    let regions_found = groups.len();
    let candidates = terms::candidates(scene, scene.render.shadows);
    let regions = groups
        .into_iter()
        .take(opts.max_regions)
        .map(|g| region(scene, expected, yours, g, &under, &candidates, opts))
        .collect();
    Ok(Report {
        width: w,
        height: h,
        same: diff_percent <= opts.max_percent,
        metrics,
        regions,
        regions_found,
    })
}

/// An object of a region (`None`: the background), its pixels, and its surfaces' pixels.
type ObjectTally = (Option<usize>, usize, Vec<(&'static str, usize)>);

fn signed_difference(expected: &RgbImage, yours: &RgbImage, (x, y): (u32, u32)) -> [i32; 3] {
    let (e, m) = (expected.get_pixel(x, y), yours.get_pixel(x, y));
    [0, 1, 2].map(|c| m[c] as i32 - e[c] as i32)
}

fn region(
    scene: &Scene,
    expected: &RgbImage,
    yours: &RgbImage,
    g: regions::PixelGroup,
    under: &[Option<(usize, &'static str)>],
    candidates: &[Term],
    opts: &Options,
) -> Region {
    let w = expected.width();
    let n = g.pixels.len();
    let diffs: Vec<[i32; 3]> = g
        .pixels
        .iter()
        .map(|&p| signed_difference(expected, yours, p))
        .collect();
    let mut mean = [0.0; 3];
    let mut median = [0i32; 3];
    for c in 0..3 {
        mean[c] = diffs.iter().map(|d| d[c] as f64).sum::<f64>() / n as f64;
        let mut v: Vec<i32> = diffs.iter().map(|d| d[c]).collect();
        v.sort_unstable();
        median[c] = v[n / 2];
    }
    let typical = (0..n)
        .min_by_key(|&i| (0..3).map(|c| (diffs[i][c] - median[c]).abs()).sum::<i32>())
        .expect("a region has pixels");
    let pixel = g.pixels[typical];

    // Objects and their surfaces, most pixels first.
    let mut objects: Vec<ObjectTally> = Vec::new();
    for &(x, y) in &g.pixels {
        let hit = under[(y * w + x) as usize];
        let o = hit.map(|h| h.0);
        let entry = match objects.iter_mut().position(|e| e.0 == o) {
            Some(i) => &mut objects[i],
            None => {
                objects.push((o, 0, Vec::new()));
                objects.last_mut().unwrap()
            }
        };
        entry.1 += 1;
        if let Some((_, s)) = hit {
            match entry.2.iter_mut().find(|e| e.0 == s) {
                Some(e) => e.1 += 1,
                None => entry.2.push((s, 1)),
            }
        }
    }
    objects.sort_by_key(|e| std::cmp::Reverse(e.1));
    let objects = objects
        .into_iter()
        .map(|(o, count, mut surfaces)| {
            surfaces.sort_by_key(|e| std::cmp::Reverse(e.1));
            RegionObject {
                name: o.map_or("background".into(), |o| scene.object_name(o).to_string()),
                surfaces: surfaces.into_iter().map(|s| s.0.to_string()).collect(),
                pixels: count,
            }
        })
        .collect();

    let fit = fit_terms(
        scene,
        expected,
        yours,
        &regions::spread(&g.pixels, opts.fit_pixels),
        candidates,
    );
    let mistakes = if opts.mistake_pixels == 0 {
        Vec::new()
    } else {
        let mut scored = regions::spread(&g.pixels, opts.mistake_pixels);
        scored.extend(regions::spread(
            &agreeing_near(expected, yours, &g, opts.tolerance),
            opts.mistake_pixels / 2,
        ));
        suspects::search(scene, expected, yours, &scored)
    };
    Region {
        bbox: g.bbox,
        members: g.pixels,
        objects,
        mean_difference: mean,
        pixel,
        explain: format!(
            "{} --pixel {},{}{}",
            opts.explain, pixel.0, pixel.1, opts.explain_flags
        ),
        fit,
        mistakes,
    }
}

/// The agreeing pixels of a region's box grown by a few pixels: a mistake that would change
/// them too is not the one that was made.
fn agreeing_near(
    expected: &RgbImage,
    yours: &RgbImage,
    g: &regions::PixelGroup,
    tolerance: u8,
) -> Vec<(u32, u32)> {
    let (w, h) = expected.dimensions();
    let m = 4;
    let b = g.bbox;
    let (x0, y0, x1, y1) = (
        b[0].saturating_sub(m),
        b[1].saturating_sub(m),
        (b[2] + m).min(w - 1),
        (b[3] + m).min(h - 1),
    );
    (y0..=y1)
        .flat_map(|y| (x0..=x1).map(move |x| (x, y)))
        .filter(|&(x, y)| !regions::differs(expected, yours, x, y, tolerance))
        .collect()
}

/// Traces `sample` (some pixels of a region) with the ledger recorder, lit and, when the
/// settings cast shadows, unshadowed, and fits the difference there by the candidate terms.
pub fn fit_terms(
    scene: &Scene,
    expected: &RgbImage,
    yours: &RgbImage,
    sample: &[(u32, u32)],
    candidates: &[Term],
) -> Fit {
    let n = scene.lights.len();
    let ledgers = |settings: &crate::scene::RenderSettings| -> Vec<pixels::Ledger> {
        pixels::trace_pixels(
            scene,
            settings,
            sample,
            || pixels::LedgerRecorder::new(n),
            |r| std::mem::take(&mut r.ledger),
        )
        .into_iter()
        .map(|p| pixels::Ledger {
            color: p.color,
            ..terms::weighted(&p.samples, n)
        })
        .collect()
    };
    let lit = ledgers(&scene.render);
    let unshadowed = scene.render.shadows.then(|| {
        let mut s = scene.render.clone();
        s.shadows = false;
        ledgers(&s)
    });
    let values: Vec<Vec<DVec3>> = (0..sample.len())
        .map(|i| {
            candidates
                .iter()
                .map(|&t| terms::value(t, &lit[i], unshadowed.as_ref().map(|u| &u[i])))
                .collect()
        })
        .collect();
    let px = |img: &RgbImage| -> Vec<[u8; 3]> {
        sample.iter().map(|&(x, y)| img.get_pixel(x, y).0).collect()
    };
    terms::fit(
        &px(yours),
        &px(expected),
        &values,
        candidates,
        scene.render.encoding,
    )
}
