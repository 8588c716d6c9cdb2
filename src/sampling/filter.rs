use crate::scene::FilterKind;

/// A reconstruction filter: the weight of a sample at offset (dx, dy) from a pixel centre.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Filter {
    pub kind: FilterKind,
    /// Support radius in pixels: samples farther than this in x or y get weight 0.
    pub radius: f64,
    /// Stretch factor: the filter's shape is drawn over `scale` pixels per unit (the
    /// subsampling factor K, so that samples K pixels apart still cover every pixel).
    pub scale: f64,
    /// Samples may lie on a pixel's far border (the corners sampler's shared corners), where
    /// a box of radius 0.5 still reaches them from the next pixel.
    pub border_samples: bool,
}

impl Filter {
    /// The filter with its usual support: box ±0.5 px (the pixel itself), tent ±1, Gaussian
    /// ±1.5 (σ = 0.5), Mitchell–Netravali ±2.
    pub fn new(kind: FilterKind) -> Filter {
        Filter::scaled(kind, 1)
    }

    /// The filter stretched `k` times (subsampling by `k`); `k` = 1 is [`Filter::new`].
    pub fn scaled(kind: FilterKind, k: u32) -> Filter {
        let base = match kind {
            FilterKind::Box => 0.5,
            FilterKind::Tent => 1.0,
            FilterKind::Gaussian => 1.5,
            FilterKind::Mitchell => 2.0,
        };
        let scale = k.max(1) as f64;
        Filter {
            kind,
            radius: base * scale,
            scale,
            border_samples: false,
        }
    }

    /// The filter a render with these settings uses: its kind, stretched by `--subsample`,
    /// reaching border samples when the sampler puts samples on pixel corners.
    pub fn for_settings(settings: &crate::scene::RenderSettings) -> Filter {
        Filter {
            border_samples: settings.sampler == crate::scene::SamplerKind::Corners,
            ..Filter::scaled(settings.filter, settings.subsample)
        }
    }

    // ANCHOR: filter
    /// Separable weight w(dx)·w(dy).
    pub fn weight(&self, dx: f64, dy: f64) -> f64 {
        self.weight_1d(dx) * self.weight_1d(dy)
    }

    pub(super) fn weight_1d(&self, x: f64) -> f64 {
        let x = x.abs();
        if x > self.radius {
            return 0.0;
        }
        let (x, radius) = (x / self.scale, self.radius / self.scale);
        match self.kind {
            FilterKind::Box => 1.0,
            FilterKind::Tent => 1.0 - x / radius,
            FilterKind::Gaussian => {
                // Shifted down so that it reaches 0 at the radius instead of stopping abruptly.
                let sigma: f64 = 0.5;
                let g = |x: f64| (-x * x / (2.0 * sigma * sigma)).exp();
                (g(x) - g(radius)).max(0.0)
            }
            FilterKind::Mitchell => {
                // Mitchell–Netravali with B = C = 1/3 over [-2, 2].
                let (b, c) = (1.0 / 3.0, 1.0 / 3.0);
                if x < 1.0 {
                    ((12.0 - 9.0 * b - 6.0 * c) * x.powi(3)
                        + (-18.0 + 12.0 * b + 6.0 * c) * x * x
                        + (6.0 - 2.0 * b))
                        / 6.0
                } else {
                    ((-b - 6.0 * c) * x.powi(3)
                        + (6.0 * b + 30.0 * c) * x * x
                        + (-12.0 * b - 48.0 * c) * x
                        + (8.0 * b + 24.0 * c))
                        / 6.0
                }
            }
        }
    }
    // ANCHOR_END: filter

    /// How many pixels around a pixel can hold samples that reach it. A neighbour `n` pixels
    /// away holds samples from `n − 0.5` from the centre on, at its border, but only the
    /// corners sampler puts samples there (elsewhere they lie inside [x, x + 1)).
    pub fn reach(&self) -> i64 {
        if self.border_samples {
            (self.radius + 0.5).floor() as i64
        } else {
            (self.radius + 0.5).ceil() as i64 - 1
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn weights() {
        let b = Filter::new(FilterKind::Box);
        assert_eq!(b.weight(0.5, 0.0), 1.0);
        assert_eq!(b.weight(0.51, 0.0), 0.0);
        let t = Filter::new(FilterKind::Tent);
        assert_eq!(t.weight(0.5, 0.0), 0.5);
        let m = Filter::new(FilterKind::Mitchell);
        assert!((m.weight(0.0, 0.0) - (8.0 / 9.0f64).powi(2)).abs() < 1e-12);
        assert!(m.weight(1.5, 0.0) < 0.0); // negative lobe sharpens
        let g = Filter::new(FilterKind::Gaussian);
        assert!(g.weight(0.0, 0.0) > g.weight(1.0, 0.0) && g.weight(1.6, 0.0) == 0.0);
        assert_eq!(b.reach(), 0);
        let corners = Filter {
            border_samples: true,
            ..b
        };
        assert_eq!(corners.reach(), 1); // the shared corners on the far border
        assert_eq!(t.reach(), 1);
        assert_eq!(m.reach(), 2);
        // Stretched for subsampling by 2: the same shape over twice the distance.
        let t2 = Filter::scaled(FilterKind::Tent, 2);
        assert_eq!(t2.weight(1.0, 0.0), t.weight(0.5, 0.0));
        assert_eq!(t2.reach(), 2);
        // The weights of a tent add up to the same total wherever a pixel is (partition of
        // unity on a lattice): one sample per pixel, offsets −1, 0, 1 around any point.
        for off in [0.0, 0.25, 0.5] {
            let sum: f64 = (-2..=2).map(|i| t.weight(i as f64 + off, 0.0)).sum();
            assert!((sum - 1.0).abs() < 1e-12, "{off}: {sum}");
        }
    }
}
