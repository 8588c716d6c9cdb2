//! Heckbert and Hanrahan's beam tracing (SIGGRAPH 1984), in the plane, for teaching: one
//! beam from the eye, clipped against walls and mirrors nearest first. Each *piece* of the
//! beam is the part that one segment sees (or that passes everything), and a mirror's piece
//! spawns a reflected beam whose apex is the eye mirrored in the mirror.
//!
//! The renderer does not use this: it traces rays, in bundles (`accel::bundle`), which keep
//! an exact answer per ray on every kind of surface. This module exists for `rtlab beam` and
//! its figure, to show the idea the bundles descend from.
//!
//! Exact in the plane: between two consecutive directions towards a segment's end, the
//! nearest segment along every ray of the beam is the same one (segments do not cross), so
//! one ray through the middle of each such sector decides it.

use crate::shapes::working::tiny;
use glam::DVec2;

/// A wall (absorbs the beam) or a mirror (reflects it), from `a` to `b`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    pub a: DVec2,
    pub b: DVec2,
    pub mirror: bool,
}

/// A beam: the rays from `apex` between the directions `from` and `to` (counterclockwise,
/// less than half a turn). A reflected beam starts on the mirror it left (`leaves`): its
/// rays begin where they cross that mirror's line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Beam {
    pub apex: DVec2,
    pub from: DVec2,
    pub to: DVec2,
    pub leaves: Option<usize>,
}

impl Beam {
    /// The beam from `apex` between directions `a` and `b`, the narrower way round (its edges
    /// put in counterclockwise order).
    pub fn between(apex: DVec2, a: DVec2, b: DVec2) -> Beam {
        let (from, to) = if angle(a, b) >= 0.0 { (a, b) } else { (b, a) };
        Beam {
            apex,
            from,
            to,
            leaves: None,
        }
    }
}

/// The part of a beam that one segment sees, or that passes everything (`hit` is `None`).
#[derive(Debug, Clone, PartialEq)]
pub struct Piece {
    /// Its two edge directions (unit), counterclockwise.
    pub from: DVec2,
    pub to: DVec2,
    /// Its angular width, in degrees.
    pub degrees: f64,
    /// Where its two edge rays start: the apex, or on the mirror a reflected beam leaves.
    pub near: [DVec2; 2],
    /// The segment that sees it and where its edge rays meet that segment.
    pub hit: Option<(usize, [DVec2; 2])>,
    /// The beam a mirror's piece reflects, clipped in turn (while depth remains).
    pub reflected: Option<(Beam, Vec<Piece>)>,
}

/// A segment's name, as `rtlab beam` prints it and its figure labels it: walls and mirrors
/// numbered apart, in the order given ("wall 2", "mirror 1").
pub fn name(segments: &[Segment], i: usize) -> String {
    let n = segments[..=i]
        .iter()
        .filter(|s| s.mirror == segments[i].mirror)
        .count();
    let kind = if segments[i].mirror { "mirror" } else { "wall" };
    format!("{kind} {n}")
}

/// Why a beam cannot be traced (the face says which argument).
#[derive(Debug, Clone, PartialEq)]
pub enum Problem {
    /// The beam is no wider than 1e-7°, or not narrower than [`WIDEST`] (its width in
    /// degrees).
    Width(f64),
    /// Segment `i` has no length, or is too short to tell from a point where it lies
    /// ([`min_length`]).
    Empty(usize),
    /// The apex lies on segment `i`.
    OnSegment(usize),
    /// Segments `i` and `j` cross, or overlap along a common line.
    Cross(usize, usize),
}

impl Problem {
    /// The message, naming segments as the user knows them ([`name`]).
    pub fn message(&self, segments: &[Segment]) -> String {
        match *self {
            // Rounding keeps order, so a width refused reads as breaking the rule as well.
            Problem::Width(d) if d > 90.0 => {
                // Seven decimals show the limit; as many more as it takes for a width under
                // 180° to read under 180°, and one past the limit to read past it.
                let k = (7..=15)
                    .find(|&k| {
                        let v = fixed(d, k).parse::<f64>().unwrap_or(d);
                        (d >= 180.0 || v < 180.0) && (d == WIDEST || v != WIDEST)
                    })
                    .unwrap_or(15);
                format!(
                    "the two directions are {}° apart: a beam must be less than {}° wide \
                     (180° less {}°, so that its two edges are not one line)",
                    fixed(d, k),
                    fixed(WIDEST, 7),
                    tiny(SLACK)
                )
            }
            Problem::Width(d) => format!(
                "the two directions are {}° apart: a beam must be more than {}° wide \
                 (so that its two edges are two directions)",
                tiny(d),
                tiny(SLACK)
            ),
            Problem::Empty(i) => {
                let s = &segments[i];
                let len = (s.b - s.a).length();
                if len == 0.0 {
                    format!("{} has no length: its two ends are the same point", name(segments, i))
                } else {
                    format!(
                        "{} is {} long: a segment must be longer than {} (10⁻¹² of its far end's distance from the origin)",
                        name(segments, i),
                        tiny(len),
                        tiny(min_length(s))
                    )
                }
            }
            Problem::OnSegment(i) => format!("the eye lies on {}", name(segments, i)),
            Problem::Cross(i, j) => format!(
                "{} and {} cross or overlap: a beam is clipped against segments that meet at most at their ends",
                name(segments, i),
                name(segments, j)
            ),
        }
    }
}

/// The angle of `v` from `from`, counterclockwise, in (−π, π].
fn angle(from: DVec2, v: DVec2) -> f64 {
    from.perp_dot(v).atan2(from.dot(v))
}

/// `from` turned counterclockwise by `a` radians, unit length.
fn turn(from: DVec2, a: f64) -> DVec2 {
    DVec2::from_angle(a).rotate(from.normalize())
}

/// Where the ray `p + t·d` meets the line through `s`, as t (`None` if parallel).
fn line_t(p: DVec2, d: DVec2, s: &Segment) -> Option<f64> {
    let e = s.b - s.a;
    let den = d.perp_dot(e);
    (den != 0.0).then(|| (s.a - p).perp_dot(e) / den)
}

/// Where the ray `p + t·d`, from `t_min` on, meets segment `s`, as t.
fn segment_t(p: DVec2, d: DVec2, s: &Segment, t_min: f64) -> Option<f64> {
    let e = s.b - s.a;
    let den = d.perp_dot(e);
    if den == 0.0 {
        return None;
    }
    let t = (s.a - p).perp_dot(e) / den;
    let u = (s.a - p).perp_dot(d) / den;
    (t > t_min && (0.0..=1.0).contains(&u)).then_some(t)
}

/// The length a segment must exceed: relative to where it lies (10⁻¹² of its far end's
/// distance from the origin), so a segment of 1e-13 near the origin is a segment, but one of
/// 1e-13 at x = 2 cannot be told from a point.
pub fn min_length(s: &Segment) -> f64 {
    1e-12 * s.a.length().max(s.b.length())
}

/// Checks the segments and the eye before any beam is traced.
pub fn check(eye: DVec2, segments: &[Segment]) -> Result<(), Problem> {
    for (i, s) in segments.iter().enumerate() {
        let e = s.b - s.a;
        if e.length() <= min_length(s) {
            return Err(Problem::Empty(i));
        }
        let u = (eye - s.a).dot(e) / e.length_squared();
        if (0.0..=1.0).contains(&u) && (s.a + u * e - eye).length() <= 1e-14 * e.length() {
            return Err(Problem::OnSegment(i));
        }
    }
    for i in 0..segments.len() {
        for j in i + 1..segments.len() {
            if cross(&segments[i], &segments[j]) {
                return Err(Problem::Cross(i, j));
            }
        }
    }
    Ok(())
}

/// Whether two segments cross at a point inside both, or overlap along a common line
/// (meeting at an end is allowed).
fn cross(p: &Segment, q: &Segment) -> bool {
    let side = |s: &Segment, x: DVec2| (s.b - s.a).perp_dot(x - s.a);
    let (a, b) = (side(p, q.a), side(p, q.b));
    let (c, d) = (side(q, p.a), side(q, p.b));
    if a == 0.0 && b == 0.0 {
        // On one line: they overlap when their spans along it share more than a point.
        let e = p.b - p.a;
        let along = |x: DVec2| (x - p.a).dot(e) / e.length_squared();
        let (u, v) = (along(q.a), along(q.b));
        return u.max(v).min(1.0) > u.min(v).max(0.0);
    }
    a * b < 0.0 && c * d < 0.0
}

/// How much wider than nothing and narrower than half a turn a beam must be, in degrees: its
/// two edges are two directions, and not one line.
const SLACK: f64 = 1e-7;

/// The widest a beam may be, in degrees: 179.9999999 (1e-7° short of half a turn).
pub const WIDEST: f64 = 180.0 - SLACK;

/// `x` with `k` decimals, trailing zeros dropped.
fn fixed(x: f64, k: usize) -> String {
    let s = format!("{x:.k$}");
    match s.contains('.') {
        true => s.trim_end_matches('0').trim_end_matches('.').to_string(),
        false => s,
    }
}

/// The width of `beam` in degrees, or the problem with it: more than 1e-7°, and less than
/// [`WIDEST`].
pub fn width(beam: &Beam) -> Result<f64, Problem> {
    let degrees = angle(beam.from, beam.to).abs().to_degrees();
    if !(degrees > SLACK && degrees < WIDEST) {
        return Err(Problem::Width(degrees));
    }
    Ok(degrees)
}

/// Clips `beam` against `segments`, nearest first, and each mirror's piece's reflection in
/// turn while `depth` reflections remain. Call [`check`] and [`width`] first.
pub fn trace(beam: &Beam, segments: &[Segment], depth: u32) -> Vec<Piece> {
    let from = beam.from.normalize();
    let span = angle(from, beam.to);
    // The directions of the segments' ends, inside the beam: the only places where the
    // nearest segment can change.
    let mut cuts = vec![0.0, span];
    for (i, s) in segments.iter().enumerate() {
        if Some(i) == beam.leaves {
            continue;
        }
        for p in [s.a, s.b] {
            let a = angle(from, p - beam.apex);
            if a > 0.0 && a < span {
                cuts.push(a);
            }
        }
    }
    cuts.sort_by(f64::total_cmp);
    cuts.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    // Where a ray of the beam starts: the apex, or the mirror a reflected beam leaves.
    let start = |d: DVec2| match beam.leaves {
        Some(m) => line_t(beam.apex, d, &segments[m]).unwrap_or(0.0),
        None => 0.0,
    };
    let nearest = |d: DVec2| {
        // Past the apex (t > 0), or just past the mirror a reflected beam leaves: the margin
        // is relative, so a room at any scale is clipped alike.
        let t_min = start(d) * (1.0 + 1e-9);
        segments
            .iter()
            .enumerate()
            .filter(|&(i, _)| Some(i) != beam.leaves)
            .filter_map(|(i, s)| segment_t(beam.apex, d, s, t_min).map(|t| (i, t)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(i, _)| i)
    };
    // One sector per pair of cuts, merged while the same segment sees them.
    let mut sectors: Vec<(f64, f64, Option<usize>)> = Vec::new();
    for w in cuts.windows(2) {
        let seen = nearest(turn(from, (w[0] + w[1]) / 2.0));
        match sectors.last_mut() {
            Some(last) if last.2 == seen => last.1 = w[1],
            _ => sectors.push((w[0], w[1], seen)),
        }
    }
    sectors
        .into_iter()
        .map(|(a, b, seen)| {
            let (da, db) = (turn(from, a), turn(from, b));
            let near = [beam.apex + start(da) * da, beam.apex + start(db) * db];
            let hit = seen.map(|i| {
                let s = &segments[i];
                let at = |d: DVec2| beam.apex + line_t(beam.apex, d, s).unwrap_or(0.0) * d;
                (i, [at(da), at(db)])
            });
            let reflected = match hit {
                Some((i, _)) if segments[i].mirror && depth > 0 => {
                    let r = reflect(beam.apex, da, db, &segments[i], i);
                    let pieces = trace(&r, segments, depth - 1);
                    Some((r, pieces))
                }
                _ => None,
            };
            Piece {
                from: da,
                to: db,
                degrees: (b - a).to_degrees(),
                near,
                hit,
                reflected,
            }
        })
        .collect()
}

/// The beam that mirror `s` (segment `i`) reflects from the rays between `da` and `db` from
/// `apex`: its apex is `apex` mirrored in the mirror's line, its directions the two edges
/// mirrored (a mirror turns counterclockwise into clockwise, so they swap).
fn reflect(apex: DVec2, da: DVec2, db: DVec2, s: &Segment, i: usize) -> Beam {
    let n = (s.b - s.a).perp().normalize();
    let mirror_point = |p: DVec2| p - 2.0 * (p - s.a).dot(n) * n;
    let mirror_dir = |d: DVec2| d - 2.0 * d.dot(n) * n;
    Beam {
        apex: mirror_point(apex),
        from: mirror_dir(db),
        to: mirror_dir(da),
        leaves: Some(i),
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A segment from a to b (for tests here and of the figure).
    pub(crate) fn seg(a: (f64, f64), b: (f64, f64), mirror: bool) -> Segment {
        Segment {
            a: DVec2::new(a.0, a.1),
            b: DVec2::new(b.0, b.1),
            mirror,
        }
    }

    fn room() -> (Beam, Vec<Segment>) {
        let beam = Beam::between(DVec2::ZERO, DVec2::new(-0.6, 1.0), DVec2::new(0.9, 1.0));
        let segments = vec![
            seg((-1.0, 2.0), (0.2, 2.0), false),
            seg((0.4, 1.2), (1.2, 1.6), true),
            seg((-2.0, 4.0), (3.0, 4.0), false),
            seg((2.5, 0.5), (2.5, 3.5), false),
        ];
        (beam, segments)
    }

    /// Casts one ray and returns the segment it meets first from `t_min` on.
    fn brute(
        p: DVec2,
        d: DVec2,
        segs: &[Segment],
        skip: Option<usize>,
        t_min: f64,
    ) -> Option<usize> {
        segs.iter()
            .enumerate()
            .filter(|&(i, _)| Some(i) != skip)
            .filter_map(|(i, s)| segment_t(p, d, s, t_min).map(|t| (i, t)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(i, _)| i)
    }

    /// Every ray of every piece meets the piece's segment first, and the pieces tile the beam.
    fn check_pieces(beam: &Beam, segs: &[Segment], pieces: &[Piece]) {
        let total: f64 = pieces.iter().map(|p| p.degrees).sum();
        assert!((total - width(beam).unwrap()).abs() < 1e-9, "{total}");
        for w in pieces.windows(2) {
            assert!((w[0].to - w[1].from).length() < 1e-12, "pieces leave a gap");
        }
        for p in pieces {
            for k in 1..20 {
                let d = turn(p.from, angle(p.from, p.to) * k as f64 / 20.0);
                let t_min = match beam.leaves {
                    Some(m) => line_t(beam.apex, d, &segs[m]).unwrap() * (1.0 + 1e-9),
                    None => 0.0,
                };
                assert_eq!(
                    brute(beam.apex, d, segs, beam.leaves, t_min),
                    p.hit.map(|h| h.0)
                );
            }
            if let Some((r, rp)) = &p.reflected {
                check_pieces(r, segs, rp);
            }
        }
    }

    #[test]
    fn pieces_tile_the_beam_and_each_is_seen_by_the_nearest_segment() {
        let (beam, segs) = room();
        check(beam.apex, &segs).unwrap();
        let pieces = trace(&beam, &segs, 2);
        check_pieces(&beam, &segs, &pieces);
        // Right to left: the side wall, the mirror, the far wall between the mirror and the
        // near wall, the near wall, and past the far wall's end.
        let hits: Vec<_> = pieces.iter().map(|p| p.hit.map(|h| h.0)).collect();
        assert_eq!(hits, vec![Some(3), Some(1), Some(2), Some(0), None]);
        let mirror = &pieces[1];
        let (r, rp) = mirror.reflected.as_ref().expect("the mirror reflects");
        // The reflected beam's apex is the eye mirrored in the mirror's line.
        let n = (segs[1].b - segs[1].a).perp().normalize();
        assert!(((r.apex - segs[1].a).dot(n) + (beam.apex - segs[1].a).dot(n)).abs() < 1e-12);
        assert!(rp.iter().any(|p| p.hit.map(|h| h.0) == Some(3)), "{rp:?}");
        // The mirror's piece and its reflection are equally wide.
        let wide: f64 = rp.iter().map(|p| p.degrees).sum();
        assert!((wide - mirror.degrees).abs() < 1e-9);
    }

    #[test]
    fn a_room_is_clipped_alike_at_every_scale() {
        let (beam, segs) = room();
        let at = |k: f64| {
            let segs: Vec<Segment> = segs
                .iter()
                .map(|s| Segment {
                    a: s.a * k,
                    b: s.b * k,
                    mirror: s.mirror,
                })
                .collect();
            check(beam.apex, &segs).unwrap();
            let hits = |p: &[Piece]| {
                p.iter()
                    .map(|p| (p.hit.map(|h| h.0), p.degrees))
                    .collect::<Vec<_>>()
            };
            let pieces = trace(&beam, &segs, 1);
            (
                hits(&pieces),
                hits(&pieces[1].reflected.as_ref().unwrap().1),
            )
        };
        let one = at(1.0);
        for k in [1e-10, 1e-6, 1e6, 1e11] {
            let other = at(k);
            assert_eq!(one.0.len(), other.0.len(), "scale {k}");
            for (a, b) in one
                .0
                .iter()
                .chain(&one.1)
                .zip(other.0.iter().chain(&other.1))
            {
                assert_eq!(a.0, b.0, "scale {k}");
                assert!((a.1 - b.1).abs() < 1e-6, "scale {k}: {a:?} {b:?}");
            }
        }
    }

    #[test]
    fn depth_zero_reflects_nothing_and_an_empty_room_is_one_piece() {
        let (beam, segs) = room();
        assert!(trace(&beam, &segs, 0).iter().all(|p| p.reflected.is_none()));
        let alone = trace(&beam, &[], 1);
        assert_eq!(alone.len(), 1);
        assert!(alone[0].hit.is_none());
    }

    #[test]
    fn bad_beams_and_rooms_are_named() {
        let (beam, mut segs) = room();
        let flat = Beam::between(beam.apex, beam.from, -beam.from);
        assert!(matches!(width(&flat), Err(Problem::Width(d)) if (d - 180.0).abs() < 1e-9));
        let none = Beam::between(beam.apex, beam.from, 2.0 * beam.from);
        assert!(matches!(width(&none), Err(Problem::Width(_))));
        segs.push(seg((-1.0, 1.0), (1.0, 3.0), false));
        assert_eq!(check(DVec2::ZERO, &segs), Err(Problem::Cross(0, 4)));
        assert!(Problem::Cross(0, 1)
            .message(&segs)
            .starts_with("wall 1 and mirror 1 cross"));
        // Overlapping on one line is refused; meeting end to end is not.
        let line = [
            seg((0.0, 2.0), (2.0, 2.0), true),
            seg((-1.0, 2.0), (1.0, 2.0), false),
        ];
        assert_eq!(check(DVec2::ZERO, &line), Err(Problem::Cross(0, 1)));
        let ends = [
            seg((0.0, 2.0), (2.0, 2.0), true),
            seg((-1.0, 2.0), (0.0, 2.0), false),
        ];
        assert_eq!(check(DVec2::ZERO, &ends), Ok(()));
        assert_eq!(
            check(DVec2::new(0.0, 2.0), &segs[..1]),
            Err(Problem::OnSegment(0))
        );
        assert_eq!(
            check(DVec2::ZERO, &[seg((1.0, 1.0), (1.0, 1.0), false)]),
            Err(Problem::Empty(0))
        );
    }

    #[test]
    fn a_width_refused_visibly_breaks_the_rule_it_is_told() {
        let width_of =
            |b: (f64, f64)| width(&Beam::between(DVec2::ZERO, DVec2::X, DVec2::new(b.0, b.1)));
        let message = |b: (f64, f64)| width_of(b).unwrap_err().message(&[]);
        // 179.99999994°: less than 180°, but not less than 179.9999999°.
        assert_eq!(
            message((-1.0, 1e-9)),
            "the two directions are 179.99999994° apart: a beam must be less than 179.9999999° \
             wide (180° less 1.0e-7°, so that its two edges are not one line)"
        );
        assert!(message((-1.0, 0.0)).starts_with(
            "the two directions are 180° apart: a beam must be less than 179.9999999° wide"
        ));
        // 5.7e-9°: more than 0°, but not more than 1.0e-7°.
        assert_eq!(
            message((1.0, 1e-10)),
            "the two directions are 5.7e-9° apart: a beam must be more than 1.0e-7° wide \
             (so that its two edges are two directions)"
        );
        assert!(message((2.0, 0.0)).starts_with("the two directions are 0° apart"));
        // Past the limits, a beam is traced.
        assert!(width_of((-1.0, 2e-9)).unwrap() < WIDEST);
        assert!(width_of((1.0, 2e-9)).unwrap() > SLACK);
    }

    #[test]
    fn a_segment_too_short_is_told_the_length_it_needs() {
        let short = [seg((-1e-13, 2.0), (1e-13, 2.0), true)];
        assert_eq!(check(DVec2::ZERO, &short), Err(Problem::Empty(0)));
        assert_eq!(
            Problem::Empty(0).message(&short),
            "mirror 1 is 2.0e-13 long: a segment must be longer than 2.0e-12 \
             (10⁻¹² of its far end's distance from the origin)"
        );
        // Near the origin the same length is a segment.
        let near = [seg((-1e-13, 0.0), (1e-13, 0.0), false)];
        assert_eq!(check(DVec2::new(0.0, 1.0), &near), Ok(()));
        let point = [seg((1.0, 1.0), (1.0, 1.0), false)];
        assert_eq!(
            Problem::Empty(0).message(&point),
            "wall 1 has no length: its two ends are the same point"
        );
    }
}
