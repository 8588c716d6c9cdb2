//! The slab test rays run at every node: four boxes at once in f32 lanes, with the ray's
//! rounding bounded so that it never culls a box the exact f64 ray enters.

use super::{Node, WIDTH};
use crate::accel::lanes::FW;
use crate::math::Ray;

impl Node {
    // ANCHOR: slab
    /// Slab test of the four boxes at once. Returns a bit mask of the lanes the ray may enter
    /// within [t_min, t_max] and, per lane, a t no later than the one at which it enters.
    ///
    /// Per axis the ray enters through the plane it meets first (lo for a positive
    /// direction, hi for a negative one; [`RayBox`] picks them once per ray). The entry is
    /// the largest of the three entries, the exit the smallest of the exits. The test runs in
    /// f32 on a ray rounded to f32 ([`RayBox`]), and the computed entry and exit are moved
    /// apart by a bound on every rounding error: a box the exact f64 ray enters is never
    /// culled, and at worst a box it just misses is kept. (A box entered beyond f32's range,
    /// t > 3.4·10³⁸, counts as missed; scene coordinates are limited far below that.) A ray parallel to a slab and
    /// starting exactly on its plane makes 0·∞ = NaN; `max(t, near)` and `min(t, far)` keep
    /// `near` and `far` when `t` is NaN, which leaves that axis unconstrained.
    ///
    /// `SIGNED` is for a t_min below zero (a line rather than a ray, as CSG's crossings ask):
    /// then an entry or exit may be negative, and the widening must know its sign. With
    /// t_min ≥ 0 the entry is never negative, and a negative exit culls the box either way.
    #[inline(always)]
    pub(in crate::accel) fn enter<const SIGNED: bool>(
        &self,
        r: &RayBox,
        t_min: f32,
        t_max: f32,
    ) -> (u32, [f32; WIDTH]) {
        let slab = |k: usize| {
            let (enter, exit) = (r.neg[k] as usize, !r.neg[k] as usize);
            let inv = FW::splat(r.inv[k]);
            let t_in = (FW::load(&self.planes[enter][k]) - FW::splat(r.origin_in[k])) * inv;
            let t_out = (FW::load(&self.planes[exit][k]) - FW::splat(r.origin_out[k])) * inv;
            (t_in, t_out)
        };
        let ((x_in, x_out), (y_in, y_out), (z_in, z_out)) = (slab(0), slab(1), slab(2));
        let near = z_in.max_or(y_in.max_or(x_in.max_or(FW::splat(t_min))));
        let far = z_out.min_or(y_out.min_or(x_out.min_or(FW::splat(t_max))));
        // Widened by the rounding bound (see [`SHRINK`]): one product each when t ≥ 0.
        let (near, far) = if SIGNED {
            let (s, g) = (FW::splat(SHRINK), FW::splat(GROW));
            ((near * s).min_or(near * g), (far * g).max_or(far * s))
        } else {
            (near * FW::splat(SHRINK), far * FW::splat(GROW))
        };
        (near.le_mask(far), near.0)
    }
    // ANCHOR_END: slab
}

/// A ray as the slab test wants it, in f32: reciprocal direction, which plane (lo = 0,
/// hi = 1) it enters each slab through, and its origin rounded twice, per axis.
///
/// The exact entry (plane − o)·(1/d) is bounded from below by using, for the entry plane,
/// an f32 origin on the side that makes the difference smaller (at or above o when
/// 1/d > 0, at or below when 1/d < 0; see [`bracket`]), and the exact exit from above by
/// taking the other side. What is left
/// are the three f32 roundings of (plane − o′)·(1/d) itself (the subtraction, 1/d, the
/// product): relative errors, covered by widening by [`SHRINK`] and [`GROW`].
#[derive(Debug, Clone, Copy)]
pub(in crate::accel) struct RayBox {
    pub origin_in: [f32; 3],
    pub origin_out: [f32; 3],
    pub inv: [f32; 3],
    pub neg: [bool; 3],
}

/// How far the slab test's entry and exit are moved apart to cover its rounding. Each
/// computed t is the exact (bracketed) one times (1 + θ) with |θ| ≤ γ(3) ≈ 3u (u = 2⁻²⁴, the
/// subtraction, 1/d and the product), and the widening product is rounded once more. So an
/// entry t ≥ 0 times 1 − 5u (rounded) is at most (1 + 3u)(1 − 5u)(1 + u) ≈ 1 − u times the
/// exact one: never later; an exit times 1 + 6u (the next f32 above 1 + 5u) is at least
/// (1 − 3u)(1 + 6u)(1 − u) ≈ 1 + 2u times it: never earlier. For t < 0 the two factors swap
/// roles ([`Node::enter`]'s `SIGNED`).
pub(in crate::accel) const SHRINK: f32 = 1.0 - 5.0 * (f32::EPSILON * 0.5);
pub(in crate::accel) const GROW: f32 = 1.0 + 3.0 * f32::EPSILON;

impl RayBox {
    #[inline(always)]
    pub(in crate::accel) fn new(ray: &Ray) -> RayBox {
        let inv = ray.dir.recip().to_array();
        let o = ray.origin.to_array();
        RayBox::from_axes(|k| (inv[k] as f32, inv[k] < 0.0, bracket(o[k])))
    }

    /// The slab-test form from what `axis(k)` gives for each axis: the reciprocal
    /// direction in `f32`, whether the ray goes towards −k, and the bracketed origin (below,
    /// above). A ray going towards −k enters through the max plane, so its entry subtracts
    /// the origin's upper bound.
    #[inline(always)]
    pub(in crate::accel) fn from_axes(axis: impl Fn(usize) -> (f32, bool, (f32, f32))) -> RayBox {
        let mut r = RayBox {
            origin_in: [0.0; 3],
            origin_out: [0.0; 3],
            inv: [0.0; 3],
            neg: [false; 3],
        };
        for k in 0..3 {
            let (inv, neg, (below, above)) = axis(k);
            r.origin_in[k] = if neg { below } else { above };
            r.origin_out[k] = if neg { above } else { below };
            r.inv[k] = inv;
            r.neg[k] = neg;
        }
        r
    }
}

/// Two f32 values, one no greater and one no less than x (finite, within f32's range),
/// without branches: x rounded to nearest, moved each way by 2⁻²³ of itself (at least one
/// unit in the last place, more than the half unit rounding can be off) plus the smallest
/// normal f32 (for x near zero). Both moves are exact in f32. Looser than [`down`] and [`up`]
/// by about an ulp, and much cheaper: it runs for every ray's origin.
#[inline(always)]
pub(in crate::accel) fn bracket(x: f64) -> (f32, f32) {
    let f = x as f32;
    let m = f.abs() * f32::EPSILON + f32::MIN_POSITIVE;
    (f - m, f + m)
}

/// The largest f32 not above x. (`inline`: the walks call it per ray and per hit, from
/// other modules, which may land in other codegen units.)
#[inline]
pub(in crate::accel) fn down(x: f64) -> f32 {
    let f = x as f32;
    if f as f64 > x {
        f.next_down()
    } else {
        f
    }
}

/// The smallest f32 not below x.
#[inline]
pub(in crate::accel) fn up(x: f64) -> f32 {
    let f = x as f32;
    if (f as f64) < x {
        f.next_up()
    } else {
        f
    }
}
