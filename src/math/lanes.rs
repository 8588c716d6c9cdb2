//! Numbers side by side: one `f64`, or a block of them worked on lane by lane ([`Lanes`]),
//! and 2D and 3D vectors of either ([`V2`], [`V3`]). Code written once over [`Real`] runs on
//! one sample or on a bundle's worth at a time, and since every operation is the same IEEE
//! operation in every lane, in the same order, lane i's bits are exactly what the scalar
//! code gives for input i. The vectors do glam's `DVec2`/`DVec3` arithmetic in glam's order
//! (its dot product, its `normalize`, its `transform_point3`), so code moved from glam onto
//! them keeps its bits too. Ray generation runs on them ([`crate::camera::Camera::generate_in`]):
//! sixteen camera rays made side by side overlap their divisions and square roots instead of
//! waiting on each in turn.

use glam::{DMat4, DVec2, DVec3};
use std::ops::{Add, Div, Mul, MulAssign, Neg, Sub};

/// A number the generic code runs on: `f64`, or [`Lanes`] of them. Operations with a plain
/// `f64` apply it to every lane (with the `f64` on the left too: code generic over `T`
/// states that as `where f64: Mul<T, Output = T>`, and so on).
pub trait Real:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Add<f64, Output = Self>
    + Sub<f64, Output = Self>
    + Mul<f64, Output = Self>
    + Div<f64, Output = Self>
    + MulAssign<f64>
{
    /// `x` in every lane.
    fn splat(x: f64) -> Self;
    fn sqrt(self) -> Self;
    fn cos(self) -> Self;
    fn sin(self) -> Self;
}

impl Real for f64 {
    #[inline(always)]
    fn splat(x: f64) -> f64 {
        x
    }
    #[inline(always)]
    fn sqrt(self) -> f64 {
        f64::sqrt(self)
    }
    #[inline(always)]
    fn cos(self) -> f64 {
        f64::cos(self)
    }
    #[inline(always)]
    fn sin(self) -> f64 {
        f64::sin(self)
    }
}

/// `N` numbers worked on together, lane by lane (the compiler turns each operation into
/// vector instructions).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lanes<const N: usize>(pub [f64; N]);

impl<const N: usize> Lanes<N> {
    /// Lane i is `f(i)`.
    #[inline(always)]
    pub fn from_fn(f: impl FnMut(usize) -> f64) -> Self {
        Lanes(std::array::from_fn(f))
    }

    #[inline(always)]
    fn map(self, f: impl Fn(f64) -> f64) -> Self {
        Lanes(self.0.map(f))
    }

    #[inline(always)]
    fn zip(self, o: Self, f: impl Fn(f64, f64) -> f64) -> Self {
        Lanes(std::array::from_fn(|i| f(self.0[i], o.0[i])))
    }
}

/// The four operations, lane by lane, and with a number in every lane on either side.
macro_rules! lane_ops {
    ($($tr:ident $f:ident $op:tt),*) => {$(
        impl<const N: usize> $tr for Lanes<N> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: Self) -> Self {
                self.zip(o, |a, b| a $op b)
            }
        }
        impl<const N: usize> $tr<f64> for Lanes<N> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: f64) -> Self {
                self.map(|a| a $op o)
            }
        }
        impl<const N: usize> $tr<Lanes<N>> for f64 {
            type Output = Lanes<N>;
            #[inline(always)]
            fn $f(self, o: Lanes<N>) -> Lanes<N> {
                o.map(|b| self $op b)
            }
        }
    )*};
}
lane_ops!(Add add +, Sub sub -, Mul mul *, Div div /);

impl<const N: usize> MulAssign<f64> for Lanes<N> {
    #[inline(always)]
    fn mul_assign(&mut self, o: f64) {
        *self = *self * o;
    }
}

impl<const N: usize> Neg for Lanes<N> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        self.map(|a| -a)
    }
}

impl<const N: usize> Real for Lanes<N> {
    #[inline(always)]
    fn splat(x: f64) -> Self {
        Lanes([x; N])
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        self.map(f64::sqrt)
    }
    #[inline(always)]
    fn cos(self) -> Self {
        self.map(f64::cos)
    }
    #[inline(always)]
    fn sin(self) -> Self {
        self.map(f64::sin)
    }
}

/// A 2D vector of [`Real`]s (glam's `DVec2`, lane by lane).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct V2<T> {
    pub x: T,
    pub y: T,
}

/// A 3D vector of [`Real`]s (glam's `DVec3`, lane by lane).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct V3<T> {
    pub x: T,
    pub y: T,
    pub z: T,
}

impl<T: Real> V2<T> {
    /// `v` in every lane.
    #[inline(always)]
    pub fn splat(v: DVec2) -> Self {
        V2 {
            x: T::splat(v.x),
            y: T::splat(v.y),
        }
    }
}

impl V2<f64> {
    #[inline(always)]
    pub fn glam(self) -> DVec2 {
        DVec2::new(self.x, self.y)
    }
}

impl<T: Real> V3<T> {
    /// `v` in every lane.
    #[inline(always)]
    pub fn splat(v: DVec3) -> Self {
        V3 {
            x: T::splat(v.x),
            y: T::splat(v.y),
            z: T::splat(v.z),
        }
    }

    /// glam's `dot`: (x·x′ + y·y′) + z·z′.
    #[inline(always)]
    pub fn dot(self, o: Self) -> T {
        (self.x * o.x) + (self.y * o.y) + (self.z * o.z)
    }

    /// glam's `normalize`: times 1 / √(v·v).
    #[inline(always)]
    pub fn normalize(self) -> Self {
        let recip = T::splat(1.0) / self.dot(self).sqrt();
        self * recip
    }
}

/// A 4×4 matrix applied to the points of [`V3`]s.
pub trait TransformPoint<T> {
    /// glam's `DMat4::transform_point3` of the point `p`: x·col0, then col1·y + that,
    /// col2·z + that, col3 + that.
    fn transform_point(&self, p: V3<T>) -> V3<T>;
}

impl<T: Real> TransformPoint<T> for DMat4 {
    #[inline(always)]
    fn transform_point(&self, p: V3<T>) -> V3<T> {
        let (c0, c1, c2, c3) = (self.x_axis, self.y_axis, self.z_axis, self.w_axis);
        // A function, not a closure: closures are not inlined on demand, and this one ran as
        // three calls per sixteen camera rays.
        #[inline(always)]
        fn row<T: Real>(p: &V3<T>, a: f64, b: f64, c: f64, d: f64) -> T {
            let r = p.x * a;
            let r = p.y * b + r;
            let r = p.z * c + r;
            r + d
        }
        V3 {
            x: row(&p, c0.x, c1.x, c2.x, c3.x),
            y: row(&p, c0.y, c1.y, c2.y, c3.y),
            z: row(&p, c0.z, c1.z, c2.z, c3.z),
        }
    }
}

impl V3<f64> {
    #[inline(always)]
    pub fn glam(self) -> DVec3 {
        DVec3::new(self.x, self.y, self.z)
    }
}

impl<const N: usize> V3<Lanes<N>> {
    /// Lane `i` as a glam vector.
    #[inline(always)]
    pub fn lane(&self, i: usize) -> DVec3 {
        DVec3::new(self.x.0[i], self.y.0[i], self.z.0[i])
    }
}

/// Moved by the same offset in every lane.
impl<T: Real> Sub<DVec2> for V2<T> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: DVec2) -> Self {
        V2 {
            x: self.x - o.x,
            y: self.y - o.y,
        }
    }
}

/// Sum and difference, component by component.
macro_rules! v3_ops {
    ($($tr:ident $f:ident $op:tt),*) => {$(
        impl<T: Real> $tr for V3<T> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: Self) -> Self {
                V3 {
                    x: self.x $op o.x,
                    y: self.y $op o.y,
                    z: self.z $op o.z,
                }
            }
        }
    )*};
}
v3_ops!(Add add +, Sub sub -);

impl<T: Real> Neg for V3<T> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        V3 {
            x: -self.x,
            y: -self.y,
            z: -self.z,
        }
    }
}

/// Scaled by one number (per lane).
impl<T: Real> Mul<T> for V3<T> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, s: T) -> Self {
        V3 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The vectors give glam's bits: the same dot, normalize and transform_point3, scalar
    /// and in every lane.
    #[test]
    fn vectors_are_glams_bit_for_bit() {
        let m = DMat4::from_cols_array(&[
            0.3, -1.7, 2.2, 0.0, 1e-3, 0.9, -0.4, 0.0, 5.5, 0.125, -3.3, 0.0, 0.7, -2.9, 11.0, 1.0,
        ]);
        let mut rng = crate::math::Rng::new(&[7, 1230]);
        let mut r = || (rng.next_f64() - 0.5) * 37.0;
        let points: Vec<DVec3> = (0..64).map(|_| DVec3::new(r(), r(), r())).collect();
        for chunk in points.chunks(16) {
            let lanes: V3<Lanes<16>> = V3 {
                x: Lanes::from_fn(|i| chunk[i].x),
                y: Lanes::from_fn(|i| chunk[i].y),
                z: Lanes::from_fn(|i| chunk[i].z),
            };
            let moved = m.transform_point(lanes);
            let unit = moved.normalize();
            let dots = lanes.dot(moved);
            let bits = |v: DVec3| v.to_array().map(f64::to_bits);
            for (i, p) in chunk.iter().enumerate() {
                let want = m.transform_point3(*p);
                let scalar = m.transform_point(V3::<f64>::splat(*p));
                assert_eq!(bits(scalar.glam()), bits(want));
                assert_eq!(bits(moved.lane(i)), bits(want));
                assert_eq!(bits(unit.lane(i)), bits(want.normalize()));
                assert_eq!(dots.0[i].to_bits(), p.dot(want).to_bits());
            }
        }
    }
}
