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
}
