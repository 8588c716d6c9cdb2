//! Sixteen lanes, one per ray of a bundle: the rays stored lane by lane ("structure of
//! arrays"), so that one box, or one face, is tested against all of them in one pass
//! ([`super::isa::Wide`] does the arithmetic at the processor's SIMD width). And four lanes,
//! the four boxes of a node, for one ray's slab test.

use super::bvh::{up, WIDTH};

/// Lanes in a bundle: a 4×4 block of pixels.
pub const LANES: usize = 16;

/// Sixteen `f32` lanes.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(64))]
pub struct F32s(pub [f32; LANES]);

/// Sixteen `f64` lanes.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(64))]
pub struct F64s(pub [f64; LANES]);

impl F32s {
    #[inline(always)]
    pub fn splat(x: f32) -> F32s {
        F32s([x; LANES])
    }

    /// Each lane of `t` rounded up to `f32` (the smallest `f32` not below it).
    #[inline(always)]
    pub fn up(t: &[f64; LANES]) -> F32s {
        F32s(t.map(up))
    }
}

/// Counters of the rays in a bundle: adds one to each lane set in `mask`.
#[inline(always)]
pub fn count(counters: &mut [u32; LANES], mask: u32) {
    for (i, c) in counters.iter_mut().enumerate() {
        *c += mask >> i & 1;
    }
}

/// Four `f32` lanes: the four boxes of a node, tested against one ray (or one bundle's
/// bounds) at once. Written lane by lane in a shape the compiler turns into one SSE
/// instruction per operation (`max_or` is `maxps`, which returns its second operand when
/// either is NaN; `le_mask` is `cmpleps` + `movmskps`).
#[derive(Debug, Clone, Copy)]
pub(super) struct FW(pub [f32; WIDTH]);

impl FW {
    #[inline(always)]
    pub fn splat(x: f32) -> FW {
        FW([x; WIDTH])
    }
    #[inline(always)]
    pub fn load(a: &[f32; WIDTH]) -> FW {
        FW(*a)
    }
    /// max(self, other), but `other` where `self` is NaN.
    #[inline(always)]
    pub fn max_or(self, o: FW) -> FW {
        FW(std::array::from_fn(|i| {
            if self.0[i] > o.0[i] {
                self.0[i]
            } else {
                o.0[i]
            }
        }))
    }
    /// min(self, other), but `other` where `self` is NaN.
    #[inline(always)]
    pub fn min_or(self, o: FW) -> FW {
        FW(std::array::from_fn(|i| {
            if self.0[i] < o.0[i] {
                self.0[i]
            } else {
                o.0[i]
            }
        }))
    }
    /// Bit i set where lane i of self ≤ lane i of other (clear for NaN).
    #[inline(always)]
    pub fn le_mask(self, o: FW) -> u32 {
        let m: [u32; WIDTH] = std::array::from_fn(|i| ((self.0[i] <= o.0[i]) as u32) << i);
        m.iter().fold(0, |a, b| a | b)
    }
}

impl std::ops::Sub for FW {
    type Output = FW;
    #[inline(always)]
    fn sub(self, o: FW) -> FW {
        FW(std::array::from_fn(|i| self.0[i] - o.0[i]))
    }
}

impl std::ops::Mul for FW {
    type Output = FW;
    #[inline(always)]
    fn mul(self, o: FW) -> FW {
        FW(std::array::from_fn(|i| self.0[i] * o.0[i]))
    }
}
