use crate::math::Rng;
use crate::mistakes::{Mistake, Mistakes};
use glam::DVec3;

/// The kinds of light of the lecture, plus the rectangular area light for soft shadows.
#[derive(Debug, Clone, PartialEq)]
pub enum LightKind {
    Point {
        position: DVec3,
    },
    /// `direction` is where the light travels (unit length).
    Directional {
        direction: DVec3,
    },
    /// `angle` is the outer half-angle and `penumbra` the width of the soft edge, in radians.
    Spot {
        position: DVec3,
        direction: DVec3,
        angle: f64,
        penumbra: f64,
    },
    /// A parallelogram `corner + s·edge_u + t·edge_v`, sampled on a `samples` grid.
    Area {
        corner: DVec3,
        edge_u: DVec3,
        edge_v: DVec3,
        samples: [u32; 2],
    },
}

#[derive(Debug, Clone, PartialEq)]
pub struct Light {
    pub name: String,
    pub kind: LightKind,
    pub color: DVec3,
    /// c1, c2, c3 of f_att = min(1, 1/(c1 + c2·d + c3·d²)).
    pub attenuation: [f64; 3],
}

/// One point of a light as seen from a shaded point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightSample {
    /// Unit vector from the surface towards the light.
    pub l: DVec3,
    /// Distance to the light (infinite for directional lights).
    pub distance: f64,
    /// f_att for point, spot and area lights; 1 for directional.
    pub f_att: f64,
    /// Spot falloff (1 outside spot lights).
    pub spot: f64,
    /// Fraction of the light's colour this sample carries (1/N for area lights).
    pub share: f64,
}

impl Light {
    /// Directional lights are the only ones the course's Intersect stage renders.
    pub fn is_directional(&self) -> bool {
        matches!(self.kind, LightKind::Directional { .. })
    }

    /// How many shadow rays this light needs per shaded point.
    pub fn sample_count(&self) -> usize {
        match self.kind {
            LightKind::Area { samples, .. } => (samples[0] * samples[1]) as usize,
            _ => 1,
        }
    }

    pub fn f_att(&self, d: f64) -> f64 {
        self.f_att_as(d, Mistakes::NONE)
    }

    // ANCHOR: f_att
    /// f_att = min(1, 1/(c1 + c2·d + c3·d²)); the catalogue's `no-attenuation` takes 1,
    /// `attenuation-unclamped` drops the min.
    pub fn f_att_as(&self, d: f64, mistakes: Mistakes) -> f64 {
        if mistakes.has(Mistake::NoAttenuation) {
            return 1.0;
        }
        let [c1, c2, c3] = self.attenuation;
        let denom = c1 + c2 * d + c3 * d * d;
        if denom <= 0.0 {
            1.0
        } else if mistakes.has(Mistake::AttenuationUnclamped) {
            1.0 / denom
        } else {
            (1.0 / denom).min(1.0)
        }
    }
    // ANCHOR_END: f_att

    // ANCHOR: light_sample
    /// Sample `k` of this light seen from `p`. Area lights are stratified: one jittered point
    /// per cell of their grid, from the sample's own random stream.
    pub fn sample(&self, p: DVec3, k: usize, rng: &mut Rng) -> LightSample {
        self.sample_as(p, k, rng, Mistakes::NONE)
    }

    /// [`Light::sample`] under the catalogue's light mistakes (none: the lecture's).
    pub fn sample_as(&self, p: DVec3, k: usize, rng: &mut Rng, mistakes: Mistakes) -> LightSample {
        match &self.kind {
            LightKind::Directional { direction } => LightSample {
                // `directional-not-negated`: the direction the light travels used as l.
                l: if mistakes.has(Mistake::DirectionalNotNegated) {
                    *direction
                } else {
                    -*direction
                },
                distance: f64::INFINITY,
                f_att: 1.0,
                spot: 1.0,
                share: 1.0,
            },
            LightKind::Point { position } => self.towards(p, *position, 1.0, 1.0, mistakes),
            LightKind::Spot {
                position,
                direction,
                angle,
                penumbra,
            } => {
                let mut s = self.towards(p, *position, 1.0, 1.0, mistakes);
                s.spot = spot_falloff_as(
                    (-s.l).dot(*direction).clamp(-1.0, 1.0).acos(),
                    *angle,
                    *penumbra,
                    mistakes,
                );
                s
            }
            LightKind::Area {
                corner,
                edge_u,
                edge_v,
                samples,
            } => {
                // Stratified: sample k lies in cell (k mod nu, k div nu) of the light's grid,
                // jittered by the camera sample's own random stream, so `explain` replays it.
                let (nu, nv) = (samples[0] as usize, samples[1] as usize);
                let (i, j) = (k % nu, k / nu);
                let su = (i as f64 + rng.next_f64()) / nu as f64;
                let sv = (j as f64 + rng.next_f64()) / nv as f64;
                let q = *corner + *edge_u * su + *edge_v * sv;
                self.towards(p, q, 1.0, 1.0 / (nu * nv) as f64, mistakes)
            }
        }
    }
    // ANCHOR_END: light_sample

    fn towards(
        &self,
        p: DVec3,
        q: DVec3,
        spot: f64,
        share: f64,
        mistakes: Mistakes,
    ) -> LightSample {
        let to = q - p;
        let distance = to.length();
        let l = if distance > 0.0 {
            to / distance
        } else {
            DVec3::Y
        };
        LightSample {
            l,
            distance,
            f_att: self.f_att_as(distance, mistakes),
            spot,
            share,
        }
    }
}

// ANCHOR: spot
/// Spot falloff at angle `x` from the axis: full inside `angle − penumbra`, zero outside
/// `angle`, and 1 − (3t² − 2t³) in between (t running 0 → 1 across the penumbra). Under the
/// catalogue's spot mistakes, `spot-full-angle` takes the angle as the full cone angle (half
/// of it as the edge), `spot-linear-falloff` drops the smoothstep for 1 − t.
pub fn spot_falloff_as(x: f64, angle: f64, penumbra: f64, mistakes: Mistakes) -> f64 {
    let angle = if mistakes.has(Mistake::SpotFullAngle) {
        angle / 2.0
    } else {
        angle
    };
    let inner = angle - penumbra.clamp(0.0, angle);
    if x <= inner {
        1.0
    } else if x > angle {
        0.0
    } else {
        let t = (x - inner) / (angle - inner);
        if mistakes.has(Mistake::SpotLinearFalloff) {
            1.0 - t
        } else {
            1.0 - (3.0 * t * t - 2.0 * t * t * t)
        }
    }
}
// ANCHOR_END: spot

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn attenuation_and_spot() {
        let l = Light {
            name: "l".into(),
            kind: LightKind::Point {
                position: DVec3::ZERO,
            },
            color: DVec3::ONE,
            attenuation: [1.0, 0.5, 0.25],
        };
        assert_eq!(l.f_att(2.0), 1.0 / (1.0 + 1.0 + 1.0));
        assert_eq!(l.f_att(0.0), 1.0);
        let (a, p) = (30f64.to_radians(), 10f64.to_radians());
        assert_eq!(spot_falloff_as(0.0, a, p, Mistakes::NONE), 1.0);
        assert_eq!(
            spot_falloff_as(31f64.to_radians(), a, p, Mistakes::NONE),
            0.0
        );
        assert!((spot_falloff_as(25f64.to_radians(), a, p, Mistakes::NONE) - 0.5).abs() < 1e-12);
    }
}
