//! A bounding volume hierarchy built with the binned surface area heuristic (SAH).
//!
//! The same structure serves twice: over a scene's objects (`Accel`) and over a mesh's
//! triangles (`Mesh`). It stores only boxes and primitive indices; the caller's closure tests
//! a primitive, so the exact f64 intersection routines stay the shapes' own.
//!
//! Boxes are stored in f32, rounded outwards (min down, max up), so a stored box always
//! contains the exact one and a 32-byte node fits two to a cache line. The box test itself
//! runs in f64 on the widened values: it only decides *which* primitives get tested, never
//! what t they report, so images are identical to the linear loop's.

use crate::math::Ray;
use crate::shapes::Aabb;
use glam::{DVec3, Vec3};

/// Bins per axis for the SAH sweep.
const BINS: usize = 16;
/// A leaf never holds more primitives than this (unless they cannot be told apart).
pub const MAX_LEAF: usize = 8;
/// Deeper nodes become leaves, so a traversal stack of [`STACK`] entries never overflows.
const MAX_DEPTH: usize = 60;
const STACK: usize = 64;
/// Cost of visiting a node (testing its two children's boxes) relative to testing one
/// primitive, for the SAH's leaf-or-split decision.
const TRAVERSAL_COST: f32 = 1.0;
/// Subtrees with more primitives than this are built in parallel.
const PARALLEL_MIN: usize = 8192;
/// pbrt's γ(3) for f64: widens the far end of a box interval so that rounding in the slab
/// test can never cull a primitive the exact box contains.
const FAR_WIDEN: f64 = 1.0 + 2.0 * (3.0 * f64::EPSILON * 0.5) / (1.0 - 3.0 * f64::EPSILON * 0.5);

// ANCHOR: node
/// One 32-byte node: an f32 box and either two children (`count == 0`: children at `first`
/// and `first + 1`) or a run of `count` primitives starting at `first` in `prims`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(32))]
pub struct Node {
    pub min: [f32; 3],
    pub first: u32,
    pub max: [f32; 3],
    pub count: u32,
}
// ANCHOR_END: node

const _: () = assert!(std::mem::size_of::<Node>() == 32);

impl Node {
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }

    /// The stored box, widened back to f64 (exactly).
    pub fn bounds(&self) -> Aabb {
        Aabb::new(
            DVec3::new(self.min[0] as f64, self.min[1] as f64, self.min[2] as f64),
            DVec3::new(self.max[0] as f64, self.max[1] as f64, self.max[2] as f64),
        )
    }

    // ANCHOR: slab
    /// Slab test: the t at which the ray enters this box, if it meets the box within
    /// [t_min, t_max]; `f64::INFINITY` when it misses.
    ///
    /// Per axis the ray enters through the plane it meets first (min for a positive
    /// direction, max for a negative one, chosen once per ray in [`RayBox`]). A ray parallel
    /// to a slab and starting exactly on its plane makes 0·∞ = NaN; the comparisons below
    /// are written so that a NaN loses, which leaves that axis unconstrained: the box is
    /// kept, never wrongly culled.
    #[inline(always)]
    fn entry(&self, r: &RayBox, t_min: f64, t_max: f64) -> f64 {
        let (lo, hi) = (&self.min, &self.max);
        let pick = |neg: bool, a: f32, b: f32| if neg { b } else { a };
        let mut near = t_min;
        let mut far = t_max * FAR_WIDEN;
        for k in 0..3 {
            let t_in = (pick(r.neg[k], lo[k], hi[k]) as f64 - r.origin[k]) * r.inv[k];
            let t_out = (pick(r.neg[k], hi[k], lo[k]) as f64 - r.origin[k]) * r.inv[k] * FAR_WIDEN;
            near = if t_in > near { t_in } else { near };
            far = if t_out < far { t_out } else { far };
        }
        if near <= far {
            near
        } else {
            f64::INFINITY
        }
    }
    // ANCHOR_END: slab
}

/// A ray as the slab test wants it: origin, reciprocal direction and its signs, per axis.
#[derive(Debug, Clone, Copy)]
struct RayBox {
    origin: [f64; 3],
    inv: [f64; 3],
    neg: [bool; 3],
}

impl RayBox {
    #[inline(always)]
    fn new(ray: &Ray) -> RayBox {
        let inv = ray.dir.recip();
        RayBox {
            origin: ray.origin.to_array(),
            inv: inv.to_array(),
            neg: [inv.x < 0.0, inv.y < 0.0, inv.z < 0.0],
        }
    }
}

/// A BVH over primitives given by their boxes; it stores only their indices, in leaf order:
/// leaf `n` covers `prims[n.first .. n.first + n.count]`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Bvh {
    pub nodes: Vec<Node>,
    pub prims: Vec<u32>,
}

/// A build-time box in f32, already rounded outwards.
#[derive(Debug, Clone, Copy)]
struct FBox {
    min: Vec3,
    max: Vec3,
}

impl FBox {
    const EMPTY: FBox = FBox {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };
    fn from_f64(b: &Aabb) -> FBox {
        FBox {
            min: Vec3::new(down(b.min.x), down(b.min.y), down(b.min.z)),
            max: Vec3::new(up(b.max.x), up(b.max.y), up(b.max.z)),
        }
    }
    #[inline(always)]
    fn union(self, o: FBox) -> FBox {
        FBox {
            min: vmin(self.min, o.min),
            max: vmax(self.max, o.max),
        }
    }
    #[inline(always)]
    fn grow(self, p: Vec3) -> FBox {
        FBox {
            min: vmin(self.min, p),
            max: vmax(self.max, p),
        }
    }
    fn half_area(&self) -> f32 {
        let e = self.max - self.min;
        if e.x < 0.0 {
            return 0.0;
        }
        e.x * e.y + e.y * e.z + e.z * e.x
    }
    fn node(&self, first: u32, count: u32) -> Node {
        Node {
            min: self.min.to_array(),
            first,
            max: self.max.to_array(),
            count,
        }
    }
}

// Plain comparisons (no NaN handling: build boxes hold no NaN), which compile to minss/maxss.
#[inline(always)]
fn vmin(a: Vec3, b: Vec3) -> Vec3 {
    let m = |x: f32, y: f32| if x < y { x } else { y };
    Vec3::new(m(a.x, b.x), m(a.y, b.y), m(a.z, b.z))
}
#[inline(always)]
fn vmax(a: Vec3, b: Vec3) -> Vec3 {
    let m = |x: f32, y: f32| if x > y { x } else { y };
    Vec3::new(m(a.x, b.x), m(a.y, b.y), m(a.z, b.z))
}

/// The largest f32 not above x.
fn down(x: f64) -> f32 {
    let f = x as f32;
    if f as f64 > x {
        f.next_down()
    } else {
        f
    }
}

/// The smallest f32 not below x.
fn up(x: f64) -> f32 {
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
    centroids: Vec<Vec3>,
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
    /// Builds the hierarchy over primitives given by their boxes (empty boxes are allowed).
    /// Deterministic: the same boxes give the same tree on any number of threads.
    pub fn build(boxes: &[Aabb]) -> Bvh {
        if boxes.is_empty() {
            return Bvh::default();
        }
        use rayon::prelude::*;
        let boxes: Vec<FBox> = boxes.par_iter().map(FBox::from_f64).collect();
        let centroids: Vec<Vec3> = boxes.par_iter().map(|b| (b.min + b.max) * 0.5).collect();
        let input = Input { boxes, centroids };
        let mut prims: Vec<u32> = (0..input.boxes.len() as u32).collect();
        let (bounds, centroid_bounds) = bounds_of(&input, &prims);
        let range = Range {
            start: 0,
            end: prims.len(),
            bounds,
            centroid_bounds,
            depth: 0,
        };
        let nodes = subtree(&input, &mut prims, range);
        Bvh { nodes, prims }
    }
    // ANCHOR_END: build

    // ANCHOR: closest
    /// Closest hit: visits the nearer child first and skips any node whose box starts beyond
    /// the best t so far. `test(k, t_max)` tests the primitive in slot `k` of `prims` (callers
    /// keep their data in that order) and returns its t and data if it is hit within t_max.
    /// `visited` counts the nodes whose box was reached (for the cost map and explain).
    #[inline]
    pub fn closest<T>(
        &self,
        ray: &Ray,
        t_min: f64,
        mut t_max: f64,
        visited: &mut u32,
        mut test: impl FnMut(usize, f64) -> Option<(f64, T)>,
    ) -> Option<(usize, T)> {
        let root = self.nodes.first()?;
        let r = RayBox::new(ray);
        let mut best = None;
        *visited += 1;
        if root.entry(&r, t_min, t_max) == f64::INFINITY {
            return None;
        }
        if root.is_leaf() {
            // A one-leaf tree (a scene with a single mesh): no stack to clear.
            let first = root.first as usize;
            for k in first..first + root.count as usize {
                if let Some((t, data)) = test(k, t_max) {
                    t_max = t;
                    best = Some((k, data));
                }
            }
            return best;
        }
        // Far children still to visit, packed as (entry t rounded down to f32) << 32 | index:
        // half the bytes to clear per ray, and a rounded-down entry never culls wrongly.
        let mut stack = [0u64; STACK];
        let mut sp = 0usize;
        let mut node = root;
        loop {
            if node.is_leaf() {
                let first = node.first as usize;
                for k in first..first + node.count as usize {
                    if let Some((t, data)) = test(k, t_max) {
                        t_max = t;
                        best = Some((k, data));
                    }
                }
            } else {
                let l = node.first as usize;
                let (left, right) = (&self.nodes[l], &self.nodes[l + 1]);
                let tl = left.entry(&r, t_min, t_max);
                let tr = right.entry(&r, t_min, t_max);
                *visited += (tl < f64::INFINITY) as u32 + (tr < f64::INFINITY) as u32;
                if tl < f64::INFINITY {
                    if tr < f64::INFINITY {
                        // Both: go to the nearer now, keep the farther for later.
                        let (near, far, t_far) = if tl <= tr {
                            (left, l + 1, tr)
                        } else {
                            (right, l, tl)
                        };
                        stack[sp] = ((down(t_far).to_bits() as u64) << 32) | far as u64;
                        sp += 1;
                        node = near;
                    } else {
                        node = left;
                    }
                    continue;
                } else if tr < f64::INFINITY {
                    node = right;
                    continue;
                }
            }
            // Pop the next node that can still hold something closer than t_max.
            loop {
                if sp == 0 {
                    return best;
                }
                sp -= 1;
                let (index, t_enter) = (stack[sp] as u32, f32::from_bits((stack[sp] >> 32) as u32));
                if t_enter as f64 <= t_max {
                    node = &self.nodes[index as usize];
                    break;
                }
            }
        }
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
        mut test: impl FnMut(usize) -> bool,
    ) -> Option<usize> {
        let root = self.nodes.first()?;
        let r = RayBox::new(ray);
        *visited += 1;
        if root.entry(&r, t_min, t_max) == f64::INFINITY {
            return None;
        }
        if root.is_leaf() {
            let first = root.first as usize;
            return (first..first + root.count as usize).find(|&k| test(k));
        }
        let mut stack = [0u32; STACK];
        let mut sp = 0usize;
        let mut node = root;
        loop {
            if node.is_leaf() {
                let first = node.first as usize;
                for k in first..first + node.count as usize {
                    if test(k) {
                        return Some(k);
                    }
                }
            } else {
                let l = node.first as usize;
                let (left, right) = (&self.nodes[l], &self.nodes[l + 1]);
                let hl = left.entry(&r, t_min, t_max) < f64::INFINITY;
                let hr = right.entry(&r, t_min, t_max) < f64::INFINITY;
                *visited += hl as u32 + hr as u32;
                match (hl, hr) {
                    (true, true) => {
                        stack[sp] = l as u32 + 1;
                        sp += 1;
                        node = left;
                        continue;
                    }
                    (true, false) => {
                        node = left;
                        continue;
                    }
                    (false, true) => {
                        node = right;
                        continue;
                    }
                    (false, false) => {}
                }
            }
            if sp == 0 {
                return None;
            }
            sp -= 1;
            node = &self.nodes[stack[sp] as usize];
        }
    }
    // ANCHOR_END: any

    /// Bytes held by the hierarchy (nodes and the primitive order).
    pub fn memory_bytes(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<Node>() + self.prims.len() * 4
    }

    /// Depth of the deepest leaf (the root is depth 0).
    pub fn depth(&self) -> usize {
        let mut deepest = 0;
        let mut stack = vec![(0usize, 0usize)];
        while let Some((i, d)) = stack.pop() {
            let n = &self.nodes[i];
            deepest = deepest.max(d);
            if !n.is_leaf() {
                stack.push((n.first as usize, d + 1));
                stack.push((n.first as usize + 1, d + 1));
            }
        }
        deepest
    }
}

fn bounds_of(input: &Input, prims: &[u32]) -> (FBox, FBox) {
    prims.iter().fold((FBox::EMPTY, FBox::EMPTY), |(b, c), &p| {
        (
            b.union(input.boxes[p as usize]),
            c.grow(input.centroids[p as usize]),
        )
    })
}

/// Builds the subtree over `prims[range]` (`prims` here is exactly that range) and returns
/// its nodes with its root at index 0 and child indices local to the returned vector.
/// Large subtrees split once here and build their two halves in parallel.
fn subtree(input: &Input, prims: &mut [u32], range: Range) -> Vec<Node> {
    let n = range.end - range.start;
    if n < PARALLEL_MIN {
        return sequential(input, prims, range);
    }
    let Some((mid, left, right)) = split(input, prims, range) else {
        return vec![range.bounds.node(range.start as u32, n as u32)];
    };
    let (lp, rp) = prims.split_at_mut(mid - range.start);
    let (a, b) = rayon::join(|| subtree(input, lp, left), || subtree(input, rp, right));
    // Layout: root, the two child roots side by side, then the rest of each subtree.
    let mut nodes = Vec::with_capacity(1 + a.len() + b.len());
    nodes.push(range.bounds.node(1, 0));
    let shift_a = 2usize; // local index j >= 1 of `a` lands at j + 2
    let shift_b = 1 + a.len(); // local index j >= 1 of `b` lands at j + a.len() + 1
    let fix = |n: &Node, shift: usize| -> Node {
        let mut n = *n;
        if !n.is_leaf() {
            n.first += shift as u32;
        }
        n
    };
    nodes.push(fix(&a[0], shift_a));
    nodes.push(fix(&b[0], shift_b));
    nodes.extend(a[1..].iter().map(|n| fix(n, shift_a)));
    nodes.extend(b[1..].iter().map(|n| fix(n, shift_b)));
    nodes
}

/// The same build without threads: an explicit stack, children appended in pairs.
/// `prims` is the subtree's range; node `first` fields for leaves are global (range.start
/// based), for inner nodes local to the returned vector.
fn sequential(input: &Input, prims: &mut [u32], range: Range) -> Vec<Node> {
    let base = range.start;
    let mut nodes = vec![range.bounds.node(0, 0)];
    let mut stack = vec![(0usize, range)];
    while let Some((index, r)) = stack.pop() {
        let slice = &mut prims[r.start - base..r.end - base];
        match split(input, slice, rebase(r, r.start)) {
            None => {
                nodes[index] = r.bounds.node(r.start as u32, (r.end - r.start) as u32);
            }
            Some((mid, left, right)) => {
                let first = nodes.len();
                nodes[index] = r.bounds.node(first as u32, 0);
                nodes.push(left.bounds.node(0, 0));
                nodes.push(right.bounds.node(0, 0));
                let (left, right) = (
                    Range {
                        start: left.start + r.start,
                        end: left.end + r.start,
                        ..left
                    },
                    Range {
                        start: right.start + r.start,
                        end: right.end + r.start,
                        ..right
                    },
                );
                let _ = mid;
                stack.push((first + 1, right));
                stack.push((first, left));
            }
        }
    }
    nodes
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
    let cb = range.centroid_bounds;
    let extent = cb.max - cb.min;
    // Small nodes get fewer bins (as many as primitives, at least 4): the sweeps cost
    // O(bins) and dominate for the many nodes near the leaves.
    let bins = n.clamp(4, BINS);
    let mut scale = [0f32; 3];
    for axis in 0..3 {
        if extent[axis] > 0.0 {
            scale[axis] = bins as f32 * (1.0 - 1e-6) / extent[axis];
        }
    }
    let bin = |c: Vec3, axis: usize| -> usize {
        (((c[axis] - cb.min[axis]) * scale[axis]) as usize).min(bins - 1)
    };
    // One pass bins every primitive on all three axes (in parallel chunks for big nodes;
    // unions and counts do not depend on the order, so the tree does not either).
    let binned = |chunk: &[u32]| {
        let mut bin_box = [[FBox::EMPTY; BINS]; 3];
        let mut bin_n = [[0u32; BINS]; 3];
        for &p in chunk {
            let (b, c) = (input.boxes[p as usize], input.centroids[p as usize]);
            for axis in 0..3 {
                let i = bin(c, axis);
                bin_box[axis][i] = bin_box[axis][i].union(b);
                bin_n[axis][i] += 1;
            }
        }
        (bin_box, bin_n)
    };
    let (bin_box, bin_n) = if n >= PARALLEL_MIN * 4 {
        use rayon::prelude::*;
        prims.par_chunks(PARALLEL_MIN).map(binned).reduce(
            || ([[FBox::EMPTY; BINS]; 3], [[0u32; BINS]; 3]),
            |(mut ab, mut an), (bb, bn)| {
                for axis in 0..3 {
                    for i in 0..BINS {
                        ab[axis][i] = ab[axis][i].union(bb[axis][i]);
                        an[axis][i] += bn[axis][i];
                    }
                }
                (ab, an)
            },
        )
    } else {
        binned(prims)
    };
    let mut best: Option<(f32, usize, usize)> = None; // cost, axis, first bin on the right
                                                      // The union of bins i.. on each axis: the right child's box for a split before bin i.
    let mut right_box = [[FBox::EMPTY; BINS]; 3];
    for axis in 0..3 {
        if scale[axis] == 0.0 {
            continue;
        }
        // Right-hand sweep: area · count of bins i.. for every i.
        let mut right_cost = [0f32; BINS];
        let (mut acc, mut count) = (FBox::EMPTY, 0u32);
        for i in (1..bins).rev() {
            acc = acc.union(bin_box[axis][i]);
            count += bin_n[axis][i];
            right_cost[i] = acc.half_area() * count as f32;
            right_box[axis][i] = acc;
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
            let lb = bin_box[axis][..boundary]
                .iter()
                .fold(FBox::EMPTY, |a, b| a.union(*b));
            let rb = right_box[axis][boundary];
            let (mut lc, mut rc) = (FBox::EMPTY, FBox::EMPTY);
            let mid = partition(prims, |p| {
                let c = input.centroids[p as usize];
                let left = bin(c, axis) < boundary;
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

    /// Every primitive in exactly one leaf, inside that leaf's box; every child's box inside
    /// its parent's; leaves small; depth bounded (so the traversal stack cannot overflow).
    fn check_invariants(boxes: &[Aabb], bvh: &Bvh) {
        let mut seen = vec![0u32; boxes.len()];
        let mut slots = vec![0u32; boxes.len()];
        let mut stack = vec![0usize];
        while let Some(i) = stack.pop() {
            let node = &bvh.nodes[i];
            if node.is_leaf() {
                assert!(node.count as usize <= MAX_LEAF || boxes.len() <= MAX_LEAF);
                for k in node.first..node.first + node.count {
                    slots[k as usize] += 1;
                    let p = bvh.prims[k as usize] as usize;
                    seen[p] += 1;
                    assert!(
                        inside(&boxes[p], &node.bounds()),
                        "primitive {p} outside its leaf"
                    );
                }
            } else {
                for c in [node.first as usize, node.first as usize + 1] {
                    assert!(c > i, "children come after their parent");
                    assert!(
                        inside(&bvh.nodes[c].bounds(), &node.bounds()),
                        "child {c} outside {i}"
                    );
                    stack.push(c);
                }
            }
        }
        assert!(seen.iter().all(|&n| n == 1), "every primitive exactly once");
        assert!(
            slots.iter().all(|&n| n == 1),
            "leaves cover prims[] exactly"
        );
        assert!(bvh.depth() <= MAX_DEPTH);
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
        }
    }
}
