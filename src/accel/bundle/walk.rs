//! The bundle walks themselves: closest hits ([`Bvh::closest_bundle`]) and shadow rays
//! ([`Bvh::any_bundle`]) of a [`RayBundle`] through the four-wide tree, nearest child first,
//! the rays that part from the bundle walking on alone.

use super::{Bits, BundleAnyLeaf, BundleLeaf, BundleWork, RayBundle, BUNDLE, FEW};
use crate::accel::bvh::{down, up, Bvh, Pending as Single, Visit, VisitAny, STACK, WIDTH};
use crate::accel::isa::{prefetch, Wide};
use crate::accel::lanes::{count, F32s};
use arrayvec::ArrayVec;

/// A child waiting on the bundle's stack: which rays entered it, and the earliest of their
/// entry t's (the lane test's), a lower bound for each of them (to skip the rays that found
/// a closer hit since it was pushed).
#[derive(Clone, Copy)]
struct Pending {
    child: u32,
    count: u32,
    rays: u32,
    t_first: f32,
}

impl Pending {
    fn single(&self) -> Single {
        Single {
            t_enter: self.t_first,
            child: self.child,
            count: self.count,
        }
    }
}

impl Bvh {
    // ANCHOR: closest_bundle
    /// Closest hits of a bundle (bit i of `active`: ray i takes part). `t_max[i]` is ray
    /// i's best t so far; `leaf` tests primitives and lowers it. The children of an opened
    /// node are visited nearest first, by the earliest entry among the rays that enter them.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub fn closest_bundle<W: Wide, L: BundleLeaf>(
        &self,
        w: W,
        b: &RayBundle,
        active: u32,
        t_min: f64,
        t_max: &mut [f64; BUNDLE],
        work: &mut BundleWork,
        leaf: &mut L,
    ) {
        debug_assert!(t_min >= 0.0, "bundles are rays, not lines");
        let active = active & b.all;
        if self.nodes.is_empty() || active == 0 {
            return;
        }
        if !b.coherent {
            self.closest_alone(b, active, Single::ROOT, t_min, t_max, work, leaf);
        } else if b.shared_origin {
            self.closest_together::<W, true, L>(w, b, active, t_min, t_max, work, leaf);
        } else {
            self.closest_together::<W, false, L>(w, b, active, t_min, t_max, work, leaf);
        }
    }
    // ANCHOR_END: closest_bundle

    // ANCHOR: bundle_walk
    /// [`Bvh::closest_bundle`] for a coherent bundle.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn closest_together<W: Wide, const SHARED: bool, L: BundleLeaf>(
        &self,
        w: W,
        b: &RayBundle,
        active: u32,
        t_min: f64,
        t_max: &mut [f64; BUNDLE],
        work: &mut BundleWork,
        leaf: &mut L,
    ) {
        let t_min32 = down(t_min);
        let mut t_max32 = F32s::up(t_max);
        let mut stack = ArrayVec::<Pending, STACK>::new();
        let (mut node, mut mask) = (0usize, active);
        loop {
            work.opened += 1;
            count(&mut work.ray_nodes, mask);
            let nd = &self.nodes[node];
            // The child slots whose boxes pass the interval test, bit by bit.
            let slots = b.interval_enter(nd, t_min32, |_, _, _| {});
            // The children some ray enters, nearest last, to be pushed in that order.
            let mut order = [(0.0f32, 0usize, 0u32); WIDTH];
            let mut n = 0;
            for slot in 0..WIDTH {
                let (rays, near) = if slots >> slot & 1 == 1 {
                    b.lane_enter::<W, SHARED>(w, nd, slot, t_min32, w.load(&t_max32), mask)
                } else {
                    (0, 0.0)
                };
                if L::SEES && !nd.is_empty(slot) {
                    leaf.seen(node, slot, rays);
                }
                if rays != 0 {
                    let item = (near, slot, rays);
                    let mut j = n;
                    while j > 0 && order[j - 1].0 < item.0 {
                        order[j] = order[j - 1];
                        j -= 1;
                    }
                    order[j] = item;
                    n += 1;
                }
            }
            for &(t_first, slot, rays) in &order[..n] {
                let (child, count) = (nd.child[slot] as usize, nd.count[slot] as usize);
                if count == 0 {
                    prefetch(std::slice::from_ref(&self.nodes[child]));
                } else {
                    leaf.prefetch(child..child + count);
                }
                stack.push(Pending {
                    child: child as u32,
                    count: count as u32,
                    rays,
                    t_first,
                });
            }
            // The next node to open: leaves on the way are tested here.
            loop {
                let Some(p) = stack.pop() else { return };
                // Rays that found a hit closer than where the bundle enters this child drop out.
                let rays = w.le(w.splat(p.t_first), w.load(&t_max32)) & p.rays;
                if rays == 0 {
                    continue;
                }
                if p.count == 0 {
                    if rays.count_ones() > FEW {
                        (node, mask) = (p.child as usize, rays);
                        break;
                    }
                    self.closest_alone(b, rays, p.single(), t_min, t_max, work, leaf);
                    for i in Bits(rays) {
                        t_max32.0[i] = up(t_max[i]);
                    }
                    continue;
                }
                for k in p.child as usize..(p.child + p.count) as usize {
                    leaf.test(k, rays, t_max);
                }
                for i in Bits(rays) {
                    t_max32.0[i] = up(t_max[i]);
                }
            }
        }
    }
    // ANCHOR_END: bundle_walk

    /// Each ray in `rays` walks from `start` alone, with the single-ray walk.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn closest_alone<L: BundleLeaf>(
        &self,
        b: &RayBundle,
        rays: u32,
        start: Single,
        t_min: f64,
        t_max: &mut [f64; BUNDLE],
        work: &mut BundleWork,
        leaf: &mut L,
    ) {
        for i in Bits(rays) {
            let r = b.ray_box(i);
            let mut visited = 0;
            let ray_t = t_max[i];
            let one = OneRay { leaf, i, t_max };
            self.closest_from::<false, ()>(&r, start, t_min, ray_t, &mut visited, one);
            work.ray_nodes[i] += visited;
        }
    }
}

impl Bvh {
    // ANCHOR: any_bundle
    /// Shadow rays in a bundle: which of its rays (bit i of `active`: ray i takes part,
    /// within `[t_min, t_max[i]]`) are blocked. The bundle walks the tree together as in
    /// [`Bvh::closest_bundle`], children in no particular order; `leaf` tests a primitive
    /// against some rays and returns those it blocks. A ray leaves the bundle once blocked,
    /// and the walk ends when every ray is, so each ray's verdict is what [`Bvh::any`] gives
    /// it alone.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub fn any_bundle<W: Wide, L: BundleAnyLeaf>(
        &self,
        w: W,
        b: &RayBundle,
        active: u32,
        t_min: f64,
        t_max: &[f64; BUNDLE],
        work: &mut BundleWork,
        leaf: &mut L,
    ) -> u32 {
        let active = active & b.all;
        if self.nodes.is_empty() || active == 0 {
            return 0;
        }
        if !b.coherent {
            self.any_alone(b, active, Single::ROOT, t_min, t_max, leaf)
        } else if b.shared_origin {
            self.any_together::<W, true, L>(w, b, active, t_min, t_max, work, leaf)
        } else {
            self.any_together::<W, false, L>(w, b, active, t_min, t_max, work, leaf)
        }
    }
    // ANCHOR_END: any_bundle

    /// [`Bvh::any_bundle`] for a coherent bundle.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn any_together<W: Wide, const SHARED: bool, L: BundleAnyLeaf>(
        &self,
        w: W,
        b: &RayBundle,
        active: u32,
        t_min: f64,
        t_max: &[f64; BUNDLE],
        work: &mut BundleWork,
        leaf: &mut L,
    ) -> u32 {
        let t_min32 = down(t_min);
        let t_max32 = F32s::up(t_max);
        let mut blocked = 0u32;
        let mut stack = ArrayVec::<(u32, u32, u32), STACK>::new();
        stack.push((0, 0, active));
        while let Some((child, n_prims, rays_in)) = stack.pop() {
            let rays = rays_in & !blocked;
            if rays == 0 {
                continue;
            }
            let start = Single {
                t_enter: 0.0,
                child,
                count: n_prims,
            };
            if rays.count_ones() <= FEW {
                blocked |= self.any_alone(b, rays, start, t_min, t_max, leaf);
            } else if n_prims > 0 {
                let mut open = rays;
                for k in child as usize..(child + n_prims) as usize {
                    open &= !leaf.test(k, open);
                    if open == 0 {
                        break;
                    }
                }
                blocked |= rays & !open;
            } else {
                work.opened += 1;
                let nd = &self.nodes[child as usize];
                let slots = b.interval_enter(nd, t_min32, |_, _, _| {});
                for slot in 0..WIDTH {
                    if slots >> slot & 1 == 1 {
                        let t_max = w.load(&t_max32);
                        let (entered, _) =
                            b.lane_enter::<W, SHARED>(w, nd, slot, t_min32, t_max, rays);
                        if entered != 0 {
                            let (child, count) = (nd.child[slot], nd.count[slot]);
                            if count == 0 {
                                prefetch(std::slice::from_ref(&self.nodes[child as usize]));
                            }
                            stack.push((child, count, entered));
                        }
                    }
                }
            }
            if blocked & active == active {
                break;
            }
        }
        blocked
    }

    /// Each ray in `rays` walks from `start` alone (any hit); returns those blocked.
    #[inline(always)]
    fn any_alone<L: BundleAnyLeaf>(
        &self,
        b: &RayBundle,
        rays: u32,
        start: Single,
        t_min: f64,
        t_max: &[f64; BUNDLE],
        leaf: &mut L,
    ) -> u32 {
        let mut blocked = 0;
        for i in Bits(rays) {
            let r = b.ray_box(i);
            let mut visited = 0;
            let one = OneAny { leaf, i };
            let hit = self.any_from::<false>(&r, start, t_min, t_max[i], &mut visited, one);
            blocked |= (hit.is_some() as u32) << i;
        }
        blocked
    }
}

/// Ray i of a bundle walking alone: its leaf tests are the bundle's, for that ray only.
struct OneRay<'a, L> {
    leaf: &'a mut L,
    i: usize,
    t_max: &'a mut [f64; BUNDLE],
}

impl<L: BundleLeaf> Visit<()> for OneRay<'_, L> {
    #[inline(always)]
    fn test(&mut self, k: usize, best: f64) -> Option<(f64, ())> {
        self.leaf.test(k, 1 << self.i, self.t_max);
        let t = self.t_max[self.i];
        (t < best).then_some((t, ()))
    }

    #[inline(always)]
    fn test_leaf(&mut self, ks: std::ops::Range<usize>, best: f64) -> Option<(usize, f64, ())> {
        let first = ks.start;
        self.leaf.test_alone(ks, self.i, self.t_max);
        let t = self.t_max[self.i];
        (t < best).then_some((first, t, ()))
    }
}

/// Shadow ray i of a bundle walking alone.
struct OneAny<'a, L> {
    leaf: &'a mut L,
    i: usize,
}

impl<L: BundleAnyLeaf> VisitAny for OneAny<'_, L> {
    #[inline(always)]
    fn blocks(&mut self, k: usize) -> bool {
        self.leaf.test(k, 1 << self.i) != 0
    }
}
