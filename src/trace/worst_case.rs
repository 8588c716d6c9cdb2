//! How many rays one sample of a scene can trace at worst, said before the render starts.
//!
//! Each hit casts one shadow ray per light sample and spawns up to one reflection ray and one
//! transmission ray (three, one per colour, at a dispersive surface). A material that is both
//! reflective and transparent thus doubles the rays at every level: a tree of depth D holds
//! up to 2^(D+1) − 1 rays. The `min_contribution` cutoff stops a path once the product of its
//! weights falls below it, which bounds the depth only when every weight is below 1.

use crate::scene::{RenderSettings, Scene};
use std::collections::BTreeSet;

/// The largest ray tree one sample of a scene can grow.
#[derive(Debug, Clone, PartialEq)]
pub struct WorstCase {
    /// Rays (and shadow rays) one sample can trace: an upper bound.
    pub rays_per_sample: f64,
    /// Secondary rays one hit can spawn at most (2: reflection and transmission).
    pub branching: u32,
    /// The deepest level a ray can reach: `max_depth`, or less when the cutoff stops paths.
    pub depth: u32,
    /// Shadow rays one hit casts (one per point, spot or directional light, one per sample
    /// of an area light).
    pub shadow_rays: u64,
    /// A transparent material with a per-channel index splits each ray into three once.
    pub dispersive: bool,
    /// The materials that spawn `branching` rays (for the message).
    pub culprits: Vec<String>,
    /// The largest weight of one step (ks·Or or kt·Ot): the cutoff bounds the depth only
    /// when it is below 1.
    pub max_weight: f64,
}

/// Rays of a tree with `b` children per hit, `depth` levels below the camera ray, each hit
/// casting `shadow` shadow rays, split three ways once when `dispersive`.
fn tree_rays(b: u32, depth: u32, shadow: u64, dispersive: bool) -> f64 {
    let nodes = if b <= 1 {
        (depth as f64 + 1.0) * b.max(1) as f64
    } else {
        ((b as f64).powi(depth as i32 + 1) - 1.0) / (b as f64 - 1.0)
    };
    let nodes = if b == 0 { 1.0 } else { nodes };
    nodes * (1.0 + shadow as f64) * if dispersive && depth > 0 { 3.0 } else { 1.0 }
}

/// The worst case of `scene` under `settings`.
pub fn worst_case(scene: &Scene, settings: &RenderSettings) -> WorstCase {
    let g = scene.global;
    let used: BTreeSet<usize> = scene.objects.iter().map(|o| o.material).collect();
    let (mut branching, mut max_weight, mut dispersive) = (0u32, 0.0f64, false);
    let mut culprits = Vec::new();
    for &i in &used {
        let m = &scene.materials[i];
        let transmit = if settings.refractions {
            g.kt * m.transparent
        } else {
            glam::DVec3::ZERO
        };
        let local = if m.refract {
            glam::DVec3::ONE
        } else {
            glam::DVec3::ONE - transmit
        };
        let reflect = if settings.reflections {
            g.ks * m.reflective * local
        } else {
            glam::DVec3::ZERO
        };
        let (r, t) = (reflect.max_element() > 0.0, transmit.max_element() > 0.0);
        let b = r as u32 + t as u32;
        dispersive |= t && m.refract && m.is_dispersive();
        max_weight = max_weight
            .max(reflect.max_element())
            .max(transmit.max_element());
        if b > branching {
            branching = b;
            culprits.clear();
        }
        if b == branching && b > 0 {
            culprits.push(m.name.clone());
        }
    }
    let mut depth = settings.max_depth;
    if branching == 0 {
        depth = 0;
    } else if settings.min_contribution > 0.0 && max_weight < 1.0 {
        // A ray at depth d carries at most max_weight^d; it is spawned only if that is at
        // least min_contribution.
        let d = (settings.min_contribution.ln() / max_weight.ln()).floor();
        depth = depth.min(d.max(0.0) as u32);
    }
    let shadow_rays = if settings.shadows && (settings.diffuse || settings.specular) {
        scene.lights.iter().map(|l| l.sample_count() as u64).sum()
    } else {
        0
    };
    WorstCase {
        rays_per_sample: tree_rays(branching, depth, shadow_rays, dispersive),
        branching,
        depth,
        shadow_rays,
        dispersive,
        culprits,
        max_weight,
    }
}

/// A number of rays as a person reads it: exact below ten million, else like 3.7e19.
fn count(x: f64) -> String {
    if x < 1e7 {
        format!("{}", x.round() as u64)
    } else {
        format!("{x:.1e}")
    }
}

/// The warning `validate` prints (and `render`, on a terminal, before it starts) when one
/// sample of the scene can trace more rays than the ray budget allows: how many at worst, why,
/// and what to change. `None` when every tree fits the budget.
pub fn branching_warning(scene: &Scene, settings: &RenderSettings) -> Option<String> {
    let w = worst_case(scene, settings);
    let budget = settings.max_rays;
    if w.rays_per_sample <= budget as f64 {
        return None;
    }
    let names = w
        .culprits
        .iter()
        .map(|n| format!("\"{n}\""))
        .collect::<Vec<_>>()
        .join(", ");
    let why = if w.branching >= 2 {
        format!(
            "the scene can branch exponentially: material {names} is both reflective and \
             transparent, so every hit can spawn 2 rays{}; with max_depth {} and \
             min_contribution {} a sample's tree can reach depth {}, 2^{} − 1 ≈ {} rays",
            if w.dispersive {
                " (3 at a dispersive surface)"
            } else {
                ""
            },
            settings.max_depth,
            settings.min_contribution,
            w.depth,
            w.depth + 1,
            count(tree_rays(2, w.depth, 0, false)),
        )
    } else {
        format!(
            "with max_depth {} and min_contribution {} a sample's tree can reach depth {}",
            settings.max_depth, settings.min_contribution, w.depth
        )
    };
    let shadow = if w.shadow_rays > 0 {
        format!(
            ", and each hit casts {} shadow ray(s): up to {} rays per sample",
            w.shadow_rays,
            count(w.rays_per_sample)
        )
    } else {
        format!(": up to {} rays per sample", count(w.rays_per_sample))
    };
    // The deepest max_depth whose worst case fits the budget.
    let fit = (0..=w.depth)
        .take_while(|&d| tree_rays(w.branching, d, w.shadow_rays, w.dispersive) <= budget as f64)
        .last();
    let mut fixes = Vec::new();
    if let Some(d) = fit {
        fixes.push(format!("lower max_depth to {d} (--max-depth {d})"));
    }
    if w.max_weight >= 1.0 {
        fixes.push(format!(
            "lower the reflective/transparent colours of {names} below 1 and raise \
             min_contribution (weights of {} never fall below any cutoff)",
            w.max_weight
        ));
    } else if let Some(d) = fit {
        // min_contribution just above max_weight^(d+1) stops every path below depth d.
        let c = w.max_weight.powi(d as i32 + 1);
        let digits = 10f64.powf(c.log10().floor() - 1.0);
        let c = ((c / digits).floor() + 1.0) * digits;
        fixes.push(format!(
            "raise min_contribution to {} (paths stop at depth {d})",
            format!("{c:.6}").trim_end_matches('0')
        ));
    }
    fixes.push("raise --max-rays (render.max_rays) to trace more of each tree".to_string());
    Some(format!(
        "{why}{shadow}. The ray budget cuts each sample at {budget} rays (render.max_rays, \
         --max-rays), so the pixels it cuts miss part of their light. To trace whole trees: {}.",
        fixes.join("; or ")
    ))
}

#[cfg(test)]
mod tests {
    use super::tree_rays;

    #[test]
    fn a_binary_tree_of_depth_d_holds_2_to_the_d_plus_1_minus_1_rays() {
        assert_eq!(tree_rays(2, 0, 0, false), 1.0);
        assert_eq!(tree_rays(2, 3, 0, false), 15.0);
        assert_eq!(tree_rays(2, 3, 1, false), 30.0);
        assert_eq!(tree_rays(1, 4, 0, false), 5.0);
        assert_eq!(tree_rays(0, 9, 2, false), 3.0);
        assert_eq!(tree_rays(2, 64, 0, false), 2f64.powi(65) - 1.0);
    }
}
