//! Where the beam figure's plane lands on the canvas: the frame of what the beam reaches,
//! and the view that maps it to pixels and clips lines and pieces to it.

use super::{BOTTOM, H, MARGIN, TOP, W};
use crate::accel::beam::{Beam, Piece, Segment};
use glam::DVec2;

/// Where the plane's points land on the canvas: a uniform scale, y up.
pub(super) struct View {
    pub(super) min: DVec2,
    pub(super) max: DVec2,
    pub(super) scale: f64,
    pub(super) origin: (f32, f32),
}

impl View {
    /// The view of `frame` ([`frame`]'s corners), as large as the figure allows.
    pub(super) fn new([min, max]: [DVec2; 2]) -> View {
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

    pub(super) fn at(&self, p: DVec2) -> (f32, f32) {
        (
            self.origin.0 + ((p.x - self.min.x) * self.scale) as f32,
            self.origin.1 - ((p.y - self.min.y) * self.scale) as f32,
        )
    }

    /// How far a ray that meets nothing is drawn: past every corner of the view.
    pub(super) fn far(&self) -> f64 {
        (self.max - self.min).length() * 2.0
    }

    /// The part of the segment from `a` to `b` inside the view.
    pub(super) fn clip_line(&self, a: DVec2, b: DVec2) -> Option<(DVec2, DVec2)> {
        crate::viz::clip::segment(a, b, self.min, self.max).filter(|(p, q)| p != q)
    }

    /// `poly` clipped to the view's rectangle ([`crate::viz::clip::polygon`]).
    pub(super) fn clip(&self, poly: Vec<DVec2>) -> Vec<DVec2> {
        crate::viz::clip::polygon(poly, self.min, self.max)
    }
}

/// How far past what the beam reaches the frame may grow to take in whole segments and the
/// reflected beams, in multiples of the size of what it reaches.
const REACH: f64 = 3.0;

/// The part of the plane the figure shows, as its lower-left and upper-right corners: what
/// the beam reaches (the eye and where its pieces meet segments), with a margin, grown to
/// take in whatever lies within `REACH` times that size of it: whole segments, the
/// reflected beams' pieces, and always the first reflections' mirrored eyes, the apexes the
/// figure draws, and where every piece of every reflected beam meets a segment, however far,
/// so that each segment the printed list names is drawn, with the margin too, and can be
/// labelled. A segment that reaches further is cut at the frame, so a mirror 10¹² long
/// does not shrink the beam to a point.
///
/// The mirrored eyes always fit: a first reflection's apex lies twice the eye's distance
/// from the mirror's line away from the eye, and that distance is at most the distance to
/// where the beam meets the mirror, inside what the beam reaches.
pub fn frame(beam: &Beam, segments: &[Segment], pieces: &[Piece]) -> [DVec2; 2] {
    let mut points = vec![beam.apex];
    points.extend(pieces.iter().filter_map(|p| p.hit).flat_map(|(_, h)| h));
    let [lo, hi] = bounds(&points);
    // A beam that meets nothing reaches no point but the eye: then the nearest segment sets
    // the size, and the beam is drawn that far.
    let nearest = segments
        .iter()
        .map(|s| distance(beam.apex, s))
        .fold(f64::INFINITY, f64::min);
    let mut size = (hi - lo).max_element();
    if size == 0.0 {
        size = if nearest.is_finite() && nearest > 0.0 {
            nearest
        } else {
            1.0
        };
        points.extend([beam.from, beam.to].map(|d| beam.apex + size * d.normalize()));
    }
    let (near_lo, near_hi) = (lo - REACH * size, hi + REACH * size);
    let within = |p: DVec2| p.cmpge(near_lo).all() && p.cmple(near_hi).all();
    let mut further = Vec::new();
    for p in pieces {
        if let Some((r, sub)) = &p.reflected {
            points.push(r.apex);
            reached(sub, &mut further);
            met(sub, &mut points);
        }
    }
    for s in segments {
        further.extend([s.a, s.b]);
    }
    // A segment whole or not at all: half of one would look like all of it.
    for pair in further.chunks(2) {
        if pair.iter().all(|&p| within(p)) {
            points.extend(pair);
        }
    }
    let [mut lo, mut hi] = bounds(&points);
    let short = size - (hi - lo).max_element();
    if short > 0.0 {
        lo -= DVec2::splat(short / 2.0);
        hi += DVec2::splat(short / 2.0);
    }
    let pad = DVec2::splat((hi - lo).max_element() * 0.08);
    [lo - pad, hi + pad]
}

/// The points where the pieces of reflected beams start and end, in pairs, deeper beams too.
fn reached(pieces: &[Piece], out: &mut Vec<DVec2>) {
    for p in pieces {
        out.extend(p.near);
        if let Some((_, h)) = p.hit {
            out.extend(h);
        }
        if let Some((_, sub)) = &p.reflected {
            reached(sub, out);
        }
    }
}

/// Where the pieces of reflected beams meet segments, deeper beams too.
fn met(pieces: &[Piece], out: &mut Vec<DVec2>) {
    for p in pieces {
        if let Some((_, h)) = p.hit {
            out.extend(h);
        }
        if let Some((_, sub)) = &p.reflected {
            met(sub, out);
        }
    }
}

fn bounds(points: &[DVec2]) -> [DVec2; 2] {
    points.iter().fold([points[0], points[0]], |[lo, hi], &p| {
        [lo.min(p), hi.max(p)]
    })
}

/// The distance from `p` to segment `s`.
fn distance(p: DVec2, s: &Segment) -> f64 {
    let e = s.b - s.a;
    let u = ((p - s.a).dot(e) / e.length_squared()).clamp(0.0, 1.0);
    (s.a + u * e - p).length()
}
