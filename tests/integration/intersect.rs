//! `rtlab intersect` against hand computations, its figures' display lists, and the ray-tree
//! slice of `explain --diagram`.

use super::common::*;
use rtlab::cli::explain::explain;
use rtlab::viz::slice::{draw, event_count, SliceOptions, SlicePlane};
use rtlab::viz::Prim;

fn tree(scene: &rtlab::scene::Scene, x: u32, y: u32) -> rtlab::trace::RayNode {
    explain(scene, x, y).samples.remove(0).ray
}

fn count_nodes(n: &rtlab::trace::RayNode) -> usize {
    1 + n.children.iter().map(count_nodes).sum::<usize>()
}

#[test]
fn slice_events_are_the_rays_of_the_tree() {
    let scene = scene("scenes/spheres.json");
    let t = tree(&scene, 240, 150); // the mirror ball: camera, shadow, reflection
    assert_eq!(event_count(&t), count_nodes(&t));
    assert!(event_count(&t) >= 3);
    // One event: only the camera ray is drawn (one arrow in the camera colour, no other ray).
    let opts = SliceOptions {
        events: Some(1),
        ..Default::default()
    };
    let c = draw(&scene, &t, &opts).unwrap();
    // Rays in the plot, not the legend's sample arrows in the band at the bottom (the
    // legend lists every kind of the whole tree, drawn or not yet).
    let ray_colors = |c: &rtlab::viz::Canvas| {
        let band = c.height() - 70.0;
        c.display
            .iter()
            .filter_map(|p| match p {
                Prim::Arrow {
                    color, width, from, ..
                } if *width >= 2.0 && from[1] < band => Some(color.clone()),
                _ => None,
            })
            .collect::<Vec<_>>()
    };
    let camera = "#1f77b4".to_string();
    let first = ray_colors(&c);
    assert!(first.contains(&camera), "{first:?}");
    assert!(!first.contains(&"#2ca02c".to_string()), "{first:?}");
    // All events: the reflection (green) appears too.
    let all = draw(&scene, &t, &SliceOptions::default()).unwrap();
    assert!(ray_colors(&all).contains(&"#2ca02c".to_string()));
    assert!(draw(
        &scene,
        &t,
        &SliceOptions {
            width: 10,
            ..Default::default()
        }
    )
    .is_err());
}

#[test]
fn slice_cuts_the_hit_sphere_with_its_true_radius() {
    // The camera plane of pixel (70, 170) goes through the red ball's hit point; the ball's
    // section is a disc whose width in pixels matches the figure scale. We check the section
    // instead through its centre line: the red ball (radius 0.7) is filled around its hit.
    let scene = scene("scenes/spheres.json");
    let t = tree(&scene, 70, 170);
    let c = draw(&scene, &t, &SliceOptions::default()).unwrap();
    let fill = c
        .display
        .iter()
        .find_map(|p| match p {
            Prim::Mask {
                what,
                pixels,
                bounds,
                ..
            } if what == "red (inside)" => Some((*pixels, *bounds)),
            _ => None,
        })
        .expect("the red ball is cut by the slice");
    let (px, b) = fill;
    let (w, h) = ((b[2] - b[0] + 1) as f64, (b[3] - b[1] + 1) as f64);
    // A disc: round (w ≈ h) and about π/4 of its bounding square.
    assert!((w - h).abs() <= 2.0, "{w} x {h}");
    let ratio = px as f64 / (w * h);
    assert!(
        (ratio - std::f64::consts::FRAC_PI_4).abs() < 0.04,
        "{ratio}"
    );
}

#[test]
fn slice_is_deterministic_and_snapshotted() {
    let scene = scene("scenes/spheres.json");
    let t = tree(&scene, 240, 150);
    let opts = SliceOptions::default();
    let a = draw(&scene, &t, &opts).unwrap();
    let b = draw(&scene, &t, &opts).unwrap();
    assert_eq!(a.png_bytes().unwrap(), b.png_bytes().unwrap());
    assert_eq!((a.width(), a.height()), (720.0, 480.0));
    insta::with_settings!({
        description => "spheres.json pixel (240, 150): camera ray hits the mirror ball, one shadow ray, a reflection that misses",
        snapshot_path => "snapshots/intersect",
    }, {
        insta::assert_yaml_snapshot!("slice_spheres_mirror", a.display);
    });
    let bounce = SliceOptions {
        plane: SlicePlane::Bounce,
        ..Default::default()
    };
    let g = scene_glass();
    let tg = tree(&g, 160, 120);
    let c = draw(&g, &tg, &bounce).unwrap();
    assert!(c
        .display
        .iter()
        .any(|p| matches!(p, Prim::Text { text, .. } if text.contains("first bounce"))));
}

fn scene_glass() -> rtlab::scene::Scene {
    scene("scenes/glass.json")
}

#[test]
fn explain_diagram_writes_a_png_and_leaves_the_text_alone() {
    let out = tmp("diagram.png");
    let plain = rtlab(&["explain", "scenes/spheres.json", "--pixel", "70,170"]);
    let with = rtlab(&[
        "explain",
        "scenes/spheres.json",
        "--pixel",
        "70,170",
        "--diagram",
        out.to_str().unwrap(),
    ]);
    assert!(with.status.success(), "{}", stderr(&with));
    assert_eq!(plain.stdout, with.stdout);
    let img = image::open(&out).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (720, 480));
    let bad = rtlab(&[
        "explain",
        "scenes/spheres.json",
        "--pixel",
        "70,170",
        "--diagram",
        out.to_str().unwrap(),
        "--diagram-plane",
        "sideways",
    ]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(stderr(&bad).contains("camera or bounce"));
}

// ---------------------------------------------------------------------------------------
// rtlab intersect

fn intersect_json(args: &[&str]) -> serde_json::Value {
    let mut all = vec!["intersect"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["--format", "json"]);
    let o = rtlab(&all);
    assert!(o.status.success(), "{:?}: {}", args, stderr(&o));
    serde_json::from_slice(&o.stdout).expect("intersect prints JSON")
}

fn f(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

fn close(v: &serde_json::Value, x: f64) {
    assert!((f(v) - x).abs() < 1e-9, "{v} != {x}");
}

fn close_all(v: &serde_json::Value, xs: &[f64]) {
    let a = v.as_array().unwrap_or_else(|| panic!("not an array: {v}"));
    assert_eq!(a.len(), xs.len(), "{v}");
    for (a, x) in a.iter().zip(xs) {
        close(a, *x);
    }
}

#[test]
fn lecture_circle_is_a_tangent_at_t_3() {
    // P = (-3, 1), d = (0.8, -0.6): t² - 6t + 9 = 0, D = 0, t = 3, point (-0.6, -0.8).
    let j = intersect_json(&["circle", "--origin", "-3,1", "--dir", "0.8,-0.6"]);
    assert_eq!(j["shape"], "circle");
    let q = &j["quadratic"];
    close(&q["a"], 1.0);
    close(&q["b"], -6.0);
    close(&q["c"], 9.0);
    assert_eq!(q["roots"], "tangent");
    assert!(f(&q["discriminant"]).abs() < 1e-13);
    let c = j["candidates"].as_array().unwrap();
    assert_eq!(c.len(), 1, "a tangent gives one candidate");
    close(&c[0]["t"], 3.0);
    close_all(&c[0]["point"], &[-0.6, -0.8]);
    close(&j["hit"]["t"], 3.0);
    close_all(&j["hit"]["normal"], &[-0.6, -0.8]);
    // The text says D = 0 and why the computed value was not exactly 0.
    let o = rtlab(&[
        "intersect",
        "circle",
        "--origin",
        "-3,1",
        "--dir",
        "0.8,-0.6",
    ]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("D = b² − 4ac = 0"), "{text}");
    assert!(text.contains("TANGENT_TOLERANCE"), "{text}");
    assert!(text.contains("tangent"), "{text}");
}

#[test]
fn sphere_from_inside_tosses_the_root_behind() {
    // From the centre of the unit sphere along +z: t² - 1 = 0, roots -1 and 1.
    let j = intersect_json(&["sphere", "--origin", "0,0,0", "--dir", "0,0,1"]);
    close(&j["quadratic"]["discriminant"], 4.0);
    assert_eq!(j["quadratic"]["roots"], "two");
    let c = j["candidates"].as_array().unwrap();
    close(&c[0]["t"], -1.0);
    assert_eq!(c[0]["in_front"], false);
    assert!(c[0]["note"].as_str().unwrap().contains("behind"));
    close(&c[1]["t"], 1.0);
    assert!(c[1]["note"].as_str().unwrap().starts_with("kept"));
    close_all(&j["hit"]["normal"], &[0.0, 0.0, 1.0]);
}

#[test]
fn sphere_grazed_exactly_is_a_tangent() {
    // y = 1 grazes the unit sphere at (0, 1, 0): t² - 4t + 4 = 0, D = 0 exactly.
    let j = intersect_json(&["sphere", "--origin", "-2,1,0", "--dir", "1,0,0"]);
    assert_eq!(j["quadratic"]["roots"], "tangent");
    assert_eq!(j["quadratic"]["rounded_to_zero"], false);
    close(&j["hit"]["t"], 2.0);
    close_all(&j["hit"]["point"], &[0.0, 1.0, 0.0]);
}

#[test]
fn plane_parallel_and_behind() {
    let j = intersect_json(&["plane", "--origin", "0,1,0", "--dir", "1,0,0"]);
    assert!(j["quadratic"].is_null());
    // The routine reports n·d = 0 before it gives up: the text can say "parallel".
    assert_eq!(f(&j["linear"]["denominator"]), 0.0);
    close(&j["linear"]["numerator"], -1.0);
    let o = rtlab(&["intersect", "plane", "--origin", "0,1,0", "--dir", "1,0,0"]);
    assert!(String::from_utf8_lossy(&o.stdout).contains("parallel"));
    assert_eq!(j["candidates"].as_array().unwrap().len(), 0);
    assert!(j["hit"].is_null());
    let j = intersect_json(&["plane", "--origin", "0,1,0", "--dir", "0,1,0"]);
    let c = &j["candidates"][0];
    close(&c["t"], -1.0);
    assert_eq!(c["in_front"], false);
    assert!(j["hit"].is_null());
    // Not normalised: t is the parameter of P + t·d, so d = (0, -2, 0) meets y = 0 at t = 0.5.
    let j = intersect_json(&["plane", "--origin", "0,1,0", "--dir", "0,-2,0"]);
    close(&j["hit"]["t"], 0.5);
}

#[test]
fn cylinder_through_both_cap_rims() {
    // From (2, 2, 0) along (-1, -1, 0): the body roots t = 1 and 3 are the points (1, 1, 0)
    // and (-1, -1, 0), exactly on the rims, where the cap roots land too.
    let j = intersect_json(&["cylinder", "--origin", "2,2,0", "--dir", "-1,-1,0"]);
    let q = &j["quadratic"];
    close(&q["a"], 1.0);
    close(&q["b"], -4.0);
    close(&q["c"], 3.0);
    let c = j["candidates"].as_array().unwrap();
    assert_eq!(c.len(), 4);
    let ts: Vec<f64> = c.iter().map(|c| f(&c["t"])).collect();
    for (t, want) in ts.iter().zip([1.0, 1.0, 3.0, 3.0]) {
        assert!((t - want).abs() < 1e-9, "{ts:?}");
    }
    assert!(c.iter().all(|c| c["on_shape"] == true), "{c:?}");
    close(&j["hit"]["t"], 1.0);
    close_all(&j["hit"]["point"], &[1.0, 1.0, 0.0]);
}

#[test]
fn cylinder_tosses_by_y_range_and_disc() {
    // From (-3, 1.5, 0.3) along (1, -0.4, 0): body t = 3 ± √0.91, the top cap's plane at
    // t = 1.25 outside its disc (x = -1.75), the bottom's at t = 6.25 (x = 3.25).
    let j = intersect_json(&["cylinder", "--origin", "-3,1.5,0.3", "--dir", "1,-0.4,0"]);
    let c = j["candidates"].as_array().unwrap();
    let s = 0.91f64.sqrt();
    let want = [
        (1.25, "top-cap", false),
        (3.0 - s, "body", true),
        (3.0 + s, "body", true),
        (6.25, "bottom-cap", false),
    ];
    for (c, (t, surface, on)) in c.iter().zip(want) {
        close(&c["t"], t);
        assert_eq!(c["surface"], surface);
        assert_eq!(c["on_shape"], on);
    }
    assert!(c[0]["note"]
        .as_str()
        .unwrap()
        .contains("outside the cap's disc"));
    assert!(c[2]["note"]
        .as_str()
        .unwrap()
        .contains("smaller t was kept"));
    close(&j["hit"]["t"], 3.0 - s);
    // Open: no cap candidates at all.
    let j = intersect_json(&[
        "cylinder",
        "--origin",
        "-3,1.5,0.3",
        "--dir",
        "1,-0.4,0",
        "--open",
    ]);
    assert_eq!(j["candidates"].as_array().unwrap().len(), 2);
}

#[test]
fn cone_body_roots_and_normal() {
    // y = 0.5 across the unit double cone: x² = 0.25, so x = ±0.5 at t = 2.5 and 3.5.
    let j = intersect_json(&["cone", "--origin", "-3,0.5,0", "--dir", "1,0,0"]);
    close(&j["quadratic"]["discriminant"], 1.0);
    let c = j["candidates"].as_array().unwrap();
    assert_eq!(c.len(), 2, "a horizontal ray has no cap root");
    close(&c[0]["t"], 2.5);
    close(&c[1]["t"], 3.5);
    let h = 0.5f64.sqrt();
    close_all(&j["hit"]["normal"], &[-h, -h, 0.0]);
}

#[test]
fn box_faces_inside_and_parallel() {
    let j = intersect_json(&["box", "--origin", "-3,0,0", "--dir", "1,0,0"]);
    assert!(j["quadratic"].is_null());
    let c = j["candidates"].as_array().unwrap();
    assert_eq!(
        c.len(),
        2,
        "parallel to the y and z slabs: only the x faces have roots"
    );
    close(&j["hit"]["t"], 2.0);
    assert_eq!(j["hit"]["surface"], "x-min");
    close_all(&j["hit"]["normal"], &[-1.0, 0.0, 0.0]);
    let j = intersect_json(&["box", "--origin", "0,0,0", "--dir", "1,0,0"]);
    let c = j["candidates"].as_array().unwrap();
    close(&c[0]["t"], -1.0);
    assert_eq!(c[0]["in_front"], false);
    close(&j["hit"]["t"], 1.0);
}

#[test]
fn triangle_inside_outside_and_degenerate() {
    let tri = ["--a", "0,0,0", "--b", "1,0,0", "--c", "0,1,0"];
    let mut args = vec!["triangle", "--origin", "0.25,0.5,2", "--dir", "0,0,-1"];
    args.extend_from_slice(&tri);
    let j = intersect_json(&args);
    let b = &j["barycentric"];
    close(&b["alpha"], 0.25);
    close(&b["beta"], 0.25);
    close(&b["gamma"], 0.5);
    close(&b["t"], 2.0);
    close(&b["determinant"], 1.0);
    close_all(&j["hit"]["point"], &[0.25, 0.5, 0.0]);
    // Outside: the weights are still reported (alpha = -1), the hit is not.
    let mut args = vec!["triangle", "--origin", "1,1,2", "--dir", "0,0,-1"];
    args.extend_from_slice(&tri);
    let j = intersect_json(&args);
    close(&j["barycentric"]["alpha"], -1.0);
    close(&j["barycentric"]["beta"], 1.0);
    assert_eq!(j["candidates"][0]["on_shape"], false);
    assert!(j["hit"].is_null());
    // Degenerate (corners on a line): the determinant is 0, no weights, no candidate.
    let j = intersect_json(&[
        "triangle", "--origin", "0.5,0,2", "--dir", "0,0,-1", "--a", "0,0,0", "--b", "1,0,0",
        "--c", "2,0,0",
    ]);
    assert_eq!(f(&j["barycentric"]["determinant"]), 0.0);
    assert!(j["barycentric"]["beta"].is_null());
    assert_eq!(j["candidates"].as_array().unwrap().len(), 0);
    assert!(j["hit"].is_null());
}

#[test]
fn intersect_rejects_bad_arguments() {
    for args in [
        vec!["intersect", "torus", "--origin", "0,0,0", "--dir", "1,0,0"],
        vec![
            "intersect",
            "sphere",
            "--origin",
            "0,0,0",
            "--dir",
            "1,0,0",
            "--slope",
            "2",
        ],
        vec!["intersect", "sphere", "--origin", "0,0,0", "--dir", "0,0,0"],
        vec!["intersect", "circle", "--origin", "0,0,0", "--dir", "1,0"],
        vec![
            "intersect",
            "cylinder",
            "--origin",
            "0,0,0",
            "--dir",
            "1,0,0",
            "--y-min",
            "2",
        ],
        vec![
            "intersect",
            "triangle",
            "--origin",
            "0,0,0",
            "--dir",
            "1,0,0",
        ],
    ] {
        let o = rtlab(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(!stderr(&o).contains("panicked"), "{args:?}");
    }
}

fn figure(args: &[&str]) -> rtlab::viz::Canvas {
    use clap::Parser;
    let mut argv = vec!["rtlab", "intersect"];
    argv.extend_from_slice(args);
    let cli = rtlab::cli::Cli::try_parse_from(&argv).unwrap();
    let rtlab::cli::Command::Intersect(a) = cli.command else {
        unreachable!()
    };
    let (name, shape, ray) = rtlab::cli::intersect::shape_and_ray(&a).unwrap();
    rtlab::viz::intersect::figure(&rtlab::cli::intersect::report(name, shape, ray))
}

#[test]
fn intersect_figures_are_snapshotted() {
    let cases: [(&str, &[&str], &str); 4] = [
        (
            "circle_tangent",
            &["circle", "--origin", "-3,1", "--dir", "0.8,-0.6"],
            "the lecture's tangent: one root, t = 3, D printed as 0",
        ),
        (
            "cylinder_side",
            &["cylinder", "--origin", "-3,1.5,0.3", "--dir", "1,-0.4,0"],
            "t1..t4: caps tossed outside their discs, the nearer body root kept",
        ),
        (
            "triangle_weights",
            &[
                "triangle",
                "--origin",
                "0.25,0.5,2",
                "--dir",
                "0,0,-1",
                "--a",
                "0,0,0",
                "--b",
                "1,0,0",
                "--c",
                "0,1,0",
            ],
            "sub-triangle areas shaded: alpha 0.25, beta 0.25, gamma 0.5",
        ),
        (
            "box_slabs",
            &["box", "--origin", "-3,1.5,0.3", "--dir", "1,-0.4,0.1"],
            "six face roots, kept where the slabs overlap",
        ),
    ];
    for (name, args, what) in cases {
        let c = figure(args);
        insta::with_settings!({
            description => what,
            info => &args.join(" "),
            snapshot_path => "snapshots/intersect",
        }, {
            insta::assert_yaml_snapshot!(name, c.display);
        });
    }
}

#[test]
fn circle_figure_png_is_stable_and_marks_the_hit() {
    let out = tmp("circle.png");
    let run = || {
        let o = rtlab(&[
            "intersect",
            "circle",
            "--origin",
            "-3,1",
            "--dir",
            "0.8,-0.6",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        std::fs::read(&out).unwrap()
    };
    let (a, b) = (run(), run());
    assert_eq!(a, b, "same command, same bytes");
    let img = image::load_from_memory(&a).unwrap().to_rgb8();
    assert_eq!(img.width(), 720);
    // The kept hit is a red dot: find its centre in the display list and check the pixel.
    let c = figure(&["circle", "--origin", "-3,1", "--dir", "0.8,-0.6"]);
    assert_eq!(img.height() as f32, c.height());
    let red = c
        .display
        .iter()
        .find_map(|p| match p {
            Prim::Circle {
                center,
                fill: Some(f),
                ..
            } if f == "#d62728" => Some(*center),
            _ => None,
        })
        .expect("a red hit dot");
    let px = img.get_pixel(red[0] as u32, red[1] as u32);
    assert!(px[0] > 180 && px[1] < 90 && px[2] < 90, "{px:?}");
    // The hit sits where the tangent point (-0.6, -0.8) is, relative to the centre C at
    // radius 1: the dot is on the circle's outline, below-left of C.
    let circle = c
        .display
        .iter()
        .find_map(|p| match p {
            Prim::Circle { center, radius, .. } if *radius > 20.0 => Some((*center, *radius)),
            _ => None,
        })
        .expect("the unit circle");
    let (cc, r) = circle;
    let (dx, dy) = ((red[0] - cc[0]) / r, (red[1] - cc[1]) / r);
    assert!(
        (dx + 0.6).abs() < 0.02 && (dy - 0.8).abs() < 0.02,
        "{dx} {dy}"
    );
}
