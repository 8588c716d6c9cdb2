//! The figure of `rtlab intersect box --bundle-to`: a bundle of rays against one box of a
//! BVH node. Left, the rays and the box seen along y, with the interval test's two bounds
//! drawn where they fall on every ray; right, the same test along t: each axis's bounds as
//! a bar, the three together, and each ray's own entry.

use super::canvas::{Anchor, Canvas};
use super::style;
use crate::accel::BundleWorking;
use crate::math::Ray;
use crate::shapes::working::short;
use glam::DVec2;

const W: f32 = 960.0;
const H: f32 = 500.0;
const MARGIN: f32 = 24.0;
const TOP: f32 = 96.0;
const BOTTOM: f32 = 40.0;
const GAP: f32 = 40.0;

/// The figure for `rays` and their `working` (from [`crate::accel::bundle_working`]).
pub fn figure(rays: &[Ray], w: &BundleWorking) -> Canvas {
    let mut c = Canvas::new(W as u32, H as u32, style::background());
    let n = rays.len();
    let entering = w.rays.iter().filter(|v| v.lane.unwrap_or(v.own)).count();
    c.text(
        (MARGIN, 22.0),
        &format!("The interval test: a bundle of {n} rays against one box of a BVH node"),
        15.0,
        style::ink(),
        Anchor::Left,
    );
    let verdict = match w.kept {
        None => "not sign-coherent (a direction changes sign along an axis): no interval test, each ray goes alone".to_string(),
        Some(true) => format!(
            "kept: the bounds leave room for a ray to enter; then the lane test: {entering} of {n} rays enter"
        ),
        Some(false) => format!(
            "culled: the bundle's entry bound comes after its exit bound, so all {n} rays miss ({entering} enter by their own tests)"
        ),
    };
    c.text((MARGIN, 44.0), &verdict, 12.0, style::ink(), Anchor::Left);
    c.text(
        (MARGIN, 64.0),
        "left: seen along y (z to the right, x up); right: the same test along t, the distance along each ray (P + t·d)",
        12.0,
        style::muted(),
        Anchor::Left,
    );
    let bounds = w.together;
    let split = (W - GAP) / 2.0;
    space(&mut c, rays, w, bounds, (MARGIN, TOP, split, H - BOTTOM));
    times(
        &mut c,
        w,
        bounds,
        (split + GAP, TOP, W - MARGIN, H - BOTTOM),
    );
    c.text(
        (MARGIN, H - 16.0),
        "Red dots: where each ray's own slab test says it enters. Grey rays miss the box. The bounds hold for every ray at once.",
        11.0,
        style::ink(),
        Anchor::Left,
    );
    c
}

/// (z, x) of a 3D point: the view along y.
fn zx(p: glam::DVec3) -> DVec2 {
    DVec2::new(p.z, p.x)
}

/// Left panel: box, rays, entry dots, and the two bounds as fronts across the rays.
fn space(
    c: &mut Canvas,
    rays: &[Ray],
    w: &BundleWorking,
    bounds: Option<(f32, f32)>,
    (x0, y0, x1, y1): (f32, f32, f32, f32),
) {
    let (bmin, bmax) = (
        DVec2::new(w.min[2] as f64, w.min[0] as f64),
        DVec2::new(w.max[2] as f64, w.max[0] as f64),
    );
    let origin = zx(rays[0].origin);
    let (mut lo, mut hi) = (bmin.min(origin), bmax.max(origin));
    let pad = (hi - lo).max_element() * 0.15;
    (lo, hi) = (lo - pad, hi + pad);
    // One scale for both axes, centred in the panel.
    let (pw, ph) = ((x1 - x0) as f64, (y1 - y0) as f64);
    let scale = (pw / (hi.x - lo.x)).min(ph / (hi.y - lo.y));
    let centre = (lo + hi) * 0.5;
    let map = |p: DVec2| -> (f32, f32) {
        (
            (x0 as f64 + pw / 2.0 + (p.x - centre.x) * scale) as f32,
            (y0 as f64 + ph / 2.0 - (p.y - centre.y) * scale) as f32,
        )
    };
    let (vlo, vhi) = (
        centre - DVec2::new(pw, ph) / (2.0 * scale),
        centre + DVec2::new(pw, ph) / (2.0 * scale),
    );
    c.rect(
        (x0, y0),
        (x1 - x0, y1 - y0),
        Some((style::grid(), 1.0)),
        None,
    );
    // The box.
    let (a, b) = (map(bmin), map(bmax));
    let corner = (a.0.min(b.0), a.1.min(b.1));
    let size = ((b.0 - a.0).abs(), (b.1 - a.1).abs());
    if w.kept == Some(false) {
        let pts = [
            corner,
            (corner.0 + size.0, corner.1),
            (corner.0 + size.0, corner.1 + size.1),
            (corner.0, corner.1 + size.1),
        ];
        for i in 0..4 {
            c.line(pts[i], pts[(i + 1) % 4], style::tossed(), 1.6, true);
        }
    } else {
        c.rect(
            corner,
            size,
            Some((style::shape_stroke(), 1.6)),
            Some(style::shape_fill()),
        );
    }
    // Under the box, outside it: a label inside would cover the entry dots of the rays
    // that enter through its lower side.
    c.text(
        (corner.0 + size.0, corner.1 + size.1 + 9.0),
        "box",
        11.0,
        style::muted(),
        Anchor::Right,
    );
    // Each ray from its origin to where it leaves the view.
    let leave = |r: &Ray| -> f64 {
        let (o, d) = (zx(r.origin), zx(r.dir));
        let mut t = f64::INFINITY;
        for (o, d, lo, hi) in [(o.x, d.x, vlo.x, vhi.x), (o.y, d.y, vlo.y, vhi.y)] {
            if d != 0.0 {
                t = t.min(((lo - o) / d).max((hi - o) / d));
            }
        }
        t
    };
    for (r, v) in rays.iter().zip(&w.rays) {
        let color = if v.lane.unwrap_or(v.own) {
            style::ray(crate::trace::RayKind::Camera)
        } else {
            style::tossed()
        };
        c.line(
            map(zx(r.origin)),
            map(zx(r.at(leave(r)))),
            color,
            1.0,
            false,
        );
    }
    // The bounds: where each ray is at t = bound, joined across the bundle.
    if let Some((entry, exit)) = bounds {
        for (t, name) in [(entry, "entry bound"), (exit, "exit bound")] {
            let t = t as f64;
            if !t.is_finite() || rays.iter().any(|r| t > leave(r)) {
                continue;
            }
            let pts: Vec<(f32, f32)> = rays.iter().map(|r| map(zx(r.at(t)))).collect();
            for p in pts.windows(2) {
                c.line(p[0], p[1], style::ink(), 1.4, true);
            }
            // The entry bound's label above the front, the exit bound's below it.
            let top = pts
                .iter()
                .copied()
                .fold(pts[0], |m, p| if p.1 < m.1 { p } else { m });
            let low = pts
                .iter()
                .copied()
                .fold(pts[0], |m, p| if p.1 > m.1 { p } else { m });
            let (at, dy) = if name == "entry bound" {
                (top, -10.0)
            } else {
                (low, 12.0)
            };
            c.text(
                (at.0, at.1 + dy),
                &format!("t = {name}"),
                11.0,
                style::ink(),
                Anchor::Center,
            );
        }
    }
    for (r, v) in rays.iter().zip(&w.rays).filter(|(_, v)| v.own) {
        let p = map(zx(r.at(v.t_enter as f64)));
        c.circle(p, 3.5, Some((style::background(), 1.2)), Some(style::hit()));
    }
    c.circle(map(origin), 3.0, None, Some(style::ink()));
    let o = map(origin);
    c.text((o.0, o.1 + 14.0), "P", 12.0, style::ink(), Anchor::Center);
}

/// Right panel: the t axis, a row per slab, the three together, and the rays' own entries.
fn times(
    c: &mut Canvas,
    w: &BundleWorking,
    bounds: Option<(f32, f32)>,
    (x0, y0, x1, y1): (f32, f32, f32, f32),
) {
    let label_w = 150.0;
    let (t0, t1) = (x0 + label_w + 40.0, x1 - 50.0);
    // The scale: from 0 (where the walk starts each ray) to past the bounds that decide and
    // every ray's entry; a bar beyond either end is cut there, its true end written beside.
    let focus = bounds
        .iter()
        .flat_map(|&(a, b)| [a, b])
        .chain(w.rays.iter().filter(|v| v.own).map(|v| v.t_enter))
        .filter(|t| t.is_finite());
    let t_max = focus.fold(0.0f32, f32::max).max(1e-6) * 1.6;
    let at = |t: f32| t0 + (t.clamp(0.0, t_max) / t_max) * (t1 - t0);
    let rows = 6.0;
    let row_h = ((y1 - y0) - 40.0) / rows;
    let row_y = |i: usize| y0 + 10.0 + row_h * (i as f32 + 0.5);
    let num = |t: f32| {
        if t.is_finite() {
            short(t as f64)
        } else {
            "∞".to_string()
        }
    };
    let bar = |c: &mut Canvas, y: f32, a: f32, b: f32| {
        let (xa, xb) = (at(a), at(b));
        c.rect(
            (xa, y - 8.0),
            (xb - xa, 16.0),
            Some((style::shape_stroke(), 1.4)),
            Some(style::shape_fill()),
        );
        let cut = |t: f32| {
            if (0.0..=t_max).contains(&t) {
                ""
            } else {
                " (cut)"
            }
        };
        c.text(
            (xa - 4.0, y),
            &format!("{}{}", num(a), cut(a)),
            10.0,
            style::ink(),
            Anchor::Right,
        );
        c.text(
            (xb + 4.0, y),
            &format!("{}{}", num(b), cut(b)),
            10.0,
            style::ink(),
            Anchor::Left,
        );
    };
    for (k, axis) in w.axes.iter().enumerate() {
        let y = row_y(k);
        let name = ["x", "y", "z"][k];
        c.text(
            (x0, y),
            &format!("{name} slab: bounds"),
            12.0,
            style::ink(),
            Anchor::Left,
        );
        match axis {
            Some((a, b)) => bar(c, y, *a, *b),
            None => c.text(
                (t0, y),
                if w.kept.is_some() {
                    "no bound (some ray's 1/d is ±∞ along it)"
                } else {
                    "no interval test (not sign-coherent)"
                },
                11.0,
                style::muted(),
                Anchor::Left,
            ),
        }
    }
    let y = row_y(3);
    c.text(
        (x0, y),
        "all three: entry–exit",
        12.0,
        style::ink(),
        Anchor::Left,
    );
    match (bounds, w.kept) {
        (Some((a, b)), Some(true)) => bar(c, y, a, b),
        (Some((a, b)), _) => {
            c.line((at(b), y), (at(a), y), style::hit(), 2.0, false);
            c.text(
                ((at(a) + at(b)) / 2.0, y - 14.0),
                "empty: entry after exit → culled",
                11.0,
                style::hit(),
                Anchor::Center,
            );
            c.text(
                (at(b) - 4.0, y),
                &format!("exit {}", num(b)),
                10.0,
                style::ink(),
                Anchor::Right,
            );
            c.text(
                (at(a) + 4.0, y),
                &format!("entry {}", num(a)),
                10.0,
                style::ink(),
                Anchor::Left,
            );
        }
        (None, _) => c.text(
            (t0, y),
            "no interval test",
            11.0,
            style::muted(),
            Anchor::Left,
        ),
    }
    let y = row_y(4);
    c.text(
        (x0, y),
        "each ray's own entry",
        12.0,
        style::ink(),
        Anchor::Left,
    );
    let own: Vec<f32> = w.rays.iter().filter(|v| v.own).map(|v| v.t_enter).collect();
    if own.is_empty() {
        c.text((t0, y), "none enters", 11.0, style::muted(), Anchor::Left);
    }
    for t in own {
        c.circle(
            (at(t), y),
            3.5,
            Some((style::background(), 1.2)),
            Some(style::hit()),
        );
    }
    // The t axis.
    let y = row_y(5);
    c.line((t0, y), (t1, y), style::ink(), 1.0, false);
    for i in 0..=4 {
        let t = t_max * i as f32 / 4.0;
        c.line((at(t), y - 4.0), (at(t), y + 4.0), style::ink(), 1.0, false);
        c.text(
            (at(t), y + 14.0),
            &num(t),
            10.0,
            style::ink(),
            Anchor::Center,
        );
    }
    c.text((t1 + 6.0, y), "t", 12.0, style::ink(), Anchor::Left);
}
