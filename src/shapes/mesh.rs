use super::{cramer_hit, Aabb, LocalHit, Observer, Triangle};
use crate::math::Ray;
use glam::{DVec2, DVec3};

/// A triangle mesh in object space, with optional per-vertex normals and texture coordinates
/// (one index per corner, as OBJ files are flattened on load).
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    pub positions: Vec<DVec3>,
    pub normals: Vec<DVec3>,
    pub uvs: Vec<DVec2>,
    pub faces: Vec<[u32; 3]>,
    pub bounds: Aabb,
    /// A per-mesh bounding volume hierarchy over the faces (object space).
    pub bvh: crate::accel::Bvh,
}

impl Mesh {
    pub fn new(
        positions: Vec<DVec3>,
        normals: Vec<DVec3>,
        uvs: Vec<DVec2>,
        faces: Vec<[u32; 3]>,
    ) -> Mesh {
        let bounds = Aabb::around(&positions);
        let boxes: Vec<Aabb> = faces
            .iter()
            .map(|f| Aabb::around(&f.map(|i| positions[i as usize])))
            .collect();
        let bvh = crate::accel::Bvh::build(&boxes);
        Mesh {
            positions,
            normals,
            uvs,
            faces,
            bounds,
            bvh,
        }
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

    /// Closest face hit. The observer sees how many faces were tested, then the winning face's
    /// own Cramer working (re-solved, only for active observers).
    pub fn intersect<O: Observer>(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        obs: &mut O,
    ) -> Option<LocalHit> {
        let mut tested = 0usize;
        let found = self.bvh.closest(ray, t_min, t_max, |i, t_max| {
            tested += 1;
            let f = self.faces[i];
            let v = f.map(|k| self.positions[k as usize]);
            cramer_hit(&v, ray, t_min, t_max).map(|b| (b.t, b))
        });
        obs.mesh(tested, found.map(|(i, _)| i));
        let (index, b) = found?;
        let tri = self.triangle(index);
        if O::ACTIVE {
            // Report the winning face's working as a triangle would.
            tri.intersect(ray, t_min, t_max, obs);
        }
        Some(tri.local_hit(ray, &b, index as u32))
    }

    /// Every face the whole line P + t·d crosses (any t, in no particular order), with
    /// whether the line enters the solid there (d against the face's winding normal). The
    /// CSG interval query of a closed mesh; the test per face is the same Cramer solve.
    pub fn crossings(&self, ray: &Ray, mut found: impl FnMut(LocalHit, bool)) {
        let mut visited = 0;
        self.bvh
            .any(ray, f64::NEG_INFINITY, f64::INFINITY, &mut visited, |i| {
                let v = self.faces[i].map(|k| self.positions[k as usize]);
                if let Some(b) = cramer_hit(&v, ray, f64::NEG_INFINITY, f64::INFINITY) {
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
