//! CS1230 course scenefiles: they load into the same Scene as native files, with the course's
//! conventions (canonical shapes, T·R·S·M order, templates, lights, defaults), render through
//! the one tracer, and convert to a native file that renders to the same bytes.

use super::common::*;
use glam::{DMat4, DVec2, DVec3};
use rtlab::cli::explain::rounded;
use rtlab::math::Ray;
use rtlab::sampling::render;
use rtlab::scene::{Scene, SceneFormat};
use rtlab::shading::LightKind;
use rtlab::shapes::NoObserver;
use rtlab::trace::{trace_sample, NoRecorder};
use serde_json::{json, Value};
use std::path::PathBuf;

fn course_scenes() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(path("tests/cs1230/scenes"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    v.sort();
    v
}

fn stem(p: &std::path::Path) -> String {
    p.file_stem().unwrap().to_string_lossy().into_owned()
}

fn v3(v: DVec3) -> Value {
    json!([v.x, v.y, v.z])
}

/// What a loaded scene is, as data a reviewer can read: camera, settings, lights, objects
/// with their world matrices and materials.
fn summary(s: &Scene) -> Value {
    let c = &s.camera;
    let r = &s.render;
    let lights: Vec<Value> = s
        .lights
        .iter()
        .map(|l| {
            let kind = match &l.kind {
                LightKind::Point { position } => json!({"point": {"position": v3(*position)}}),
                LightKind::Directional { direction } => {
                    json!({"directional": {"direction": v3(*direction)}})
                }
                LightKind::Spot {
                    position,
                    direction,
                    angle,
                    penumbra,
                } => json!({"spot": {"position": v3(*position), "direction": v3(*direction),
                    "angle_deg": angle.to_degrees(), "penumbra_deg": penumbra.to_degrees()}}),
                LightKind::Area { .. } => json!("area"),
            };
            json!({"name": l.name, "kind": kind, "color": v3(l.color), "attenuation": l.attenuation})
        })
        .collect();
    let objects: Vec<Value> = s
        .objects
        .iter()
        .map(|o| {
            let m = &s.materials[o.material];
            let w = o.transform.world_from_object;
            let rows: Vec<Value> = (0..4)
                .map(|i| {
                    let r = w.row(i);
                    json!([r.x, r.y, r.z, r.w])
                })
                .collect();
            let texture = m.texture.as_ref().map(|t| {
                json!({"blend": t.blend, "repeat": [t.repeat.x, t.repeat.y]})
            });
            json!({
                "name": o.name,
                "shape": format!("{:?}", o.shape).split('(').next().unwrap().to_string(),
                "world_from_object": rows,
                "bounds": o.bounds.map(|b| json!({"min": v3(b.min), "max": v3(b.max)})),
                "material": {"ambient": v3(m.ambient), "diffuse": v3(m.diffuse), "specular": v3(m.specular),
                    "shininess": m.shininess, "reflective": v3(m.reflective), "transparent": v3(m.transparent),
                    "ior": m.ior.x, "texture": texture},
            })
        })
        .collect();
    json!({
        "format": format!("{:?}", s.format),
        "camera": {"position": v3(c.position), "look_at": v3(c.look_at), "up": v3(c.up), "fov_y": c.fov_y,
            "size": [c.width, c.height], "aperture": c.aperture, "focal_distance": c.focal_distance,
            "u": v3(c.basis[0]), "v": v3(c.basis[1]), "w": v3(c.basis[2])},
        "render": {"max_depth": r.max_depth, "min_contribution": r.min_contribution,
            "clamp_each_ray": r.clamp_each_ray, "background": v3(r.background), "spp": r.spp},
        "global": {"ka": s.global.ka, "kd": s.global.kd, "ks": s.global.ks, "kt": s.global.kt},
        "ambient_light": v3(s.ambient_light),
        "lights": lights,
        "objects": objects,
    })
}

#[test]
fn snapshots_of_loaded_scenes() {
    for p in course_scenes() {
        let s = Scene::load(&p).unwrap_or_else(|e| panic!("{e}"));
        let v = rounded(&summary(&s));
        let mut settings = insta::Settings::clone_current();
        settings.set_snapshot_path("snapshots/cs1230");
        settings.set_prepend_module_to_snapshot(false);
        settings.set_description(
            "a CS1230 scenefile loaded: world matrices (T·R·S·M, templates expanded), course defaults",
        );
        settings.set_info(&json!({"scene": format!("tests/cs1230/scenes/{}.json", stem(&p))}));
        settings.bind(|| insta::assert_yaml_snapshot!(format!("scene_{}", stem(&p)), v));
    }
}

const CASES: &[Case] = &[
    Case { name: "primitives_miss", scene: "primitives", pixel: (20, 20), depth: None, teaches: "a miss: the course's background is black" },
    Case { name: "primitives_cone_side", scene: "primitives", pixel: (680, 450), depth: None, teaches: "the canonical cone's side (apex at y = +0.5): normal ∝ (2x, (0.5 − y)/2, 2z); a point light with f_att = 1/(c1 + c2·d + c3·d²) and a directional light" },
    Case { name: "primitives_mesh", scene: "primitives", pixel: (850, 410), depth: None, teaches: "a mesh primitive (OBJ octahedron): barycentric weights of the triangle hit" },
    Case { name: "lights_spot_penumbra", scene: "lights", pixel: (765, 385), depth: None, teaches: "a point inside the soft spot's penumbra: falloff 1 − (3t² − 2t³) between angle − penumbra and angle" },
    Case { name: "textures_sphere", scene: "textures", pixel: (400, 400), depth: None, teaches: "a textured sphere: diffuse = (1 − blend)·kd·Od + blend·texel, repeat 2 × 1; the sum exceeds 1 and the ray's colour is clamped (clamped: true), as the course clamps every traced colour" },
    Case { name: "mirrors_chrome", scene: "mirrors", pixel: (330, 400), depth: Some(2), teaches: "a near-mirror sphere: the reflection ray's colour is weighted by ks·Or (specularCoeff × reflective), up to the course's 4 bounces (2 here)" },
    Case { name: "mirrors_glass", scene: "mirrors", pixel: (700, 440), depth: Some(2), teaches: "refraction weighted kt·Ot (transparentCoeff), ior 1.5" },
    Case { name: "templates_lamp", scene: "templates", pixel: (512, 400), depth: None, teaches: "a template instanced three times: each instance brings its own light" },
];

#[test]
fn snapshots_of_explained_pixels() {
    for c in CASES {
        let file = format!("tests/cs1230/scenes/{}.json", c.scene);
        let name = format!("explain_{}", c.name);
        snapshot_explained(
            c,
            Scene::load(&path(&file)).unwrap(),
            "snapshots/cs1230",
            &name,
            |s| json!({"scene": file, "pixel": [c.pixel.0, c.pixel.1], "max_depth": s.render.max_depth, "size": [1024, 768]}),
        );
    }
}

#[test]
fn course_files_get_the_course_settings_and_size() {
    for p in course_scenes() {
        let s = Scene::load(&p).unwrap();
        assert_eq!(s.format, SceneFormat::Cs1230);
        assert_eq!((s.camera.width, s.camera.height), (1024, 768));
        assert_eq!(s.render.max_depth, 4);
        assert!(s.render.clamp_each_ray);
        assert_eq!(s.ambient_light, DVec3::ONE);
    }
    // --width/--height override the default size, for render and explain alike.
    let out = tmp("cs_small.png");
    let scene = path("tests/cs1230/scenes/primitives.json");
    let o = rtlab(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--width",
        "64",
        "--height",
        "48",
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let img = image::open(&out).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (64, 48));
    let o = rtlab(&[
        "explain",
        scene.to_str().unwrap(),
        "--pixel",
        "32,30",
        "--width",
        "64",
        "--height",
        "48",
        "--format",
        "json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    let enc: Vec<u8> = v["encoded"]
        .as_array()
        .unwrap()
        .iter()
        .map(|b| b.as_u64().unwrap() as u8)
        .collect();
    assert_eq!(enc, img.get_pixel(32, 30).0.to_vec());
    let o = rtlab(&["validate", scene.to_str().unwrap()]);
    assert!(String::from_utf8_lossy(&o.stdout)
        .contains("valid CS1230 scenefile: 6 object(s), 2 light(s)"));
}

#[test]
fn convert_writes_a_native_scene_that_renders_the_same_bytes() {
    for p in course_scenes() {
        let out = tmp(&format!("converted/{}.json", stem(&p)));
        std::fs::create_dir_all(out.parent().unwrap()).unwrap();
        let o = rtlab(&["convert", p.to_str().unwrap(), "-o", out.to_str().unwrap()]);
        assert!(o.status.success(), "{}: {}", p.display(), stderr(&o));
        let a = Scene::load(&p).unwrap();
        let b = Scene::load(&out).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(b.format, SceneFormat::Native);
        assert_eq!(a.render, b.render, "{}", p.display());
        assert_eq!(a.camera, b.camera, "{}", p.display());
        assert_eq!(a.lights, b.lights, "{}", p.display());
        assert_eq!(a.objects.len(), b.objects.len());
        for (x, y) in a.objects.iter().zip(&b.objects) {
            assert_eq!(x.transform, y.transform, "{} {}", p.display(), x.name);
        }
        let (mut a, mut b) = (a, b);
        a.camera.update_size(128, 96);
        b.camera.update_size(128, 96);
        let ia = render(&a, &a.render, false, None)
            .image
            .to_rgb8(a.render.encoding);
        let ib = render(&b, &b.render, false, None)
            .image
            .to_rgb8(b.render.encoding);
        assert!(
            ia.as_raw() == ib.as_raw(),
            "{}: the converted scene renders differently",
            p.display()
        );
        // Not a blank image: the test would pass trivially otherwise.
        assert!(ia.as_raw().iter().any(|&v| v > 40), "{}", p.display());
    }
}

#[test]
fn convert_refuses_native_scenes_and_reports_warnings() {
    let out = tmp("conv_native.json");
    let o = rtlab(&[
        "convert",
        "scenes/spheres.json",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("already a native rtlab scene"),
        "{}",
        stderr(&o)
    );
    assert!(!out.exists());
    let out = tmp("conv_tex.json");
    let o = rtlab(&[
        "convert",
        "tests/cs1230/scenes/textures.json",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("warning:") && text.contains("missing.png"),
        "{text}"
    );
}

/// A scenefile written to a temporary folder (with the test meshes and textures reachable
/// as "meshes/..." from the folder above it, as the course resolves paths).
fn course_file(name: &str, body: &str) -> PathBuf {
    let p = tmp(&format!("course/scenes/{name}"));
    std::fs::create_dir_all(p.parent().unwrap()).unwrap();
    std::fs::write(&p, body).unwrap();
    p
}

const HEAD: &str = r#""globalData": {"ambientCoeff": 0.5, "diffuseCoeff": 0.5, "specularCoeff": 0.5},
  "cameraData": {"position": [0, 0, 5], "look": [0, 0, -1], "up": [0, 1, 0], "heightAngle": 30}"#;

#[test]
fn errors_name_the_file_the_json_path_and_the_problem() {
    let cases: &[(&str, String, &str, &str)] = &[
        ("unknown_type.json", format!(r#"{{{HEAD}, "groups": [{{"primitives": [{{"type": "sphre"}}]}}]}}"#),
            "groups[0].primitives[0].type", "unknown primitive type \"sphre\" (did you mean \"sphere\"?)"),
        ("matrix_rows.json", format!(r#"{{{HEAD}, "groups": [{{"matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,0]], "primitives": [{{"type": "cube"}}]}}]}}"#),
            "groups[0].matrix", "4 rows of 4 numbers"),
        ("matrix_projective.json", format!(r#"{{{HEAD}, "groups": [{{"matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,1,1]], "primitives": [{{"type": "cube"}}]}}]}}"#),
            "groups[0].matrix[3]", "last row of a matrix must be [0, 0, 0, 1]"),
        ("matrix_singular.json", format!(r#"{{{HEAD}, "groups": [{{"matrix": [[1,0,0,0],[0,0,0,0],[0,0,1,0],[0,0,0,1]], "primitives": [{{"type": "cube"}}]}}]}}"#),
            "groups[0].matrix", "singular"),
        ("missing_template.json", format!(r#"{{{HEAD}, "templateGroups": [{{"name": "lamp", "primitives": [{{"type": "cube"}}]}}], "groups": [{{"groups": [{{"name": "lmap"}}]}}]}}"#),
            "groups[0].groups[0]", "no template named \"lmap\" (did you mean \"lamp\"?)"),
        ("late_template.json", format!(r#"{{{HEAD}, "templateGroups": [{{"name": "a", "groups": [{{"name": "b"}}]}}, {{"name": "b", "primitives": [{{"type": "cube"}}]}}]}}"#),
            "templateGroups[0].groups[0]", "template \"b\" is used before it is defined (at templateGroups[1])"),
        ("template_cycle.json", format!(r#"{{{HEAD}, "templateGroups": [{{"name": "a", "groups": [{{"translate": [1, 0, 0], "groups": [{{"name": "a"}}]}}]}}], "groups": [{{"name": "a"}}]}}"#),
            "templateGroups[0].groups[0].groups[0]", "template \"a\" is used inside its own definition"),
        ("missing_mesh.json", format!(r#"{{{HEAD}, "groups": [{{"primitives": [{{"type": "mesh", "meshFile": "meshes/dragon.obj"}}]}}]}}"#),
            "groups[0].primitives[0].meshFile", "mesh file not found"),
        ("mesh_without_file.json", format!(r#"{{{HEAD}, "groups": [{{"primitives": [{{"type": "mesh"}}]}}]}}"#),
            "groups[0].primitives[0]", "missing required key \"meshFile\""),
        ("look_and_focus.json", r#"{"globalData": {"ambientCoeff": 1, "diffuseCoeff": 1, "specularCoeff": 1}, "cameraData": {"position": [0, 0, 5], "look": [0, 0, -1], "focus": [0, 0, 0], "up": [0, 1, 0], "heightAngle": 30}}"#.to_string(),
            "cameraData", "both \"look\""),
        ("unknown_key.json", format!(r#"{{{HEAD}, "groups": [{{"primitives": [{{"type": "cube", "difuse": [1, 0, 0]}}]}}]}}"#),
            "groups[0].primitives[0].difuse", "unknown key \"difuse\" (did you mean \"diffuse\"?)"),
        ("spot_without_angle.json", format!(r#"{{{HEAD}, "groups": [{{"lights": [{{"type": "spot", "color": [1, 1, 1], "direction": [0, -1, 0], "penumbra": 5, "attenuationCoeff": [1, 0, 0]}}]}}]}}"#),
            "groups[0].lights[0]", "missing required key \"angle\""),
    ];
    // A texture file that exists but is not an image: an error (only a missing one is skipped).
    let bad = tmp("course/textures/not_an_image.png");
    std::fs::create_dir_all(bad.parent().unwrap()).unwrap();
    std::fs::write(&bad, "this is not a PNG").unwrap();
    let mut cases = cases.to_vec();
    cases.push(("bad_texture.json", format!(r#"{{{HEAD}, "groups": [{{"primitives": [{{"type": "cube", "textureFile": "textures/not_an_image.png", "blend": 1}}]}}]}}"#),
        "groups[0].primitives[0].textureFile", "cannot decode texture image"));
    for (name, body, at, msg) in &cases {
        let p = course_file(name, body);
        let o = rtlab(&["validate", p.to_str().unwrap()]);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{name}: {e}");
        assert_eq!(e.trim().lines().count(), 1, "{name}: one line: {e}");
        assert!(
            e.contains(&format!("{name}: {at}: ")),
            "{name}: path {at} in: {e}"
        );
        assert!(e.contains(msg), "{name}: \"{msg}\" in: {e}");
    }
}

#[test]
fn template_blow_up_is_refused_quickly_with_its_path() {
    // t0 is one sphere; each next template uses the previous one twice: t24 is 2^24 spheres.
    let mut ts = vec![r#"{"name": "t0", "primitives": [{"type": "sphere"}]}"#.to_string()];
    for i in 1..=24 {
        ts.push(format!(
            r#"{{"name": "t{i}", "groups": [{{"name": "t{0}"}}, {{"translate": [1, 0, 0], "groups": [{{"name": "t{0}"}}]}}]}}"#,
            i - 1
        ));
    }
    let body = format!(
        r#"{{{HEAD}, "templateGroups": [{}], "groups": [{{"primitives": [{{"type": "cube"}}]}}, {{"groups": [{{"name": "t24"}}]}}]}}"#,
        ts.join(", ")
    );
    let p = course_file("blow_up.json", &body);
    let o = rtlab(&["validate", p.to_str().unwrap()]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    // The limit is a memory budget, said the way the image-size limit is.
    let max = rtlab::scene::cs1230::max_expanded();
    let each = rtlab::scene::cs1230::bytes_per_primitive();
    assert!(
        e.contains("expands to")
            && e.contains(&format!(
                "GiB (about {each} bytes each); the limit is 3.0 GiB, about {max} primitives"
            )),
        "{e}"
    );
    // The culprit is the deepest group that alone is too large: inside t(k), the first
    // template of more than `max` spheres, whose two references to t(k-1) are each small
    // enough.
    let k = (1..=24).find(|k| (1u64 << k) > max).unwrap();
    assert!(e.contains(&format!("t{k}")), "{e}");
    assert!(
        e.contains("groups[1].groups[0] uses template \"t24\""),
        "{e}"
    );
    // Above the old limit of 200 000 primitives, the scene loads: 2^18 = 262144 spheres.
    assert!(1 << 18 <= max);
    let body = body.replace(r#"{"name": "t24"}]}]}"#, r#"{"name": "t18"}]}]}"#);
    let p = course_file("above_old_limit.json", &body);
    let s = Scene::load(&p).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.objects.len(), (1 << 18) + 1);
}

#[test]
fn transforms_apply_in_the_fixed_order_t_r_s_m() {
    // Keys written in the reverse order: the result is still T · R · S · M.
    let body = format!(
        r#"{{{HEAD}, "groups": [{{"translate": [1, 2, 3], "groups": [{{
            "matrix": [[1, 0.5, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]],
            "scale": [2, 3, 4], "rotate": [0, 0, 2, 90], "translate": [5, 0, 0],
            "primitives": [{{"type": "cube"}}, {{"type": "cone"}}],
            "lights": [{{"type": "spot", "color": [1, 1, 1], "direction": [1, 0, 0], "angle": 30, "penumbra": 5, "attenuationCoeff": [1, 0, 0]}}]
        }}]}}]}}"#
    );
    let p = course_file("order.json", &body);
    let s = Scene::load(&p).unwrap();
    let parent = DMat4::from_translation(DVec3::new(1.0, 2.0, 3.0));
    let t = DMat4::from_translation(DVec3::new(5.0, 0.0, 0.0));
    let r = DMat4::from_axis_angle(DVec3::Z, 90f64.to_radians());
    let sc = DMat4::from_scale(DVec3::new(2.0, 3.0, 4.0));
    let m = DMat4::from_cols_array_2d(&[
        [1.0, 0.5, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ])
    .transpose();
    let expect = parent * t * r * sc * m;
    assert!(s.objects[0]
        .transform
        .world_from_object
        .abs_diff_eq(expect, 1e-12));
    // The cone is rtlab's apex-at-origin cone shifted up by 0.5 inside the same transform.
    let cone = expect * DMat4::from_translation(DVec3::new(0.0, 0.5, 0.0));
    assert!(s.objects[1]
        .transform
        .world_from_object
        .abs_diff_eq(cone, 1e-12));
    // The light sits at CTM·origin and points along CTM·direction.
    let LightKind::Spot {
        position,
        direction,
        ..
    } = s.lights[0].kind
    else {
        panic!()
    };
    assert!((position - DVec3::new(6.0, 2.0, 3.0)).length() < 1e-12);
    let d = expect.transform_vector3(DVec3::X).normalize();
    assert!((direction - d).length() < 1e-12);
}

/// Intersects a world ray with an object of a scene (its shape in object space).
fn hit(s: &Scene, object: usize, origin: DVec3, dir: DVec3) -> Option<(DVec3, DVec3)> {
    let o = &s.objects[object];
    let local = o.transform.ray_to_object(&Ray::new(origin, dir));
    let h = o
        .shape
        .intersect(&local, 0.0, f64::INFINITY, &mut NoObserver)?;
    Some((
        o.transform.point_to_world(h.point),
        o.transform.normal_to_world(h.normal),
    ))
}

#[test]
fn canonical_shapes_fill_the_unit_cube_like_the_course() {
    let body = format!(
        r#"{{{HEAD}, "groups": [{{"primitives": [{{"type": "cube"}}, {{"type": "sphere"}}, {{"type": "cylinder"}}, {{"type": "cone"}}]}}]}}"#
    );
    let s = Scene::load(&course_file("shapes.json", &body)).unwrap();
    let down = DVec3::NEG_Y;
    let up = DVec3::Y;
    let far = 10.0;
    // cube: top face at y = 0.5
    let (p, n) = hit(&s, 0, DVec3::new(0.3, far, 0.2), down).unwrap();
    assert!((p.y - 0.5).abs() < 1e-12 && n == DVec3::Y);
    // sphere: radius 0.5
    let (p, _) = hit(&s, 1, DVec3::new(0.0, 0.0, far), DVec3::NEG_Z).unwrap();
    assert!((p.z - 0.5).abs() < 1e-12);
    // cylinder: radius 0.5, caps at ±0.5
    let (p, _) = hit(&s, 2, DVec3::new(far, 0.1, 0.0), DVec3::NEG_X).unwrap();
    assert!((p.x - 0.5).abs() < 1e-12);
    let (p, n) = hit(&s, 2, DVec3::new(0.2, -far, 0.0), up).unwrap();
    assert!((p.y + 0.5).abs() < 1e-12 && n == DVec3::NEG_Y);
    // cone: apex at (0, 0.5, 0), base disc of radius 0.5 at y = −0.5
    let (p, _) = hit(&s, 3, DVec3::new(0.0, far, 0.0), down).unwrap();
    assert!((p - DVec3::new(0.0, 0.5, 0.0)).length() < 1e-9);
    let (p, n) = hit(&s, 3, DVec3::new(0.45, -far, 0.0), up).unwrap();
    assert!((p.y + 0.5).abs() < 1e-12 && n == DVec3::NEG_Y);
    assert!(hit(&s, 3, DVec3::new(0.55, -far, 0.0), up).is_none());
    // cone side at height y: radius (0.5 − y)/2; normal ∝ (2, 1, 0)/√5 on the +x side
    let (p, n) = hit(&s, 3, DVec3::new(far, 0.0, 0.0), DVec3::NEG_X).unwrap();
    assert!((p.x - 0.25).abs() < 1e-12);
    assert!((n - DVec3::new(2.0, 1.0, 0.0) / 5f64.sqrt()).length() < 1e-12);
    // diffuse defaults to white, everything else to 0
    let m = s.material_of(0);
    assert_eq!(
        (m.diffuse, m.ambient, m.specular, m.shininess),
        (DVec3::ONE, DVec3::ZERO, DVec3::ZERO, 0.0)
    );
}

#[test]
fn a_pixel_matches_the_course_equation_by_hand() {
    // Sphere of radius 0.5 at the origin; camera at z = 5; a point light at the camera with
    // attenuation (1, 0.1, 0): the centre ray hits (0, 0, 0.5) with N = L = V = +z, so
    // I = ka·Oa + f_att·I_L·(kd·Od + ks·Os), f_att = 1/(1 + 0.1·4.5).
    let body = r#"{"globalData": {"ambientCoeff": 0.5, "diffuseCoeff": 0.6, "specularCoeff": 0.3},
      "cameraData": {"position": [0, 0, 5], "focus": [0, 0, 0], "up": [0, 1, 0], "heightAngle": 30},
      "groups": [{"translate": [0, 0, 5], "lights": [{"type": "point", "color": [1, 0.5, 0.25], "attenuationCoeff": [1, 0.1, 0]}]},
                 {"primitives": [{"type": "sphere", "ambient": [0.2, 0.1, 0], "diffuse": [0.5, 0.5, 1], "specular": [1, 1, 1], "shininess": 7}]}]}"#;
    let mut s = Scene::load(&course_file("hand.json", body)).unwrap();
    s.camera.update_size(9, 9);
    let c = trace_sample(
        &s,
        &s.render,
        4,
        4,
        0,
        DVec2::new(4.5, 4.5),
        &mut NoRecorder::default(),
    )
    .color;
    let f_att = 1.0 / (1.0 + 0.1 * 4.5);
    let light = DVec3::new(1.0, 0.5, 0.25);
    let expect = 0.5 * DVec3::new(0.2, 0.1, 0.0)
        + f_att * light * (0.6 * DVec3::new(0.5, 0.5, 1.0) + 0.3 * DVec3::ONE);
    assert!((c - expect).abs().max_element() < 1e-12, "{c} vs {expect}");
}

#[test]
fn templates_replace_the_referencing_entry_and_bring_their_lights() {
    let s = Scene::load(&path("tests/cs1230/scenes/templates.json")).unwrap();
    // "lamp" refers to "post" with a translate of 100 that the course's reader ignores.
    for o in &s.objects {
        let b = o.bounds.unwrap();
        assert!(b.max.abs().max_element() < 10.0, "{} at {b:?}", o.name);
    }
    // Three lamps, three lamp lights, at the lamps' places (row at z = −1, x = ±3; one at z = 1 scaled 1.2).
    let mut at: Vec<DVec3> = s
        .lights
        .iter()
        .filter_map(|l| match l.kind {
            LightKind::Point { position } => Some(position),
            _ => None,
        })
        .collect();
    at.sort_by(|a, b| a.x.total_cmp(&b.x));
    let expect = [
        DVec3::new(-3.0, 2.0, -0.4),
        DVec3::new(0.0, 2.4, 1.72),
        DVec3::new(3.0, 2.0, -0.4),
    ];
    assert_eq!(at.len(), 3);
    for (a, e) in at.iter().zip(expect) {
        assert!((*a - e).length() < 1e-12, "{a} vs {e}");
    }
    // A name that is no template is only a label.
    assert!(s
        .objects
        .iter()
        .any(|o| o.transform.point_to_world(DVec3::ZERO).z > 2.4));
}

#[test]
fn missing_textures_draw_without_the_texture() {
    let s = Scene::load(&path("tests/cs1230/scenes/textures.json")).unwrap();
    let textured = s
        .objects
        .iter()
        .filter(|o| s.materials[o.material].texture.is_some())
        .count();
    assert_eq!(textured, 5);
    let o = rtlab(&["validate", "tests/cs1230/scenes/textures.json"]);
    assert!(o.status.success());
    assert!(String::from_utf8_lossy(&o.stdout)
        .contains("groups[6].primitives[0].textureFile: texture not found"));
}

#[test]
fn camera_focus_is_a_point_look_a_direction_and_the_lens_is_read() {
    let cam = |c: &str| {
        let body = format!(
            r#"{{"globalData": {{"ambientCoeff": 1, "diffuseCoeff": 1, "specularCoeff": 1}}, "cameraData": {c}}}"#
        );
        Scene::load(&course_file("camera.json", &body))
            .unwrap()
            .camera
    };
    let a =
        cam(r#"{"position": [1, 2, 3], "focus": [1, 2, -7], "up": [0, 1, 0], "heightAngle": 45}"#);
    let b =
        cam(r#"{"position": [1, 2, 3], "look": [0, 0, -10], "up": [0, 1, 0], "heightAngle": 45}"#);
    assert_eq!(a.basis, b.basis);
    assert_eq!(a.basis[2], DVec3::Z); // w = −look
    assert_eq!((a.fov_y, a.aperture), (45.0, 0.0));
    let c = cam(
        r#"{"position": [0, 0, 0], "look": [0, 0, -1], "up": [0, 1, 0], "heightAngle": 60, "aperture": 0.2, "focalLength": 4}"#,
    );
    assert_eq!((c.aperture, c.focal_distance), (0.2, 4.0));
    // The full vertical field of view: the top edge of the film is at tan(30°) (FORMAT §3).
    let top = c
        .world_from_canonical
        .transform_point3(DVec3::new(0.0, 1.0, -1.0));
    assert!((top.y - 30f64.to_radians().tan()).abs() < 1e-12);
}
