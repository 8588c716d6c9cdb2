//! The figure of `rtlab beam`: one beam from the eye, in the plane, cut into the pieces that
//! each wall or mirror sees (blue), the pieces that pass everything (grey), and each mirror's
//! reflected beam (green) from the eye mirrored in it (dashed: where its rays seem to come
//! from).

use super::canvas::{Anchor, Canvas};
use super::style;
use crate::accel::beam::{name, Beam, Piece, Segment};
use crate::trace::RayKind;
use glam::DVec2;

const W: f32 = 960.0;
const H: f32 = 620.0;
const MARGIN: f32 = 24.0;
const TOP: f32 = 84.0;
const BOTTOM: f32 = 64.0;

/// Where the plane's points land on the canvas: a uniform scale, y up.
struct View {
    min: DVec2,
    max: DVec2,
    scale: f64,
    origin: (f32, f32),
}

impl View {
    fn new(points: &[DVec2]) -> View {
        let (mut min, mut max) = (points[0], points[0]);
        for &p in points {
            min = min.min(p);
            max = max.max(p);
        }
        let pad = ((max - min).max_element() * 0.08).max(1e-6);
        let (min, max) = (min - DVec2::splat(pad), max + DVec2::splat(pad));
        let (aw, ah) = ((W - 2.0 * MARGIN) as f64, (H - TOP - BOTTOM) as f64);
        let scale = (aw / (max.x - min.x)).min(ah / (max.y - min.y));
        // Centred in the area.
        let used = ((max.x - min.x) * scale, (max.y - min.y) * scale);
        let origin = (
            MARGIN + ((aw - used.0) / 2.0) as f32,
            TOP + ((ah - used.1) / 2.0) as f32 + used.1 as f32,
        );
        View {
            min,
            max,
            scale,
            origin,
        }
    }

    fn at(&self, p: DVec2) -> (f32, f32) {
        (
            self.origin.0 + ((p.x - self.min.x) * self.scale) as f32,
            self.origin.1 - ((p.y - self.min.y) * self.scale) as f32,
        )
    }

    /// How far a ray that meets nothing is drawn: past every corner of the view.
    fn far(&self) -> f64 {
        (self.max - self.min).length() * 2.0
    }

    /// The part of the segment from `a` to `b` inside the view (Liang–Barsky).
    fn clip_line(&self, a: DVec2, b: DVec2) -> Option<(DVec2, DVec2)> {
        let d = b - a;
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        for axis in 0..2 {
            for (edge, low) in [(self.min[axis], true), (self.max[axis], false)] {
                // Inside: a + t·d on the view's side of this edge.
                let (p, q) = if low {
                    (-d[axis], a[axis] - edge)
                } else {
                    (d[axis], edge - a[axis])
                };
                if p == 0.0 {
                    if q < 0.0 {
                        return None;
                    }
                } else if p < 0.0 {
                    t0 = t0.max(q / p);
                } else {
                    t1 = t1.min(q / p);
                }
            }
        }
        (t0 < t1).then(|| (a + t0 * d, a + t1 * d))
    }

    /// `poly` clipped to the view's rectangle (Sutherland–Hodgman, one edge at a time).
    fn clip(&self, poly: Vec<DVec2>) -> Vec<DVec2> {
        let edges: [(usize, f64, bool); 4] = [
            (0, self.min.x, true),
            (0, self.max.x, false),
            (1, self.min.y, true),
            (1, self.max.y, false),
        ];
        let mut out = poly;
        for (axis, v, low) in edges {
            let inside = |p: DVec2| if low { p[axis] >= v } else { p[axis] <= v };
            let input = std::mem::take(&mut out);
            for (i, &p) in input.iter().enumerate() {
                let q = input[(i + 1) % input.len()];
                if inside(p) {
                    out.push(p);
                }
                if inside(p) != inside(q) {
                    let t = (v - p[axis]) / (q[axis] - p[axis]);
                    out.push(p + t * (q - p));
                }
            }
            if out.is_empty() {
                break;
            }
        }
        out
    }
}

/// Every point the figure must show: the eyes (the real one and the mirrored ones) and the
/// segments.
fn points(beam: &Beam, segments: &[Segment], pieces: &[Piece], out: &mut Vec<DVec2>) {
    out.push(beam.apex);
    for s in segments {
        out.extend([s.a, s.b]);
    }
    for p in pieces {
        if let Some((r, sub)) = &p.reflected {
            points(r, segments, sub, out);
        }
    }
}

/// The figure of `beam`'s `pieces` against `segments`.
pub fn figure(beam: &Beam, segments: &[Segment], pieces: &[Piece]) -> Canvas {
    let mut c = Canvas::new(W as u32, H as u32, style::background());
    c.text(
        (MARGIN, 22.0),
        "Beam tracing (Heckbert and Hanrahan, 1984): one beam, clipped against the walls and mirrors nearest first",
        15.0,
        style::ink(),
        Anchor::Left,
    );
    c.text(
        (MARGIN, 44.0),
        "Each numbered piece is the part of the beam that one segment sees; the rest of the beam goes on past it.",
        12.0,
        style::ink(),
        Anchor::Left,
    );
    c.text(
        (MARGIN, 62.0),
        "A mirror's piece is reflected: a new beam whose rays seem to come from the eye mirrored in the mirror (dashed).",
        12.0,
        style::muted(),
        Anchor::Left,
    );
    let mut all = Vec::new();
    points(beam, segments, pieces, &mut all);
    let view = View::new(&all);
    let (x0, y1) = view.at(view.min);
    let (x1, y0) = view.at(view.max);
    c.rect(
        (x0, y0),
        (x1 - x0, y1 - y0),
        Some((style::grid(), 1.0)),
        None,
    );
    let eye = Lineage {
        prefix: String::new(),
        level: 0,
        mirrored: String::new(),
    };
    draw_pieces(&mut c, &view, (beam, pieces), segments, &eye);
    for (i, s) in segments.iter().enumerate() {
        let color = if s.mirror {
            style::ray(RayKind::Reflection)
        } else {
            style::ink()
        };
        c.line(view.at(s.a), view.at(s.b), color, 3.5, false);
        // The name beside the segment's middle, on the side away from the eye.
        let mid = (s.a + s.b) / 2.0;
        let mut n = (s.b - s.a).perp().normalize();
        if n.dot(mid - beam.apex) < 0.0 {
            n = -n;
        }
        let (mx, my) = view.at(mid);
        let at = (mx + 16.0 * n.x as f32, my - 16.0 * n.y as f32);
        let anchor = match n.x {
            x if x > 0.4 => Anchor::Left,
            x if x < -0.4 => Anchor::Right,
            _ => Anchor::Center,
        };
        label(&mut c, at, &name(segments, i), color, anchor);
    }
    let eye = view.at(beam.apex);
    c.circle(eye, 4.5, None, Some(style::ink()));
    c.text(
        (eye.0, eye.1 + 16.0),
        "eye",
        12.0,
        style::ink(),
        Anchor::Center,
    );
    c.text(
        (MARGIN, H - 36.0),
        "Blue: a piece some segment sees (the number is the piece's in the printed list). Grey: a piece that passes everything.",
        12.0,
        style::ink(),
        Anchor::Left,
    );
    c.text(
        (MARGIN, H - 16.0),
        "Green: the beams the mirrors reflect, clipped the same way. Every ray of the beam lies in exactly one piece.",
        12.0,
        style::ink(),
        Anchor::Left,
    );
    c
}

/// A label on a pale backing, so that the thin lines it falls on do not cross its letters.
fn label(c: &mut Canvas, at: (f32, f32), text: &str, color: tiny_skia::Color, anchor: Anchor) {
    let w = Canvas::text_width(text, 12.0);
    let x = match anchor {
        Anchor::Left => at.0,
        Anchor::Center => at.0 - w / 2.0,
        Anchor::Right => at.0 - w,
    };
    c.rect(
        (x - 2.0, at.1 - 8.0),
        (w + 4.0, 16.0),
        None,
        Some(style::rgba(255, 255, 255, 210)),
    );
    c.text(at, text, 12.0, color, anchor);
}

/// Where a beam stands among the reflections: its pieces' numbers begin with `prefix`,
/// `level` reflections made it, and `mirrored` says from which mirrored eye ("" for the eye).
struct Lineage {
    prefix: String,
    level: u32,
    mirrored: String,
}

/// Draws `pieces` of `beam` (numbered `prefix` 1, 2, …), then each reflected beam's.
fn draw_pieces(
    c: &mut Canvas,
    view: &View,
    (beam, pieces): (&Beam, &[Piece]),
    segments: &[Segment],
    lineage: &Lineage,
) {
    let Lineage {
        prefix,
        level,
        mirrored,
    } = lineage;
    let level = *level;
    let (seen, passing, edge) = match level {
        0 => (
            style::rgba(31, 119, 180, 60),
            style::rgba(150, 150, 158, 36),
            style::ray(RayKind::Camera),
        ),
        _ => (
            style::rgba(44, 160, 44, 60),
            style::rgba(44, 160, 44, 22),
            style::ray(RayKind::Reflection),
        ),
    };
    if level > 0 {
        // Where the reflected rays seem to come from: the mirrored eye, dashed to the mirror.
        let apex = view.at(beam.apex);
        if let (Some(first), Some(last)) = (pieces.first(), pieces.last()) {
            for q in [first.near[0], last.near[1]] {
                c.line(apex, view.at(q), style::muted(), 1.0, true);
            }
        }
        c.circle(
            apex,
            4.5,
            Some((style::ink(), 1.2)),
            Some(style::background()),
        );
        label(
            c,
            (apex.0 - 9.0, apex.1),
            mirrored.as_str(),
            style::muted(),
            Anchor::Right,
        );
    }
    for (k, p) in pieces.iter().enumerate() {
        let ends = match p.hit {
            Some((_, ends)) => ends,
            None => [
                p.near[0] + view.far() * p.from,
                p.near[1] + view.far() * p.to,
            ],
        };
        let poly = view.clip(vec![p.near[0], ends[0], ends[1], p.near[1]]);
        if poly.len() < 3 {
            continue;
        }
        let pts: Vec<(f32, f32)> = poly.iter().map(|&q| view.at(q)).collect();
        let fill = if p.hit.is_some() { seen } else { passing };
        c.polygon(&pts, None, Some(fill));
        for (a, b) in [(p.near[0], ends[0]), (p.near[1], ends[1])] {
            if let Some((a, b)) = view.clip_line(a, b) {
                c.line(view.at(a), view.at(b), edge, 1.0, false);
            }
        }
        // The piece's number on its middle ray, towards its far end, where it is widest.
        let (near, far) = ((p.near[0] + p.near[1]) / 2.0, (ends[0] + ends[1]) / 2.0);
        let Some((a, b)) = view.clip_line(near, far) else {
            continue;
        };
        // Not where the mirror's own name or the reflected beam's numbers go.
        let along = match p.hit {
            _ if level > 0 => 0.5,
            Some((i, _)) if segments[i].mirror => 0.55,
            Some(_) => 0.8,
            None => 0.6,
        };
        label(
            c,
            view.at(a + along * (b - a)),
            &format!("{prefix}{}", k + 1),
            style::ink(),
            Anchor::Center,
        );
    }
    for (k, p) in pieces.iter().enumerate() {
        if let (Some((r, sub)), Some((m, _))) = (&p.reflected, p.hit) {
            let chain = match mirrored.as_str() {
                "" => format!("eye mirrored in {}", name(segments, m)),
                before => format!("{before}, then in {}", name(segments, m)),
            };
            let next = Lineage {
                prefix: format!("{prefix}{}.", k + 1),
                level: level + 1,
                mirrored: chain,
            };
            draw_pieces(c, view, (r, sub), segments, &next);
        }
    }
}
