use crate::math::Ray;
use crate::shading::{LightTerm, Shading};
use crate::shapes::{LocalHit, NoObserver, Observer};
use glam::DVec3;
use serde::Serialize;

/// Why a ray was cast.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum RayKind {
    Camera,
    Shadow,
    Reflection,
    Refraction,
    /// Straight through a non-refractive transparent surface.
    Transmission,
}

/// Why a ray's recursion stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum End {
    /// Nothing was hit: the background colour (for a shadow ray: the light is visible).
    Miss,
    /// Shaded, and every secondary ray it wanted was traced.
    Shaded,
    /// A reflection or refraction ray was wanted, but the maximum depth was reached.
    MaxDepth,
    /// A secondary ray would have carried less than `min_contribution`.
    Cutoff,
    /// Refraction was impossible (sin θt > 1): the transmitted ray was reflected instead.
    TotalInternalReflection,
    /// A shadow ray that hit an object before reaching its light.
    Blocked,
    /// A reflection or refraction ray was wanted, but the sample had already traced its ray
    /// budget (`max_rays`): the rest of its tree was cut.
    RayBudget,
}

/// The winning hit of a ray, with everything shading derived from it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HitInfo {
    pub object: usize,
    pub t: f64,
    pub point: DVec3,
    /// World-space outward normal (unit).
    pub normal: DVec3,
    /// The object-space ray and hit.
    pub local_ray: Ray,
    pub local: LocalHit,
}

/// Observes the tracer. Every method defaults to doing nothing, so a recorder implements
/// only what it keeps (the model is ripgrep's `Sink`).
pub trait Recorder {
    /// The observer handed to each shape's intersection routine.
    type Obs: Observer;
    /// True when the recorder keeps anything (lets the tracer skip work done only for it).
    const ACTIVE: bool = false;
    fn observer(&mut self) -> &mut Self::Obs;
    fn begin_ray(&mut self, _kind: RayKind, _depth: u32, _ray: &Ray) {}
    /// One object was tested (its working is in the observer); `t` is its hit, if any.
    fn tested(&mut self, _object: usize, _t: Option<f64>, _t_max: f64, _local_ray: &Ray) {}
    /// BVH nodes visited by one query.
    fn nodes_visited(&mut self, _n: u32) {}
    /// A camera ray whose closest hit a bundle found ([`crate::accel::Accel::closest_bundle`]):
    /// instead of each test and node, its share of the bundle's work, `tests` intersection
    /// tests (objects and faces) and `nodes` BVH nodes it was slab-tested at. Only counting
    /// recorders can follow a bundle; the others (explain) get single rays.
    fn bundled(&mut self, _tests: u32, _nodes: u32) {}
    fn hit(&mut self, _hit: &HitInfo) {}
    /// The material colours at the hit being shaded (textures applied, switches folded in).
    fn surface(&mut self, _s: &Shading) {}
    fn ambient(&mut self, _c: DVec3) {}
    fn light(&mut self, _term: &LightTerm) {}
    /// A light the settings leave out (`directional_only`): its term as it would have been,
    /// unshadowed, which the colour does not include.
    fn ignored_light(&mut self, _term: &LightTerm) {}
    fn reflected(&mut self, _c: DVec3) {}
    fn transmitted(&mut self, _c: DVec3) {}
    /// A refraction child carries only one colour channel (dispersion).
    fn channel(&mut self, _channel: usize) {}
    /// The weight the next child ray's colour will be multiplied by (ks·Or, kt·Ot, ...).
    fn weight(&mut self, _w: DVec3) {}
    fn end_ray(&mut self, _color: DVec3, _end: End, _clamped: bool) {}
}

/// The recorder of `render`: keeps nothing.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoRecorder(NoObserver);

impl Recorder for NoRecorder {
    type Obs = NoObserver;
    #[inline(always)]
    fn observer(&mut self) -> &mut NoObserver {
        &mut self.0
    }
}
