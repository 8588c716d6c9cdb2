//! The text form of `explain`: an indented ray tree a student can read, using the lecture's
//! names (D = b² − 4ac, beta, gamma, f_att).

use super::explain::Explanation;
use crate::scene::{Encoding, Scene};
use crate::shapes::working::{short, vector, BlobWorking, CsgWorking, SpanRecord};
use crate::shapes::Roots;
use crate::trace::{End, RayKind, RayNode};
use glam::{DVec2, DVec3};
use std::fmt::Write;

pub fn v3(v: DVec3) -> String {
    vector(&v.to_array(), short)
}
pub fn v2(v: DVec2) -> String {
    vector(&v.to_array(), short)
}
fn color(v: DVec3) -> String {
    format!("({:.3}, {:.3}, {:.3})", v.x, v.y, v.z).replace("-0.000", "0.000")
}

/// Rays in a tree, and the nodes the ray budget cut.
fn budget_of(n: &RayNode) -> (usize, usize) {
    n.children
        .iter()
        .map(budget_of)
        .fold((1, (n.end == End::RayBudget) as usize), |(a, b), (c, d)| {
            (a + c, b + d)
        })
}

pub fn text(scene: &Scene, e: &Explanation) -> String {
    let mut o = String::new();
    let r = &scene.render;
    let own = e.own_samples();
    let spp = match r.sampler {
        crate::scene::SamplerKind::Corners => {
            "5 samples per pixel (the centre + 4 corners shared with the neighbours)".to_string()
        }
        crate::scene::SamplerKind::Adaptive => format!(
            "{own} samples in this pixel (4, split where they differ by more than {}, down to {} per pixel)",
            r.adaptive_threshold, r.spp
        ),
        _ => format!("{} sample(s) per pixel", r.spp),
    };
    let _ = writeln!(
        o,
        "pixel ({}, {}) of {}: {spp}, {} sampler, {} filter{}",
        e.pixel[0],
        e.pixel[1],
        scene.path.display(),
        r.sampler.name(),
        r.filter.name(),
        if r.subsample > 1 {
            format!(
                ", only every {} pixel traced (--subsample)",
                crate::report::ordinal(r.subsample)
            )
        } else {
            String::new()
        }
    );
    let how = match r.encoding {
        Encoding::Clamp => "floor(255 · clamp(c, 0, 1))",
        Encoding::Srgb => "sRGB curve",
    };
    let _ = writeln!(
        o,
        "colour {} -> bytes ({}, {}, {}) by {how}",
        color(e.color),
        e.encoded[0],
        e.encoded[1],
        e.encoded[2]
    );
    for s in &e.samples {
        let _ = writeln!(o);
        let owner = if s.pixel == e.pixel {
            String::new()
        } else {
            format!(" of neighbour pixel ({}, {})", s.pixel[0], s.pixel[1])
        };
        let _ = writeln!(
            o,
            "sample {}{owner} at film position {}, weight {}",
            s.index,
            v2(s.film),
            short(s.weight)
        );
        let (rays, cut) = budget_of(&s.ray);
        if cut > 0 {
            let _ = writeln!(
                o,
                "  cut: ray budget reached: this sample traced {rays} rays, the budget is {} (max_rays, --max-rays); \
                 {cut} ray(s) below marked \"cut: ray budget reached\" wanted more",
                r.max_rays
            );
        }
        let _ = writeln!(
            o,
            "  ray generation: ndc {} -> film point {} on the canonical far plane -> world {} -> direction = world - eye",
            v2(s.camera.ndc),
            v3(s.camera.film_point),
            v3(s.camera.world_point)
        );
        ray(&mut o, scene, &s.ray, 1);
        let _ = writeln!(o, "  sample colour {}", color(s.color));
    }
    o
}

fn kind_name(k: RayKind) -> &'static str {
    match k {
        RayKind::Camera => "camera ray",
        RayKind::Shadow => "shadow ray",
        RayKind::Reflection => "reflection ray",
        RayKind::Refraction => "refraction ray",
        RayKind::Transmission => "transmission ray",
    }
}

fn ray(o: &mut String, scene: &Scene, n: &RayNode, depth: usize) {
    let pad = "  ".repeat(depth);
    let channel = n
        .channel
        .map(|c| format!(" [{c} channel]"))
        .unwrap_or_default();
    let weight = n
        .weight
        .map(|w| format!(", weight {}", color(w)))
        .unwrap_or_default();
    let _ = writeln!(
        o,
        "{pad}{}{channel} (depth {}): origin {}, direction {}{weight}",
        kind_name(n.kind),
        n.depth,
        v3(n.origin),
        v3(n.direction)
    );
    if n.kind == RayKind::Shadow {
        match &n.hit {
            Some(h) => {
                let _ = writeln!(
                    o,
                    "{pad}  blocked by {} at t = {} after {} test(s)",
                    h.object,
                    short(h.t),
                    n.tests.len()
                );
            }
            None => {
                let _ = writeln!(
                    o,
                    "{pad}  reaches the light: nothing in the way ({} test(s))",
                    n.tests.len()
                );
            }
        }
        return;
    }
    for t in &n.tests {
        let _ = write!(o, "{pad}  test {} ({})", t.object, t.shape);
        if let Some(q) = &t.quadratic {
            let verdict = match q.q.roots {
                Roots::Two => "two roots".to_string(),
                Roots::Tangent if q.q.rounded_to_zero => {
                    format!("tangent (D came out as {:e} from rounding; |D| is within 1e-10 of b², taken as 0)", q.q.discriminant)
                }
                Roots::Tangent => "tangent (D = 0)".to_string(),
                Roots::One => "a = 0: linear, one root".to_string(),
                Roots::None => "D < 0: no real root, missed".to_string(),
            };
            let _ = write!(
                o,
                ": {} a = {}, b = {}, c = {}; D = b² - 4ac = {} -> {verdict}",
                q.surface,
                short(q.q.a),
                short(q.q.b),
                short(q.q.c),
                short(q.q.discriminant)
            );
        }
        if let Some(b) = &t.barycentric {
            let _ = write!(
                o,
                ": Cramer det = {}, beta = {}, gamma = {}, alpha = {}",
                short(b.determinant),
                short(b.beta),
                short(b.gamma),
                short(b.alpha)
            );
        }
        if let Some(n) = t.triangles_tested {
            let _ = write!(o, ": {n} triangle(s) tested");
            if let Some(m) = t.mesh_bvh_nodes {
                let _ = write!(o, " in {m} node(s) of its BVH");
            }
            if let Some(i) = t.triangle {
                let _ = write!(o, ", closest is triangle {i}");
            }
        }
        let _ = writeln!(o);
        if let Some(c) = &t.csg {
            csg_text(o, c, &format!("{pad}    "));
        }
        if let Some(b) = &t.blob {
            blob_text(o, b, &format!("{pad}    "));
        }
        for c in &t.candidates {
            let _ = writeln!(
                o,
                "{pad}    t = {:>9} on {:<10} point {}: {}",
                short(c.t),
                c.surface,
                v3(c.point),
                c.note
            );
        }
    }
    if n.bvh_nodes > 0 {
        let _ = writeln!(o, "{pad}  BVH nodes visited: {}", n.bvh_nodes);
    }
    let Some(h) = &n.hit else {
        let _ = writeln!(o, "{pad}  miss: background {}", color(n.color));
        return;
    };
    let _ = writeln!(
        o,
        "{pad}  hit {} ({}) at t = {}, point {}, normal {}",
        h.object,
        h.surface,
        short(h.t),
        v3(h.point),
        v3(h.normal)
    );
    let _ = writeln!(
        o,
        "{pad}    object space: point {}, normal {}",
        v3(h.object_space.point),
        v3(h.object_space.normal)
    );
    if let Some(b) = h.barycentric {
        let _ = writeln!(
            o,
            "{pad}    barycentric (alpha, beta, gamma) = ({}, {}, {})",
            short(b[0]),
            short(b[1]),
            short(b[2])
        );
    }
    let mut shadows = n.children.iter().filter(|c| c.kind == RayKind::Shadow);
    let mut others = n.children.iter().filter(|c| c.kind != RayKind::Shadow);
    if let Some(s) = &n.shading {
        let _ = writeln!(o, "{pad}  shading: ambient ka·La·Oa = {}", color(s.ambient));
        for (i, l) in s.lights.iter().enumerate() {
            let dist = l
                .distance
                .map(|d| format!(" (d = {})", short(d)))
                .unwrap_or_default();
            let spot = if l.spot != 1.0 {
                format!(", spot falloff {}", short(l.spot))
            } else {
                String::new()
            };
            let light = &scene.lights[i.min(scene.lights.len() - 1)];
            let _ = light;
            let _ = writeln!(
                o,
                "{pad}    light {}: f_att = {}{dist}{spot}, n·l = {}, diffuse = {}, r·v = {}, (r·v)^n = {}, specular = {}",
                l.light,
                short(l.attenuation),
                short(l.n_dot_l),
                color(l.diffuse),
                short(l.r_dot_v),
                short(l.r_dot_v_pow),
                color(l.specular)
            );
            if l.n_dot_l <= 0.0 {
                let _ = writeln!(o, "{pad}      the surface faces away from this light (n·l ≤ 0): no shadow ray needed");
            } else if l.spot <= 0.0 {
                let _ = writeln!(
                    o,
                    "{pad}      outside the spot's cone: no light, no shadow ray"
                );
            } else {
                let count = scene
                    .lights
                    .iter()
                    .find(|x| x.name == l.light)
                    .map_or(1, |x| x.sample_count());
                for _ in 0..count {
                    if let Some(sr) = shadows.next() {
                        ray(o, scene, sr, depth + 3);
                    }
                }
            }
        }
        for l in &s.ignored_lights {
            let dist = l
                .distance
                .map(|d| format!(" (d = {})", short(d)))
                .unwrap_or_default();
            let _ = writeln!(
                o,
                "{pad}    light {}: IGNORED (directional lights only, as in the course's Intersect stage): would add f_att = {}{dist}, n·l = {}, diffuse = {}, specular = {} (unshadowed); not in the colour",
                l.light,
                short(l.attenuation),
                short(l.n_dot_l),
                color(l.diffuse),
                color(l.specular)
            );
        }
        if s.reflected != DVec3::ZERO || n.children.iter().any(|c| c.kind == RayKind::Reflection) {
            let _ = writeln!(o, "{pad}    reflected ks·Or·I_r = {}", color(s.reflected));
        }
        if s.transmitted != DVec3::ZERO
            || n.children
                .iter()
                .any(|c| matches!(c.kind, RayKind::Refraction | RayKind::Transmission))
        {
            let _ = writeln!(
                o,
                "{pad}    transmitted kt·Ot·I_t = {}",
                color(s.transmitted)
            );
        }
    }
    if n.shading.is_none() && n.kind == RayKind::Refraction && scene.render.course_refraction {
        let why = if n.end == End::TotalInternalReflection {
            ": total internal reflection, nothing leaves (the course's refraction)"
        } else {
            ""
        };
        let _ = writeln!(
            o,
            "{pad}  the exit point, not shaded: the ray bends out here (the course's refraction); colour = what leaves = {}{why}",
            color(n.color)
        );
        for c in others.by_ref() {
            ray(o, scene, c, depth + 1);
        }
        return;
    }
    let clamped = if n.clamped {
        " (clamped to [0, 1])"
    } else {
        ""
    };
    let why = match n.end {
        End::Shaded => "",
        End::MaxDepth => ", stopped: maximum depth reached",
        End::Cutoff => ", stopped: the next ray would contribute less than min_contribution",
        End::TotalInternalReflection if scene.render.course_refraction => {
            ", total internal reflection: nothing is transmitted (the course's refraction)"
        }
        End::TotalInternalReflection => {
            ", total internal reflection: the transmitted ray was reflected"
        }
        End::RayBudget => {
            ", cut: ray budget reached (max_rays; the rest of this sample's tree was not traced)"
        }
        End::Miss | End::Blocked => "",
    };
    let _ = writeln!(
        o,
        "{pad}  colour = ambient + lights + reflected + transmitted = {}{clamped}{why}",
        color(n.color)
    );
    for c in others.by_ref() {
        ray(o, scene, c, depth + 1);
    }
}

/// Intervals as `[t_in surface, t_out surface]` pieces.
pub fn spans_text(spans: &[SpanRecord]) -> String {
    if spans.is_empty() {
        return "none".to_string();
    }
    spans
        .iter()
        .map(|s| {
            format!(
                "[{} {}, {} {}]",
                short(s.enter.t),
                s.enter.surface,
                short(s.exit.t),
                s.exit.surface
            )
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// A CSG node's working: each child's intervals (nested nodes indented), then the result.
pub fn csg_text(o: &mut String, c: &CsgWorking, pad: &str) {
    let _ = writeln!(
        o,
        "{pad}CSG {} of {} children, intervals of t inside each:",
        c.op.name(),
        c.children.len()
    );
    for (i, ch) in c.children.iter().enumerate() {
        let _ = writeln!(
            o,
            "{pad}  {} {} ({}): {}",
            if i == 0 { "first" } else { c.op.symbol() },
            ch.name,
            ch.shape,
            spans_text(&ch.spans)
        );
        if let Some(n) = &ch.csg {
            csg_text(o, n, &format!("{pad}    "));
        }
    }
    let _ = writeln!(o, "{pad}  = combined: {}", spans_text(&c.combined));
}

/// A blob's root search in a few lines.
pub fn blob_text(o: &mut String, b: &BlobWorking, pad: &str) {
    let pieces: Vec<String> = b
        .segments
        .iter()
        .map(|s| format!("[{}, {}]", short(s[0]), short(s[1])))
        .collect();
    if pieces.is_empty() {
        let _ = writeln!(
            o,
            "{pad}blob: the ray misses every component's sphere of influence, where the field is 0 < {}: no root",
            short(b.threshold)
        );
        return;
    }
    let _ = writeln!(
        o,
        "{pad}blob: surface where the field = {}; |dF/dt| ≤ L = {}; inside the spheres of influence on t in {}",
        short(b.threshold),
        short(b.lipschitz),
        pieces.join(" ")
    );
    let _ = writeln!(
        o,
        "{pad}  {} field samples: a piece [a, b] is ruled out when F has the same sign at both ends and |F(a)| + |F(b)| > L·(b − a), or the field's bounds on it stay on one side of the threshold; else it is halved",
        b.samples.len()
    );
    for br in &b.brackets {
        let _ = writeln!(
            o,
            "{pad}  bracket [{}, {}] (width {:.1e}): field {:.7} → {:.7} crosses {}",
            short(br.a),
            short(br.b),
            br.b - br.a,
            br.field_a,
            br.field_b,
            short(b.threshold)
        );
    }
    if !b.steps.is_empty() {
        let newton = b.steps.iter().filter(|s| s.method == "newton").count();
        let _ = writeln!(
            o,
            "{pad}  refined in {} steps ({} Newton, {} bisection)",
            b.steps.len(),
            newton,
            b.steps.len() - newton
        );
    }
    for r in &b.roots {
        let _ = writeln!(
            o,
            "{pad}  root t = {} ({})",
            short(r.t),
            if r.entering { "entering" } else { "leaving" }
        );
    }
}
