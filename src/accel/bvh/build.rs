//! Building the hierarchy: a binary tree by the binned surface area heuristic, built in
//! place on all threads, then collapsed into the four-wide [`Node`](super::Node)s rays
//! walk ([`super::collapse`]).

use super::binary::{BinNode, FBox};
use super::{Bvh, MAX_DEPTH, MAX_LEAF};
use crate::accel::pages::vec_on_huge_pages;
use crate::shapes::Aabb;
use glam::Vec3A;

/// Bins per axis for the SAH sweep. (Thirty-two made a terrain's tree its bundles walked no
/// faster: book appendix, "The Xeon again".)
const BINS: usize = 16;
/// Cost of visiting a node relative to testing one primitive, for the SAH's leaf-or-split
/// decision. (0.5 saved 3 % of bunny_56k's camera-ray instructions, 1 % on the other meshes,
/// for more memory and reshaped teaching trees: book chapter 13.)
const TRAVERSAL_COST: f32 = 1.0;
/// Subtrees with more primitives than this are built in parallel.
const PARALLEL_MIN: usize = 8192;

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
        // The leaf order and the nodes are arrays rays walk: on huge pages when big
        // (`crate::accel::pages`), asked for as they are made, not copied there after.
        let mut prims: Vec<u32> = vec_on_huge_pages(n);
        prims.extend(0..n as u32);
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
            nodes: super::collapse::collapse(&binary),
            prims,
        }
    }
    // ANCHOR_END: build
}

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
