//! A mesh's faces as the leaves of a bundle walk ([`crate::accel::RayBundle`]): the closest
//! hits and the shadow-ray verdicts of up to sixteen rays from one walk of the mesh's BVH,
//! each face prepared once for the rays that reach it, every answer exactly the single
//! ray's ([`Mesh::intersect`], [`Mesh::occluded`]).

use super::{face_wins, Mesh};
use crate::accel::isa::{self, Kernel, Wide};
use crate::accel::{count, Bits, BundleAnyLeaf, BundleLeaf, BundleWork, F64s, RayBundle, BUNDLE};
use crate::math::Ray;
use crate::shapes::{
    cramer_hit_plane_first, cramer_hit_prepared, Barycentric, FaceFrom, LocalHit, Numerators,
};
use glam::DVec3;

impl Mesh {
    // ANCHOR: mesh_bundle
    /// Closest face hits of a bundle of object-space rays (bit i of `active`: ray i takes
    /// part), each within `[t_min, t_max[i]]`: what [`Mesh::intersect`] gives each ray, found
    /// by one walk of the BVH for all of them ([`Bvh::closest_bundle`](crate::accel::Bvh::closest_bundle)) and handed to
    /// `found(i, hit)` (a ray that hits nothing is not). A face reached by several rays is
    /// prepared once and tested against each, exactly as a single ray tests it. `work` gets
    /// the nodes; `tests[i]` the faces ray i tested.
    #[allow(clippy::too_many_arguments)]
    pub fn intersect_bundle(
        &self,
        rays: &[Ray],
        active: u32,
        t_min: f64,
        t_max: [f64; BUNDLE],
        work: &mut BundleWork,
        tests: &mut [u32; BUNDLE],
        found: impl FnMut(usize, LocalHit),
    ) {
        self.intersect_bundle_seen(rays, active, t_min, t_max, work, tests, |_, _, _| {}, found)
    }
    // ANCHOR_END: mesh_bundle

    /// [`Mesh::intersect_bundle`], telling `seen` which children of each opened node the
    /// bundle entered ([`crate::accel::BundleLeaf::seen`]; for the bundle figure).
    #[allow(clippy::too_many_arguments)]
    pub fn intersect_bundle_seen(
        &self,
        rays: &[Ray],
        active: u32,
        t_min: f64,
        t_max: [f64; BUNDLE],
        work: &mut BundleWork,
        tests: &mut [u32; BUNDLE],
        seen: impl FnMut(usize, usize, u32),
        found: impl FnMut(usize, LocalHit),
    ) {
        isa::run(ClosestFaces {
            mesh: self,
            rays,
            active,
            t_min,
            t_max,
            work,
            tests,
            seen,
            found,
        })
    }

    /// Which of a bundle of object-space shadow rays (bit i of `active`) some face blocks
    /// within `[t_min, t_max[i]]`: each ray's [`Mesh::occluded`] verdict, found by one walk of
    /// the BVH for all of them ([`Bvh::any_bundle`](crate::accel::Bvh::any_bundle)), each face prepared once for the rays
    /// that reach it.
    pub fn occluded_bundle(
        &self,
        rays: &[Ray],
        active: u32,
        t_min: f64,
        t_max: &[f64; BUNDLE],
        work: &mut BundleWork,
    ) -> u32 {
        isa::run(AnyFace {
            mesh: self,
            rays,
            active,
            t_min,
            t_max,
            work,
        })
    }
}

// ANCHOR: face_leaf
/// A mesh's faces as the leaves of a bundle walk. Each face a leaf holds is prepared once
/// for the rays that reached it; when they share their origin (a pinhole camera's rays),
/// the part of Cramer's rule that depends only on the face and the origin ([`FaceFrom`]) is
/// computed once too, and each ray adds three dot products, in one pass over the lanes when
/// enough rays are there to fill them.
struct Faces<'a, 'r, W> {
    w: W,
    mesh: &'a Mesh,
    b: &'a RayBundle<'r>,
    t_min: f64,
}

impl<W: Wide> Faces<'_, '_, W> {
    /// Calls `hit(i, weights, t_max)` for each ray i in `rays` that hits face slot `k`
    /// within `[t_min, t_max[i]]`: exactly what [`cramer_hit_prepared`] says for that ray.
    /// (`PLANE_FIRST`: rays from different points test each face's plane first,
    /// [`cramer_hit_plane_first`], as shadow rays do; the same answers.)
    #[inline(always)]
    fn hits<const PLANE_FIRST: bool>(
        &self,
        k: usize,
        rays: u32,
        t_max: &mut [f64; BUNDLE],
        mut hit: impl FnMut(usize, Barycentric, &mut [f64; BUNDLE]),
    ) {
        let p = self.mesh.packed[k].prepared();
        let b = self.b;
        if !b.shared_origin {
            for i in Bits(rays) {
                let (ray, t_min) = (&b.rays[i], self.t_min);
                let found = if PLANE_FIRST {
                    cramer_hit_plane_first(&p, ray, t_min, t_max[i])
                } else {
                    cramer_hit_prepared(&p, ray, t_min, t_max[i])
                };
                if let Some(w) = found {
                    hit(i, w, t_max);
                }
            }
            return;
        }
        let face = FaceFrom::new(&p, b.rays[0].origin);
        let m = |i: usize| -DVec3::new(b.dir[0].0[i], b.dir[1].0[i], b.dir[2].0[i]);
        if rays.count_ones() >= W::LEVEL.lanes_from() {
            let (inside, [det, beta, gamma]) = self.numerators_lanes(&face);
            for i in Bits(inside & rays) {
                let nums = Numerators {
                    determinant: det.0[i],
                    beta: beta.0[i],
                    gamma: gamma.0[i],
                };
                if let Some(w) = face.solve(&nums, self.t_min, t_max[i]) {
                    hit(i, w, t_max);
                }
            }
        } else {
            for i in Bits(rays) {
                let nums = face.numerators(m(i));
                if !nums.inside() {
                    continue;
                }
                if let Some(w) = face.solve(&nums, self.t_min, t_max[i]) {
                    hit(i, w, t_max);
                }
            }
        }
    }

    /// Calls `hit(k, weights, t_max)` for each face slot `k` of `ks`, in order, that ray `i`
    /// hits within `[t_min, t_max[i]]`: what [`Faces::hits`] says of each of them for that ray
    /// alone. A leaf's faces are taken [`SIDE_BY_SIDE`] at a time: the part of Cramer's rule
    /// that does not depend on t_max ([`FaceFrom`] and the [`Numerators`]) is computed for
    /// them together, lane by lane with the same operations as glam's `cross` and `dot` (so
    /// the same bits), and each face that passes the inside test is solved alone, in slot
    /// order, against the best t so far.
    #[inline(always)]
    fn hits_alone(
        &self,
        ks: std::ops::Range<usize>,
        i: usize,
        t_max: &mut [f64; BUNDLE],
        mut hit: impl FnMut(usize, Barycentric, &mut [f64; BUNDLE]),
    ) {
        let ray = &self.b.rays[i];
        let (o, m) = (ray.origin.to_array(), (-ray.dir).to_array());
        let mut first = ks.start;
        while first < ks.end {
            let n = (ks.end - first).min(SIDE_BY_SIDE);
            // Lanes past the leaf's last face repeat it (their answers are not read).
            let corner = |v: usize| -> [Side; 3] {
                std::array::from_fn(|ax| {
                    std::array::from_fn(|j| {
                        self.mesh.packed[first + j.min(n - 1)].corners[v][ax] as f64
                    })
                })
            };
            let (a, b, c) = (corner(0), corner(1), corner(2));
            let e1 = sub3(&b, &a);
            let e2 = sub3(&c, &a);
            let s: [Side; 3] = std::array::from_fn(|ax| std::array::from_fn(|j| o[ax] - a[ax][j]));
            let normal = cross3(&e1, &e2);
            let s_x_e2 = cross3(&s, &e2);
            let e1_x_s = cross3(&e1, &s);
            let (det, beta, gamma) = (dot3(&m, &normal), dot3(&m, &s_x_e2), dot3(&m, &e1_x_s));
            for j in 0..n {
                let nums = Numerators {
                    determinant: det[j],
                    beta: beta[j],
                    gamma: gamma[j],
                };
                if !nums.inside() {
                    continue;
                }
                let lane = |v: &[Side; 3]| DVec3::new(v[0][j], v[1][j], v[2][j]);
                let face = FaceFrom {
                    s: lane(&s),
                    n: lane(&normal),
                    s_x_e2: lane(&s_x_e2),
                    e1_x_s: lane(&e1_x_s),
                };
                if let Some(w) = face.solve(&nums, self.t_min, t_max[i]) {
                    hit(first + j, w, t_max);
                }
            }
            first += n;
        }
    }

    /// [`FaceFrom::numerators`] for all sixteen rays at once (the same products and sums in
    /// the same order: the dot products of glam's `DVec3`, lane by lane), and the rays for
    /// which [`Numerators::inside`] holds.
    #[inline(always)]
    fn numerators_lanes(&self, face: &FaceFrom) -> (u32, [F64s; 3]) {
        let (w, b) = (self.w, self.b);
        let m = [
            w.neg_d(w.load_d(&b.dir[0])),
            w.neg_d(w.load_d(&b.dir[1])),
            w.neg_d(w.load_d(&b.dir[2])),
        ];
        let det = dot_lanes(w, &m, face.n);
        let beta = dot_lanes(w, &m, face.s_x_e2);
        let gamma = dot_lanes(w, &m, face.e1_x_s);
        let zero = w.splat_d(0.0);
        let (inf, minus_inf) = (w.splat_d(f64::INFINITY), w.splat_d(f64::NEG_INFINITY));
        let positive = w.lt_d(zero, det) & w.lt_d(det, inf);
        let negative = w.lt_d(det, zero) & w.lt_d(minus_inf, det);
        let inside = (positive & w.le_d(zero, beta) & w.le_d(zero, gamma))
            | (negative & w.le_d(beta, zero) & w.le_d(gamma, zero));
        (inside, [w.store_d(det), w.store_d(beta), w.store_d(gamma)])
    }
}

/// Faces a lone ray tests side by side ([`Faces::hits_alone`]): a leaf holds two on most
/// meshes, up to eight.
const SIDE_BY_SIDE: usize = 4;

/// One coordinate of [`SIDE_BY_SIDE`] faces.
type Side = [f64; SIDE_BY_SIDE];

/// u − v, lane by lane.
#[inline(always)]
fn sub3(u: &[Side; 3], v: &[Side; 3]) -> [Side; 3] {
    std::array::from_fn(|ax| std::array::from_fn(|j| u[ax][j] - v[ax][j]))
}

/// u × v lane by lane, as glam's `DVec3::cross`: x = u.y·v.z − v.y·u.z, and so on.
#[inline(always)]
fn cross3(u: &[Side; 3], v: &[Side; 3]) -> [Side; 3] {
    let c = |p: usize, q: usize| -> Side {
        std::array::from_fn(|j| u[p][j] * v[q][j] - v[p][j] * u[q][j])
    };
    [c(1, 2), c(2, 0), c(0, 1)]
}

/// m · v for one vector m and each lane of v, as glam's `DVec3::dot`: (m.x·v.x + m.y·v.y) + m.z·v.z.
#[inline(always)]
fn dot3(m: &[f64; 3], v: &[Side; 3]) -> Side {
    std::array::from_fn(|j| (m[0] * v[0][j] + m[1] * v[1][j]) + m[2] * v[2][j])
}

/// m · v for the sixteen directions `m` (lane by lane) and one vector: glam's `DVec3::dot`,
/// (m.x·v.x + m.y·v.y) + m.z·v.z.
#[inline(always)]
fn dot_lanes<W: Wide>(w: W, m: &[W::D; 3], v: DVec3) -> W::D {
    let xy = w.add_d(w.mul_d(m[0], w.splat_d(v.x)), w.mul_d(m[1], w.splat_d(v.y)));
    w.add_d(xy, w.mul_d(m[2], w.splat_d(v.z)))
}

/// The closest-hit leaves: each ray's best face so far (closest t, then lowest slot, as
/// [`Mesh::intersect`] breaks ties).
struct ClosestLeaf<'a, 'r, W, S> {
    faces: Faces<'a, 'r, W>,
    best: [Option<(usize, Barycentric)>; BUNDLE],
    tests: &'a mut [u32; BUNDLE],
    seen: S,
}

/// Keeps face slot `k`, hit by ray `i` with weights `w`, if it wins over ray i's best so far
/// ([`face_wins`]), lowering its t_max.
#[inline(always)]
fn keep_face(
    best: &mut [Option<(usize, Barycentric)>; BUNDLE],
    i: usize,
    k: usize,
    w: Barycentric,
    t_max: &mut [f64; BUNDLE],
) {
    let best_k = best[i].as_ref().map_or(usize::MAX, |(bk, _)| *bk);
    if face_wins(w.t, k, t_max[i], best_k) {
        t_max[i] = w.t;
        best[i] = Some((k, w));
    }
}

impl<W: Wide, S: FnMut(usize, usize, u32)> BundleLeaf for ClosestLeaf<'_, '_, W, S> {
    #[inline(always)]
    fn test(&mut self, k: usize, rays: u32, t_max: &mut [f64; BUNDLE]) {
        count(self.tests, rays);
        let best = &mut self.best;
        self.faces.hits::<false>(k, rays, t_max, |i, w, t_max| {
            keep_face(best, i, k, w, t_max)
        });
    }

    /// The faces side by side ([`Faces::hits_alone`]): the same answers as `test` on each.
    #[inline(always)]
    fn test_alone(&mut self, ks: std::ops::Range<usize>, i: usize, t_max: &mut [f64; BUNDLE]) {
        self.tests[i] += ks.len() as u32;
        let best = &mut self.best;
        self.faces
            .hits_alone(ks, i, t_max, |k, w, t_max| keep_face(best, i, k, w, t_max));
    }

    #[inline(always)]
    fn prefetch(&self, ks: std::ops::Range<usize>) {
        isa::prefetch(&self.faces.mesh.packed[ks]);
    }

    const SEES: bool = true;
    #[inline(always)]
    fn seen(&mut self, node: usize, slot: usize, rays: u32) {
        (self.seen)(node, slot, rays)
    }
}

/// The any-hit leaves: a face blocks the rays it hits.
struct AnyLeaf<'a, 'r, W> {
    faces: Faces<'a, 'r, W>,
    /// The rays' t_max (a copy: `hits` may lower it, an any-hit never does).
    t_max: [f64; BUNDLE],
}

impl<W: Wide> BundleAnyLeaf for AnyLeaf<'_, '_, W> {
    #[inline(always)]
    fn test(&mut self, k: usize, rays: u32) -> u32 {
        let mut blocked = 0;
        self.faces
            .hits::<true>(k, rays, &mut self.t_max, |i, _, _| blocked |= 1 << i);
        blocked
    }
}
// ANCHOR_END: face_leaf

/// [`Mesh::intersect_bundle_seen`]'s work, compiled at each SIMD width ([`isa::run`]).
struct ClosestFaces<'a, 'r, S, F> {
    mesh: &'a Mesh,
    rays: &'r [Ray],
    active: u32,
    t_min: f64,
    t_max: [f64; BUNDLE],
    work: &'a mut BundleWork,
    tests: &'a mut [u32; BUNDLE],
    seen: S,
    found: F,
}

impl<S: FnMut(usize, usize, u32), F: FnMut(usize, LocalHit)> Kernel for ClosestFaces<'_, '_, S, F> {
    type Output = ();
    #[inline(always)]
    fn run<W: Wide>(self, w: W) {
        let ClosestFaces {
            mesh,
            rays,
            active,
            t_min,
            mut t_max,
            work,
            tests,
            seen,
            mut found,
        } = self;
        let b = RayBundle::new(w, rays);
        let mut leaf = ClosestLeaf {
            faces: Faces {
                w,
                mesh,
                b: &b,
                t_min,
            },
            best: [None; BUNDLE],
            tests,
            seen,
        };
        mesh.bvh
            .closest_bundle(w, &b, active, t_min, &mut t_max, work, &mut leaf);
        for i in Bits(active & b.all) {
            if let Some((k, w)) = leaf.best[i] {
                found(i, mesh.local_hit(&rays[i], &w, k));
            }
        }
    }
}

/// [`Mesh::occluded_bundle`]'s work, compiled at each SIMD width.
struct AnyFace<'a, 'r> {
    mesh: &'a Mesh,
    rays: &'r [Ray],
    active: u32,
    t_min: f64,
    t_max: &'a [f64; BUNDLE],
    work: &'a mut BundleWork,
}

impl Kernel for AnyFace<'_, '_> {
    type Output = u32;
    #[inline(always)]
    fn run<W: Wide>(self, w: W) -> u32 {
        let b = RayBundle::new(w, self.rays);
        let mut leaf = AnyLeaf {
            faces: Faces {
                w,
                mesh: self.mesh,
                b: &b,
                t_min: self.t_min,
            },
            t_max: *self.t_max,
        };
        self.mesh.bvh.any_bundle(
            w,
            &b,
            self.active,
            self.t_min,
            self.t_max,
            self.work,
            &mut leaf,
        )
    }
}
