//! The figure of `rtlab beam`: one beam from the eye, in the plane, cut into the pieces that
//! each wall or mirror sees (blue), the pieces that meet no segment (grey), and each mirror's
//! reflected beam (green, paler at each further reflection) from the eye mirrored in it
//! (dashed: where the first reflections' rays seem to come from). The frame is what the beam
//! reaches ([`frame`]), and a piece is numbered only where its number fits inside it, clear
//! of every other mark, except the first beam's, which are always numbered.

use super::canvas::{Anchor, Canvas};
use super::labels::{around_rings, text_box, Box2, Labels, AROUND};
use super::style;
use crate::accel::beam::{name, Beam, Piece, Segment};
use crate::trace::RayKind;
use glam::DVec2;

mod place;
mod view;
use place::{behind_first, beside, label, number_jobs, Job};
pub use view::frame;
use view::View;

const W: f32 = 960.0;
const H: f32 = 620.0;
const MARGIN: f32 = 24.0;
const TOP: f32 = 84.0;
const BOTTOM: f32 = 64.0;
/// How far from the eye (pixels) the beam's edges keep labels off, so that the apex shows.
const APEX: f32 = 60.0;

/// How each depth of reflection is drawn: fills for pieces a segment sees and pieces that
/// meet none, the edges' colour and width. Deeper is paler and thinner, so that the first
/// beam, drawn last, stays on top and readable.
struct Look {
    seen: tiny_skia::Color,
    passing: tiny_skia::Color,
    edge: tiny_skia::Color,
    width: f32,
}

fn look(level: u32) -> Look {
    let g = |a: u8| style::rgba(44, 160, 44, a);
    match level {
        0 => Look {
            seen: style::rgba(31, 119, 180, 70),
            passing: style::rgba(150, 150, 158, 40),
            edge: style::ray(RayKind::Camera),
            width: 1.2,
        },
        1 => Look {
            seen: g(56),
            passing: g(24),
            edge: style::ray(RayKind::Reflection),
            width: 1.0,
        },
        2 => Look {
            seen: g(28),
            passing: g(12),
            edge: g(150),
            width: 0.7,
        },
        _ => Look {
            seen: g(16),
            passing: g(8),
            edge: g(100),
            width: 0.5,
        },
    }
}

/// One beam of the figure: the first (level 0) or one a mirror reflected (`mirror`), with
/// its pieces numbered `prefix` 1, 2, ….
struct Drawn<'a> {
    level: u32,
    prefix: String,
    beam: &'a Beam,
    pieces: &'a [Piece],
    mirror: Option<usize>,
}

/// The beam and every beam reflected from it, in the order the text lists them.
fn collect<'a>(drawn: Drawn<'a>, out: &mut Vec<Drawn<'a>>) {
    let (level, prefix, pieces) = (drawn.level, drawn.prefix.clone(), drawn.pieces);
    out.push(drawn);
    for (k, p) in pieces.iter().enumerate() {
        if let (Some((r, sub)), Some((m, _))) = (&p.reflected, p.hit) {
            let next = Drawn {
                level: level + 1,
                prefix: format!("{prefix}{}.", k + 1),
                beam: r,
                pieces: sub,
                mirror: Some(m),
            };
            collect(next, out);
        }
    }
}

/// The figure of `beam`'s `pieces` against `segments`.
pub fn figure(beam: &Beam, segments: &[Segment], pieces: &[Piece]) -> Canvas {
    let mut c = Canvas::new(W as u32, H as u32, style::background());
    let mut beams = Vec::new();
    let first = Drawn {
        level: 0,
        prefix: String::new(),
        beam,
        pieces,
        mirror: None,
    };
    collect(first, &mut beams);
    let deepest = beams.iter().map(|d| d.level).max().unwrap_or(0);
    heading(&mut c, segments, pieces, deepest);

    let view = View::new(frame(beam, segments, pieces));
    let (x0, y1) = view.at(view.min);
    let (x1, y0) = view.at(view.max);
    c.rect(
        (x0, y0),
        (x1 - x0, y1 - y0),
        Some((style::grid(), 1.0)),
        None,
    );
    let inside_frame =
        |b: &Box2| b[0] >= x0 + 1.0 && b[1] >= y0 + 1.0 && b[2] <= x1 - 1.0 && b[3] <= y1 - 1.0;
    // Labels may go anywhere between the title and the legend; piece numbers only inside
    // the frame (checked per candidate).
    let mut labels = Labels::new([4.0, TOP - 6.0, W - 4.0, H - BOTTOM + 8.0]);

    let polygons = draw_pieces(&mut c, &view, &beams, deepest);

    // The first reflections' apexes, the mirrored eyes, each with the dashed lines from it
    // to the part of the mirror its beam leaves (deeper apexes are in the printed list).
    let mut apexes: Vec<(usize, (f32, f32))> = Vec::new();
    for d in beams.iter().filter(|d| d.level == 1) {
        let (Some(first), Some(last)) = (d.pieces.first(), d.pieces.last()) else {
            continue;
        };
        for q in [first.near[0], last.near[1]] {
            if let Some((a, b)) = view.clip_line(d.beam.apex, q) {
                let (a, b) = (view.at(a), view.at(b));
                c.line(a, b, style::muted(), 1.0, true);
                labels.block_segment(a, b, 1.5);
            }
        }
        let m = d.mirror.expect("a reflected beam has its mirror");
        if !apexes.iter().any(|&(n, _)| n == m) {
            apexes.push((m, view.at(d.beam.apex)));
        }
    }

    // The segments, cut at the frame, and the eye: obstacles for every label.
    let mut names = Vec::new();
    for (i, s) in segments.iter().enumerate() {
        let Some((a, b)) = view.clip_line(s.a, s.b) else {
            continue; // wholly outside what the beam reaches
        };
        let color = if s.mirror {
            style::ray(RayKind::Reflection)
        } else {
            style::ink()
        };
        let (a, b) = (view.at(a), view.at(b));
        c.line(a, b, color, 3.5, false);
        labels.block_segment(a, b, 3.5);
        names.push((i, a, b, color));
    }
    let eye = view.at(beam.apex);
    labels.block_point(eye, 7.0);
    // The first part of the beam's edges, where they leave the eye: no label hides the apex.
    for d in [beam.from, beam.to] {
        let d = d.normalize();
        let tip = (eye.0 + APEX * d.x as f32, eye.1 - APEX * d.y as f32);
        labels.block_segment(eye, tip, 1.5);
    }
    for &(_, at) in &apexes {
        c.circle(
            at,
            4.5,
            Some((style::ink(), 1.2)),
            Some(style::background()),
        );
        labels.block_point(at, 7.0);
    }
    c.circle(eye, 4.5, None, Some(style::ink()));

    // The labels, most needed first: names, the eye, the mirrored eyes, then the pieces'
    // numbers from the first beam down.
    // A label may go outside the frame, but inside it first, and across its edge last:
    // among all the candidates, or (`group`) among each run of that many (the rings around
    // a point, so that a label does not leave its point for a place inside the frame).
    let framed_first = |candidates: Vec<((f32, f32), Anchor)>, text: &str, group: usize| {
        let mut ranked: Vec<_> = candidates.into_iter().enumerate().collect();
        ranked.sort_by_key(|&(i, (at, anchor))| {
            let b = text_box(at, text, 12.0, anchor);
            let outside = b[2] <= x0 || b[0] >= x1 || b[3] <= y0 || b[1] >= y1;
            let rank = match (inside_frame(&b), outside) {
                (true, _) => 0,
                (false, true) => 1,
                (false, false) => 2,
            };
            (i / group, rank)
        });
        ranked.into_iter().map(|(_, c)| c).collect::<Vec<_>>()
    };
    let mut jobs = Vec::new();
    for &(i, a, b, color) in &names {
        let text = name(segments, i);
        jobs.push(Job {
            candidates: framed_first(beside(a, b, eye), &text, usize::MAX),
            text,
            color,
            needed: true,
        });
    }
    jobs.push(Job {
        candidates: behind_first(eye, beam, "eye"),
        text: "eye".to_string(),
        color: style::ink(),
        needed: true,
    });
    for &(m, at) in &apexes {
        let text = format!("eye mirrored in {}", name(segments, m));
        jobs.push(Job {
            candidates: framed_first(around_rings(at, 10.0), &text, AROUND),
            text,
            color: style::muted(),
            needed: true,
        });
    }
    jobs.extend(number_jobs(
        &view,
        &beams,
        &polygons,
        deepest,
        &inside_frame,
    ));
    let total =
        beams.iter().map(|d| d.pieces.len()).sum::<usize>() + names.len() + 1 + apexes.len();
    let mut placed = 0;
    for job in &jobs {
        if let Some((at, anchor)) = labels.reserve(&job.candidates, &job.text, 12.0, job.needed) {
            label(&mut c, at, &job.text, job.color, anchor);
            placed += 1;
        }
    }

    legend(&mut c, deepest, placed == total);
    c
}

/// The title and the two lines under it; the second says what the figure shows of mirrors.
fn heading(c: &mut Canvas, segments: &[Segment], pieces: &[Piece], deepest: u32) {
    let mirror_seen = pieces
        .iter()
        .any(|p| p.hit.is_some_and(|(i, _)| segments[i].mirror));
    c.text(
        (MARGIN, 22.0),
        "Beam tracing (Heckbert and Hanrahan, 1984): one beam, clipped against the walls and mirrors nearest first",
        15.0,
        style::ink(),
        Anchor::Left,
    );
    c.text(
        (MARGIN, 44.0),
        "The beam is cut into numbered pieces: each is the part that one segment sees, or a part that goes on past them all.",
        12.0,
        style::ink(),
        Anchor::Left,
    );
    // Only what the figure shows: the mirrored eye is drawn for every first reflection.
    let reflection = if deepest > 1 {
        "A mirror's piece is reflected: a new beam whose rays seem to come from the eye mirrored in the mirror (drawn for the first reflections)."
    } else if deepest > 0 {
        "A mirror's piece is reflected: a new beam whose rays seem to come from the eye mirrored in the mirror (where the dashed lines meet)."
    } else if mirror_seen {
        "A mirror's piece would be reflected as a new beam; --depth 0 follows no reflection."
    } else if segments.iter().any(|s| s.mirror) {
        "A mirror's piece would be reflected as a new beam; no mirror sees this beam."
    } else {
        "There is no mirror here: every piece stops at a wall or goes on."
    };
    c.text(
        (MARGIN, 62.0),
        reflection,
        12.0,
        style::muted(),
        Anchor::Left,
    );
}

/// The pieces of every beam, deepest reflections first so that the first beam is drawn on
/// top; returns each beam's pieces' outlines (pixels), as `beams` lists them.
fn draw_pieces(
    c: &mut Canvas,
    view: &View,
    beams: &[Drawn],
    deepest: u32,
) -> Vec<Vec<Vec<(f32, f32)>>> {
    let mut polygons: Vec<Vec<Vec<(f32, f32)>>> = Vec::new();
    for d in beams {
        polygons.push(d.pieces.iter().map(|p| outline(view, p)).collect());
    }
    for level in (0..=deepest).rev() {
        let look = look(level);
        for (d, polys) in beams.iter().zip(&polygons) {
            if d.level != level {
                continue;
            }
            for (p, poly) in d.pieces.iter().zip(polys) {
                if poly.len() < 3 {
                    continue;
                }
                let fill = if p.hit.is_some() {
                    look.seen
                } else {
                    look.passing
                };
                c.polygon(poly, None, Some(fill));
                let [e0, e1] = ends(view, p);
                for (a, b) in [(p.near[0], e0), (p.near[1], e1)] {
                    if let Some((a, b)) = view.clip_line(a, b) {
                        c.line(view.at(a), view.at(b), look.edge, look.width, false);
                    }
                }
            }
        }
    }
    polygons
}

/// The colours' key at the foot, and whether every piece carries its number.
fn legend(c: &mut Canvas, deepest: u32, all_numbered: bool) {
    c.text(
        (MARGIN, H - 36.0),
        "Blue: a piece a segment sees (numbered as in the printed list). Grey: a piece that meets no segment.",
        12.0,
        style::ink(),
        Anchor::Left,
    );
    let mut last = String::new();
    if deepest > 0 {
        last += "Green: the beams the mirrors reflect, clipped the same way";
        last += if deepest > 1 {
            ", paler at each further reflection. "
        } else {
            ". "
        };
    }
    last += if !all_numbered {
        "Pieces without a number are in the printed list."
    } else {
        "Every ray of the beam lies in exactly one piece."
    };
    c.text((MARGIN, H - 16.0), &last, 12.0, style::ink(), Anchor::Left);
}

/// Where a piece's edge rays end: on the segment that sees it, or past the frame.
fn ends(view: &View, p: &Piece) -> [DVec2; 2] {
    match p.hit {
        Some((_, ends)) => ends,
        None => [
            p.near[0] + view.far() * p.from,
            p.near[1] + view.far() * p.to,
        ],
    }
}

/// The piece as the figure draws it, in pixels: cut at the frame (empty if outside it).
fn outline(view: &View, p: &Piece) -> Vec<(f32, f32)> {
    let [e0, e1] = ends(view, p);
    let poly = view.clip(vec![p.near[0], e0, e1, p.near[1]]);
    poly.iter().map(|&q| view.at(q)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::beam::tests::seg;
    use crate::accel::beam::trace;

    fn contains([lo, hi]: [DVec2; 2], p: DVec2) -> bool {
        p.cmpge(lo).all() && p.cmple(hi).all()
    }

    #[test]
    fn the_frame_is_what_the_beam_reaches_not_a_long_mirrors_length() {
        let beam = Beam::between(DVec2::ZERO, DVec2::new(-1.0, 1.0), DVec2::new(1.0, 1.0));
        let segs = [seg((-1e12, 2.0), (1e12, 2.0), true)];
        let pieces = trace(&beam, &segs, 1);
        let f = frame(&beam, &segs, &pieces);
        // The eye, where the beam meets the mirror (±2, 2), and the mirrored eye (0, 4),
        // with a margin; the mirror itself is cut at the frame.
        for p in [(0.0, 0.0), (-2.0, 2.0), (2.0, 2.0), (0.0, 4.0)] {
            assert!(contains(f, DVec2::new(p.0, p.1)), "{p:?} outside {f:?}");
        }
        assert!(f[0].cmpge(DVec2::splat(-3.0)).all() && f[1].cmple(DVec2::splat(5.0)).all());
        // The beam fills the figure: the eye and the mirror are far apart on it.
        let view = View::new(f);
        assert!(view.at(DVec2::ZERO).1 - view.at(DVec2::new(0.0, 2.0)).1 > 150.0);
    }

    #[test]
    fn the_frame_holds_a_room_whole_and_every_first_mirrored_eye() {
        // The book's room: every segment lies near what the beam reaches, so all are whole.
        let beam = Beam::between(DVec2::ZERO, DVec2::new(-0.6, 1.0), DVec2::new(1.3, 1.0));
        let segs = [
            seg((-0.7, 1.4), (-0.1, 1.4), false),
            seg((0.6, 1.7), (1.4, 2.3), true),
            seg((-1.0, 3.6), (2.0, 3.6), false),
            seg((3.2, 1.0), (3.2, 3.4), false),
        ];
        let pieces = trace(&beam, &segs, 1);
        let f = frame(&beam, &segs, &pieces);
        for s in &segs {
            assert!(contains(f, s.a) && contains(f, s.b), "{s:?} cut by {f:?}");
        }
        assert!(contains(f, DVec2::new(-1.2, 1.6)), "the mirrored eye");
        // A mirror on the far side of the room puts the mirrored eye outside the room.
        let eye = DVec2::new(1.0, 1.0);
        let beam = Beam::between(eye, DVec2::new(1.0, 0.2), DVec2::new(1.0, 2.0));
        let segs = [
            seg((3.0, 0.0), (3.0, 4.0), true),
            seg((0.0, -2.0), (0.0, 5.0), false),
        ];
        let pieces = trace(&beam, &segs, 1);
        assert!(contains(frame(&beam, &segs, &pieces), DVec2::new(5.0, 1.0)));
    }

    #[test]
    fn a_beam_that_meets_nothing_is_framed_as_far_as_the_nearest_segment() {
        let beam = Beam::between(DVec2::ZERO, DVec2::new(-1.0, 1.0), DVec2::new(1.0, 1.0));
        let segs = [seg((5.0, -1.0), (6.0, -1.0), false)];
        let pieces = trace(&beam, &segs, 1);
        assert!(pieces.iter().all(|p| p.hit.is_none()));
        let [lo, hi] = frame(&beam, &segs, &pieces);
        // Not a point at the eye: the beam is drawn some way out.
        assert!(hi.y > 3.0 && lo.y < 0.0, "{lo} {hi}");
    }

    #[test]
    fn the_frame_holds_where_every_reflection_meets_a_segment_with_a_margin() {
        // The first beam reaches only (1, 1); its third reflection meets the wall at x = 5.
        let beam = Beam::between(DVec2::ZERO, DVec2::new(0.5, 1.0), DVec2::new(1.0, 1.0));
        let segs = [
            seg((-5.0, 1.0), (5.0, 1.0), true),
            seg((-5.0, -1.0), (5.0, -1.0), true),
            seg((5.0, -1.0), (5.0, 1.0), false),
        ];
        let pieces = trace(&beam, &segs, 3);
        let [lo, hi] = frame(&beam, &segs, &pieces);
        let margin = 0.05 * (hi - lo).max_element();
        let inner = [lo + DVec2::splat(margin), hi - DVec2::splat(margin)];
        assert!(contains(inner, DVec2::new(5.0, -1.0)), "{lo} {hi}");
        assert!(contains(inner, DVec2::new(5.0, 1.0)), "{lo} {hi}");
    }
}
