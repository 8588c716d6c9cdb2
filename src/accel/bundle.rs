//! Bundle traversal (beam tracing's modern form): up to [`BUNDLE`] neighbouring rays walk a
//! BVH together. A node is opened once for the whole bundle; each ray still active there
//! gets the node's conservative f32 slab test ([`Node::enter`], four boxes at once), and a
//! child is culled when it misses every ray of the bundle. A leaf's primitives are tested
//! against the rays that reached it by the caller's exact f64 routine, so which primitive a
//! ray hits, and at what t, is exactly what the single-ray walk ([`Bvh::closest`]) finds, as
//! long as the caller breaks ties the same way (closest t, then lowest index: order-free).
//!
//! What is shared: fetching and decoding each node, the stack, ordering the children, and
//! (for meshes) preparing a face's corner and edges once for all rays that test it.

use super::bvh::{down, up, Bvh, Node, RayBox, STACK, WIDTH};
use crate::math::Ray;
use arrayvec::ArrayVec;

/// Rays in a bundle: a 4×4 block of pixels (camera rays of one sample index).
pub const BUNDLE: usize = 16;

/// A child waiting on the bundle's stack: which rays entered it, and the earliest entry of
/// any of them (a lower bound for each, for skipping the rays that found a closer hit since
/// it was pushed). One t for all keeps an entry at 16 bytes: a t per ray made it 76, and the
/// copies in and out cost more than the slab tests the finer skip saved.
#[derive(Clone, Copy)]
struct Pending {
    child: u32,
    count: u32,
    rays: u32,
    t_first: f32,
}

/// What a bundle traversal did: nodes opened (once per bundle), and per ray the nodes it
/// was slab-tested at (what the single-ray walk would call the nodes it visited).
#[derive(Debug, Clone, Copy, Default)]
pub struct BundleWork {
    pub opened: u32,
    pub ray_nodes: [u32; BUNDLE],
}

impl Bvh {
    // ANCHOR: closest_bundle
    /// Closest hits of `rays` (at most [`BUNDLE`]; bit i of `active` says ray i takes part).
    /// `t_max[i]` is ray i's best t so far; `test(k, rays, t_max)` tests primitive slot `k`
    /// against the rays whose bits are set in `rays` and lowers `t_max[i]` for each ray that
    /// hit it closer (keeping the hit itself). The children of an opened node are visited
    /// nearest first by the nearest entry of any ray.
    #[inline]
    pub fn closest_bundle(
        &self,
        rays: &[Ray],
        active: u32,
        t_min: f64,
        t_max: &mut [f64; BUNDLE],
        work: &mut BundleWork,
        test: impl FnMut(usize, u32, &mut [f64; BUNDLE]),
    ) {
        self.closest_bundle_seen(rays, active, t_min, t_max, work, test, |_, _, _| {});
    }

    /// [`Bvh::closest_bundle`], telling `seen(node, lane, rays)` about every non-empty child
    /// lane of every node it opens: `rays` is the mask of the bundle's rays that enter it
    /// (0: culled, every ray missed it). For figures; the render passes a no-op.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub fn closest_bundle_seen(
        &self,
        rays: &[Ray],
        active: u32,
        t_min: f64,
        t_max: &mut [f64; BUNDLE],
        work: &mut BundleWork,
        mut test: impl FnMut(usize, u32, &mut [f64; BUNDLE]),
        mut seen: impl FnMut(usize, usize, u32),
    ) {
        if self.nodes.is_empty() || active == 0 {
            return;
        }
        let (boxes, t_min32, mut t_max32) = prepare(rays, t_min, t_max);
        let mut stack = ArrayVec::<Pending, STACK>::new();
        let mut node = 0usize;
        let mut mask = active;
        loop {
            work.opened += 1;
            let nd = &self.nodes[node];
            let (lane_rays, first) = enter_all(nd, &boxes, mask, t_min32, &t_max32, work);
            // Children entered by some ray, farthest (by the nearest ray's entry) pushed first.
            let mut order: ArrayVec<(f32, usize), WIDTH> = ArrayVec::new();
            for lane in 0..WIDTH {
                if !nd.is_empty(lane) {
                    seen(node, lane, lane_rays[lane]);
                }
                if lane_rays[lane] != 0 {
                    order.push((first[lane], lane));
                }
            }
            order.sort_unstable_by(|a, b| b.0.total_cmp(&a.0).then(b.1.cmp(&a.1)));
            for &(t_first, lane) in &order {
                stack.push(Pending {
                    child: nd.child[lane],
                    count: nd.count[lane],
                    rays: lane_rays[lane],
                    t_first,
                });
            }
            // The next node to open: leaves on the way are tested here.
            loop {
                let Some(p) = stack.pop() else { return };
                // Rays that found a hit closer than where the bundle enters this child drop out.
                let mut rays_in = 0u32;
                let mut r = p.rays;
                while r != 0 {
                    let i = r.trailing_zeros() as usize;
                    r &= r - 1;
                    if p.t_first as f64 <= t_max[i] {
                        rays_in |= 1 << i;
                    }
                }
                if rays_in == 0 {
                    continue;
                }
                if p.count == 0 {
                    node = p.child as usize;
                    mask = rays_in;
                    break;
                }
                for k in p.child as usize..(p.child + p.count) as usize {
                    test(k, rays_in, t_max);
                }
                let mut r = rays_in;
                while r != 0 {
                    let i = r.trailing_zeros() as usize;
                    r &= r - 1;
                    t_max32[i] = up(t_max[i]);
                }
            }
        }
    }
    // ANCHOR_END: closest_bundle
}

impl Bvh {
    // ANCHOR: any_bundle
    /// Shadow rays in a bundle: which of `rays` (bit i of `active`: ray i takes part, within
    /// [t_min, t_max[i]]) are blocked. The bundle walks the tree together as in
    /// [`Bvh::closest_bundle`], children in no particular order; `test(k, rays)` tests
    /// primitive slot `k` against the rays in `rays` and returns those it blocks. A ray
    /// leaves the bundle once blocked, and the walk ends when every ray is, so each ray's
    /// verdict is what [`Bvh::any`] gives it alone.
    pub fn any_bundle(
        &self,
        rays: &[Ray],
        active: u32,
        t_min: f64,
        t_max: &[f64; BUNDLE],
        work: &mut BundleWork,
        mut test: impl FnMut(usize, u32) -> u32,
    ) -> u32 {
        if self.nodes.is_empty() || active == 0 {
            return 0;
        }
        let (boxes, t_min32, t_max32) = prepare(rays, t_min, t_max);
        let mut blocked = 0u32;
        let mut stack = ArrayVec::<(u32, u32), STACK>::new();
        stack.push((0, active));
        while let Some((node, rays_in)) = stack.pop() {
            let mask = rays_in & !blocked;
            if mask == 0 {
                continue;
            }
            work.opened += 1;
            let nd = &self.nodes[node as usize];
            let (lane_rays, _) = enter_all(nd, &boxes, mask, t_min32, &t_max32, work);
            for (lane, &entered) in lane_rays.iter().enumerate() {
                let r = entered & !blocked;
                if r == 0 {
                    continue;
                }
                let (child, count) = (nd.child[lane], nd.count[lane]);
                if count == 0 {
                    stack.push((child, r));
                    continue;
                }
                let mut open = r;
                for k in child as usize..(child + count) as usize {
                    let b = test(k, open);
                    blocked |= b;
                    open &= !b;
                    if open == 0 {
                        break;
                    }
                }
                if blocked & active == active {
                    return blocked;
                }
            }
        }
        blocked
    }
    // ANCHOR_END: any_bundle
}

/// A bundle's rays as the slab test wants them (the last ray repeated into unused slots),
/// and its t range in f32, rounded outwards.
#[inline(always)]
fn prepare(
    rays: &[Ray],
    t_min: f64,
    t_max: &[f64; BUNDLE],
) -> ([RayBox; BUNDLE], f32, [f32; BUNDLE]) {
    let n = rays.len();
    debug_assert!(n <= BUNDLE && n > 0);
    debug_assert!(t_min >= 0.0, "bundles are rays, not lines");
    // Loops rather than `array::from_fn`: whether the compiler inlined from_fn's closure
    // changed with how the crate fell into codegen units (80 instructions a pixel).
    let mut boxes = [RayBox::new(&rays[n - 1]); BUNDLE];
    for (b, r) in boxes.iter_mut().zip(&rays[..n - 1]) {
        *b = RayBox::new(r);
    }
    let mut t_max32 = [0.0; BUNDLE];
    for (t32, &t) in t_max32.iter_mut().zip(t_max) {
        *t32 = up(t);
    }
    (boxes, down(t_min), t_max32)
}

/// Node `nd` opened for the rays in `mask`: each ray's slab test of the four children. Per
/// child, the mask of the rays that enter it and the earliest entry among them (∞ if none).
#[inline(always)]
fn enter_all(
    nd: &Node,
    boxes: &[RayBox; BUNDLE],
    mask: u32,
    t_min32: f32,
    t_max32: &[f32; BUNDLE],
    work: &mut BundleWork,
) -> ([u32; WIDTH], [f32; WIDTH]) {
    let mut lane_rays = [0u32; WIDTH];
    let mut first = [f32::INFINITY; WIDTH];
    let mut m = mask;
    while m != 0 {
        let i = m.trailing_zeros() as usize;
        m &= m - 1;
        work.ray_nodes[i] += 1;
        let (hit, t) = nd.enter::<false>(&boxes[i], t_min32, t_max32[i]);
        for lane in 0..WIDTH {
            let entered = (hit >> lane) & 1;
            lane_rays[lane] |= entered << i;
            let t = if entered != 0 { t[lane] } else { f32::INFINITY };
            first[lane] = first[lane].min(t);
        }
    }
    (lane_rays, first)
}
