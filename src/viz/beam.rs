//! The figure of `rtlab beam`: one beam from the eye, in the plane, cut into the pieces that
//! each wall or mirror sees (blue), the pieces that pass everything (grey), and each mirror's
//! reflected beam (green) from the eye mirrored in it (dashed: where its rays seem to come
//! from).

use super::canvas::{Anchor, Canvas};
use super::labels::{text_box, Labels};
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
        // Relative: a room of any size fills the figure (segments have a length, so the
        // extent is never zero).
        let pad = (max - min).max_element() * 0.08;
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
    // The room: the eye and the segments. A mirrored eye may lie far outside it (two facing
    // mirrors put them ever further away); its dashed lines are drawn up to the frame.
    let mut room = vec![beam.apex];
    for s in segments {
        room.extend([s.a, s.b]);
    }
    let view = View::new(&room);
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
        eye: beam.apex,
    };
    // Where each segment's name goes, and the eye's: kept clear of the pieces' numbers.
    let names: Vec<((f32, f32), Anchor)> = segments
        .iter()
        .map(|s| {
            // Beside the segment's middle, on the side away from the eye.
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
            (at, anchor)
        })
        .collect();
    let eye_at = view.at(beam.apex);
    let mut labels = Labels::new([0.0, 0.0, W, H]);
    for (i, &(at, anchor)) in names.iter().enumerate() {
        labels.block(text_box(at, &name(segments, i), 12.0, anchor));
    }
    labels.block(text_box(
        (eye_at.0, eye_at.1 + 16.0),
        "eye",
        12.0,
        Anchor::Center,
    ));
    let mut jobs = Vec::new();
    draw_pieces(&mut c, &view, (beam, pieces), segments, &eye, &mut jobs);
    place(&mut c, &jobs, &mut labels);
    for (i, s) in segments.iter().enumerate() {
        let color = if s.mirror {
            style::ray(RayKind::Reflection)
        } else {
            style::ink()
        };
        c.line(view.at(s.a), view.at(s.b), color, 3.5, false);
        let (at, anchor) = names[i];
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

/// A label to place once every beam is drawn: the first free candidate, or (if `needed`)
/// the first one even if it overlaps.
struct Job {
    candidates: Vec<((f32, f32), Anchor)>,
    text: String,
    color: tiny_skia::Color,
    needed: bool,
}

/// Places `jobs` in order, each clear of the boxes `labels` holds and of the ones placed
/// before it.
fn place(c: &mut Canvas, jobs: &[Job], labels: &mut Labels) {
    for job in jobs {
        if let Some((at, anchor)) = labels.reserve(&job.candidates, &job.text, 12.0, job.needed) {
            label(c, at, &job.text, job.color, anchor);
        }
    }
}

/// A label on a pale backing, so that the thin lines it falls on do not cross its letters.
fn label(c: &mut Canvas, at: (f32, f32), text: &str, color: tiny_skia::Color, anchor: Anchor) {
    let b = text_box(at, text, 12.0, anchor);
    c.rect(
        (b[0], b[1]),
        (b[2] - b[0], b[3] - b[1]),
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
    /// The real eye, where every lineage starts.
    eye: DVec2,
}

/// Draws `pieces` of `beam` (numbered `prefix` 1, 2, …), then each reflected beam's.
fn draw_pieces(
    c: &mut Canvas,
    view: &View,
    (beam, pieces): (&Beam, &[Piece]),
    segments: &[Segment],
    lineage: &Lineage,
    jobs: &mut Vec<Job>,
) {
    let Lineage {
        prefix,
        level,
        mirrored,
        ..
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
        if let (Some(first), Some(last)) = (pieces.first(), pieces.last()) {
            for q in [first.near[0], last.near[1]] {
                if let Some((a, b)) = view.clip_line(beam.apex, q) {
                    c.line(view.at(a), view.at(b), style::muted(), 1.0, true);
                }
            }
        }
        // The mirrored eye itself, when it is in the frame; named only for the first
        // reflection (deeper chains are in the printed list), and not over the eye's name.
        let (lo, hi) = (view.min, view.max);
        let p = beam.apex;
        if p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y {
            let apex = view.at(p);
            c.circle(
                apex,
                4.5,
                Some((style::ink(), 1.2)),
                Some(style::background()),
            );
            let eye = view.at(lineage.eye);
            if level == 1 && (apex.0 - eye.0).hypot(apex.1 - eye.1) > 24.0 {
                jobs.push(Job {
                    candidates: vec![
                        ((apex.0 - 9.0, apex.1), Anchor::Right),
                        ((apex.0 + 9.0, apex.1), Anchor::Left),
                        ((apex.0, apex.1 + 16.0), Anchor::Center),
                    ],
                    text: mirrored.clone(),
                    color: style::muted(),
                    needed: true,
                });
            }
        }
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
        if p.degrees < 0.5 {
            continue; // too narrow to hold its number
        }
        // Not where the mirror's own name or the reflected beam's numbers go; then nearer
        // and further along the same ray if that place is taken.
        let along: f64 = match p.hit {
            _ if level > 0 => 0.5,
            Some((i, _)) if segments[i].mirror => 0.55,
            Some(_) => 0.8,
            None => 0.6,
        };
        let candidates = [0.0, -0.12, 0.12, -0.25, 0.25, -0.35]
            .iter()
            .map(|d| (along + d).clamp(0.1, 0.95))
            .map(|f| (view.at(a + f * (b - a)), Anchor::Center))
            .collect();
        jobs.push(Job {
            candidates,
            text: format!("{prefix}{}", k + 1),
            color: style::ink(),
            // The first beam's numbers always; a deeper one's only where there is room
            // (every piece is in the printed list).
            needed: level == 0,
        });
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
                eye: lineage.eye,
            };
            draw_pieces(c, view, (r, sub), segments, &next, jobs);
        }
    }
}
