use super::working::short;
use super::{u_around_y, Candidate, LocalHit, Observer, Quadratic, ON_SHAPE_EPS};
use crate::math::Ray;
use crate::mistakes::{Mistake, Mistakes};
use glam::{DVec2, DVec3};

/// The finite cylinder x² + z² = r², y_min ≤ y ≤ y_max, around the y axis, with flat caps
/// unless `capped` is false.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cylinder {
    pub radius: f64,
    pub y_min: f64,
    pub y_max: f64,
    pub capped: bool,
}

impl Cylinder {
    // ANCHOR: cylinder
    /// The lecture's case-by-case method: body roots t1, t2 from the infinite cylinder, tossed
    /// when their y is outside [y_min, y_max]; cap roots t3, t4 from the planes y = y_max and
    /// y = y_min, tossed when x² + z² > r². The smallest remaining t ≥ t_min wins.
    pub fn intersect<O: Observer>(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        obs: &mut O,
    ) -> Option<LocalHit> {
        self.intersect_as(ray, t_min, t_max, Mistakes::NONE, obs)
    }

    /// [`Cylinder::intersect`] under the catalogue's mistakes (`cap-radius`).
    pub fn intersect_as<O: Observer>(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        mistakes: Mistakes,
        obs: &mut O,
    ) -> Option<LocalHit> {
        let c = Candidate::nearest(t_max, |f| self.candidates_as(ray, t_min, mistakes, obs, f))?;
        Some(self.local_hit(c.point, c.t, c.surface))
    }

    /// Every candidate t1..t4, on the finite shape or not, handed to `found` in the order
    /// they are computed (and shown to the observer with the reason a tossed one was tossed).
    /// Serves both the closest hit above and the CSG interval query.
    pub fn candidates<O: Observer>(
        &self,
        ray: &Ray,
        t_min: f64,
        obs: &mut O,
        found: impl FnMut(Candidate),
    ) {
        self.candidates_as(ray, t_min, Mistakes::NONE, obs, found)
    }

    /// [`Cylinder::candidates`] under the catalogue's mistakes: `cap-radius` accepts a cap
    /// root at x² + z² ≤ r instead of r².
    pub fn candidates_as<O: Observer>(
        &self,
        ray: &Ray,
        t_min: f64,
        mistakes: Mistakes,
        obs: &mut O,
        mut found: impl FnMut(Candidate),
    ) {
        let (p, d, r) = (ray.origin, ray.dir, self.radius);
        let mut consider = |t: f64,
                            surface: &'static str,
                            on_shape: bool,
                            why: &dyn Fn() -> String,
                            obs: &mut O| {
            let c = Candidate {
                t,
                point: ray.at(t),
                surface,
                on_shape,
                in_front: t >= t_min,
            };
            obs.candidate(c, why);
            found(c);
        };

        // Body: substitute into x² + z² − r² = 0.
        let q = Quadratic::new(
            d.x * d.x + d.z * d.z,
            2.0 * (p.x * d.x + p.z * d.z),
            p.x * p.x + p.z * p.z - r * r,
        );
        obs.quadratic("body", &q);
        let (roots, n) = q.solve();
        let tol = ON_SHAPE_EPS * (self.y_max - self.y_min).abs().max(1.0);
        for &t in &roots[..n] {
            let y = p.y + t * d.y;
            let on_shape = y >= self.y_min - tol && y <= self.y_max + tol;
            let why = || {
                format!(
                    "y = {} is outside [{}, {}]",
                    short(y),
                    short(self.y_min),
                    short(self.y_max)
                )
            };
            consider(t, "body", on_shape, &why, obs);
        }

        // Caps: the planes y = y_max (top) and y = y_min (bottom).
        if self.capped && d.y != 0.0 {
            for (plane, surface) in [(self.y_max, "top-cap"), (self.y_min, "bottom-cap")] {
                let t = (plane - p.y) / d.y;
                let (x, z) = (p.x + t * d.x, p.z + t * d.z);
                let rr = x * x + z * z;
                let r2 = if mistakes.has(Mistake::CapRadius) {
                    r
                } else {
                    r * r
                };
                let on_shape = rr <= r2 * (1.0 + ON_SHAPE_EPS);
                let why = || {
                    format!(
                        "x² + z² = {} > r² = {}: outside the cap's disc",
                        short(rr),
                        short(r2)
                    )
                };
                consider(t, surface, on_shape, &why, obs);
            }
        }
    }
    // ANCHOR_END: cylinder

    pub(crate) fn local_hit(&self, mut point: DVec3, t: f64, surface: &'static str) -> LocalHit {
        let r = self.radius;
        let (normal, uv) = match surface {
            "top-cap" => {
                point.y = self.y_max;
                (
                    DVec3::Y,
                    DVec2::new(point.x / (2.0 * r) + 0.5, 0.5 - point.z / (2.0 * r)),
                )
            }
            "bottom-cap" => {
                point.y = self.y_min;
                (
                    DVec3::NEG_Y,
                    DVec2::new(point.x / (2.0 * r) + 0.5, point.z / (2.0 * r) + 0.5),
                )
            }
            _ => {
                let v = (point.y - self.y_min) / (self.y_max - self.y_min);
                (
                    DVec3::new(point.x, 0.0, point.z).normalize_or(DVec3::X),
                    DVec2::new(u_around_y(point.x, point.z), v),
                )
            }
        };
        LocalHit {
            t,
            point,
            normal,
            uv,
            surface,
            barycentric: None,
            index: 0,
        }
    }
}
