//! AVX2 and AVX-512: the [`Wide`] operations as intrinsics, and the entry points compiled
//! for those instructions. rtlab's `unsafe` code, but for one `madvise` call in
//! [`crate::accel::pages`].
//!
//! Soundness rests on one rule: the tokens [`Avx2`] and [`Avx512`] have private fields, so
//! they exist only inside `run_avx2` and `run_avx512`, which are called only after
//! [`detected`] found every feature they are compiled with. An intrinsic is then a plain
//! function on that processor; each `unsafe` block below is such a call (or an aligned
//! load or store of a 64-byte-aligned array of the right length). The one exception is
//! [`prefetch`], which needs no token: its instruction is part of x86-64 itself.
#![allow(unsafe_code)]

use super::{Kernel, Level, Wide};
use crate::accel::lanes::{F32s, F64s};
use std::arch::x86_64::*;

/// Every feature the AVX-512 entry point is compiled with is present.
fn has_avx512() -> bool {
    is_x86_feature_detected!("avx512f")
        && is_x86_feature_detected!("avx512bw")
        && is_x86_feature_detected!("avx512dq")
        && is_x86_feature_detected!("avx512vl")
        && has_avx2()
}

/// Every feature the AVX2 entry point is compiled with is present.
fn has_avx2() -> bool {
    is_x86_feature_detected!("avx2")
        && is_x86_feature_detected!("fma")
        && is_x86_feature_detected!("bmi1")
        && is_x86_feature_detected!("bmi2")
        && is_x86_feature_detected!("popcnt")
        && is_x86_feature_detected!("lzcnt")
}

pub(super) fn detected() -> Level {
    if has_avx512() {
        Level::Avx512
    } else if has_avx2() {
        Level::Avx2
    } else {
        Level::Base
    }
}

/// Runs `k` compiled for AVX-512. Called only when [`super::level`] is `Avx512`, which it
/// is only when [`detected`] found AVX-512.
pub(super) fn avx512<K: Kernel>(k: K) -> K::Output {
    debug_assert!(has_avx512());
    // SAFETY: every feature `run_avx512` is compiled with is present (see above).
    unsafe { run_avx512(k) }
}

/// Runs `k` compiled for AVX2, when [`super::level`] is `Avx2` (or higher).
pub(super) fn avx2<K: Kernel>(k: K) -> K::Output {
    debug_assert!(has_avx2());
    // SAFETY: as above, for `run_avx2`.
    unsafe { run_avx2(k) }
}

#[target_feature(enable = "avx512f,avx512bw,avx512dq,avx512vl,avx2,fma,bmi1,bmi2,popcnt,lzcnt")]
fn run_avx512<K: Kernel>(k: K) -> K::Output {
    k.run(Avx512(()))
}

#[target_feature(enable = "avx2,fma,bmi1,bmi2,popcnt,lzcnt")]
fn run_avx2<K: Kernel>(k: K) -> K::Output {
    k.run(Avx2(()))
}

/// Every cache line of `x`, prefetched ([`super::prefetch`]): a byte every 64 from its
/// start, and its last byte (`x` need not start on a line, so the steps can miss its last).
#[inline(always)]
pub(super) fn prefetch<T>(x: &[T]) {
    let (p, len) = (x.as_ptr() as *const i8, std::mem::size_of_val(x));
    let lines = (0..len).step_by(64).chain(len.checked_sub(1));
    for at in lines {
        // SAFETY: SSE is part of x86-64 itself, so the instruction is always there; a
        // prefetch reads nothing the program sees and cannot fault, and `at < len` keeps
        // the address inside `x`.
        unsafe { _mm_prefetch::<_MM_HINT_T0>(p.add(at)) }
    }
}

/// Proof that AVX2 is present: sixteen `f32` lanes in two registers, sixteen `f64` in four.
#[derive(Debug, Clone, Copy)]
pub struct Avx2(());

/// Proof that AVX-512 is present: sixteen `f32` lanes in one register, sixteen `f64` in two.
#[derive(Debug, Clone, Copy)]
pub struct Avx512(());

impl Wide for Avx2 {
    type F = [__m256; 2];
    type D = [__m256d; 4];
    const LEVEL: Level = Level::Avx2;

    #[inline(always)]
    fn load(self, a: &F32s) -> Self::F {
        let p = a.0.as_ptr();
        // SAFETY: AVX2 is present (the token); `a` is 64-byte aligned and holds 16 floats.
        unsafe { [_mm256_load_ps(p), _mm256_load_ps(p.add(8))] }
    }
    #[inline(always)]
    fn store(self, v: Self::F) -> F32s {
        let mut out = F32s([0.0; 16]);
        let p = out.0.as_mut_ptr();
        // SAFETY: AVX2 is present; `out` is 64-byte aligned and holds 16 floats.
        unsafe {
            _mm256_store_ps(p, v[0]);
            _mm256_store_ps(p.add(8), v[1]);
        }
        out
    }
    #[inline(always)]
    fn splat(self, x: f32) -> Self::F {
        // SAFETY: AVX2 is present.
        let v = unsafe { _mm256_set1_ps(x) };
        [v, v]
    }
    #[inline(always)]
    fn sub(self, a: Self::F, b: Self::F) -> Self::F {
        // SAFETY: AVX2 is present.
        unsafe { [_mm256_sub_ps(a[0], b[0]), _mm256_sub_ps(a[1], b[1])] }
    }
    #[inline(always)]
    fn mul(self, a: Self::F, b: Self::F) -> Self::F {
        // SAFETY: AVX2 is present.
        unsafe { [_mm256_mul_ps(a[0], b[0]), _mm256_mul_ps(a[1], b[1])] }
    }
    #[inline(always)]
    fn min(self, a: Self::F, b: Self::F) -> Self::F {
        // SAFETY: AVX2 is present.
        unsafe { [_mm256_min_ps(a[0], b[0]), _mm256_min_ps(a[1], b[1])] }
    }
    #[inline(always)]
    fn max(self, a: Self::F, b: Self::F) -> Self::F {
        // SAFETY: AVX2 is present.
        unsafe { [_mm256_max_ps(a[0], b[0]), _mm256_max_ps(a[1], b[1])] }
    }
    #[inline(always)]
    fn le(self, a: Self::F, b: Self::F) -> u32 {
        // SAFETY: AVX2 is present.
        unsafe {
            let lo = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(a[0], b[0])) as u32;
            let hi = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(a[1], b[1])) as u32;
            lo | hi << 8
        }
    }
    #[inline(always)]
    fn min_of(self, a: Self::F, mask: u32) -> f32 {
        // SAFETY: AVX2 is present.
        unsafe {
            let bits = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
            let lo_on = _mm256_and_si256(_mm256_set1_epi32((mask & 0xff) as i32), bits);
            let hi_on = _mm256_and_si256(_mm256_set1_epi32((mask >> 8 & 0xff) as i32), bits);
            let lo_on = _mm256_castsi256_ps(_mm256_cmpeq_epi32(lo_on, bits));
            let hi_on = _mm256_castsi256_ps(_mm256_cmpeq_epi32(hi_on, bits));
            let inf = _mm256_set1_ps(f32::INFINITY);
            let lo = _mm256_blendv_ps(inf, a[0], lo_on);
            let hi = _mm256_blendv_ps(inf, a[1], hi_on);
            let m = _mm256_min_ps(lo, hi);
            let m = _mm_min_ps(_mm256_castps256_ps128(m), _mm256_extractf128_ps::<1>(m));
            let m = _mm_min_ps(m, _mm_movehl_ps(m, m));
            let m = _mm_min_ss(m, _mm_shuffle_ps::<0b01>(m, m));
            _mm_cvtss_f32(m)
        }
    }

    #[inline(always)]
    fn load_d(self, a: &F64s) -> Self::D {
        let p = a.0.as_ptr();
        // SAFETY: AVX2 is present; `a` is 64-byte aligned and holds 16 doubles.
        unsafe {
            [
                _mm256_load_pd(p),
                _mm256_load_pd(p.add(4)),
                _mm256_load_pd(p.add(8)),
                _mm256_load_pd(p.add(12)),
            ]
        }
    }
    #[inline(always)]
    fn store_d(self, v: Self::D) -> F64s {
        let mut out = F64s([0.0; 16]);
        let p = out.0.as_mut_ptr();
        // SAFETY: AVX2 is present; `out` is 64-byte aligned and holds 16 doubles.
        unsafe {
            for (i, &v) in v.iter().enumerate() {
                _mm256_store_pd(p.add(4 * i), v);
            }
        }
        out
    }
    #[inline(always)]
    fn splat_d(self, x: f64) -> Self::D {
        // SAFETY: AVX2 is present.
        let v = unsafe { _mm256_set1_pd(x) };
        [v; 4]
    }
    #[inline(always)]
    fn neg_d(self, a: Self::D) -> Self::D {
        // SAFETY: AVX2 is present. Flipping the sign bit is exact negation.
        unsafe {
            let s = _mm256_set1_pd(-0.0);
            [
                _mm256_xor_pd(a[0], s),
                _mm256_xor_pd(a[1], s),
                _mm256_xor_pd(a[2], s),
                _mm256_xor_pd(a[3], s),
            ]
        }
    }
    #[inline(always)]
    fn add_d(self, a: Self::D, b: Self::D) -> Self::D {
        // SAFETY: AVX2 is present.
        unsafe {
            [
                _mm256_add_pd(a[0], b[0]),
                _mm256_add_pd(a[1], b[1]),
                _mm256_add_pd(a[2], b[2]),
                _mm256_add_pd(a[3], b[3]),
            ]
        }
    }
    #[inline(always)]
    fn mul_d(self, a: Self::D, b: Self::D) -> Self::D {
        // SAFETY: AVX2 is present.
        unsafe {
            [
                _mm256_mul_pd(a[0], b[0]),
                _mm256_mul_pd(a[1], b[1]),
                _mm256_mul_pd(a[2], b[2]),
                _mm256_mul_pd(a[3], b[3]),
            ]
        }
    }
    #[inline(always)]
    fn lt_d(self, a: Self::D, b: Self::D) -> u32 {
        let mut m = 0;
        for i in 0..4 {
            // SAFETY: AVX2 is present.
            let c = unsafe { _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_LT_OQ>(a[i], b[i])) };
            m |= (c as u32) << (4 * i);
        }
        m
    }
    #[inline(always)]
    fn le_d(self, a: Self::D, b: Self::D) -> u32 {
        let mut m = 0;
        for i in 0..4 {
            // SAFETY: AVX2 is present.
            let c = unsafe { _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_LE_OQ>(a[i], b[i])) };
            m |= (c as u32) << (4 * i);
        }
        m
    }
}

impl Wide for Avx512 {
    type F = __m512;
    type D = [__m512d; 2];
    const LEVEL: Level = Level::Avx512;

    #[inline(always)]
    fn load(self, a: &F32s) -> Self::F {
        // SAFETY: AVX-512 is present (the token); `a` is 64-byte aligned, 16 floats.
        unsafe { _mm512_load_ps(a.0.as_ptr()) }
    }
    #[inline(always)]
    fn store(self, v: Self::F) -> F32s {
        let mut out = F32s([0.0; 16]);
        // SAFETY: AVX-512 is present; `out` is 64-byte aligned and holds 16 floats.
        unsafe { _mm512_store_ps(out.0.as_mut_ptr(), v) };
        out
    }
    #[inline(always)]
    fn splat(self, x: f32) -> Self::F {
        // SAFETY: AVX-512 is present.
        unsafe { _mm512_set1_ps(x) }
    }
    #[inline(always)]
    fn sub(self, a: Self::F, b: Self::F) -> Self::F {
        // SAFETY: AVX-512 is present.
        unsafe { _mm512_sub_ps(a, b) }
    }
    #[inline(always)]
    fn mul(self, a: Self::F, b: Self::F) -> Self::F {
        // SAFETY: AVX-512 is present.
        unsafe { _mm512_mul_ps(a, b) }
    }
    #[inline(always)]
    fn min(self, a: Self::F, b: Self::F) -> Self::F {
        // SAFETY: AVX-512 is present.
        unsafe { _mm512_min_ps(a, b) }
    }
    #[inline(always)]
    fn max(self, a: Self::F, b: Self::F) -> Self::F {
        // SAFETY: AVX-512 is present.
        unsafe { _mm512_max_ps(a, b) }
    }
    #[inline(always)]
    fn le(self, a: Self::F, b: Self::F) -> u32 {
        // SAFETY: AVX-512 is present.
        unsafe { _mm512_cmp_ps_mask::<_CMP_LE_OQ>(a, b) as u32 }
    }
    #[inline(always)]
    fn min_of(self, a: Self::F, mask: u32) -> f32 {
        // SAFETY: AVX-512 is present.
        unsafe {
            let inf = _mm512_set1_ps(f32::INFINITY);
            _mm512_reduce_min_ps(_mm512_mask_blend_ps(mask as u16, inf, a))
        }
    }

    #[inline(always)]
    fn load_d(self, a: &F64s) -> Self::D {
        let p = a.0.as_ptr();
        // SAFETY: AVX-512 is present; `a` is 64-byte aligned and holds 16 doubles.
        unsafe { [_mm512_load_pd(p), _mm512_load_pd(p.add(8))] }
    }
    #[inline(always)]
    fn store_d(self, v: Self::D) -> F64s {
        let mut out = F64s([0.0; 16]);
        let p = out.0.as_mut_ptr();
        // SAFETY: AVX-512 is present; `out` is 64-byte aligned and holds 16 doubles.
        unsafe {
            _mm512_store_pd(p, v[0]);
            _mm512_store_pd(p.add(8), v[1]);
        }
        out
    }
    #[inline(always)]
    fn splat_d(self, x: f64) -> Self::D {
        // SAFETY: AVX-512 is present.
        let v = unsafe { _mm512_set1_pd(x) };
        [v, v]
    }
    #[inline(always)]
    fn neg_d(self, a: Self::D) -> Self::D {
        // SAFETY: AVX-512 (with DQ) is present. Flipping the sign bit is exact negation.
        unsafe {
            let s = _mm512_set1_pd(-0.0);
            [_mm512_xor_pd(a[0], s), _mm512_xor_pd(a[1], s)]
        }
    }
    #[inline(always)]
    fn add_d(self, a: Self::D, b: Self::D) -> Self::D {
        // SAFETY: AVX-512 is present.
        unsafe { [_mm512_add_pd(a[0], b[0]), _mm512_add_pd(a[1], b[1])] }
    }
    #[inline(always)]
    fn mul_d(self, a: Self::D, b: Self::D) -> Self::D {
        // SAFETY: AVX-512 is present.
        unsafe { [_mm512_mul_pd(a[0], b[0]), _mm512_mul_pd(a[1], b[1])] }
    }
    #[inline(always)]
    fn lt_d(self, a: Self::D, b: Self::D) -> u32 {
        // SAFETY: AVX-512 is present.
        unsafe {
            let lo = _mm512_cmp_pd_mask::<_CMP_LT_OQ>(a[0], b[0]) as u32;
            let hi = _mm512_cmp_pd_mask::<_CMP_LT_OQ>(a[1], b[1]) as u32;
            lo | hi << 8
        }
    }
    #[inline(always)]
    fn le_d(self, a: Self::D, b: Self::D) -> u32 {
        // SAFETY: AVX-512 is present.
        unsafe {
            let lo = _mm512_cmp_pd_mask::<_CMP_LE_OQ>(a[0], b[0]) as u32;
            let hi = _mm512_cmp_pd_mask::<_CMP_LE_OQ>(a[1], b[1]) as u32;
            lo | hi << 8
        }
    }
}
