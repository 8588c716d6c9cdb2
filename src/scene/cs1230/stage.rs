//! The course's stages: what its template `.ini` files switch on for a stage *and* what that
//! stage's reference renderer does beyond them (FORMAT §10, §12). A preset over
//! [`RenderSettings`]; explicit switches (an ini key, a command-line flag) apply after it.

use crate::scene::{RenderSettings, Scene};
use crate::shading::LightKind;

/// A stage of the course's ray-tracing project.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CourseStage {
    /// Ray casting: no shadows, reflections, refractions or textures, depth 0, 1 spp, and
    /// lit by directional lights only (the references ignore point and spot lights, §12).
    Intersect,
    /// Shadows, reflections and textures on, refraction off, depth 4, 1 spp.
    Illuminate,
}

impl CourseStage {
    pub const NAMES: [&'static str; 2] = ["intersect", "illuminate"];

    pub fn parse(s: &str) -> Option<CourseStage> {
        match s.to_ascii_lowercase().as_str() {
            "intersect" => Some(CourseStage::Intersect),
            "illuminate" => Some(CourseStage::Illuminate),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    /// The stage's name as the course writes it.
    pub fn title(self) -> &'static str {
        match self {
            CourseStage::Intersect => "Intersect",
            CourseStage::Illuminate => "Illuminate",
        }
    }

    /// Sets what the stage decides; everything else (sampler, filter, encoding, ...) stays.
    pub fn apply(self, r: &mut RenderSettings) {
        let on = self == CourseStage::Illuminate;
        r.shadows = on;
        r.reflections = on;
        r.textures = on;
        r.refractions = false;
        r.depth_of_field = false;
        r.max_depth = if on { super::COURSE_MAX_DEPTH } else { 0 };
        r.spp = 1;
        r.sampler = crate::scene::SamplerKind::Center;
        r.subsample = 1;
        r.directional_only = !on;
    }
}

/// What a student is told when the settings leave lights out, e.g. "ignored 2 point lights
/// (point#0, point#1): the Intersect stage renders directional lights only"; `None` when
/// every light counts.
pub fn ignored_lights_note(scene: &Scene) -> Option<String> {
    if !scene.render.directional_only {
        return None;
    }
    let mut groups: Vec<(&str, Vec<&str>)> = Vec::new();
    for l in scene.lights.iter().filter(|l| !l.is_directional()) {
        let kind = match l.kind {
            LightKind::Point { .. } => "point",
            LightKind::Spot { .. } => "spot",
            _ => "area",
        };
        match groups.iter_mut().find(|(k, _)| *k == kind) {
            Some((_, names)) => names.push(&l.name),
            None => groups.push((kind, vec![&l.name])),
        }
    }
    if groups.is_empty() {
        return None;
    }
    let parts: Vec<String> = groups
        .iter()
        .map(|(kind, names)| {
            let plural = if names.len() == 1 { "" } else { "s" };
            // At most 6 names: a template can place a light hundreds of times.
            let shown = names.len().min(6);
            let more = if names.len() > shown { ", …" } else { "" };
            format!(
                "{} {kind} light{plural} ({}{more})",
                names.len(),
                names[..shown].join(", ")
            )
        })
        .collect();
    Some(format!(
        "ignored {}: the Intersect stage renders directional lights only",
        parts.join(" and ")
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shading::{Light, LightKind};
    use glam::DVec3;

    #[test]
    fn the_note_counts_by_kind_and_names_a_few() {
        let mut scene = crate::scene::Scene::load(std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/cs1230/scenes/lights.json"
        )))
        .unwrap();
        assert_eq!(
            ignored_lights_note(&scene),
            None,
            "only under directional_only"
        );
        CourseStage::Intersect.apply(&mut scene.render);
        let point = |i: usize| Light {
            name: format!("p{i}"),
            kind: LightKind::Point {
                position: DVec3::ZERO,
            },
            color: DVec3::ONE,
            attenuation: [1.0, 0.0, 0.0],
        };
        scene.lights.retain(|l| l.is_directional());
        scene.lights.extend((0..8).map(point));
        assert_eq!(
            ignored_lights_note(&scene).unwrap(),
            "ignored 8 point lights (p0, p1, p2, p3, p4, p5, …): the Intersect stage renders directional lights only"
        );
        scene.lights.retain(|l| l.is_directional());
        assert_eq!(ignored_lights_note(&scene), None);
    }
}
