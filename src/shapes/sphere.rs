use super::{u_around_y, Candidate, LocalHit, Observer, Quadratic};
use crate::math::Ray;
use glam::{DVec2, DVec3};
use std::f64::consts::PI;

/// A sphere |Q − center|² = radius².
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere {
    pub center: DVec3,
    pub radius: f64,
}

impl Sphere {
    // ANCHOR: sphere
    /// Substitute P + t·d into |Q − C|² − r² = 0: (d·d)t² + 2(d·(P − C))t + |P − C|² − r² = 0.
    pub fn intersect<O: Observer>(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        obs: &mut O,
    ) -> Option<LocalHit> {
        let mut best = None;
        self.candidates(ray, t_min, obs, |c| {
            if c.in_front && c.t <= t_max && best.is_none() {
                best = Some(c.t); // roots come sorted: the first one in front is the closest
            }
        });
        best.map(|t| self.local_hit(ray, t))
    }

    /// Every root of the sphere's quadratic, smallest first, each handed to `found` (and
    /// shown to the observer). The closest-hit query above and the CSG interval query
    /// ([`super::interval`]) both start here.
    pub fn candidates<O: Observer>(
        &self,
        ray: &Ray,
        t_min: f64,
        obs: &mut O,
        mut found: impl FnMut(Candidate),
    ) {
        let oc = ray.origin - self.center;
        let q = Quadratic::new(
            ray.dir.dot(ray.dir),
            2.0 * oc.dot(ray.dir),
            oc.dot(oc) - self.radius * self.radius,
        );
        obs.quadratic("sphere", &q);
        let (roots, n) = q.solve();
        for &t in &roots[..n] {
            let c = Candidate {
                t,
                point: ray.at(t),
                surface: "sphere",
                on_shape: true,
                in_front: t >= t_min,
            };
            obs.candidate(c, String::new);
            found(c);
        }
    }
    // ANCHOR_END: sphere

    pub(crate) fn local_hit(&self, ray: &Ray, t: f64) -> LocalHit {
        let point = ray.at(t);
        let n = (point - self.center) / self.radius;
        let v = 0.5 + n.y.clamp(-1.0, 1.0).asin() / PI;
        let u = if n.y.abs() > 1.0 - 1e-12 {
            0.5
        } else {
            u_around_y(n.x, n.z)
        };
        LocalHit {
            t,
            point,
            normal: n.normalize(),
            uv: DVec2::new(u, v),
            surface: "sphere",
            barycentric: None,
            index: 0,
        }
    }
}
