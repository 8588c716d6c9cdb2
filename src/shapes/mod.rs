//! The shapes, each in its own canonical object space.
//!
//! Every shape has exactly one intersection routine, generic over an [`Observer`] that can
//! watch its working (the quadratic and its discriminant, every candidate root and why it was
//! kept or tossed, Cramer's determinants). The renderer passes [`NoObserver`], a zero-sized
//! type whose empty methods compile away; `explain` and `intersect` pass [`Working`].

mod aabb;
mod blob;
mod cone;
mod csg;
mod cuboid;
mod cylinder;
pub mod interval;
mod mesh;
mod plane;
mod quadratic;
mod sphere;
mod triangle;
pub mod working;

pub use aabb::Aabb;
pub use blob::{Blob, BlobStep, Component, Falloff};
pub use cone::Cone;
pub use csg::{Csg, CsgChild};
pub use cuboid::Cuboid;
pub use cylinder::Cylinder;
pub use interval::{CsgOp, Span};
pub use mesh::{single_precision, Mesh, PackedFace};
pub use plane::Plane;
pub use quadratic::{Quadratic, Roots, TANGENT_TOLERANCE};
pub use sphere::Sphere;
pub use triangle::{
    cramer, cramer_hit, cramer_hit_plane_first, cramer_hit_prepared, cramer_prepared, Barycentric,
    FaceFrom, Numerators, Prepared, Triangle,
};
pub use working::{Candidate, Working};

use crate::math::Ray;
use glam::{DVec2, DVec3};
use std::f64::consts::PI;
use std::sync::Arc;

/// Watches one shape's intersection working. Every method defaults to doing nothing.
pub trait Observer {
    /// True for observers that keep what they see; shapes use it to skip work done only for
    /// the observer (formatting a reason, re-running the winning mesh triangle).
    const ACTIVE: bool = false;
    /// The quadratic a·t² + b·t + c = 0 that a surface's equation became.
    fn quadratic(&mut self, _label: &'static str, _q: &Quadratic) {}
    /// A root of some equation: `why` is asked only by active observers, and says why a
    /// candidate that is not on the finite shape was tossed.
    fn candidate(&mut self, _c: Candidate, _why: impl FnOnce() -> String) {}
    /// A linear equation t = numerator / denominator (a plane: n·(Q0 − P) / n·d), reported
    /// before the division, so a zero denominator (a parallel ray) can be shown.
    fn linear(&mut self, _label: &'static str, _numerator: f64, _denominator: f64) {}
    /// Cramer's rule for a triangle (also when the point lies outside).
    fn barycentric(&mut self, _b: &Barycentric) {}
    /// A mesh tested `n` triangles; the winning one was `index`.
    fn mesh(&mut self, _tested: usize, _index: Option<usize>) {}
    /// A CSG node starts combining its children (nested nodes begin and end inside).
    fn csg_begin(&mut self, _op: CsgOp) {}
    /// One child's spans, in the node's space.
    fn csg_child(&mut self, _child: &CsgChild, _spans: &[Span]) {}
    /// The node's combined spans.
    fn csg_end(&mut self, _combined: &[Span]) {}
    /// A blob's root search begins: the pieces of the ray inside the components' spheres of
    /// influence and the Lipschitz bound of F(t) on them.
    fn blob_search(&mut self, _threshold: f64, _lipschitz: f64, _segments: &[[f64; 2]]) {}
    /// One evaluation of the field Σ s·f at t.
    fn blob_sample(&mut self, _t: f64, _field: f64) {}
    /// A bracket [a, b] with the field on opposite sides of the threshold at its ends.
    fn blob_bracket(&mut self, _a: f64, _b: f64, _field_a: f64, _field_b: f64) {}
    /// One refinement step inside a bracket.
    fn blob_step(&mut self, _step: BlobStep) {}
    /// A root, entering or leaving the blob.
    fn blob_root(&mut self, _t: f64, _entering: bool) {}
    /// A shape's own BVH (a mesh's) visited `n` nodes.
    fn bvh_nodes(&mut self, _n: u32) {}
}

/// The observer of `render`: sees nothing, costs nothing.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoObserver;
impl Observer for NoObserver {}

/// Where on an object a ray landed, in the object's own space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalHit {
    pub t: f64,
    pub point: DVec3,
    /// Outward normal in object space, unit length.
    pub normal: DVec3,
    pub uv: DVec2,
    pub surface: &'static str,
    /// Barycentric weights (alpha, beta, gamma) for triangles and meshes.
    pub barycentric: Option<[f64; 3]>,
    /// The triangle of a mesh.
    pub index: u32,
}

/// Everything that can be intersected. A closed set, so an enum: one `match` per query.
#[derive(Debug, Clone)]
pub enum Shape {
    Sphere(Sphere),
    Plane(Plane),
    Box(Cuboid),
    Cylinder(Cylinder),
    Cone(Cone),
    Triangle(Triangle),
    Mesh(Arc<Mesh>),
    /// A CSG node (its children are shapes, CSG nodes included).
    Csg(Arc<Csg>),
    Blob(Arc<Blob>),
}

impl Shape {
    /// The closest intersection with `t_min <= t <= t_max` of an object-space ray.
    #[inline]
    pub fn intersect<O: Observer>(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        obs: &mut O,
    ) -> Option<LocalHit> {
        match self {
            Shape::Sphere(s) => s.intersect(ray, t_min, t_max, obs),
            Shape::Plane(s) => s.intersect(ray, t_min, t_max, obs),
            Shape::Box(s) => s.intersect(ray, t_min, t_max, obs),
            Shape::Cylinder(s) => s.intersect(ray, t_min, t_max, obs),
            Shape::Cone(s) => s.intersect(ray, t_min, t_max, obs),
            Shape::Triangle(s) => s.intersect(ray, t_min, t_max, obs),
            Shape::Mesh(s) => s.intersect(ray, t_min, t_max, obs),
            Shape::Csg(s) => s.intersect(ray, t_min, t_max, obs),
            Shape::Blob(s) => s.intersect(ray, t_min, t_max, obs),
        }
    }

    /// [`Shape::intersect`] under the catalogue's shape mistakes (`cap-radius`,
    /// `cone-normal`); other shapes have none.
    #[inline]
    pub fn intersect_as<O: Observer>(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        mistakes: crate::mistakes::Mistakes,
        obs: &mut O,
    ) -> Option<LocalHit> {
        match self {
            Shape::Cylinder(s) => s.intersect_as(ray, t_min, t_max, mistakes, obs),
            Shape::Cone(s) => s.intersect_as(ray, t_min, t_max, mistakes, obs),
            _ => self.intersect(ray, t_min, t_max, obs),
        }
    }

    /// Is there any intersection with `t_min <= t <= t_max`? For shadow rays: a mesh stops at
    /// the first face it finds; other shapes answer with their closest hit (as cheap).
    /// Returns that hit; `is_some()` always equals `intersect(..).is_some()`.
    #[inline(always)]
    pub fn occluded<O: Observer>(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        obs: &mut O,
    ) -> Option<LocalHit> {
        match self {
            Shape::Mesh(s) => s.occluded(ray, t_min, t_max, obs),
            _ => self.intersect(ray, t_min, t_max, obs),
        }
    }

    /// Object-space bounds; `None` for unbounded shapes (the plane).
    pub fn bounds(&self) -> Option<Aabb> {
        match self {
            Shape::Sphere(s) => Some(Aabb::new(
                s.center - DVec3::splat(s.radius),
                s.center + DVec3::splat(s.radius),
            )),
            Shape::Plane(_) => None,
            Shape::Box(s) => Some(Aabb::new(s.min, s.max)),
            Shape::Cylinder(s) => Some(Aabb::new(
                DVec3::new(-s.radius, s.y_min, -s.radius),
                DVec3::new(s.radius, s.y_max, s.radius),
            )),
            Shape::Cone(s) => {
                let r = s.slope * s.y_min.abs().max(s.y_max.abs());
                Some(Aabb::new(
                    DVec3::new(-r, s.y_min, -r),
                    DVec3::new(r, s.y_max, r),
                ))
            }
            Shape::Triangle(s) => Some(Aabb::around(&s.v)),
            Shape::Mesh(m) => Some(m.bounds),
            Shape::Csg(c) => c.bounds(),
            Shape::Blob(b) => b.bounds(),
        }
    }

    /// The shape's name as the scene format spells it.
    pub fn kind(&self) -> &'static str {
        match self {
            Shape::Sphere(_) => "sphere",
            Shape::Plane(_) => "plane",
            Shape::Box(_) => "box",
            Shape::Cylinder(_) => "cylinder",
            Shape::Cone(_) => "cone",
            Shape::Triangle(_) => "triangle",
            Shape::Mesh(_) => "mesh",
            Shape::Csg(_) => "csg",
            Shape::Blob(_) => "blob",
        }
    }
}

/// The longitude texture coordinate of the lecture: u runs once around the y axis,
/// increasing counter-clockwise seen from above... matching the course's convention
/// (u = -θ/2π for θ < 0, else 1 - θ/2π, with θ = atan2(z, x)).
pub fn u_around_y(x: f64, z: f64) -> f64 {
    let theta = z.atan2(x);
    if theta < 0.0 {
        -theta / (2.0 * PI)
    } else {
        1.0 - theta / (2.0 * PI)
    }
}

/// Relative tolerance used by the "is this point on the finite shape" tests, so that a root
/// computed a few ulps outside a cap rim or a face edge still counts.
pub(crate) const ON_SHAPE_EPS: f64 = 1e-9;
