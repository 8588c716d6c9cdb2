//! Blobby objects: the surface where a sum of smooth bumps reaches a threshold.
//!
//! Each component adds a bump s·f(r) around its centre, with r = |Q − c| / R the distance in
//! units of its radius of influence R (f(0) = 1, f = 0 for r ≥ 1). The surface is
//! F(Q) = Σ s·f(r) − T = 0, inside where F > 0. Substituting the ray gives F(t), a sum of
//! polynomials (Wyvill) or exponentials (Gaussian) in t: no closed form, so the roots are
//! found numerically, and robustly:
//!
//! 1. Bracket. Outside every component's sphere of influence F = −T < 0, so only the pieces
//!    of the ray inside those spheres can hold a root. On a piece [a, b], F cannot change by
//!    more than L·(b − a), where L bounds |dF/dt| (a Lipschitz constant: Σ |s|·max|f'|/R·|d|).
//!    If F(a) and F(b) have the same sign and |F(a)| + |F(b)| > L·(b − a), there is no root
//!    in [a, b]. Nor is there when interval arithmetic keeps the field on one side of T (each
//!    bump is largest where the piece passes closest to its centre, smallest at the far
//!    end). Otherwise halve the piece and look again. Nothing thinner than the smallest piece
//!    looked at (a millionth of the smallest radius) can be missed.
//! 2. Refine each bracket [a, b] with F(a), F(b) of opposite sign by Newton's method,
//!    falling back to bisection whenever a Newton step would leave the bracket.
//!
//! The normal is −∇F / |∇F|: the field falls off outwards.

use super::{Aabb, LocalHit, NoObserver, Observer, Span, Sphere};
use crate::math::Ray;
use glam::{DVec2, DVec3};
use serde::Serialize;

/// The shape of one component's bump, as a function of u = r² (no square roots needed).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Falloff {
    /// The Wyvills' soft-object polynomial 1 − 22/9·u + 17/9·u² − 4/9·u³ (f(0.5) = 0.5).
    Wyvill,
    /// A Gaussian e^(−4u), shifted and scaled to reach 0 at r = 1.
    Gaussian,
}

const E4: f64 = 0.018_315_638_888_734_18; // e^-4

impl Falloff {
    pub const NAMES: [&'static str; 2] = ["wyvill", "gaussian"];
    pub fn parse(s: &str) -> Option<Falloff> {
        match s {
            "wyvill" => Some(Falloff::Wyvill),
            "gaussian" => Some(Falloff::Gaussian),
            _ => None,
        }
    }
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }
    // ANCHOR: falloff
    /// f and df/du at u = r² (both 0 for u ≥ 1).
    #[inline]
    pub fn eval(self, u: f64) -> (f64, f64) {
        if u >= 1.0 {
            return (0.0, 0.0);
        }
        match self {
            Falloff::Wyvill => (
                1.0 + u * (-22.0 / 9.0 + u * (17.0 / 9.0 - u * 4.0 / 9.0)),
                -22.0 / 9.0 + u * (34.0 / 9.0 - u * 12.0 / 9.0),
            ),
            Falloff::Gaussian => {
                let e = (-4.0 * u).exp();
                ((e - E4) / (1.0 - E4), -4.0 * e / (1.0 - E4))
            }
        }
    }
    // ANCHOR_END: falloff
    /// An upper bound of |df/dr| over r in [0, 1] (df/dr = 2r·df/du); a unit test checks it.
    pub fn max_slope(self) -> f64 {
        match self {
            Falloff::Wyvill => 1.6,    // the maximum is 1.58.. near r = 0.52
            Falloff::Gaussian => 1.75, // 2√2·e^(−1/2)/(1 − e^−4) = 1.747.. at r = 1/√8
        }
    }
}

/// One bump of the field.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Component {
    pub center: DVec3,
    /// Radius of influence R: the bump is 0 from r = R on.
    pub radius: f64,
    /// s: the bump's height at its centre (negative strengths carve).
    pub strength: f64,
}

/// A blobby object: F(Q) = Σ s·f(|Q − c|²/R²) − threshold, inside where F > 0.
#[derive(Debug, Clone, PartialEq)]
pub struct Blob {
    pub threshold: f64,
    pub falloff: Falloff,
    pub components: Vec<Component>,
}

/// What the root finder saw on one ray (kept by active observers).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BlobStep {
    /// "bisection" or "newton".
    pub method: &'static str,
    pub t: f64,
    /// The field Σ s·f at t (compare with the threshold).
    pub field: f64,
    /// The bracket after this step.
    pub a: f64,
    pub b: f64,
}

impl Blob {
    // ANCHOR: field
    /// The field Σ s·f(r) at a point and its gradient.
    pub fn field(&self, p: DVec3) -> (f64, DVec3) {
        let mut value = 0.0;
        let mut gradient = DVec3::ZERO;
        for c in &self.components {
            let q = p - c.center;
            let r2 = 1.0 / (c.radius * c.radius);
            let u = q.length_squared() * r2;
            if u < 1.0 {
                let (f, df) = self.falloff.eval(u);
                value += c.strength * f;
                gradient += c.strength * df * 2.0 * r2 * q; // du/dQ = 2q/R²
            }
        }
        (value, gradient)
    }
    // ANCHOR_END: field

    /// Object-space bounds: the spheres of influence of the positive components (negative
    /// ones only remove material).
    pub fn bounds(&self) -> Option<Aabb> {
        let b = self
            .components
            .iter()
            .filter(|c| c.strength > 0.0)
            .fold(Aabb::EMPTY, |b, c| {
                b.union(Aabb::new(
                    c.center - DVec3::splat(c.radius),
                    c.center + DVec3::splat(c.radius),
                ))
            });
        (!b.is_empty()).then_some(b)
    }

    /// The pieces of the line inside the positive components' spheres of influence, merged
    /// and sorted (from the sphere's own quadratic), and the Lipschitz bound L of F(t).
    pub fn segments(&self, ray: &Ray) -> (Vec<[f64; 2]>, f64) {
        let mut pieces: Vec<[f64; 2]> = Vec::new();
        for c in self.components.iter().filter(|c| c.strength > 0.0) {
            let sphere = Sphere {
                center: c.center,
                radius: c.radius,
            };
            let mut roots = Vec::with_capacity(2);
            sphere.candidates(ray, f64::NEG_INFINITY, &mut NoObserver, |c| roots.push(c.t));
            if roots.len() == 2 {
                pieces.push([roots[0], roots[1]]);
            }
        }
        pieces.sort_by(|a, b| a[0].total_cmp(&b[0]));
        let mut merged: Vec<[f64; 2]> = Vec::new();
        for p in pieces {
            match merged.last_mut() {
                Some(m) if p[0] <= m[1] => m[1] = m[1].max(p[1]),
                _ => merged.push(p),
            }
        }
        let slope: f64 = self
            .components
            .iter()
            .map(|c| c.strength.abs() / c.radius)
            .sum();
        (merged, slope * self.falloff.max_slope() * ray.dir.length())
    }

    // ANCHOR: roots
    /// The roots of F(t) = 0 with t_min ≤ t ≤ t_max, in order, each with whether the ray
    /// enters the blob there; only the first one when `first_only`. Every field evaluation,
    /// bracket and refinement step is shown to the observer.
    pub fn roots<O: Observer>(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        first_only: bool,
        obs: &mut O,
    ) -> Vec<(f64, bool)> {
        let (segments, lipschitz) = self.segments(ray);
        obs.blob_search(self.threshold, lipschitz, &segments);
        let min_radius = self
            .components
            .iter()
            .map(|c| c.radius)
            .fold(f64::INFINITY, f64::min);
        // The finest piece looked at, in t: a millionth of the smallest radius.
        let h_min = 1e-6 * min_radius / ray.dir.length();
        let mut search = Search {
            blob: self,
            ray,
            lipschitz,
            h_min,
            first_only,
            roots: Vec::new(),
            obs,
        };
        for [a, b] in segments {
            let (a, b) = (a.max(t_min), b.min(t_max));
            if a > b {
                continue;
            }
            let (fa, fb) = (search.f(a), search.f(b));
            if search.bracket(a, b, fa, fb) {
                break;
            }
        }
        search.roots
    }
    // ANCHOR_END: roots

    /// The closest root with t_min ≤ t ≤ t_max.
    pub fn intersect<O: Observer>(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        obs: &mut O,
    ) -> Option<LocalHit> {
        let (t, _) = *self.roots(ray, t_min, t_max, true, obs).first()?;
        Some(self.local_hit(ray, t))
    }

    /// The spans of the whole line inside the blob.
    pub fn spans<O: Observer>(&self, ray: &Ray, obs: &mut O) -> Vec<Span> {
        let xs = self
            .roots(ray, f64::NEG_INFINITY, f64::INFINITY, false, obs)
            .into_iter()
            .map(|(t, entering)| (self.local_hit(ray, t), entering))
            .collect();
        super::interval::spans_from_crossings(xs)
    }

    pub fn local_hit(&self, ray: &Ray, t: f64) -> LocalHit {
        let point = ray.at(t);
        let (_, g) = self.field(point);
        // Where the gradient vanishes (a saddle exactly on the surface), face the ray.
        let normal = (-g).try_normalize().unwrap_or(-ray.dir.normalize());
        LocalHit {
            t,
            point,
            normal,
            uv: DVec2::new(
                0.5 + normal.x.atan2(normal.z) / std::f64::consts::TAU,
                0.5 + 0.5 * normal.y,
            ),
            surface: "blob",
            barycentric: None,
            index: 0,
        }
    }
}

/// The recursive bracketing search on one ray.
struct Search<'a, O: Observer> {
    blob: &'a Blob,
    ray: &'a Ray,
    lipschitz: f64,
    h_min: f64,
    first_only: bool,
    roots: Vec<(f64, bool)>,
    obs: &'a mut O,
}

impl<O: Observer> Search<'_, O> {
    /// F(t) = field − threshold, with the evaluation shown to the observer.
    fn f(&mut self, t: f64) -> f64 {
        let field = self.blob.field(self.ray.at(t)).0;
        self.obs.blob_sample(t, field);
        field - self.blob.threshold
    }

    /// Bounds of the field on the piece [a, b] by interval arithmetic: f falls with r, so a
    /// bump is largest at the point of the piece closest to its centre and smallest at the
    /// farther end.
    fn field_range(&self, a: f64, b: f64) -> (f64, f64) {
        let (p, d) = (self.ray.origin, self.ray.dir);
        let dd = d.length_squared();
        let (mut lo, mut hi) = (0.0, 0.0);
        for c in &self.blob.components {
            let inv_r2 = 1.0 / (c.radius * c.radius);
            let closest = ((c.center - p).dot(d) / dd).clamp(a, b);
            let near = (p + closest * d - c.center).length_squared() * inv_r2;
            let far = (p + a * d - c.center)
                .length_squared()
                .max((p + b * d - c.center).length_squared())
                * inv_r2;
            let (f_near, f_far) = (
                self.blob.falloff.eval(near).0,
                self.blob.falloff.eval(far).0,
            );
            if c.strength > 0.0 {
                hi += c.strength * f_near;
                lo += c.strength * f_far;
            } else {
                hi += c.strength * f_far;
                lo += c.strength * f_near;
            }
        }
        (lo, hi)
    }

    /// Looks for roots in [a, b] in order; returns true to stop (first root found).
    fn bracket(&mut self, a: f64, b: f64, fa: f64, fb: f64) -> bool {
        let same_sign = (fa > 0.0) == (fb > 0.0);
        if same_sign && fa.abs() + fb.abs() > self.lipschitz * (b - a) {
            return false; // F cannot reach 0 between a and b
        }
        if same_sign {
            let (lo, hi) = self.field_range(a, b);
            let t = self.blob.threshold;
            if hi < t || lo > t {
                return false; // the field stays on one side of the threshold on [a, b]
            }
        }
        if b - a <= self.h_min {
            if !same_sign {
                return self.refine(a, b, fa, fb);
            }
            // A bump narrower than the piece? Look at its middle once.
            let m = 0.5 * (a + b);
            let fm = self.f(m);
            if (fm > 0.0) != (fa > 0.0) {
                return self.refine(a, m, fa, fm) || self.refine(m, b, fm, fb);
            }
            return false;
        }
        let m = 0.5 * (a + b);
        let fm = self.f(m);
        self.bracket(a, m, fa, fm) || self.bracket(m, b, fm, fb)
    }

    // ANCHOR: refine
    /// Newton's method inside the bracket [a, b] (F(a), F(b) of opposite signs), with a
    /// bisection step whenever Newton would leave the bracket or the slope vanishes.
    fn refine(&mut self, mut a: f64, mut b: f64, fa: f64, fb: f64) -> bool {
        self.obs
            .blob_bracket(a, b, fa + self.blob.threshold, fb + self.blob.threshold);
        let entering = fa <= 0.0 && fb > 0.0;
        let rising = fb > fa;
        let mut t = 0.5 * (a + b);
        for _ in 0..60 {
            let p = self.ray.at(t);
            let (field, gradient) = self.blob.field(p);
            let f = field - self.blob.threshold;
            // Shrink the bracket to the side that still holds the sign change.
            if (f > 0.0) == rising {
                b = t;
            } else {
                a = t;
            }
            let slope = gradient.dot(self.ray.dir);
            let newton = t - f / slope;
            let (next, method) = if slope != 0.0 && newton > a && newton < b {
                (newton, "newton")
            } else {
                (0.5 * (a + b), "bisection")
            };
            self.obs.blob_step(BlobStep {
                method,
                t,
                field,
                a,
                b,
            });
            if f == 0.0 {
                break; // t is the root exactly
            }
            let close = (next - t).abs() <= 1e-14 * (1.0 + t.abs());
            t = next;
            if close || b - a <= 1e-15 * (1.0 + t.abs()) {
                break;
            }
        }
        self.obs.blob_root(t, entering);
        self.roots.push((t, entering));
        self.first_only
    }
    // ANCHOR_END: refine
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn max_slopes_bound_the_falloffs() {
        for falloff in [Falloff::Wyvill, Falloff::Gaussian] {
            let worst = (0..=100_000)
                .map(|i| {
                    let r = i as f64 / 100_000.0;
                    (2.0 * r * falloff.eval(r * r).1).abs()
                })
                .fold(0.0, f64::max);
            assert!(worst <= falloff.max_slope(), "{falloff:?}: {worst}");
            assert!(
                worst > 0.95 * falloff.max_slope(),
                "{falloff:?}: bound too loose"
            );
            let (f0, _) = falloff.eval(0.0);
            assert!((f0 - 1.0).abs() < 1e-15);
            assert!(falloff.eval(0.999_999).0.abs() < 1e-5);
        }
        assert!((Falloff::Wyvill.eval(0.25).0 - 0.5).abs() < 1e-15);
    }

    #[test]
    fn gradient_matches_finite_differences() {
        let blob = Blob {
            threshold: 0.5,
            falloff: Falloff::Wyvill,
            components: vec![
                Component {
                    center: DVec3::ZERO,
                    radius: 1.5,
                    strength: 1.0,
                },
                Component {
                    center: DVec3::new(1.0, 0.2, 0.0),
                    radius: 1.0,
                    strength: 0.8,
                },
            ],
        };
        let p = DVec3::new(0.4, 0.3, -0.2);
        let (_, g) = blob.field(p);
        let h = 1e-6;
        for k in 0..3 {
            let mut e = DVec3::ZERO;
            e[k] = h;
            let fd = (blob.field(p + e).0 - blob.field(p - e).0) / (2.0 * h);
            assert!((fd - g[k]).abs() < 1e-7, "axis {k}: {fd} vs {}", g[k]);
        }
    }
}
