//! The left panel of the interval figure: which axis it looks along (the one from which the
//! rays' fan looks widest), and how the scene lands on its pixels.

use crate::accel::BundleWorking;
use crate::math::Ray;
use glam::DVec2;

/// The left panel's projection: the scene seen along one axis, drawn in pixels, one scale
/// for both directions.
pub(super) struct View {
    /// The axis seen along, then the axes drawn to the right and up.
    pub(super) axes: [usize; 3],
    /// The panel, in pixels: (x0, y0, x1, y1).
    pub(super) rect: (f64, f64, f64, f64),
    /// The point drawn at the panel's centre, (right, up), and pixels per unit.
    pub(super) centre: DVec2,
    pub(super) scale: f64,
}

impl View {
    /// Seen along the axis that shows the bundle best: of the views in which every ray
    /// is a clear line (at least half its length across the view; the axis in which the
    /// unit directions are smallest always qualifies, at worst with 0.58), the one in which
    /// the rays' fan looks widest; y on ties (the book's view). To the right, of the other two
    /// axes, the one the rays move along most (on ties, the next after the view axis: z, x
    /// for y), so P + t·d reads left to right as on the t axis. The box and P fill the panel.
    pub(super) fn new(
        rays: &[Ray],
        w: &BundleWorking,
        (x0, y0, x1, y1): (f32, f32, f32, f32),
    ) -> View {
        let unit = |r: &Ray, k: usize| (r.dir[k] / r.dir.length()).abs();
        let most = |k: usize| rays.iter().map(|r| unit(r, k)).fold(0.0, f64::max);
        let mean = |k: usize| rays.iter().map(|r| unit(r, k)).sum::<f64>();
        let across = |k: usize, d: glam::DVec3| DVec2::new(d[(k + 1) % 3], d[(k + 2) % 3]);
        let clear = |k: usize| {
            rays.iter()
                .all(|r| across(k, r.dir).length() >= 0.5 * r.dir.length())
        };
        let fan = |k: usize| {
            let (a, b) = (across(k, rays[0].dir), across(k, rays[rays.len() - 1].dir));
            a.angle_to(b).abs()
        };
        // The first of the clear views that fans out most; never empty, but should it be,
        // the axis in which the directions are smallest.
        let along = [1, 0, 2]
            .into_iter()
            .filter(|&k| clear(k))
            .reduce(|best, k| if fan(k) > fan(best) + 1e-9 { k } else { best })
            .unwrap_or_else(|| {
                [1, 0, 2]
                    .into_iter()
                    .min_by(|&a, &b| most(a).total_cmp(&most(b)))
                    .expect("three axes")
            });
        let (mut right, mut up) = ((along + 1) % 3, (along + 2) % 3);
        if mean(up) > mean(right) {
            (right, up) = (up, right);
        }
        let flat = |p: [f64; 3]| DVec2::new(p[right], p[up]);
        let (bmin, bmax) = (flat(w.min.map(f64::from)), flat(w.max.map(f64::from)));
        let origin = flat(rays[0].origin.to_array());
        let (lo, hi) = (bmin.min(origin), bmax.max(origin));
        let pad = (hi - lo).max_element().max(1e-6) * 0.15;
        let (lo, hi) = (lo - pad, hi + pad);
        let rect = (x0 as f64, y0 as f64, x1 as f64, y1 as f64);
        let scale = ((rect.2 - rect.0) / (hi.x - lo.x)).min((rect.3 - rect.1) / (hi.y - lo.y));
        View {
            axes: [along, right, up],
            rect,
            centre: (lo + hi) * 0.5,
            scale,
        }
    }

    /// A 3D point in pixels.
    pub(super) fn px(&self, p: glam::DVec3) -> DVec2 {
        let (x0, y0, x1, y1) = self.rect;
        DVec2::new(
            (x0 + x1) / 2.0 + (p[self.axes[1]] - self.centre.x) * self.scale,
            (y0 + y1) / 2.0 - (p[self.axes[2]] - self.centre.y) * self.scale,
        )
    }

    pub(super) fn inside(&self, p: DVec2) -> bool {
        let (x0, y0, x1, y1) = self.rect;
        (x0..=x1).contains(&p.x) && (y0..=y1).contains(&p.y)
    }

    /// The part of segment a–b inside the panel, or `None`.
    pub(super) fn clip(&self, a: DVec2, b: DVec2) -> Option<(DVec2, DVec2)> {
        let (x0, y0, x1, y1) = self.rect;
        crate::viz::clip::segment(a, b, DVec2::new(x0, y0), DVec2::new(x1, y1))
    }

    /// The t at which `r`, from P inside the panel, leaves it: `None` for a ray seen
    /// end-on (its motion across the view under 10⁻⁶ of its length; the choice of view
    /// rules that out, but the drawing must not depend on it). Such a ray has no such t:
    /// an unguarded ∞ here put 0·∞ = NaN into the drawing, which tiny-skia drew as a line
    /// towards the canvas's corner, through the title.
    pub(super) fn leave(&self, r: &Ray) -> Option<f64> {
        let (x0, y0, x1, y1) = self.rect;
        let (o, d) = (
            self.px(r.origin),
            self.px(r.origin + r.dir) - self.px(r.origin),
        );
        // Across the view, in pixels per unit of t, against the whole direction's length.
        if d.length() < 1e-6 * r.dir.length() * self.scale {
            return None;
        }
        let mut t = f64::INFINITY;
        for (o, d, lo, hi) in [(o.x, d.x, x0, x1), (o.y, d.y, y0, y1)] {
            if d != 0.0 {
                t = t.min(((lo - o) / d).max((hi - o) / d));
            }
        }
        t.is_finite().then_some(t)
    }
}
