use super::triangle::interpolated_hit;
use super::{
    cramer_hit_plane_first, cramer_hit_prepared, Aabb, Barycentric, LocalHit, Observer, Prepared,
    Triangle,
};
use crate::accel::Bvh;
use crate::math::Ray;
use glam::{DVec2, DVec3};

mod bundle;

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
            hit = cramer_hit_plane_first(&self.packed[k].prepared(), ray, t_min, t_max);
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

/// Does face slot `k`, hit at `t` (no farther than `t_max`, the best t so far), take the
/// place of the best face so far, slot `best_k` (`usize::MAX`: none yet)? The closer one
/// wins; at an equal t (a ray through an edge two faces share) the lower slot, so the order
/// the faces are tested in (a single ray's or a bundle's) does not change the answer.
#[inline(always)]
fn face_wins(t: f64, k: usize, t_max: f64, best_k: usize) -> bool {
    t < t_max || k < best_k
}
