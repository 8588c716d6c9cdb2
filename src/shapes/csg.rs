//! Constructive solid geometry: solids combined by union, intersection and difference.
//!
//! A CSG node never solves an equation of its own. Each child (a closed shape, or another
//! CSG node) reports the intervals of the ray inside it ([`Span`]s) in its own space; the
//! node merges the lists by its operation ([`combine`]); the first boundary of the result in
//! front of the origin is the hit. Shadow, reflection and refraction rays need nothing more:
//! to the tracer a CSG object is one more shape with a closest-hit routine.

use super::interval::{combine, first_hit, primitive_spans, CsgOp, Span};
use super::{Aabb, Candidate, LocalHit, Observer, Shape};
use crate::math::{Ray, Transform};

/// One operand of a CSG node: a shape placed in the node's space by its own transform.
#[derive(Debug, Clone)]
pub struct CsgChild {
    /// The child's name in the scene file (`#index` when it has none), for explain.
    pub name: String,
    pub shape: Shape,
    /// node_from_child (named like an object's world_from_object, one level down).
    pub transform: Transform,
    /// The child's bounds in the node's space (`None`: unbounded), computed once.
    pub bounds: Option<Aabb>,
}

impl CsgChild {
    pub fn new(name: impl Into<String>, shape: Shape, transform: Transform) -> CsgChild {
        let bounds = shape
            .bounds()
            .map(|b| b.transformed(&transform.world_from_object));
        CsgChild {
            name: name.into(),
            shape,
            transform,
            bounds,
        }
    }

    /// True when the whole line misses the child's bounding box: then it has no spans, and
    /// nothing needs solving.
    fn missed_by(&self, ray: &Ray) -> bool {
        self.bounds.is_some_and(|b| {
            b.hit(ray, ray.dir.recip(), f64::NEG_INFINITY, f64::INFINITY)
                .is_none()
        })
    }
}

/// A CSG node: its operation folded over the children from left to right
/// (A − B − C = (A − B) − C = A − (B ∪ C)).
#[derive(Debug, Clone)]
pub struct Csg {
    pub op: CsgOp,
    pub children: Vec<CsgChild>,
}

impl Csg {
    // ANCHOR: spans
    /// The spans of the ray inside this node's solid, over the whole line. Each child's ray
    /// goes into the child's space (t is shared, as for objects), the child's normals come back
    /// through its inverse transpose, and the lists are combined by the node's operation.
    pub fn spans<O: Observer>(&self, ray: &Ray, obs: &mut O) -> Vec<Span> {
        obs.csg_begin(self.op);
        let mut result: Option<Vec<Span>> = None;
        for child in &self.children {
            if !O::ACTIVE
                && result.as_ref().is_some_and(|r| r.is_empty())
                && self.op != CsgOp::Union
            {
                break; // nothing ∩ X and nothing − X are nothing
            }
            let mut spans = if child.missed_by(ray) {
                Vec::new()
            } else {
                child.shape.spans(&child.transform.ray_to_object(ray), obs)
            };
            for s in &mut spans {
                for h in [&mut s.enter, &mut s.exit] {
                    h.normal = child.transform.normal_to_world(h.normal);
                    h.point = ray.at(h.t);
                }
            }
            obs.csg_child(child, &spans);
            result = Some(match result {
                None => spans,
                Some(acc) => combine(self.op, &acc, &spans),
            });
        }
        let result = result.unwrap_or_default();
        obs.csg_end(&result);
        result
    }
    // ANCHOR_END: spans

    /// The closest boundary of the combined solid with t_min ≤ t ≤ t_max. Every boundary of
    /// the result is shown to the observer as a candidate.
    pub fn intersect<O: Observer>(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        obs: &mut O,
    ) -> Option<LocalHit> {
        let spans = self.spans(ray, obs);
        if O::ACTIVE {
            for h in spans.iter().flat_map(|s| [s.enter, s.exit]) {
                let c = Candidate {
                    t: h.t,
                    point: h.point,
                    surface: h.surface,
                    on_shape: true,
                    in_front: h.t >= t_min,
                };
                obs.candidate(c, String::new);
            }
        }
        first_hit(&spans, t_min, t_max)
    }

    /// Bounds in the node's space: a union is bounded by all children, an intersection by
    /// the overlap of their boxes, a difference by its first child.
    pub fn bounds(&self) -> Option<Aabb> {
        let mut boxes = self.children.iter().map(|c| c.bounds);
        let first = boxes.next()??;
        match self.op {
            CsgOp::Difference => Some(first),
            CsgOp::Union => boxes.try_fold(first, |acc, b| b.map(|b| acc.union(b))),
            CsgOp::Intersection => Some(boxes.flatten().fold(first, |acc, b| Aabb {
                min: acc.min.max(b.min),
                max: acc.max.min(b.max),
            })),
        }
    }
}

impl Shape {
    /// The spans of the ray inside this shape (the interval query), over the whole line.
    /// Canonical shapes derive them from their candidate roots; CSG nodes and blobs from their
    /// own routines. CSG nodes show their working to the observer, the others' internal
    /// working is not repeated under a CSG node.
    pub fn spans<O: Observer>(&self, ray: &Ray, obs: &mut O) -> Vec<Span> {
        match self {
            Shape::Csg(c) => c.spans(ray, obs),
            Shape::Blob(b) => b.spans(ray, &mut super::NoObserver),
            other => primitive_spans(other, ray),
        }
    }

    /// True for shapes that bound a solid (what CSG can combine): spheres, boxes, capped
    /// cylinders and cones, closed meshes, blobs and CSG nodes.
    pub fn is_solid(&self) -> bool {
        match self {
            Shape::Sphere(_) | Shape::Box(_) | Shape::Csg(_) | Shape::Blob(_) => true,
            Shape::Cylinder(c) => c.capped,
            Shape::Cone(c) => c.capped,
            Shape::Mesh(m) => m.is_closed(),
            Shape::Plane(_) | Shape::Triangle(_) => false,
        }
    }
}
