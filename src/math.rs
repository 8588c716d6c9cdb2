//! Rays and transforms: the two pieces of linear algebra every other module shares.

pub mod lanes;

use crate::mistakes::{Mistake, Mistakes};
use glam::{DMat3, DMat4, DVec3};

/// A ray `P + t·d`. The direction is *not* assumed to be unit length: object-space rays keep
/// the same parameter t as their world-space parent because the direction is transformed
/// without renormalising.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    pub origin: DVec3,
    pub dir: DVec3,
}

impl Ray {
    pub fn new(origin: DVec3, dir: DVec3) -> Self {
        Ray { origin, dir }
    }
    /// The point at parameter t.
    #[inline]
    pub fn at(&self, t: f64) -> DVec3 {
        self.origin + self.dir * t
    }
}

// ANCHOR: transform
/// An object's placement: `world_from_object` and the matrices derived from it once, at load.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transform {
    pub world_from_object: DMat4,
    pub object_from_world: DMat4,
    /// Inverse transpose of the upper 3x3 of `world_from_object`: carries normals to world space.
    pub normal_to_world: DMat3,
    pub identity: bool,
}

/// Whether `m`'s linear part (its upper 3×3, what the ray directions go through) has an
/// inverse worth the name, whatever its size: every axis (column) finite and at least
/// 10⁻¹² of the longest, and the axes far from lying in one plane (the determinant more
/// than 10⁻¹² of the product of their lengths, Hadamard's bound, which it reaches when
/// they are at right angles). So a uniform scale of 10⁻⁶ (a mesh modelled in the wrong
/// unit) is as good as 1, and so is a thin rod (1, 10⁻⁶, 10⁻⁶); an axis flattened to
/// 10⁻¹³ of the longest, a zero scale, or two axes along one line, is not.
pub fn invertible(m: &DMat4) -> bool {
    let linear = DMat3::from_mat4(*m);
    let lengths = [linear.x_axis, linear.y_axis, linear.z_axis].map(|a| a.length());
    let longest = lengths[0].max(lengths[1]).max(lengths[2]);
    let shortest = lengths[0].min(lengths[1]).min(lengths[2]);
    let det = linear.determinant();
    det.is_finite()
        && longest.is_finite()
        && shortest >= 1e-12 * longest
        && det.abs() > 1e-12 * lengths.iter().product::<f64>()
}

impl Transform {
    pub const IDENTITY: Transform = Transform {
        world_from_object: DMat4::IDENTITY,
        object_from_world: DMat4::IDENTITY,
        normal_to_world: DMat3::IDENTITY,
        identity: true,
    };

    /// Builds a transform. Returns `None` when the matrix cannot be inverted (a zero scale).
    pub fn new(world_from_object: DMat4) -> Option<Transform> {
        if !invertible(&world_from_object) {
            return None;
        }
        let object_from_world = world_from_object.inverse();
        // A matrix whose last row is not (0, 0, 0, 1) may still have no inverse.
        if !object_from_world.is_finite() {
            return None;
        }
        let normal_to_world = DMat3::from_mat4(object_from_world).transpose();
        Some(Transform {
            world_from_object,
            object_from_world,
            normal_to_world,
            identity: world_from_object == DMat4::IDENTITY,
        })
    }

    /// The world ray in object space. The direction is not renormalised, so t is shared.
    /// (`inline(always)`: every ray of every object test passes here; left to the compiler,
    /// whether it was inlined changed with how the crate fell into codegen units.)
    #[inline(always)]
    pub fn ray_to_object(&self, ray: &Ray) -> Ray {
        if self.identity {
            return *ray;
        }
        Ray {
            origin: self.object_from_world.transform_point3(ray.origin),
            dir: self.object_from_world.transform_vector3(ray.dir),
        }
    }

    /// An object-space normal in world space: through the inverse transpose, then normalised.
    #[inline]
    pub fn normal_to_world(&self, n: DVec3) -> DVec3 {
        if self.identity {
            return n.normalize();
        }
        (self.normal_to_world * n).normalize()
    }

    /// [`Transform::normal_to_world`] under the catalogue's normal mistakes:
    /// `normal-object-matrix` uses the object's matrix M instead of (M⁻¹)ᵀ, and
    /// `normal-not-normalized` skips the final normalisation.
    #[inline]
    pub fn normal_to_world_as(&self, n: DVec3, mistakes: Mistakes) -> DVec3 {
        if mistakes.is_empty() {
            return self.normal_to_world(n);
        }
        let m = if mistakes.has(Mistake::NormalObjectMatrix) {
            DMat3::from_mat4(self.world_from_object)
        } else {
            self.normal_to_world
        };
        let n = m * n;
        if mistakes.has(Mistake::NormalNotNormalized) {
            n
        } else {
            n.normalize()
        }
    }

    pub fn point_to_world(&self, p: DVec3) -> DVec3 {
        self.world_from_object.transform_point3(p)
    }
    pub fn point_to_object(&self, p: DVec3) -> DVec3 {
        self.object_from_world.transform_point3(p)
    }
    pub fn vector_to_object(&self, v: DVec3) -> DVec3 {
        self.object_from_world.transform_vector3(v)
    }
}
// ANCHOR_END: transform

/// Counter-based random numbers: a sample's stream depends only on the key it was created
/// with (seed, pixel, sample index, purpose), never on thread scheduling.
#[derive(Debug, Clone)]
pub struct Rng(Stream);

#[derive(Debug, Clone)]
enum Stream {
    /// A key not hashed yet ([`Rng::keyed`]): hashed at the first draw.
    Keyed([u64; 4]),
    Running(u64),
}

impl Rng {
    pub fn new(key: &[u64]) -> Rng {
        Rng(Stream::Running(hash(key)))
    }

    /// [`Rng::new`] of a four-word key, hashed only if a number is ever drawn: a camera
    /// ray's stream (seed, pixel, sample index) is made for every sample, and drawn from
    /// only under depth of field or area lights.
    #[inline]
    pub fn keyed(key: [u64; 4]) -> Rng {
        Rng(Stream::Keyed(key))
    }

    /// A uniform number in [0, 1).
    pub fn next_f64(&mut self) -> f64 {
        let state = match self.0 {
            Stream::Running(s) => s,
            Stream::Keyed(key) => hash(&key),
        };
        let state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        self.0 = Stream::Running(state);
        (splitmix(state) >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// A key's starting state.
fn hash(key: &[u64]) -> u64 {
    let mut h = 0x9E37_79B9_7F4A_7C15u64;
    for &k in key {
        h = splitmix(h ^ k);
    }
    h
}

fn splitmix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn rng_is_keyed_and_uniform() {
        let a: Vec<f64> = (0..4)
            .map({
                let mut r = Rng::new(&[1, 2, 3]);
                move |_| r.next_f64()
            })
            .collect();
        let b: Vec<f64> = (0..4)
            .map({
                let mut r = Rng::new(&[1, 2, 3]);
                move |_| r.next_f64()
            })
            .collect();
        assert_eq!(a, b);
        // A key hashed late draws what it would have drawn hashed at once.
        let mut late = Rng::keyed([1, 2, 3, 4]);
        let mut now = Rng::new(&[1, 2, 3, 4]);
        let (l, n): (Vec<f64>, Vec<f64>) =
            (0..4).map(|_| (late.next_f64(), now.next_f64())).unzip();
        assert_eq!(l, n);
        let mut r = Rng::new(&[7]);
        let mean = (0..10000).map(|_| r.next_f64()).sum::<f64>() / 10000.0;
        assert!((mean - 0.5).abs() < 0.02);
    }
    #[test]
    fn normals_use_inverse_transpose() {
        // Scale x by 2: the sphere's normal at (1,1,0)/√2 must tilt toward y in world space.
        let t = Transform::new(DMat4::from_scale(DVec3::new(2.0, 1.0, 1.0))).unwrap();
        let n = t.normal_to_world(DVec3::new(1.0, 1.0, 0.0));
        let expect = DVec3::new(0.5, 1.0, 0.0).normalize();
        assert!((n - expect).length() < 1e-12);
        assert!(Transform::new(DMat4::from_scale(DVec3::new(0.0, 1.0, 1.0))).is_none());
    }

    /// Invertibility does not depend on size: a uniform scale of 10⁻⁶ (a determinant of
    /// 10⁻¹⁸) or 10⁶ is fine, far from the origin too, and so are thin rods; an axis 10⁻¹³
    /// of the longest (at either size), a zero, a NaN, or two equal columns is not.
    #[test]
    fn invertible_whatever_the_scale() {
        use super::invertible;
        let s = |x: f64, y: f64, z: f64| DMat4::from_scale(DVec3::new(x, y, z));
        assert!(invertible(&s(1e-6, 1e-6, 1e-6)));
        assert!(invertible(&s(1e6, 1e6, 1e6)));
        assert!(invertible(&s(1.0, 1e-6, 1.0)));
        let far = DMat4::from_translation(DVec3::splat(1e6)) * s(1e-4, 1e-4, 1e-4);
        assert!(invertible(&far));
        assert!(Transform::new(s(1e-6, 1e-6, 1e-6)).is_some());
        assert!(invertible(&s(1.0, 1e-6, 1e-6)), "a thin rod");
        assert!(invertible(&s(1000.0, 1e-3, 1e-3)), "a long thin rod");
        assert!(!invertible(&s(1.0, 1e-13, 1.0)));
        assert!(!invertible(&s(1e-6, 1e-19, 1e-6)));
        let huge = DMat4::from_translation(DVec3::splat(1e300)) * s(1e10, 1e10, 1e10);
        assert!(
            invertible(&huge),
            "a translation does not enter the linear part"
        );
        assert!(!invertible(&s(1.0, 0.0, 1.0)));
        assert!(!invertible(&s(1.0, f64::NAN, 1.0)));
        let flat = DMat4::from_cols(
            glam::DVec4::X,
            glam::DVec4::X,
            glam::DVec4::Z,
            glam::DVec4::W,
        );
        assert!(!invertible(&flat));
        let mut no_w = DMat4::IDENTITY;
        no_w.w_axis = glam::DVec4::ZERO;
        assert!(Transform::new(no_w).is_none(), "a last row of zeros");
    }
}
