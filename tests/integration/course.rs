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
