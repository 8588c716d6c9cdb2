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

use crate::math::Ray;
use crate::shapes::Aabb;
use arrayvec::ArrayVec;
use glam::{DVec3, Vec3A};

/// Bins per axis for the SAH sweep.
const BINS: usize = 16;
/// A leaf never holds more primitives than this (unless they cannot be told apart).
pub const MAX_LEAF: usize = 8;
/// Deeper nodes become leaves, so a traversal stack of [`STACK`] entries never overflows.
const MAX_DEPTH: usize = 60;
/// Children per node of the tree rays walk. (Eight was tried: slower on the 1M-triangle
/// terrain, the nodes being four cache lines; and again built for AVX2, where eight lanes
/// are one instruction: 1046 instructions a camera ray on bunny_56k against 955, and slower.)
pub const WIDTH: usize = 4;
/// Opening a node pushes at most WIDTH children and pops one, and the wide tree is no deeper
/// than the binary one.
pub(super) const STACK: usize = (WIDTH - 1) * MAX_DEPTH + WIDTH;
/// Cost of visiting a node relative to testing one primitive, for the SAH's leaf-or-split
/// decision. (0.5 saved 3 % of bunny_56k's camera-ray instructions, 1 % on the other meshes,
/// for more memory and reshaped teaching trees: book chapter 13.)
const TRAVERSAL_COST: f32 = 1.0;
/// Subtrees with more primitives than this are built in parallel.
const PARALLEL_MIN: usize = 8192;
/// The collapse into wide nodes shares the tree among threads in this many subtrees.
const COLLAPSE_SUBTREES: usize = 64;

/// One node of the binary tree the SAH builder makes: an f32 box and either two children
/// (`count == 0`: children at `first` and `first + 1`) or a run of `count` primitives
/// starting at `first` in `prims`. The builder's output only: [`Bvh::build`] collapses it
/// into four-wide [`Node`]s, which is what rays traverse.
#[derive(Debug, Clone, Copy, PartialEq)]
struct BinNode {
    min: [f32; 3],
    first: u32,
    max: [f32; 3],
    count: u32,
}

impl BinNode {
    /// A slot of the builder's array no node took.
    const UNUSED: BinNode = BinNode {
        min: [0.0; 3],
        first: 0,
        max: [0.0; 3],
        count: 0,
    };

    fn is_leaf(&self) -> bool {
        self.count > 0
    }

    fn half_area(&self) -> f32 {
        FBox {
            min: Vec3A::from_array(self.min),
            max: Vec3A::from_array(self.max),
        }
        .half_area()
    }
}

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
    const EMPTY: Node = Node {
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
    pub(super) fn enter<const SIGNED: bool>(
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
pub(super) struct RayBox {
    origin_in: [f32; 3],
    origin_out: [f32; 3],
    inv: [f32; 3],
    neg: [bool; 3],
}

/// How far the slab test's entry and exit are moved apart to cover its rounding. Each
/// computed t is the exact (bracketed) one times (1 + θ) with |θ| ≤ γ(3) ≈ 3u (u = 2⁻²⁴, the
/// subtraction, 1/d and the product), and the widening product is rounded once more. So an
/// entry t ≥ 0 times 1 − 5u (rounded) is at most (1 + 3u)(1 − 5u)(1 + u) ≈ 1 − u times the
/// exact one: never later; an exit times 1 + 6u (the next f32 above 1 + 5u) is at least
/// (1 − 3u)(1 + 6u)(1 − u) ≈ 1 + 2u times it: never earlier. For t < 0 the two factors swap
/// roles ([`Node::enter`]'s `SIGNED`).
const SHRINK: f32 = 1.0 - 5.0 * (f32::EPSILON * 0.5);
const GROW: f32 = 1.0 + 3.0 * f32::EPSILON;

impl RayBox {
    #[inline(always)]
    pub(super) fn new(ray: &Ray) -> RayBox {
        let inv = ray.dir.recip().to_array();
        let o = ray.origin.to_array();
        let neg = inv.map(|x| x < 0.0);
        let (below, above) = (o.map(|x| bracket(x).0), o.map(|x| bracket(x).1));
        RayBox {
            origin_in: std::array::from_fn(|k| if neg[k] { below[k] } else { above[k] }),
            origin_out: std::array::from_fn(|k| if neg[k] { above[k] } else { below[k] }),
            inv: inv.map(|x| x as f32),
            neg,
        }
    }
}

/// Four f32 lanes, each operation written lane by lane with plain comparisons, in a shape
/// the compiler turns into one SSE instruction per operation (`max_or` is `maxps`, which
/// returns its second operand when either is NaN; `le_mask` is `cmpleps` + `movmskps`).
/// No `unsafe` and no intrinsics: the crate forbids unsafe code.
#[derive(Debug, Clone, Copy)]
struct FW([f32; WIDTH]);

impl FW {
    #[inline(always)]
    fn splat(x: f32) -> FW {
        FW([x; WIDTH])
    }
    #[inline(always)]
    fn load(a: &[f32; WIDTH]) -> FW {
        FW(*a)
    }
    /// max(self, other), but `other` where `self` is NaN.
    #[inline(always)]
    fn max_or(self, o: FW) -> FW {
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
    fn min_or(self, o: FW) -> FW {
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
    fn le_mask(self, o: FW) -> u32 {
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

impl std::ops::Add for FW {
    type Output = FW;
    #[inline(always)]
    fn add(self, o: FW) -> FW {
        FW(std::array::from_fn(|i| self.0[i] + o.0[i]))
    }
}

impl std::ops::Mul for FW {
    type Output = FW;
    #[inline(always)]
    fn mul(self, o: FW) -> FW {
        FW(std::array::from_fn(|i| self.0[i] * o.0[i]))
    }
}

/// A BVH over primitives given by their boxes; it stores only their indices, in leaf order:
/// a leaf lane covers `prims[child .. child + count]`. The root is `nodes[0]`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Bvh {
    pub nodes: Vec<Node>,
    pub prims: Vec<u32>,
}

/// A build-time box in f32, already rounded outwards. `Vec3A` (16 bytes, SIMD) so that a
/// union is one `minps` and one `maxps`: binning is most of the build's time.
#[derive(Debug, Clone, Copy)]
struct FBox {
    min: Vec3A,
    max: Vec3A,
}

impl FBox {
    const EMPTY: FBox = FBox {
        min: Vec3A::splat(f32::INFINITY),
        max: Vec3A::splat(f32::NEG_INFINITY),
    };
    fn from_f64(b: &Aabb) -> FBox {
        FBox {
            min: Vec3A::new(down(b.min.x), down(b.min.y), down(b.min.z)),
            max: Vec3A::new(up(b.max.x), up(b.max.y), up(b.max.z)),
        }
    }
    // Build boxes hold no NaN, so glam's min and max (minps, maxps) need no NaN rule.
    #[inline(always)]
    fn union(self, o: FBox) -> FBox {
        FBox {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }
    #[inline(always)]
    fn grow(self, p: Vec3A) -> FBox {
        FBox {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }
    fn half_area(&self) -> f32 {
        let e = self.max - self.min;
        if e.x < 0.0 {
            return 0.0;
        }
        e.x * e.y + e.y * e.z + e.z * e.x
    }
    fn node(&self, first: u32, count: u32) -> BinNode {
        BinNode {
            min: self.min.to_array(),
            first,
            max: self.max.to_array(),
            count,
        }
    }
}

/// Two f32 values, one no greater and one no less than x (finite, within f32's range),
/// without branches: x rounded to nearest, moved each way by 2⁻²³ of itself (at least one
/// unit in the last place, more than the half unit rounding can be off) plus the smallest
/// normal f32 (for x near zero). Both moves are exact in f32. Looser than [`down`] and [`up`]
/// by about an ulp, and much cheaper: it runs for every ray's origin.
#[inline(always)]
fn bracket(x: f64) -> (f32, f32) {
    let f = x as f32;
    let m = f.abs() * f32::EPSILON + f32::MIN_POSITIVE;
    (f - m, f + m)
}

/// The largest f32 not above x.
pub(super) fn down(x: f64) -> f32 {
    let f = x as f32;
    if f as f64 > x {
        f.next_down()
    } else {
        f
    }
}

/// The smallest f32 not below x.
pub(super) fn up(x: f64) -> f32 {
    let f = x as f32;
    if (f as f64) < x {
        f.next_up()
    } else {
        f
    }
}

/// What the builder reads: every primitive's box and centroid.
struct Input {
    boxes: Vec<FBox>,
    centroids: Vec<Vec3A>,
}

/// A node's primitives and the two boxes the builder keeps for them.
#[derive(Clone, Copy)]
struct Range {
    start: usize,
    end: usize,
    bounds: FBox,
    centroid_bounds: FBox,
    depth: usize,
}

impl Bvh {
    // ANCHOR: build
    /// Builds the hierarchy over primitives given by their boxes (empty boxes are allowed):
    /// a binary tree by the binned SAH, then collapsed into four-wide nodes (`collapse`).
    /// Deterministic: the same boxes give the same tree on any number of threads.
    pub fn build(boxes: &[Aabb]) -> Bvh {
        Bvh::build_with(boxes.len(), |i| boxes[i])
    }

    /// [`Bvh::build`] over `n` primitives whose boxes `box_of(i)` gives, so a caller that
    /// computes them (a mesh's faces) need not store them all in f64 first.
    pub fn build_with(n: usize, box_of: impl Fn(usize) -> Aabb + Sync) -> Bvh {
        if n == 0 {
            return Bvh::default();
        }
        use rayon::prelude::*;
        let boxes: Vec<FBox> = (0..n)
            .into_par_iter()
            .map(|i| FBox::from_f64(&box_of(i)))
            .collect();
        let centroids: Vec<Vec3A> = boxes.par_iter().map(|b| (b.min + b.max) * 0.5).collect();
        let input = Input { boxes, centroids };
        let mut prims: Vec<u32> = (0..input.boxes.len() as u32).collect();
        let (bounds, centroid_bounds) = prims
            .par_chunks(PARALLEL_MIN)
            .map(|chunk| bounds_of(&input, chunk))
            .reduce(
                || (FBox::EMPTY, FBox::EMPTY),
                |a, b| (a.0.union(b.0), a.1.union(b.1)),
            );
        let range = Range {
            start: 0,
            end: prims.len(),
            bounds,
            centroid_bounds,
            depth: 0,
        };
        // A binary tree over n primitives has at most 2n − 1 nodes. Each subtree gets its own
        // slice of that array (2m − 1 slots for m primitives), so threads write in place.
        let mut binary = Vec::with_capacity(2 * prims.len() - 1);
        binary.par_extend(rayon::iter::repeat_n(BinNode::UNUSED, 2 * prims.len() - 1));
        let (root, rest) = binary.split_at_mut(1);
        let slots = Slots {
            root: &mut root[0],
            rest,
            offset: 1,
        };
        subtree(&input, &mut prims, range, slots);
        drop(input); // the boxes are in the nodes now: free them before the collapse
        Bvh {
            nodes: collapse(&binary),
            prims,
        }
    }
    // ANCHOR_END: build

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
        mut t_max: f64,
        visited: &mut u32,
        mut test: impl FnMut(usize, f64) -> Option<(f64, T)>,
    ) -> Option<(usize, T)> {
        let root = self.nodes.first()?;
        let r = RayBox::new(ray);
        let (t_min32, mut t_max32) = (down(t_min), up(t_max));
        *visited += 1;
        let (mask, near) = root.enter::<SIGNED>(&r, t_min32, t_max32);
        if mask == 0 {
            return None; // most rays of a typical image: no stack to set up
        }
        let mut best = None;
        let mut stack = ArrayVec::<Pending, STACK>::new();
        // The nearest child the ray enters is opened next without going through the stack;
        // only its siblings wait there.
        let mut next = nearest_pushing_rest(&mut stack, root, mask, &near);
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
                    let (mask, near) = node.enter::<SIGNED>(&r, t_min32, t_max32);
                    if mask != 0 {
                        next = nearest_pushing_rest(&mut stack, node, mask, &near);
                        continue;
                    }
                } else {
                    for k in child..child + count as usize {
                        if let Some((t, data)) = test(k, t_max) {
                            t_max = t;
                            t_max32 = up(t);
                            best = Some((k, data));
                        }
                    }
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
        mut test: impl FnMut(usize) -> bool,
    ) -> Option<usize> {
        if self.nodes.is_empty() {
            return None;
        }
        let r = RayBox::new(ray);
        let (t_min32, t_max32) = (down(t_min), up(t_max));
        let mut stack = ArrayVec::<u32, STACK>::new();
        let mut node = 0usize;
        loop {
            *visited += 1;
            let n = &self.nodes[node];
            let (mut mask, _) = n.enter::<SIGNED>(&r, t_min32, t_max32);
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                let (child, count) = (n.child[lane] as usize, n.count[lane] as usize);
                if count == 0 {
                    stack.push(child as u32);
                } else if let Some(k) = (child..child + count).find(|&k| test(k)) {
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

/// A child waiting on the traversal stack: where the ray enters its box (a lower bound) and
/// what it is (a node, or a leaf's run of primitives), copied from its parent's lane.
#[derive(Debug, Clone, Copy)]
struct Pending {
    t_enter: f32,
    child: u32,
    count: u32,
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

/// Turns the binary tree into four-wide nodes: each wide node takes a binary node's two
/// children, then keeps replacing the inner child with the largest surface by its own two
/// children until it holds four (or only leaves are left). Halves the depth, so a ray opens
/// about half as many nodes and tests four boxes with each.
fn collapse(binary: &[BinNode]) -> Vec<Node> {
    let mut nodes = Vec::with_capacity(binary.len() / 4 + 1);
    nodes.push(Node::EMPTY);
    // The top of the tree breadth first, until there are subtrees enough to share among the
    // threads; each is then collapsed on its own and appended in this order (so the layout
    // does not depend on the number of threads).
    let mut frontier = std::collections::VecDeque::from([(0usize, 0usize)]);
    while frontier.len() < COLLAPSE_SUBTREES {
        let Some((b, w)) = frontier.pop_front() else {
            break;
        };
        nodes[w] = wide_node(binary, b, &mut nodes, &mut frontier);
    }
    let frontier = Vec::from(frontier);
    use rayon::prelude::*;
    let parts: Vec<Vec<Node>> = frontier
        .par_iter()
        .map(|&(b, _)| {
            let mut part = vec![Node::EMPTY];
            let mut todo = vec![(b, 0)];
            while let Some((b, w)) = todo.pop() {
                part[w] = wide_node(binary, b, &mut part, &mut todo);
            }
            part
        })
        .collect();
    // Part i's node j ≥ 1 lands at shift_i + j; its root replaces the placeholder at w.
    let mut shifts = Vec::with_capacity(parts.len());
    let mut end = nodes.len();
    for part in &parts {
        shifts.push((end - 1) as u32);
        end += part.len() - 1;
    }
    // Inner lanes are those with no primitives and a child other than 0 (the root is
    // nobody's child; unused lanes point at 0), whatever their box.
    let fix = |n: &Node, shift: u32| {
        let mut n = *n;
        for lane in 0..WIDTH {
            if n.count[lane] == 0 && n.child[lane] != 0 {
                n.child[lane] += shift;
            }
        }
        n
    };
    for ((&(_, w), part), &shift) in frontier.iter().zip(&parts).zip(&shifts) {
        nodes[w] = fix(&part[0], shift);
    }
    // The rest is copied in parallel, each part into its own stretch of the array.
    let top = nodes.len();
    nodes.par_extend(rayon::iter::repeat_n(Node::EMPTY, end - top));
    let mut stretches = Vec::with_capacity(parts.len());
    let mut free = &mut nodes[top..];
    for part in &parts {
        let (stretch, rest) = free.split_at_mut(part.len() - 1);
        stretches.push(stretch);
        free = rest;
    }
    stretches
        .into_par_iter()
        .zip(parts.into_par_iter().zip(shifts))
        .for_each(|(stretch, (part, shift))| {
            for (slot, n) in stretch.iter_mut().zip(&part[1..]) {
                *slot = fix(n, shift);
            }
        });
    nodes
}

// ANCHOR: collapse
/// The wide node for binary node `b`: its two children, then the inner child with the
/// largest surface replaced by its own two children until there are four (or only leaves).
/// Inner lanes get a placeholder appended to `nodes`, and (binary node, its index) goes to
/// `pending` to be filled in later.
fn wide_node(
    binary: &[BinNode],
    b: usize,
    nodes: &mut Vec<Node>,
    pending: &mut impl Extend<(usize, usize)>,
) -> Node {
    let root = &binary[b];
    let mut kids = ArrayVec::<usize, WIDTH>::new();
    if root.is_leaf() {
        kids.push(b); // a one-leaf tree: the root node holds just that leaf
    } else {
        kids.extend([root.first as usize, root.first as usize + 1]);
    }
    while kids.len() < WIDTH {
        let widest = kids
            .iter()
            .enumerate()
            .filter(|(_, &k)| !binary[k].is_leaf())
            .max_by(|(i, &a), (j, &b)| {
                binary[a]
                    .half_area()
                    .total_cmp(&binary[b].half_area())
                    .then(j.cmp(i)) // ties: the leftmost
            })
            .map(|(i, _)| i);
        let Some(i) = widest else { break };
        let first = binary[kids[i]].first as usize;
        kids[i] = first;
        kids.insert(i + 1, first + 1);
    }
    let mut node = Node::EMPTY;
    for (lane, &k) in kids.iter().enumerate() {
        let bn = &binary[k];
        for axis in 0..3 {
            node.planes[0][axis][lane] = bn.min[axis];
            node.planes[1][axis][lane] = bn.max[axis];
        }
        node.count[lane] = bn.count;
        node.child[lane] = if bn.is_leaf() {
            bn.first
        } else {
            nodes.push(Node::EMPTY);
            pending.extend([(k, nodes.len() - 1)]);
            (nodes.len() - 1) as u32
        };
    }
    node
}
// ANCHOR_END: collapse

fn bounds_of(input: &Input, prims: &[u32]) -> (FBox, FBox) {
    prims.iter().fold((FBox::EMPTY, FBox::EMPTY), |(b, c), &p| {
        (
            b.union(input.boxes[p as usize]),
            c.grow(input.centroids[p as usize]),
        )
    })
}

/// Where a subtree's nodes go: its root into `root`, the rest into `rest`, whose 2m − 2
/// slots for m primitives start at index `offset` of the whole array.
struct Slots<'a> {
    root: &'a mut BinNode,
    rest: &'a mut [BinNode],
    offset: usize,
}

/// Builds the subtree over `prims` (exactly the range's primitives) into `slots`. Large
/// subtrees split once here: the two child roots go side by side at the front of `rest`, and
/// each half builds, in parallel, into its own share of the remaining slots. Leaves' `first`
/// is an index into `prims`, inner nodes' into the array.
fn subtree(input: &Input, prims: &mut [u32], range: Range, slots: Slots) {
    let n = range.end - range.start;
    if n < PARALLEL_MIN {
        return sequential(input, prims, range, slots);
    }
    let Some((mid, left, right)) = split(input, prims, range) else {
        *slots.root = range.bounds.node(range.start as u32, n as u32);
        return;
    };
    let offset = slots.offset;
    *slots.root = range.bounds.node(offset as u32, 0);
    let (pair, rest) = slots.rest.split_at_mut(2);
    let (left_root, right_root) = pair.split_at_mut(1);
    let n_left = mid - range.start;
    let (left_rest, right_rest) = rest.split_at_mut(2 * n_left - 2);
    let left_slots = Slots {
        root: &mut left_root[0],
        offset: offset + 2,
        rest: left_rest,
    };
    let right_slots = Slots {
        root: &mut right_root[0],
        offset: offset + 2 + left_slots.rest.len(),
        rest: right_rest,
    };
    let (lp, rp) = prims.split_at_mut(n_left);
    rayon::join(
        || subtree(input, lp, left, left_slots),
        || subtree(input, rp, right, right_slots),
    );
}

/// The same build without threads: an explicit stack, children written in pairs at the
/// front of the free slots of `rest`.
fn sequential(input: &Input, prims: &mut [u32], range: Range, slots: Slots) {
    let base = range.start;
    let mut used = 0;
    // Each entry: the slot its node goes to (None: `root`, Some(i): `rest[i]`) and its range.
    let mut stack = vec![(None, range)];
    while let Some((slot, r)) = stack.pop() {
        let slice = &mut prims[r.start - base..r.end - base];
        let node = match split(input, slice, rebase(r, r.start)) {
            None => r.bounds.node(r.start as u32, (r.end - r.start) as u32),
            Some((_, left, right)) => {
                let global = |c: Range| Range {
                    start: c.start + r.start,
                    end: c.end + r.start,
                    ..c
                };
                stack.push((Some(used + 1), global(right)));
                stack.push((Some(used), global(left)));
                used += 2;
                r.bounds.node((slots.offset + used - 2) as u32, 0)
            }
        };
        match slot {
            None => *slots.root = node,
            Some(i) => slots.rest[i] = node,
        }
    }
}

/// The range shifted so that it starts at `start - offset` (slices are local).
fn rebase(r: Range, offset: usize) -> Range {
    Range {
        start: r.start - offset,
        end: r.end - offset,
        ..r
    }
}

// ANCHOR: sah
/// Finds the cheapest binned SAH plane for `prims` (the range's primitives) and partitions
/// them around it. Returns `None` when one leaf is cheaper (or the node is too deep);
/// otherwise the split point (in `range` coordinates) and the two children.
///
/// Cost of a split = TRAVERSAL_COST + (A_left·N_left + A_right·N_right) / A_node, in units of
/// one primitive test; a leaf costs N. Areas are half surface areas (the ratio is the same).
fn split(input: &Input, prims: &mut [u32], range: Range) -> Option<(usize, Range, Range)> {
    let n = prims.len();
    if n <= 1 || range.depth >= MAX_DEPTH {
        return None;
    }
    // The bin arrays are sized for the bins used: most nodes are small, and clearing three
    // rows of 16 boxes for each of them was a large part of the build.
    match n {
        0..=4 => split_binned::<4>(input, prims, range),
        5..=8 => split_binned::<8>(input, prims, range),
        _ => split_binned::<BINS>(input, prims, range),
    }
}

/// [`split`] with room for `B` bins per axis (B ≥ the bins used).
fn split_binned<const B: usize>(
    input: &Input,
    prims: &mut [u32],
    range: Range,
) -> Option<(usize, Range, Range)> {
    let n = prims.len();
    let cb = range.centroid_bounds;
    let extent = cb.max - cb.min;
    // Small nodes get fewer bins (as many as primitives, at least 4): the sweeps cost
    // O(bins) and dominate for the many nodes near the leaves.
    let bins = n.clamp(4, BINS).min(B);
    let mut scale = Vec3A::ZERO;
    for axis in 0..3 {
        if extent[axis] > 0.0 {
            scale[axis] = bins as f32 * (1.0 - 1e-6) / extent[axis];
        }
    }
    // The bin of a centroid on every axis at once; `bin(c)[axis]` is the one rule used both
    // for binning and for partitioning.
    let last = glam::UVec3::splat(bins as u32 - 1);
    let bin = |c: Vec3A| ((c - cb.min) * scale).as_uvec3().min(last);
    // One pass bins every primitive on all three axes (in parallel chunks for big nodes;
    // unions and counts do not depend on the order, so the tree does not either).
    // The arrays are filled in place: returning them by value copied them for every node.
    let mut bin_box = [[FBox::EMPTY; B]; 3];
    let mut bin_n = [[0u32; B]; 3];
    let binned = |chunk: &[u32], bin_box: &mut [[FBox; B]; 3], bin_n: &mut [[u32; B]; 3]| {
        for &p in chunk {
            let (b, c) = (input.boxes[p as usize], input.centroids[p as usize]);
            let i = bin(c);
            for axis in 0..3 {
                let i = i[axis] as usize;
                bin_box[axis][i] = bin_box[axis][i].union(b);
                bin_n[axis][i] += 1;
            }
        }
    };
    if n >= PARALLEL_MIN * 4 {
        use rayon::prelude::*;
        (bin_box, bin_n) = prims
            .par_chunks(PARALLEL_MIN)
            .map(|chunk| {
                let (mut bb, mut bn) = ([[FBox::EMPTY; B]; 3], [[0u32; B]; 3]);
                binned(chunk, &mut bb, &mut bn);
                (bb, bn)
            })
            .reduce(
                || ([[FBox::EMPTY; B]; 3], [[0u32; B]; 3]),
                |(mut ab, mut an), (bb, bn)| {
                    for axis in 0..3 {
                        for i in 0..B {
                            ab[axis][i] = ab[axis][i].union(bb[axis][i]);
                            an[axis][i] += bn[axis][i];
                        }
                    }
                    (ab, an)
                },
            );
    } else {
        binned(prims, &mut bin_box, &mut bin_n);
    }
    // The cheapest plane: (cost, axis, first bin on the right).
    let mut best: Option<(f32, usize, usize)> = None;
    for axis in 0..3 {
        if scale[axis] == 0.0 {
            continue;
        }
        // Right-hand sweep: area · count of bins i.. for every i.
        let mut right_cost = [0f32; B];
        let (mut acc, mut count) = (FBox::EMPTY, 0u32);
        for i in (1..bins).rev() {
            acc = acc.union(bin_box[axis][i]);
            count += bin_n[axis][i];
            right_cost[i] = acc.half_area() * count as f32;
        }
        let (mut acc, mut count) = (FBox::EMPTY, 0u32);
        for i in 0..bins - 1 {
            acc = acc.union(bin_box[axis][i]);
            count += bin_n[axis][i];
            if count == 0 || count as usize == n {
                continue;
            }
            let cost = acc.half_area() * count as f32 + right_cost[i + 1];
            if best.is_none_or(|b| cost < b.0) {
                best = Some((cost, axis, i + 1));
            }
        }
    }
    let area = range.bounds.half_area();
    let (mid, lb, lc, rb, rc) = match best {
        Some((cost, axis, boundary)) => {
            let split_cost = TRAVERSAL_COST + cost / area.max(f32::MIN_POSITIVE);
            if n <= MAX_LEAF && split_cost >= n as f32 {
                return None;
            }
            // The children's boxes are the unions of their bins; only the centroid boxes
            // need another pass, made while partitioning.
            let union = |bins: &[FBox]| bins.iter().fold(FBox::EMPTY, |a, b| a.union(*b));
            let lb = union(&bin_box[axis][..boundary]);
            let rb = union(&bin_box[axis][boundary..bins]);
            let (mut lc, mut rc) = (FBox::EMPTY, FBox::EMPTY);
            let mid = partition(prims, |p| {
                let c = input.centroids[p as usize];
                let left = (bin(c)[axis] as usize) < boundary;
                if left {
                    lc = lc.grow(c);
                } else {
                    rc = rc.grow(c);
                }
                left
            });
            (mid, lb, lc, rb, rc)
        }
        // Every centroid in one point: no plane separates them; halve the list if too long.
        None if n > MAX_LEAF => {
            let (lb, lc) = bounds_of(input, &prims[..n / 2]);
            let (rb, rc) = bounds_of(input, &prims[n / 2..]);
            (n / 2, lb, lc, rb, rc)
        }
        None => return None,
    };
    let child = |start, end, bounds, centroid_bounds| Range {
        start,
        end,
        bounds,
        centroid_bounds,
        depth: range.depth + 1,
    };
    Some((
        range.start + mid,
        child(range.start, range.start + mid, lb, lc),
        child(range.start + mid, range.end, rb, rc),
    ))
}
// ANCHOR_END: sah

/// Moves the primitives for which `left` holds to the front; returns how many there are.
/// `left` is asked exactly once per primitive.
fn partition(prims: &mut [u32], mut left: impl FnMut(u32) -> bool) -> usize {
    let (mut i, mut j) = (0, prims.len());
    while i < j {
        if left(prims[i]) {
            i += 1;
        } else {
            j -= 1;
            prims.swap(i, j);
        }
    }
    i
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Rng;

    #[test]
    fn bracket_holds_its_value() {
        let mut rng = Rng::new(&[41]);
        for i in 0..200_000 {
            let scale = 10f64.powi((i % 76) - 40); // 1e-40 to 1e35: within f32's range
            let x = (rng.next_f64() * 2.0 - 1.0) * scale;
            for x in [
                x,
                x as f32 as f64,
                0.0,
                -0.0,
                1e-45,
                -3e-39,
                f32::MAX as f64 * 0.99,
            ] {
                let (lo, hi) = bracket(x);
                assert!(lo as f64 <= x && x <= hi as f64, "{x}: {lo} {hi}");
            }
        }
    }

    #[test]
    fn rounding_is_outward() {
        for x in [
            0.1,
            -0.1,
            1.0 / 3.0,
            -1e-30,
            1e30,
            0.0,
            123456.789,
            1e300,
            -1e300,
        ] {
            assert!(down(x) as f64 <= x && up(x) as f64 >= x, "{x}");
        }
    }

    fn random_boxes(n: usize, seed: u64) -> Vec<Aabb> {
        let mut rng = Rng::new(&[seed]);
        (0..n)
            .map(|_| {
                let c = DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64()) * 100.0;
                let e = DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64()) * 3.0;
                Aabb::new(c - e, c + e * 0.5)
            })
            .collect()
    }

    fn inside(inner: &Aabb, outer: &Aabb) -> bool {
        inner.min.cmpge(outer.min).all() && inner.max.cmple(outer.max).all()
    }

    /// Every primitive in exactly one leaf, inside that leaf's box; every node reached once,
    /// after its parent, with its boxes inside the parent's lane; leaves small; depth
    /// bounded (so the traversal stack cannot overflow).
    fn check_invariants(boxes: &[Aabb], bvh: &Bvh) {
        let mut seen = vec![0u32; boxes.len()];
        let mut slots = vec![0u32; boxes.len()];
        let mut reached = vec![0u32; bvh.nodes.len()];
        let everything = Aabb::new(DVec3::splat(f64::NEG_INFINITY), DVec3::splat(f64::INFINITY));
        let mut stack = vec![(0usize, everything)];
        while let Some((i, parent)) = stack.pop() {
            reached[i] += 1;
            let node = &bvh.nodes[i];
            for lane in (0..WIDTH).filter(|&l| !node.is_empty(l)) {
                let b = node.bounds(lane);
                assert!(
                    inside(&b, &parent),
                    "node {i} lane {lane} outside its parent"
                );
                let (child, count) = (node.child[lane], node.count[lane]);
                if count > 0 {
                    assert!(count as usize <= MAX_LEAF || boxes.len() <= MAX_LEAF);
                    for k in child..child + count {
                        slots[k as usize] += 1;
                        let p = bvh.prims[k as usize] as usize;
                        seen[p] += 1;
                        assert!(inside(&boxes[p], &b), "primitive {p} outside its leaf");
                    }
                } else {
                    assert!(child as usize > i, "children come after their parent");
                    stack.push((child as usize, b));
                }
            }
        }
        assert!(seen.iter().all(|&n| n == 1), "every primitive exactly once");
        assert!(
            slots.iter().all(|&n| n == 1),
            "leaves cover prims[] exactly"
        );
        assert!(
            reached.iter().all(|&n| n == 1),
            "every node reached exactly once"
        );
        assert!(bvh.depth() <= MAX_DEPTH);
    }

    /// Collapsing leaves few lanes empty: every node but the root of a tiny tree is at least
    /// three-quarters full on these inputs.
    #[test]
    fn wide_nodes_are_full() {
        let bvh = Bvh::build(&random_boxes(20_000, 3));
        let lanes: usize = bvh
            .nodes
            .iter()
            .map(|n| (0..WIDTH).filter(|&l| !n.is_empty(l)).count())
            .sum();
        assert!(
            lanes as f64 / bvh.nodes.len() as f64 > 0.75 * WIDTH as f64,
            "{lanes} lanes in {} nodes",
            bvh.nodes.len()
        );
    }

    /// The f32 slab test never culls a box the exact ray enters, whatever the origin's
    /// rounding to f32 and however nearly parallel the ray is to a slab; its entry t is never
    /// later than the exact one. Boxes sit right at the ray (touching, tangent, thin) so that
    /// rounding decides.
    #[test]
    fn slab_test_is_conservative() {
        let mut rng = Rng::new(&[31]);
        let mut near_misses = 0;
        for _ in 0..200_000 {
            let mut f = || rng.next_f64() * 2.0 - 1.0;
            let scale = [1e-3, 1.0, 1e3, 1e6][(f().abs() * 3.99) as usize];
            let o = DVec3::new(f(), f(), f()) * scale + DVec3::splat(0.1234567891234);
            let mut d = DVec3::new(f(), f(), f());
            // Some rays nearly or exactly parallel to an axis plane.
            match (f().abs() * 6.0) as usize {
                0 => d.x = 0.0,
                1 => d.y *= 1e-9,
                2 => d.z = -0.0,
                _ => {}
            }
            if d == DVec3::ZERO {
                continue;
            }
            let ray = Ray::new(o, d);
            // A box around a point on the ray, shrunk or pushed so the ray grazes it.
            let t_hit = f().abs() * 10.0 * scale;
            let p = ray.at(t_hit);
            let half = DVec3::new(f().abs(), f().abs(), f().abs()) * scale * 0.01;
            let shift = DVec3::new(f(), f(), f()) * half * 1.5;
            let exact = Aabb::new(p - half + shift, p + half + shift);
            let stored = FBox::from_f64(&exact);
            let mut node = Node::EMPTY;
            for axis in 0..3 {
                node.planes[0][axis][2] = stored.min[axis];
                node.planes[1][axis][2] = stored.max[axis];
            }
            // Rays from t = 0, and lines (t from −∞, or from a t before the box) as CSG asks.
            let t_min = [0.0, 0.0, f64::NEG_INFINITY, -t_hit][(f().abs() * 3.99) as usize];
            let t_max = [f64::INFINITY, t_hit][(f() > 0.0) as usize];
            let r = RayBox::new(&ray);
            let (mask, near) = if t_min >= 0.0 {
                node.enter::<false>(&r, down(t_min), up(t_max))
            } else {
                node.enter::<true>(&r, down(t_min), up(t_max))
            };
            assert_eq!(mask & !0b100, 0, "empty lanes are never entered");
            let bounds = node.bounds(2);
            let inv = ray.dir.recip();
            if let Some(t) = bounds.hit(&ray, inv, t_min, t_max) {
                assert!(
                    mask == 0b100,
                    "culled a box the ray enters at t = {t}: {ray:?} {bounds:?}"
                );
                assert!(near[2] as f64 <= t, "entry {} after the exact {t}", near[2]);
            } else if mask != 0 {
                near_misses += 1;
            }
        }
        // Kept-but-missed boxes are the price of rounding; they must stay rare.
        assert!(
            near_misses < 2000,
            "{near_misses} boxes kept that the ray misses"
        );
    }

    #[test]
    fn invariants_hold_small_and_large() {
        for (n, seed) in [(1, 1), (2, 2), (7, 3), (100, 4), (5000, 5), (40_000, 6)] {
            let boxes = random_boxes(n, seed);
            check_invariants(&boxes, &Bvh::build(&boxes));
        }
    }

    #[test]
    fn identical_boxes_still_split_into_small_leaves() {
        let boxes = vec![Aabb::new(DVec3::ZERO, DVec3::ONE); 1000];
        let bvh = Bvh::build(&boxes);
        check_invariants(&boxes, &bvh);
    }

    #[test]
    fn build_is_deterministic_across_thread_counts() {
        let boxes = random_boxes(30_000, 9);
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let four = rayon::ThreadPoolBuilder::new()
            .num_threads(4)
            .build()
            .unwrap();
        assert_eq!(
            one.install(|| Bvh::build(&boxes)),
            four.install(|| Bvh::build(&boxes))
        );
    }

    /// Closest and any-hit over boxes-as-primitives agree with testing every box.
    #[test]
    fn traversal_matches_brute_force() {
        // One box (a one-leaf tree), a few, many.
        for (n, rays) in [(1, 300), (5, 300), (3000, 2000)] {
            brute_force_check(&random_boxes(n, 11), rays);
        }
    }

    /// Flat boxes (a mesh's axis-aligned faces) behind a line's origin: the unsigned widening
    /// would shrink a negative entry and grow a negative exit, culling every one of them.
    #[test]
    fn lines_find_flat_boxes_behind_the_origin() {
        for i in 1..=40 {
            // One face per tree, so that the flat box is a lane's own box.
            let x = -(i as f64) * 0.37;
            let face = Aabb::new(DVec3::new(x, -1.0, -1.0), DVec3::new(x, 1.0, 1.0));
            let bvh = Bvh::build(&[face]);
            let ray = Ray::new(
                DVec3::new(0.0, 0.1, 0.2),
                DVec3::new(1.0, 0.001 * i as f64, -0.002),
            );
            let inv = ray.dir.recip();
            let t_min = -100.0;
            let exact = face.hit(&ray, inv, t_min, f64::INFINITY);
            assert!(exact.is_some());
            let found = bvh.closest_on_line(&ray, t_min, f64::INFINITY, &mut 0, |_, t_max| {
                face.hit(&ray, inv, t_min, t_max).map(|t| (t, t))
            });
            assert_eq!(found.map(|f| f.1), exact, "face at x = {x}");
            let on_line = bvh.any_on_line(&ray, &mut 0, |_| true);
            assert_eq!(on_line, Some(0), "face at x = {x}");
        }
    }

    fn brute_force_check(boxes: &[Aabb], rays: usize) {
        let bvh = Bvh::build(boxes);
        let mut rng = Rng::new(&[12]);
        for _ in 0..rays {
            let o = DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64()) * 140.0 - 20.0;
            let d = DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64()) - 0.5;
            let ray = Ray::new(o, d);
            let inv = d.recip();
            let brute = boxes
                .iter()
                .filter_map(|b| b.hit(&ray, inv, 0.0, f64::INFINITY))
                .min_by(f64::total_cmp);
            let found = bvh.closest(&ray, 0.0, f64::INFINITY, &mut 0, |k, t_max| {
                boxes[bvh.prims[k] as usize]
                    .hit(&ray, inv, 0.0, t_max)
                    .map(|t| (t, t))
            });
            assert_eq!(found.map(|f| f.1), brute);
            let any = bvh.any(&ray, 0.0, f64::INFINITY, &mut 0, |k| {
                boxes[bvh.prims[k] as usize]
                    .hit(&ray, inv, 0.0, f64::INFINITY)
                    .is_some()
            });
            assert_eq!(any.is_some(), brute.is_some());
            // The whole line (as the slice figures and CSG ask): every box on it, either side
            // of the origin, within a window that starts behind it.
            let t_min = -100.0 * rng.next_f64();
            let behind = boxes
                .iter()
                .filter_map(|b| b.hit(&ray, inv, t_min, f64::INFINITY))
                .min_by(f64::total_cmp);
            let found = bvh.closest_on_line(&ray, t_min, f64::INFINITY, &mut 0, |k, t_max| {
                boxes[bvh.prims[k] as usize]
                    .hit(&ray, inv, t_min, t_max)
                    .map(|t| (t, t))
            });
            assert_eq!(found.map(|f| f.1), behind, "t_min = {t_min}");
            let mut on_line = 0;
            bvh.any_on_line(&ray, &mut 0, |k| {
                let hit =
                    boxes[bvh.prims[k] as usize].hit(&ray, inv, f64::NEG_INFINITY, f64::INFINITY);
                on_line += hit.is_some() as usize;
                false
            });
            let crossed = boxes
                .iter()
                .filter(|b| b.hit(&ray, inv, f64::NEG_INFINITY, f64::INFINITY).is_some())
                .count();
            assert_eq!(on_line, crossed);
        }
    }
}
