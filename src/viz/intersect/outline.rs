//! The shape in each figure (outlines, fills, sections, slabs, sub-triangles) and the
//! drawing helpers that keep labels off every line, drawn before the ray.

use super::view::{box_axes, side_offset, View};
use super::{clip, Pending, PLOT};
use crate::report::intersect::Report;
use crate::shapes::working::short;
use crate::shapes::{Cone, Cuboid, Cylinder, Shape, Sphere, Triangle};
use crate::viz::labels::{around, Labels};
use crate::viz::style;
use crate::viz::{Anchor, Canvas};
use tiny_skia::Color;

/// Draws a segment clipped to the plot and keeps labels off it.
pub(super) fn line(
    c: &mut Canvas,
    l: &mut Labels,
    a: (f32, f32),
    b: (f32, f32),
    color: Color,
    width: f32,
    dashed: bool,
) {
    if let Some((a, b)) = clip(a, b) {
        c.line(a, b, color, width, dashed);
        l.block_segment(a, b, 1.0 + width / 2.0);
    }
}

fn polyline(
    c: &mut Canvas,
    l: &mut Labels,
    pts: &[(f32, f32)],
    color: Color,
    width: f32,
    dashed: bool,
) {
    for w in pts.windows(2) {
        line(c, l, w[0], w[1], color, width, dashed);
    }
}

fn later(
    pending: &mut Vec<Pending>,
    cands: &[((f32, f32), Anchor)],
    text: &str,
    size: f32,
    color: Color,
) {
    pending.push((cands.to_vec(), text.to_string(), size, color));
}

/// A dotted guide across the whole plot: an infinite surface's section or a cap plane,
/// where tossed roots land.
enum Guide {
    /// The vertical line u = x.
    Upright(f64),
    /// The horizontal line v = y.
    Across(f64),
}

fn guide(c: &mut Canvas, labels: &mut Labels, v: &View, g: Guide) {
    let b = v.bounds();
    let (a, z) = match g {
        Guide::Upright(x) => ((x, b.1), (x, b.3)),
        Guide::Across(y) => ((b.0, y), (b.2, y)),
    };
    line(
        c,
        labels,
        v.px_uv(a),
        v.px_uv(z),
        style::rgb(175, 185, 205),
        1.2,
        true,
    );
}

/// A polygon's outline as blocked segments.
fn block_polygon(l: &mut Labels, pts: &[(f32, f32)]) {
    for i in 0..pts.len() {
        if let Some((a, b)) = clip(pts[i], pts[(i + 1) % pts.len()]) {
            l.block_segment(a, b, 1.5);
        }
    }
}
/// Shape outlines and fills in view coordinates, drawn before the ray.
pub(super) fn draw_shape(
    c: &mut Canvas,
    r: &Report,
    v: &View,
    labels: &mut Labels,
    pending: &mut Vec<Pending>,
) {
    match &r.solid {
        Shape::Sphere(s) => sphere(c, r, v, labels, pending, s),
        Shape::Plane(_) => plane(c, v, labels, pending),
        Shape::Cylinder(cy) => cylinder(c, r, v, labels, pending, cy),
        Shape::Cone(k) => cone(c, r, v, labels, pending, k),
        Shape::Box(bx) => slabs(c, r, v, labels, pending, bx),
        Shape::Triangle(t) => triangle(c, r, v, labels, pending, t),
        Shape::Mesh(_) | Shape::Csg(_) | Shape::Blob(_) => {}
    }
}

/// The sphere (or circle): its outline, filled, and the centre.
fn sphere(
    c: &mut Canvas,
    r: &Report,
    v: &View,
    labels: &mut Labels,
    pending: &mut Vec<Pending>,
    s: &Sphere,
) {
    let (fill, stroke) = (style::shape_fill(), style::shape_stroke());
    let c0 = v.px(s.center);
    c.circle(
        c0,
        (s.radius * v.scale) as f32,
        Some((stroke, 2.0)),
        Some(fill),
    );
    c.circle(c0, 2.5, None, Some(stroke));
    let rp = (s.radius * v.scale) as f32;
    for i in 0..96 {
        let a = i as f32 / 96.0 * std::f32::consts::TAU;
        labels.block_point((c0.0 + rp * a.cos(), c0.1 + rp * a.sin()), 2.0);
    }
    labels.block_point(c0, 3.0);
    let name = if r.is_2d() { "C" } else { "C (centre)" };
    later(pending, &around(c0, 8.0), name, 12.0, stroke);
}

/// The plane seen edge-on (the view is set up so that it is the line v = 0): the line, the
/// back side shaded, the normal.
fn plane(c: &mut Canvas, v: &View, labels: &mut Labels, pending: &mut Vec<Pending>) {
    let stroke = style::shape_stroke();
    let b = v.bounds();
    let (l, rr) = (v.px_uv((b.0, 0.0)), v.px_uv((b.2, 0.0)));
    let low = v.px_uv((b.0, b.1)).1.min(PLOT[3]);
    c.rect(
        (PLOT[0], l.1),
        (PLOT[2] - PLOT[0], (low - l.1).max(0.0)),
        None,
        Some(style::rgba(120, 120, 130, 30)),
    );
    line(c, labels, l, rr, stroke, 2.2, false);
    let q0 = v.px_uv((0.0, 0.0));
    c.arrow(q0, (q0.0, q0.1 - 36.0), style::normal(), 1.8);
    labels.block([q0.0 - 4.0, q0.1 - 40.0, q0.0 + 4.0, q0.1]);
    later(
        pending,
        &[((q0.0 + 6.0, q0.1 - 30.0), Anchor::Left)],
        "n",
        12.0,
        style::normal(),
    );
    later(
        pending,
        &[((PLOT[2] - 6.0, l.1 + 12.0), Anchor::Right)],
        "plane (seen edge-on)",
        12.0,
        stroke,
    );
}

/// The cylinder's section by the ray's vertical plane, its silhouette and the surfaces tossed roots land on.
fn cylinder(
    c: &mut Canvas,
    r: &Report,
    v: &View,
    labels: &mut Labels,
    pending: &mut Vec<Pending>,
    cy: &Cylinder,
) {
    let (fill, stroke) = (style::shape_fill(), style::shape_stroke());
    let m = side_offset(r);
    let rr = cy.radius;
    // The infinite cylinder's section (where body roots land) and the cap planes.
    let half = (rr * rr - m * m).max(0.0).sqrt();
    for x in [-half, half] {
        if rr * rr - m * m > 0.0 {
            guide(c, labels, v, Guide::Upright(x));
        }
    }
    for y in [cy.y_min, cy.y_max] {
        if cy.capped {
            guide(c, labels, v, Guide::Across(y));
        }
    }
    // Silhouette of the finite cylinder (dashed) and the section the ray's plane cuts.
    let sil = [
        (-rr, cy.y_min),
        (rr, cy.y_min),
        (rr, cy.y_max),
        (-rr, cy.y_max),
    ];
    let sp: Vec<(f32, f32)> = sil.iter().map(|p| v.px_uv(*p)).collect();
    c.polygon(&sp, Some((style::muted(), 1.0)), None);
    block_polygon(labels, &sp);
    if half > 0.0 {
        let sec = [
            (-half, cy.y_min),
            (half, cy.y_min),
            (half, cy.y_max),
            (-half, cy.y_max),
        ];
        let pp: Vec<(f32, f32)> = sec.iter().map(|p| v.px_uv(*p)).collect();
        c.polygon(&pp, None, Some(fill));
        line(c, labels, pp[1], pp[2], stroke, 2.2, false);
        line(c, labels, pp[3], pp[0], stroke, 2.2, false);
        if cy.capped {
            line(c, labels, pp[0], pp[1], stroke, 2.2, false);
            line(c, labels, pp[2], pp[3], stroke, 2.2, false);
        }
    }
    side_labels(pending, v, cy.y_min, cy.y_max, cy.capped);
}

/// The cone's section by the ray's vertical plane (hyperbola branches), its silhouette and caps.
fn cone(
    c: &mut Canvas,
    r: &Report,
    v: &View,
    labels: &mut Labels,
    pending: &mut Vec<Pending>,
    k: &Cone,
) {
    let stroke = style::shape_stroke();
    let faint = style::rgb(175, 185, 205);
    let b = v.bounds();
    let m = side_offset(r);
    let s = k.slope;
    // x' = ±sqrt(k²y² − m²): the cone's section by the ray's vertical plane.
    let branch = |y0: f64, y1: f64, sign: f64| -> Vec<(f32, f32)> {
        (0..=200)
            .filter_map(|i| {
                let y = y0 + (y1 - y0) * i as f64 / 200.0;
                let q = s * s * y * y - m * m;
                (q >= 0.0).then(|| v.px_uv((sign * q.sqrt(), y)))
            })
            .collect()
    };
    for (y0, y1) in [(b.1, 0.0), (0.0, b.3)] {
        for sign in [-1.0, 1.0] {
            polyline(c, labels, &branch(y0, y1, sign), faint, 1.2, true);
        }
    }
    // Silhouette lines x = ±k·y within the range.
    for sign in [-1.0, 1.0] {
        let a = v.px_uv((sign * s * k.y_min, k.y_min));
        let bb = v.px_uv((sign * s * k.y_max, k.y_max));
        let z = v.px_uv((0.0, 0.0));
        if k.y_min < 0.0 && k.y_max > 0.0 {
            line(c, labels, a, z, style::muted(), 1.0, false);
            line(c, labels, z, bb, style::muted(), 1.0, false);
        } else {
            line(c, labels, a, bb, style::muted(), 1.0, false);
        }
    }
    for y in [k.y_min, k.y_max] {
        if k.capped && y != 0.0 {
            guide(c, labels, v, Guide::Across(y));
            let q = s * s * y * y - m * m;
            if q > 0.0 {
                let h = q.sqrt();
                line(
                    c,
                    labels,
                    v.px_uv((-h, y)),
                    v.px_uv((h, y)),
                    stroke,
                    2.2,
                    false,
                );
            }
        }
    }
    for sign in [-1.0, 1.0] {
        let lo = k.y_min.max(b.1);
        let hi = k.y_max.min(b.3);
        if k.y_min < 0.0 && k.y_max > 0.0 {
            polyline(c, labels, &branch(lo, 0.0, sign), stroke, 2.2, false);
            polyline(c, labels, &branch(0.0, hi, sign), stroke, 2.2, false);
        } else {
            polyline(c, labels, &branch(lo, hi, sign), stroke, 2.2, false);
        }
    }
    side_labels(pending, v, k.y_min, k.y_max, k.capped);
}

/// The box seen along one axis: the two slabs shaded and the box where they overlap.
fn slabs(
    c: &mut Canvas,
    r: &Report,
    v: &View,
    labels: &mut Labels,
    pending: &mut Vec<Pending>,
    bx: &Cuboid,
) {
    let (fill, stroke) = (style::shape_fill(), style::shape_stroke());
    let b = v.bounds();
    let (a1, a2, _) = box_axes(r);
    let names = ["x", "y", "z"];
    // Slabs: the band between each pair of face planes, and the box where they overlap.
    let band1 = [
        v.px_uv((bx.min[a1], b.1)),
        v.px_uv((bx.max[a1], b.1)),
        v.px_uv((bx.max[a1], b.3)),
        v.px_uv((bx.min[a1], b.3)),
    ];
    let band2 = [
        v.px_uv((b.0, bx.min[a2])),
        v.px_uv((b.2, bx.min[a2])),
        v.px_uv((b.2, bx.max[a2])),
        v.px_uv((b.0, bx.max[a2])),
    ];
    let clampy = |p: (f32, f32)| (p.0.clamp(PLOT[0], PLOT[2]), p.1.clamp(PLOT[1], PLOT[3]));
    c.polygon(
        &band1.map(clampy),
        None,
        Some(style::rgba(230, 150, 20, 26)),
    );
    c.polygon(
        &band2.map(clampy),
        None,
        Some(style::rgba(148, 103, 189, 26)),
    );
    for x in [bx.min[a1], bx.max[a1]] {
        guide(c, labels, v, Guide::Upright(x));
    }
    for y in [bx.min[a2], bx.max[a2]] {
        guide(c, labels, v, Guide::Across(y));
    }
    let rect = [
        v.px_uv((bx.min[a1], bx.min[a2])),
        v.px_uv((bx.max[a1], bx.min[a2])),
        v.px_uv((bx.max[a1], bx.max[a2])),
        v.px_uv((bx.min[a1], bx.max[a2])),
    ];
    c.polygon(&rect, Some((stroke, 2.2)), Some(fill));
    block_polygon(labels, &rect);
    let top = v.px_uv((bx.max[a1], b.3)).0;
    later(
        pending,
        &[((top + 4.0, PLOT[1] + 10.0), Anchor::Left)],
        &format!("{} slab", names[a1]),
        12.0,
        style::rgb(190, 110, 10),
    );
    let right = v.px_uv((b.2, bx.max[a2])).1;
    later(
        pending,
        &[((PLOT[2] - 6.0, right - 10.0), Anchor::Right)],
        &format!("{} slab", names[a2]),
        12.0,
        style::rgb(120, 80, 170),
    );
}

/// The triangle in its own plane, with the sub-triangles of the hit's weights when there is one.
fn triangle(
    c: &mut Canvas,
    r: &Report,
    v: &View,
    labels: &mut Labels,
    pending: &mut Vec<Pending>,
    t: &Triangle,
) {
    let (fill, stroke) = (style::shape_fill(), style::shape_stroke());
    let pts: Vec<(f32, f32)> = t.v.iter().map(|p| v.px(*p)).collect();
    if let (Some(bar), Some(hit_t)) = (
        r.barycentric.as_ref(),
        r.barycentric.as_ref().and_then(|b| b.t),
    ) {
        let q = v.px(r.ray3.at(hit_t));
        // The sub-triangle opposite each corner has that corner's weight as its share
        // of the area: alpha ↔ (Q, b, c), beta ↔ (Q, c, a), gamma ↔ (Q, a, b).
        let subs = [
            (
                "α",
                bar.alpha,
                [q, pts[1], pts[2]],
                style::rgba(214, 39, 40, 60),
            ),
            (
                "β",
                bar.beta,
                [q, pts[2], pts[0]],
                style::rgba(44, 160, 44, 60),
            ),
            (
                "γ",
                bar.gamma,
                [q, pts[0], pts[1]],
                style::rgba(31, 119, 180, 60),
            ),
        ];
        // A negative weight (the point is outside, across that corner's edge) is an
        // area that counts against: outlined dashed, not filled.
        for (_, w, tri, col) in &subs {
            if w.unwrap_or(0.0) >= 0.0 {
                c.polygon(tri, Some((style::rgba(60, 60, 70, 90), 0.8)), Some(*col));
            } else {
                let solid = Color::from_rgba(col.red(), col.green(), col.blue(), 1.0)
                    .unwrap_or(style::ink());
                for k in 0..3 {
                    line(c, labels, tri[k], tri[(k + 1) % 3], solid, 1.4, true);
                }
            }
        }
        c.polygon(&pts, Some((stroke, 2.2)), None);
        block_polygon(labels, &pts);
        for (_, _, tri, _) in &subs {
            block_polygon(labels, tri);
        }
        for (name, w, tri, col) in &subs {
            let cen = (
                (tri[0].0 + tri[1].0 + tri[2].0) / 3.0,
                (tri[0].1 + tri[1].1 + tri[2].1) / 3.0,
            );
            let col = Color::from_rgba(col.red() * 0.7, col.green() * 0.7, col.blue() * 0.7, 1.0)
                .unwrap_or(style::ink());
            let text = format!("{name} = {}", short(w.unwrap_or(0.0)));
            let mut cands = vec![(cen, Anchor::Center)];
            cands.extend(around(cen, 10.0));
            later(pending, &cands, &text, 13.0, col);
        }
    } else {
        c.polygon(&pts, Some((stroke, 2.2)), Some(fill));
        block_polygon(labels, &pts);
    }
    for (p, name) in pts.iter().zip(["a", "b", "c"]) {
        c.circle(*p, 3.0, None, Some(stroke));
        let cen = (
            (pts[0].0 + pts[1].0 + pts[2].0) / 3.0,
            (pts[0].1 + pts[1].1 + pts[2].1) / 3.0,
        );
        let (dx, dy) = (p.0 - cen.0, p.1 - cen.1);
        let l = dx.hypot(dy).max(1.0);
        let at = (p.0 + dx / l * 14.0, p.1 + dy / l * 14.0);
        let mut cands = vec![(at, Anchor::Center)];
        cands.extend(around(*p, 10.0));
        later(pending, &cands, name, 14.0, stroke);
    }
}

/// Labels of the side view: the range and the surfaces tossed roots land on.
fn side_labels(pending: &mut Vec<Pending>, v: &View, lo: f64, hi: f64, capped: bool) {
    let faint_ink = style::rgb(120, 130, 150);
    for (y, name) in [(hi, "y_max"), (lo, "y_min")] {
        let p = v.px_uv((v.bounds().2, y));
        let text = if capped {
            format!("{name} = {} (cap plane)", short(y))
        } else {
            format!("{name} = {}", short(y))
        };
        later(
            pending,
            &[
                ((PLOT[2] - 4.0, p.1 - 11.0), Anchor::Right),
                ((PLOT[2] - 4.0, p.1 + 11.0), Anchor::Right),
                ((PLOT[0] + 4.0, p.1 - 11.0), Anchor::Left),
                ((PLOT[0] + 4.0, p.1 + 11.0), Anchor::Left),
            ],
            &text,
            11.0,
            faint_ink,
        );
    }
}
