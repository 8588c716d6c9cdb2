//! The local terms of the lighting equation at a hit, and the shadow rays that decide
//! which lights reach it.

use super::shade::At;
use super::Tracer;
use crate::math::{Ray, Rng};
use crate::mistakes::Mistake;
use crate::shading::{LightTerm, Shading};
use crate::trace::{End, HitInfo, RayKind, Recorder};
use glam::DVec3;

impl Tracer<'_> {
    // ANCHOR: direct
    /// The local terms at a hit: ka·La·Oa, then for each light f_att·L·[kd·Od·(n·l) +
    /// ks·Os·(r·v)^n] where its shadow ray ([`Tracer::shadow_ray`]) reaches the light (an
    /// area light: the share of its samples that do).
    pub(super) fn direct<R: Recorder>(
        &self,
        hit: &HitInfo,
        s: &Shading,
        at: &At,
        depth: u32,
        rng: &mut Rng,
        rec: &mut R,
    ) -> DVec3 {
        let scene = self.scene;
        let (n, v, above) = (at.n, at.v, at.above);
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
        color
    }
    // ANCHOR_END: direct

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
                    rec.hit(&self.hit_info(&ray, object, &local));
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
