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

use super::labels::{around, around_rings, Labels};
use super::style;
use super::{Anchor, Canvas};
use crate::report::intersect::Report;
use crate::shapes::working::short;
use crate::shapes::{Roots, Shape};
use glam::DVec3;
use tiny_skia::Color;

pub const WIDTH: u32 = 720;
const PLOT: [f32; 4] = [16.0, 40.0, 704.0, 350.0];

/// A 2D view: a projection of 3D points and the fitted pixel mapping.
struct View {
    origin: DVec3,
    e1: DVec3,
    e2: DVec3,
    center: (f64, f64),
    scale: f64,
}

impl View {
    fn new(origin: DVec3, e1: DVec3, e2: DVec3) -> View {
        View {
            origin,
            e1,
            e2,
            center: (0.0, 0.0),
            scale: 1.0,
        }
    }
    fn uv(&self, p: DVec3) -> (f64, f64) {
        let q = p - self.origin;
        (q.dot(self.e1), q.dot(self.e2))
    }
    fn px_uv(&self, (u, v): (f64, f64)) -> (f32, f32) {
        let cx = (PLOT[0] + PLOT[2]) as f64 / 2.0;
        let cy = (PLOT[1] + PLOT[3]) as f64 / 2.0;
        (
            (cx + (u - self.center.0) * self.scale) as f32,
            (cy - (v - self.center.1) * self.scale) as f32,
        )
    }
    fn px(&self, p: DVec3) -> (f32, f32) {
        self.px_uv(self.uv(p))
    }
    /// Fits the plot around `pts` (in view coordinates) with a margin.
    fn fit(&mut self, pts: &[(f64, f64)]) {
        let b = pts
            .iter()
            .fold((f64::MAX, f64::MAX, f64::MIN, f64::MIN), |b, p| {
                (b.0.min(p.0), b.1.min(p.1), b.2.max(p.0), b.3.max(p.1))
            });
        let ext = (b.2 - b.0).max(b.3 - b.1).max(1e-9);
        let (w, h) = ((b.2 - b.0).max(ext * 0.3), (b.3 - b.1).max(ext * 0.3));
        let (w, h) = (w * 1.2 + ext * 0.05, h * 1.2 + ext * 0.05);
        self.center = ((b.0 + b.2) / 2.0, (b.1 + b.3) / 2.0);
        let (pw, ph) = ((PLOT[2] - PLOT[0]) as f64, (PLOT[3] - PLOT[1]) as f64);
        self.scale = (pw / w).min(ph / h);
    }
    /// The view-space rectangle the plot shows.
    fn bounds(&self) -> (f64, f64, f64, f64) {
        let hw = (PLOT[2] - PLOT[0]) as f64 / 2.0 / self.scale;
        let hh = (PLOT[3] - PLOT[1]) as f64 / 2.0 / self.scale;
        (
            self.center.0 - hw,
            self.center.1 - hh,
            self.center.0 + hw,
            self.center.1 + hh,
        )
    }
}

fn perpendicular(v: DVec3) -> DVec3 {
    let seed = if v.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
    (seed - v * v.dot(seed)).normalize()
}

/// Clips a pixel segment to the plot (Liang–Barsky, shared with the slice diagram).
fn clip(a: (f32, f32), b: (f32, f32)) -> Option<((f32, f32), (f32, f32))> {
    super::slice::clip(a, b, PLOT)
}

/// A label waiting to be placed once every line and mark is down.
type Pending = (Vec<((f32, f32), Anchor)>, String, f32, Color);

/// Draws a segment clipped to the plot and keeps labels off it.
fn line(
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

/// A polygon's outline as blocked segments.
fn block_polygon(l: &mut Labels, pts: &[(f32, f32)]) {
    for i in 0..pts.len() {
        if let Some((a, b)) = clip(pts[i], pts[(i + 1) % pts.len()]) {
            l.block_segment(a, b, 1.5);
        }
    }
}

/// Shape outlines and fills in view coordinates, drawn before the ray.
fn draw_shape(
    c: &mut Canvas,
    r: &Report,
    v: &View,
    labels: &mut Labels,
    pending: &mut Vec<Pending>,
) {
    let (fill, stroke) = (style::shape_fill(), style::shape_stroke());
    let faint = style::rgb(175, 185, 205);
    let b = v.bounds();
    match &r.solid {
        Shape::Sphere(s) => {
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
        Shape::Plane(_) => {
            // Seen edge-on: the line v = 0, its back side shaded.
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
        Shape::Cylinder(cy) => {
            let m = side_offset(r);
            let rr = cy.radius;
            // The infinite cylinder's section (where body roots land) and the cap planes.
            let half = (rr * rr - m * m).max(0.0).sqrt();
            for x in [-half, half] {
                if rr * rr - m * m > 0.0 {
                    line(
                        c,
                        labels,
                        v.px_uv((x, b.1)),
                        v.px_uv((x, b.3)),
                        faint,
                        1.2,
                        true,
                    );
                }
            }
            for y in [cy.y_min, cy.y_max] {
                if cy.capped {
                    line(
                        c,
                        labels,
                        v.px_uv((b.0, y)),
                        v.px_uv((b.2, y)),
                        faint,
                        1.2,
                        true,
                    );
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
        Shape::Cone(k) => {
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
                    line(
                        c,
                        labels,
                        v.px_uv((b.0, y)),
                        v.px_uv((b.2, y)),
                        faint,
                        1.2,
                        true,
                    );
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
        Shape::Box(bx) => {
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
                line(
                    c,
                    labels,
                    v.px_uv((x, b.1)),
                    v.px_uv((x, b.3)),
                    faint,
                    1.2,
                    true,
                );
            }
            for y in [bx.min[a2], bx.max[a2]] {
                line(
                    c,
                    labels,
                    v.px_uv((b.0, y)),
                    v.px_uv((b.2, y)),
                    faint,
                    1.2,
                    true,
                );
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
        Shape::Triangle(t) => {
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
                    let col =
                        Color::from_rgba(col.red() * 0.7, col.green() * 0.7, col.blue() * 0.7, 1.0)
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
        Shape::Mesh(_) | Shape::Csg(_) | Shape::Blob(_) => {}
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

/// The side view's horizontal axis: the ray's horizontal direction (x when it is vertical).
fn side_axes(r: &Report) -> (DVec3, DVec3) {
    let d = r.ray3.dir;
    let h = DVec3::new(d.x, 0.0, d.z)
        .try_normalize()
        .unwrap_or(DVec3::X);
    let across = DVec3::new(-h.z, 0.0, h.x);
    (h, across)
}

/// How far the ray's vertical plane is from the axis.
fn side_offset(r: &Report) -> f64 {
    let (_, across) = side_axes(r);
    r.ray3.origin.dot(across)
}

/// The two axes a box figure shows (dropping the one the ray moves least along).
fn box_axes(r: &Report) -> (usize, usize, usize) {
    let d = r.ray3.dir.abs();
    let drop = if d.x <= d.y && d.x <= d.z {
        0
    } else if d.y <= d.z {
        1
    } else {
        2
    };
    match drop {
        0 => (2, 1, 0), // look along x: z right, y up
        1 => (0, 2, 1), // look along y: x right, z up
        _ => (0, 1, 2), // look along z: x right, y up
    }
}

fn view_for(r: &Report) -> (View, String) {
    let p = r.ray3.origin;
    let d = r.ray3.dir;
    match &r.solid {
        Shape::Sphere(_) if r.is_2d() => (
            View::new(DVec3::ZERO, DVec3::X, DVec3::Y),
            "circle: the ray P + t·d against (x − cx)² + (y − cy)² = r²".to_string(),
        ),
        Shape::Sphere(s) => {
            let e1 = d.normalize();
            let to_c = s.center - p;
            let e2 = (to_c - e1 * to_c.dot(e1))
                .try_normalize()
                .unwrap_or_else(|| perpendicular(e1));
            (
                View::new(p, e1, e2),
                "sphere, cut by the plane through the ray and the centre".to_string(),
            )
        }
        Shape::Plane(pl) => {
            let n = pl.normal;
            let h = (d - n * n.dot(d))
                .try_normalize()
                .unwrap_or_else(|| perpendicular(n));
            (
                View::new(pl.point, h, n),
                "plane, seen edge-on (the view contains the normal and the ray)".to_string(),
            )
        }
        Shape::Cylinder(_) | Shape::Cone(_) => {
            let (h, across) = side_axes(r);
            let what = if matches!(r.solid, Shape::Cylinder(_)) {
                "cylinder"
            } else {
                "cone"
            };
            let m = p.dot(across);
            (
                View::new(across * m, h, DVec3::Y),
                format!(
                    "{what}, side view: the vertical plane of the ray ({} from the axis)",
                    short(m.abs())
                ),
            )
        }
        Shape::Box(_) => {
            let (a1, a2, a0) = box_axes(r);
            let mut e1 = DVec3::ZERO;
            e1[a1] = 1.0;
            let mut e2 = DVec3::ZERO;
            e2[a2] = 1.0;
            let names = ["x", "y", "z"];
            (
                View::new(DVec3::ZERO, e1, e2),
                format!(
                    "box, looking along {} ({} right, {} up): a root counts where the slabs overlap",
                    names[a0], names[a1], names[a2]
                ),
            )
        }
        Shape::Triangle(t) => {
            let (e1, e2) = {
                let u = t.v[1] - t.v[0];
                let n = u.cross(t.v[2] - t.v[0]);
                match (u.try_normalize(), n.try_normalize()) {
                    (Some(e1), Some(n)) => (e1, n.cross(e1)),
                    _ => {
                        let e1 = [t.v[1] - t.v[0], t.v[2] - t.v[0], t.v[2] - t.v[1]]
                            .into_iter()
                            .max_by(|a, b| a.length().total_cmp(&b.length()))
                            .and_then(|e| e.try_normalize())
                            .unwrap_or(DVec3::X);
                        (e1, perpendicular(e1))
                    }
                }
            };
            (
                View::new(t.v[0], e1, e2),
                "triangle, in its own plane: each weight is the area opposite its corner"
                    .to_string(),
            )
        }
        Shape::Mesh(_) | Shape::Csg(_) | Shape::Blob(_) => {
            (View::new(DVec3::ZERO, DVec3::X, DVec3::Y), "mesh".into())
        }
    }
}

/// The figure of an `intersect` report.
pub fn figure(r: &Report) -> Canvas {
    let mut c = Canvas::new(WIDTH, height(r), style::background());
    let (mut v, title) = view_for(r);

    // Fit: the shape's extent, the origin, every candidate.
    let mut pts: Vec<(f64, f64)> = vec![v.uv(r.ray3.origin)];
    for cand in &r.candidates {
        let p = r.ray3.at(cand.t);
        pts.push(v.uv(p));
    }
    if let Some(h) = &r.hit {
        pts.push(v.uv(r.ray3.at(h.t)));
    }
    match &r.solid {
        Shape::Sphere(s) => {
            let c0 = v.uv(s.center);
            pts.push((c0.0 - s.radius, c0.1 - s.radius));
            pts.push((c0.0 + s.radius, c0.1 + s.radius));
        }
        Shape::Plane(_) => pts.push((0.0, 0.0)),
        Shape::Cylinder(cy) => {
            pts.push((-cy.radius, cy.y_min));
            pts.push((cy.radius, cy.y_max));
        }
        Shape::Cone(k) => {
            let w = k.slope * k.y_min.abs().max(k.y_max.abs());
            pts.push((-w, k.y_min));
            pts.push((w, k.y_max));
        }
        Shape::Box(b) => {
            pts.push(v.uv(b.min));
            pts.push(v.uv(b.max));
        }
        Shape::Triangle(t) => pts.extend(t.v.iter().map(|p| v.uv(*p))),
        Shape::Mesh(_) | Shape::Csg(_) | Shape::Blob(_) => {}
    }
    v.fit(&pts);

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

/// The figure's height: the plot and as many panel lines as the report needs.
pub fn height(r: &Report) -> u32 {
    let lines = 1
        + 2 * r.quadratic.is_some() as usize
        + r.barycentric.is_some() as usize
        + r.linear.is_some() as usize
        + r.candidates.len().max(1)
        + r.hit.is_none() as usize;
    (PLOT[3] + 12.0 + 18.0 * lines as f32 + 10.0).ceil() as u32
}

/// The text under the drawing: equation, discriminant, verdict, candidates.
fn panel(c: &mut Canvas, r: &Report) {
    let mut y = PLOT[3] + 18.0;
    let x = 24.0;
    let mut say = |c: &mut Canvas, text: &str, color: Color, size: f32| {
        c.text((x, y), text, size, color, Anchor::Left);
        y += size + 5.0;
    };
    c.line(
        (16.0, PLOT[3] + 4.0),
        (WIDTH as f32 - 16.0, PLOT[3] + 4.0),
        style::grid(),
        1.0,
        false,
    );
    let ray = format!(
        "P = ({}),  d = ({})",
        r.ray
            .origin
            .iter()
            .map(|x| short(*x))
            .collect::<Vec<_>>()
            .join(", "),
        r.ray
            .direction
            .iter()
            .map(|x| short(*x))
            .collect::<Vec<_>>()
            .join(", ")
    );
    say(c, &ray, style::ink(), 13.0);
    if let Some(q) = &r.quadratic {
        let sgn = |x: f64| {
            if x < 0.0 {
                format!("− {}", short(-x))
            } else {
                format!("+ {}", short(x))
            }
        };
        let surface = match r.shape {
            "cylinder" | "cone" => "body: ",
            _ => "",
        };
        say(
            c,
            &format!(
                "{surface}{}·t² {}·t {} = 0      (a = {}, b = {}, c = {})",
                short(q.a),
                sgn(q.b),
                sgn(q.c),
                short(q.a),
                short(q.b),
                short(q.c)
            ),
            style::ink(),
            13.0,
        );
        let verdict = match q.roots {
            Roots::Two => "D > 0: two roots".to_string(),
            Roots::Tangent if q.rounded_to_zero => format!(
                "D = 0 → tangent (floating point gave {:.1e}: within rounding of 0, so taken as 0)",
                q.discriminant
            ),
            Roots::Tangent => "D = 0: tangent, one root".to_string(),
            Roots::One => "a = 0: linear, one root".to_string(),
            Roots::None => "D < 0: no real root, a miss".to_string(),
        };
        let dtext = if q.rounded_to_zero {
            verdict
        } else {
            format!("D = b² − 4ac = {}  →  {verdict}", short(q.discriminant))
        };
        say(c, &dtext, style::ink(), 13.0);
    }
    if let Some(l) = &r.linear {
        let text = if l.denominator == 0.0 {
            "n·d = 0: the ray is parallel to the plane, no root".to_string()
        } else {
            format!(
                "t = n·(Q0 − P) / (n·d) = {} / {} = {}",
                short(l.numerator),
                short(l.denominator),
                short(l.numerator / l.denominator)
            )
        };
        say(c, &text, style::ink(), 13.0);
    }
    if let Some(b) = &r.barycentric {
        let text = match (b.alpha, b.beta, b.gamma, b.t) {
            (Some(a), Some(be), Some(g), Some(t)) => format!(
                "Cramer: det = {},  β = {},  γ = {},  t = {},  α = 1 − β − γ = {}",
                short(b.determinant),
                short(be),
                short(g),
                short(t),
                short(a)
            ),
            _ => "Cramer: det[e1 e2 −d] = 0: the ray is parallel to the plane, or the triangle is degenerate".into(),
        };
        say(c, &text, style::ink(), 13.0);
    }
    if r.candidates.is_empty() {
        say(c, "no candidate root: the ray misses", style::muted(), 12.0);
    }
    for (i, cand) in r.candidates.iter().enumerate() {
        let kept = cand.note.starts_with("kept");
        let name = if r.candidates.len() == 1 {
            "t".to_string()
        } else {
            format!("t{}", i + 1)
        };
        let text = format!(
            "{name} = {} on {}: {}",
            short(cand.t),
            cand.surface,
            cand.note
        );
        let color = if kept {
            style::hit()
        } else {
            style::rgb(120, 120, 128)
        };
        let text = fit_text(&text, 12.0, WIDTH as f32 - 48.0);
        say(c, &text, color, 12.0);
    }
    if r.hit.is_none() {
        say(c, "no hit", style::ink(), 12.0);
    }
}

/// Shortens `text` with an ellipsis so it fits in `width` pixels.
fn fit_text(text: &str, size: f32, width: f32) -> String {
    if Canvas::text_width(text, size) <= width {
        return text.to_string();
    }
    let mut s: Vec<char> = text.chars().collect();
    while !s.is_empty() && Canvas::text_width(&(s.iter().collect::<String>() + "…"), size) > width
    {
        s.pop();
    }
    s.into_iter().collect::<String>() + "…"
}
