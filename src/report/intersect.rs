//! What `rtlab intersect` found for one ray against one canonical shape: the document of
//! `--format json` plus what the text and the figure (`viz::intersect`) need. A library type,
//! so that figures and the server do not depend on the CLI.
//!
//! The numbers come from the shape's own intersection routine (`src/shapes/`), the one the
//! tracer runs, watched by a [`Working`] observer; nothing here solves anything itself.

use crate::math::Ray;
use crate::shapes::{Roots, Shape, Working};
use glam::DVec3;
use serde::Serialize;

#[derive(Debug, Clone, Serialize)]
pub struct RayJson {
    pub origin: Vec<f64>,
    pub direction: Vec<f64>,
}

#[derive(Debug, Clone, Serialize)]
pub struct QuadraticJson {
    pub a: f64,
    pub b: f64,
    pub c: f64,
    pub discriminant: f64,
    pub roots: Roots,
    /// D came out tiny but nonzero and was taken as 0 (a tangent).
    pub rounded_to_zero: bool,
}

/// A linear equation t = numerator / denominator (the plane: n·(Q0 − P) / n·d).
#[derive(Debug, Clone, Serialize)]
pub struct LinearJson {
    pub numerator: f64,
    pub denominator: f64,
}

#[derive(Debug, Clone, Serialize)]
pub struct CandidateJson {
    pub t: f64,
    pub point: Vec<f64>,
    pub surface: &'static str,
    pub on_shape: bool,
    pub in_front: bool,
    pub note: String,
}

/// Cramer's rule for a triangle. The fields are `null` when the determinant is 0 (the ray is
/// parallel to the triangle's plane, or the triangle is degenerate).
#[derive(Debug, Clone, Serialize)]
pub struct BarycentricJson {
    pub alpha: Option<f64>,
    pub beta: Option<f64>,
    pub gamma: Option<f64>,
    pub determinant: f64,
    pub t: Option<f64>,
}

#[derive(Debug, Clone, Serialize)]
pub struct HitJson {
    pub t: f64,
    pub point: Vec<f64>,
    pub normal: Vec<f64>,
    pub surface: &'static str,
}

/// Everything `intersect` found: the JSON document, plus what the text and figure need.
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    pub shape: &'static str,
    pub ray: RayJson,
    pub quadratic: Option<QuadraticJson>,
    /// Shapes solved by one division (the plane): added to the contract's fields.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub linear: Option<LinearJson>,
    pub candidates: Vec<CandidateJson>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub barycentric: Option<BarycentricJson>,
    pub hit: Option<HitJson>,
    /// The shape intersected (the circle as its sphere in z = 0).
    #[serde(skip)]
    pub solid: Shape,
    /// The 3D ray given to the routine.
    #[serde(skip)]
    pub ray3: Ray,
}

impl Report {
    pub fn is_2d(&self) -> bool {
        self.shape == "circle"
    }
}

/// Runs the shape's routine with a [`Working`] observer and gathers the report.
pub fn report(name: &'static str, shape: Shape, ray: Ray) -> Report {
    let mut w = Working::default();
    let hit = shape.intersect(&ray, 0.0, f64::INFINITY, &mut w);
    w.conclude(hit.map(|h| h.t), f64::INFINITY);
    let two_d = name == "circle";
    let p = |v: DVec3| -> Vec<f64> {
        if two_d {
            vec![v.x, v.y]
        } else {
            vec![v.x, v.y, v.z]
        }
    };
    let quadratic = w.quadratics.first().map(|(_, q)| QuadraticJson {
        a: q.a,
        b: q.b,
        c: q.c,
        discriminant: q.discriminant,
        roots: q.roots,
        rounded_to_zero: q.rounded_to_zero,
    });
    let barycentric = matches!(shape, Shape::Triangle(_)).then(|| match w.barycentric {
        Some(b) => BarycentricJson {
            alpha: Some(b.alpha),
            beta: Some(b.beta),
            gamma: Some(b.gamma),
            determinant: b.determinant,
            t: Some(b.t),
        },
        None => BarycentricJson {
            alpha: None,
            beta: None,
            gamma: None,
            determinant: 0.0,
            t: None,
        },
    });
    let surface_name = |s: &'static str| if two_d && s == "sphere" { "circle" } else { s };
    Report {
        shape: name,
        ray: RayJson {
            origin: p(ray.origin),
            direction: p(ray.dir),
        },
        quadratic,
        linear: w.linear.first().map(|(_, n, d)| LinearJson {
            numerator: *n,
            denominator: *d,
        }),
        candidates: w
            .candidates
            .iter()
            .map(|c| CandidateJson {
                t: c.t,
                point: p(c.point),
                surface: surface_name(c.surface),
                on_shape: c.on_shape,
                in_front: c.in_front,
                note: c.note.replace("on this shape", &format!("on this {name}")),
            })
            .collect(),
        barycentric,
        hit: hit.map(|h| HitJson {
            t: h.t,
            point: p(h.point),
            normal: p(h.normal),
            surface: surface_name(h.surface),
        }),
        solid: shape,
        ray3: ray,
    }
}
