//! Where the beam figure's labels go: the candidates for each label (a segment's name beside
//! it, the eye's behind it, a piece's number inside its own piece, away from the other
//! beams), and the pale backing each is drawn on. [`super::figure`] places them, most
//! needed first, with [`Labels`](crate::viz::labels::Labels).

use super::view::View;
use super::{ends, Drawn};
use crate::accel::beam::{Beam, Piece};
use crate::viz::canvas::{Anchor, Canvas};
use crate::viz::labels::{around_rings, text_box, Box2};
use crate::viz::style;

/// A label to place once everything is drawn: the first free candidate, or (if `needed`)
/// the first one even if it overlaps.
pub(super) struct Job {
    pub(super) candidates: Vec<((f32, f32), Anchor)>,
    pub(super) text: String,
    pub(super) color: tiny_skia::Color,
    pub(super) needed: bool,
}

/// The pieces' numbers, down to the second reflection (the third's pieces are in the printed
/// list): each piece's candidates wholly inside it, the places fewest other beams cover
/// first. `polygons[n]` are the outlines of `beams[n]`'s pieces; `inside_frame` says whether
/// a label's box lies inside the frame.
pub(super) fn number_jobs(
    view: &View,
    beams: &[Drawn],
    polygons: &[Vec<Vec<(f32, f32)>>],
    deepest: u32,
    inside_frame: &dyn Fn(&Box2) -> bool,
) -> Vec<Job> {
    let mut jobs = Vec::new();
    for level in 0..=deepest.min(2) {
        for (n, (d, polys)) in beams.iter().zip(polygons).enumerate() {
            if d.level != level {
                continue;
            }
            // How many other beams' pieces cover a place: the fewer, the less a number there
            // could be taken for theirs.
            let covered = |b: &Box2| {
                let corners = [[b[0], b[1]], [b[2], b[1]], [b[2], b[3]], [b[0], b[3]]];
                polygons
                    .iter()
                    .enumerate()
                    .filter(|&(m, _)| m != n)
                    .flat_map(|(_, polys)| polys)
                    .filter(|poly| corners.iter().any(|&[x, y]| box_in(&[x, y, x, y], poly)))
                    .count()
            };
            for (k, (p, poly)) in d.pieces.iter().zip(polys).enumerate() {
                let text = format!("{}{}", d.prefix, k + 1);
                let spots = spots(view, p);
                // Wholly inside its own piece, so that it cannot be read as a neighbour's.
                let mut candidates: Vec<_> = spots
                    .iter()
                    .filter(|&&(at, anchor)| {
                        let b = text_box(at, &text, 12.0, anchor);
                        inside_frame(&b) && box_in(&b, poly)
                    })
                    .copied()
                    .collect();
                candidates.sort_by_key(|&(at, anchor)| covered(&text_box(at, &text, 12.0, anchor)));
                // The first beam's numbers always (the nearest free place on the piece's
                // middle ray if none fits inside); a reflection's only where one fits.
                let needed = level == 0 && p.degrees >= 0.5;
                if needed {
                    candidates.extend(
                        spots.iter().filter(|&&(at, anchor)| {
                            inside_frame(&text_box(at, &text, 12.0, anchor))
                        }),
                    );
                }
                jobs.push(Job {
                    candidates,
                    text,
                    color: style::ink(),
                    needed,
                });
            }
        }
    }
    jobs
}

/// Candidate places for the eye's label: around it, those behind the eye, away from where
/// the beam goes, first.
pub(super) fn behind_first(eye: (f32, f32), beam: &Beam, text: &str) -> Vec<((f32, f32), Anchor)> {
    // The beam's middle direction, in pixels (y down); it is less than half a turn wide.
    let m = beam.from.normalize() + beam.to.normalize();
    let m = (m.x as f32, -m.y as f32);
    let ahead = |&(at, anchor): &((f32, f32), Anchor)| {
        let b = text_box(at, text, 12.0, anchor);
        let (x, y) = ((b[0] + b[2]) / 2.0 - eye.0, (b[1] + b[3]) / 2.0 - eye.1);
        (x * m.0 + y * m.1) / x.hypot(y).max(1e-3)
    };
    // Nearer rings first among places about as far behind.
    let mut out = around_rings(eye, 10.0);
    out.sort_by_key(|c| (ahead(c) * 2.0).round() as i32);
    out
}

/// Candidate places for a piece's number, in pixels: along its middle ray, then rays nearer
/// its edges, each first towards the far end of its part in the frame, where a piece that
/// widens away from its apex has most room.
fn spots(view: &View, p: &Piece) -> Vec<((f32, f32), Anchor)> {
    let [e0, e1] = ends(view, p);
    let mut out = Vec::new();
    for u in [0.5, 0.3, 0.7, 0.15, 0.85] {
        let (n, e) = (p.near[0].lerp(p.near[1], u), e0.lerp(e1, u));
        if let Some((a, b)) = view.clip_line(n, e) {
            for v in [0.7, 0.55, 0.82, 0.4, 0.9, 0.25, 0.12] {
                out.push((view.at(a.lerp(b, v)), Anchor::Center));
            }
        }
    }
    out
}

/// Whether box `b` lies inside the convex polygon `poly` (pixels).
pub(super) fn box_in(b: &Box2, poly: &[(f32, f32)]) -> bool {
    if poly.len() < 3 {
        return false;
    }
    let corners = [(b[0], b[1]), (b[2], b[1]), (b[2], b[3]), (b[0], b[3])];
    let side = |p: (f32, f32), q: (f32, f32), x: (f32, f32)| {
        (q.0 - p.0) * (x.1 - p.1) - (q.1 - p.1) * (x.0 - p.0)
    };
    let n = poly.len();
    let edges = || (0..n).map(|i| (poly[i], poly[(i + 1) % n]));
    // Either winding: every corner on the same side of every edge as the polygon's inside.
    [1.0f32, -1.0]
        .iter()
        .any(|&s| edges().all(|(p, q)| corners.iter().all(|&x| s * side(p, q, x) >= 0.0)))
}

/// Candidate places for a segment's name beside it (pixels `a` to `b`): at its middle, then
/// further along, on the side away from the eye first; then the same further out (a
/// slanted segment's name close by can touch it at a corner of its box).
pub(super) fn beside(a: (f32, f32), b: (f32, f32), eye: (f32, f32)) -> Vec<((f32, f32), Anchor)> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len = dx.hypot(dy).max(1e-3);
    let (mut nx, mut ny) = (-dy / len, dx / len);
    let mid = (a.0 + dx / 2.0, a.1 + dy / 2.0);
    if nx * (mid.0 - eye.0) + ny * (mid.1 - eye.1) < 0.0 {
        (nx, ny) = (-nx, -ny);
    }
    let mut out = Vec::new();
    for further in [0.0f32, 8.0, 16.0] {
        for side in [1.0f32, -1.0] {
            for f in [0.5f32, 0.35, 0.65, 0.2, 0.8, 0.08, 0.92] {
                let m = (a.0 + dx * f, a.1 + dy * f);
                let (ox, oy) = (nx * side, ny * side);
                let anchor = crate::viz::labels::side_anchor(ox);
                let gap = if anchor == Anchor::Center { 14.0 } else { 9.0 } + further;
                out.push(((m.0 + ox * gap, m.1 + oy * gap), anchor));
            }
        }
    }
    out
}

/// A label on a pale backing, so that the thin lines it falls on do not cross its letters.
pub(super) fn label(
    c: &mut Canvas,
    at: (f32, f32),
    text: &str,
    color: tiny_skia::Color,
    anchor: Anchor,
) {
    let b = text_box(at, text, 12.0, anchor);
    c.rect(
        (b[0], b[1]),
        (b[2] - b[0], b[3] - b[1]),
        None,
        Some(style::rgba(255, 255, 255, 210)),
    );
    c.text(at, text, 12.0, color, anchor);
}

#[cfg(test)]
mod tests {
    use super::box_in;

    #[test]
    fn a_box_lies_in_a_convex_polygon_only_when_all_its_corners_do() {
        let square = [(0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0)];
        assert!(box_in(&[1.0, 1.0, 9.0, 9.0], &square));
        assert!(!box_in(&[5.0, 5.0, 11.0, 9.0], &square));
        let mut other = square;
        other.reverse();
        assert!(box_in(&[1.0, 1.0, 9.0, 9.0], &other), "either winding");
    }
}
