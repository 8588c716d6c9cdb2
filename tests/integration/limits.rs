//! Scenes built to freeze rtlab (issue 22): mirror-and-glass trees that double at every bounce,
//! Ctrl-C inside one huge tree, JSON nested past the reader's limit. Each must end quickly
//! and say what happened.

use crate::common::{path, rtlab, stderr, tmp, write_tmp};
use rtlab::scene::Scene;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The scene of the issue: three nested spheres, each a perfect mirror and perfect glass,
/// max_depth 64 and no cutoff, so every hit splits in two and a tree can reach 2^65 rays.
const NESTED_GLASS: &str = r#"{
  "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov_y": 40, "width": 64, "height": 48},
  "render": {"max_depth": 64, "min_contribution": 0},
  "lights": [{"name": "key", "type": "point", "position": [3, 4, 5]}],
  "materials": {
    "glass": {"diffuse": [0.1, 0.1, 0.1], "reflective": [1, 1, 1], "transparent": [1, 1, 1], "ior": 1.5}
  },
  "objects": [
    {"name": "outer", "shape": "sphere", "center": [0, 0, 0], "radius": 1.5, "material": "glass"},
    {"name": "middle", "shape": "sphere", "center": [0, 0, 0], "radius": 1.0, "material": "glass"},
    {"name": "inner", "shape": "sphere", "center": [0, 0, 0], "radius": 0.5, "material": "glass"}
  ]
}"#;

fn nested_glass(name: &str) -> String {
    write_tmp(name, NESTED_GLASS).display().to_string()
}

/// The render's budget warning: (samples cut, the explain command it gives).
fn budget_warning(err: &str) -> (u64, String) {
    let line = err
        .lines()
        .find(|l| l.starts_with("warning: the ray budget"))
        .unwrap_or_else(|| panic!("no ray-budget warning in:\n{err}"));
    let cut = line
        .split(") cut ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no count in: {line}"));
    let cmd = line
        .split("See where it was cut with: ")
        .nth(1)
        .unwrap_or_else(|| panic!("no explain command in: {line}"))
        .to_string();
    (cut, cmd)
}

#[test]
fn nested_mirror_glass_renders_with_a_budget_warning_on_any_thread_count() {
    let scene = nested_glass("nested.json");
    let (one, two) = (tmp("nested-1.png"), tmp("nested-2.png"));
    let t0 = Instant::now();
    let o = rtlab(&[
        "render",
        &scene,
        "-o",
        one.to_str().unwrap(),
        "--threads",
        "1",
    ]);
    // A sanity bound only (the machine may be busy): before the budget it never finished.
    assert!(t0.elapsed() < Duration::from_secs(300));
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("warning: the ray budget (10000 rays per sample"),
        "{err}"
    );
    let (cut, cmd) = budget_warning(&err);
    assert!(cut > 0, "{err}");
    // The first cut pixel is the first in row-major order and the command replays it.
    assert!(
        cmd.starts_with(&format!("rtlab explain {scene} --pixel ")) && cmd.contains(" --sample "),
        "{cmd}"
    );
    let o2 = rtlab(&[
        "render",
        &scene,
        "-o",
        two.to_str().unwrap(),
        "--threads",
        "2",
    ]);
    assert!(o2.status.success(), "{}", stderr(&o2));
    assert_eq!(
        budget_warning(&stderr(&o2)),
        (cut, cmd),
        "the same cut on any thread count"
    );
    assert_eq!(
        std::fs::read(&one).unwrap(),
        std::fs::read(&two).unwrap(),
        "--threads 1 and 2 give the same bytes"
    );
}

/// Every ray of an explain tree, depth first.
fn count_rays(node: &serde_json::Value) -> usize {
    1 + node["children"]
        .as_array()
        .map_or(0, |c| c.iter().map(count_rays).sum())
}

fn ends(node: &serde_json::Value, out: &mut Vec<String>) {
    out.push(node["end"].as_str().unwrap_or("").to_string());
    for c in node["children"].as_array().into_iter().flatten() {
        ends(c, out);
    }
}

/// Renders the nested glass (as `NAME.json`, with `options`) under a budget of 40 rays a
/// sample; the explain command its warning gives.
fn cut_at_40(name: &str, options: &[&str]) -> String {
    let scene = nested_glass(&format!("{name}.json"));
    let out = tmp(&format!("{name}.png"));
    let mut args = vec!["render", &scene, "-o", out.to_str().unwrap()];
    args.extend(["--max-rays", "40", "--quiet"]);
    args.extend(options);
    let o = rtlab(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    budget_warning(&stderr(&o)).1
}

#[test]
fn explain_of_a_cut_pixel_shows_where_the_budget_cut_it() {
    let cmd = cut_at_40("nested-explain", &[]);
    assert!(cmd.ends_with("--max-rays 40"), "{cmd}");
    let args: Vec<&str> = cmd.split(' ').skip(1).collect();
    let mut json_args = args.clone();
    json_args.extend(["--format", "json"]);
    let j = rtlab(&json_args);
    assert!(j.status.success(), "{}", stderr(&j));
    let v: serde_json::Value = serde_json::from_slice(&j.stdout).unwrap();
    let samples = v["samples"].as_array().unwrap();
    assert_eq!(samples.len(), 1, "--sample picks the cut sample");
    let tree = &samples[0]["ray"];
    let mut e = Vec::new();
    ends(tree, &mut e);
    assert!(e.iter().any(|s| s == "ray-budget"), "{e:?}");
    // At most the budget, plus the shadow ray of the last hit (one light).
    let rays = count_rays(tree);
    assert!((40..=41).contains(&rays), "{rays} rays in a tree cut at 40");
    let t = rtlab(&args);
    assert!(t.status.success(), "{}", stderr(&t));
    let text = String::from_utf8_lossy(&t.stdout);
    assert!(text.contains("cut: ray budget reached"), "{text}");
    // The sample's header says so too, with the same count as the JSON tree.
    assert!(
        text.contains(&format!(
            "cut: ray budget reached: this sample traced {rays} rays, the budget is 40"
        )),
        "{text}"
    );
}

/// A pass of `--passes K` (or of a time budget) traces its own samples (pass 3 of a 1-spp
/// scene: 4 spp grid): the warning's explain command names them, and finds the cut sample.
#[test]
fn a_pass_cut_by_the_budget_is_explained_with_the_pass_samples() {
    let options = ["--passes", "3", "--width", "16", "--height", "12"];
    let cmd = cut_at_40("nested-pass", &options);
    assert!(cmd.contains(" --spp 4 --sampler grid"), "{cmd}");
    let args: Vec<&str> = cmd.split(' ').skip(1).collect();
    let t = rtlab(&args);
    assert!(t.status.success(), "{cmd}: {}", stderr(&t));
    let text = String::from_utf8_lossy(&t.stdout);
    assert!(text.contains("cut: ray budget reached"), "{text}");
}

#[test]
fn the_budget_is_per_sample_in_the_library_too() {
    let mut scene = Scene::load(&path("scenes/glass.json")).unwrap();
    scene.render.max_depth = 64;
    scene.render.min_contribution = 0.0;
    scene.render.max_rays = 25;
    let s = scene.render.clone();
    // A pixel on the glass sphere (135 rays at the scene's own max_depth 8).
    let film = glam::DVec2::new(569.5, 205.5);
    let mut rec = rtlab::trace::NoRecorder::default();
    let a = rtlab::trace::trace_sample(&scene, &s, 569, 205, 0, film, &mut rec);
    let b = rtlab::trace::trace_sample(&scene, &s, 569, 205, 0, film, &mut rec);
    assert_eq!((a.color, a.rays, a.cut), (b.color, b.rays, b.cut));
    assert!(a.cut);
    // Two point lights: at most two shadow rays past the budget.
    assert!((25..=25 + 2).contains(&a.rays), "{} rays", a.rays);
    // With the scene's own settings the tree is whole.
    let scene = Scene::load(&path("scenes/glass.json")).unwrap();
    let s = scene.render.clone();
    let full = rtlab::trace::trace_sample(&scene, &s, 569, 205, 0, film, &mut rec);
    assert!(!full.cut && full.rays > 27, "{} rays", full.rays);
}

#[test]
fn the_default_budget_never_binds_on_the_shipped_and_course_scenes() {
    let mut files = crate::common::all_scenes();
    for f in std::fs::read_dir(path("tests/cs1230/scenes")).unwrap() {
        files.push(f.unwrap().path());
    }
    files.sort();
    for f in files {
        // Smaller images, same trees per sample.
        let args = rtlab::cli::RenderArgs {
            width: Some(96),
            height: Some(64),
            ..Default::default()
        };
        let scene = args.load(&f).unwrap();
        assert_eq!(scene.render.max_rays, rtlab::trace::DEFAULT_MAX_RAYS);
        let out = rtlab::sampling::render(&scene, &scene.render, false, None);
        assert_eq!(out.cut_samples, 0, "{} was cut", f.display());
        // And no warning before the render.
        assert_eq!(
            rtlab::trace::branching_warning(&scene, &scene.render),
            None,
            "{}",
            f.display()
        );
    }
}

#[test]
fn validate_warns_of_exponential_trees_with_the_worst_case_and_the_way_out() {
    let scene = nested_glass("nested-validate.json");
    let o = rtlab(&["validate", &scene]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    for part in [
        "warning: the scene can branch exponentially",
        "material \"glass\" is both reflective and transparent",
        "2^65 − 1 ≈ 3.7e19 rays",
        "each hit casts 1 shadow ray(s): up to 7.4e19 rays per sample",
        "cuts each sample at 10000 rays",
        // 2^12 − 1 = 4095 nodes, twice that with the shadow rays: 8190 ≤ 10000.
        "lower max_depth to 11 (--max-depth 11)",
        "raise --max-rays",
    ] {
        assert!(out.contains(part), "missing {part:?} in:\n{out}");
    }
    // Within the budget the warning goes away.
    let mut s = Scene::load(std::path::Path::new(&scene)).unwrap();
    s.render.max_depth = 11;
    assert_eq!(rtlab::trace::branching_warning(&s, &s.render), None);
    s.render.max_depth = 12;
    assert!(rtlab::trace::branching_warning(&s, &s.render).is_some());
    // Weights below 1 and a cutoff bound the depth: 0.5^10 < 0.001, so depth 9 at most.
    s.render.max_depth = 64;
    s.render.min_contribution = 0.001;
    for m in &mut s.materials {
        m.reflective = glam::DVec3::splat(0.5);
        m.transparent = glam::DVec3::splat(0.5);
    }
    let w = rtlab::trace::worst_case(&s, &s.render);
    assert_eq!((w.branching, w.depth, w.shadow_rays), (2, 9, 1));
    assert_eq!(w.rays_per_sample, (1024.0 - 1.0) * 2.0);
    assert_eq!(rtlab::trace::branching_warning(&s, &s.render), None);
}

/// Waits until the child runs more than one thread (the Ctrl-C handler's thread exists).
fn wait_for_handler(pid: u32) {
    let status = format!("/proc/{pid}/status");
    for _ in 0..2000 {
        let threads = std::fs::read_to_string(&status)
            .ok()
            .and_then(|s| {
                s.lines()
                    .find_map(|l| l.strip_prefix("Threads:").map(|n| n.trim().to_string()))
            })
            .and_then(|n| n.parse::<u32>().ok())
            .unwrap_or(0);
        if threads > 1 {
            return;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

#[test]
fn ctrl_c_inside_one_huge_tree_stops_within_seconds_and_writes_nothing() {
    let scene = nested_glass("nested-ctrl-c.json");
    let out = tmp("nested-ctrl-c.png");
    let _ = std::fs::remove_file(&out);
    // One pixel, a budget it will not reach for hours: all the time is inside one tree.
    let child = Command::new(env!("CARGO_BIN_EXE_rtlab"))
        .args([
            "render",
            &scene,
            "-o",
            out.to_str().unwrap(),
            "--width",
            "1",
            "--height",
            "1",
            "--max-rays",
            "4000000000",
            "--threads",
            "1",
        ])
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    wait_for_handler(child.id());
    std::thread::sleep(Duration::from_millis(300));
    let t0 = Instant::now();
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let o = child.wait_with_output().unwrap();
    let waited = t0.elapsed();
    assert_eq!(o.status.code(), Some(130), "{}", stderr(&o));
    assert!(stderr(&o).contains("nothing was written"), "{}", stderr(&o));
    assert!(waited < Duration::from_secs(10), "stopped after {waited:?}");
    assert!(!out.exists(), "an interrupted render wrote its file");
}

#[test]
fn a_cancelled_token_stops_a_render_inside_one_huge_tree() {
    let mut scene = Scene::load(std::path::Path::new(&nested_glass("nested-cancel.json"))).unwrap();
    scene.camera.update_size(1, 1);
    scene.render.max_rays = u64::MAX;
    let cancel = rtlab::interrupt::Cancel::new();
    scene.render.cancel = cancel.clone();
    assert!(!cancel.is_cancelled());
    let t = std::thread::spawn(move || {
        std::thread::sleep(Duration::from_millis(200));
        cancel.cancel();
    });
    let out = rtlab::sampling::render(&scene, &scene.render, false, None);
    t.join().unwrap();
    assert!(out.cancelled);
    assert!(scene.render.cancel.is_cancelled());
    // A token of its own does not touch the global Ctrl-C flag.
    assert!(!rtlab::interrupt::requested());
    assert!(!rtlab::interrupt::Cancel::default().is_cancelled());
}

#[test]
fn a_cancelled_render_skips_its_tiles_without_planning_them() {
    // The bundled render plans each tile's samples before tracing it: 2000×2000 pixels at
    // 64 samples is 256 million samples to plan, many seconds of work. A render whose token
    // is already cancelled (Ctrl-C pressed while the scene loaded) must skip every tile, in
    // both traversals, as promptly as the single-ray render always did.
    let mut scene = Scene::load(std::path::Path::new(&nested_glass("cancel-tiles.json"))).unwrap();
    scene.camera.update_size(2000, 2000);
    scene.render.spp = 64;
    scene.render.sampler = rtlab::scene::SamplerKind::Grid;
    let cancel = rtlab::interrupt::Cancel::new();
    cancel.cancel();
    scene.render.cancel = cancel;
    for traversal in [
        rtlab::accel::Traversal::Bundle,
        rtlab::accel::Traversal::Single,
    ] {
        let mut settings = scene.render.clone();
        settings.traversal = traversal;
        let t0 = Instant::now();
        let out = rtlab::sampling::render(&scene, &settings, false, None);
        assert!(out.cancelled);
        let took = t0.elapsed();
        assert!(
            took < Duration::from_secs(3),
            "{traversal:?}: took {took:?} to give up"
        );
    }
}

#[test]
fn json_nested_past_the_reader_limit_says_the_limit_and_the_way_out() {
    fn csg(levels: usize) -> String {
        let mut node = r#"{"shape": "sphere", "radius": 1}"#.to_string();
        for _ in 0..levels {
            node = format!(
                r#"{{"shape": "csg", "op": "union", "children": [{node}, {{"shape": "sphere", "radius": 1}}]}}"#
            );
        }
        format!(r#"{{"camera": {{"position": [0, 0, 5]}}, "objects": [{node}]}}"#)
    }
    let ok = write_tmp("csg-62.json", &csg(62));
    let o = rtlab(&["validate", ok.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let deep = write_tmp("csg-63.json", &csg(63));
    let o = rtlab(&["validate", deep.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    for part in [
        "csg-63.json: line 1:",
        "nested more than 128 levels deep",
        "a CSG tree can be about 62 levels deep",
        "takes any number of children",
    ] {
        assert!(err.contains(part), "missing {part:?} in: {err}");
    }
}

#[test]
fn a_budget_of_zero_rays_is_refused() {
    let scene = nested_glass("nested-zero.json");
    let o = rtlab(&["render", &scene, "-o", "x.png", "--max-rays", "0"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("argument --max-rays: must be at least 1"),
        "{}",
        stderr(&o)
    );
    let s = write_tmp(
        "zero-budget.json",
        r#"{"camera": {"position": [0, 0, 5]}, "render": {"max_rays": 0}}"#,
    );
    let o = rtlab(&["validate", s.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("render.max_rays: max_rays must be at least 1"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_storyboard_of_a_huge_tree_is_refused_with_the_limit_and_the_way_out() {
    let scene = nested_glass("nested-steps.json");
    let dir = tmp("nested-steps");
    let t0 = Instant::now();
    let o = rtlab(&[
        "steps",
        &scene,
        "-o",
        dir.to_str().unwrap(),
        "--pixel",
        "29,3",
    ]);
    assert!(t0.elapsed() < Duration::from_secs(60));
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("ray tree has 10000 rays, more than the 500 a storyboard draws"),
        "{err}"
    );
    // Cut short by the budget, the same pixel makes a storyboard that ends at the cut.
    let o = rtlab(&[
        "steps",
        &scene,
        "-o",
        dir.to_str().unwrap(),
        "--pixel",
        "29,3",
        "--max-rays",
        "12",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("cut: ray budget reached"), "{out}");
}

/// The memory a render needs counts the samples of the pixels it traces: under
/// `--subsample 64` a 120×90 image traces 3×3 pixels, so 16,384 samples each fit easily,
/// where the same samples at every pixel would not.
#[test]
fn the_memory_estimate_counts_only_the_traced_pixels() {
    use rtlab::sampling::{memory_needed, MEMORY_BUDGET};
    let every = memory_needed(120, 90, 16384, 1);
    let sub = memory_needed(120, 90, 16384, 64);
    assert!(
        every > MEMORY_BUDGET && sub < MEMORY_BUDGET / 100,
        "{every} {sub}"
    );
    // 3 traced columns of 120 (0, 64 and the last, 119), 3 rows of 90 (0, 64, 89).
    let per_sample = (every - memory_needed(120, 90, 16383, 1)) / (120 * 90);
    assert_eq!(every - sub, (120 * 90 - 9) * 16384 * per_sample);
    let o = rtlab(&[
        "render",
        "scenes/whitted.json",
        "--width",
        "120",
        "--height",
        "90",
        "--subsample",
        "64",
        "--spp",
        "16384",
        "--sampler",
        "grid",
        "-o",
        tmp("sub64.png").to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// The adaptive sampler keeps every level it refines through (4 + 16 + 64 samples at
/// `--spp 64`), and the memory estimate counts them: there is an image size that 64 samples
/// a pixel fit and the adaptive sampler's 84 do not, and the refusal says why.
#[test]
fn the_memory_estimate_counts_the_adaptive_samplers_levels() {
    use rtlab::sampling::check_memory;
    use rtlab::scene::SamplerKind::{Adaptive, Jittered};
    assert_eq!(rtlab::sampling::most_samples(Adaptive, 64), 84);
    assert_eq!(rtlab::sampling::most_samples(Adaptive, 1), 1);
    assert_eq!(rtlab::sampling::most_samples(Jittered, 64), 64);
    let side = (100..20_000u32)
        .step_by(10)
        .find(|&s| check_memory(s, s, Adaptive, 64, 1).is_err())
        .unwrap();
    assert!(check_memory(side, side, Jittered, 64, 1).is_ok(), "{side}");
    let e = check_memory(side, side, Adaptive, 64, 1).unwrap_err();
    assert!(e.contains("up to 84 samples per pixel"), "{e}");
}

/// The corners sampler keeps two samples a pixel (its centre and the corner it owns, more
/// on the right and bottom borders), whatever `spp` says (1 or 5): there is an image size
/// that one sample a pixel fits and corners does not, the refusal says why, and `render`
/// refuses it before tracing anything, writing nothing.
#[test]
fn the_memory_estimate_counts_the_corners_samplers_two_samples() {
    use rtlab::sampling::check_memory;
    use rtlab::scene::SamplerKind::{Center, Corners};
    let side = (100..12_000u32)
        .step_by(100)
        .find(|&s| check_memory(s, s, Corners, 1, 1).is_err())
        .unwrap();
    assert!(check_memory(side, side, Center, 1, 1).is_ok(), "{side}");
    assert!(check_memory(side, side, Corners, 5, 1).is_err(), "{side}");
    let e = check_memory(side, side, Corners, 1, 1).unwrap_err();
    assert!(e.contains("two samples each (the corners sampler"), "{e}");
    let out = tmp("corners-too-big.png");
    let side = side.to_string();
    let o = rtlab(&[
        "render",
        "scenes/spheres.json",
        "--width",
        &side,
        "--height",
        &side,
        "--sampler",
        "corners",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("the corners sampler"), "{}", stderr(&o));
    assert!(!out.exists());
}
