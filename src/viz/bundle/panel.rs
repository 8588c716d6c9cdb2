//! The bundle figure's panels: a view of the mesh's box from above, and what is drawn in it
//! (boxes entered and culled, the bundle's frustum, its rays and hits), clipped to the
//! panel's frame; and the figure's colours.

use super::super::canvas::{Anchor, Canvas};
use super::super::labels::{text_box, Box2};
use super::super::style;
use crate::math::Ray;
use crate::shapes::{Aabb, LocalHit};
use glam::{DVec2, DVec3};

pub(super) fn entered_fill() -> tiny_skia::Color {
    style::rgba(90, 140, 200, 60)
}

/// The four edges of the rectangle from `min` to `max` (pixels), each a line (dashed: the
/// dashes start again at each corner).
pub(super) fn edges(
    c: &mut Canvas,
    (x0, y0): (f32, f32),
    (x1, y1): (f32, f32),
    color: tiny_skia::Color,
    width: f32,
    dashed: bool,
) {
    for (p, q) in [
        ((x0, y0), (x1, y0)),
        ((x1, y0), (x1, y1)),
        ((x1, y1), (x0, y1)),
        ((x0, y1), (x0, y0)),
    ] {
        c.line(p, q, color, width, dashed);
    }
}

/// The frustum's fill: a pale yellow, see-through, so the boxes under it keep their look.
pub(super) fn frustum_fill() -> tiny_skia::Color {
    style::rgba(245, 200, 40, 70)
}

/// The dashes of a culled box: darker than the figures' usual tossed grey, to read on blue.
pub(super) fn culled_color() -> tiny_skia::Color {
    style::rgb(110, 110, 120)
}

/// The outline of a box the bundle opened, drawn on its own frame under its children: dark
/// enough to tell from their blue edges, solid (dashes are the culled boxes').
pub(super) fn opened_color() -> tiny_skia::Color {
    style::rgba(50, 50, 60, 190)
}

/// Draws `text` on a pale plate (its box, `pad` pixels wider each side and 1 taller, unless
/// `pad` is 0), so that the lines under it do not cross its letters; returns the plate.
pub(super) fn plated_text(
    c: &mut Canvas,
    at: (f32, f32),
    text: &str,
    size: f32,
    color: tiny_skia::Color,
    anchor: Anchor,
    pad: f32,
) -> Box2 {
    let [x0, y0, x1, y1] = text_box(at, text, size, anchor);
    let grow = (pad, if pad > 0.0 { 1.0 } else { 0.0 });
    let plate = [x0 - grow.0, y0 - grow.1, x1 + grow.0, y1 + grow.1];
    c.rect(
        (plate[0], plate[1]),
        (plate[2] - plate[0], plate[3] - plate[1]),
        None,
        Some(style::rgba(255, 255, 255, 225)),
    );
    c.text(at, text, size, color, anchor);
    plate
}

/// One panel: the mesh's box (x right, z down) and a margin around it, fitted into a
/// rectangle of the figure; what it draws is clipped to its frame (`at`, `size`).
pub(super) struct Panel {
    pub at: (f32, f32),
    pub size: (f32, f32),
    centre: DVec2,
    /// Half the drawn extent in x and z, in object units.
    half: DVec2,
    scale: f64,
}

impl Panel {
    pub(super) fn fit(b: &Aabb, at: (f32, f32), size: (f32, f32)) -> Panel {
        // A mesh flat in x or z (a wall seen edge-on from above) still gets a band to draw
        // its rays across: neither side under a fifth of the other.
        let raw = DVec2::new(b.max.x - b.min.x, b.max.z - b.min.z);
        let extent = raw
            .max(DVec2::splat(raw.max_element() * 0.2))
            .max(DVec2::splat(1e-9))
            * 1.08;
        let scale = (size.0 as f64 / extent.x).min(size.1 as f64 / extent.y);
        // The frame hugs the root's box and its margin, centred across the space given.
        let fitted = ((extent.x * scale) as f32, (extent.y * scale) as f32);
        Panel {
            at: (at.0 + (size.0 - fitted.0) * 0.5, at.1),
            size: fitted,
            centre: DVec2::new(b.min.x + b.max.x, b.min.z + b.max.z) * 0.5,
            half: extent * 0.5,
            scale,
        }
    }

    /// Pixels per object unit.
    pub(super) fn scale(&self) -> f64 {
        self.scale
    }

    pub(super) fn map(&self, p: DVec3) -> (f32, f32) {
        (
            (self.at.0 as f64 + self.size.0 as f64 * 0.5 + (p.x - self.centre.x) * self.scale)
                as f32,
            (self.at.1 as f64 + self.size.1 as f64 * 0.5 + (p.z - self.centre.y) * self.scale)
                as f32,
        )
    }

    pub(super) fn outline(
        &self,
        c: &mut Canvas,
        bx: &Aabb,
        color: tiny_skia::Color,
        width: f32,
        dashed: bool,
    ) {
        let (a, z) = (self.map(bx.min), self.map(bx.max));
        let (min, max) = ((a.0.min(z.0), a.1.min(z.1)), (a.0.max(z.0), a.1.max(z.1)));
        edges(c, min, max, color, width, dashed);
    }

    /// A tested box: filled and outlined if some ray entered it, dashed if all missed it;
    /// drawn `inset` pixels inside its edges (less on a box too small for that).
    pub(super) fn level_box(&self, c: &mut Canvas, bx: &Aabb, entered: bool, inset: f32) {
        let (a, z) = (self.map(bx.min), self.map(bx.max));
        let size = ((z.0 - a.0).abs(), (z.1 - a.1).abs());
        let inset = inset.min(size.0.min(size.1) * 0.25);
        let min = (a.0.min(z.0) + inset, a.1.min(z.1) + inset);
        let size = (size.0 - 2.0 * inset, size.1 - 2.0 * inset);
        if entered {
            c.rect(
                min,
                size,
                Some((style::shape_stroke(), 1.8)),
                Some(entered_fill()),
            );
        } else {
            let far = (min.0 + size.0, min.1 + size.1);
            edges(c, min, far, culled_color(), 1.6, true);
        }
    }

    /// A t at which ray `r` is past the mesh's box `b` and the panel: its distance to the
    /// box's centre, the box's diagonal and twice the panel's width beyond, over the length
    /// of its direction (in the mesh's own space a direction is not of unit length when the
    /// mesh is scaled). Every hit on the mesh comes before it.
    fn far_t(&self, r: &Ray, b: &Aabb) -> f64 {
        let beyond = (b.max - b.min).length() + 4.0 * self.half.max_element();
        (r.origin.distance(b.centroid()) + beyond) / r.dir.length()
    }

    /// Where `p` is drawn, in f64 for clipping.
    fn point(&self, p: DVec3) -> DVec2 {
        let (x, y) = self.map(p);
        DVec2::new(x as f64, y as f64)
    }

    /// The panel's frame, its top-left and bottom-right corners.
    fn frame(&self) -> (DVec2, DVec2) {
        let min = DVec2::new(self.at.0 as f64, self.at.1 as f64);
        (
            min,
            min + DVec2::new(self.size.0 as f64, self.size.1 as f64),
        )
    }

    /// The bundle's frustum as the panel shows it, filled pale under the rays: the smallest
    /// convex region holding every ray from its origin to well past the panel (hits or not),
    /// cut by the frame. With one origin (a pinhole camera) it is the wedge between the
    /// outermost rays.
    pub(super) fn frustum(&self, c: &mut Canvas, rays: &[Ray], b: &Aabb) {
        let ends = rays
            .iter()
            .flat_map(|r| [self.point(r.origin), self.point(r.at(self.far_t(r, b)))])
            .collect();
        let (min, max) = self.frame();
        let cut = crate::viz::clip::polygon(crate::viz::clip::convex_hull(ends), min, max);
        if cut.len() >= 3 {
            let corners: Vec<(f32, f32)> = cut.iter().map(|p| (p.x as f32, p.y as f32)).collect();
            c.polygon(&corners, None, Some(frustum_fill()));
        }
    }

    /// The rays, from where they enter the panel to their hit (a dot) or across it. The dots
    /// go on after every line, in the figures' hit colour with a white rim, so that no ray's
    /// line hides another ray's hit. Returns how many rays it drew.
    pub(super) fn rays(
        &self,
        c: &mut Canvas,
        rays: &[Ray],
        hits: &[Option<LocalHit>],
        b: &Aabb,
    ) -> usize {
        let mut drawn = 0;
        let color = style::ray(crate::trace::RayKind::Camera);
        let mut dots = Vec::new();
        let (min, max) = self.frame();
        for (r, hit) in rays.iter().zip(hits) {
            // From the origin to the hit, or on past the panel, cut by the frame.
            let end = r.at(hit.map_or(self.far_t(r, b), |h| h.t));
            let Some((a, z)) =
                crate::viz::clip::segment(self.point(r.origin), self.point(end), min, max)
            else {
                continue;
            };
            // A ray seen end-on from above (straight down) is only its hit's dot.
            if a != z {
                c.line(
                    (a.x as f32, a.y as f32),
                    (z.x as f32, z.y as f32),
                    color,
                    1.0,
                    false,
                );
            }
            drawn += 1;
            // The hit is shown when it is inside the frame.
            let at = self.point(end);
            if hit.is_some() && at.cmpge(min).all() && at.cmple(max).all() {
                dots.push((at.x as f32, at.y as f32));
            }
        }
        for at in dots {
            c.circle(
                at,
                3.5,
                Some((style::background(), 1.2)),
                Some(style::hit()),
            );
        }
        drawn
    }
}
