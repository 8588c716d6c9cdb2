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
    let ray_colors = |c: &rtlab::viz::Canvas| {
        c.display
            .iter()
            .filter_map(|p| match p {
                Prim::Arrow { color, width, .. } if *width >= 2.0 => Some(color.clone()),
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
