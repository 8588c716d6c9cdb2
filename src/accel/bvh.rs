//! A bounding volume hierarchy built with the binned surface area heuristic.

use crate::math::Ray;
use crate::shapes::Aabb;
use glam::DVec3;

const BINS: usize = 12;
const MAX_LEAF: usize = 4;

/// One node: a box and either two children (`count == 0`: children at `first` and
/// `first + 1`) or a run of `count` primitives starting at `first` in `prims`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Node {
    pub bounds: Aabb,
    pub first: u32,
    pub count: u32,
}

/// A BVH over primitives given by their boxes; it stores only their indices.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Bvh {
    pub nodes: Vec<Node>,
    pub prims: Vec<u32>,
}

impl Bvh {
    pub fn build(boxes: &[Aabb]) -> Bvh {
        if boxes.is_empty() {
            return Bvh::default();
        }
        let centroids: Vec<DVec3> = boxes.iter().map(|b| b.centroid()).collect();
        let mut prims: Vec<u32> = (0..boxes.len() as u32).collect();
        let mut nodes = vec![Node {
            bounds: Aabb::EMPTY,
            first: 0,
            count: 0,
        }];
        let mut stack = vec![(0usize, 0usize, boxes.len())];
        while let Some((node, start, end)) = stack.pop() {
            let bounds = prims[start..end]
                .iter()
                .fold(Aabb::EMPTY, |b, &p| b.union(boxes[p as usize]));
            nodes[node].bounds = bounds;
            let n = end - start;
            let split = if n <= MAX_LEAF {
                None
            } else {
                sah_split(boxes, &centroids, &mut prims[start..end], bounds)
            };
            match split {
                None => {
                    nodes[node].first = start as u32;
                    nodes[node].count = n as u32;
                }
                Some(mid) => {
                    let left = nodes.len();
                    nodes.push(Node {
                        bounds: Aabb::EMPTY,
                        first: 0,
                        count: 0,
                    });
                    nodes.push(Node {
                        bounds: Aabb::EMPTY,
                        first: 0,
                        count: 0,
                    });
                    nodes[node].first = left as u32;
                    nodes[node].count = 0;
                    stack.push((left, start, start + mid));
                    stack.push((left + 1, start + mid, end));
                }
            }
        }
        Bvh { nodes, prims }
    }

    /// Closest hit: visits children nearest first and narrows t_max as hits are found.
    /// `test(prim, t_max)` returns the primitive's hit (its t and data) within t_max.
    /// `visited` counts the nodes touched (for the cost map).
    #[inline]
    pub fn closest<T>(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        test: impl FnMut(usize, f64) -> Option<(f64, T)>,
    ) -> Option<(usize, T)> {
        self.closest_counted(ray, t_min, t_max, &mut 0, test)
            .map(|(i, _, v)| (i, v))
    }

    pub fn closest_counted<T>(
        &self,
        ray: &Ray,
        t_min: f64,
        mut t_max: f64,
        visited: &mut u32,
        mut test: impl FnMut(usize, f64) -> Option<(f64, T)>,
    ) -> Option<(usize, f64, T)> {
        if self.nodes.is_empty() {
            return None;
        }
        let inv = ray.dir.recip();
        let mut best = None;
        let mut stack = [0u32; 64];
        let mut sp = 0usize;
        let mut node = 0usize;
        if self.nodes[0].bounds.hit(ray, inv, t_min, t_max).is_none() {
            *visited += 1;
            return None;
        }
        loop {
            *visited += 1;
            let n = self.nodes[node];
            if n.count > 0 {
                for &p in &self.prims[n.first as usize..(n.first + n.count) as usize] {
                    if let Some((t, data)) = test(p as usize, t_max) {
                        t_max = t;
                        best = Some((p as usize, t, data));
                    }
                }
            } else {
                let (l, r) = (n.first as usize, n.first as usize + 1);
                let tl = self.nodes[l].bounds.hit(ray, inv, t_min, t_max);
                let tr = self.nodes[r].bounds.hit(ray, inv, t_min, t_max);
                match (tl, tr) {
                    (Some(a), Some(b)) => {
                        let (near, far) = if a <= b { (l, r) } else { (r, l) };
                        if sp < stack.len() {
                            stack[sp] = far as u32;
                            sp += 1;
                        }
                        node = near;
                        continue;
                    }
                    (Some(_), None) => {
                        node = l;
                        continue;
                    }
                    (None, Some(_)) => {
                        node = r;
                        continue;
                    }
                    (None, None) => {}
                }
            }
            // Pop the next node that can still hold something closer.
            loop {
                if sp == 0 {
                    return best;
                }
                sp -= 1;
                let cand = stack[sp] as usize;
                if self.nodes[cand]
                    .bounds
                    .hit(ray, inv, t_min, t_max)
                    .is_some()
                {
                    node = cand;
                    break;
                }
            }
        }
    }

    /// Any hit: stops at the first primitive `test` accepts (shadow rays).
    pub fn any(
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
        let inv = ray.dir.recip();
        let mut stack = [0u32; 64];
        let mut sp = 1usize;
        while sp > 0 {
            sp -= 1;
            let n = self.nodes[stack[sp] as usize];
            *visited += 1;
            if n.bounds.hit(ray, inv, t_min, t_max).is_none() {
                continue;
            }
            if n.count > 0 {
                for &p in &self.prims[n.first as usize..(n.first + n.count) as usize] {
                    if test(p as usize) {
                        return Some(p as usize);
                    }
                }
            } else if sp + 2 <= stack.len() {
                stack[sp] = n.first;
                stack[sp + 1] = n.first + 1;
                sp += 2;
            }
        }
        None
    }
}

/// Partitions `prims` by the cheapest binned SAH plane; `None` when a leaf is cheaper.
fn sah_split(
    boxes: &[Aabb],
    centroids: &[DVec3],
    prims: &mut [u32],
    bounds: Aabb,
) -> Option<usize> {
    let cb = prims
        .iter()
        .fold(Aabb::EMPTY, |b, &p| b.grow(centroids[p as usize]));
    let extent = cb.max - cb.min;
    let mut best: Option<(f64, usize, usize)> = None; // cost, axis, bin boundary
    for axis in 0..3 {
        if extent[axis] <= 0.0 {
            continue;
        }
        let scale = BINS as f64 / extent[axis];
        let bin_of = |p: u32| {
            (((centroids[p as usize][axis] - cb.min[axis]) * scale) as usize).min(BINS - 1)
        };
        let mut bin_box = [Aabb::EMPTY; BINS];
        let mut bin_n = [0usize; BINS];
        for &p in prims.iter() {
            let b = bin_of(p);
            bin_box[b] = bin_box[b].union(boxes[p as usize]);
            bin_n[b] += 1;
        }
        // Sweep from the right to get the right-hand areas, then from the left.
        let mut right_area = [0.0; BINS];
        let (mut acc, mut n) = (Aabb::EMPTY, 0usize);
        let mut right_n = [0usize; BINS];
        for i in (1..BINS).rev() {
            acc = acc.union(bin_box[i]);
            n += bin_n[i];
            right_area[i] = acc.surface_area();
            right_n[i] = n;
        }
        let (mut acc, mut n) = (Aabb::EMPTY, 0usize);
        for i in 0..BINS - 1 {
            acc = acc.union(bin_box[i]);
            n += bin_n[i];
            if n == 0 || right_n[i + 1] == 0 {
                continue;
            }
            let cost = acc.surface_area() * n as f64 + right_area[i + 1] * right_n[i + 1] as f64;
            if best.is_none_or(|b| cost < b.0) {
                best = Some((cost, axis, i + 1));
            }
        }
    }
    let (cost, axis, boundary) = best?;
    // Traversal costs about one box test per child; compare against testing everything.
    if cost / bounds.surface_area().max(1e-300) + 1.0 >= prims.len() as f64 && prims.len() <= 16 {
        return None;
    }
    let scale = BINS as f64 / extent[axis];
    let mut i = 0;
    let mut j = prims.len();
    while i < j {
        let b =
            (((centroids[prims[i] as usize][axis] - cb.min[axis]) * scale) as usize).min(BINS - 1);
        if b < boundary {
            i += 1;
        } else {
            j -= 1;
            prims.swap(i, j);
        }
    }
    (i > 0 && i < prims.len()).then_some(i)
}
