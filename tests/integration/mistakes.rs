//! The catalogue of mistakes: each switch changes the image where and how its description
//! says, and nowhere else where that can be stated. Scenes: tests/mistakes/*.json.

use super::common::*;
use glam::{DVec2, DVec3};
use rtlab::mistakes::{Mistake, Mistakes};
use rtlab::sampling::render;
use rtlab::scene::{RenderSettings, Scene};
use rtlab::shading::{LightKind, TextureSource};
use rtlab::trace::{trace_sample, NoRecorder};

fn load(name: &str) -> Scene {
    scene(&format!("tests/mistakes/{name}.json"))
}

fn under(scene: &Scene, m: Mistake) -> RenderSettings {
    let mut s = scene.render.clone();
    s.mistakes = Mistakes::one(m);
    s
}

/// Linear colours of a render.
fn linear(scene: &Scene, settings: &RenderSettings) -> Vec<DVec3> {
    render(scene, settings, false, None).image.pixels
}

/// Encoded bytes of a render, as `render` writes them.
fn bytes(scene: &Scene, settings: &RenderSettings) -> image::RgbImage {
    render(scene, settings, false, None)
        .image
        .to_rgb8_for(settings)
}

fn differs(a: DVec3, b: DVec3) -> bool {
    (a - b).abs().max_element() > 1e-9
}

/// Indices of the pixels that differ.
fn changed(a: &[DVec3], b: &[DVec3]) -> Vec<usize> {
    assert_eq!(a.len(), b.len());
    (0..a.len()).filter(|&i| differs(a[i], b[i])).collect()
}

/// What each pixel's centre camera ray hits first (object name, surface), under `mistakes`
/// (which the camera and the closest-hit search honour).
fn hits(scene: &Scene, mistakes: Mistakes) -> Vec<Option<(String, &'static str)>> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let mut v = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let film = DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
            let (ray, _) = scene.camera.generate_as(film, None, mistakes);
            let hit = scene.accel.closest_as(
                &scene.objects,
                &ray,
                0.0,
                f64::INFINITY,
                mistakes,
                &mut NoRecorder::default(),
            );
            v.push(hit.map(|(i, l)| (scene.objects[i].name.clone(), l.surface)));
        }
    }
    v
}

fn on(h: &Option<(String, &'static str)>, names: &[&str]) -> bool {
    h.as_ref().is_some_and(|(n, _)| names.contains(&n.as_str()))
}

/// Every changed pixel satisfies `ok`, and at least `min` pixels changed.
fn assert_only(what: &str, changed: &[usize], min: usize, ok: impl Fn(usize) -> bool) {
    assert!(
        changed.len() >= min,
        "{what}: only {} pixel(s) changed, expected at least {min}",
        changed.len()
    );
    let bad: Vec<usize> = changed.iter().copied().filter(|&i| !ok(i)).collect();
    assert!(
        bad.is_empty(),
        "{what}: {} changed pixel(s) where the mistake should change nothing, e.g. pixel {}",
        bad.len(),
        bad[0]
    );
}

/// `a` is nowhere brighter than `b`.
fn darker_or_equal(a: DVec3, b: DVec3) -> bool {
    (a - b).max_element() <= 1e-12
}

#[test]
fn every_mistake_changes_its_scene_and_the_empty_set_changes_nothing() {
    let scenes = ["lit", "mirror", "occlusion", "textured", "solids", "spot", "glass"];
    let loaded: Vec<Scene> = scenes.iter().map(|s| load(s)).collect();
    // The scene settings that show each mistake (the Intersect ones need the stage).
    for &m in Mistake::ALL {
        let mut shown = false;
        for scene in &loaded {
            let mut base = scene.render.clone();
            if matches!(m, Mistake::IntersectPointLights | Mistake::IntersectShadows) {
                base.directional_only = true;
                base.shadows = false;
            }
            if matches!(m, Mistake::NDotLUnclamped | Mistake::SpecularBehindLight) {
                base.shadows = false;
            }
            let mut with = base.clone();
            with.mistakes = Mistakes::one(m);
            if bytes(scene, &base) != bytes(scene, &with) {
                shown = true;
                break;
            }
        }
        assert!(shown, "{m}: no test scene changes under it");
    }
    let scene = load("lit");
    let mut none = scene.render.clone();
    none.mistakes = Mistakes::NONE;
    assert_eq!(none, RenderSettings { ..scene.render.clone() });
    assert_eq!(linear(&scene, &none), linear(&scene, &scene.render));
}

#[test]
fn normal_mistakes_change_only_the_scaled_objects() {
    let scene = load("lit");
    let good = linear(&scene, &scene.render);
    let hit = hits(&scene, Mistakes::NONE);
    // ball: uniformly scaled by 0.8, so (M⁻¹)ᵀn is 1.25 n: unnormalised, it is lit brighter.
    let bad = linear(&scene, &under(&scene, Mistake::NormalNotNormalized));
    let c = changed(&good, &bad);
    assert_only("normal-not-normalized", &c, 200, |i| on(&hit[i], &["ball", "egg"]));
    assert!(c.iter().any(|&i| on(&hit[i], &["ball"])) && c.iter().any(|&i| on(&hit[i], &["egg"])));
    for &i in &c {
        if on(&hit[i], &["ball"]) {
            assert!(darker_or_equal(good[i], bad[i]), "the unnormalised 1.25·n brightens");
        }
    }
    // The object's matrix has the same direction as its inverse transpose for a uniform
    // scale: only the non-uniformly scaled egg changes.
    let bad = linear(&scene, &under(&scene, Mistake::NormalObjectMatrix));
    let c = changed(&good, &bad);
    assert_only("normal-object-matrix", &c, 100, |i| on(&hit[i], &["egg"]));
}

#[test]
fn acne_darkens_speckles_of_lit_surfaces_and_mirrors() {
    let scene = load("lit");
    let good = linear(&scene, &scene.render);
    let bad = linear(&scene, &under(&scene, Mistake::ShadowAcne));
    let c = changed(&good, &bad);
    // Shadow rays that hit their own surface: some lit pixels fall into shadow, none brightens.
    assert_only("shadow-acne", &c, 100, |i| darker_or_equal(bad[i], good[i]));
    assert!(c.len() < good.len() * 9 / 10, "acne is speckles, not every pixel");

    let scene = load("mirror");
    let good = linear(&scene, &scene.render);
    let hit = hits(&scene, Mistakes::NONE);
    let bad = linear(&scene, &under(&scene, Mistake::ReflectionAcne));
    let c = changed(&good, &bad);
    assert_only("reflection-acne", &c, 50, |i| {
        on(&hit[i], &["floor", "mirror ball"])
    });
}

#[test]
fn far_side_lighting_mistakes() {
    let scene = load("lit");
    let mut base = scene.render.clone();
    base.shadows = false;
    let good = linear(&scene, &base);
    let mut s = base.clone();
    s.mistakes = Mistakes::one(Mistake::NDotLUnclamped);
    let bad = linear(&scene, &s);
    let c = changed(&good, &bad);
    // A negative n·l subtracts light: pixels turned away from a light only get darker.
    assert_only("n-dot-l-unclamped", &c, 100, |i| darker_or_equal(bad[i], good[i]));

    s.mistakes = Mistakes::one(Mistake::SpecularBehindLight);
    let bad = linear(&scene, &s);
    let c = changed(&good, &bad);
    assert_only("specular-behind-light", &c, 20, |i| darker_or_equal(good[i], bad[i]));
    // Only the specular term: without it the images agree.
    let mut no_spec = base.clone();
    no_spec.specular = false;
    let mut bad_no_spec = no_spec.clone();
    bad_no_spec.mistakes = Mistakes::one(Mistake::SpecularBehindLight);
    assert_eq!(linear(&scene, &no_spec), linear(&scene, &bad_no_spec));
}

#[test]
fn specular_mistakes_change_only_the_specular_term() {
    let scene = load("lit");
    let good = linear(&scene, &scene.render);
    let hit = hits(&scene, Mistakes::NONE);
    for m in [Mistake::ReflectSign, Mistake::ShininessZero, Mistake::BlinnPhong] {
        let bad = linear(&scene, &under(&scene, m));
        let c = changed(&good, &bad);
        let mut no_spec = scene.render.clone();
        no_spec.specular = false;
        let mut bad_no_spec = no_spec.clone();
        bad_no_spec.mistakes = Mistakes::one(m);
        assert_eq!(
            linear(&scene, &no_spec),
            linear(&scene, &bad_no_spec),
            "{m} changes more than the specular term"
        );
        match m {
            // Only the block has shininess 0 (and a specular colour): it gets a flat wash.
            Mistake::ShininessZero => assert_only("shininess-zero", &c, 100, |i| {
                on(&hit[i], &["block"]) && darker_or_equal(good[i], bad[i])
            }),
            _ => assert_only(m.name(), &c, 100, |_| true),
        }
    }
}

#[test]
fn light_mistakes_equal_the_scene_they_pretend_it_is() {
    let base = load("lit");
    let render_as = |edit: &dyn Fn(&mut Scene)| {
        let mut s = base.clone();
        edit(&mut s);
        linear(&s, &s.render)
    };
    // directional-not-negated: the fill light as if it travelled the other way.
    let bad = linear(&base, &under(&base, Mistake::DirectionalNotNegated));
    let expect = render_as(&|s| {
        for l in &mut s.lights {
            if let LightKind::Directional { direction } = &mut l.kind {
                *direction = -*direction;
            }
        }
    });
    assert_eq!(bad, expect, "directional-not-negated");
    // no-attenuation: as if every light had attenuation (1, 0, 0).
    let bad = linear(&base, &under(&base, Mistake::NoAttenuation));
    let expect = render_as(&|s| s.lights.iter_mut().for_each(|l| l.attenuation = [1.0, 0.0, 0.0]));
    assert_eq!(bad, expect, "no-attenuation");
    assert_ne!(bad, linear(&base, &base.render));
    // ambient-times-light: as if the ambient light were La times the sum of the lights.
    let bad = linear(&base, &under(&base, Mistake::AmbientTimesLight));
    let sum: DVec3 = base.lights.iter().map(|l| l.color).sum();
    let expect = render_as(&|s| s.ambient_light *= sum);
    assert_eq!(bad, expect, "ambient-times-light");
    // no-global-coefficients: as if ka = kd = ks = kt = 1.
    let bad = linear(&base, &under(&base, Mistake::NoGlobalCoefficients));
    let expect = render_as(&|s| {
        s.global = rtlab::scene::Global {
            ka: 1.0,
            kd: 1.0,
            ks: 1.0,
            kt: 1.0,
        }
    });
    assert_eq!(bad, expect, "no-global-coefficients");
}

#[test]
fn unclamped_attenuation_only_brightens_and_only_where_it_exceeds_one() {
    let scene = load("lit");
    let good = linear(&scene, &scene.render);
    let bad = linear(&scene, &under(&scene, Mistake::AttenuationUnclamped));
    let c = changed(&good, &bad);
    assert_only("attenuation-unclamped", &c, 100, |i| darker_or_equal(good[i], bad[i]));
    // With c1 ≥ 1 the fraction never exceeds 1: nothing to clamp, nothing changes.
    let mut s = scene.clone();
    s.lights.iter_mut().for_each(|l| l.attenuation[0] = 1.0);
    assert_eq!(
        linear(&s, &s.render),
        linear(&s, &under(&s, Mistake::AttenuationUnclamped))
    );
}

#[test]
fn object_space_t_loses_scaled_objects_and_shadow_beyond_light_darkens() {
    let scene = load("occlusion");
    let good = linear(&scene, &scene.render);
    let hit = hits(&scene, Mistakes::NONE);
    let m = Mistakes::one(Mistake::ObjectSpaceT);
    let bad = linear(&scene, &under(&scene, Mistake::ObjectSpaceT));
    let c = changed(&good, &bad);
    // The small sphere is a unit sphere scaled by 0.3: its object-space t is 3.3 times its
    // world t, so the wall behind it wins wherever they overlap.
    assert_only("object-space-t", &c, 50, |i| on(&hit[i], &["small"]));
    let wrong = hits(&scene, m);
    for &i in &c {
        assert!(on(&wrong[i], &["wall"]), "the wall behind wins, found {:?}", wrong[i]);
    }

    let bad = linear(&scene, &under(&scene, Mistake::ShadowBeyondLight));
    let c = changed(&good, &bad);
    assert_only("shadow-beyond-light", &c, 200, |i| darker_or_equal(bad[i], good[i]));
}

#[test]
fn recursion_mistakes_change_only_mirrors() {
    let scene = load("mirror");
    let good = linear(&scene, &scene.render);
    let hit = hits(&scene, Mistakes::NONE);
    for m in [Mistake::RecursionUnclamped, Mistake::ReflectionWithoutKs] {
        let bad = linear(&scene, &under(&scene, m));
        let c = changed(&good, &bad);
        // Reflected colours carried unclamped (the lamp is brighter than 1) or without ks = 0.6:
        // brighter, and only on reflective surfaces.
        assert_only(m.name(), &c, 50, |i| {
            on(&hit[i], &["floor", "mirror ball"]) && darker_or_equal(good[i], bad[i])
        });
    }
    // Without per-ray clamping there is nothing to forget to clamp.
    let mut s = scene.render.clone();
    s.clamp_each_ray = false;
    let mut with = s.clone();
    with.mistakes = Mistakes::one(Mistake::RecursionUnclamped);
    assert_eq!(linear(&scene, &s), linear(&scene, &with));
}

/// The scene with every image texture transformed texel by texel.
fn retextured(scene: &Scene, f: impl Fn(u32, u32, u32, u32) -> (u32, u32)) -> Scene {
    let mut s = scene.clone();
    for m in &mut s.materials {
        if let Some(t) = &mut m.texture {
            if let TextureSource::Image {
                width,
                height,
                texels,
            } = &mut t.source
            {
                let (w, h) = (*width, *height);
                let old = texels.clone();
                let mut new = Vec::with_capacity(old.len());
                for row in 0..h {
                    for col in 0..w {
                        let (c, r) = f(col, row, w, h);
                        new.push(old[(r * w + c) as usize]);
                    }
                }
                *texels = std::sync::Arc::new(new);
            }
        }
    }
    s
}

#[test]
fn texture_flips_equal_a_flipped_texture() {
    let scene = load("textured");
    let good = linear(&scene, &scene.render);
    let hit = hits(&scene, Mistakes::NONE);
    let textured = |i: usize| on(&hit[i], &["picture", "crate"]);
    for (m, flip) in [
        (Mistake::TextureVFlipped, true),
        (Mistake::TextureUMirrored, false),
    ] {
        let bad = linear(&scene, &under(&scene, m));
        assert_only(m.name(), &changed(&good, &bad), 300, textured);
        let flipped = retextured(&scene, |c, r, w, h| {
            if flip {
                (c, h - 1 - r)
            } else {
                (w - 1 - c, r)
            }
        });
        let expect = linear(&flipped, &flipped.render);
        // Equal but where a pixel centre lies exactly on a texel boundary.
        let off = changed(&expect, &bad).len();
        assert!(
            off * 200 < good.len(),
            "{m}: {off} pixels differ from the render with a flipped texture"
        );
    }
}

#[test]
fn texture_times_diffuse_darkens_only_textured_pixels() {
    let scene = load("textured");
    let good = linear(&scene, &scene.render);
    let hit = hits(&scene, Mistakes::NONE);
    let bad = linear(&scene, &under(&scene, Mistake::TextureTimesDiffuse));
    assert_only("texture-times-diffuse", &changed(&good, &bad), 300, |i| {
        on(&hit[i], &["picture", "crate"]) && darker_or_equal(bad[i], good[i])
    });
}

#[test]
fn texture_off_by_one_reads_the_texel_half_a_texel_on() {
    let scene = load("textured");
    let good = linear(&scene, &scene.render);
    let hit = hits(&scene, Mistakes::NONE);
    let bad = linear(&scene, &under(&scene, Mistake::TextureOffByOne));
    assert_only("texture-off-by-one", &changed(&good, &bad), 100, |i| {
        on(&hit[i], &["picture", "crate"])
    });
    // Rounding instead of flooring is the right lookup half a texel further along u, and
    // half a texel down in v (rows run from the top); at u = 1 it wraps to the first column.
    let m = scene.materials.iter().find_map(|m| m.texture.clone()).unwrap();
    let TextureSource::Image { width, height, .. } = m.source else {
        panic!("an image texture")
    };
    let (du, dv) = (
        0.5 / (width as f64 * m.repeat.x),
        0.5 / (height as f64 * m.repeat.y),
    );
    let mut rng = rtlab::math::Rng::new(&[19]);
    for _ in 0..2000 {
        let uv = DVec2::new(rng.next_f64(), rng.next_f64());
        assert_eq!(
            m.texel_as(uv, Mistakes::one(Mistake::TextureOffByOne)),
            m.texel(uv + DVec2::new(du, -dv)),
            "uv {uv}"
        );
    }
}

#[test]
fn byte_mistakes() {
    let scene = load("lit");
    let good = bytes(&scene, &scene.render);
    let round = bytes(&scene, &under(&scene, Mistake::RoundBytes));
    let gamma = bytes(&scene, &under(&scene, Mistake::SrgbGamma));
    let (mut rounded_up, mut mid_brightened) = (0, 0);
    for ((g, r), s) in good.as_raw().iter().zip(round.as_raw()).zip(gamma.as_raw()) {
        // Rounding instead of truncating: the same byte or one more.
        assert!(*r == *g || *r == *g + 1, "round-bytes: {g} became {r}");
        rounded_up += usize::from(r != g);
        // The sRGB curve lifts every value but black and white.
        assert!(s >= g, "srgb-gamma darkened {g} to {s}");
        if (*g == 0 || *g == 255) && s != g {
            panic!("srgb-gamma changed the end point {g} to {s}");
        }
        if (64..=160).contains(g) && *s as i32 - *g as i32 >= 30 {
            mid_brightened += 1;
        }
    }
    assert!(rounded_up > good.as_raw().len() / 4, "about half the bytes round up");
    assert!(mid_brightened > 1000, "mid tones are lifted by 30 levels or more");
}

#[test]
fn pixel_corner_traces_the_top_left_corner_of_each_pixel() {
    let scene = load("lit");
    let bad = linear(&scene, &under(&scene, Mistake::PixelCorner));
    let w = scene.camera.width;
    for (i, c) in bad.iter().enumerate() {
        let (x, y) = (i as u32 % w, i as u32 / w);
        let corner = trace_sample(
            &scene,
            &scene.render,
            x,
            y,
            0,
            DVec2::new(x as f64, y as f64),
            &mut NoRecorder::default(),
        )
        .color;
        assert!(!differs(*c, corner), "pixel ({x}, {y})");
    }
    assert_ne!(bad, linear(&scene, &scene.render));
}

#[test]
fn image_flipped_is_the_correct_image_upside_down() {
    let scene = load("lit");
    let good = bytes(&scene, &scene.render);
    let bad = bytes(&scene, &under(&scene, Mistake::ImageFlipped));
    let flipped = image::imageops::flip_vertical(&good);
    let mut off = 0;
    for (a, b) in flipped.as_raw().iter().zip(bad.as_raw()) {
        assert!((*a as i32 - *b as i32).abs() <= 1, "{a} vs {b}");
        off += usize::from(a != b);
    }
    // Film positions computed from the other edge may differ in the last bit.
    assert!(off * 1000 < good.as_raw().len(), "{off} bytes differ");
    assert_ne!(good, bad);
}

/// Columns and rows an object covers in the image, under `mistakes`.
fn extent(scene: &Scene, name: &str, mistakes: Mistakes) -> (u32, u32) {
    let w = scene.camera.width;
    let hit = hits(scene, mistakes);
    let mut cols = std::collections::BTreeSet::new();
    let mut rows = std::collections::BTreeSet::new();
    for (i, h) in hit.iter().enumerate() {
        if on(h, &[name]) {
            cols.insert(i as u32 % w);
            rows.insert(i as u32 / w);
        }
    }
    (cols.len() as u32, rows.len() as u32)
}

#[test]
fn width_angle_mistakes_squeeze_or_stretch_wide_images_only() {
    let mut scene = load("lit");
    let (cols, rows) = extent(&scene, "ball", Mistakes::NONE);
    // fov-width-angle: θw = aspect·θh is wider than the true width angle, so objects narrow;
    // aspect-ignored: a square film on a wide image, so they widen. Rows stay.
    let (c, r) = extent(&scene, "ball", Mistakes::one(Mistake::FovWidthAngle));
    assert!(c < cols && r == rows, "fov-width-angle: {c}×{r} against {cols}×{rows}");
    let (c, r) = extent(&scene, "ball", Mistakes::one(Mistake::AspectIgnored));
    assert!(c > cols && r == rows, "aspect-ignored: {c}×{r} against {cols}×{rows}");
    for m in [Mistake::FovWidthAngle, Mistake::AspectIgnored] {
        assert_ne!(linear(&scene, &scene.render), linear(&scene, &under(&scene, m)));
    }
    // A square image has nothing to get wrong.
    scene.camera.update_size(100, 100);
    let good = linear(&scene, &scene.render);
    for m in [Mistake::FovWidthAngle, Mistake::AspectIgnored] {
        assert!(changed(&good, &linear(&scene, &under(&scene, m))).is_empty(), "{m}");
    }
}

#[test]
fn cap_radius_changes_only_caps_and_cone_normal_only_the_cone_body() {
    let scene = load("solids");
    let mut base = scene.render.clone();
    base.shadows = false; // a larger cap also casts a larger shadow
    let good = linear(&scene, &base);
    let m = Mistakes::one(Mistake::CapRadius);
    let mut s = base.clone();
    s.mistakes = m;
    let bad = linear(&scene, &s);
    let wrong = hits(&scene, m);
    let right = hits(&scene, Mistakes::NONE);
    let cap = |h: &Option<(String, &'static str)>| h.as_ref().is_some_and(|(_, s)| s.ends_with("cap"));
    assert_only("cap-radius", &changed(&good, &bad), 50, |i| {
        cap(&wrong[i]) && !cap(&right[i]) || cap(&wrong[i]) && right[i] == wrong[i]
    });
    // Caps of radius 0.5 accepted out to √0.5: the cap grows past the body.
    let grown = (0..good.len())
        .filter(|&i| cap(&wrong[i]) && !cap(&right[i]))
        .count();
    assert!(grown > 50, "{grown} pixels of grown cap");

    let mut s = base.clone();
    s.mistakes = Mistakes::one(Mistake::ConeNormal);
    let bad = linear(&scene, &s);
    assert_only("cone-normal", &changed(&good, &bad), 100, |i| {
        right[i] == Some(("cone".to_string(), "body"))
    });
}

#[test]
fn spot_mistakes_change_the_penumbra_and_the_cone() {
    let scene = load("spot");
    let good = linear(&scene, &scene.render);
    let LightKind::Spot {
        position,
        direction,
        angle,
        penumbra,
    } = scene.lights[0].kind
    else {
        panic!("the first light is the spot")
    };
    // The angle from the spot's axis of each pixel's visible point.
    let (w, h) = (scene.camera.width, scene.camera.height);
    let mut angles = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let (ray, _) = scene
                .camera
                .generate(DVec2::new(x as f64 + 0.5, y as f64 + 0.5), None);
            let hit = scene.accel.closest(
                &scene.objects,
                &ray,
                0.0,
                f64::INFINITY,
                &mut NoRecorder::default(),
            );
            angles.push(hit.map(|(_, l)| {
                let p = ray.at(l.t);
                (p - position).normalize().dot(direction).clamp(-1.0, 1.0).acos()
            }));
        }
    }
    let bad = linear(&scene, &under(&scene, Mistake::SpotLinearFalloff));
    let inner = angle - penumbra;
    assert_only("spot-linear-falloff", &changed(&good, &bad), 100, |i| {
        angles[i].is_some_and(|a| a > inner - 1e-9 && a < angle + 1e-9)
    });
    let bad = linear(&scene, &under(&scene, Mistake::SpotFullAngle));
    // Half the angle: the spot shrinks; outside the true cone nothing changes.
    assert_only("spot-full-angle", &changed(&good, &bad), 300, |i| {
        darker_or_equal(bad[i], good[i]) && angles[i].is_some_and(|a| a < angle + 1e-9)
    });
}

#[test]
fn intersect_stage_mistakes_light_what_the_stage_leaves_out() {
    let scene = load("spot");
    let mut stage = scene.render.clone();
    stage.directional_only = true;
    stage.shadows = false;
    // intersect-point-lights: every light, as if the stage were not on.
    let mut with = stage.clone();
    with.mistakes = Mistakes::one(Mistake::IntersectPointLights);
    let mut all_lights = stage.clone();
    all_lights.directional_only = false;
    assert_eq!(linear(&scene, &with), linear(&scene, &all_lights));
    // intersect-shadows: the stage's directional lights, shadowed.
    with.mistakes = Mistakes::one(Mistake::IntersectShadows);
    let mut shadowed = stage.clone();
    shadowed.shadows = true;
    assert_eq!(linear(&scene, &with), linear(&scene, &shadowed));
    assert_ne!(linear(&scene, &with), linear(&scene, &stage));
    // Outside the Intersect stage, shadows off means off.
    let mut plain = scene.render.clone();
    plain.shadows = false;
    let mut with = plain.clone();
    with.mistakes = Mistakes::one(Mistake::IntersectShadows);
    assert_eq!(linear(&scene, &plain), linear(&scene, &with));
}

#[test]
fn mistakes_combine() {
    let scene = load("lit");
    let mut s = scene.render.clone();
    s.mistakes = [Mistake::RoundBytes, Mistake::ImageFlipped].into_iter().collect();
    let both = bytes(&scene, &s);
    let flipped = bytes(&scene, &under(&scene, Mistake::ImageFlipped));
    let mut n = 0;
    for (a, b) in flipped.as_raw().iter().zip(both.as_raw()) {
        assert!(*b == *a || *b == *a + 1);
        n += usize::from(a != b);
    }
    assert!(n > 0);
}

#[test]
fn cli_mistake_flag_and_catalogue() {
    let out = rtlab(&["mistakes"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    for m in Mistake::ALL {
        assert!(text.contains(m.name()) && text.contains(m.breaks()), "{m}");
    }
    let out = rtlab(&["mistakes", "--format", "json"]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v.as_array().unwrap().len(), Mistake::ALL.len());
    assert_eq!(v[0]["name"], Mistake::ALL[0].name());

    // Unknown names: an argument error with the nearest name, exit 2, no image written.
    let png = tmp("mistake-typo.png");
    let out = rtlab(&[
        "render",
        "tests/mistakes/lit.json",
        "--mistake",
        "image-flipped,cap-raduis",
        "-o",
        png.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("argument --mistake: unknown mistake \"cap-raduis\" (did you mean \"cap-radius\"?"),
        "{}",
        stderr(&out)
    );
    assert!(!png.exists());

    // render: repeatable and comma-separated, the same bytes as the library's settings.
    let a = tmp("mistake-a.png");
    let out = rtlab(&[
        "render",
        "tests/mistakes/lit.json",
        "--quiet",
        "--mistake",
        "round-bytes,image-flipped",
        "-o",
        a.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let b = tmp("mistake-b.png");
    let out = rtlab(&[
        "render",
        "tests/mistakes/lit.json",
        "--quiet",
        "--mistake",
        "round-bytes",
        "--mistake",
        "image-flipped",
        "-o",
        b.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let scene = load("lit");
    let mut s = scene.render.clone();
    s.mistakes = [Mistake::RoundBytes, Mistake::ImageFlipped].into_iter().collect();
    let expect = bytes(&scene, &s);
    for p in [&a, &b] {
        assert_eq!(image::open(p).unwrap().to_rgb8(), expect);
    }
}

#[test]
fn explain_marks_what_the_mistake_changes() {
    let args = ["explain", "tests/mistakes/lit.json", "--pixel", "40,55"];
    let plain = rtlab(&args);
    assert!(plain.status.success());
    assert!(!String::from_utf8_lossy(&plain.stdout).contains("--mistake"));
    let mut with: Vec<&str> = args.to_vec();
    with.extend(["--mistake", "blinn-phong"]);
    let out = rtlab(&with);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("Where --mistake blinn-phong changes the numbers"), "{text}");
    assert!(text.contains("light key › specular"), "{text}");
    assert!(!text.contains("› diffuse"), "blinn-phong leaves diffuse alone: {text}");
    with.extend(["--format", "json"]);
    let out = rtlab(&with);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["mistakes"][0], "blinn-phong");
    let d = v["differences"].as_array().unwrap();
    assert!(d.iter().any(|d| d["json_path"]
        .as_str()
        .unwrap()
        .ends_with("lights[0].r_dot_v_pow")));
    // The explanation itself is the with-mistake one.
    let scene = load("lit");
    let mut s = scene.render.clone();
    s.mistakes = Mistakes::one(Mistake::BlinnPhong);
    let img = bytes(&scene, &s);
    let p = img.get_pixel(40, 55);
    assert_eq!(v["encoded"], serde_json::json!([p[0], p[1], p[2]]));
}

#[test]
fn steps_and_compare_take_the_mistake() {
    let dir = tmp("mistake-steps");
    let _ = std::fs::remove_dir_all(&dir);
    let run_steps = |extra: &[&str], out: &std::path::Path| {
        let mut a = vec![
            "steps",
            "tests/mistakes/lit.json",
            "--frames",
            "specular",
            "--quiet",
            "-o",
            out.to_str().unwrap(),
        ];
        a.extend_from_slice(extra);
        let o = rtlab(&a);
        assert!(o.status.success(), "{}", stderr(&o));
        std::fs::read(out).unwrap()
    };
    let good = run_steps(&[], &tmp("mistake-steps-good.png"));
    let bad = run_steps(&["--mistake", "blinn-phong"], &tmp("mistake-steps-bad.png"));
    assert_ne!(good, bad, "steps --mistake changes the frames");

    let run_compare = |extra: &[&str]| {
        let mut a = vec![
            "compare",
            "tests/mistakes/lit.json",
            "--spp",
            "1",
            "--reference-spp",
            "4",
            "--format",
            "json",
        ];
        a.extend_from_slice(extra);
        let o = rtlab(&a);
        assert!(o.status.success(), "{}", stderr(&o));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        v["runs"][0]["rmse"].as_f64().unwrap()
    };
    assert_ne!(run_compare(&[]), run_compare(&["--mistake", "pixel-corner"]));
}

#[test]
fn no_ambient_is_the_ambient_term_switched_off() {
    let scene = load("lit");
    let mut off = scene.render.clone();
    off.ambient = false;
    let bad = linear(&scene, &under(&scene, Mistake::NoAmbient));
    assert_eq!(bad, linear(&scene, &off));
    assert_ne!(bad, linear(&scene, &scene.render));
}

#[test]
fn unnormalised_shadow_rays_count_blockers_out_to_the_distance_squared() {
    // The lamp is more than 1 away from everything lit: blockers out to d² count too, so the
    // slab beyond the lamp shadows the floor, as with shadow-beyond-light, never brightening.
    let scene = load("occlusion");
    let good = linear(&scene, &scene.render);
    let bad = linear(&scene, &under(&scene, Mistake::ShadowRayUnnormalized));
    let c = changed(&good, &bad);
    assert_only("shadow-ray-unnormalized", &c, 200, |i| darker_or_equal(bad[i], good[i]));
    let beyond = linear(&scene, &under(&scene, Mistake::ShadowBeyondLight));
    for &i in &c {
        assert!(!differs(bad[i], beyond[i]) || darker_or_equal(beyond[i], bad[i]));
    }
}

#[test]
fn inverted_eta_changes_only_what_is_seen_through_glass() {
    let scene = load("glass");
    let good = linear(&scene, &scene.render);
    let hit = hits(&scene, Mistakes::NONE);
    let bad = linear(&scene, &under(&scene, Mistake::RefractionEtaInverted));
    assert_only("refraction-eta-inverted", &changed(&good, &bad), 500, |i| {
        on(&hit[i], &["glass"])
    });
}

#[test]
fn the_gallery_shows_every_mistake() {
    let chapter = std::fs::read_to_string(path("book/src/15-when-your-image-is-wrong.md")).unwrap();
    let lesson = std::fs::read_to_string(path("lessons/15-when-your-image-is-wrong.json")).unwrap();
    for m in Mistake::ALL {
        assert!(chapter.contains(&format!("| `{}` |", m.name())), "{m} has no row in chapter 15");
        // The Intersect-stage pair needs the stage's switch to be rendered from the CLI.
        if !matches!(m, Mistake::IntersectPointLights | Mistake::IntersectShadows) {
            assert!(
                lesson.contains(&format!("--mistake {} ", m.name())),
                "{m} has no figure in lessons/15"
            );
        }
    }
}
