//! The figures of `rtlab intersect` (DESIGN §6): the ray, the shape (or the section of it the
//! figure's plane cuts), every candidate root (kept in red, tossed in grey with its reason)
//! and, below the drawing, the equation, the discriminant and the verdict.
//!
//! Each shape picks the 2D view that shows its working:
//! - circle: the plane itself; sphere: the plane through the ray and the centre (a great
//!   circle);
//! - plane: the plane of the normal and the ray (the plane seen edge-on);
//! - cylinder and cone: a side view, the vertical plane that contains the ray (the shape's
//!   section in it, its silhouette dashed, and the infinite surface and cap planes dotted,
//!   where tossed roots land);
//! - box: looking along the axis the ray moves least on, slabs shaded;
//! - triangle: the triangle's own plane, the three sub-triangles shaded by their weights.
//!
//! Everything drawn is computed from the [`Report`] (the routine's own working) plus plain
//! projections; the figure solves nothing.

mod outline;
mod panel;
mod view;

use super::labels::{around, around_rings, Labels};
use super::style;
use super::{Anchor, Canvas};
use crate::report::intersect::Report;
use crate::shapes::working::short;
use crate::shapes::Roots;
use glam::DVec3;
use outline::{draw_shape, line};
pub use panel::height;
use panel::panel;
use tiny_skia::Color;

pub const WIDTH: u32 = 720;
const PLOT: [f32; 4] = [16.0, 40.0, 704.0, 350.0];

/// Clips a pixel segment to the plot (Liang–Barsky, shared with the slice diagram).
fn clip(a: (f32, f32), b: (f32, f32)) -> Option<((f32, f32), (f32, f32))> {
    super::slice::clip(a, b, PLOT)
}

/// A label waiting to be placed once every line and mark is down.
type Pending = (Vec<((f32, f32), Anchor)>, String, f32, Color);

/// The figure of an `intersect` report.
pub fn figure(r: &Report) -> Canvas {
    let mut c = Canvas::new(WIDTH, height(r), style::background());
    let (v, title) = view::fitted(r);

    let mut labels = Labels::new(PLOT);
    c.text(
        (WIDTH as f32 / 2.0, 18.0),
        &title,
        14.0,
        style::ink(),
        Anchor::Center,
    );
    let mut pending: Vec<Pending> = Vec::new();
    draw_shape(&mut c, r, &v, &mut labels, &mut pending);

    // The ray: behind the origin dotted, ahead solid to the plot's edge.
    let ray_color = style::ray(crate::trace::RayKind::Camera);
    let o = v.px(r.ray3.origin);
    let dpx = {
        let q = v.px(r.ray3.origin + r.ray3.dir);
        (q.0 - o.0, q.1 - o.1)
    };
    let len = dpx.0.hypot(dpx.1);
    if len > 1e-3 {
        let (ux, uy) = (dpx.0 / len, dpx.1 / len);
        let far = 4000.0;
        line(
            &mut c,
            &mut labels,
            o,
            (o.0 - ux * far, o.1 - uy * far),
            style::muted(),
            1.2,
            true,
        );
        if let Some((a, b)) = clip(o, (o.0 + ux * far, o.1 + uy * far)) {
            c.arrow(a, b, ray_color, 2.2);
            labels.block_segment(a, b, 2.5);
        }
    } else {
        // The ray is perpendicular to the view: it pierces it at P.
        c.circle(o, 6.0, Some((ray_color, 1.8)), None);
    }
    c.circle(o, 4.0, None, Some(style::ink()));
    labels.block_point(o, 5.0);
    let pierce = r.candidates.first().map(|c| v.px(r.ray3.at(c.t)));
    if pierce.is_some_and(|q| (q.0 - o.0).hypot(q.1 - o.1) < 14.0) {
        // The ray comes straight at the view: P is right above the point it pierces.
        labels.place_any(
            &mut c,
            &around_rings(o, 12.0),
            "P (above)",
            12.0,
            style::ink(),
        );
    } else {
        labels.place_any(&mut c, &around_rings(o, 9.0), "P", 13.0, style::ink());
    }

    // The hit's normal.
    if let Some(h) = &r.hit {
        let p = r.ray3.at(h.t);
        let n = if h.normal.len() == 2 {
            DVec3::new(h.normal[0], h.normal[1], 0.0)
        } else {
            DVec3::new(h.normal[0], h.normal[1], h.normal[2])
        };
        let a = v.px(p);
        let b = v.px(p + n * (34.0 / v.scale));
        if (b.0 - a.0).hypot(b.1 - a.1) > 6.0 && clip(a, a).is_some() {
            c.arrow(a, b, style::normal(), 1.8);
            labels.place(&mut c, &around(b, 7.0), "n", 12.0, style::normal());
        }
    }

    // Candidates: kept red, tossed grey (hollow).
    let kept_t = r.hit.as_ref().map(|h| h.t);
    for (i, cand) in r.candidates.iter().enumerate() {
        let p = v.px(r.ray3.at(cand.t));
        if clip(p, p).is_none() {
            continue;
        }
        let kept = kept_t == Some(cand.t) && cand.note.starts_with("kept");
        if kept {
            c.circle(p, 5.5, Some((style::background(), 1.5)), Some(style::hit()));
        } else {
            c.circle(
                p,
                4.5,
                Some((style::tossed(), 1.8)),
                Some(style::background()),
            );
        }
        labels.block_point(p, 5.0);
        let tangent = r
            .quadratic
            .as_ref()
            .is_some_and(|q| q.roots == Roots::Tangent);
        let name = if r.candidates.len() == 1 && tangent {
            let pt: Vec<String> = cand.point.iter().map(|x| short(*x)).collect();
            format!("t = {}: tangent at ({})", short(cand.t), pt.join(", "))
        } else if r.candidates.len() == 1 {
            format!("t = {}", short(cand.t))
        } else {
            format!("t{} = {}", i + 1, short(cand.t))
        };
        let color = if kept {
            style::hit()
        } else {
            style::rgb(120, 120, 128)
        };
        labels.place_any(&mut c, &around_rings(p, 9.0), &name, 12.0, color);
    }
    for (cands, text, size, color) in pending {
        labels.place_any(&mut c, &cands, &text, size, color);
    }
    panel(&mut c, r);
    c
}
