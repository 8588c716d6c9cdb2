//! The portable level: sixteen lanes as plain arrays, each operation a loop the compiler
//! vectorizes as it can (four `f32` lanes per SSE instruction on x86-64).

use super::{Level, Wide};
use crate::accel::lanes::{F32s, F64s, LANES};

/// The [`Wide`] of any processor.
#[derive(Debug, Clone, Copy)]
pub struct Portable;

#[inline(always)]
fn map(a: &[f32; LANES], b: &[f32; LANES], f: impl Fn(f32, f32) -> f32) -> [f32; LANES] {
    let mut out = [0.0; LANES];
    for i in 0..LANES {
        out[i] = f(a[i], b[i]);
    }
    out
}

#[inline(always)]
fn map_d(a: &[f64; LANES], b: &[f64; LANES], f: impl Fn(f64, f64) -> f64) -> [f64; LANES] {
    let mut out = [0.0; LANES];
    for i in 0..LANES {
        out[i] = f(a[i], b[i]);
    }
    out
}

#[inline(always)]
fn bits<T: Copy>(a: &[T; LANES], b: &[T; LANES], f: impl Fn(T, T) -> bool) -> u32 {
    let mut m = 0;
    for i in 0..LANES {
        m |= (f(a[i], b[i]) as u32) << i;
    }
    m
}

impl Wide for Portable {
    type F = [f32; LANES];
    type D = [f64; LANES];
    const LEVEL: Level = Level::Base;

    #[inline(always)]
    fn load(self, a: &F32s) -> Self::F {
        a.0
    }
    #[inline(always)]
    fn store(self, v: Self::F) -> F32s {
        F32s(v)
    }
    #[inline(always)]
    fn splat(self, x: f32) -> Self::F {
        [x; LANES]
    }
    #[inline(always)]
    fn sub(self, a: Self::F, b: Self::F) -> Self::F {
        map(&a, &b, |x, y| x - y)
    }
    #[inline(always)]
    fn mul(self, a: Self::F, b: Self::F) -> Self::F {
        map(&a, &b, |x, y| x * y)
    }
    #[inline(always)]
    fn min(self, a: Self::F, b: Self::F) -> Self::F {
        map(&a, &b, |x, y| if x < y { x } else { y })
    }
    #[inline(always)]
    fn max(self, a: Self::F, b: Self::F) -> Self::F {
        map(&a, &b, |x, y| if x > y { x } else { y })
    }
    #[inline(always)]
    fn le(self, a: Self::F, b: Self::F) -> u32 {
        bits(&a, &b, |x, y| x <= y)
    }
    #[inline(always)]
    fn min_of(self, a: Self::F, mask: u32) -> f32 {
        let mut m = f32::INFINITY;
        for (i, &x) in a.iter().enumerate() {
            if mask >> i & 1 == 1 && x < m {
                m = x;
            }
        }
        m
    }

    #[inline(always)]
    fn load_d(self, a: &F64s) -> Self::D {
        a.0
    }
    #[inline(always)]
    fn store_d(self, v: Self::D) -> F64s {
        F64s(v)
    }
    #[inline(always)]
    fn splat_d(self, x: f64) -> Self::D {
        [x; LANES]
    }
    #[inline(always)]
    fn neg_d(self, a: Self::D) -> Self::D {
        a.map(|x| -x)
    }
    #[inline(always)]
    fn add_d(self, a: Self::D, b: Self::D) -> Self::D {
        map_d(&a, &b, |x, y| x + y)
    }
    #[inline(always)]
    fn mul_d(self, a: Self::D, b: Self::D) -> Self::D {
        map_d(&a, &b, |x, y| x * y)
    }
    #[inline(always)]
    fn lt_d(self, a: Self::D, b: Self::D) -> u32 {
        bits(&a, &b, |x, y| x < y)
    }
    #[inline(always)]
    fn le_d(self, a: Self::D, b: Self::D) -> u32 {
        bits(&a, &b, |x, y| x <= y)
    }
}
