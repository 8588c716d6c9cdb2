use super::{Barycentric, Observer, Quadratic};
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
    /// Nodes of the shape's own BVH (a mesh's) that the ray visited.
    pub bvh_nodes: Option<u32>,
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
    fn barycentric(&mut self, b: &Barycentric) {
        self.barycentric = Some(*b);
    }
    fn mesh(&mut self, tested: usize, index: Option<usize>) {
        self.mesh = Some((tested, index));
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
