//! Finding the closest object along a ray: the lecture's "for every object" loop
//! ([`AccelKind::Linear`]) or a bounding volume hierarchy over the objects' world bounds
//! ([`AccelKind::Bvh`], meshes carrying their own BVH over their triangles inside).

pub mod beam;
mod bundle;
mod bvh;
pub mod isa;
mod lanes;
mod objects;
pub mod pages;

pub use bundle::{
    bundle_working, Bits, BundleAnyLeaf, BundleLeaf, BundleWork, BundleWorking, RayBundle,
    RayVerdict, BUNDLE, FEW,
};
pub use bvh::{Bvh, Node, WIDTH};
pub use lanes::{count, F32s, F64s, LANES};

use crate::math::Ray;
use crate::mistakes::{Mistake, Mistakes};
use crate::scene::Object;
use crate::shapes::{Aabb, LocalHit};
use crate::trace::Recorder;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AccelKind {
    Linear,
    Bvh,
}

impl AccelKind {
    /// The names `parse` accepts.
    pub const NAMES: [&'static str; 2] = ["linear", "bvh"];

    pub fn parse(s: &str) -> Option<AccelKind> {
        match s {
            "linear" => Some(AccelKind::Linear),
            "bvh" => Some(AccelKind::Bvh),
            _ => None,
        }
    }
}

/// How camera rays walk the acceleration structures: one at a time, or in bundles of
/// [`BUNDLE`] neighbours ([`Accel::closest_bundle`]). The image is the same either way.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Traversal {
    Single,
    Bundle,
}

impl Traversal {
    /// The names `parse` accepts.
    pub const NAMES: [&'static str; 2] = ["single", "bundle"];

    pub fn parse(s: &str) -> Option<Traversal> {
        match s {
            "single" => Some(Traversal::Single),
            "bundle" => Some(Traversal::Bundle),
            _ => None,
        }
    }
}

/// What a bundle of camera rays cost: the nodes it opened (once for the bundle), and per
/// ray the intersection tests (objects and faces) and nodes it was slab-tested at, as
/// [`crate::trace::Counter`] counts them for a single ray.
#[derive(Debug, Clone, Copy, Default)]
pub struct BundleCost {
    pub opened: u32,
    pub tests: [u32; BUNDLE],
    pub nodes: [u32; BUNDLE],
}

/// The acceleration structure of a scene.
#[derive(Debug, Clone, Default)]
pub struct Accel {
    pub linear: bool,
    pub bvh: Bvh,
    /// Objects in the BVH, by BVH primitive index.
    pub bounded: Vec<usize>,
    /// Objects tested by every ray, before the BVH: those without bounds (planes), and a
    /// scene's only bounded object (its BVH would be one box around it).
    pub unbounded: Vec<usize>,
    /// Seconds [`Accel::build`] took (the meshes' own BVHs not included: [`Accel::build_seconds`]).
    pub own_build_seconds: f64,
}

// ANCHOR: object_test
/// Tests one object: the world ray goes into object space (t is shared, see [`Ray`]), the
/// shape's own routine runs with the recorder's observer, and the recorder hears the verdict.
/// `mistakes` are the catalogue's shape mistakes ([`Mistakes::NONE`]: the correct test).
#[inline]
pub fn test_object_as<R: Recorder>(
    objects: &[Object],
    i: usize,
    ray: &Ray,
    t_min: f64,
    t_max: f64,
    mistakes: Mistakes,
    rec: &mut R,
) -> Option<LocalHit> {
    let object = &objects[i];
    let local_ray = object.transform.ray_to_object(ray);
    let hit = object
        .shape
        .intersect_as(&local_ray, t_min, t_max, mistakes, rec.observer());
    rec.tested(i, hit.map(|h| h.t), t_max, &local_ray);
    hit
}
// ANCHOR_END: object_test

/// [`test_object_as`] without mistakes: the test every correct render runs.
#[inline]
pub fn test_object<R: Recorder>(
    objects: &[Object],
    i: usize,
    ray: &Ray,
    t_min: f64,
    t_max: f64,
    rec: &mut R,
) -> Option<LocalHit> {
    test_object_as(objects, i, ray, t_min, t_max, Mistakes::NONE, rec)
}

// ANCHOR: object_any
/// The any-hit twin of [`test_object`], for shadow rays: the shape may stop at its first hit.
#[inline]
pub fn test_object_any<R: Recorder>(
    objects: &[Object],
    i: usize,
    ray: &Ray,
    t_min: f64,
    t_max: f64,
    rec: &mut R,
) -> Option<LocalHit> {
    let object = &objects[i];
    let local_ray = object.transform.ray_to_object(ray);
    let hit = object
        .shape
        .occluded(&local_ray, t_min, t_max, rec.observer());
    rec.tested(i, hit.map(|h| h.t), t_max, &local_ray);
    hit
}
// ANCHOR_END: object_any

impl Accel {
    /// Seconds it took to build everything a scene's rays traverse: this structure and each
    /// mesh's own BVH and packed faces (each mesh once, however many objects or CSG children
    /// share it), as each was timed when it was built (for `--stats`, which builds nothing
    /// again).
    pub fn build_seconds(&self, objects: &[Object]) -> f64 {
        use crate::shapes::{Mesh, Shape};
        use std::collections::HashMap;
        fn meshes(shape: &Shape, seen: &mut HashMap<*const Mesh, f64>) {
            match shape {
                Shape::Mesh(m) => {
                    seen.insert(std::sync::Arc::as_ptr(m), m.build_seconds);
                }
                Shape::Csg(c) => c.children.iter().for_each(|k| meshes(&k.shape, seen)),
                _ => {}
            }
        }
        let mut seen = HashMap::new();
        objects.iter().for_each(|o| meshes(&o.shape, &mut seen));
        self.own_build_seconds + seen.values().sum::<f64>()
    }

    pub fn build(kind: AccelKind, objects: &[Object]) -> Accel {
        let start = std::time::Instant::now();
        let mut accel = Accel {
            linear: kind == AccelKind::Linear,
            ..Default::default()
        };
        let mut boxes: Vec<Aabb> = Vec::new();
        for (i, o) in objects.iter().enumerate() {
            match o.bounds {
                Some(b) if !accel.linear => {
                    accel.bounded.push(i);
                    boxes.push(b);
                }
                _ => accel.unbounded.push(i),
            }
        }
        // One bounded object (a scene that is one mesh, say) gets no tree: its box would be
        // tested twice, once here and once at the root of its own BVH.
        if boxes.len() == 1 {
            accel.unbounded.append(&mut accel.bounded);
            accel.unbounded.sort_unstable();
        } else if !accel.linear {
            accel.bvh = Bvh::build(&boxes);
        }
        accel.own_build_seconds = start.elapsed().as_secs_f64();
        accel
    }

    // ANCHOR: closest
    /// The closest hit with t in [t_min, t_max]: each test narrows t_max to the best t so far.
    /// Equal t (coincident surfaces) goes to the lower object index, whatever order the
    /// objects were tested in, so the linear loop and the BVH always pick the same object.
    /// With the linear list (`unbounded` then holds every object) this is the lecture's loop.
    pub fn closest<R: Recorder>(
        &self,
        objects: &[Object],
        ray: &Ray,
        t_min: f64,
        mut t_max: f64,
        rec: &mut R,
    ) -> Option<(usize, LocalHit)> {
        if let ([i], true) = (self.unbounded.as_slice(), self.bvh.nodes.is_empty()) {
            // One object and no tree (a scene that is one mesh): nothing to compare.
            return test_object(objects, *i, ray, t_min, t_max, rec).map(|h| (*i, h));
        }
        let mut best: Option<(usize, LocalHit)> = None;
        let mut key: Option<(f64, usize)> = None;
        for &i in &self.unbounded {
            if let Some(h) = test_object(objects, i, ray, t_min, t_max, rec) {
                if precedes((h.t, i), key) {
                    t_max = h.t;
                    key = Some((h.t, i));
                    best = Some((i, h));
                }
            }
        }
        if self.bvh.nodes.is_empty() {
            return best;
        }
        let mut visited = 0;
        // The BVH keeps what the closure returns, so return only hits that beat the best.
        let found = self
            .bvh
            .closest(ray, t_min, t_max, &mut visited, |k, t_max| {
                let i = self.bounded[self.bvh.prims[k] as usize];
                let h = test_object(objects, i, ray, t_min, t_max, rec)?;
                precedes((h.t, i), key).then(|| {
                    key = Some((h.t, i));
                    (h.t, (i, h))
                })
            });
        rec.nodes_visited(visited);
        found.map(|(_, hit)| hit).or(best)
    }
    // ANCHOR_END: closest

    /// [`Accel::closest`] under the catalogue's mistakes. `cap-radius` grows caps past the
    /// bounds the BVH trusts and `object-space-t` compares t values the BVH's boxes do not
    /// measure, so under them every object is tested, the lecture's loop; `object-space-t`
    /// then ranks each hit by its t along the object-space direction made unit length,
    /// t_object = t·|M⁻¹d| (the hit itself, point and normal, stays right).
    #[inline]
    pub fn closest_as<R: Recorder>(
        &self,
        objects: &[Object],
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        mistakes: Mistakes,
        rec: &mut R,
    ) -> Option<(usize, LocalHit)> {
        if !mistakes.changes_hits() {
            return self.closest(objects, ray, t_min, t_max, rec);
        }
        Accel::closest_every_object(objects, ray, t_min, t_max, mistakes, rec)
    }

    /// [`Accel::closest_as`] under a mistake that changes hits: the lecture's loop over every
    /// object. Out of line, so the renderer's own path stays small enough to inline.
    #[cold]
    #[inline(never)]
    fn closest_every_object<R: Recorder>(
        objects: &[Object],
        ray: &Ray,
        t_min: f64,
        mut t_max: f64,
        mistakes: Mistakes,
        rec: &mut R,
    ) -> Option<(usize, LocalHit)> {
        let object_t = mistakes.has(Mistake::ObjectSpaceT);
        let mut best: Option<(usize, LocalHit)> = None;
        let mut key: Option<(f64, usize)> = None;
        for i in 0..objects.len() {
            if let Some(h) = test_object_as(objects, i, ray, t_min, t_max, mistakes, rec) {
                let t = if object_t {
                    h.t * objects[i].transform.ray_to_object(ray).dir.length()
                } else {
                    h.t
                };
                if precedes((t, i), key) {
                    if !object_t {
                        t_max = h.t;
                    }
                    key = Some((t, i));
                    best = Some((i, h));
                }
            }
        }
        best
    }

    /// [`Accel::occluded`] under the catalogue's mistakes (`cap-radius`: every object).
    #[inline]
    pub fn occluded_as<R: Recorder>(
        &self,
        objects: &[Object],
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        mistakes: Mistakes,
        rec: &mut R,
    ) -> Option<(usize, LocalHit)> {
        if !(mistakes.has(Mistake::CapRadius) || mistakes.has(Mistake::ConeNormal)) {
            return self.occluded(objects, ray, t_min, t_max, rec);
        }
        Accel::occluded_every_object(objects, ray, t_min, t_max, mistakes, rec)
    }

    /// [`Accel::occluded_as`] under `cap-radius` or `cone-normal`: every object, in order.
    #[cold]
    #[inline(never)]
    fn occluded_every_object<R: Recorder>(
        objects: &[Object],
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        mistakes: Mistakes,
        rec: &mut R,
    ) -> Option<(usize, LocalHit)> {
        (0..objects.len()).find_map(|i| {
            test_object_as(objects, i, ray, t_min, t_max, mistakes, rec).map(|h| (i, h))
        })
    }

    // ANCHOR: occluded
    /// Any hit with t in [t_min, t_max] (shadow rays): the first object found, not the
    /// closest, and inside a mesh the first face found.
    #[inline]
    pub fn occluded<R: Recorder>(
        &self,
        objects: &[Object],
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        rec: &mut R,
    ) -> Option<(usize, LocalHit)> {
        for &i in &self.unbounded {
            if let Some(h) = test_object_any(objects, i, ray, t_min, t_max, rec) {
                return Some((i, h));
            }
        }
        let mut visited = 0;
        let mut found = None;
        self.bvh.any(ray, t_min, t_max, &mut visited, |k| {
            let i = self.bounded[self.bvh.prims[k] as usize];
            found = test_object_any(objects, i, ray, t_min, t_max, rec).map(|h| (i, h));
            found.is_some()
        });
        if !self.bvh.nodes.is_empty() {
            rec.nodes_visited(visited);
        }
        found
    }
    // ANCHOR_END: occluded
}

/// Does a hit (t, object index) come before the best so far? Closer first; on equal t the
/// lower object index, so the answer does not depend on the order objects were tested in.
#[inline]
fn precedes((t, i): (f64, usize), best: Option<(f64, usize)>) -> bool {
    match best {
        None => true,
        Some((bt, bi)) => t < bt || (t == bt && i < bi),
    }
}
