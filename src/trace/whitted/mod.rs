//! The Whitted recursion: one tracer, observed through its [`Recorder`].
//!
//! - this file: the tracer and `trace` (find the closest hit, shade it, clamp), and what a
//!   hit's surface is (materials, textures, the global weights);
//! - `camera`: a sample's camera ray, made and traced (alone, or with its hit found by a
//!   bundle of camera rays);
//! - `shade`: the lighting equation at a hit, and the rays it spawns (mirror, transmitted,
//!   refracted, the course's two-bend refraction);
//! - `light`: the local terms, ambient and each light's diffuse and specular, and the
//!   shadow rays that decide whether a light is seen.

mod camera;
mod light;
mod shade;

pub use camera::{
    camera_ray, camera_rays, trace_camera, trace_sample, CameraRay, Found, SampleResult,
};

use super::budget::Budget;
use super::{End, HitInfo, RayKind, Recorder};
use crate::math::{Ray, Rng};
use crate::mistakes::Mistake;
use crate::scene::{RenderSettings, Scene};
use crate::shading::Shading;
use glam::DVec3;

/// The recursive ray tracer over one scene with one set of render settings.
pub struct Tracer<'a> {
    pub scene: &'a Scene,
    pub settings: &'a RenderSettings,
    /// The rays this sample has traced, against `settings.max_rays`.
    budget: Budget<'a>,
}

impl<'a> Tracer<'a> {
    /// A tracer for one sample: its ray budget starts at zero.
    pub fn new(scene: &'a Scene, settings: &'a RenderSettings) -> Tracer<'a> {
        Tracer {
            scene,
            settings,
            budget: Budget::new(settings.max_rays, &settings.cancel),
        }
    }

    // ANCHOR: trace
    /// Traces one ray and returns its colour. `weight` is the product of the weights on the
    /// path from the camera (for the `min_contribution` cutoff).
    pub fn trace<R: Recorder>(
        &self,
        ray: &Ray,
        kind: RayKind,
        depth: u32,
        weight: DVec3,
        rng: &mut Rng,
        rec: &mut R,
    ) -> DVec3 {
        self.trace_found(ray, kind, depth, weight, rng, rec, None)
    }

    /// [`Tracer::trace`], the closest hit given when a bundle found it already.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)] // with a counting recorder (`--stats`) it was not inlined, and the call cost a tenth of a bundled render
    pub(super) fn trace_found<R: Recorder>(
        &self,
        ray: &Ray,
        kind: RayKind,
        depth: u32,
        weight: DVec3,
        rng: &mut Rng,
        rec: &mut R,
        found: Option<Found>,
    ) -> DVec3 {
        rec.begin_ray(kind, depth, ray);
        self.budget.count();
        let scene = self.scene;
        // The hit is read where it lies (in the bundle's results, or here): it is copied
        // once, into the hit record.
        let walked;
        let closest = match found {
            Some(f) => {
                rec.bundled(f.tests, f.nodes);
                f.hit
            }
            None => {
                walked = scene.accel.closest_as(
                    &scene.objects,
                    ray,
                    0.0,
                    f64::INFINITY,
                    self.settings.mistakes,
                    rec,
                );
                walked.as_ref()
            }
        };
        let Some((object, local)) = closest else {
            let color = self.settings.background;
            rec.end_ray(color, End::Miss, false);
            return color;
        };
        self.shade_hit(ray, *object, local, depth, weight, rng, rec)
    }

    /// The rest of [`Tracer::trace_found`] for a ray that hit something: the hit record, the
    /// lighting equation and the rays it spawns, the clamp. (Not inlined: then a miss, three
    /// camera rays in four on a mesh in the middle of the image, costs only the lines above.)
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    fn shade_hit<R: Recorder>(
        &self,
        ray: &Ray,
        object: usize,
        local: &crate::shapes::LocalHit,
        depth: u32,
        weight: DVec3,
        rng: &mut Rng,
        rec: &mut R,
    ) -> DVec3 {
        let hit = self.hit_info(ray, object, local);
        rec.hit(&hit);
        let (color, end) = self.shade(ray, &hit, depth, weight, rng, rec);
        // `recursion-unclamped`: only the camera ray's colour is clamped.
        let clamp = self.settings.clamp_each_ray
            && !(depth > 0 && self.settings.mistakes.has(Mistake::RecursionUnclamped));
        let (color, clamped) = if clamp {
            let c = color.clamp(DVec3::ZERO, DVec3::ONE);
            (c, c != color)
        } else {
            (color, false)
        };
        rec.end_ray(color, end, clamped);
        color
    }
    // ANCHOR_END: trace

    fn hit_info(&self, ray: &Ray, object: usize, local: &crate::shapes::LocalHit) -> HitInfo {
        let o = &self.scene.objects[object];
        HitInfo {
            object,
            t: local.t,
            point: ray.at(local.t),
            normal: o
                .transform
                .normal_to_world_as(local.normal, self.settings.mistakes),
            local_ray: o.transform.ray_to_object(ray),
            local: *local,
        }
    }

    /// The global weights ka, kd, ks, kt (all 1 under `no-global-coefficients`).
    fn global(&self) -> crate::scene::Global {
        if self.settings.mistakes.has(Mistake::NoGlobalCoefficients) {
            let one = crate::scene::Global {
                ka: 1.0,
                kd: 1.0,
                ks: 1.0,
                kt: 1.0,
            };
            return one;
        }
        self.scene.global
    }

    /// The material colours at a hit, textures applied, global weights folded in.
    fn surface(&self, hit: &HitInfo) -> (Shading, DVec3) {
        let g = self.global();
        let m = self.scene.material_of(hit.object);
        let mut diffuse = g.kd * m.diffuse;
        if let (Some(tex), true) = (&m.texture, self.settings.textures) {
            let texel = tex.lookup_as(
                hit.local.uv,
                self.settings.texture_filter,
                self.settings.mistakes,
            );
            // `texture-times-diffuse`: the texel multiplied by kd·Od in its share of the blend.
            let texel = if self.settings.mistakes.has(Mistake::TextureTimesDiffuse) {
                texel * diffuse
            } else {
                texel
            };
            diffuse = (1.0 - tex.blend) * diffuse + tex.blend * texel;
        }
        let transmit = if self.settings.refractions {
            g.kt * m.transparent
        } else {
            DVec3::ZERO
        };
        // Non-refractive transparency: I = (1 − kt·Ot)·I_here + kt·Ot·I_behind.
        let local_weight = if m.refract {
            DVec3::ONE
        } else {
            DVec3::ONE - transmit
        };
        let on = |flag: bool| if flag { 1.0 } else { 0.0 };
        let st = self.settings;
        let shading = Shading {
            ambient: g.ka * m.ambient * local_weight * on(st.ambient),
            diffuse: diffuse * on(st.diffuse),
            specular: g.ks * m.specular * on(st.specular),
            shininess: m.shininess,
            local_weight,
        };
        (shading, transmit)
    }
}
