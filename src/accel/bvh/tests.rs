//! The hierarchy's invariants, the slab test's conservativeness and the walks against brute force.

use super::binary::FBox;
use super::slab::*;
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
            let hit = boxes[bvh.prims[k] as usize].hit(&ray, inv, f64::NEG_INFINITY, f64::INFINITY);
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
