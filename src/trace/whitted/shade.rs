//! The lighting equation at a hit and the rays it spawns: the local terms
//! ([`Tracer::direct`]), the mirror ray, and the transmitted or refracted one.

use super::Tracer;
use crate::math::{Ray, Rng};
use crate::mistakes::Mistake;
use crate::shading::optics::{reflect, refract};
use crate::trace::{End, HitInfo, RayKind, Recorder};
use glam::DVec3;

/// A hit as shading sees it: the incoming direction, the normal turned towards it, and the
/// two points new rays start from, ε off the surface on either side.
pub(super) struct At {
    /// Unit direction of the incoming ray.
    pub d: DVec3,
    /// Does the ray enter the object (meet its outer side)?
    pub entering: bool,
    /// The normal on the incoming side (n·d < 0).
    pub n: DVec3,
    /// Towards the viewer: −d.
    pub v: DVec3,
    /// Spawn points on the incoming side and on the far side.
    pub above: DVec3,
    pub below: DVec3,
}

/// How far off the surface at `p` a spawned ray starts: ε, scaled with the size of the
/// coordinates so that it stays above their rounding far from the origin.
fn offset(epsilon: f64, p: DVec3) -> f64 {
    epsilon * (1.0 + p.abs().max_element())
}

impl At {
    fn new(ray: &Ray, hit: &HitInfo, epsilon: f64) -> At {
        let d = ray.dir.normalize();
        let entering = hit.normal.dot(d) < 0.0;
        let n = if entering { hit.normal } else { -hit.normal }; // faces the incoming ray
        let eps = offset(epsilon, hit.point);
        At {
            d,
            entering,
            n,
            v: -d,
            above: hit.point + n * eps,
            below: hit.point - n * eps,
        }
    }
}

/// Where a spawned ray's parent sits in the ray tree: its depth, the product of the weights
/// from the camera to it, and its end reason, which a ray that cannot be spawned sets.
pub(super) struct Step<'e> {
    depth: u32,
    weight: DVec3,
    end: &'e mut End,
}

impl Tracer<'_> {
    // ANCHOR: shade
    /// The lighting equation at a hit:
    /// I = ka·La·Oa + Σ f_att·L·[kd·Od·(n·l) + ks·Os·(r·v)^n] + ks·Or·I_r + kt·Ot·I_t.
    /// The local terms come from [`Tracer::direct`]; `spawn` decides whether each of the two
    /// recursive rays is traced.
    pub(super) fn shade<R: Recorder>(
        &self,
        ray: &Ray,
        hit: &HitInfo,
        depth: u32,
        weight: DVec3,
        rng: &mut Rng,
        rec: &mut R,
    ) -> (DVec3, End) {
        let m = self.scene.material_of(hit.object);
        let at = At::new(ray, hit, self.settings.epsilon);
        let (s, transmit) = self.surface(hit);
        rec.surface(&s);
        let mut color = self.direct(hit, &s, &at, depth, rng, rec);
        let mistakes = self.settings.mistakes;

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
                at.above
            };
            let dir = reflect(at.d, at.n);
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
            let mut step = Step {
                depth,
                weight,
                end: &mut end,
            };
            let c = self.transmission(hit, &at, transmit, &mut step, rng, rec);
            rec.transmitted(c);
            color += c;
        }
        (color, end)
    }
    // ANCHOR_END: shade

    // ANCHOR: transmission
    /// The transmitted light kt·Ot·I_t (`w`): the course's two-bend refraction, a ray
    /// straight through a non-refractive surface, or a ray bent by Snell's law (one per
    /// colour channel when the index of refraction differs per channel).
    fn transmission<R: Recorder>(
        &self,
        hit: &HitInfo,
        at: &At,
        w: DVec3,
        step: &mut Step,
        rng: &mut Rng,
        rec: &mut R,
    ) -> DVec3 {
        let m = self.scene.material_of(hit.object);
        let (depth, weight) = (step.depth, step.weight);
        if self.settings.course_refraction && m.refract {
            return self.course_refraction(hit, at, w, step, rng, rec);
        }
        if !m.refract {
            let t = Ray::new(at.below, at.d);
            rec.weight(w);
            return w * self.trace(&t, RayKind::Transmission, depth + 1, weight * w, rng, rec);
        }
        let mistakes = self.settings.mistakes;
        let (d, n) = (at.d, at.n);
        let mut c = DVec3::ZERO;
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
            let eta = if at.entering != inverted {
                1.0 / ior
            } else {
                ior
            };
            let mask = match ch {
                Some(k) => DVec3::AXES[k],
                None => DVec3::ONE,
            };
            let w = w * mask;
            if (weight * w).max_element() <= 0.0 {
                continue; // a one-channel ray splits no further: other channels carry nothing
            }
            if !self.budget.allows() {
                *step.end = End::RayBudget;
                break;
            }
            let t = match refract(d, n, eta) {
                Some(dir) => Ray::new(at.below, dir),
                None => {
                    *step.end = End::TotalInternalReflection;
                    Ray::new(at.above, reflect(d, n))
                }
            };
            if let Some(k) = ch {
                rec.channel(k);
            }
            rec.weight(w);
            c += w * self.trace(&t, RayKind::Refraction, depth + 1, weight * w, rng, rec);
        }
        c
    }
    // ANCHOR_END: transmission

    // ANCHOR: course_refraction
    /// The course's refraction (FORMAT §8, `render.course_refraction`): bend in with
    /// η = 1/ior, follow the ray inside to where it leaves the same object (that surface is
    /// not shaded), bend out with η = ior and trace on; total internal reflection at either
    /// surface adds nothing. Weighted kt·Ot by the caller's `w`.
    fn course_refraction<R: Recorder>(
        &self,
        hit: &HitInfo,
        at: &At,
        w: DVec3,
        st: &mut Step,
        rng: &mut Rng,
        rec: &mut R,
    ) -> DVec3 {
        let (d, n, entering) = (at.d, at.n, at.entering);
        let ior = self.scene.material_of(hit.object).ior[0];
        let (depth, weight) = (st.depth, st.weight);
        // Met from inside (a camera inside the object): one bend, out.
        let eta = if entering { 1.0 / ior } else { ior };
        let Some(d_in) = refract(d, n, eta) else {
            *st.end = End::TotalInternalReflection;
            return DVec3::ZERO;
        };
        let inner = Ray::new(at.below, d_in);
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
        let exit = self.hit_info(&inner, hit.object, &local);
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
        let out = Ray::new(
            exit.point - n_exit * offset(self.settings.epsilon, exit.point),
            d_out,
        );
        rec.weight(DVec3::ONE);
        let i = self.trace(&out, RayKind::Refraction, depth + 1, weight * w, rng, rec);
        rec.end_ray(i, End::Shaded, false);
        w * i
    }
    // ANCHOR_END: course_refraction
}
