//! `rtlab intersect box --bundle-to`: the interval test's figure and working, for bundles
//! the book's examples do not cover (rays along y, a ray of almost no length across the
//! book's view, bundles that change sign along some axes only).

use crate::common::{rtlab, stderr, tmp};
use rtlab::viz::{Anchor, Canvas, Prim};

/// The figure for `intersect box ARGS`, built in-process so that its display list can be read.
fn figure(args: &[&str]) -> Canvas {
    use clap::Parser;
    let mut argv = vec!["rtlab", "intersect", "box"];
    argv.extend_from_slice(args);
    let cli = rtlab::cli::Cli::try_parse_from(&argv).unwrap();
    let rtlab::cli::Command::Intersect(a) = cli.command else {
        unreachable!()
    };
    let to = a.bundle_to.clone().expect("--bundle-to");
    let (rays, bounds) = rtlab::cli::intersect_bundle::bundle_and_box(&a, &to).unwrap();
    rtlab::viz::interval::figure(&rays, &rtlab::accel::bundle_working(&rays, &bounds))
}

/// `rtlab intersect box ARGS`, its output (text, or JSON with `--format json`).
fn run(args: &[&str]) -> String {
    let mut all = vec!["intersect", "box"];
    all.extend_from_slice(args);
    let o = rtlab(&all);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    String::from_utf8(o.stdout).unwrap()
}

fn has_text(c: &Canvas, part: &str) -> bool {
    c.texts().iter().any(|t| t.contains(part))
}

/// Where the figure draws P (the one dot of radius 3).
fn p_at(c: &Canvas) -> [f32; 2] {
    c.display
        .iter()
        .find_map(|p| match p {
            Prim::Circle { center, radius, .. } if *radius == 3.0 => Some(*center),
            _ => None,
        })
        .expect("P")
}

/// The left panel, in pixels (x0, y0, x1, y1): everything drawn left of the right panel.
const LEFT: (f32, f32, f32, f32) = (24.0, 96.0, 460.0, 460.0);

/// Every line and circle of the left panel lies inside it: none is NaN, none runs into
/// the title or the other panel.
fn assert_in_left_panel(c: &Canvas, what: &str) {
    let inside = |p: [f32; 2]| {
        p.iter().all(|v| v.is_finite())
            && (LEFT.0 - 0.5..=LEFT.2 + 0.5).contains(&p[0])
            && (LEFT.1 - 0.5..=LEFT.3 + 0.5).contains(&p[1])
    };
    for p in &c.display {
        let points = match p {
            Prim::Line { from, to, .. } => vec![*from, *to],
            Prim::Circle { center, .. } => vec![*center],
            _ => continue,
        };
        // The right panel's primitives start at x = 500.
        if points.iter().all(|q| q[0] >= 480.0) {
            continue;
        }
        assert!(points.iter().all(|&q| inside(q)), "{what}: {p:?}");
    }
}

const ALONG_Y: &[&str] = &[
    "--origin",
    "0,-5,0",
    "--dir",
    "0,1,0",
    "--bundle-to",
    "0.1,1,0.1",
    "--rays",
    "4",
];

/// A ray along y has no length seen along y: it used to be drawn from P to NaN (the
/// point at t = ∞), which tiny-skia drew as a line towards the canvas corner, through
/// the title. The view is now chosen so that every ray is a line, and named.
#[test]
fn a_bundle_along_y_is_seen_along_another_axis_and_stays_in_its_panel() {
    let c = figure(ALONG_Y);
    assert_in_left_panel(&c, "along y");
    assert!(
        has_text(&c, "Seen along x (y to the right, z up)"),
        "{:?}",
        c.texts()
    );
    // The rays are lines from P to the right edge, in the direction they have.
    let p = p_at(&c);
    let rays: Vec<([f32; 2], [f32; 2])> = c
        .display
        .iter()
        .filter_map(|q| match q {
            Prim::Line {
                from, to, dashed, ..
            } if !dashed && *from == p => Some((*from, *to)),
            _ => None,
        })
        .collect();
    assert_eq!(rays.len(), 4, "{rays:?}");
    assert!(rays.iter().all(|(a, b)| b[0] > a[0] + 300.0), "{rays:?}");
    // The text names the axes that bound nothing: x and z (some direction is 0 there).
    let text = run(ALONG_Y);
    assert!(text.contains("x: no bound"), "{text}");
    assert!(text.contains("z: no bound"), "{text}");
    assert!(text.contains("y: entry ≥"), "{text}");
}

/// The middle ray of this bundle is (0, 5·10⁻⁷, 0): seen along y, a point.
#[test]
fn a_ray_that_is_a_point_seen_along_y_is_drawn_as_the_line_it_is() {
    let args = [
        "--origin",
        "-5,0,0",
        "--dir",
        "1,0,0",
        "--bundle-to",
        "-1,1e-6,0",
        "--rays",
        "3",
    ];
    let c = figure(&args);
    assert_in_left_panel(&c, "tiny");
    assert!(has_text(&c, "Seen along z (x to the right, y up)"));
    // Up from P, the middle ray; right and left, the other two.
    let ends: Vec<[f32; 2]> = c
        .display
        .iter()
        .filter_map(|p| match p {
            Prim::Line { to, dashed, .. } if !dashed && to[0] < 480.0 => Some(*to),
            _ => None,
        })
        .collect();
    assert!(ends.iter().any(|e| (e[1] - LEFT.1).abs() < 1.0), "{ends:?}");
    assert!(ends.iter().any(|e| (e[0] - LEFT.0).abs() < 1.0), "{ends:?}");
    assert!(ends.iter().any(|e| (e[0] - LEFT.2).abs() < 1.0), "{ends:?}");
}

/// The labels of the two bounds keep off P and its label, and off each other.
#[test]
fn the_bounds_labels_keep_off_p() {
    for args in [
        ALONG_Y,
        &[
            "--origin",
            "0,5,0",
            "--dir",
            "0,-1,0",
            "--bundle-to",
            "0.2,-1,0",
        ],
        &[
            "--origin",
            "0,0,0",
            "--dir",
            "0.1,0.05,1",
            "--bundle-to",
            "0.4,0.05,1",
        ],
    ] {
        let c = figure(args);
        assert_in_left_panel(&c, &format!("{args:?}"));
        let area = |p: &Prim| match p {
            Prim::Text {
                at,
                text,
                size,
                anchor,
                ..
            } => {
                let w = Canvas::text_width(text, *size);
                let x = match anchor {
                    Anchor::Left => at[0],
                    Anchor::Center => at[0] - w / 2.0,
                    Anchor::Right => at[0] - w,
                };
                (x, at[1] - size / 2.0, x + w, at[1] + size / 2.0)
            }
            _ => unreachable!(),
        };
        let labels: Vec<(f32, f32, f32, f32)> = c
            .display
            .iter()
            .filter(
                |p| matches!(p, Prim::Text { text, .. } if text == "P" || text.starts_with("t = ")),
            )
            .map(area)
            .collect();
        let p = p_at(&c);
        for (i, a) in labels.iter().enumerate() {
            let clear =
                |b: &(f32, f32, f32, f32)| a.2 <= b.0 || b.2 <= a.0 || a.3 <= b.1 || b.3 <= a.1;
            assert!(
                labels[i + 1..].iter().all(clear),
                "{args:?}: {labels:?} overlap"
            );
            assert!(
                clear(&(p[0] - 3.0, p[1] - 3.0, p[0] + 3.0, p[1] + 3.0)),
                "{args:?}: {a:?} covers P at {p:?}"
            );
        }
    }
}

const MIXED: &[&str] = &[
    "--origin",
    "0,0,-5",
    "--dir",
    "-0.3,-0.2,1",
    "--bundle-to",
    "0.3,0.25,1",
];

/// Not sign-coherent along x and y, coherent along z: the figure, the text and the JSON
/// all say which axes change sign, and that the box gets no interval test at all.
#[test]
fn a_mixed_bundle_names_the_axes_that_change_sign() {
    let c = figure(MIXED);
    assert!(has_text(&c, "change sign along x and y"), "{:?}", c.texts());
    assert!(has_text(&c, "dx changes sign"));
    assert!(has_text(&c, "dy changes sign"));
    assert!(has_text(&c, "dz = 1 for every ray: one sign"));
    assert!(!has_text(&c, "dz changes sign"));
    assert!(!has_text(&c, "(not sign-coherent)"));
    // No bounds, so no sentence about them.
    assert!(!has_text(&c, "The bounds hold"), "{:?}", c.texts());
    assert!(has_text(&c, "no interval test: mixed along x and y"));

    let text = run(MIXED);
    assert!(text.contains("change sign along x and y"), "{text}");
    assert!(
        text.contains("x: dx from -0.3 to 0.3, changes sign"),
        "{text}"
    );
    assert!(
        text.contains("y: dy from -0.2 to 0.25, changes sign"),
        "{text}"
    );
    assert!(
        text.contains("z: dz = 1 for every ray, one sign (positive)"),
        "{text}"
    );

    let mut args = MIXED.to_vec();
    args.extend(["--format", "json"]);
    let j: serde_json::Value = serde_json::from_str(&run(&args)).unwrap();
    assert_eq!(j["sign_coherent"], false);
    assert_eq!(
        j["sign_coherent_axes"],
        serde_json::json!([false, false, true])
    );
    // Only ever added to: every field the JSON had stays.
    for key in [
        "shape",
        "box",
        "rays",
        "sign_coherent",
        "shared_origin",
        "interval_test",
    ] {
        assert!(j.get(key).is_some(), "{key}");
    }
    for key in ["axes", "together", "kept"] {
        assert!(j["interval_test"].get(key).is_some(), "{key}");
    }
    assert!(j["interval_test"]["kept"].is_null());

    // A coherent bundle: every axis coherent, and the bounds' sentence is back.
    let mut args = ALONG_Y.to_vec();
    args.extend(["--format", "json"]);
    let j: serde_json::Value = serde_json::from_str(&run(&args)).unwrap();
    assert_eq!(
        j["sign_coherent_axes"],
        serde_json::json!([true, true, true])
    );
    assert!(has_text(
        &figure(ALONG_Y),
        "The bounds hold for every ray at once"
    ));
}

/// A direction of −0 along an axis is negative to the walk (1/−0 = −∞): beside +0 the
/// bundle is mixed along that axis, and the working's per-axis signs say so, as the walk's
/// own verdict does. (The command's lerp turns −0 into +0, so only the library sees this.)
#[test]
fn signed_zeros_split_the_bundle_as_the_walk_does() {
    use glam::DVec3;
    use rtlab::math::Ray;
    let o = DVec3::new(0.0, 0.0, -5.0);
    let rays = [
        Ray::new(o, DVec3::new(-0.0, 0.1, 1.0)),
        Ray::new(o, DVec3::new(0.0, 0.2, 1.0)),
    ];
    let b = rtlab::shapes::Aabb::new(DVec3::splat(-1.0), DVec3::splat(1.0));
    let w = rtlab::accel::bundle_working(&rays, &b);
    assert!(!w.coherent);
    assert_eq!(w.coherent_axes, [false, true, true]);
    assert!(w.kept.is_none());
    let text = rtlab::cli::intersect_bundle::text(&rays, &w);
    assert!(text.contains("change sign along x:"), "{text}");
}

/// The figures the book uses are still seen along y, z to the right; every figure is the
/// same twice, and `-o` writes it.
#[test]
fn the_books_views_stay_and_figures_are_deterministic() {
    let culled: &[&str] = &[
        "--origin",
        "0,0,-5",
        "--dir",
        "0.3,0.05,1",
        "--bundle-to",
        "0.6,0.05,1",
        "--rays",
        "6",
    ];
    let spread: &[&str] = &[
        "--origin",
        "0,0,0",
        "--min",
        "1.6,-1,1.0",
        "--max",
        "1.9,1,1.3",
        "--dir",
        "0.1,0.05,1",
        "--bundle-to",
        "1,0.05,0.1",
    ];
    for args in [culled, spread] {
        let c = figure(args);
        assert!(
            has_text(&c, "Seen along y (z to the right, x up)"),
            "{args:?}"
        );
        assert_in_left_panel(&c, &format!("{args:?}"));
    }
    for args in [ALONG_Y, MIXED, culled] {
        assert_eq!(
            figure(args).png_bytes().unwrap(),
            figure(args).png_bytes().unwrap(),
            "{args:?}"
        );
    }
    let out = tmp("interval-along-y.png");
    let mut args = ALONG_Y.to_vec();
    let o = out.to_str().unwrap();
    args.extend(["-o", o]);
    run(&args);
    let png = image::open(&out).expect("a PNG").to_rgb8();
    assert_eq!(png.dimensions(), (960, 500));
}
