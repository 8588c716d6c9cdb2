//! Finding the closest object along a ray: the lecture's "for every object" loop
//! ([`AccelKind::Linear`]) or a bounding volume hierarchy over the objects' world bounds
//! ([`AccelKind::Bvh`], meshes carrying their own BVH over their triangles inside).

mod bundle;
mod bvh;
pub mod isa;
mod lanes;
pub mod pages;

pub use bundle::{Bits, BundleAnyLeaf, BundleLeaf, BundleWork, RayBundle, BUNDLE, FEW};
pub use bvh::{Bvh, Node, WIDTH};
pub use lanes::{count, F32s, F64s, LANES};

use crate::math::Ray;
use crate::mistakes::{Mistake, Mistakes};
use crate::scene::Object;
use crate::shapes::{Aabb, LocalHit};
use crate::trace::Recorder;
use isa::Kernel;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AccelKind {
    Linear,
    Bvh,
}

impl AccelKind {
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

    // ANCHOR: closest_bundle
    /// [`Accel::closest`] for each of up to [`BUNDLE`] rays (t in [t_min, ∞)), the rays
    /// walking the scene's BVH and each mesh's BVH together. Same tie rule (closest, then
    /// lower object index), so the same answers; `cost` gets what it took.
    pub fn closest_bundle(
        &self,
        objects: &[Object],
        rays: &[Ray],
        t_min: f64,
        cost: &mut BundleCost,
    ) -> [Option<(usize, LocalHit)>; BUNDLE] {
        let mut best = [None; BUNDLE];
        self.closest_bundle_into(objects, rays, t_min, cost, &mut best);
        best
    }

    /// [`Accel::closest_bundle`], the hits written into `best` (its first `rays.len()`
    /// lanes, the others left as they were), which saves copying sixteen hit records around.
    pub fn closest_bundle_into(
        &self,
        objects: &[Object],
        rays: &[Ray],
        t_min: f64,
        cost: &mut BundleCost,
        best: &mut [Option<(usize, LocalHit)>; BUNDLE],
    ) {
        best.iter_mut().take(rays.len()).for_each(|b| *b = None);
        isa::run(ObjectLeaf {
            accel: self,
            objects,
            rays,
            t_min,
            cost,
            best,
        })
    }
    // ANCHOR_END: closest_bundle
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

    /// [`Accel::occluded`]'s verdict for each of up to [`BUNDLE`] shadow rays, ray i within
    /// [t_min, t_max[i]], as a bit mask (bit i: ray i is blocked): the rays walk the scene's
    /// BVH and each mesh's BVH together ([`Bvh::any_bundle`]). `cost` gets the nodes opened.
    pub fn occluded_bundle(
        &self,
        objects: &[Object],
        rays: &[Ray],
        t_min: f64,
        t_max: &[f64; BUNDLE],
        cost: &mut BundleCost,
    ) -> u32 {
        isa::run(AnyObjectLeaf {
            accel: self,
            objects,
            rays,
            t_min,
            t_max,
            cost,
        })
    }
}

/// [`Accel::closest_bundle`]'s work, compiled at each SIMD width ([`isa::run`]): the
/// objects outside the BVH, then the walk, with the request itself as the walk's leaves.
impl Kernel for ObjectLeaf<'_> {
    type Output = ();
    #[inline(always)]
    fn run<W: isa::Wide>(mut self, w: W) {
        let (accel, rays, t_min) = (self.accel, self.rays, self.t_min);
        let all = bundle_mask(rays);
        let mut t_max = [f64::INFINITY; BUNDLE];
        for &i in &accel.unbounded {
            test_object_bundle(
                self.objects,
                i,
                rays,
                all,
                t_min,
                &mut t_max,
                self.best,
                self.cost,
            );
        }
        if accel.bvh.nodes.is_empty() {
            return;
        }
        let b = RayBundle::new(w, rays);
        let mut work = BundleWork::default();
        accel
            .bvh
            .closest_bundle(w, &b, all, t_min, &mut t_max, &mut work, &mut self);
        self.cost.opened += work.opened;
        for (n, w) in self.cost.nodes.iter_mut().zip(work.ray_nodes) {
            *n += w;
        }
    }
}

/// The scene's objects as the leaves of a bundle walk.
struct ObjectLeaf<'a> {
    accel: &'a Accel,
    objects: &'a [Object],
    rays: &'a [Ray],
    t_min: f64,
    best: &'a mut [Option<(usize, LocalHit)>; BUNDLE],
    cost: &'a mut BundleCost,
}

impl BundleLeaf for ObjectLeaf<'_> {
    #[inline(always)]
    fn test(&mut self, k: usize, rays: u32, t_max: &mut [f64; BUNDLE]) {
        let i = self.accel.bounded[self.accel.bvh.prims[k] as usize];
        test_object_bundle(
            self.objects,
            i,
            self.rays,
            rays,
            self.t_min,
            t_max,
            self.best,
            self.cost,
        );
    }
}

/// [`Accel::occluded_bundle`]'s work, compiled at each SIMD width: the objects outside the
/// BVH, then the walk, with the request itself as the walk's leaves.
impl Kernel for AnyObjectLeaf<'_> {
    type Output = u32;
    #[inline(always)]
    fn run<W: isa::Wide>(mut self, w: W) -> u32 {
        let (accel, rays, t_min, t_max) = (self.accel, self.rays, self.t_min, self.t_max);
        let all = bundle_mask(rays);
        let mut blocked = 0u32;
        for &i in &accel.unbounded {
            let mask = all & !blocked;
            blocked |= occluded_object_bundle(self.objects, i, rays, mask, t_min, t_max, self.cost);
        }
        if accel.bvh.nodes.is_empty() {
            return blocked;
        }
        let b = RayBundle::new(w, rays);
        let mut work = BundleWork::default();
        blocked |= accel
            .bvh
            .any_bundle(w, &b, all & !blocked, t_min, t_max, &mut work, &mut self);
        self.cost.opened += work.opened;
        blocked
    }
}

/// The scene's objects as the leaves of a shadow-ray bundle walk.
struct AnyObjectLeaf<'a> {
    accel: &'a Accel,
    objects: &'a [Object],
    rays: &'a [Ray],
    t_min: f64,
    t_max: &'a [f64; BUNDLE],
    cost: &'a mut BundleCost,
}

impl BundleAnyLeaf for AnyObjectLeaf<'_> {
    #[inline(always)]
    fn test(&mut self, k: usize, rays: u32) -> u32 {
        let i = self.accel.bounded[self.accel.bvh.prims[k] as usize];
        occluded_object_bundle(
            self.objects,
            i,
            self.rays,
            rays,
            self.t_min,
            self.t_max,
            self.cost,
        )
    }
}

/// Which shadow rays of a bundle (in `mask`) object `i` blocks: a mesh takes them through
/// its own BVH together, any other shape tests them one by one with its own routine.
fn occluded_object_bundle(
    objects: &[Object],
    i: usize,
    rays: &[Ray],
    mask: u32,
    t_min: f64,
    t_max: &[f64; BUNDLE],
    cost: &mut BundleCost,
) -> u32 {
    if mask == 0 {
        return 0;
    }
    let object = &objects[i];
    let mut moved = None;
    let local = in_object(object, rays, mask, &mut moved);
    if let crate::shapes::Shape::Mesh(m) = &object.shape {
        let mut work = BundleWork::default();
        let blocked = m.occluded_bundle(local, mask, t_min, t_max, &mut work);
        cost.opened += work.opened;
        return blocked;
    }
    let mut blocked = 0;
    for r in Bits(mask) {
        let hit = object
            .shape
            .occluded(&local[r], t_min, t_max[r], &mut crate::shapes::NoObserver);
        blocked |= (hit.is_some() as u32) << r;
    }
    blocked
}

/// Tests object `i` against the rays of a bundle in `mask` (each within [t_min, t_max[r]]),
/// keeping each ray's best by [`precedes`]. A mesh takes the rays through its own BVH
/// together; any other shape tests them one by one with its own routine.
#[allow(clippy::too_many_arguments)]
fn test_object_bundle(
    objects: &[Object],
    i: usize,
    rays: &[Ray],
    mask: u32,
    t_min: f64,
    t_max: &mut [f64; BUNDLE],
    best: &mut [Option<(usize, LocalHit)>; BUNDLE],
    cost: &mut BundleCost,
) {
    let object = &objects[i];
    let mut moved = None;
    let local = in_object(object, rays, mask, &mut moved);
    for r in Bits(mask) {
        cost.tests[r] += 1;
    }
    // The rays' limits as the object's walk starts (`keep` lowers them as hits come).
    let t = *t_max;
    // Ray r's hit on the object, kept if it precedes r's best so far.
    let mut keep = |r: usize, h: LocalHit| {
        let key = best[r].as_ref().map(|(o, b)| (b.t, *o));
        if precedes((h.t, i), key) {
            t_max[r] = h.t;
            best[r] = Some((i, h));
        }
    };
    match &object.shape {
        crate::shapes::Shape::Mesh(m) => {
            let mut work = BundleWork::default();
            let tests = &mut cost.tests;
            m.intersect_bundle(local, mask, t_min, t, &mut work, tests, keep);
            cost.opened += work.opened;
            for (c, w) in cost.nodes.iter_mut().zip(work.ray_nodes) {
                *c += w;
            }
        }
        shape => {
            for r in Bits(mask) {
                let mut no = crate::shapes::NoObserver;
                if let Some(h) = shape.intersect(&local[r], t_min, t[r], &mut no) {
                    keep(r, h);
                }
            }
        }
    }
}

/// The bundle's rays as `object` sees them: `rays` themselves when it is not moved (the
/// common case of a mesh placed as it was modelled), else [`to_object`]'s, kept in `moved`.
#[inline(always)]
fn in_object<'r>(
    object: &Object,
    rays: &'r [Ray],
    mask: u32,
    moved: &'r mut Option<[Ray; BUNDLE]>,
) -> &'r [Ray] {
    if object.transform.identity {
        rays
    } else {
        &moved.insert(to_object(object, rays, mask))[..rays.len()]
    }
}

/// A bundle's rays in `object`'s space: those in `mask` taken there, every other lane
/// filled with the first of them (never read as a ray of its own, and so no lane the mask
/// leaves out makes the bundle look less coherent than the rays it carries, or hides that
/// they share an origin). A bundle that reaches an object with few of its rays transforms
/// only those. (A plain loop over the mask's bits, inlined: built with `array::from_fn` and
/// left to the compiler, whether the 16 rays were copied out depended on how the crate fell
/// into codegen units.)
#[inline(always)]
fn to_object(object: &Object, rays: &[Ray], mask: u32) -> [Ray; BUNDLE] {
    let first = (mask.trailing_zeros() as usize).min(rays.len() - 1);
    let mut out = [object.transform.ray_to_object(&rays[first]); BUNDLE];
    for r in Bits(mask) {
        out[r] = object.transform.ray_to_object(&rays[r]);
    }
    out
}

/// The mask of a bundle's rays (bit i: ray i). A bundle holds at most [`BUNDLE`] rays: its
/// arrays have that many lanes.
fn bundle_mask(rays: &[Ray]) -> u32 {
    assert!(
        !rays.is_empty() && rays.len() <= BUNDLE,
        "a bundle holds 1 to {BUNDLE} rays, not {}",
        rays.len()
    );
    (1u32 << rays.len()) - 1
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
