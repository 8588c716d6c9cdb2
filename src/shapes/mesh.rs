use super::triangle::interpolated_hit;
use super::{
    cramer_hit_prepared, Aabb, Barycentric, FaceFrom, LocalHit, Numerators, Observer, Prepared,
    Triangle,
};
use crate::accel::isa::{self, Kernel, Wide};
use crate::accel::{
    count, Bits, BundleAnyLeaf, BundleLeaf, BundleWork, Bvh, F64s, RayBundle, BUNDLE,
};
use crate::math::Ray;
use glam::{DVec2, DVec3};

// ANCHOR: mesh
/// A triangle mesh in object space, with optional per-vertex normals and texture coordinates
/// (one index per corner, as OBJ files are flattened on load). Vertex positions are single
/// precision, as in OBJ readers and GPU pipelines: [`Mesh::new`] rounds them to f32 (and
/// keeps them as f64 holding those values), and everything is computed from them in f64.
///
/// It carries its own BVH over its faces, and every face's corners in f32 ([`PackedFace`],
/// 36 bytes) in the BVH's leaf order, so a leaf's faces sit next to each other in memory:
/// slot k of `packed` is face `bvh.prims[k]`.
#[derive(Debug, Clone)]
pub struct Mesh {
    pub positions: Vec<DVec3>,
    pub normals: Vec<DVec3>,
    pub uvs: Vec<DVec2>,
    pub faces: Vec<[u32; 3]>,
    pub bounds: Aabb,
    /// The bounding volume hierarchy over the faces (object space).
    pub bvh: Bvh,
    pub packed: Vec<PackedFace>,
    /// Seconds it took to build `bvh` and `packed` (for `--stats`).
    pub build_seconds: f64,
}

/// A mesh face as the BVH's leaves keep it: its three corners in f32. The mesh's positions
/// hold exactly these values, so [`PackedFace::prepared`] gives the same corner and edges,
/// bit for bit, as [`Prepared::new`] on the mesh's own corners, in half the bytes: on a
/// million triangles that do not fit in cache, bytes per face are time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PackedFace {
    pub corners: [[f32; 3]; 3],
}

impl PackedFace {
    fn new(v: &[DVec3; 3]) -> PackedFace {
        PackedFace {
            corners: v.map(|p| p.as_vec3().to_array()),
        }
    }

    /// The face ready for Cramer's rule: corner a and edges e1 = b − a, e2 = c − a in f64.
    #[inline(always)]
    pub fn prepared(&self) -> Prepared {
        Prepared::new(
            &self
                .corners
                .map(|c| DVec3::new(c[0] as f64, c[1] as f64, c[2] as f64)),
        )
    }
}

/// The nearest f32 value, kept as f64: how mesh vertices are stored.
pub fn single_precision(p: DVec3) -> DVec3 {
    p.as_vec3().as_dvec3()
}
// ANCHOR_END: mesh

impl Mesh {
    pub fn new(
        positions: Vec<DVec3>,
        normals: Vec<DVec3>,
        uvs: Vec<DVec2>,
        faces: Vec<[u32; 3]>,
    ) -> Mesh {
        let positions: Vec<DVec3> = positions.into_iter().map(single_precision).collect();
        let bounds = Aabb::around(&positions);
        let start = std::time::Instant::now();
        let (bvh, packed) = Mesh::build_bvh(&positions, &faces);
        let build_seconds = start.elapsed().as_secs_f64();
        Mesh {
            positions,
            normals,
            uvs,
            faces,
            bounds,
            bvh,
            packed,
            build_seconds,
        }
    }

    /// Builds the BVH over the faces and the packed faces in its leaf order (what `new`
    /// does; public so the benchmarks can time it alone). `positions` are single precision.
    pub fn build_bvh(positions: &[DVec3], faces: &[[u32; 3]]) -> (Bvh, Vec<PackedFace>) {
        use rayon::prelude::*;
        let corners = |f: &[u32; 3]| f.map(|i| positions[i as usize]);
        let bvh = Bvh::build_with(faces.len(), |i| Aabb::around(&corners(&faces[i])));
        // Rays read the faces at every leaf: huge pages, as the BVH's nodes.
        let mut packed = crate::accel::pages::vec_on_huge_pages(faces.len());
        packed.par_extend(
            bvh.prims
                .par_iter()
                .map(|&i| PackedFace::new(&corners(&faces[i as usize]))),
        );
        (bvh, packed)
    }

    /// The face as a standalone triangle (with its normals and uvs when the mesh has them).
    pub fn triangle(&self, index: usize) -> Triangle {
        let f = self.faces[index];
        let idx = f.map(|i| i as usize);
        Triangle {
            v: idx.map(|i| self.positions[i]),
            normals: (!self.normals.is_empty()).then(|| idx.map(|i| self.normals[i])),
            uvs: (!self.uvs.is_empty()).then(|| idx.map(|i| self.uvs[i])),
        }
    }

    /// Bytes held per face by the intersection structures (BVH nodes, leaf order, prepared
    /// faces), averaged; the vertex and face arrays come on top.
    pub fn accel_bytes(&self) -> usize {
        self.bvh.memory_bytes() + self.packed.len() * std::mem::size_of::<PackedFace>()
    }

    // ANCHOR: mesh_intersect
    /// Closest face hit. The observer sees how many faces were tested and how many BVH nodes
    /// were visited, then the winning face's own Cramer working (re-solved, only for active
    /// observers).
    pub fn intersect<O: Observer>(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        obs: &mut O,
    ) -> Option<LocalHit> {
        if t_min < 0.0 {
            return self.intersect_line(ray, t_min, t_max, obs);
        }
        self.intersect_in::<false, O>(ray, t_min, t_max, obs)
    }

    /// [`Mesh::intersect`] along a ray (`LINE` false) or a line.
    #[inline(always)]
    fn intersect_in<const LINE: bool, O: Observer>(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        obs: &mut O,
    ) -> Option<LocalHit> {
        let mut tested = 0usize;
        let mut visited = 0u32;
        // Equal t (a ray through an edge two faces share): the lower slot wins, whatever the
        // order they were tested in, so a bundle of rays ([`Mesh::intersect_bundle`]) that
        // walks the tree in another order picks the same face.
        let mut best_k = usize::MAX;
        let test = |k: usize, t_max: f64| {
            tested += 1;
            let b = cramer_hit_prepared(&self.packed[k].prepared(), ray, t_min, t_max)?;
            face_wins(b.t, k, t_max, best_k).then(|| {
                best_k = k;
                (b.t, b)
            })
        };
        let found = if LINE {
            self.bvh
                .closest_on_line(ray, t_min, t_max, &mut visited, test)
        } else {
            self.bvh.closest(ray, t_min, t_max, &mut visited, test)
        };
        obs.mesh(
            tested,
            found.as_ref().map(|(k, _)| self.bvh.prims[*k] as usize),
        );
        obs.bvh_nodes(visited);
        let (k, b) = found?;
        if O::ACTIVE {
            // Report the winning face's working as a triangle would.
            let index = self.bvh.prims[k] as usize;
            self.triangle(index).intersect(ray, t_min, t_max, obs);
        }
        Some(self.local_hit(ray, &b, k))
    }

    /// [`Mesh::intersect`] from a t_min below zero: the closest face hit along the line
    /// (the slice figures peel crossings off this way), through [`Bvh::closest_on_line`].
    #[cold]
    #[inline(never)]
    fn intersect_line<O: Observer>(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        obs: &mut O,
    ) -> Option<LocalHit> {
        self.intersect_in::<true, O>(ray, t_min, t_max, obs)
    }

    /// The hit on the face in BVH slot `k`: what [`Triangle::local_hit`] gives for that face,
    /// with the plane's normal taken from the packed corners already in cache (the same
    /// expression, so the same bits) rather than from the corners.
    fn local_hit(&self, ray: &Ray, b: &Barycentric, k: usize) -> LocalHit {
        let index = self.bvh.prims[k];
        let p = self.packed[k].prepared();
        let geometric = p.e1.cross(p.e2).normalize_or_zero();
        // The face's corner indices only when there is something to read at them: on a big
        // mesh each is a cache miss.
        let corners = || self.faces[index as usize].map(|i| i as usize);
        let normals = (!self.normals.is_empty()).then(|| corners().map(|i| self.normals[i]));
        let uvs = (!self.uvs.is_empty()).then(|| corners().map(|i| self.uvs[i]));
        interpolated_hit(ray, b, index, geometric, normals, uvs)
    }
    // ANCHOR_END: mesh_intersect

    // ANCHOR: mesh_bundle
    /// Closest face hits of a bundle of object-space rays (bit i of `active`: ray i takes
    /// part), each within [t_min, t_max[i]]: what [`Mesh::intersect`] gives each ray, found
    /// by one walk of the BVH for all of them ([`Bvh::closest_bundle`]) and handed to
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
    /// within [t_min, t_max[i]]: each ray's [`Mesh::occluded`] verdict, found by one walk of
    /// the BVH for all of them ([`Bvh::any_bundle`]), each face prepared once for the rays
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

    /// Any face hit within [t_min, t_max] (shadow rays): the first one found, not the
    /// closest. Active observers (explain) get the closest hit and its full working instead,
    /// so the blocker a student reads about is the nearest one; the verdict is the same.
    pub fn occluded<O: Observer>(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        obs: &mut O,
    ) -> Option<LocalHit> {
        if O::ACTIVE {
            return self.intersect(ray, t_min, t_max, obs);
        }
        let mut tested = 0usize;
        let mut visited = 0u32;
        let mut hit = None;
        let found = self.bvh.any(ray, t_min, t_max, &mut visited, |k| {
            tested += 1;
            hit = cramer_hit_prepared(&self.packed[k].prepared(), ray, t_min, t_max);
            hit.is_some()
        });
        obs.mesh(tested, found.map(|k| self.bvh.prims[k] as usize));
        obs.bvh_nodes(visited);
        let (k, b) = (found?, hit?);
        Some(self.local_hit(ray, &b, k))
    }

    /// Every face the whole line P + t·d crosses (any t, in no particular order), with
    /// whether the line enters the solid there (d against the face's winding normal). The
    /// CSG interval query of a closed mesh; the test per face is the same Cramer solve.
    pub fn crossings(&self, ray: &Ray, mut found: impl FnMut(LocalHit, bool)) {
        let mut visited = 0;
        self.bvh.any_on_line(ray, &mut visited, |k| {
            let i = self.bvh.prims[k] as usize;
            let (lo, hi) = (f64::NEG_INFINITY, f64::INFINITY);
            if let Some(b) = cramer_hit_prepared(&self.packed[k].prepared(), ray, lo, hi) {
                let tri = self.triangle(i);
                let entering = tri.geometric_normal().dot(ray.dir) < 0.0;
                found(tri.local_hit(ray, &b, i as u32), entering);
            }
            false // keep going: every crossing counts
        });
    }

    /// True when every edge is shared by exactly two faces (a closed, watertight surface):
    /// only then does the mesh bound a solid that CSG can combine.
    pub fn is_closed(&self) -> bool {
        use std::collections::HashMap;
        let key = |p: DVec3| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
        let mut edges: HashMap<([u64; 3], [u64; 3]), u32> = HashMap::new();
        for f in &self.faces {
            for k in 0..3 {
                let (a, b) = (
                    key(self.positions[f[k] as usize]),
                    key(self.positions[f[(k + 1) % 3] as usize]),
                );
                *edges
                    .entry(if a < b { (a, b) } else { (b, a) })
                    .or_default() += 1;
            }
        }
        !edges.is_empty() && edges.values().all(|&n| n == 2)
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
    /// within [t_min, t_max[i]]: exactly what [`cramer_hit_prepared`] says for that ray.
    #[inline(always)]
    fn hits(
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
                if let Some(w) = cramer_hit_prepared(&p, &b.rays[i], self.t_min, t_max[i]) {
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
    /// hits within [t_min, t_max[i]]: what [`Faces::hits`] says of each of them for that ray
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

/// Does face slot `k`, hit at `t` (no farther than `t_max`, the best t so far), take the
/// place of the best face so far, slot `best_k` (`usize::MAX`: none yet)? The closer one
/// wins; at an equal t (a ray through an edge two faces share) the lower slot, so the order
/// the faces are tested in (a single ray's or a bundle's) does not change the answer.
#[inline(always)]
fn face_wins(t: f64, k: usize, t_max: f64, best_k: usize) -> bool {
    t < t_max || k < best_k
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
        self.faces.hits(k, rays, t_max, |i, w, t_max| {
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
    fn seen(&mut self, node: usize, lane: usize, rays: u32) {
        (self.seen)(node, lane, rays)
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
            .hits(k, rays, &mut self.t_max, |i, _, _| blocked |= 1 << i);
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
