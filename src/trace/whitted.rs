use super::budget::Budget;
use super::{End, HitInfo, RayKind, Recorder};
use crate::camera::RayGeneration;
use crate::math::{Ray, Rng};
use crate::mistakes::Mistake;
use crate::scene::{RenderSettings, Scene};
use crate::shading::optics::{reflect, refract};
use crate::shading::{LightTerm, Shading};
use glam::{DVec2, DVec3};

/// The recursive ray tracer over one scene with one set of render settings.
pub struct Tracer<'a> {
    pub scene: &'a Scene,
    pub settings: &'a RenderSettings,
    /// The rays this sample has traced, against `settings.max_rays`.
    budget: Budget<'a>,
}

/// One traced sample: where it was on the film and what colour it brought back.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampleResult {
    pub film: DVec2,
    pub color: DVec3,
    pub generation: RayGeneration,
    /// Rays the sample traced, of every kind.
    pub rays: u64,
    /// The ray budget (`settings.max_rays`) cut the tree: some node ends with
    /// [`End::RayBudget`] (or the render was cancelled).
    pub cut: bool,
}

/// Traces sample `index` at film position `film` of pixel (`px`, `py`). The sample's random
/// numbers (lens, area lights) come from (seed, pixel, sample index) alone.
pub fn trace_sample<R: Recorder>(
    scene: &Scene,
    settings: &RenderSettings,
    px: u32,
    py: u32,
    index: u32,
    film: DVec2,
    rec: &mut R,
) -> SampleResult {
    let mut camera = camera_ray(scene, settings, px, py, index, film);
    trace_camera(scene, settings, &mut camera, rec)
}

/// A sample's camera ray, made but not yet traced: the ray, how it was generated, the
/// sample's random stream after the lens sample, and (when a bundle of camera rays already
/// walked the scene, [`crate::sampling::bundles`]) its closest hit and what finding it cost.
#[derive(Debug, Clone)]
pub struct CameraRay {
    pub ray: Ray,
    pub generation: RayGeneration,
    pub rng: Rng,
    pub found: Option<Found>,
}

/// A camera ray's closest hit found in a bundle: exactly what `Accel::closest` returns for
/// it, with its share of the work (intersection tests, nodes it was tested at).
#[derive(Debug, Clone, Copy)]
pub struct Found {
    pub hit: Option<(usize, crate::shapes::LocalHit)>,
    pub tests: u32,
    pub nodes: u32,
}

/// The camera ray of sample `index` at `film` of pixel (`px`, `py`); its random numbers (lens,
/// then area lights) come from (seed, pixel, sample index) alone.
pub fn camera_ray(
    scene: &Scene,
    settings: &RenderSettings,
    px: u32,
    py: u32,
    index: u32,
    film: DVec2,
) -> CameraRay {
    let mut rng = Rng::new(&[settings.seed, px as u64, py as u64, index as u64]);
    let lens = scene.camera.lens_sample(settings.depth_of_field, &mut rng);
    let (ray, generation) = scene.camera.generate_as(film, lens, settings.mistakes);
    CameraRay {
        ray,
        generation,
        rng,
        found: None,
    }
}

/// Traces a camera ray ([`camera_ray`]); with its hit already found, the recorder hears the
/// bundle's share of the work ([`Recorder::bundled`]) instead of the walk.
/// The camera ray is borrowed, not moved: it is a few hundred bytes, and a tile's bundled
/// rays are traced where they lie.
pub fn trace_camera<R: Recorder>(
    scene: &Scene,
    settings: &RenderSettings,
    camera: &mut CameraRay,
    rec: &mut R,
) -> SampleResult {
    let CameraRay {
        ray,
        generation,
        rng,
        found,
    } = camera;
    let tracer = Tracer::new(scene, settings);
    let color = tracer.trace_found(
        ray,
        RayKind::Camera,
        0,
        DVec3::ONE,
        rng,
        rec,
        found.as_ref(),
    );
    SampleResult {
        film: generation.film,
        color,
        generation: *generation,
        rays: tracer.budget.rays(),
        cut: tracer.budget.cut(),
    }
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
    #[inline]
    fn trace_found<R: Recorder>(
        &self,
        ray: &Ray,
        kind: RayKind,
        depth: u32,
        weight: DVec3,
        rng: &mut Rng,
        rec: &mut R,
        found: Option<&Found>,
    ) -> DVec3 {
        rec.begin_ray(kind, depth, ray);
        self.budget.count();
        let scene = self.scene;
        let closest = match found {
            Some(f) => {
                rec.bundled(f.tests, f.nodes);
                f.hit
            }
            None => scene.accel.closest_as(
                &scene.objects,
                ray,
                0.0,
                f64::INFINITY,
                self.settings.mistakes,
                rec,
            ),
        };
        let Some((object, local)) = closest else {
            let color = self.settings.background;
            rec.end_ray(color, End::Miss, false);
            return color;
        };
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

    fn hit_info(&self, ray: &Ray, object: usize, local: crate::shapes::LocalHit) -> HitInfo {
        let o = &self.scene.objects[object];
        HitInfo {
            object,
            t: local.t,
            point: ray.at(local.t),
            normal: o
                .transform
                .normal_to_world_as(local.normal, self.settings.mistakes),
            local_ray: o.transform.ray_to_object(ray),
            local,
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

    // ANCHOR: shade
    /// The lighting equation at a hit:
    /// I = ka·La·Oa + Σ f_att·L·[kd·Od·(n·l) + ks·Os·(r·v)^n] + ks·Or·I_r + kt·Ot·I_t.
    fn shade<R: Recorder>(
        &self,
        ray: &Ray,
        hit: &HitInfo,
        depth: u32,
        weight: DVec3,
        rng: &mut Rng,
        rec: &mut R,
    ) -> (DVec3, End) {
        let scene = self.scene;
        let m = scene.material_of(hit.object);
        let d = ray.dir.normalize();
        let entering = hit.normal.dot(d) < 0.0;
        let n = if entering { hit.normal } else { -hit.normal }; // faces the incoming ray
        let v = -d;
        let (s, transmit) = self.surface(hit);
        rec.surface(&s);
        let eps = self.settings.epsilon * (1.0 + hit.point.abs().max_element());
        let above = hit.point + n * eps; // spawn point on the incoming side
        let below = hit.point - n * eps; // spawn point on the far side
        let mistakes = self.settings.mistakes;
        // `intersect-point-lights`: the lights the Intersect stage leaves out are lit anyway.
        let leaves_out = |light: &crate::shading::Light| {
            self.settings.directional_only
                && !light.is_directional()
                && !mistakes.has(Mistake::IntersectPointLights)
        };
        // `intersect-shadows`: shadow rays cast although the Intersect stage has none.
        let shadows = self.settings.shadows
            || (self.settings.directional_only && mistakes.has(Mistake::IntersectShadows));

        let ambient = if mistakes.has(Mistake::NoAmbient) {
            DVec3::ZERO // `no-ambient`
        } else if mistakes.has(Mistake::AmbientTimesLight) {
            // `ambient-times-light`: added once per light, times that light's colour.
            let lit: DVec3 = scene
                .lights
                .iter()
                .filter(|l| !leaves_out(l))
                .map(|l| l.color)
                .sum();
            scene.ambient_light * lit * s.ambient
        } else {
            scene.ambient_light * s.ambient
        };
        rec.ambient(ambient);
        let mut color = ambient;

        let lights = if self.settings.diffuse || self.settings.specular {
            &scene.lights[..]
        } else {
            &[]
        };
        for (li, light) in lights.iter().enumerate() {
            // Evaluated even when ignored, so the random numbers of an area light are drawn
            // the same way in render and explain.
            let ignored = leaves_out(light);
            let count = light.sample_count();
            let mut term = LightTerm {
                light: li,
                visible: false,
                visibility: 0.0,
                distance: 0.0,
                attenuation: 0.0,
                spot: 0.0,
                n_dot_l: 0.0,
                diffuse: DVec3::ZERO,
                r_dot_v: 0.0,
                r_dot_v_pow: 0.0,
                specular: DVec3::ZERO,
            };
            for k in 0..count {
                let ls = light.sample_as(hit.point, k, rng, mistakes);
                let share = ls.share;
                term.distance += ls.distance * share;
                term.attenuation += ls.f_att * share;
                term.spot += ls.spot * share;
                // `n-dot-l-unclamped` and `specular-behind-light` light the far side too.
                let faces_light = (n.dot(ls.l) > 0.0
                    || mistakes.has(Mistake::NDotLUnclamped)
                    || mistakes.has(Mistake::SpecularBehindLight))
                    && ls.spot > 0.0;
                // `shadow-acne`: the shadow ray starts on the surface itself.
                let origin = if mistakes.has(Mistake::ShadowAcne) {
                    hit.point
                } else {
                    above
                };
                let visible = faces_light
                    && (ignored
                        || !shadows
                        || self.shadow_ray(origin, ls.l, ls.distance, depth, rec));
                let (diffuse, specular, n_dot_l, r_dot_v, pow) = s.light_as(
                    light.color * ls.spot * share,
                    ls.l,
                    n,
                    v,
                    ls.f_att,
                    mistakes,
                );
                term.n_dot_l += n_dot_l * share;
                term.r_dot_v += r_dot_v * share;
                term.r_dot_v_pow += pow * share;
                if visible {
                    term.visible = true;
                    term.visibility += share;
                    term.diffuse += diffuse;
                    term.specular += specular;
                }
            }
            if ignored {
                rec.ignored_light(&term);
                continue;
            }
            rec.light(&term);
            color += term.diffuse + term.specular;
        }

        let mut end = End::Shaded;
        let can_recurse = depth < self.settings.max_depth;
        let spawn = |w: DVec3, end: &mut End| -> bool {
            if w.max_element() <= 0.0 {
                return false;
            }
            if !can_recurse {
                *end = End::MaxDepth;
                return false;
            }
            if (weight * w).max_element() < self.settings.min_contribution {
                if *end == End::Shaded {
                    *end = End::Cutoff;
                }
                return false;
            }
            if !self.budget.allows() {
                *end = End::RayBudget;
                return false;
            }
            true
        };

        // Reflection: ks·Or·I_r, the mirror ray from the incoming side.
        let w_reflect = if !self.settings.reflections {
            DVec3::ZERO
        } else if mistakes.has(Mistake::ReflectionWithoutKs) {
            m.reflective * s.local_weight // `reflection-without-ks`: Or alone
        } else {
            self.global().ks * m.reflective * s.local_weight
        };
        if spawn(w_reflect, &mut end) {
            // `reflection-acne`: from the surface itself; `reflect-sign`: −r.
            let origin = if mistakes.has(Mistake::ReflectionAcne) {
                hit.point
            } else {
                above
            };
            let dir = reflect(d, n);
            let dir = if mistakes.has(Mistake::ReflectSign) {
                -dir
            } else {
                dir
            };
            let r = Ray::new(origin, dir);
            rec.weight(w_reflect);
            let i_r = self.trace(
                &r,
                RayKind::Reflection,
                depth + 1,
                weight * w_reflect,
                rng,
                rec,
            );
            let c = w_reflect * i_r;
            rec.reflected(c);
            color += c;
        }

        // Transmission: kt·Ot·I_t, straight through or bent by Snell's law.
        if spawn(transmit, &mut end) {
            let mut c = DVec3::ZERO;
            if self.settings.course_refraction && m.refract {
                let mut st = CourseStep {
                    depth,
                    weight,
                    end: &mut end,
                };
                c = self.course_refraction(d, n, entering, hit, transmit, &mut st, rng, rec);
            } else if !m.refract {
                let t = Ray::new(below, d);
                rec.weight(transmit);
                c = transmit
                    * self.trace(
                        &t,
                        RayKind::Transmission,
                        depth + 1,
                        weight * transmit,
                        rng,
                        rec,
                    );
            } else {
                // One ray, or one per channel when the index differs per channel (dispersion).
                let channels: &[Option<usize>] = if m.is_dispersive() {
                    &[Some(0), Some(1), Some(2)]
                } else {
                    &[None]
                };
                for &ch in channels {
                    let ior = m.ior[ch.unwrap_or(0)];
                    // `refraction-eta-inverted`: η₂/η₁ instead of η₁/η₂.
                    let inverted = mistakes.has(Mistake::RefractionEtaInverted);
                    let eta = if entering != inverted { 1.0 / ior } else { ior };
                    let mask = match ch {
                        Some(k) => DVec3::AXES[k],
                        None => DVec3::ONE,
                    };
                    let w = transmit * mask;
                    if (weight * w).max_element() <= 0.0 {
                        continue; // a one-channel ray splits no further: other channels carry nothing
                    }
                    if !self.budget.allows() {
                        end = End::RayBudget;
                        break;
                    }
                    let t = match refract(d, n, eta) {
                        Some(dir) => Ray::new(below, dir),
                        None => {
                            end = End::TotalInternalReflection;
                            Ray::new(above, reflect(d, n))
                        }
                    };
                    if let Some(k) = ch {
                        rec.channel(k);
                    }
                    rec.weight(w);
                    c += w * self.trace(&t, RayKind::Refraction, depth + 1, weight * w, rng, rec);
                }
            }
            rec.transmitted(c);
            color += c;
        }
        (color, end)
    }
    // ANCHOR_END: shade

    // ANCHOR: course_refraction
    /// The course's refraction (FORMAT §8, `render.course_refraction`): bend in with
    /// η = 1/ior, follow the ray inside to where it leaves the same object (that surface is
    /// not shaded), bend out with η = ior and trace on; total internal reflection at either
    /// surface adds nothing. Weighted kt·Ot by the caller's `w`.
    #[allow(clippy::too_many_arguments)]
    fn course_refraction<R: Recorder>(
        &self,
        d: DVec3,
        n: DVec3,
        entering: bool,
        hit: &HitInfo,
        w: DVec3,
        st: &mut CourseStep,
        rng: &mut Rng,
        rec: &mut R,
    ) -> DVec3 {
        let ior = self.scene.material_of(hit.object).ior[0];
        let eps = |p: DVec3| self.settings.epsilon * (1.0 + p.abs().max_element());
        let (depth, weight) = (st.depth, st.weight);
        // Met from inside (a camera inside the object): one bend, out.
        let eta = if entering { 1.0 / ior } else { ior };
        let Some(d_in) = refract(d, n, eta) else {
            *st.end = End::TotalInternalReflection;
            return DVec3::ZERO;
        };
        let inner = Ray::new(hit.point - n * eps(hit.point), d_in);
        rec.weight(w);
        if !entering {
            return w * self.trace(&inner, RayKind::Refraction, depth + 1, weight * w, rng, rec);
        }
        // The inner segment: tested against this object only, recorded without shading.
        rec.begin_ray(RayKind::Refraction, depth + 1, &inner);
        let objects = &self.scene.objects;
        let Some(local) =
            crate::accel::test_object(objects, hit.object, &inner, 0.0, f64::INFINITY, rec)
        else {
            rec.end_ray(DVec3::ZERO, End::Miss, false);
            return DVec3::ZERO;
        };
        let exit = self.hit_info(&inner, hit.object, local);
        rec.hit(&exit);
        let n_exit = if exit.normal.dot(d_in) < 0.0 {
            exit.normal
        } else {
            -exit.normal
        };
        let Some(d_out) = refract(d_in, n_exit, ior) else {
            rec.end_ray(DVec3::ZERO, End::TotalInternalReflection, false);
            return DVec3::ZERO;
        };
        let out = Ray::new(exit.point - n_exit * eps(exit.point), d_out);
        rec.weight(DVec3::ONE);
        let i = self.trace(&out, RayKind::Refraction, depth + 1, weight * w, rng, rec);
        rec.end_ray(i, End::Shaded, false);
        w * i
    }
    // ANCHOR_END: course_refraction

    // ANCHOR: shadow
    /// Casts a shadow ray from `origin` towards a light `distance` away along `l`: the light
    /// is visible unless some object is hit first (any hit will do, not the closest).
    fn shadow_ray<R: Recorder>(
        &self,
        origin: glam::DVec3,
        l: DVec3,
        distance: f64,
        depth: u32,
        rec: &mut R,
    ) -> bool {
        let mistakes = self.settings.mistakes;
        // `shadow-ray-unnormalized`: the direction light − p, t still bounded by the distance.
        let ray = if mistakes.has(Mistake::ShadowRayUnnormalized) && distance.is_finite() {
            Ray::new(origin, l * distance)
        } else {
            Ray::new(origin, l)
        };
        rec.begin_ray(RayKind::Shadow, depth + 1, &ray);
        self.budget.count();
        let scene = self.scene;
        // `shadow-beyond-light`: blockers counted at any distance, past the light too.
        let t_max = if mistakes.has(Mistake::ShadowBeyondLight) {
            f64::INFINITY
        } else {
            distance
        };
        let blocker = scene
            .accel
            .occluded_as(&scene.objects, &ray, 0.0, t_max, mistakes, rec);
        match blocker {
            Some((object, local)) => {
                if R::ACTIVE {
                    rec.hit(&self.hit_info(&ray, object, local));
                }
                rec.end_ray(DVec3::ZERO, End::Blocked, false);
                false
            }
            None => {
                rec.end_ray(DVec3::ONE, End::Miss, false);
                true
            }
        }
    }
    // ANCHOR_END: shadow
}

/// Where a course refraction starts in the ray tree (for [`Tracer::course_refraction`]).
struct CourseStep<'e> {
    depth: u32,
    weight: DVec3,
    end: &'e mut End,
}
