use crate::mistakes::{Mistake, Mistakes};
use glam::DVec3;
use serde::Serialize;

/// What one light contributes to a shaded point: every factor of its term of the lighting
/// equation, kept so `explain` can print it and tests can add it up.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LightTerm {
    pub light: usize,
    /// Reached by at least one shadow ray (or shadows are off).
    pub visible: bool,
    /// Fraction of the light's samples that were not blocked (1 or 0 for point lights).
    pub visibility: f64,
    /// Distance to the light (mean over samples; infinite for directional lights).
    pub distance: f64,
    /// f_att = min(1, 1/(c1 + c2·d + c3·d²)), 1 for directional lights.
    pub attenuation: f64,
    /// Spot falloff factor (1 for other lights).
    pub spot: f64,
    pub n_dot_l: f64,
    pub diffuse: DVec3,
    pub r_dot_v: f64,
    /// (r·v)^n.
    pub r_dot_v_pow: f64,
    pub specular: DVec3,
}

/// The material colours at one point, with textures applied and global weights folded in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shading {
    /// ka·O_a.
    pub ambient: DVec3,
    /// kd·O_d, or (1 − blend)·kd·O_d + blend·texel.
    pub diffuse: DVec3,
    /// ks·O_s.
    pub specular: DVec3,
    pub shininess: f64,
    /// Non-refractive transparency scales every local term by (1 − kt·O_t).
    pub local_weight: DVec3,
}

impl Shading {
    /// One light sample's diffuse and specular terms at a point with unit normal `n` seen from
    /// direction `v` (unit, towards the viewer), before visibility:
    /// f_att·L·[kd·O_d·(n·l) + ks·O_s·(r·v)^n], with r = 2(n·l)n − l the mirrored light.
    pub fn light(
        &self,
        light_color: DVec3,
        l: DVec3,
        n: DVec3,
        v: DVec3,
        f_att: f64,
    ) -> (DVec3, DVec3, f64, f64, f64) {
        self.light_as(light_color, l, n, v, f_att, Mistakes::NONE)
    }

    // ANCHOR: light_term
    /// [`Shading::light`] under the catalogue's mistakes (none: the lecture's formula). Each
    /// mistake is the one-line variant next to the line it gets wrong.
    pub fn light_as(
        &self,
        light_color: DVec3,
        l: DVec3,
        n: DVec3,
        v: DVec3,
        f_att: f64,
        mistakes: Mistakes,
    ) -> (DVec3, DVec3, f64, f64, f64) {
        let n_dot_l = if mistakes.has(Mistake::NDotLUnclamped) {
            n.dot(l)
        } else {
            n.dot(l).max(0.0)
        };
        let diffuse = f_att * light_color * self.diffuse * n_dot_l * self.local_weight;
        let r = if mistakes.has(Mistake::ReflectSign) {
            l - 2.0 * n.dot(l) * n
        } else {
            2.0 * n.dot(l) * n - l
        };
        let r_dot_v = if mistakes.has(Mistake::BlinnPhong) {
            n.dot((l + v).normalize_or_zero()).max(0.0) // n·h, h the half vector
        } else {
            r.dot(v).max(0.0)
        };
        let shininess_ok = self.shininess > 0.0 || mistakes.has(Mistake::ShininessZero);
        let lit_side = n_dot_l > 0.0 || mistakes.has(Mistake::SpecularBehindLight);
        let (pow, specular) = if shininess_ok && lit_side {
            let pow = r_dot_v.powf(self.shininess);
            (
                pow,
                f_att * light_color * self.specular * pow * self.local_weight,
            )
        } else {
            (0.0, DVec3::ZERO) // shininess 0 means "no highlight", not x⁰ = 1 everywhere
        };
        (diffuse, specular, n_dot_l, r_dot_v, pow)
    }
    // ANCHOR_END: light_term
}
