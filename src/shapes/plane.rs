use super::{Candidate, LocalHit, Observer};
use crate::math::Ray;
use glam::{DVec2, DVec3};

/// An infinite plane through `point` with unit `normal`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    pub point: DVec3,
    pub normal: DVec3,
}

impl Plane {
    /// Substitute P + t·d into n·(Q − Q0) = 0: t = n·(Q0 − P) / n·d (no hit when n·d = 0).
    pub fn intersect<O: Observer>(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        obs: &mut O,
    ) -> Option<LocalHit> {
        let denom = self.normal.dot(ray.dir);
        let numerator = self.normal.dot(self.point - ray.origin);
        obs.linear("plane", numerator, denom);
        if denom.abs() < 1e-300 {
            return None; // parallel: no root at all
        }
        let t = numerator / denom;
        let point = ray.at(t);
        let in_front = t >= t_min;
        obs.candidate(
            Candidate {
                t,
                point,
                surface: "plane",
                on_shape: true,
                in_front,
            },
            String::new,
        );
        if !(in_front && t <= t_max) {
            return None;
        }
        let (e1, e2) = self.tangents();
        let rel = point - self.point;
        let uv = DVec2::new(rel.dot(e1), rel.dot(e2));
        Some(LocalHit {
            t,
            point,
            normal: self.normal,
            uv,
            surface: "plane",
            barycentric: None,
            index: 0,
        })
    }

    /// Two unit vectors spanning the plane (texture axes): e1 is x projected onto the plane
    /// (z when the plane is perpendicular to x), e2 = n × e1... chosen so a floor y = 0 maps
    /// u to +x and v to −z, as seen from above.
    pub fn tangents(&self) -> (DVec3, DVec3) {
        let n = self.normal;
        let seed = if n.x.abs() < 0.9 { DVec3::X } else { DVec3::Z };
        let e1 = (seed - n * n.dot(seed)).normalize();
        let e2 = n.cross(e1);
        (e1, e2)
    }
}
