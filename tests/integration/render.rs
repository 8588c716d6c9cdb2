//! The render command end to end: every scene renders, output is deterministic.

use super::common::*;
use rtlab::sampling::render;

#[test]
fn every_scene_renders_small() {
    for p in all_scenes() {
        let mut scene =
            rtlab::scene::Scene::load(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        scene.camera.update_size(48, 36);
        let out = render(&scene, &scene.render, false, None);
        assert!(
            out.first_nan.is_none(),
            "{}: NaN sample {:?}",
            p.display(),
            out.first_nan
        );
        let lit = out
            .image
            .pixels
            .iter()
            .filter(|c| c.max_element() > 0.02)
            .count();
        assert!(
            lit > 48 * 36 / 10,
            "{}: the image is almost black ({lit} lit pixels)",
            p.display()
        );
    }
}

#[test]
fn same_bytes_on_any_thread_count() {
    let out1 = tmp("t1.png");
    let out2 = tmp("t2.png");
    let s = path("scenes/spheres.json");
    for (threads, out) in [("1", &out1), ("2", &out2)] {
        let o = rtlab(&[
            "render",
            s.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--threads",
            threads,
            "--width",
            "96",
            "--height",
            "72",
            "--quiet",
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    assert_eq!(std::fs::read(&out1).unwrap(), std::fs::read(&out2).unwrap());
}

#[test]
fn stats_json_has_the_contract_keys_and_counts_add_up() {
    let out = tmp("stats.png");
    let s = path("scenes/spheres.json");
    let o = rtlab(&[
        "render",
        s.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--width",
        "64",
        "--height",
        "48",
        "--stats",
        "json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let r = &v["rays"];
    let sum: u64 = ["camera", "shadow", "reflection", "refraction"]
        .iter()
        .map(|k| r[k].as_u64().unwrap())
        .sum();
    assert_eq!(sum, r["total"].as_u64().unwrap());
    assert_eq!(r["camera"].as_u64().unwrap(), 64 * 48);
    for k in ["load", "build", "trace"] {
        assert!(v["seconds"][k].as_f64().unwrap() >= 0.0);
    }
    assert!(v["mrays_per_s"].as_f64().unwrap() > 0.0);
}

/// The BVHs are built once, at load, and `--stats` times that build: part of the load, and
/// every mesh's counted (the teapot's 992 faces take a measurable moment).
#[test]
fn stats_time_the_build_the_load_made() {
    let out = tmp("stats-build.png");
    let s = path("scenes/teapot.json");
    let args = ["--width", "16", "--height", "12", "--stats", "json"];
    let o = rtlab(
        &[
            &["render", s.to_str().unwrap(), "-o", out.to_str().unwrap()][..],
            &args,
        ]
        .concat(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let (load, build) = (
        v["seconds"]["load"].as_f64().unwrap(),
        v["seconds"]["build"].as_f64().unwrap(),
    );
    assert!(
        build > 0.0 && build <= load,
        "build {build} s, load {load} s"
    );
    let scene = rtlab::scene::Scene::load(&s).unwrap();
    let meshes: Vec<f64> = scene
        .objects
        .iter()
        .filter_map(|o| match &o.shape {
            rtlab::shapes::Shape::Mesh(m) => Some(m.build_seconds),
            _ => None,
        })
        .collect();
    assert!(!meshes.is_empty() && meshes.iter().all(|&t| t > 0.0));
    let total = scene.accel.build_seconds(&scene.objects);
    assert_eq!(
        total,
        scene.accel.own_build_seconds + meshes.iter().sum::<f64>()
    );
}

#[test]
fn default_output_is_the_scene_stem_in_the_current_folder() {
    let dir = tmp("default-out");
    std::fs::create_dir_all(&dir).unwrap();
    let s = path("scenes/spheres.json");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_rtlab"))
        .args([
            "render",
            s.to_str().unwrap(),
            "--width",
            "16",
            "--height",
            "12",
            "--quiet",
        ])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.join("spheres.png").exists());
}

#[test]
fn depth_of_field_blurs_deterministically_and_can_be_switched_off() {
    let scene = r#"{
      "camera": {"position": [0, 0, 6], "fov_y": 30, "width": 48, "height": 32, "aperture": 0.6, "focal_distance": 6},
      "render": {"spp": 16, "sampler": "jittered"},
      "lights": [{"type": "directional", "direction": [0, 0, -1]}],
      "objects": [{"shape": "sphere", "radius": 1}, {"shape": "sphere", "center": [2, 0, -6], "radius": 1}]
    }"#;
    let p = write_tmp("dof.json", scene);
    let render_to = |name: &str, extra: &[&str]| {
        let out = tmp(name);
        let mut args = vec![
            "render",
            p.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--quiet",
        ];
        args.extend_from_slice(extra);
        let o = rtlab(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        std::fs::read(out).unwrap()
    };
    let a = render_to("dof1.png", &[]);
    let b = render_to("dof2.png", &["--threads", "1"]);
    let pinhole = render_to("dof3.png", &["--no-depth-of-field"]);
    assert_eq!(a, b, "same bytes on any thread count");
    assert_ne!(a, pinhole, "the aperture blurs the out-of-focus sphere");
}

/// The atomic write goes through a temporary file, which tempfile makes 0600; the PNG must
/// still get the mode any other new file gets here (0666 less the umask).
#[cfg(unix)]
#[test]
fn output_files_get_the_usual_permissions() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tmp("out-mode");
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("mode.png");
    let plain = dir.join("plain.txt");
    std::fs::write(&plain, b"x").unwrap();
    let s = path("scenes/spheres.json");
    let o = rtlab(&[
        "render",
        s.to_str().unwrap(),
        "--width",
        "8",
        "--height",
        "6",
        "--quiet",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let mode = |p: &std::path::Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode(&out), mode(&plain));
}

/// The ray budget's default, as `--help` and the scene schema tell it, is the one the tracer
/// uses (they once said 100000 while it was 10000).
#[test]
fn the_ray_budgets_default_is_told_as_it_is() {
    let told = format!("(default {})", rtlab::trace::DEFAULT_MAX_RAYS);
    let help = rtlab(&["render", "--help"]);
    let help = String::from_utf8_lossy(&help.stdout);
    let max_rays = help
        .split("--max-rays")
        .nth(1)
        .expect("render --help has --max-rays");
    assert!(max_rays.contains(&told), "--max-rays help: {max_rays}");
    let schema = std::fs::read_to_string(path("src/scene/schema.json")).unwrap();
    let schema: serde_json::Value = serde_json::from_str(&schema).unwrap();
    let text = schema.to_string();
    let at = text
        .find("Ray budget of one sample")
        .expect("schema describes max_rays");
    assert!(text[at..at + 60].contains(&told), "{}", &text[at..at + 60]);
}

/// The files a command read are its own: run in one process (as a library user may), a
/// command that reads texture t.png does not make a later command's `-o t.png` refused.
#[test]
fn an_earlier_commands_inputs_do_not_refuse_a_later_ones_output() {
    use clap::Parser;
    let dir = tmp("reads-per-command");
    std::fs::create_dir_all(&dir).unwrap();
    let png = rtlab::output::png_bytes(&image::RgbImage::new(1, 1)).unwrap();
    std::fs::write(dir.join("t.png"), png).unwrap();
    let scene = |objects: &str| {
        format!(
            r#"{{"camera": {{"position": [0, 0, 5], "width": 8, "height": 6}},
 "lights": [{{"type": "point", "position": [2, 2, 5]}}], "objects": [{objects}]}}"#
        )
    };
    let textured = r#"{"shape": "sphere", "material": {"texture": {"file": "t.png"}}}"#;
    std::fs::write(dir.join("textured.json"), scene(textured)).unwrap();
    std::fs::write(dir.join("plain.json"), scene(r#"{"shape": "sphere"}"#)).unwrap();
    let run = |args: &[&str]| {
        let cli = rtlab::cli::Cli::try_parse_from(args).unwrap();
        rtlab::cli::run(cli, &mut Vec::new())
    };
    let at = |name: &str| dir.join(name).to_str().unwrap().to_string();
    // Within one command the texture is protected...
    let e = run(&[
        "rtlab",
        "render",
        &at("textured.json"),
        "-o",
        &at("t.png"),
        "-q",
    ]);
    assert!(e
        .unwrap_err()
        .to_string()
        .contains("a file the scene reads"));
    // ...and a later command that does not read it may write it.
    run(&[
        "rtlab",
        "render",
        &at("textured.json"),
        "-o",
        &at("a.png"),
        "-q",
    ])
    .unwrap();
    run(&[
        "rtlab",
        "render",
        &at("plain.json"),
        "-o",
        &at("t.png"),
        "-q",
    ])
    .unwrap();
}
