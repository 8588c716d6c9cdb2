//! The course's own workflow: stages (`--course-stage`), its `.ini` files, its texture
//! paths. The fake project under tests/cs1230/course/ has the course template's layout:
//! `template_inis/<stage>/*.ini` next to `scenefiles/…`.

use super::common::*;
use clap::Parser;
use rtlab::cli::{Cli, Command, RenderArgs};
use rtlab::scene::{CourseStage, Scene};
use std::path::{Path, PathBuf};

const LIGHTS: &str = "tests/cs1230/scenes/lights.json";
const INTERSECT_INI: &str = "tests/cs1230/course/template_inis/intersect/lights.ini";
const ILLUMINATE_INI: &str = "tests/cs1230/course/template_inis/illuminate/textures.ini";

/// The RenderArgs of `rtlab render <args>`.
fn render_args(args: &[&str]) -> RenderArgs {
    let mut argv = vec!["rtlab", "render"];
    argv.extend_from_slice(args);
    match Cli::try_parse_from(argv).expect("parses").command {
        Command::Render(a) => a.render,
        _ => unreachable!(),
    }
}

fn settings(args: &[&str]) -> rtlab::scene::RenderSettings {
    let a = render_args(&args[1..]);
    a.load_full(&path(args[0])).unwrap().scene.render
}

fn png(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// Copies the fake course project into a fresh folder (render writes into it).
fn project_copy(name: &str) -> PathBuf {
    fn copy(from: &Path, to: &Path) {
        std::fs::create_dir_all(to).unwrap();
        for e in std::fs::read_dir(from).unwrap() {
            let e = e.unwrap();
            let dst = to.join(e.file_name());
            if e.file_type().unwrap().is_dir() {
                copy(&e.path(), &dst);
            } else {
                std::fs::copy(e.path(), dst).unwrap();
            }
        }
    }
    let dst = tmp(name);
    let _ = std::fs::remove_dir_all(&dst);
    copy(&path("tests/cs1230/course"), &dst);
    dst
}

#[test]
fn intersect_stage_is_the_scene_without_its_point_and_spot_lights() {
    // The same scenefile with its point and spot lights taken out, rendered with the stage's
    // switches spelled out, gives the same bytes: the ignored lights add nothing.
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path(LIGHTS)).unwrap()).unwrap();
    for g in v["groups"].as_array_mut().unwrap() {
        if let Some(ls) = g.get_mut("lights").and_then(|l| l.as_array_mut()) {
            ls.retain(|l| l["type"] == "directional");
        }
    }
    let stripped = write_tmp("course-stripped_lights.json", &v.to_string());
    let (a, b) = (tmp("course-stage.png"), tmp("course-stripped.png"));
    let o = rtlab(&[
        "render",
        LIGHTS,
        "--course-stage",
        "intersect",
        "--width",
        "64",
        "--height",
        "48",
        "-o",
        a.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert_eq!(
        err.matches("ignored").count(),
        1,
        "one warning, once: {err}"
    );
    assert!(
        err.contains("warning: ignored 1 point light (bulb) and 2 spot lights (soft spot, hard spot): the Intersect stage renders directional lights only"),
        "{err}"
    );
    let o = rtlab(&[
        "render",
        stripped.to_str().unwrap(),
        "--width",
        "64",
        "--height",
        "48",
        "--no-shadows",
        "--no-reflections",
        "--no-refractions",
        "--no-textures",
        "--max-depth",
        "0",
        "-o",
        b.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("ignored"));
    assert_eq!(png(&a), png(&b));
    // Lit by every light, the image is another one.
    let c = tmp("course-all_lights.png");
    let o = rtlab(&[
        "render",
        LIGHTS,
        "--width",
        "64",
        "--height",
        "48",
        "-o",
        c.to_str().unwrap(),
    ]);
    assert!(o.status.success());
    assert_ne!(png(&a), png(&c));
}

#[test]
fn quiet_silences_the_stage_warning() {
    let out = tmp("course-quiet.png");
    let o = rtlab(&[
        "render",
        LIGHTS,
        "--course-stage",
        "intersect",
        "--width",
        "32",
        "--height",
        "24",
        "-q",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success());
    assert_eq!(stderr(&o), "");
}

#[test]
fn stage_presets_and_overrides_in_both_directions() {
    let r = settings(&[LIGHTS, "x", "--course-stage", "intersect"]);
    assert!(r.directional_only);
    assert!(!r.shadows && !r.reflections && !r.refractions && !r.textures && !r.depth_of_field);
    assert_eq!((r.max_depth, r.spp), (0, 1));
    let r = settings(&[LIGHTS, "x", "--course-stage", "illuminate"]);
    assert!(!r.directional_only);
    assert!(r.shadows && r.reflections && r.textures && !r.refractions);
    assert_eq!((r.max_depth, r.spp), (4, 1));
    // Switched on over a stage that has them off ...
    let r = settings(&[
        LIGHTS,
        "x",
        "--course-stage",
        "intersect",
        "--shadows",
        "--reflections",
        "--refractions",
        "--textures",
        "--max-depth",
        "3",
        "--spp",
        "4",
        "--sampler",
        "grid",
    ]);
    assert!(r.shadows && r.reflections && r.refractions && r.textures);
    assert_eq!((r.max_depth, r.spp), (3, 4));
    assert!(r.directional_only, "the lights stay the stage's");
    // ... and off over one that has them on.
    let r = settings(&[
        LIGHTS,
        "x",
        "--course-stage",
        "illuminate",
        "--no-shadows",
        "--no-reflections",
        "--no-textures",
    ]);
    assert!(!r.shadows && !r.reflections && !r.textures);
    // The ini's folder names the stage; --course-stage says otherwise.
    let r = settings(&[INTERSECT_INI, "x"]);
    assert!(r.directional_only && !r.shadows);
    let r = settings(&[INTERSECT_INI, "x", "--course-stage", "illuminate"]);
    assert!(!r.directional_only);
    // The ini's own keys win over the stage (shadows = false), switches over both.
    assert!(!r.shadows);
    let r = settings(&[INTERSECT_INI, "x", "--shadows"]);
    assert!(r.shadows && r.directional_only);
    // A switch with its negation is an argument error; so is an unknown stage.
    let o = rtlab(&["render", LIGHTS, "--shadows", "--no-shadows"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("cannot be used with"), "{}", stderr(&o));
    let o = rtlab(&["render", LIGHTS, "--course-stage", "intersekt"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("argument --course-stage: unknown course stage \"intersekt\""),
        "{}",
        stderr(&o)
    );
}

#[test]
fn explain_shows_the_ignored_light() {
    // A pixel of the floor lit by the point light "bulb" and the spot "hard spot".
    let o = rtlab(&[
        "explain",
        LIGHTS,
        "--course-stage",
        "intersect",
        "--pixel",
        "512,500",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("light sky: f_att = 1"), "{text}");
    assert!(
        text.contains("light bulb: IGNORED (directional lights only, as in the course's Intersect stage): would add f_att = 0.2178"),
        "{text}"
    );
    let o = rtlab(&[
        "explain",
        LIGHTS,
        "--course-stage",
        "intersect",
        "--pixel",
        "512,500",
        "--format",
        "json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let shading = &v["samples"][0]["ray"]["shading"];
    let ignored: Vec<&str> = shading["ignored_lights"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l["light"].as_str().unwrap())
        .collect();
    assert_eq!(ignored, ["bulb", "soft spot", "hard spot"]);
    let lit: Vec<&str> = shading["lights"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l["light"].as_str().unwrap())
        .collect();
    assert_eq!(lit, ["sky"]);
}

#[test]
fn ini_renders_to_its_output_like_the_scenefile_under_its_stage() {
    let root = project_copy("course/project_intersect");
    let ini = root.join("template_inis/intersect/lights.ini");
    // Run from inside the ini's folder: the scene is not under the current folder, so it
    // is found from the project root (the folder holding template_inis/).
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_rtlab"))
        .args(["render", "lights.ini"])
        .current_dir(ini.parent().unwrap())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("ignored 1 point light"),
        "{}",
        stderr(&o)
    );
    let written = root.join("student_outputs/intersect/required/lights.png");
    let img = image::open(&written).unwrap();
    assert_eq!((img.width(), img.height()), (96, 72), "the ini's [Canvas]");
    // The same as the scenefile with the stage named on the command line.
    let direct = tmp("course-direct.png");
    let o = rtlab(&[
        "render",
        LIGHTS,
        "--course-stage",
        "intersect",
        "--width",
        "96",
        "--height",
        "72",
        "-o",
        direct.to_str().unwrap(),
    ]);
    assert!(o.status.success());
    assert_eq!(png(&written), png(&direct));
    // -o wins over the ini's output.
    let other = tmp("course-other.png");
    let o = rtlab(&["render", INTERSECT_INI, "-o", other.to_str().unwrap(), "-q"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(png(&other), png(&direct));
}

#[test]
fn ini_keys_reach_the_settings() {
    let loaded = RenderArgs::default()
        .load_full(&path(ILLUMINATE_INI))
        .unwrap();
    assert_eq!(loaded.stage, Some(CourseStage::Illuminate));
    let r = &loaded.scene.render;
    assert!(r.shadows && r.reflections && r.textures && !r.refractions);
    assert_eq!(r.texture_filter, rtlab::shading::TextureFilter::Bilinear);
    assert_eq!(r.max_depth, 4);
    assert_eq!(
        (loaded.scene.camera.width, loaded.scene.camera.height),
        (96, 72)
    );
    assert!(loaded
        .output
        .unwrap()
        .ends_with("course/student_outputs/illuminate/required/textures.png"));
    // post-process = true has no effect in rtlab: said once.
    let notes: Vec<&String> = loaded
        .warnings
        .iter()
        .filter(|w| w.contains("post-process"))
        .collect();
    assert_eq!(notes.len(), 1, "{:?}", loaded.warnings);
    assert!(notes[0].contains(
        "line 17: [Feature] post-process = true: rtlab has no post-processing filter: no effect"
    ));
    // super-sample with a count and a pattern.
    let ini = write_tmp(
        "course/ss/x.ini",
        &format!(
            "[IO]\nscene = {}\n[Feature]\nsuper-sample = true\nsamples-per-pixel = 9\n[Settings]\nsuper-sampler-pattern = \"grid\"\n",
            path(LIGHTS).display()
        ),
    );
    let r = RenderArgs::default().load_full(&ini).unwrap().scene.render;
    assert_eq!((r.spp, r.sampler), (9, rtlab::scene::SamplerKind::Grid));
    // A pattern rtlab does not know, or a grid of a count that is not square: the sampler
    // used is said, with the ini's line.
    for (count, pattern, said) in [
        (
            9,
            "poisson",
            "not a pattern rtlab knows (grid, jittered or random): grid samples are used",
        ),
        (
            3,
            "grid",
            "3 samples make no square grid: random samples are used",
        ),
    ] {
        let ini = write_tmp(
            &format!("course/ss/{pattern}.ini"),
            &format!(
                "[IO]\nscene = {}\n[Feature]\nsuper-sample = true\nsamples-per-pixel = {count}\n[Settings]\nsuper-sampler-pattern = \"{pattern}\"\n",
                path(LIGHTS).display()
            ),
        );
        let loaded = RenderArgs::default().load_full(&ini).unwrap();
        let w = loaded
            .warnings
            .iter()
            .find(|w| w.contains("super-sampler-pattern"));
        let w = w.unwrap_or_else(|| panic!("{pattern}: nothing said: {:?}", loaded.warnings));
        assert!(
            w.contains("line 7: [Settings] super-sampler-pattern = "),
            "{w}"
        );
        assert!(w.contains(said), "{w}");
    }
}

#[test]
fn ini_errors_name_file_line_column_key_and_the_nearest_key() {
    let scene = path(LIGHTS).display().to_string();
    let cases = [
        (
            "typo.ini",
            format!("[IO]\n  scene = {scene}\n[Feature]\n  shadows = false\n  reflekt = true\n"),
            "typo.ini: line 5:3: unknown key \"reflekt\" in [Feature] (did you mean \"reflect\"?)",
        ),
        (
            "section.ini",
            format!("[IO]\n  scene = {scene}\n[Canvass]\n  width = 10\n"),
            "section.ini: line 3:2: unknown section [Canvass] (did you mean [Canvas]?",
        ),
        (
            "value.ini",
            format!("[IO]\n  scene = {scene}\n[Canvas]\n  width = wide\n"),
            "value.ini: line 4:11: [Canvas] width: expected a whole number ≥ 0, found \"wide\"",
        ),
        (
            "size.ini",
            format!("[IO]\n  scene = {scene}\n[Canvas]\n  width = 0\n"),
            "size.ini: line 4:11: [Canvas] width: the image size must be at least 1×1",
        ),
        (
            "noscene.ini",
            "[IO]\n  output = x.png\n".to_string(),
            "noscene.ini: [IO]: no scene",
        ),
        (
            "missing.ini",
            "[IO]\n  scene = nowhere/x.json\n".to_string(),
            "missing.ini: line 2:11: [IO] scene: scenefile not found: tried nowhere/x.json (from the current folder) and ",
        ),
        (
            "empty.ini",
            "[IO]\n  scene =\n".to_string(),
            "empty.ini: line 2:10: [IO] scene: is empty: give the scenefile",
        ),
        (
            "folder.ini",
            "[IO]\n  scene = /tmp\n".to_string(),
            "folder.ini: line 2:11: [IO] scene: /tmp is a folder, not a scenefile (.json)",
        ),
        (
            "quote.ini",
            format!("[IO]\n  scene = {scene}\n[Settings]\n  super-sampler-pattern = \"grid\n"),
            "quote.ini: line 4:27: [Settings] super-sampler-pattern: \"\"grid\" has a quote (\") at one end only",
        ),
        (
            "jpg.ini",
            format!("[IO]\n  scene = {scene}\n  output = out/x.jpg\n"),
            "jpg.ini: line 3:12: [IO] output: cannot write .jpg images: use a .png file name",
        ),
        (
            "long.ini",
            format!("[IO]\n  scene = {scene}\n[Canvas]\n  width = 96{}x\n", " ".repeat(1000)),
            "(1003 characters)",
        ),
    ];
    for (name, text, want) in cases {
        let p = write_tmp(&format!("course/bad/{name}"), &text);
        for cmd in ["render", "validate"] {
            let o = rtlab(&[cmd, p.to_str().unwrap()]);
            assert_eq!(o.status.code(), Some(2), "{name}");
            let err = stderr(&o);
            assert!(err.contains(want), "{name} ({cmd}): {err}");
            assert_eq!(err.lines().count(), 1, "{err}");
        }
    }
}

#[test]
fn file_prefix_and_textures_folder_fallback() {
    let ini = path(ILLUMINATE_INI);
    let o = rtlab(&["validate", ini.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    // file:src/../../../image_source/uv_grid.png: found in scenefiles/illuminate/textures/.
    let found: Vec<&str> = out.lines().filter(|l| l.contains("; using ")).collect();
    assert_eq!(found.len(), 1, "{out}");
    assert!(found[0].contains("groups[2].primitives[0].textureFile: texture not found at "));
    assert!(found[0].contains("image_source/uv_grid.png; using "));
    assert!(found[0].contains("course/scenefiles/illuminate/textures/uv_grid.png"));
    assert!(
        !found[0].contains("file:"),
        "the prefix is not part of the path"
    );
    // The one missing everywhere is still drawn without a texture, and said.
    assert!(out.contains("groups[3].primitives[0].textureFile: texture not found: "));
    // The fallback texture is used: the cube is textured.
    let scene = Scene::load(&path(
        "tests/cs1230/course/scenefiles/illuminate/required/texture_tests/textures.json",
    ))
    .unwrap();
    let textured: Vec<bool> = scene
        .objects
        .iter()
        .map(|o| scene.materials[o.material].texture.is_some())
        .collect();
    assert_eq!(textured, [true, true, false]);
    // render says it once on stderr.
    let out = tmp("course-fallback.png");
    let o = rtlab(&["render", ini.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(stderr(&o).matches("; using ").count(), 1, "{}", stderr(&o));
}

#[test]
fn texture_filter_flag_changes_the_lookup() {
    let r = settings(&[LIGHTS, "x", "--texture-filter", "bilinear"]);
    assert_eq!(r.texture_filter, rtlab::shading::TextureFilter::Bilinear);
    let r = settings(&[LIGHTS, "x"]);
    assert_eq!(r.texture_filter, rtlab::shading::TextureFilter::Nearest);
    let (a, b) = (tmp("course-nearest.png"), tmp("course-bilinear.png"));
    let scene = "tests/cs1230/scenes/textures.json";
    for (out, f) in [(&a, "nearest"), (&b, "bilinear")] {
        let o = rtlab(&[
            "render",
            scene,
            "--width",
            "96",
            "--height",
            "72",
            "--texture-filter",
            f,
            "-q",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    assert_ne!(png(&a), png(&b));
    let o = rtlab(&["render", scene, "--texture-filter", "trilinear"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("unknown texture filter \"trilinear\""));
}

/// Traces one ray through a scene with the tree recorder.
fn trace_tree(scene: &Scene, origin: glam::DVec3, dir: glam::DVec3) -> rtlab::trace::RayNode {
    use rtlab::trace::{RayKind, Tracer, TreeRecorder};
    let mut rec = TreeRecorder::new(scene);
    let tracer = Tracer::new(scene, &scene.render);
    let mut rng = rtlab::math::Rng::new(&[0]);
    let ray = rtlab::math::Ray::new(origin, dir.normalize());
    tracer.trace(
        &ray,
        RayKind::Camera,
        0,
        glam::DVec3::ONE,
        &mut rng,
        &mut rec,
    );
    rec.root.unwrap()
}

fn not_shadow(n: &rtlab::trace::RayNode) -> Vec<&rtlab::trace::RayNode> {
    n.children
        .iter()
        .filter(|c| c.kind != rtlab::trace::RayKind::Shadow)
        .collect()
}

/// A course scenefile: a clear glass object (no local shading: ka = kd = ks = 0 on it) in
/// front of a lit white wall.
fn glass_scene(name: &str, shape: &str, scale: [f64; 3], ior: f64) -> PathBuf {
    let text = format!(
        r#"{{"globalData": {{"ambientCoeff": 1, "diffuseCoeff": 1, "specularCoeff": 0, "transparentCoeff": 1}},
  "cameraData": {{"position": [0, 0, 5], "look": [0, 0, -1], "up": [0, 1, 0], "heightAngle": 45}},
  "groups": [
    {{"lights": [{{"type": "directional", "color": [1, 1, 1], "direction": [0, 0, -1]}}]}},
    {{"scale": {scale:?}, "primitives": [{{"type": "{shape}", "diffuse": [0, 0, 0], "transparent": [1, 1, 1], "ior": {ior}}}]}},
    {{"translate": [0, 0, -3], "scale": [40, 40, 0.1], "primitives": [{{"type": "cube", "diffuse": [0.5, 0.5, 0.5], "ambient": [0.1, 0.1, 0.1]}}]}}
  ]}}"#
    );
    write_tmp(&format!("course-refract/{name}.json"), &text)
}

#[test]
fn course_refraction_bends_twice_on_the_same_object_without_shading_inside() {
    use glam::DVec3;
    use rtlab::trace::{End, RayKind};
    let scene = Scene::load(&glass_scene("sphere", "sphere", [2.0, 2.0, 2.0], 1.5)).unwrap();
    assert!(
        scene.render.course_refraction,
        "the course loader turns it on"
    );
    // A ray parallel to the axis at height h hits the sphere (radius 1) at angle θi with
    // sin θi = h; inside it bends to θt = asin(h / 1.5); by symmetry it leaves deviated by
    // 2(θi − θt) towards the axis.
    let h = 0.5f64;
    let root = trace_tree(&scene, DVec3::new(0.0, h, 5.0), DVec3::NEG_Z);
    let rays = not_shadow(&root);
    assert_eq!(rays.len(), 1, "one transmitted ray, no reflection");
    let inner = rays[0];
    assert_eq!(inner.kind, RayKind::Refraction);
    assert!(inner.shading.is_none(), "the inner surface is not shaded");
    let exit = inner.hit.as_ref().unwrap();
    assert_eq!(
        exit.object,
        root.hit.as_ref().unwrap().object,
        "exit on the same object"
    );
    let (ti, tt) = (h.asin(), (h / 1.5).asin());
    let dev = 2.0 * (ti - tt);
    let out = not_shadow(inner)[0];
    assert_eq!(out.kind, RayKind::Refraction);
    let want = DVec3::new(0.0, -dev.sin(), -dev.cos());
    // (Up to the spawn offsets, a few 1e-6 in this 40-unit scene.)
    assert!(
        (out.direction.normalize() - want).length() < 1e-5,
        "{} vs {want}",
        out.direction
    );
    // The pixel is kt·Ot times what leaves: the wall at y ≈ −0.4, in the glass's shadow
    // (objects block whatever their transparency), so its ambient ka·Oa = 0.1 alone.
    assert!(
        (out.color - DVec3::splat(0.1)).length() < 1e-9,
        "{}",
        out.color
    );
    assert!((root.color - out.color).length() < 1e-12);
    assert_eq!(inner.end, End::Shaded);

    // Native scenes keep the general Whitted refraction: the inner surface is shaded (a
    // refraction ray hits it, with shading) and no exit search happens.
    let mut general = scene.clone();
    general.render.course_refraction = false;
    let root = trace_tree(&general, DVec3::new(0.0, h, 5.0), DVec3::NEG_Z);
    let inner = not_shadow(&root)[0];
    assert!(inner.shading.is_some());
}

#[test]
fn course_refraction_adds_nothing_on_total_internal_reflection() {
    use glam::DVec3;
    use rtlab::trace::End;
    // A tall block (x, z in [−0.5, 0.5], y in [−2, 2]) with ior 2: a ray entering its top at
    // 48.6° from the vertical bends to 22° and meets the side x = 0.5 at 68° from its
    // normal, past the critical angle asin(1/2) = 30°.
    let scene = Scene::load(&glass_scene("block", "cube", [1.0, 4.0, 1.0], 2.0)).unwrap();
    let dir = DVec3::new(3.4, -3.0, 0.0);
    let origin = DVec3::new(0.4, 2.0, 0.0) - dir;
    let root = trace_tree(&scene, origin, dir);
    let inner = not_shadow(&root)[0];
    let exit = inner.hit.as_ref().unwrap();
    assert!(
        (exit.point.x - 0.5).abs() < 1e-6,
        "leaves by the side: {}",
        exit.point
    );
    assert_eq!(inner.end, End::TotalInternalReflection);
    assert!(not_shadow(inner).is_empty(), "nothing is traced on");
    assert_eq!(inner.color, DVec3::ZERO);
    assert_eq!(
        root.color,
        DVec3::ZERO,
        "no local shading on the glass, nothing transmitted"
    );
    // rtlab's general refraction reflects inside instead, and brings light back.
    let mut general = scene.clone();
    general.render.course_refraction = false;
    let root = trace_tree(&general, origin, dir);
    assert_ne!(not_shadow(not_shadow(&root)[0]).len(), 0);
}
