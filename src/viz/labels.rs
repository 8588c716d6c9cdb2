//! Label placement without overlaps: each label is offered a few candidate positions, in order
//! of preference, and takes the first whose box is inside the area and clear of every box
//! placed so far (other labels, and marks registered as obstacles).

use super::{Anchor, Canvas};
use tiny_skia::Color;

/// A box [x0, y0, x1, y1] in pixels.
pub type Box2 = [f32; 4];

/// The boxes already taken on a figure.
#[derive(Debug, Clone)]
pub struct Labels {
    taken: Vec<Box2>,
    area: Box2,
}

fn overlaps(a: &Box2, b: &Box2) -> bool {
    a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3]
}

/// The box of `text` drawn at `at` with `anchor` (vertical middle at `at.1`), with a margin.
pub fn text_box(at: (f32, f32), text: &str, size: f32, anchor: Anchor) -> Box2 {
    let w = Canvas::text_width(text, size);
    let x0 = match anchor {
        Anchor::Left => at.0,
        Anchor::Center => at.0 - w / 2.0,
        Anchor::Right => at.0 - w,
    };
    let h = size * 0.62;
    [x0 - 2.0, at.1 - h - 1.0, x0 + w + 2.0, at.1 + h + 1.0]
}

impl Labels {
    /// Labels must stay inside `area` ([x0, y0, x1, y1]).
    pub fn new(area: Box2) -> Labels {
        Labels {
            taken: Vec::new(),
            area,
        }
    }

    /// Marks a box as taken (a point mark, a legend).
    pub fn block(&mut self, b: Box2) {
        self.taken.push(b);
    }

    /// Marks the pixels along a segment as taken (so labels do not sit on lines).
    pub fn block_segment(&mut self, a: (f32, f32), b: (f32, f32), r: f32) {
        let n = ((b.0 - a.0).hypot(b.1 - a.1) / 6.0).ceil().min(2000.0) as usize;
        for i in 0..=n {
            let f = if n == 0 { 0.0 } else { i as f32 / n as f32 };
            self.block_point((a.0 + (b.0 - a.0) * f, a.1 + (b.1 - a.1) * f), r);
        }
    }

    /// Marks a small square around a point as taken.
    pub fn block_point(&mut self, p: (f32, f32), r: f32) {
        self.taken.push([p.0 - r, p.1 - r, p.0 + r, p.1 + r]);
    }

    fn free(&self, b: &Box2) -> bool {
        b[0] >= self.area[0]
            && b[1] >= self.area[1]
            && b[2] <= self.area[2]
            && b[3] <= self.area[3]
            && !self.taken.iter().any(|t| overlaps(t, b))
    }

    /// Draws `text` at the first free candidate (position and anchor) and returns where, or
    /// draws nothing and returns `None` when every candidate overlaps something (for labels a
    /// figure can do without, such as a t value that is also in the text output).
    pub fn place(
        &mut self,
        canvas: &mut Canvas,
        candidates: &[((f32, f32), Anchor)],
        text: &str,
        size: f32,
        color: Color,
    ) -> Option<(f32, f32)> {
        self.place_inner(canvas, candidates, text, size, color, false)
    }

    /// As [`Labels::place`], but when no candidate is free, uses the first one inside the area
    /// (a readable overlap beats a missing name).
    pub fn place_any(
        &mut self,
        canvas: &mut Canvas,
        candidates: &[((f32, f32), Anchor)],
        text: &str,
        size: f32,
        color: Color,
    ) -> Option<(f32, f32)> {
        self.place_inner(canvas, candidates, text, size, color, true)
    }

    fn place_inner(
        &mut self,
        canvas: &mut Canvas,
        candidates: &[((f32, f32), Anchor)],
        text: &str,
        size: f32,
        color: Color,
        overlap: bool,
    ) -> Option<(f32, f32)> {
        let (at, anchor) = self.reserve(candidates, text, size, overlap)?;
        canvas.text(at, text, size, color, anchor);
        Some(at)
    }

    /// Chooses where `text` goes as [`Labels::place`] does (with `overlap`, as
    /// [`Labels::place_any`]) and marks that box taken, without drawing: for a caller that
    /// draws the label its own way (on a backing, say).
    pub fn reserve(
        &mut self,
        candidates: &[((f32, f32), Anchor)],
        text: &str,
        size: f32,
        overlap: bool,
    ) -> Option<((f32, f32), Anchor)> {
        let boxes: Vec<Box2> = candidates
            .iter()
            .map(|(at, a)| text_box(*at, text, size, *a))
            .collect();
        let inside = |b: &Box2| {
            b[0] >= self.area[0]
                && b[1] >= self.area[1]
                && b[2] <= self.area[2]
                && b[3] <= self.area[3]
        };
        let pick = (0..candidates.len())
            .find(|&i| self.free(&boxes[i]))
            .or_else(|| {
                (0..candidates.len())
                    .filter(|_| overlap)
                    .find(|&i| inside(&boxes[i]))
            })?;
        self.taken.push(boxes[pick]);
        Some(candidates[pick])
    }
}

/// How many places [`around`] gives: one ring of [`around_rings`].
pub const AROUND: usize = 8;

/// Candidate label positions around a point: right, left, above, below, then the diagonals,
/// `gap` pixels away.
pub fn around(p: (f32, f32), gap: f32) -> Vec<((f32, f32), Anchor)> {
    let ring: [_; AROUND] = [
        ((p.0 + gap, p.1), Anchor::Left),
        ((p.0 - gap, p.1), Anchor::Right),
        ((p.0, p.1 - gap - 4.0), Anchor::Center),
        ((p.0, p.1 + gap + 4.0), Anchor::Center),
        ((p.0 + gap, p.1 - gap - 2.0), Anchor::Left),
        ((p.0 - gap, p.1 - gap - 2.0), Anchor::Right),
        ((p.0 + gap, p.1 + gap + 2.0), Anchor::Left),
        ((p.0 - gap, p.1 + gap + 2.0), Anchor::Right),
    ];
    ring.to_vec()
}

/// [`around`] at three distances: near first, then farther out.
pub fn around_rings(p: (f32, f32), gap: f32) -> Vec<((f32, f32), Anchor)> {
    let mut v = around(p, gap);
    v.extend(around(p, gap * 2.0));
    v.extend(around(p, gap * 3.2));
    v
}

/// How a label set off a line in direction x = `ox` (of a unit offset) hangs from its
/// point: to the right of it (anchored left), to the left, or centred above or below.
pub fn side_anchor(ox: f32) -> Anchor {
    if ox > 0.35 {
        Anchor::Left
    } else if ox < -0.35 {
        Anchor::Right
    } else {
        Anchor::Center
    }
}

/// Candidate positions beside a segment a→b: at its middle, then at a third and two thirds,
/// on either side (`gap` pixels off the line).
pub fn beside(a: (f32, f32), b: (f32, f32), gap: f32) -> Vec<((f32, f32), Anchor)> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len = (dx * dx + dy * dy).sqrt().max(1e-3);
    // The normal that points up (screen y down), so "above the line" comes first.
    let (mut nx, mut ny) = (dy / len, -dx / len);
    if ny > 0.0 {
        nx = -nx;
        ny = -ny;
    }
    let mut out = Vec::new();
    for f in [0.5f32, 0.3, 0.7, 0.15, 0.85] {
        let m = (a.0 + dx * f, a.1 + dy * f);
        for s in [1.0f32, -1.0] {
            let (ox, oy) = (nx * s, ny * s);
            let anchor = side_anchor(ox);
            let extra = if anchor == Anchor::Center { 5.0 } else { 0.0 };
            out.push(((m.0 + ox * gap, m.1 + oy * (gap + extra)), anchor));
        }
    }
    out
}
