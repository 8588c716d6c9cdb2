//! Where a pixel's samples go. Every position and every random number of a sample depends only
//! on (seed, pixel, sample index), so one sample can be replayed alone (`explain --sample k`)
//! and the image is the same on any number of threads.

use crate::math::Rng;
use crate::scene::{RenderSettings, SamplerKind};
use glam::{DVec2, DVec3};

/// The most samples per pixel any sampler takes (4⁸ = 256², a square and a power of four,
/// so every sampler reaches it).
pub const MAX_SPP: u32 = 65536;

/// Checks that `spp` suits the sampler (the centre is one sample, grids need a square
/// number, the adaptive sampler a power of four: its finest level is a 2ᵏ×2ᵏ grid).
pub fn validate_spp(kind: SamplerKind, spp: u32) -> Result<(), String> {
    if spp == 0 {
        return Err("samples per pixel must be at least 1".into());
    }
    if spp > MAX_SPP {
        return Err(format!(
            "{spp} samples per pixel is more than the limit of {MAX_SPP}"
        ));
    }
    if kind == SamplerKind::Center && spp != 1 {
        return Err(format!(
            "the center sampler takes one sample per pixel, found {spp}: for more, choose a \
             sampler that takes several (grid, jittered, random or adaptive)"
        ));
    }
    if kind == SamplerKind::Corners && spp != 1 && spp != 5 {
        return Err(format!(
            "the corners sampler takes five samples per pixel (its centre and its four \
             corners, each corner shared by the four pixels around it), found {spp}: give 5, or \
             1 (the default); for more, choose a sampler that takes several (grid, jittered, \
             random or adaptive)"
        ));
    }
    if matches!(kind, SamplerKind::Grid | SamplerKind::Jittered) {
        let n = (spp as f64).sqrt().round() as u32;
        if n * n != spp {
            return Err(format!(
                "the {} sampler needs a square number of samples (1, 4, 9, 16, ...), found {spp}",
                kind.name()
            ));
        }
    }
    if kind == SamplerKind::Adaptive
        && !(spp.is_power_of_two() && spp.trailing_zeros().is_multiple_of(2))
    {
        return Err(format!(
            "the adaptive sampler needs a power of four (1, 4, 16, 64, 256): the finest grid it \
             refines to, found {spp}"
        ));
    }
    Ok(())
}

/// One traced sample a pixel owns.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PixelSample {
    /// Its index within the pixel that owns it: the key of its random numbers.
    pub index: u32,
    /// Film position in pixel units (x right, y down).
    pub film: DVec2,
    /// The share of the film it stands for, multiplied into its filter weight: 1 for the
    /// fixed patterns, the area of its cell for the adaptive sampler.
    pub area: f64,
    pub color: DVec3,
}

impl PixelSample {
    /// A placeholder for a sample not traced yet.
    pub const UNTRACED: PixelSample = PixelSample {
        index: 0,
        film: DVec2::ZERO,
        area: 1.0,
        color: DVec3::ZERO,
    };
}

/// The centre of pixel (x, y) on the film: the centre sampler's one sample.
pub(super) fn centre(x: u32, y: u32) -> DVec2 {
    DVec2::new(x as f64, y as f64) + DVec2::splat(0.5)
}

/// Does every pixel trace exactly one sample, at its centre ([`planned_films_into`] under
/// the centre sampler with no subsampling)? Then pixel (x, y)'s film is `centre(x, y)`.
pub fn only_centres(settings: &RenderSettings) -> bool {
    settings.sampler == SamplerKind::Center && settings.subsample <= 1
}

// ANCHOR: samplers
/// The film positions of the fixed sampling patterns for pixel (x, y), in sample-index order.
/// Random positions come from (seed, pixel, sample index) alone. `Corners` lists the centre
/// and all four corners (which of them a pixel traces itself: [`sample_pixel`]); `Adaptive`
/// lists its first level, the 2×2 grid.
pub fn pixel_samples(kind: SamplerKind, spp: u32, seed: u64, x: u32, y: u32) -> Vec<DVec2> {
    let corner = DVec2::new(x as f64, y as f64);
    let rng = |k: u32| Rng::new(&[seed, x as u64, y as u64, k as u64, 0x5A3B]);
    match kind {
        SamplerKind::Center => vec![centre(x, y)],
        // n×n strata; grid takes each stratum's centre, jittered a random point inside it.
        SamplerKind::Grid | SamplerKind::Jittered => {
            let n = (spp as f64).sqrt().round() as u32;
            (0..n * n)
                .map(|k| {
                    let (i, j) = (k % n, k / n);
                    let offset = if kind == SamplerKind::Grid {
                        DVec2::splat(0.5)
                    } else {
                        let mut r = rng(k);
                        DVec2::new(r.next_f64(), r.next_f64())
                    };
                    corner + (DVec2::new(i as f64, j as f64) + offset) / n as f64
                })
                .collect()
        }
        // Anywhere in the pixel: clumps and gaps, but no regular pattern to alias with.
        SamplerKind::Random => (0..spp)
            .map(|k| {
                let mut r = rng(k);
                corner + DVec2::new(r.next_f64(), r.next_f64())
            })
            .collect(),
        SamplerKind::Corners => vec![
            corner + DVec2::splat(0.5),
            corner,
            corner + DVec2::new(1.0, 0.0),
            corner + DVec2::new(0.0, 1.0),
            corner + DVec2::new(1.0, 1.0),
        ],
        SamplerKind::Adaptive => [(0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75)]
            .iter()
            .map(|&(u, v)| corner + DVec2::new(u, v))
            .collect(),
    }
}
// ANCHOR_END: samplers

// ANCHOR: subsample
/// Does pixel (x, y) of a `width`×`height` image trace samples at all? With `--subsample K`
/// only every K-th column and row do, plus the last column and row so that the border has
/// samples to reconstruct from; the filter, stretched K times, fills in the others.
pub fn traces_samples(settings: &RenderSettings, width: u32, height: u32, x: u32, y: u32) -> bool {
    let k = settings.subsample.max(1);
    if k == 1 {
        return true; // every pixel (and no division on the renderer's path)
    }
    (x.is_multiple_of(k) || x + 1 == width) && (y.is_multiple_of(k) || y + 1 == height)
}

// ANCHOR_END: subsample

/// The pixel that traces for (x, y) under `--subsample K`: (x, y) itself if it traces
/// ([`traces_samples`]), otherwise the nearest traced pixel, column and row each (the one
/// before on a tie), whose samples the stretched box filter gives it.
pub fn standing_for(
    settings: &RenderSettings,
    width: u32,
    height: u32,
    x: u32,
    y: u32,
) -> (u32, u32) {
    if traces_samples(settings, width, height, x, y) {
        return (x, y);
    }
    let k = settings.subsample.max(1);
    let nearest = |v: u32, n: u32| {
        if v + 1 == n {
            return v; // the last line traces
        }
        // The traced lines around v: a multiple of K, and the next one or the last line.
        let before = v - v % k;
        let after = (before + k).min(n - 1);
        if v - before <= after - v {
            before
        } else {
            after
        }
    };
    (nearest(x, width), nearest(y, height))
}
// ANCHOR: corners
/// The corner samples pixel (x, y) traces itself: its top-left corner, and the corners on the
/// image's right and bottom border that no pixel further right or down can own. Every corner
/// of the image is thus traced exactly once and shared by the (up to) four pixels around it.
fn owned_corners(x: u32, y: u32, width: u32, height: u32) -> Vec<DVec2> {
    let c = DVec2::new(x as f64, y as f64);
    let (right, bottom) = (x + 1 == width, y + 1 == height);
    let mut v = vec![c];
    if right {
        v.push(c + DVec2::new(1.0, 0.0));
    }
    if bottom {
        v.push(c + DVec2::new(0.0, 1.0));
    }
    if right && bottom {
        v.push(c + DVec2::new(1.0, 1.0));
    }
    v
}
// ANCHOR_END: corners

/// The film positions of the samples pixel (x, y) traces, in index order, when they are
/// known before any is traced: every sampler but the adaptive one (`None`), which decides
/// as it goes. Empty for a pixel `--subsample` skips. Bundles of camera rays are made from
/// these ([`super::bundles`]), and [`sample_pixel`] traces exactly these.
pub fn planned_films(
    settings: &RenderSettings,
    width: u32,
    height: u32,
    x: u32,
    y: u32,
) -> Option<Vec<DVec2>> {
    let mut films = Vec::new();
    planned_films_into(settings, width, height, x, y, &mut films).then_some(films)
}

/// [`planned_films`], appended to `out` (false, and nothing appended, for the adaptive
/// sampler): the renderer keeps a tile's films in one vector, and the one-sample case needs
/// no list of its own.
pub fn planned_films_into(
    settings: &RenderSettings,
    width: u32,
    height: u32,
    x: u32,
    y: u32,
    out: &mut Vec<DVec2>,
) -> bool {
    if !traces_samples(settings, width, height, x, y) {
        return true;
    }
    match settings.sampler {
        SamplerKind::Adaptive => return false,
        // What `pixel_samples` gives the centre sampler, without a list of one.
        SamplerKind::Center => out.push(centre(x, y)),
        SamplerKind::Corners => {
            out.push(centre(x, y));
            out.extend(owned_corners(x, y, width, height));
        }
        kind => out.extend(pixel_samples(kind, settings.spp, settings.seed, x, y)),
    }
    true
}

/// Traces the samples pixel (x, y) of a `width`×`height` image owns, calling `trace(index,
/// film)` for each in index order. Fixed patterns are planned up front; the adaptive sampler
/// decides where to look next from the colours `trace` returns, so `render` and `explain`,
/// which pass different tracers, take the same decisions.
pub fn sample_pixel(
    settings: &RenderSettings,
    width: u32,
    height: u32,
    x: u32,
    y: u32,
    trace: impl FnMut(u32, DVec2) -> DVec3,
) -> Vec<PixelSample> {
    let mut out = Vec::new();
    sample_pixel_into(settings, width, height, x, y, &mut out, trace);
    out
}

/// [`sample_pixel`], appending the samples to `out` (the renderer keeps a tile's samples in
/// one vector rather than one per pixel: two allocations fewer per pixel).
pub fn sample_pixel_into(
    settings: &RenderSettings,
    width: u32,
    height: u32,
    x: u32,
    y: u32,
    out: &mut Vec<PixelSample>,
    mut trace: impl FnMut(u32, DVec2) -> DVec3,
) {
    if settings.sampler == SamplerKind::Center && traces_samples(settings, width, height, x, y) {
        // The one-sample case, without a list of one film position.
        let film = centre(x, y);
        let color = trace(0, film);
        out.push(PixelSample {
            index: 0,
            film,
            area: 1.0,
            color,
        });
        return;
    }
    let Some(films) = planned_films(settings, width, height, x, y) else {
        out.extend(adaptive(settings, x, y, trace));
        return;
    };
    out.extend(films.into_iter().enumerate().map(|(k, film)| PixelSample {
        index: k as u32,
        film,
        area: 1.0,
        color: trace(k as u32, film),
    }));
}

/// The samples each pixel's filter takes with `kind` at `spp`: `spp`, except under
/// `corners`, always 5 (its centre and its four corners, whether the scene says `spp` 1 or
/// 5), though each corner is traced once for the four pixels that share it.
pub fn filter_samples(kind: SamplerKind, spp: u32) -> u32 {
    match kind {
        SamplerKind::Corners => 5,
        _ => spp,
    }
}

/// The most samples a render keeps when `cols` × `rows` of its pixels trace: each pixel's
/// [`most_samples`], except under `corners`, where a pixel keeps its centre and the corners
/// it owns (`owned_corners`): two a pixel, and one more for each row on the right border,
/// each column on the bottom border and the image's last corner.
pub fn samples_kept(kind: SamplerKind, spp: u32, cols: u64, rows: u64) -> u64 {
    match kind {
        SamplerKind::Corners => 2 * cols * rows + cols + rows + 1,
        _ => cols * rows * most_samples(kind, spp) as u64,
    }
}

/// The most samples one pixel keeps with `kind` at `spp`: `spp`, except for the adaptive
/// sampler, which keeps every level it refines through, 4 + 16 + … + spp (and `corners`,
/// whose pixels keep different counts: [`super::samples_kept`]).
pub fn most_samples(kind: SamplerKind, spp: u32) -> u32 {
    match kind {
        SamplerKind::Adaptive if spp >= 4 => ((4 * spp as u64 - 4) / 3).min(u32::MAX as u64) as u32,
        _ => spp,
    }
}

// ANCHOR: adaptive
/// Adaptive sampling: trace the 2×2 grid of the pixel; where a cell's samples disagree by more
/// than `adaptive_threshold` (largest channel difference), split every cell of that group into
/// four and trace their centres, down to the `spp` grid (√spp × √spp). A split cell keeps its
/// own sample: the cell's area is shared by it and its four children, a fifth each. Flat pixels
/// cost 4 samples; an edge pixel at `--spp 16` costs 4 + 16.
fn adaptive(
    settings: &RenderSettings,
    x: u32,
    y: u32,
    mut trace: impl FnMut(u32, DVec2) -> DVec3,
) -> Vec<PixelSample> {
    let corner = DVec2::new(x as f64, y as f64);
    let finest = (settings.spp as f64).sqrt().round().max(1.0); // cells per side at the end
    let mut out = Vec::new();
    if finest < 2.0 {
        let film = corner + DVec2::splat(0.5);
        out.push(PixelSample {
            index: 0,
            film,
            area: 1.0,
            color: trace(0, film),
        });
        return out;
    }
    // The whole pixel is a cell of size 1 whose four children are always traced.
    refine(
        settings, corner, 1.0, 1.0, finest, None, &mut trace, &mut out,
    );
    out
}

/// Traces the four children of the square cell at `origin` with side `size`, then splits them
/// again if they (with the parent's own sample, when there is one) disagree. `share` is the
/// area the children split among them.
#[allow(clippy::too_many_arguments)]
fn refine(
    settings: &RenderSettings,
    origin: DVec2,
    size: f64,
    share: f64,
    finest: f64,
    parent: Option<DVec3>,
    trace: &mut impl FnMut(u32, DVec2) -> DVec3,
    out: &mut Vec<PixelSample>,
) {
    let half = size / 2.0;
    let first = out.len();
    for (i, j) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
        let film = origin + DVec2::new(i + 0.5, j + 0.5) * half;
        let index = out.len() as u32;
        let color = trace(index, film);
        out.push(PixelSample {
            index,
            film,
            area: share / 4.0,
            color,
        });
    }
    let colors: Vec<DVec3> = out[first..first + 4]
        .iter()
        .map(|s| s.color)
        .chain(parent)
        .collect();
    let (lo, hi) = colors.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), c| (lo.min(*c), hi.max(*c)),
    );
    let disagree = (hi - lo).max_element() > settings.adaptive_threshold;
    if disagree && 1.0 / half < finest {
        for c in 0..4 {
            // Child c now shares its area with its own four children: a fifth each.
            let s = out[first + c];
            out[first + c].area = s.area / 5.0;
            let child_origin = s.film - DVec2::splat(half / 2.0);
            refine(
                settings,
                child_origin,
                half,
                s.area * 4.0 / 5.0,
                finest,
                Some(s.color),
                trace,
                out,
            );
        }
    }
}
// ANCHOR_END: adaptive

#[cfg(test)]
mod tests {

    #[test]
    fn an_untraced_pixel_stands_for_the_nearest_traced_one() {
        let s = RenderSettings {
            subsample: 4,
            ..RenderSettings::default()
        };
        // Columns 0, 4, 8 and the last (9) trace in a 10-wide image; rows 0, 4 and 5 of 6.
        let at = |x, y| standing_for(&s, 10, 6, x, y);
        assert_eq!(at(0, 0), (0, 0));
        assert_eq!(at(1, 1), (0, 0));
        assert_eq!(at(2, 2), (0, 0)); // a tie: the one before
        assert_eq!(at(3, 3), (4, 4));
        assert_eq!(at(8, 5), (8, 5));
        assert_eq!(at(9, 1), (9, 0));
        assert_eq!(at(7, 5), (8, 5));
    }
    use super::*;

    fn settings(kind: SamplerKind, spp: u32) -> RenderSettings {
        RenderSettings {
            sampler: kind,
            spp,
            seed: 7,
            ..RenderSettings::default()
        }
    }

    #[test]
    fn samples_stay_in_their_pixel_and_strata() {
        for kind in [
            SamplerKind::Grid,
            SamplerKind::Jittered,
            SamplerKind::Random,
        ] {
            let s = pixel_samples(kind, 16, 7, 3, 5);
            assert_eq!(s.len(), 16);
            for p in &s {
                assert!(
                    p.x >= 3.0 && p.x < 4.0 && p.y >= 5.0 && p.y < 6.0,
                    "{kind:?} {p}"
                );
            }
        }
        // Jittered: exactly one sample per 4x4 stratum.
        let s = pixel_samples(SamplerKind::Jittered, 16, 7, 0, 0);
        for (k, p) in s.iter().enumerate() {
            let (i, j) = ((p.x * 4.0) as usize, (p.y * 4.0) as usize);
            assert_eq!(j * 4 + i, k);
        }
        assert!(validate_spp(SamplerKind::Grid, 8).is_err());
        // Corners always traces its five: 5 or the default 1, nothing else.
        assert!(validate_spp(SamplerKind::Corners, 1).is_ok());
        assert!(validate_spp(SamplerKind::Corners, 5).is_ok());
        assert!(validate_spp(SamplerKind::Corners, 4).is_err());
        assert!(validate_spp(SamplerKind::Corners, 16).is_err());
        assert!(validate_spp(SamplerKind::Random, 0).is_err());
        assert!(validate_spp(SamplerKind::Adaptive, 8).is_err());
        assert!(validate_spp(SamplerKind::Adaptive, 16).is_ok());
    }

    #[test]
    fn every_corner_is_traced_once() {
        let s = settings(SamplerKind::Corners, 5);
        let (w, h) = (4, 3);
        let mut corners = std::collections::BTreeMap::new();
        for y in 0..h {
            for x in 0..w {
                let got = sample_pixel(&s, w, h, x, y, |_, _| DVec3::ZERO);
                assert_eq!(got[0].film, DVec2::new(x as f64 + 0.5, y as f64 + 0.5));
                for p in &got[1..] {
                    *corners
                        .entry((p.film.x as u32, p.film.y as u32))
                        .or_insert(0) += 1;
                }
            }
        }
        assert_eq!(corners.len(), ((w + 1) * (h + 1)) as usize);
        assert!(corners.values().all(|&n| n == 1));
    }

    #[test]
    fn adaptive_refines_only_where_samples_disagree() {
        let s = settings(SamplerKind::Adaptive, 16);
        // A flat pixel: the first 2×2 level only.
        let flat = sample_pixel(&s, 8, 8, 2, 2, |_, _| DVec3::splat(0.5));
        assert_eq!(flat.len(), 4);
        // An edge at x = 2.3 through pixel 2: everything refines to the 4×4 grid.
        let edge = sample_pixel(&s, 8, 8, 2, 2, |_, f| {
            DVec3::splat(if f.x < 2.3 { 0.0 } else { 1.0 })
        });
        assert_eq!(edge.len(), 4 + 16);
        let area: f64 = edge.iter().map(|p| p.area).sum();
        assert!((area - 1.0).abs() < 1e-12, "areas add to the pixel: {area}");
        for p in &edge {
            assert!(p.film.x > 2.0 && p.film.x < 3.0 && p.film.y > 2.0 && p.film.y < 3.0);
        }
        let idx: Vec<u32> = edge.iter().map(|p| p.index).collect();
        assert_eq!(idx, (0..20).collect::<Vec<_>>());
    }

    #[test]
    fn subsampling_traces_one_pixel_in_k_by_k() {
        let s = RenderSettings {
            subsample: 2,
            ..settings(SamplerKind::Center, 1)
        };
        // Columns and rows 0, 2, 4 and the last one, 5.
        let n: usize = (0..6)
            .flat_map(|y| (0..6).map(move |x| (x, y)))
            .map(|(x, y)| sample_pixel(&s, 6, 6, x, y, |_, _| DVec3::ZERO).len())
            .sum();
        assert_eq!(n, 16);
    }
}
