use super::{Barycentric, BlobStep, CsgChild, CsgOp, Observer, Quadratic, Span};
use glam::DVec3;
use serde::Serialize;

/// One root of one equation, reported whether or not it counts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Candidate {
    pub t: f64,
    /// Object-space point P + t·d.
    pub point: DVec3,
    pub surface: &'static str,
    /// On the finite shape (inside the cap's disc, within the body's y range, inside the triangle).
    pub on_shape: bool,
    /// At or beyond the ray's t_min.
    pub in_front: bool,
}

impl Candidate {
    /// The lecture's rule over a shape's candidates: the smallest t that is on the finite
    /// shape, in front of the origin and within `t_max`. `each` hands every candidate over.
    pub fn nearest(t_max: f64, each: impl FnOnce(&mut dyn FnMut(Candidate))) -> Option<Candidate> {
        let mut best: Option<Candidate> = None;
        each(&mut |c: Candidate| {
            if c.on_shape && c.in_front && c.t <= t_max && best.is_none_or(|b| c.t < b.t) {
                best = Some(c);
            }
        });
        best
    }
}

/// A candidate as it is written out, with the reason it was kept or tossed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CandidateRecord {
    pub t: f64,
    pub point: DVec3,
    pub surface: &'static str,
    pub on_shape: bool,
    pub in_front: bool,
    pub note: String,
    #[serde(skip)]
    pub off_shape_reason: String,
}

/// The observer that keeps everything: what `explain` and `intersect` print.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Working {
    pub quadratics: Vec<(&'static str, Quadratic)>,
    pub candidates: Vec<CandidateRecord>,
    pub barycentric: Option<Barycentric>,
    pub mesh: Option<(usize, Option<usize>)>,
    /// Linear equations t = numerator / denominator, by surface.
    pub linear: Vec<(&'static str, f64, f64)>,
    /// A CSG object's intervals: each child's and the combination.
    pub csg: Option<CsgWorking>,
    /// A blob's root search.
    pub blob: Option<BlobWorking>,
    /// Nodes of the shape's own BVH (a mesh's) that the ray visited.
    pub bvh_nodes: Option<u32>,
    /// CSG nodes being combined (nested nodes sit above their parent).
    #[serde(skip)]
    csg_stack: Vec<CsgWorking>,
    /// A nested node that just finished, waiting for its parent to list it as a child.
    #[serde(skip)]
    csg_nested: Option<CsgWorking>,
}

/// Where a ray crosses a solid's boundary, as explain writes it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Boundary {
    pub t: f64,
    pub surface: &'static str,
    pub point: DVec3,
    /// Outward normal of the solid (of the combined solid, for a node's result).
    pub normal: DVec3,
}

/// One interval of the ray inside a solid.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SpanRecord {
    pub enter: Boundary,
    pub exit: Boundary,
}

impl SpanRecord {
    pub fn of(s: &Span) -> SpanRecord {
        let b = |h: &super::LocalHit| Boundary {
            t: h.t,
            surface: h.surface,
            point: h.point,
            normal: h.normal,
        };
        SpanRecord {
            enter: b(&s.enter),
            exit: b(&s.exit),
        }
    }
}

/// A CSG node's working: its children's intervals (in the node's space, with the shared t)
/// and the intervals of the combination.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CsgWorking {
    pub op: CsgOp,
    pub children: Vec<CsgChildWorking>,
    pub combined: Vec<SpanRecord>,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CsgChildWorking {
    pub name: String,
    pub shape: &'static str,
    pub spans: Vec<SpanRecord>,
    /// The child's own working when it is a CSG node itself.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub csg: Option<Box<CsgWorking>>,
}

/// A blob's root search on one ray: field samples, brackets and refinement steps.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct BlobWorking {
    pub threshold: f64,
    /// Bound on |dF/dt| used to rule pieces of the ray out.
    pub lipschitz: f64,
    /// Pieces of the ray inside the components' spheres of influence, [t_in, t_out].
    pub segments: Vec<[f64; 2]>,
    /// Every evaluation of the field, [t, field], in the order the search made them.
    pub samples: Vec<[f64; 2]>,
    pub brackets: Vec<BlobBracket>,
    pub steps: Vec<BlobStep>,
    pub roots: Vec<BlobRoot>,
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BlobBracket {
    pub a: f64,
    pub b: f64,
    pub field_a: f64,
    pub field_b: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BlobRoot {
    pub t: f64,
    pub entering: bool,
}

impl Observer for Working {
    const ACTIVE: bool = true;
    fn quadratic(&mut self, label: &'static str, q: &Quadratic) {
        self.quadratics.push((label, *q));
    }
    fn candidate(&mut self, c: Candidate, why: impl FnOnce() -> String) {
        let off_shape_reason = if c.on_shape { String::new() } else { why() };
        self.candidates.push(CandidateRecord {
            t: c.t,
            point: c.point,
            surface: c.surface,
            on_shape: c.on_shape,
            in_front: c.in_front,
            note: String::new(),
            off_shape_reason,
        });
    }
    fn linear(&mut self, label: &'static str, numerator: f64, denominator: f64) {
        self.linear.push((label, numerator, denominator));
    }
    fn barycentric(&mut self, b: &Barycentric) {
        self.barycentric = Some(*b);
    }
    fn mesh(&mut self, tested: usize, index: Option<usize>) {
        self.mesh = Some((tested, index));
    }
    fn csg_begin(&mut self, op: CsgOp) {
        self.csg_stack.push(CsgWorking {
            op,
            children: Vec::new(),
            combined: Vec::new(),
        });
    }
    fn csg_child(&mut self, child: &CsgChild, spans: &[Span]) {
        let nested = self.csg_nested.take().map(Box::new);
        if let Some(node) = self.csg_stack.last_mut() {
            node.children.push(CsgChildWorking {
                name: child.name.clone(),
                shape: child.shape.kind(),
                spans: spans.iter().map(SpanRecord::of).collect(),
                csg: nested,
            });
        }
    }
    fn csg_end(&mut self, combined: &[Span]) {
        if let Some(mut node) = self.csg_stack.pop() {
            node.combined = combined.iter().map(SpanRecord::of).collect();
            if self.csg_stack.is_empty() {
                self.csg = Some(node);
            } else {
                self.csg_nested = Some(node);
            }
        }
    }
    fn blob_search(&mut self, threshold: f64, lipschitz: f64, segments: &[[f64; 2]]) {
        self.blob = Some(BlobWorking {
            threshold,
            lipschitz,
            segments: segments.to_vec(),
            ..Default::default()
        });
    }
    fn blob_sample(&mut self, t: f64, field: f64) {
        if let Some(b) = &mut self.blob {
            b.samples.push([t, field]);
        }
    }
    fn blob_bracket(&mut self, a: f64, b: f64, field_a: f64, field_b: f64) {
        if let Some(w) = &mut self.blob {
            w.brackets.push(BlobBracket {
                a,
                b,
                field_a,
                field_b,
            });
        }
    }
    fn blob_step(&mut self, step: BlobStep) {
        if let Some(b) = &mut self.blob {
            b.steps.push(step);
        }
    }
    fn blob_root(&mut self, t: f64, entering: bool) {
        if let Some(b) = &mut self.blob {
            b.roots.push(BlobRoot { t, entering });
        }
    }
    fn bvh_nodes(&mut self, n: u32) {
        self.bvh_nodes = Some(n);
    }
}

impl Working {
    /// Sorts the candidates by t and writes each one's verdict, given the t that won
    /// (`None`: nothing was hit) and the t_max the search was limited to.
    pub fn conclude(&mut self, hit_t: Option<f64>, t_max: f64) {
        self.candidates.sort_by(|a, b| a.t.total_cmp(&b.t));
        let mut kept = false;
        for c in &mut self.candidates {
            c.note = if !c.on_shape {
                format!("tossed: {}", c.off_shape_reason)
            } else if !c.in_front && c.t.abs() < 1e-5 {
                "tossed: t ≈ 0 is the surface this ray starts from (its origin is nudged off it)"
                    .to_string()
            } else if !c.in_front {
                "tossed: behind the ray's origin (t < 0)".to_string()
            } else if !kept && hit_t == Some(c.t) {
                kept = true;
                "kept: the smallest t on this shape that is in front of the origin".to_string()
            } else if c.t > t_max {
                format!(
                    "tossed: farther than a closer hit already found (t = {})",
                    short(t_max)
                )
            } else {
                "tossed: a smaller t was kept".to_string()
            };
        }
    }
}

/// A number in a short human form for notes (full precision lives in the JSON fields).
pub fn short(x: f64) -> String {
    let s = format!("{:.4}", x);
    let s = s.trim_end_matches('0').trim_end_matches('.').to_string();
    if s == "-0" {
        "0".into()
    } else {
        s
    }
}

/// A vector as the working prints it: "(x, y, z)", each coordinate written by `number`
/// ([`short`] or [`tiny`]).
pub fn vector(coords: &[f64], number: fn(f64) -> String) -> String {
    let parts: Vec<String> = coords.iter().map(|&x| number(x)).collect();
    format!("({})", parts.join(", "))
}

/// A number that may be tiny: scientific notation below 1e-4, else the short form.
pub fn tiny(x: f64) -> String {
    if x != 0.0 && x.abs() < 1e-4 {
        format!("{x:.1e}")
    } else {
        short(x)
    }
}
