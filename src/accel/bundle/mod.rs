//! Bundle traversal (beam tracing's modern form): up to [`BUNDLE`] neighbouring rays walk a
//! BVH together.
//!
//! The rays are stored lane by lane ([`RayBundle`], sixteen lanes). At each node the bundle
//! opens, two tests decide which of its four children to go on with:
//!
//! 1. the **interval test** tests the four boxes against the whole bundle at once: its range
//!    of origins and of reciprocal directions per axis, so one test bounds every ray's entry
//!    and exit, and a box it rejects is missed by every ray;
//! 2. each box that passes gets the **lane test**: the box against all sixteen rays in one
//!    pass over the lanes, which gives exactly the verdict each ray's own slab test gives.
//!
//! A child goes on the stack with the rays that enter it and the earliest of their entry t's
//! (from the lane test), so rays that have since found a closer hit drop out when it comes
//! off. A leaf's primitives are tested against the rays that reached it by the caller's exact
//! f64 routine ([`BundleLeaf`]); which primitive a ray hits, and at what t, is exactly what
//! the single-ray walk ([`Bvh::closest`](super::bvh::Bvh::closest)) finds, as long as the
//! caller breaks ties the same way (closest t, then lowest slot: order-free). When only one
//! ray is left in a subtree ([`FEW`]) the bundle stops paying, and that ray walks the
//! subtree alone with the single-ray walk; a bundle whose rays point different ways along an
//! axis (the interval test needs one sign) walks ray by ray from the root. The walks
//! themselves are in [`walk`].

use super::bvh::{bracket, Node, RayBox, GROW, SHRINK};
use super::isa::Wide;
use super::lanes::{F32s, F64s, FW, LANES};
use crate::math::Ray;

/// Rays in a bundle: a 4×4 block of pixels (camera rays of one sample index). (Eight and
/// thirty-two were tried on an AVX2 processor: eight ran the terrain's bundles at 0.85;
/// thirty-two the bare bundles at 1.00 to 1.12 but the bundled render at 0.90 to 0.96.)
pub const BUNDLE: usize = LANES;

/// A subtree that no more than this many of the bundle's rays enter is walked by each of them
/// alone: a lone ray walks faster by itself. Two rays still gain from walking together: with
/// AVX-512 a box test of sixteen `f32` lanes is one instruction a step (a face test's
/// sixteen `f64` lanes two), and two rays from one point share each face's set-up
/// ([`crate::shapes::FaceFrom`]). (Timed on the terrain on an AVX-512 Xeon against two,
/// book appendix "A calm morning on the Xeon": the bundled render at 1.03 (eight pairs,
/// every one faster), the camera bundles at 1.02, the shadow bundles at about 1.07;
/// capped to AVX2 on the same processor, 1.00 and 0.98. Earlier, on an AVX2 processor,
/// one ran at 0.96 of two and three and four at 0.85 and 0.86; on the Xeon three and four
/// could not be told from two.)
pub const FEW: u32 = 1;

/// What a bundle traversal did: nodes opened (once per bundle), and per ray the nodes it
/// was slab-tested at (what the single-ray walk would call the nodes it visited; counted by
/// the closest-hit walk, for `--stats` and the `cost` AOV, which count camera rays).
#[derive(Debug, Clone, Copy, Default)]
pub struct BundleWork {
    pub opened: u32,
    pub ray_nodes: [u32; BUNDLE],
}

// ANCHOR: ray_bundle
/// Up to sixteen rays prepared for the walk, lane by lane: each ray's reciprocal direction
/// and bracketed origin in `f32` (what its own slab test uses, `RayBox`), and per axis the
/// bundle's bounds for the interval test. Lanes past the last ray repeat it; `all` says
/// which lanes hold rays.
#[derive(Debug, Clone)]
pub struct RayBundle<'r> {
    pub rays: &'r [Ray],
    pub all: u32,
    /// The directions in `f64`, axis by axis (for the faces' exact test).
    pub dir: [F64s; 3],
    /// Every ray starts at the same point (camera rays of a pinhole camera): its bracket is
    /// then `shared_below`/`shared_above`, and the lane test subtracts one number.
    pub shared_origin: bool,
    inv: [F32s; 3],
    /// Each ray's origin rounded down and up to `f32` ([`super::bvh::bracket`]), per axis.
    below: [F32s; 3],
    above: [F32s; 3],
    shared_below: [f32; 3],
    shared_above: [f32; 3],
    /// Per axis: does every ray point towards −axis (they all agree, or `coherent` is false)?
    neg: [bool; 3],
    /// The directions agree in sign on every axis: the bundle can walk together.
    pub coherent: bool,
    /// Per axis, the interval test's bounds; `None` where some reciprocal direction (or,
    /// for rays from different points, some origin's bracket) is not finite: that axis then
    /// constrains nothing.
    interval: [Option<Interval>; 3],
}

/// The bundle along one axis: the extreme bracketed origins on the entry and exit sides,
/// and the range of the reciprocal directions (all of one sign).
#[derive(Debug, Clone, Copy)]
struct Interval {
    origin_in: f32,
    origin_out: f32,
    inv_lo: f32,
    inv_hi: f32,
}
// ANCHOR_END: ray_bundle

/// Every lane of a bundle.
const EVERY: u32 = u32::MAX >> (32 - LANES);

/// Bit i set where lane i is below zero (−0 is not, −∞ is, NaN is not).
#[inline(always)]
fn below_zero<W: Wide>(w: W, v: &F32s) -> u32 {
    let x = w.load(v);
    // x < 0 is "not 0 ≤ x", but for NaN, which is not even x ≤ x.
    !w.le(w.splat(0.0), x) & w.le(x, x)
}

/// The smallest and the largest lane, when every lane is finite (`None` if one is ±∞ or
/// NaN: an axis the interval test then leaves out).
#[inline(always)]
fn finite_range<W: Wide>(w: W, v: &F32s) -> Option<(f32, f32)> {
    let (x, zero) = (w.load(v), w.splat(0.0));
    // x − x is 0 for a finite lane and NaN for ±∞ and NaN, which fail every comparison.
    if w.le(w.sub(x, x), zero) != EVERY {
        return None;
    }
    // The largest is minus the smallest of 0 − x (exact for finite x; a zero may come back
    // with the other sign, and ±0 compare equal in every test the bounds go into).
    Some((w.min_of(x, EVERY), -w.min_of(w.sub(zero, x), EVERY)))
}

impl<'r> RayBundle<'r> {
    /// Prepares 1 to [`BUNDLE`] rays (with `w`'s lanes: a bundle is prepared for every
    /// sixteen rays it walks, a miss of the whole tree included).
    #[inline(always)]
    pub fn new<W: Wide>(w: W, rays: &'r [Ray]) -> RayBundle<'r> {
        let n = rays.len();
        assert!(
            (1..=BUNDLE).contains(&n),
            "a bundle holds 1 to {BUNDLE} rays, not {n}"
        );
        let all = u32::MAX >> (32 - n);
        let mut dir = [F64s([0.0; LANES]); 3];
        let origin = rays[0].origin;
        let mut shared_origin = true;
        for (i, ray) in rays.iter().enumerate() {
            // `&`, not `&&`: no branch per coordinate.
            let o = ray.origin;
            shared_origin &= (o.x == origin.x) & (o.y == origin.y) & (o.z == origin.z);
            dir[0].0[i] = ray.dir.x;
            dir[1].0[i] = ray.dir.y;
            dir[2].0[i] = ray.dir.z;
        }
        for d in &mut dir {
            let last = d.0[n - 1];
            d.0[n..].fill(last);
        }
        // As `RayBox::new`: 1/d in f64, then rounded to f32.
        let mut inv = [F32s([0.0; LANES]); 3];
        for k in 0..3 {
            for i in 0..LANES {
                inv[k].0[i] = (1.0 / dir[k].0[i]) as f32;
            }
        }
        // Lanes past the last ray repeat it, so every lane agrees or the bundle is mixed.
        let (mut coherent, mut neg) = (true, [false; 3]);
        let o = origin.to_array();
        let (mut shared_below, mut shared_above) = ([0.0; 3], [0.0; 3]);
        let (mut below, mut above) = ([F32s::splat(0.0); 3], [F32s::splat(0.0); 3]);
        for k in 0..3 {
            let negs = below_zero(w, &inv[k]);
            coherent &= negs == 0 || negs == EVERY;
            neg[k] = negs != 0;
            (shared_below[k], shared_above[k]) = bracket(o[k]);
            below[k] = F32s::splat(shared_below[k]);
            above[k] = F32s::splat(shared_above[k]);
        }
        if !shared_origin {
            for i in 0..LANES {
                let p = rays[i.min(n - 1)].origin.to_array();
                for k in 0..3 {
                    (below[k].0[i], above[k].0[i]) = bracket(p[k]);
                }
            }
        }
        let mut interval = [None; 3];
        for k in 0..3 {
            let Some((inv_lo, inv_hi)) = finite_range(w, &inv[k]).filter(|_| coherent) else {
                continue;
            };
            let (below_lo, above_hi) = if shared_origin {
                (shared_below[k], shared_above[k])
            } else {
                match (finite_range(w, &below[k]), finite_range(w, &above[k])) {
                    (Some(b), Some(a)) => (b.0, a.1),
                    _ => continue,
                }
            };
            // The entry bound wants the origin that makes (plane − o)·(1/d) smallest: the
            // largest o for a positive direction (which enters with o rounded up), the
            // smallest for a negative one (o rounded down); the exit bound the opposite.
            interval[k] = Some(Interval {
                origin_in: if neg[k] { below_lo } else { above_hi },
                origin_out: if neg[k] { above_hi } else { below_lo },
                inv_lo,
                inv_hi,
            });
        }
        RayBundle {
            rays,
            all,
            dir,
            shared_origin,
            inv,
            below,
            above,
            shared_below,
            shared_above,
            neg,
            coherent,
            interval,
        }
    }

    /// Ray i's own slab-test form (as [`RayBox::new`] gives it).
    #[inline(always)]
    fn ray_box(&self, i: usize) -> RayBox {
        RayBox::from_axes(|k| {
            let inv = self.inv[k].0[i];
            (inv, inv < 0.0, (self.below[k].0[i], self.above[k].0[i]))
        })
    }

    // ANCHOR: interval_test
    /// The interval test: the node's four boxes against the whole bundle. Returns the child
    /// slots (bit k: the box in slot k) some ray may enter: a box left out is missed by
    /// every ray.
    ///
    /// Along an axis with a positive direction a ray enters at (lo − o)·(1/d). Over the
    /// bundle, (lo − o) is smallest for the largest origin, and the product of that fixed
    /// difference with 1/d is smallest at one end of the range of 1/d; rounding to nearest
    /// is monotonic, so the same `f32` operations on these bounds give a t no later than the
    /// one each ray's own test computes, and never cull a box a ray's own test keeps.
    /// (`seen` hears each axis's entry and exit bounds, `Some(axis)`, then the bundle's,
    /// `None`, widened as the verdict compares them: for `rtlab intersect box --bundle-to`.
    /// The walk passes a closure that does nothing and compiles to nothing.)
    #[inline(always)]
    fn interval_enter(
        &self,
        nd: &Node,
        t_min: f32,
        mut seen: impl FnMut(Option<usize>, FW, FW),
    ) -> u32 {
        let mut near = FW::splat(t_min);
        let mut far = FW::splat(f32::INFINITY);
        for k in 0..3 {
            let Some(iv) = self.interval[k] else { continue };
            let (e, x) = (self.neg[k] as usize, !self.neg[k] as usize);
            let a = FW::load(&nd.planes[e][k]) - FW::splat(iv.origin_in);
            let b = FW::load(&nd.planes[x][k]) - FW::splat(iv.origin_out);
            let (lo, hi) = (FW::splat(iv.inv_lo), FW::splat(iv.inv_hi));
            let (enter, exit) = ((a * lo).min_or(a * hi), (b * lo).max_or(b * hi));
            seen(Some(k), enter, exit);
            near = enter.max_or(near);
            far = exit.min_or(far);
        }
        let (near, far) = (near * FW::splat(SHRINK), far * FW::splat(GROW));
        seen(None, near, far);
        near.le_mask(far)
    }
    // ANCHOR_END: interval_test

    // ANCHOR: lane_test
    /// The lane test: the node's box in child slot `slot` (0 to 3) against all sixteen
    /// rays, each within its own [t_min, t_max]. Bit i is exactly what ray i's own slab
    /// test ([`Node::enter`]) says of that box: the same operations in the same order, one lane per ray. (`SHARED`:
    /// every ray starts at the same point, so the plane minus the origin is one number.)
    /// Returns the rays of `rays` that enter, and the earliest entry among them.
    #[inline(always)]
    fn lane_enter<W: Wide, const SHARED: bool>(
        &self,
        w: W,
        nd: &Node,
        slot: usize,
        t_min: f32,
        t_max: W::F,
        rays: u32,
    ) -> (u32, f32) {
        let mut near = w.splat(t_min);
        let mut far = t_max;
        for k in 0..3 {
            let (e, x) = (self.neg[k] as usize, !self.neg[k] as usize);
            let (entry, exit) = (nd.planes[e][k][slot], nd.planes[x][k][slot]);
            let inv = w.load(&self.inv[k]);
            let (t_in, t_out) = if SHARED {
                let (o_in, o_out) = if self.neg[k] {
                    (self.shared_below[k], self.shared_above[k])
                } else {
                    (self.shared_above[k], self.shared_below[k])
                };
                (
                    w.mul(w.splat(entry - o_in), inv),
                    w.mul(w.splat(exit - o_out), inv),
                )
            } else {
                let (o_in, o_out) = if self.neg[k] {
                    (&self.below[k], &self.above[k])
                } else {
                    (&self.above[k], &self.below[k])
                };
                (
                    w.mul(w.sub(w.splat(entry), w.load(o_in)), inv),
                    w.mul(w.sub(w.splat(exit), w.load(o_out)), inv),
                )
            };
            near = w.max(t_in, near);
            far = w.min(t_out, far);
        }
        let near = w.mul(near, w.splat(SHRINK));
        let entered = w.le(near, w.mul(far, w.splat(GROW))) & rays;
        (entered, w.min_of(near, entered))
    }
    // ANCHOR_END: lane_test
}

/// What a bundle walk asks of the primitives in its leaves.
pub trait BundleLeaf {
    /// Tests primitive slot `k` against the rays whose bits are set in `rays`, lowering
    /// `t_max[i]` for each ray that hit it closer (and keeping the hit itself).
    fn test(&mut self, k: usize, rays: u32, t_max: &mut [f64; BUNDLE]);

    /// Tests primitive slots `ks` against ray `i` alone: what `test` does for each of them
    /// in order with that ray only (a leaf may test them side by side).
    #[inline(always)]
    fn test_alone(&mut self, ks: std::ops::Range<usize>, i: usize, t_max: &mut [f64; BUNDLE]) {
        for k in ks {
            self.test(k, 1 << i, t_max);
        }
    }

    /// Primitive slots `ks` will be tested soon: a leaf may start loading them
    /// ([`super::isa::prefetch`]).
    #[inline(always)]
    fn prefetch(&self, _ks: std::ops::Range<usize>) {}

    /// Does `seen` want to hear of every child the bundle tests (for figures)?
    const SEES: bool = false;
    /// The child in slot `slot` of the opened node `node`, and the rays that enter it (0:
    /// culled).
    #[inline(always)]
    fn seen(&mut self, _node: usize, _slot: usize, _rays: u32) {}
}

/// What a shadow-ray bundle asks of the primitives in its leaves.
pub trait BundleAnyLeaf {
    /// Tests primitive slot `k` against the rays in `rays`; returns those it blocks.
    fn test(&mut self, k: usize, rays: u32) -> u32;
}

mod walk;
mod working;

pub use working::{bundle_working, BundleWorking, RayVerdict};

/// The set bits of a mask, lowest first.
#[derive(Clone, Copy)]
pub struct Bits(pub u32);

impl Iterator for Bits {
    type Item = usize;
    #[inline(always)]
    fn next(&mut self) -> Option<usize> {
        if self.0 == 0 {
            return None;
        }
        let i = self.0.trailing_zeros() as usize;
        self.0 &= self.0 - 1;
        Some(i)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::isa::{self, Kernel};
    use crate::math::Rng;

    /// `below_zero` and `finite_range` on one set of lanes.
    struct Lanes(F32s);

    impl Kernel for Lanes {
        type Output = (u32, Option<(f32, f32)>);
        #[inline(always)]
        fn run<W: Wide>(self, w: W) -> Self::Output {
            (below_zero(w, &self.0), finite_range(w, &self.0))
        }
    }

    /// At every SIMD level the processor has, the lanes' signs and range are what one
    /// lane at a time says: x < 0 lane by lane, and the smallest and largest lane when
    /// every lane is finite (none otherwise), on ordinary numbers, zeros of both signs,
    /// infinities and NaN.
    #[test]
    fn signs_and_ranges_of_the_lanes_at_every_level() {
        let mut rng = Rng::new(&[21, 3]);
        let special = [0.0, -0.0, f32::INFINITY, f32::NEG_INFINITY, f32::NAN, 1e-40];
        for round in 0..2000 {
            // Every other round ordinary numbers only, so the range is exercised too.
            let odd = round % 2 == 1;
            let lanes = F32s(std::array::from_fn(|_| {
                if odd && rng.next_f64() < 0.1 {
                    special[(rng.next_f64() * 6.0) as usize]
                } else {
                    ((rng.next_f64() - 0.5) * 100.0) as f32
                }
            }));
            let negative = (0..LANES).fold(0, |m, i| m | ((lanes.0[i] < 0.0) as u32) << i);
            let range = lanes.0.iter().all(|x| x.is_finite()).then(|| {
                let lo = lanes.0.iter().copied().fold(f32::INFINITY, f32::min);
                let hi = lanes.0.iter().copied().fold(f32::NEG_INFINITY, f32::max);
                (lo, hi)
            });
            for level in isa::levels() {
                let (signs, found) = isa::run_at(level, Lanes(lanes));
                assert_eq!(signs, negative, "round {round}, {level:?}: {lanes:?}");
                // By value: a zero may come back with either sign.
                let same = match (found, range) {
                    (Some((l, h)), Some((lo, hi))) => l == lo && h == hi,
                    (None, None) => true,
                    _ => false,
                };
                assert!(
                    same,
                    "round {round}, {level:?}: {found:?}, not {range:?}, of {lanes:?}"
                );
            }
        }
    }
}
