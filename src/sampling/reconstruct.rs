//! From samples back to pixels: each pixel the filter-weighted mean of the samples near it.

use super::Filter;
use glam::{DVec2, DVec3};

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
#[inline]
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
#[inline]
pub(super) fn reconstruct_color<I: IntoIterator<Item = (DVec2, DVec3, f64)>>(
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::RenderSettings;

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
}
