//! A bounding volume hierarchy built with the binned surface area heuristic (SAH).
//!
//! The same structure serves twice: over a scene's objects (`Accel`) and over a mesh's
//! triangles (`Mesh`). It stores only boxes and primitive indices; the caller's closure tests
//! a primitive, so the exact f64 intersection routines stay the shapes' own.
//!
//! It is built as a binary tree and collapsed into four-wide nodes ([`Node`], 128 bytes).
//! Boxes are stored in f32, rounded outwards (min down, max up), so a stored box always
//! contains the exact one; the box test runs in f32 lanes, four boxes at a time, with the
//! ray's rounding bounded so that it never culls a box the exact ray enters. It only
//! decides *which* primitives get tested, never what t they report, so images are identical
//! to the linear loop's.

mod binary;
mod build;
mod collapse;
mod slab;
#[cfg(test)]
mod tests;

pub(super) use slab::{bracket, down, up, RayBox, GROW, SHRINK};

use crate::math::Ray;
use crate::shapes::Aabb;
use arrayvec::ArrayVec;
use glam::DVec3;

/// A leaf never holds more primitives than this (unless they cannot be told apart).
pub const MAX_LEAF: usize = 8;
/// Deeper nodes become leaves, so a traversal stack of [`STACK`] entries never overflows.
const MAX_DEPTH: usize = 60;
/// Children per node of the tree rays walk. (Eight was tried: slower on the 1M-triangle
/// terrain, the nodes being four cache lines; and again built for AVX2, where eight lanes
/// are one instruction: 1046 instructions a camera ray on bunny_56k against 955, and slower;
/// and once more with bundles, on an AVX2 processor: bundles no faster, single rays 0.89;
/// and with bundles on an AVX-512 Xeon: bundles and the bundled render no faster.)
pub const WIDTH: usize = 4;
/// Opening a node pushes at most WIDTH children and pops one, and the wide tree is no deeper
/// than the binary one.
pub(super) const STACK: usize = (WIDTH - 1) * MAX_DEPTH + WIDTH;

// ANCHOR: node
/// One node of the tree rays walk: the boxes of up to four children, stored axis by axis
/// (`lo[axis][lane]`, `hi[axis][lane]`) so that one SIMD instruction handles the same slab of
/// all four boxes. Boxes are f32, rounded outwards from the exact f64 boxes. Lane `i` is an
/// inner node (`count[i] == 0`, node index `child[i]`), a leaf (`count[i]` primitives from
/// `prims[child[i]]`), or empty (an inverted box no ray can enter). 128 bytes: two cache
/// lines, aligned to them.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(64))]
pub struct Node {
    /// `planes[0]` holds the boxes' lower corners, `planes[1]` the upper: `planes[side][axis][lane]`.
    pub planes: [[[f32; WIDTH]; 3]; 2],
    pub child: [u32; WIDTH],
    pub count: [u32; WIDTH],
}
// ANCHOR_END: node

const _: () = assert!(std::mem::size_of::<Node>() == 32 * WIDTH);

impl Node {
    pub(in crate::accel) const EMPTY: Node = Node {
        planes: [[[f32::INFINITY; WIDTH]; 3], [[f32::NEG_INFINITY; WIDTH]; 3]],
        child: [0; WIDTH],
        count: [0; WIDTH],
    };

    /// Lane `i`'s box, widened back to f64 (exactly).
    pub fn bounds(&self, i: usize) -> Aabb {
        Aabb::new(
            DVec3::from_array(self.planes[0].map(|p| p[i] as f64)),
            DVec3::from_array(self.planes[1].map(|p| p[i] as f64)),
        )
    }

    /// Is lane `i` empty (its box inverted)?
    pub fn is_empty(&self, i: usize) -> bool {
        self.planes[0][0][i] > self.planes[1][0][i]
    }
}

/// A BVH over primitives given by their boxes; it stores only their indices, in leaf order:
/// a leaf lane covers `prims[child .. child + count]`. The root is `nodes[0]`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Bvh {
    pub nodes: Vec<Node>,
    pub prims: Vec<u32>,
}

impl Bvh {
    // ANCHOR: closest
    /// Closest hit: opens a node, goes on to the nearest child the ray enters and pushes the
    /// others farthest first, so the nearest of them comes off the stack next, and skips any
    /// child whose box starts beyond the best t so far. `test(k, t_max)` tests the primitive
    /// in slot `k` of `prims` (callers keep their data in that order) and returns its t and
    /// data if it is hit within t_max.
    /// `visited` counts the nodes opened (for the cost map and explain).
    /// The ray starts at t_min ≥ 0; a line (t_min < 0) takes [`Bvh::closest_on_line`].
    #[inline]
    pub fn closest<T>(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        visited: &mut u32,
        test: impl FnMut(usize, f64) -> Option<(f64, T)>,
    ) -> Option<(usize, T)> {
        debug_assert!(t_min >= 0.0, "a ray; `closest_on_line` is for lines");
        self.closest_in::<false, T>(ray, t_min, t_max, visited, test)
    }

    /// [`Bvh::closest`] from a t_min below zero (a line, as the slice figures ask): the slab
    /// test then widens negative entries and exits too. A walk of its own, so that the rays'
    /// walk stays lean (a branch between the two in one function cost 5% more instructions).
    pub fn closest_on_line<T>(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        visited: &mut u32,
        test: impl FnMut(usize, f64) -> Option<(f64, T)>,
    ) -> Option<(usize, T)> {
        self.closest_in::<true, T>(ray, t_min, t_max, visited, test)
    }

    #[inline(always)]
    fn closest_in<const SIGNED: bool, T>(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        visited: &mut u32,
        test: impl FnMut(usize, f64) -> Option<(f64, T)>,
    ) -> Option<(usize, T)> {
        let root = self.nodes.first()?;
        let r = RayBox::new(ray);
        *visited += 1;
        let (mask, near) = root.enter::<SIGNED>(&r, down(t_min), up(t_max));
        if mask == 0 {
            return None; // most rays of a typical image: no stack to set up
        }
        let mut stack = ArrayVec::<Pending, STACK>::new();
        // The nearest child the ray enters is opened next without going through the stack;
        // only its siblings wait there.
        let next = nearest_pushing_rest(&mut stack, root, mask, &near);
        self.walk_closest::<SIGNED, T>(&r, &mut stack, next, t_min, t_max, visited, test)
    }

    /// The closest-hit walk of one ray from `start` (a child a bundle handed over:
    /// [`super::bundle`]).
    #[inline(always)]
    pub(super) fn closest_from<const SIGNED: bool, T>(
        &self,
        r: &RayBox,
        start: Pending,
        t_min: f64,
        t_max: f64,
        visited: &mut u32,
        test: impl Visit<T>,
    ) -> Option<(usize, T)> {
        let mut stack = ArrayVec::<Pending, STACK>::new();
        self.walk_closest::<SIGNED, T>(r, &mut stack, start, t_min, t_max, visited, test)
    }

    /// The walk itself: opens `next`, then what comes off `stack`.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn walk_closest<const SIGNED: bool, T>(
        &self,
        r: &RayBox,
        stack: &mut ArrayVec<Pending, STACK>,
        mut next: Pending,
        t_min: f64,
        mut t_max: f64,
        visited: &mut u32,
        mut test: impl Visit<T>,
    ) -> Option<(usize, T)> {
        let (t_min32, mut t_max32) = (down(t_min), up(t_max));
        let mut best = None;
        loop {
            let Pending {
                t_enter,
                child,
                count,
            } = next;
            // Unless a closer hit was found since this child was pushed: open it.
            if t_enter as f64 <= t_max {
                let child = child as usize;
                if count == 0 {
                    *visited += 1;
                    let node = &self.nodes[child];
                    let (mask, near) = node.enter::<SIGNED>(r, t_min32, t_max32);
                    if mask != 0 {
                        next = nearest_pushing_rest(stack, node, mask, &near);
                        continue;
                    }
                } else if let Some((k, t, data)) =
                    test.test_leaf(child..child + count as usize, t_max)
                {
                    t_max = t;
                    t_max32 = up(t);
                    best = Some((k, data));
                }
            }
            match stack.pop() {
                Some(p) => next = p,
                None => break,
            }
        }
        best
    }
    // ANCHOR_END: closest

    // ANCHOR: any
    /// Any hit (shadow rays): stops at the first primitive `test(k)` accepts, in no
    /// particular order, since a shadow ray only asks whether something is in the way.
    #[inline]
    pub fn any(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        visited: &mut u32,
        test: impl FnMut(usize) -> bool,
    ) -> Option<usize> {
        debug_assert!(t_min >= 0.0, "a ray; `any_on_line` is for lines");
        self.any_in::<false>(ray, t_min, t_max, visited, test)
    }

    /// [`Bvh::any`] along the whole line P + t·d, every t (CSG's crossings): the slab test
    /// then widens negative entries and exits too.
    pub fn any_on_line(
        &self,
        ray: &Ray,
        visited: &mut u32,
        test: impl FnMut(usize) -> bool,
    ) -> Option<usize> {
        let all = (f64::NEG_INFINITY, f64::INFINITY);
        self.any_in::<true>(ray, all.0, all.1, visited, test)
    }

    #[inline(always)]
    fn any_in<const SIGNED: bool>(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        visited: &mut u32,
        test: impl FnMut(usize) -> bool,
    ) -> Option<usize> {
        if self.nodes.is_empty() {
            return None;
        }
        let r = RayBox::new(ray);
        self.any_from::<SIGNED>(&r, Pending::ROOT, t_min, t_max, visited, test)
    }

    /// The any-hit walk of one ray from `start` (the root, or a child a bundle handed over).
    #[inline(always)]
    pub(super) fn any_from<const SIGNED: bool>(
        &self,
        r: &RayBox,
        start: Pending,
        t_min: f64,
        t_max: f64,
        visited: &mut u32,
        mut test: impl VisitAny,
    ) -> Option<usize> {
        let (t_min32, t_max32) = (down(t_min), up(t_max));
        if start.count != 0 {
            let first = start.child as usize;
            return (first..first + start.count as usize).find(|&k| test.blocks(k));
        }
        let mut stack = ArrayVec::<u32, STACK>::new();
        let mut node = start.child as usize;
        loop {
            *visited += 1;
            let n = &self.nodes[node];
            let (mut mask, _) = n.enter::<SIGNED>(r, t_min32, t_max32);
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                let (child, count) = (n.child[lane] as usize, n.count[lane] as usize);
                if count == 0 {
                    stack.push(child as u32);
                } else if let Some(k) = (child..child + count).find(|&k| test.blocks(k)) {
                    return Some(k);
                }
            }
            node = stack.pop()? as usize;
        }
    }
    // ANCHOR_END: any

    /// Bytes held by the hierarchy (nodes and the primitive order).
    pub fn memory_bytes(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<Node>() + self.prims.len() * 4
    }

    /// Number of nodes on the longest path from the root to a leaf's node (1 for a tree of
    /// one node).
    pub fn depth(&self) -> usize {
        if self.nodes.is_empty() {
            return 0;
        }
        let mut deepest = 0;
        let mut stack = vec![(0usize, 1usize)];
        while let Some((i, d)) = stack.pop() {
            deepest = deepest.max(d);
            let n = &self.nodes[i];
            for lane in 0..WIDTH {
                if !n.is_empty(lane) && n.count[lane] == 0 {
                    stack.push((n.child[lane] as usize, d + 1));
                }
            }
        }
        deepest
    }
}

/// What the closest-hit walk asks of the primitive in slot `k` it reaches: its t and data if
/// it is hit within t_max. Closures are the usual form; a type of its own (with its method
/// `#[inline(always)]`) is inlined for certain, which the bundles' SIMD kernels need.
pub trait Visit<T> {
    fn test(&mut self, k: usize, t_max: f64) -> Option<(f64, T)>;

    /// A leaf's slots `ks`, in order, each within the best t so far: the last slot that
    /// lowered it, the t and its data. (A visitor may test them side by side, as long as
    /// the answer is this loop's.)
    #[inline(always)]
    fn test_leaf(&mut self, ks: std::ops::Range<usize>, mut t_max: f64) -> Option<(usize, f64, T)> {
        let mut best = None;
        for k in ks {
            if let Some((t, data)) = self.test(k, t_max) {
                t_max = t;
                best = Some((k, t, data));
            }
        }
        best
    }
}

impl<T, F: FnMut(usize, f64) -> Option<(f64, T)>> Visit<T> for F {
    #[inline(always)]
    fn test(&mut self, k: usize, t_max: f64) -> Option<(f64, T)> {
        self(k, t_max)
    }
}

/// What the any-hit walk asks of a primitive: does it block the ray?
pub trait VisitAny {
    fn blocks(&mut self, k: usize) -> bool;
}

impl<F: FnMut(usize) -> bool> VisitAny for F {
    #[inline(always)]
    fn blocks(&mut self, k: usize) -> bool {
        self(k)
    }
}

/// A child waiting on the traversal stack: where the ray enters its box (a lower bound) and
/// what it is (a node, or a leaf's run of primitives), copied from its parent's lane.
#[derive(Debug, Clone, Copy)]
pub(super) struct Pending {
    pub t_enter: f32,
    pub child: u32,
    pub count: u32,
}

impl Pending {
    /// The root node, where a walk of the whole tree starts.
    pub const ROOT: Pending = Pending {
        t_enter: f32::NEG_INFINITY,
        child: 0,
        count: 0,
    };
}

/// The entered child (lane of `node` set in `mask`) with the smallest entry t, returned to be
/// opened next; the others are pushed so that the nearer ones come off the stack first
/// (equal entries: the later lane first, so the walk is deterministic).
#[inline(always)]
fn nearest_pushing_rest(
    stack: &mut ArrayVec<Pending, STACK>,
    node: &Node,
    mask: u32,
    near: &[f32; WIDTH],
) -> Pending {
    let lane = |i: u32| Pending {
        t_enter: near[i as usize],
        child: node.child[i as usize],
        count: node.count[i as usize],
    };
    let a = mask.trailing_zeros();
    let rest = mask & (mask - 1);
    if rest == 0 {
        return lane(a);
    }
    if rest & (rest - 1) == 0 {
        // Two children, the most common case after one: no sort.
        let (a, b) = (lane(a), lane(rest.trailing_zeros()));
        return if a.t_enter < b.t_enter {
            stack.push(b);
            a
        } else {
            stack.push(a);
            b
        };
    }
    // Three or four: insertion into sorted[..n], farthest first (never NaN: NaN lanes are
    // not in mask).
    let mut sorted = [lane(a); WIDTH];
    let mut n = 1;
    let mut mask = rest;
    while mask != 0 {
        let item = lane(mask.trailing_zeros());
        mask &= mask - 1;
        let mut i = n;
        while i > 0 && sorted[i - 1].t_enter < item.t_enter {
            sorted[i] = sorted[i - 1];
            i -= 1;
        }
        sorted[i] = item;
        n += 1;
    }
    for &item in &sorted[..n - 1] {
        stack.push(item);
    }
    sorted[n - 1]
}
