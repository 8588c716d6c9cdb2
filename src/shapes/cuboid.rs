use super::working::short;
use super::{Candidate, LocalHit, Observer, ON_SHAPE_EPS};
use crate::math::Ray;
use glam::{DVec2, DVec3};

/// An axis-aligned box from `min` to `max`, intersected face by face (the slab method written
/// out as six plane candidates, each kept only if it lands inside its face).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cuboid {
    pub min: DVec3,
    pub max: DVec3,
}

const FACES: [[&str; 2]; 3] = [["x-min", "x-max"], ["y-min", "y-max"], ["z-min", "z-max"]];

/// The (axis, side) of a face name.
fn face_of(surface: &str) -> (usize, usize) {
    for (axis, names) in FACES.iter().enumerate() {
        for (side, name) in names.iter().enumerate() {
            if *name == surface {
                return (axis, side);
            }
        }
    }
    (0, 0)
}

impl Cuboid {
    pub fn intersect<O: Observer>(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        obs: &mut O,
    ) -> Option<LocalHit> {
        let c = Candidate::nearest(t_max, |f| self.candidates(ray, t_min, obs, f))?;
        Some(self.local_hit(c.t, c.point, c.surface))
    }

    /// The six face candidates, on their face or not, handed to `found` (and shown to the
    /// observer). Serves both the closest hit and the CSG interval query.
    pub fn candidates<O: Observer>(
        &self,
        ray: &Ray,
        t_min: f64,
        obs: &mut O,
        mut found: impl FnMut(Candidate),
    ) {
        let size = self.max - self.min;
        for axis in 0..3 {
            let d = ray.dir[axis];
            if d == 0.0 {
                continue; // parallel to this pair of faces: no root
            }
            for (side, plane) in [self.min[axis], self.max[axis]].into_iter().enumerate() {
                let t = (plane - ray.origin[axis]) / d;
                let mut point = ray.at(t);
                point[axis] = plane;
                let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
                let inside = |k: usize| {
                    let tol = ON_SHAPE_EPS * size[k].max(1.0);
                    point[k] >= self.min[k] - tol && point[k] <= self.max[k] + tol
                };
                let c = Candidate {
                    t,
                    point,
                    surface: FACES[axis][side],
                    on_shape: inside(u) && inside(v),
                    in_front: t >= t_min,
                };
                obs.candidate(c, || {
                    let k = if inside(u) { v } else { u };
                    let name = ["x", "y", "z"][k];
                    format!(
                        "{name} = {} is outside [{}, {}]: the plane is hit beside the face",
                        short(point[k]),
                        short(self.min[k]),
                        short(self.max[k])
                    )
                });
                found(c);
            }
        }
    }

    /// The surface record of a face candidate (its point already lies on the face's plane).
    pub(crate) fn local_hit(&self, t: f64, point: DVec3, surface: &'static str) -> LocalHit {
        let (axis, side) = face_of(surface);
        let mut normal = DVec3::ZERO;
        normal[axis] = if side == 0 { -1.0 } else { 1.0 };
        LocalHit {
            t,
            point,
            normal,
            uv: self.uv(point, axis, side),
            surface,
            barycentric: None,
            index: 0,
        }
    }

    /// Each face seen from outside: u to the right, v up (the course's cube convention).
    fn uv(&self, p: DVec3, axis: usize, side: usize) -> DVec2 {
        let q = (p - self.min) / (self.max - self.min); // 0..1 across the box
        let (x, y, z) = (q.x, q.y, q.z);
        let (u, v) = match (axis, side) {
            (0, 1) => (1.0 - z, y),
            (0, _) => (z, y),
            (1, 1) => (x, 1.0 - z),
            (1, _) => (x, z),
            (2, 1) => (x, y),
            _ => (1.0 - x, y),
        };
        DVec2::new(u, v)
    }
}
