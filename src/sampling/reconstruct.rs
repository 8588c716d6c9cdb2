//! From samples back to pixels: each pixel the filter-weighted mean of the samples near it.

use super::sampler::centre;
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
    let (sum, total) = accumulate(
        &Kernel::new(filter, 1),
        (x, y),
        (width, height),
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

/// The filter as an image's reconstruction applies it, worked out once for all its pixels:
/// how far it reaches, which rows and columns of pixels may own samples, and its 1-D weights
/// at whole-pixel offsets, `taps[reach + i]` = the weight at i pixels. A sample at its pixel's
/// centre (one sample per pixel, the common case) lies a whole number of pixels from every
/// pixel centre, so its weight is two taps multiplied: the same product of the same numbers
/// as [`Filter::weight`] computes, so the same bits, without evaluating the filter (a
/// Gaussian's two `exp`s) for every sample of every pixel.
pub(super) struct Kernel<'f> {
    filter: &'f Filter,
    reach: i64,
    lines: Lines,
    taps: Vec<f64>,
}

impl<'f> Kernel<'f> {
    /// The kernel of `filter` over an image whose pixels trace samples every `subsample`
    /// rows and columns ([`Lines`]).
    pub(super) fn new(filter: &'f Filter, subsample: u32) -> Kernel<'f> {
        let reach = filter.reach();
        Kernel {
            filter,
            reach,
            lines: Lines(subsample),
            taps: (-reach..=reach)
                .map(|i| filter.weight_1d(i as f64))
                .collect(),
        }
    }

    /// The weight of a sample at `film`, owned by pixel q, for the pixel whose centre is
    /// `centre_of`, q being (ox, oy) pixels from that pixel.
    #[inline]
    fn weight(&self, film: DVec2, q: (u32, u32), centre_of: DVec2, (ox, oy): (i64, i64)) -> f64 {
        if film == centre(q.0, q.1) {
            self.taps[(self.reach + ox) as usize] * self.taps[(self.reach + oy) as usize]
        } else {
            let d = film - centre_of;
            self.filter.weight(d.x, d.y)
        }
    }
}

/// Σ w·a·c and Σ w·a over the samples within the filter's reach of pixel (x, y), in the fixed
/// order [`reconstruct`] documents, telling `weighed(qx, qy, k, w)` each nonzero weight.
/// Only the pixels on the kernel's lines (both ways) are asked for samples; the others must
/// own none, so skipping them changes no sum.
#[inline]
fn accumulate<I: IntoIterator<Item = (DVec2, DVec3, f64)>>(
    kernel: &Kernel,
    (x, y): (u32, u32),
    (width, height): (u32, u32),
    samples_of: impl Fn(u32, u32) -> I,
    mut weighed: impl FnMut(u32, u32, usize, f64),
) -> (DVec3, f64) {
    let centre_of = centre(x, y);
    let (reach, lines) = (kernel.reach, kernel.lines);
    let (mut sum, mut total) = (DVec3::ZERO, 0.0);
    let mut visit = |qx: u32, qy: u32| {
        let offset = (qx as i64 - x as i64, qy as i64 - y as i64);
        for (k, (film, color, area)) in samples_of(qx, qy).into_iter().enumerate() {
            let w = kernel.weight(film, (qx, qy), centre_of, offset) * area;
            if w != 0.0 {
                sum += w * color;
                total += w;
                weighed(qx, qy, k, w);
            }
        }
    };
    if reach == 0 && lines.0 <= 1 {
        // Only the pixel's own samples reach it (the box filter, every pixel tracing).
        visit(x, y);
    } else {
        let (x, y) = (x as i64, y as i64);
        for qy in lines.within(y - reach, y + reach, height) {
            for qx in lines.within(x - reach, x + reach, width) {
                visit(qx, qy);
            }
        }
    }
    (sum, total)
}

/// [`reconstruct`]'s colour alone (the same sums, so the same bits), keeping no weights: what
/// the renderer runs for every pixel, with the image's [`Kernel`]. Under `--subsample K` it
/// asks only the pixels that trace (one in K×K) for samples, since the others own none: the
/// stretched filter of a preview reaches K times as far each way, and visiting every pixel
/// of it cost more than tracing the preview.
#[inline]
pub(super) fn reconstruct_color<I: IntoIterator<Item = (DVec2, DVec3, f64)>>(
    kernel: &Kernel,
    (x, y): (u32, u32),
    (width, height): (u32, u32),
    samples_of: impl Fn(u32, u32) -> I,
) -> DVec3 {
    let (sum, total) = accumulate(kernel, (x, y), (width, height), samples_of, |_, _, _, _| {});
    if total.abs() < 1e-12 {
        DVec3::ZERO
    } else {
        sum / total
    }
}
// ANCHOR_END: reconstruct

/// The rows (or columns) of pixels that may own samples: under `--subsample K`, the
/// multiples of K and the last one ([`super::traces_samples`]); `Lines(1)`, every one.
#[derive(Clone, Copy)]
struct Lines(u32);

impl Lines {
    /// Those of lo..=hi (within 0..n), in increasing order.
    #[inline]
    fn within(self, lo: i64, hi: i64, n: u32) -> LinesWithin {
        let (lo, hi) = (lo.max(0), hi.min(n as i64 - 1));
        let k = self.0.max(1) as i64;
        if k == 1 {
            // Every line (no subsampling, the common case), without dividing.
            return LinesWithin {
                next: lo,
                hi,
                step: 1,
                tail: None,
            };
        }
        // The last line traces too; it is listed after the multiples, which are all below it.
        let last = n as i64 - 1;
        LinesWithin {
            next: (lo + k - 1) / k * k,
            hi,
            step: k,
            tail: (last >= lo && last <= hi && last % k != 0).then_some(last as u32),
        }
    }
}

/// [`Lines::within`]: `next`, `next + step`, … up to `hi`, then `tail`.
struct LinesWithin {
    next: i64,
    hi: i64,
    step: i64,
    tail: Option<u32>,
}

impl Iterator for LinesWithin {
    type Item = u32;
    #[inline]
    fn next(&mut self) -> Option<u32> {
        if self.next <= self.hi {
            let q = self.next as u32;
            self.next += self.step;
            Some(q)
        } else {
            self.tail.take()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::RenderSettings;

    /// A centre sample's weight from the kernel's taps is, bit for bit, what the filter
    /// itself gives at that offset, for every filter, stretch and offset within reach.
    #[test]
    fn taps_weigh_centre_samples_as_the_filter_does() {
        use crate::scene::FilterKind;
        for kind in [
            FilterKind::Box,
            FilterKind::Tent,
            FilterKind::Gaussian,
            FilterKind::Mitchell,
        ] {
            for k in 1..=4u32 {
                let filter = Filter::scaled(kind, k);
                let kernel = Kernel::new(&filter, k);
                let (x, y) = (20u32, 30u32);
                let r = kernel.reach;
                for oy in -r..=r {
                    for ox in -r..=r {
                        let q = ((x as i64 + ox) as u32, (y as i64 + oy) as u32);
                        let d = centre(q.0, q.1) - centre(x, y);
                        let want = filter.weight(d.x, d.y);
                        let got = kernel.weight(centre(q.0, q.1), q, centre(x, y), (ox, oy));
                        assert_eq!(got.to_bits(), want.to_bits(), "{kind:?} x{k} at {ox},{oy}");
                    }
                }
            }
        }
    }

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
