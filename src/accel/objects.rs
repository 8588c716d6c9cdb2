//! The scene's objects as the leaves of a bundle walk: [`Accel::closest_bundle`] and
//! [`Accel::occluded_bundle`], up to sixteen rays through the scene's BVH and, inside it,
//! each mesh's own, with the same tie rule as one ray's [`Accel::closest`] (closest, then
//! lower object index), so the same answers.

use super::bundle::{Bits, BundleAnyLeaf, BundleLeaf, BundleWork, RayBundle, BUNDLE};
use super::isa::{self, Kernel};
use super::{precedes, Accel, BundleCost};
use crate::math::Ray;
use crate::scene::Object;
use crate::shapes::LocalHit;

impl Accel {
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

    /// [`Accel::occluded`]'s verdict for each of up to [`BUNDLE`] shadow rays, ray i within
    /// `[t_min, t_max[i]]`, as a bit mask (bit i: ray i is blocked): the rays walk the scene's
    /// BVH and each mesh's BVH together ([`crate::accel::bvh::Bvh::any_bundle`]). `cost` gets the nodes opened.
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

/// Tests object `i` against the rays of a bundle in `mask` (each within `[t_min, t_max[r]]`),
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
