//! The AOVs' samples: what one camera sample saw at its own first hit ([`AovSample`]), the
//! recorder that watches the one tracer to collect it ([`AovRecorder`]), and the walk over
//! the image's samples, tile by tile as `render` plans them ([`trace_aov_samples`]).

use crate::math::Ray;
use crate::sampling::bundles::{bundled, trace_bundled, BundleTally, TilePlan};
use crate::sampling::pixel_samples;
use crate::sampling::sampler::planned_films_into;
use crate::sampling::tiles::tiles;
use crate::scene::{RenderSettings, Scene};
use crate::shading::{LightTerm, Shading};
use crate::trace::{
    camera_ray, trace_camera, CameraRay, CountObserver, End, Found, HitInfo, RayKind, Recorder,
};
use glam::{DVec2, DVec3};
use rayon::prelude::*;

/// The winning hit of the camera ray, as the AOVs need it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AovHit {
    pub object: usize,
    pub t: f64,
    pub normal: DVec3,
}

/// What one camera sample saw at its own first hit (the terms are those of the camera ray's
/// node, exactly as `explain` shows them).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct AovSample {
    pub hit: Option<AovHit>,
    pub albedo: DVec3,
    pub ambient: DVec3,
    pub diffuse: DVec3,
    pub specular: DVec3,
    pub reflection: DVec3,
    pub transmission: DVec3,
    /// Shadow rays cast from the first hit, and how many reached their light.
    pub shadow_rays: u32,
    pub shadow_reached: u32,
    /// Deepest reflection/refraction level reached (0: the camera ray only).
    pub ray_depth: u32,
    /// Intersection tests + BVH nodes visited, over the whole tree of the sample.
    pub cost: u64,
}

/// Watches one sample: the camera ray's own events (open == 1) fill the terms; every ray
/// adds to the cost and the depth.
#[derive(Debug, Default)]
pub struct AovRecorder {
    pub sample: AovSample,
    /// Rays begun and not yet ended: 1 while the camera ray itself is being shaded.
    open: u32,
    /// A shadow ray of the camera ray's hit is in flight.
    primary_shadow: bool,
    /// What meshes did inside: faces tested and nodes of their own BVHs.
    obs: CountObserver,
}

impl AovRecorder {
    /// Starts a new sample.
    pub fn reset(&mut self) {
        *self = AovRecorder::default();
    }

    /// The finished sample, its cost including the work inside meshes.
    pub fn take(&mut self) -> AovSample {
        let mut sample = std::mem::take(&mut self.sample);
        sample.cost += self.obs.faces + self.obs.nodes;
        sample
    }
}

impl Recorder for AovRecorder {
    type Obs = CountObserver;
    fn observer(&mut self) -> &mut CountObserver {
        &mut self.obs
    }
    fn begin_ray(&mut self, kind: RayKind, depth: u32, _ray: &Ray) {
        if kind == RayKind::Shadow {
            self.primary_shadow = self.open == 1;
        } else {
            self.sample.ray_depth = self.sample.ray_depth.max(depth);
        }
        self.open += 1;
    }
    fn tested(&mut self, _o: usize, _t: Option<f64>, _t_max: f64, _r: &Ray) {
        self.sample.cost += 1;
    }
    fn nodes_visited(&mut self, n: u32) {
        self.sample.cost += n as u64;
    }
    fn bundled(&mut self, tests: u32, nodes: u32) {
        self.sample.cost += tests as u64 + nodes as u64;
    }
    fn hit(&mut self, hit: &HitInfo) {
        if self.open == 1 {
            self.sample.hit = Some(AovHit {
                object: hit.object,
                t: hit.t,
                normal: hit.normal,
            });
        }
    }
    fn surface(&mut self, s: &Shading) {
        if self.open == 1 {
            self.sample.albedo = s.diffuse;
        }
    }
    fn ambient(&mut self, c: DVec3) {
        if self.open == 1 {
            self.sample.ambient += c;
        }
    }
    fn light(&mut self, term: &LightTerm) {
        if self.open == 1 {
            self.sample.diffuse += term.diffuse;
            self.sample.specular += term.specular;
        }
    }
    fn reflected(&mut self, c: DVec3) {
        if self.open == 1 {
            self.sample.reflection += c;
        }
    }
    fn transmitted(&mut self, c: DVec3) {
        if self.open == 1 {
            self.sample.transmission += c;
        }
    }
    fn end_ray(&mut self, _color: DVec3, end: End, _clamped: bool) {
        self.open -= 1;
        if self.open == 1 && self.primary_shadow {
            self.primary_shadow = false;
            self.sample.shadow_rays += 1;
            if end == End::Miss {
                self.sample.shadow_reached += 1;
            }
        }
    }
}

/// Every sample of every pixel, row-major, each with its film position: `T` is what is kept
/// of it (the whole [`AovSample`], or what one image needs of it).
pub struct AovSamples<T = AovSample> {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Vec<(DVec2, T)>>,
}

/// Traces every camera sample of the image with an [`AovRecorder`], tile by tile as `render`
/// does (tiles in parallel, gathered in order: the result does not depend on the thread
/// count). Where the render bundles ([`bundled`]), a tile goes block by block through the
/// film's own [`trace_bundled`], so each sample's cost is the share `--stats` counts for it.
/// Once `settings.cancel` is cancelled the rest is skipped: what comes back is then partial,
/// for the caller to throw away.
pub fn trace_aov_samples(scene: &Scene, settings: &RenderSettings) -> AovSamples {
    trace_kept(scene, settings, |s| s)
}

/// [`trace_aov_samples`], keeping of each sample only what `keep` makes of it: an image needs
/// a few numbers of a sample, not its whole record (a quarter of the memory).
pub fn trace_kept<T: Clone + Send>(
    scene: &Scene,
    settings: &RenderSettings,
    keep: impl Fn(AovSample) -> T + Sync,
) -> AovSamples<T> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let bundled = bundled(settings);
    let traced: Vec<_> = tiles(w, h)
        .into_par_iter()
        .map(|tile| {
            if settings.cancel.is_cancelled() {
                // The rest is skipped, and the caller throws it all away.
                let none = vec![Vec::new(); tile.len()];
                return (tile, none);
            }
            let mut rec = AovRecorder::default();
            let mut sample = |camera: &mut CameraRay, found: Option<Found>| {
                rec.reset();
                trace_camera(scene, settings, camera, found, &mut rec);
                (camera.film, keep(rec.take()))
            };
            // The render's own plan, whichever traversal: under --subsample only some pixels
            // trace, and the corners sampler's shared corners are traced once, by the pixel
            // that owns them. (The adaptive sampler decides while it traces: an AOV takes its
            // first level, the pixel's four fixed samples.)
            let plan = TilePlan::of(&tile, |x, y| {
                let mut films = Vec::new();
                if !planned_films_into(settings, w, h, x, y, &mut films) {
                    films = pixel_samples(settings.sampler, settings.spp, settings.seed, x, y);
                }
                films
            });
            // Each pixel's list holds exactly its samples (what `check_memory` counts).
            let mut out: Vec<Vec<(DVec2, T)>> = (0..tile.len())
                .map(|l| Vec::with_capacity(plan.samples_of(l) as usize))
                .collect();
            if bundled {
                let mut tally = BundleTally::default();
                let trace = |l: usize, _, _, camera: &mut CameraRay, found: Found| {
                    out[l].push(sample(camera, Some(found)));
                };
                trace_bundled(scene, settings, &tile, &plan, &mut tally, trace, |_| true);
            } else {
                'pixels: for (l, (x, y)) in tile.pixels().enumerate() {
                    for k in 0..plan.samples_of(l) {
                        if settings.cancel.is_cancelled() {
                            break 'pixels; // as the colour render: a pixel may hold thousands
                        }
                        let film = plan.sample(l, (x, y), k).0;
                        let mut camera = camera_ray(scene, settings, x, y, k, film);
                        out[l].push(sample(&mut camera, None));
                    }
                }
            }
            (tile, out)
        })
        .collect();
    let mut pixels = vec![Vec::new(); w as usize * h as usize];
    for (tile, out) in traced {
        for ((x, y), samples) in tile.pixels().zip(out) {
            pixels[(y * w + x) as usize] = samples;
        }
    }
    AovSamples {
        width: w,
        height: h,
        pixels,
    }
}
