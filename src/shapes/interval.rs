//! Intervals along a ray: where the whole line P + t·d is inside a solid.
//!
//! A closed solid cuts the line into spans [enter, exit]. Constructive solid geometry works on
//! these lists alone: each child reports its spans, the node merges them by its operation.
//! The boundaries carry the surface record of the hit (normal, uv, surface name), so the
//! combined list's first boundary in front of the origin *is* the hit, with the right normal.

use super::{LocalHit, NoObserver, Shape};
use crate::math::Ray;
use serde::Serialize;

/// How a CSG node combines its children.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum CsgOp {
    /// Inside any child.
    Union,
    /// Inside every child.
    Intersection,
    /// Inside the first child and in none of the others.
    Difference,
}

impl CsgOp {
    pub const NAMES: [&'static str; 3] = ["union", "intersection", "difference"];
    pub fn parse(s: &str) -> Option<CsgOp> {
        Some(match s {
            "union" => CsgOp::Union,
            "intersection" => CsgOp::Intersection,
            "difference" => CsgOp::Difference,
            _ => return None,
        })
    }
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }
    /// The operation's truth table: is a point inside the result, given whether it is inside
    /// the left and the right operand.
    pub fn inside(self, a: bool, b: bool) -> bool {
        match self {
            CsgOp::Union => a || b,
            CsgOp::Intersection => a && b,
            CsgOp::Difference => a && !b,
        }
    }
    /// The symbol used in figures and text: A ∪ B, A ∩ B, A − B.
    pub fn symbol(self) -> &'static str {
        match self {
            CsgOp::Union => "∪",
            CsgOp::Intersection => "∩",
            CsgOp::Difference => "−",
        }
    }
}

/// One piece of the line inside a solid. `enter.normal` and `exit.normal` are the solid's
/// outward normals there (so `enter.normal · d < 0` and `exit.normal · d > 0`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Span {
    pub enter: LocalHit,
    pub exit: LocalHit,
}

/// Two boundaries closer than this (relative to |t|) are the same point: touching solids
/// merge, zero-length pieces vanish. Shared faces computed by two shapes differ by rounding.
pub const TOUCH: f64 = 1e-9;

fn same_t(a: f64, b: f64) -> bool {
    (a - b).abs() <= TOUCH * (1.0 + a.abs().max(b.abs()))
}

// ANCHOR: crossings
/// Spans from a solid's boundary crossings, in any order: `entering` says whether the line
/// goes into the solid there. Sorted by t; crossings of the same kind at the same t (a ray
/// through a box edge, or through the edge two mesh triangles share) count once; a crossing
/// that contradicts the current state (an exit while outside: a grazing touch) is dropped.
pub fn spans_from_crossings(mut xs: Vec<(LocalHit, bool)>) -> Vec<Span> {
    xs.sort_by(|a, b| a.0.t.total_cmp(&b.0.t).then(b.1.cmp(&a.1))); // entries first at equal t
    let mut spans = Vec::new();
    let mut open: Option<LocalHit> = None;
    for (hit, entering) in xs {
        match (open, entering) {
            (None, true) => open = Some(hit),
            (Some(enter), false) => {
                spans.push(Span { enter, exit: hit });
                open = None;
            }
            _ => {} // a second entry while inside, or an exit while outside
        }
    }
    tidy(spans)
}
// ANCHOR_END: crossings

// ANCHOR: combine
/// Combines two sorted span lists by `op`: sweep the boundaries of both in t order, keep
/// track of "inside A" and "inside B", and emit a boundary wherever the truth table's answer
/// changes. A boundary keeps its surface's normal when the result enters where that operand
/// enters; where a subtracted solid's surface becomes the boundary (the result enters where
/// B is left, or leaves where B begins), the normal is flipped.
pub fn combine(op: CsgOp, a: &[Span], b: &[Span]) -> Vec<Span> {
    // (hit, from B, entering)
    let mut events: Vec<(LocalHit, bool, bool)> = Vec::with_capacity(2 * (a.len() + b.len()));
    for (list, from_b) in [(a, false), (b, true)] {
        for s in list {
            events.push((s.enter, from_b, true));
            events.push((s.exit, from_b, false));
        }
    }
    // Exits before entries at equal t: touching pieces then meet end to start, and `tidy`
    // merges or drops them instead of the sweep inventing an overlap.
    events.sort_by(|x, y| x.0.t.total_cmp(&y.0.t).then(x.2.cmp(&y.2)));
    let (mut in_a, mut in_b) = (false, false);
    let mut spans = Vec::new();
    let mut open: Option<LocalHit> = None;
    for (mut hit, from_b, entering) in events {
        let before = op.inside(in_a, in_b);
        if from_b {
            in_b = entering;
        } else {
            in_a = entering;
        }
        let after = op.inside(in_a, in_b);
        if before == after {
            continue;
        }
        if after != entering {
            hit.normal = -hit.normal; // a subtracted surface bounds the result
        }
        if after {
            open = Some(hit);
        } else if let Some(enter) = open.take() {
            spans.push(Span { enter, exit: hit });
        }
    }
    tidy(spans)
}
// ANCHOR_END: combine

/// Drops zero-length spans and joins spans that touch end to start.
fn tidy(spans: Vec<Span>) -> Vec<Span> {
    let mut out: Vec<Span> = Vec::with_capacity(spans.len());
    for s in spans {
        if same_t(s.enter.t, s.exit.t) {
            continue;
        }
        match out.last_mut() {
            Some(prev) if same_t(prev.exit.t, s.enter.t) => prev.exit = s.exit,
            _ => out.push(s),
        }
    }
    out
}

/// The first boundary with t_min ≤ t ≤ t_max: the closest hit on the solid.
pub fn first_hit(spans: &[Span], t_min: f64, t_max: f64) -> Option<LocalHit> {
    spans
        .iter()
        .flat_map(|s| [s.enter, s.exit])
        .find(|h| h.t >= t_min)
        .filter(|h| h.t <= t_max)
}

/// The spans of a canonical shape along the whole line, from the same candidate roots its
/// closest-hit routine uses: every candidate on the finite shape is a boundary crossing,
/// entering where the outward normal faces the ray. Planes and triangles bound no solid and
/// have no spans (the scene loader refuses them as CSG children).
pub fn primitive_spans(shape: &Shape, ray: &Ray) -> Vec<Span> {
    let mut xs: Vec<(LocalHit, bool)> = Vec::new();
    let d = ray.dir;
    let mut push = |h: LocalHit| {
        let side = h.normal.dot(d);
        if side != 0.0 {
            xs.push((h, side < 0.0));
        }
    };
    let all = f64::NEG_INFINITY;
    let obs = &mut NoObserver;
    match shape {
        Shape::Sphere(s) => s.candidates(ray, all, obs, |c| push(s.local_hit(ray, c.t))),
        Shape::Box(s) => s.candidates(ray, all, obs, |c| {
            if c.on_shape {
                push(s.local_hit(c.t, c.point, c.surface))
            }
        }),
        Shape::Cylinder(s) => s.candidates(ray, all, obs, |c| {
            if c.on_shape {
                push(s.local_hit(c.point, c.t, c.surface))
            }
        }),
        Shape::Cone(s) => s.candidates(ray, all, obs, |c| {
            if c.on_shape {
                push(s.local_hit(ray, c.t, c.surface))
            }
        }),
        Shape::Mesh(m) => m.crossings(ray, |h, entering| xs.push((h, entering))),
        Shape::Plane(_) | Shape::Triangle(_) | Shape::Csg(_) | Shape::Blob(_) => {}
    }
    spans_from_crossings(xs)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DVec2, DVec3};

    /// A span from a to b on a line along +x, with outward normals.
    fn span(a: f64, b: f64, name: &'static str) -> Span {
        let hit = |t: f64, n: f64| LocalHit {
            t,
            point: DVec3::new(t, 0.0, 0.0),
            normal: DVec3::new(n, 0.0, 0.0),
            uv: DVec2::ZERO,
            surface: name,
            barycentric: None,
            index: 0,
        };
        Span {
            enter: hit(a, -1.0),
            exit: hit(b, 1.0),
        }
    }
    fn ts(s: &[Span]) -> Vec<(f64, f64)> {
        s.iter().map(|s| (s.enter.t, s.exit.t)).collect()
    }

    #[test]
    fn overlapping_spans_by_each_operation() {
        let a = [span(0.0, 2.0, "a")];
        let b = [span(1.0, 3.0, "b")];
        assert_eq!(ts(&combine(CsgOp::Union, &a, &b)), [(0.0, 3.0)]);
        assert_eq!(ts(&combine(CsgOp::Intersection, &a, &b)), [(1.0, 2.0)]);
        assert_eq!(ts(&combine(CsgOp::Difference, &a, &b)), [(0.0, 1.0)]);
        assert_eq!(ts(&combine(CsgOp::Difference, &b, &a)), [(2.0, 3.0)]);
    }

    #[test]
    fn touching_spans_merge_or_vanish() {
        let a = [span(0.0, 1.0, "a")];
        let b = [span(1.0, 2.0, "b")];
        // Union of solids sharing a face: one piece, no inner wall.
        let u = combine(CsgOp::Union, &a, &b);
        assert_eq!(ts(&u), [(0.0, 2.0)]);
        assert_eq!((u[0].enter.surface, u[0].exit.surface), ("a", "b"));
        // Intersection of solids that only touch: empty, not a zero-length piece.
        assert!(combine(CsgOp::Intersection, &a, &b).is_empty());
        // Rounding of a shared face computed twice is still a touch.
        let b2 = [span(1.0 + 1e-12, 2.0, "b")];
        assert_eq!(ts(&combine(CsgOp::Union, &a, &b2)), [(0.0, 2.0)]);
        // A − B where B ends exactly where A ends: no sliver left at t = 2.
        let a3 = [span(0.0, 2.0, "a")];
        assert_eq!(
            ts(&combine(CsgOp::Difference, &a3, &b)),
            [(0.0, 1.0)],
            "difference with a shared end face"
        );
    }

    #[test]
    fn nested_spans() {
        let outer = [span(0.0, 10.0, "outer")];
        let inner = [span(3.0, 4.0, "inner")];
        assert_eq!(ts(&combine(CsgOp::Union, &outer, &inner)), [(0.0, 10.0)]);
        assert_eq!(
            ts(&combine(CsgOp::Intersection, &outer, &inner)),
            [(3.0, 4.0)]
        );
        let hollow = combine(CsgOp::Difference, &outer, &inner);
        assert_eq!(ts(&hollow), [(0.0, 3.0), (4.0, 10.0)]);
        // The inner wall's normals are the inner solid's, flipped: they point into the hole.
        assert_eq!(hollow[0].exit.surface, "inner");
        assert_eq!(hollow[0].exit.normal, DVec3::X); // inner entered at t = 3 with −x; flipped
        assert_eq!(hollow[1].enter.normal, -DVec3::X); // inner left at t = 4 with +x; flipped
        assert!(combine(CsgOp::Difference, &inner, &outer).is_empty());
        // Several pieces on each side.
        let a = [span(0.0, 2.0, "a"), span(4.0, 6.0, "a")];
        let b = [span(1.0, 5.0, "b")];
        assert_eq!(
            ts(&combine(CsgOp::Intersection, &a, &b)),
            [(1.0, 2.0), (4.0, 5.0)]
        );
        assert_eq!(
            ts(&combine(CsgOp::Difference, &a, &b)),
            [(0.0, 1.0), (5.0, 6.0)]
        );
        assert_eq!(ts(&combine(CsgOp::Union, &a, &b)), [(0.0, 6.0)]);
    }

    #[test]
    fn empty_operands_and_results() {
        let a = [span(0.0, 1.0, "a")];
        let far = [span(5.0, 6.0, "b")];
        assert!(combine(CsgOp::Intersection, &a, &far).is_empty());
        assert!(combine(CsgOp::Intersection, &a, &[]).is_empty());
        assert_eq!(ts(&combine(CsgOp::Union, &[], &a)), [(0.0, 1.0)]);
        assert_eq!(ts(&combine(CsgOp::Difference, &a, &[])), [(0.0, 1.0)]);
        assert!(combine(CsgOp::Difference, &[], &a).is_empty());
        assert!(combine(CsgOp::Difference, &a, &a).is_empty(), "A − A");
    }

    #[test]
    fn first_hit_respects_the_range() {
        let s = [span(-1.0, 2.0, "a"), span(4.0, 6.0, "a")];
        assert_eq!(first_hit(&s, 0.0, 10.0).map(|h| h.t), Some(2.0)); // from inside: the exit
        assert_eq!(first_hit(&s, 2.5, 10.0).map(|h| h.t), Some(4.0));
        assert_eq!(first_hit(&s, 2.5, 3.0), None);
    }

    #[test]
    fn box_edge_crossings_count_once() {
        // A ray through the edge of the unit box enters two faces at the same t.
        let b = Shape::Box(super::super::Cuboid {
            min: DVec3::splat(-1.0),
            max: DVec3::ONE,
        });
        let ray = Ray::new(DVec3::new(-2.0, 2.0, 0.0), DVec3::new(1.0, -1.0, 0.0));
        let s = primitive_spans(&b, &ray);
        assert_eq!(ts(&s), [(1.0, 3.0)]);
    }
}
