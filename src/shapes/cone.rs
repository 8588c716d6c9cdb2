use super::working::short;
use super::{u_around_y, Candidate, LocalHit, Observer, Quadratic, ON_SHAPE_EPS};
use crate::math::Ray;
use crate::mistakes::{Mistake, Mistakes};
use glam::{DVec2, DVec3};

/// The double cone x² + z² = (k·y)² with apex at the origin, cut to y_min ≤ y ≤ y_max, with
/// flat caps (discs of radius k·|y|) at the ends unless `capped` is false. A cap of radius 0
/// (an end at the apex) is not a surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cone {
    pub slope: f64,
    pub y_min: f64,
    pub y_max: f64,
    pub capped: bool,
}

impl Cone {
    /// Case by case, as for the cylinder: body roots tossed outside the y range, cap roots
    /// tossed outside their disc.
    pub fn intersect<O: Observer>(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        obs: &mut O,
    ) -> Option<LocalHit> {
        self.intersect_as(ray, t_min, t_max, Mistakes::NONE, obs)
    }

    /// [`Cone::intersect`] under the catalogue's mistakes (`cap-radius`, `cone-normal`).
    pub fn intersect_as<O: Observer>(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        mistakes: Mistakes,
        obs: &mut O,
    ) -> Option<LocalHit> {
        let c = Candidate::nearest(t_max, |f| self.candidates_as(ray, t_min, mistakes, obs, f))?;
        Some(self.local_hit_as(ray, c.t, c.surface, mistakes))
    }

    /// Every body and cap root, on the finite shape or not, handed to `found` (and shown to
    /// the observer). Serves both the closest hit and the CSG interval query.
    pub fn candidates<O: Observer>(
        &self,
        ray: &Ray,
        t_min: f64,
        obs: &mut O,
        found: impl FnMut(Candidate),
    ) {
        self.candidates_as(ray, t_min, Mistakes::NONE, obs, found)
    }

    /// [`Cone::candidates`] under the catalogue's mistakes: `cap-radius` accepts a cap root
    /// at x² + z² ≤ r instead of r².
    pub fn candidates_as<O: Observer>(
        &self,
        ray: &Ray,
        t_min: f64,
        mistakes: Mistakes,
        obs: &mut O,
        mut found: impl FnMut(Candidate),
    ) {
        let (p, d) = (ray.origin, ray.dir);
        let k2 = self.slope * self.slope;
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

        // Body: substitute into x² + z² − k²y² = 0.
        let q = Quadratic::new(
            d.x * d.x + d.z * d.z - k2 * d.y * d.y,
            2.0 * (p.x * d.x + p.z * d.z - k2 * p.y * d.y),
            p.x * p.x + p.z * p.z - k2 * p.y * p.y,
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
        if self.capped && d.y != 0.0 {
            for (plane, surface) in [(self.y_max, "top-cap"), (self.y_min, "bottom-cap")] {
                let cap_r = self.slope * plane.abs();
                if cap_r <= 0.0 {
                    continue;
                }
                let t = (plane - p.y) / d.y;
                let (x, z) = (p.x + t * d.x, p.z + t * d.z);
                let rr = x * x + z * z;
                let r2 = if mistakes.has(Mistake::CapRadius) {
                    cap_r
                } else {
                    cap_r * cap_r
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

    pub(crate) fn local_hit(&self, ray: &Ray, t: f64, surface: &'static str) -> LocalHit {
        self.local_hit_as(ray, t, surface, Mistakes::NONE)
    }

    fn local_hit_as(
        &self,
        ray: &Ray,
        t: f64,
        surface: &'static str,
        mistakes: Mistakes,
    ) -> LocalHit {
        // `cone-normal`: the slope dropped from the gradient, (x, 0, z), the cylinder's normal.
        let k2 = if mistakes.has(Mistake::ConeNormal) {
            0.0
        } else {
            self.slope * self.slope
        };
        let mut point = ray.at(t);
        let (normal, uv) = match surface {
            "top-cap" | "bottom-cap" => {
                let top = surface == "top-cap";
                point.y = if top { self.y_max } else { self.y_min };
                let r = self.slope * point.y.abs();
                let (u, v) = (
                    point.x / (2.0 * r) + 0.5,
                    if top {
                        0.5 - point.z / (2.0 * r)
                    } else {
                        point.z / (2.0 * r) + 0.5
                    },
                );
                (if top { DVec3::Y } else { DVec3::NEG_Y }, DVec2::new(u, v))
            }
            _ => {
                // Gradient of x² + z² − k²y², pointing away from the axis.
                let g = DVec3::new(point.x, -k2 * point.y, point.z);
                let n = g.try_normalize().unwrap_or(if point.y >= 0.0 {
                    DVec3::Y
                } else {
                    DVec3::NEG_Y
                });
                let v = (point.y - self.y_min) / (self.y_max - self.y_min);
                let u = if point.x.hypot(point.z) < 1e-12 {
                    0.5
                } else {
                    u_around_y(point.x, point.z)
                };
                (n, DVec2::new(u, v))
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
