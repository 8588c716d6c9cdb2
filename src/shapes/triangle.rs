use super::{Candidate, LocalHit, Observer};
use crate::math::Ray;
use glam::{DVec2, DVec3};
use serde::Serialize;

/// A triangle with corners a, b, c, optionally with a normal and texture coordinates per
/// corner (interpolated with the barycentric weights).
#[derive(Debug, Clone, PartialEq)]
pub struct Triangle {
    pub v: [DVec3; 3],
    pub normals: Option<[DVec3; 3]>,
    pub uvs: Option<[DVec2; 3]>,
}

/// Cramer's rule written out: the system's determinant and the solution.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Barycentric {
    pub alpha: f64,
    pub beta: f64,
    pub gamma: f64,
    pub determinant: f64,
    pub t: f64,
}

// ANCHOR: cramer
/// Solves P + t·d = a + β(b − a) + γ(c − a) for (β, γ, t) by Cramer's rule:
/// the columns are e1 = b − a, e2 = c − a, −d, the right-hand side s = P − a.
/// Returns `None` when the determinant is zero (ray parallel to the plane, or a degenerate
/// triangle).
#[inline]
pub fn cramer(v: &[DVec3; 3], ray: &Ray) -> Option<Barycentric> {
    cramer_prepared(&Prepared::new(v), ray)
}

/// The same solve for a triangle whose edges were computed once ([`Prepared`]): meshes keep
/// one per face so a test starts from e1 and e2. Each 3×3 determinant det[x y z] is written
/// as z·(x × y), exactly how glam's `DMat3::determinant` computes it, so both spellings
/// give the same bits.
#[inline]
pub fn cramer_prepared(p: &Prepared, ray: &Ray) -> Option<Barycentric> {
    let s = ray.origin - p.a;
    let m = -ray.dir;
    let n = p.e1.cross(p.e2);
    let determinant = m.dot(n); // det[e1 e2 −d]
    if determinant == 0.0 || !determinant.is_finite() {
        return None;
    }
    let beta = m.dot(s.cross(p.e2)) / determinant; // det[s e2 −d] / det
    let gamma = m.dot(p.e1.cross(s)) / determinant; // det[e1 s −d] / det
    let t = s.dot(n) / determinant; // det[e1 e2 s] / det
    Some(Barycentric {
        alpha: 1.0 - beta - gamma,
        beta,
        gamma,
        determinant,
        t,
    })
}
// ANCHOR_END: cramer

impl Triangle {
    pub fn new(v: [DVec3; 3]) -> Self {
        Triangle {
            v,
            normals: None,
            uvs: None,
        }
    }

    /// The triangle's plane normal (b − a) × (c − a), unit length (counter-clockwise front).
    pub fn geometric_normal(&self) -> DVec3 {
        (self.v[1] - self.v[0])
            .cross(self.v[2] - self.v[0])
            .normalize_or_zero()
    }

    // ANCHOR: inside
    pub fn intersect<O: Observer>(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        obs: &mut O,
    ) -> Option<LocalHit> {
        let b = cramer(&self.v, ray)?;
        obs.barycentric(&b);
        let inside = b.beta >= 0.0 && b.gamma >= 0.0 && b.beta + b.gamma <= 1.0;
        let in_front = b.t >= t_min;
        obs.candidate(Candidate { t: b.t, point: ray.at(b.t), surface: "triangle", on_shape: inside, in_front }, || {
            format!(
                "outside the triangle: needs beta ≥ 0, gamma ≥ 0, beta + gamma ≤ 1 (beta = {}, gamma = {})",
                super::working::short(b.beta),
                super::working::short(b.gamma)
            )
        });
        if !(inside && in_front && b.t <= t_max) {
            return None;
        }
        Some(self.local_hit(ray, &b, 0))
    }
    // ANCHOR_END: inside

    // ANCHOR: interpolate
    pub(crate) fn local_hit(&self, ray: &Ray, b: &Barycentric, index: u32) -> LocalHit {
        interpolated_hit(
            ray,
            b,
            index,
            self.geometric_normal(),
            self.normals,
            self.uvs,
        )
    }
}

/// The surface at a triangle hit: the corners' normals and texture coordinates weighted by
/// (α, β, γ); without per-corner normals, the plane's normal; without texture coordinates,
/// (β, γ). Shared by lone triangles and mesh faces.
pub(crate) fn interpolated_hit(
    ray: &Ray,
    b: &Barycentric,
    index: u32,
    geometric: DVec3,
    normals: Option<[DVec3; 3]>,
    uvs: Option<[DVec2; 3]>,
) -> LocalHit {
    let w = [b.alpha, b.beta, b.gamma];
    let normal = match normals {
        Some(n) => (n[0] * w[0] + n[1] * w[1] + n[2] * w[2])
            .try_normalize()
            .unwrap_or(geometric),
        None => geometric,
    };
    let uv = match uvs {
        Some(t) => t[0] * w[0] + t[1] * w[1] + t[2] * w[2],
        None => DVec2::new(b.beta, b.gamma),
    };
    LocalHit {
        t: b.t,
        point: ray.at(b.t),
        normal,
        uv,
        surface: "triangle",
        barycentric: Some(w),
        index,
    }
    // ANCHOR_END: interpolate
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn cramer_matches_hand_solution() {
        // Triangle in z = 0 with corners (0,0), (1,0), (0,1); ray straight down at (0.25, 0.5).
        let v = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let ray = Ray::new(DVec3::new(0.25, 0.5, 2.0), DVec3::new(0.0, 0.0, -1.0));
        let b = cramer(&v, &ray).unwrap();
        assert!((b.beta - 0.25).abs() < 1e-15 && (b.gamma - 0.5).abs() < 1e-15);
        assert!((b.alpha - 0.25).abs() < 1e-15 && (b.t - 2.0).abs() < 1e-15);
        // The determinant is det[e1, e2, -d] = det[[1,0,0],[0,1,0],[0,0,1]] = 1.
        assert!((b.determinant - 1.0).abs() < 1e-15);
    }

    /// The expanded determinants give exactly the bits of `DMat3::determinant`, and the
    /// early-exit mesh test the same verdict and numbers as the plain solve.
    #[test]
    fn prepared_solve_is_bit_identical() {
        use glam::DMat3;
        let mut rng = crate::math::Rng::new(&[5]);
        let mut p = || DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64()) * 4.0 - 2.0;
        for _ in 0..5000 {
            let v = [p(), p(), p()];
            let ray = Ray::new(p() * 3.0, p());
            let (e1, e2, s, m) = (v[1] - v[0], v[2] - v[0], ray.origin - v[0], -ray.dir);
            let det = DMat3::from_cols(e1, e2, m).determinant();
            let b = cramer(&v, &ray).unwrap();
            assert_eq!(b.determinant.to_bits(), det.to_bits());
            assert_eq!(
                b.beta.to_bits(),
                (DMat3::from_cols(s, e2, m).determinant() / det).to_bits()
            );
            assert_eq!(
                b.gamma.to_bits(),
                (DMat3::from_cols(e1, s, m).determinant() / det).to_bits()
            );
            assert_eq!(
                b.t.to_bits(),
                (DMat3::from_cols(e1, e2, s).determinant() / det).to_bits()
            );
            let inside = b.beta >= 0.0 && b.gamma >= 0.0 && b.beta + b.gamma <= 1.0;
            let expect = (inside && b.t >= 0.0 && b.t <= 5.0).then_some(b);
            assert_eq!(
                cramer_hit_prepared(&Prepared::new(&v), &ray, 0.0, 5.0),
                expect
            );
        }
    }

    /// The mesh test (signs first, no short-circuits) gives exactly what Cramer's rule plus
    /// the inside test give, on the inputs where the order of tests could matter: rays
    /// through corners and along edges (β or γ exactly 0, either sign of zero), rays in the
    /// triangle's plane (det = 0), degenerate triangles, tiny and huge scales, and NaN; and
    /// the plane-first order of the same tests (shadow rays) gives every bit the same.
    #[test]
    fn mesh_test_agrees_with_cramer_on_edge_cases() {
        let mut rng = crate::math::Rng::new(&[6]);
        let mut checked = [0usize; 2];
        for i in 0..20_000 {
            let mut r = || rng.next_f64() * 2.0 - 1.0;
            let scale = [1e-150, 1e-8, 1.0, 1e8, 1e150][i % 5];
            let v = [
                DVec3::new(r(), r(), r()) * scale,
                DVec3::new(r(), r(), r()) * scale,
                DVec3::new(r(), r(), r()) * scale,
            ];
            let v = match i % 7 {
                0 => [v[0], v[1], v[0] * 2.0 - v[1]], // collinear: degenerate
                1 => [v[0], v[0], v[2]],              // two equal corners
                _ => v,
            };
            let target = match i % 4 {
                0 => v[i % 3],            // a corner
                1 => (v[0] + v[1]) * 0.5, // an edge
                _ => v[0] + (v[1] - v[0]) * r().abs() + (v[2] - v[0]) * r().abs() * 0.5,
            };
            let origin = target + DVec3::new(r(), r(), r()) * scale * 3.0;
            let dir = match i % 11 {
                0 => v[1] - v[0], // in the plane (parallel to an edge)
                1 => DVec3::new(f64::NAN, 1.0, 0.0),
                _ => target - origin,
            };
            let ray = Ray { origin, dir };
            let expect = cramer(&v, &ray).filter(|b| {
                b.beta >= 0.0 && b.gamma >= 0.0 && b.beta + b.gamma <= 1.0 && b.t >= 0.0
            });
            let got = cramer_hit_prepared(&Prepared::new(&v), &ray, 0.0, f64::INFINITY);
            assert_eq!(
                got.map(|b| b.t.to_bits()),
                expect.map(|b| b.t.to_bits()),
                "case {i}"
            );
            // The plane-first order (shadow rays) gives the same answer, bit for bit, for
            // any range of t: the whole range, one that may end before the hit (t ≈ 1 here),
            // and one that may start after it.
            let ranges = [
                (0.0, f64::INFINITY),
                (0.0, r().abs() * 2.0),
                (r().abs() * 1.5, 2.0 + r().abs()),
            ];
            for (lo, hi) in ranges {
                let bits = |b: Option<Barycentric>| {
                    b.map(|b| [b.alpha, b.beta, b.gamma, b.determinant, b.t].map(f64::to_bits))
                };
                let p = Prepared::new(&v);
                assert_eq!(
                    bits(cramer_hit_plane_first(&p, &ray, lo, hi)),
                    bits(cramer_hit_prepared(&p, &ray, lo, hi)),
                    "case {i}, t in [{lo}, {hi}]"
                );
            }
            checked[got.is_some() as usize] += 1;
        }
        assert!(checked[0] > 1000 && checked[1] > 1000, "{checked:?}");
    }
}

/// Cramer's rule plus the inside and range tests, for meshes (no observer, no surface record).
#[inline]
pub fn cramer_hit(v: &[DVec3; 3], ray: &Ray, t_min: f64, t_max: f64) -> Option<Barycentric> {
    cramer_hit_prepared(&Prepared::new(v), ray, t_min, t_max)
}

/// [`cramer_hit`] on a prepared face: the same expressions as `cramer_prepared` followed by
/// the inside test, so the verdict and every bit of the result are the same. It is ordered
/// for speed, because most faces a ray is tested against are missed: first the signs of
/// β and γ, read off their numerators without dividing (β = num/det ≥ 0 exactly when num
/// and det do not have opposite signs), then t, then the divisions.
#[inline(always)]
pub fn cramer_hit_prepared(p: &Prepared, ray: &Ray, t_min: f64, t_max: f64) -> Option<Barycentric> {
    let face = FaceFrom::new(p, ray.origin);
    let m = -ray.dir;
    let nums = face.numerators(m);
    if !nums.inside() {
        return None;
    }
    face.solve(&nums, t_min, t_max)
}

/// [`cramer_hit_prepared`] with its tests in another order: the plane first (t within
/// [t_min, t_max], from the normal and the determinant alone), and only then the two cross
/// products and the inside test. Both tests must pass for a hit, and each is computed with
/// the same operations either way, so the answer is the same, bit for bit; only the work
/// differs. It pays for shadow rays, most of whose faces lie behind their origin or beyond
/// the light (a shadow ray leaving a fine mesh's surface meets the planes of the faces
/// around its start at t ≈ 0); a camera ray's first faces are tested against t_max = ∞,
/// which rejects nothing, so closest hits keep the inside test first.
#[inline(always)]
pub fn cramer_hit_plane_first(
    p: &Prepared,
    ray: &Ray,
    t_min: f64,
    t_max: f64,
) -> Option<Barycentric> {
    let s = ray.origin - p.a;
    let n = p.e1.cross(p.e2);
    let m = -ray.dir;
    let t = s.dot(n) / m.dot(n);
    if !(t >= t_min && t <= t_max) {
        return None;
    }
    let face = FaceFrom::with_normal(p, s, n);
    let nums = face.numerators(m);
    if !nums.inside() {
        return None;
    }
    face.solve(&nums, t_min, t_max)
}

// ANCHOR: face_from
/// A face seen from one ray origin P: what Cramer's rule needs that does not depend on the
/// direction. With s = P − a and m = −d, the three determinants are m·(e1 × e2),
/// m·(s × e2) and m·(e1 × s), and t's numerator is s·(e1 × e2): every cross product
/// involves only the face and P. Rays that share an origin (a pinhole camera's) share this
/// part, so a bundle of them computes it once per face and each ray adds three dot
/// products ([`FaceFrom::numerators`]); a single ray computes both halves, in the same
/// order, so the bits are the same either way.
#[derive(Debug, Clone, Copy)]
pub struct FaceFrom {
    /// s = P − a.
    pub s: DVec3,
    /// The normal e1 × e2.
    pub n: DVec3,
    pub s_x_e2: DVec3,
    pub e1_x_s: DVec3,
}

/// The numerators of β and γ over det for one direction (m = −d).
#[derive(Debug, Clone, Copy)]
pub struct Numerators {
    pub determinant: f64,
    pub beta: f64,
    pub gamma: f64,
}

impl FaceFrom {
    #[inline(always)]
    pub fn new(p: &Prepared, origin: DVec3) -> FaceFrom {
        FaceFrom::with_normal(p, origin - p.a, p.e1.cross(p.e2))
    }

    /// [`FaceFrom::new`] given s = P − a and the normal e1 × e2 already computed.
    #[inline(always)]
    fn with_normal(p: &Prepared, s: DVec3, n: DVec3) -> FaceFrom {
        FaceFrom {
            s,
            n,
            s_x_e2: s.cross(p.e2),
            e1_x_s: p.e1.cross(s),
        }
    }

    /// det[e1 e2 −d], det[s e2 −d], det[e1 s −d] for m = −d.
    #[inline(always)]
    pub fn numerators(&self, m: DVec3) -> Numerators {
        Numerators {
            determinant: m.dot(self.n),
            beta: m.dot(self.s_x_e2),
            gamma: m.dot(self.e1_x_s),
        }
    }

    /// The solution once the point is inside: t in [t_min, t_max] and the weights, or None.
    // `!(x >= 0.0)` on purpose: a NaN must fail the test, as it fails `x >= 0.0` in `cramer_hit`.
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    #[inline(always)]
    pub fn solve(&self, nums: &Numerators, t_min: f64, t_max: f64) -> Option<Barycentric> {
        let determinant = nums.determinant;
        let t = self.s.dot(self.n) / determinant;
        if !(t >= t_min && t <= t_max) {
            return None;
        }
        let (beta, gamma) = (nums.beta / determinant, nums.gamma / determinant);
        if !(beta >= 0.0 && gamma >= 0.0 && beta + gamma <= 1.0) {
            return None;
        }
        Some(Barycentric {
            alpha: 1.0 - beta - gamma,
            beta,
            gamma,
            determinant,
            t,
        })
    }
}

impl Numerators {
    /// β ≥ 0 and γ ≥ 0, read off the numerators' signs against the determinant's without
    /// dividing, with `&` and `|` rather than `&&` and `||`: one branch instead of four
    /// data-dependent ones (a zero or non-finite determinant fails both sign tests).
    #[inline(always)]
    pub fn inside(&self) -> bool {
        let d = self.determinant;
        let positive = (d > 0.0) & (d < f64::INFINITY);
        let negative = (d < 0.0) & (d > f64::NEG_INFINITY);
        (positive & (self.beta >= 0.0) & (self.gamma >= 0.0))
            | (negative & (self.beta <= 0.0) & (self.gamma <= 0.0))
    }
}
// ANCHOR_END: face_from

/// A triangle ready for repeated ray tests: corner a and the edges e1 = b − a, e2 = c − a,
/// in f64 (72 bytes). Computing the edges once changes no bit of any result. (Storing
/// e1 × e2 too saves a cross product per test but makes each face 96 bytes; on the
/// 1M-triangle terrain, whose faces do not fit in cache, that was no faster.)
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Prepared {
    pub a: DVec3,
    pub e1: DVec3,
    pub e2: DVec3,
}

impl Prepared {
    #[inline]
    pub fn new(v: &[DVec3; 3]) -> Prepared {
        let (e1, e2) = (v[1] - v[0], v[2] - v[0]);
        Prepared { a: v[0], e1, e2 }
    }
}
