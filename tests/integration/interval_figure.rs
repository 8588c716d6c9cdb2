//! `rtlab intersect box --bundle-to`: the interval test's figure and working, for bundles
//! the book's examples do not cover (rays along y, a ray of almost no length across the
//! book's view, bundles that change sign along some axes only).

use crate::common::{drawn_texts, rtlab, stderr, tmp, BOOK_CULLED, BOOK_KEPT};
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

/// The rays the left panel draws from P: its solid lines that start there (from, to).
fn rays_from(c: &Canvas, p: [f32; 2]) -> Vec<([f32; 2], [f32; 2])> {
    c.display
        .iter()
        .filter_map(|q| match q {
            Prim::Line {
                from, to, dashed, ..
            } if !dashed && *from == p => Some((*from, *to)),
            _ => None,
        })
        .collect()
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
    let rays = rays_from(&c, p);
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
    let culled = BOOK_CULLED;
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

/// The t axis's tick labels (size 10, centred under the axis), left to right, with their
/// boxes (x0, x1) in pixels.
fn tick_labels(c: &Canvas) -> Vec<(String, f32, f32)> {
    let mut ticks: Vec<(String, f32, f32)> = drawn_texts(c)
        .into_iter()
        .filter(|&(_, at, size, anchor)| anchor == Anchor::Center && size == 10.0 && at[0] > 480.0)
        .map(|(text, at, size, _)| {
            let w = Canvas::text_width(&text, size);
            (text, at[0] - w / 2.0, at[0] + w / 2.0)
        })
        .collect();
    ticks.sort_by(|a, b| a.1.total_cmp(&b.1));
    ticks
}

/// The bundle's exit bound is ∞ (no axis bounds it: every direction is 0 along z, and
/// along x or y at one end): the axis used to span 0 to 1.6·10⁻⁶ and read "0 0 0 0 0".
/// It now reaches the box's far side (t = 1 for every ray here), its labels distinct.
#[test]
fn the_t_axis_spans_the_box_when_the_exit_bound_is_infinite() {
    let c = figure(&[
        "--origin",
        "0,0,0",
        "--dir",
        "1,0,0",
        "--bundle-to",
        "0,1,0",
    ]);
    assert!(has_text(&c, "∞ (cut)"), "{:?}", c.texts());
    let ticks = tick_labels(&c);
    let names: Vec<&str> = ticks.iter().map(|t| t.0.as_str()).collect();
    assert!(ticks.len() >= 3, "{names:?}");
    let mut distinct = names.clone();
    distinct.dedup();
    assert_eq!(distinct, names, "tick labels repeat");
    assert_eq!(names[0], "0");
    // Past the far side, t = 1, which is a tick.
    assert!(names.contains(&"1"), "{names:?}");
    let last: f64 = names.last().unwrap().parse().unwrap();
    assert!((1.0..=4.0).contains(&last), "{names:?}");
}

/// At t ≈ 10¹², the ticks used to be 0, 4·10¹¹, ... written in full and run into one
/// another ("0 40000018840037001200509001800753664"): now a nice step, written compactly,
/// and no two labels overlap.
#[test]
fn tick_labels_at_a_large_scale_are_short_and_do_not_overlap() {
    let c = figure(&[
        "--origin",
        "0,0,-1e12",
        "--dir",
        "0,0,1",
        "--bundle-to",
        "1e-12,0,1",
    ]);
    let ticks = tick_labels(&c);
    let names: Vec<&str> = ticks.iter().map(|t| t.0.as_str()).collect();
    assert!(ticks.len() >= 2, "{names:?}");
    assert!(names.contains(&"1e12"), "{names:?}");
    for t in &names {
        assert!(t.len() <= 6, "{names:?}");
        // Each a nice number: 1, 2 or 5 (or 1.5, ...) times a power of ten, or 0.
        let v: f64 = t.parse().unwrap();
        assert!(v == 0.0 || v >= 1e11, "{names:?}");
    }
    for p in ticks.windows(2) {
        assert!(p[0].2 + 2.0 <= p[1].1, "{ticks:?} overlap");
    }
    // And at small and middling scales, for boxes from 10⁻⁶ to 10⁵ away.
    for z in ["-1e-6", "-0.003", "-5", "-77", "-1e5"] {
        let o = format!("0,0,{z}");
        let c = figure(&[
            "--origin",
            &o,
            "--dir",
            "0,0,1",
            "--bundle-to",
            "1e-12,0,1",
            "--min",
            "-1e-7,-1e-7,-1e-7",
            "--max",
            "1e-7,1e-7,1e-7",
        ]);
        let ticks = tick_labels(&c);
        let names: Vec<&str> = ticks.iter().map(|t| t.0.as_str()).collect();
        let mut distinct = names.clone();
        distinct.dedup();
        assert_eq!(distinct, names, "{z}: tick labels repeat");
        assert!(names.len() >= 2, "{z}: {names:?}");
        for p in ticks.windows(2) {
            assert!(p[0].2 + 2.0 <= p[1].1, "{z}: {ticks:?} overlap");
        }
    }
}

/// The exit bound's label sat on the rays just past P, on a plate of the background: the
/// rays seemed to start away from P. Every label of the left panel now keeps off P and
/// off the first 40 pixels of every ray.
#[test]
fn labels_keep_off_the_rays_near_p() {
    let cases: [&[&str]; 3] = [
        &[
            "--origin",
            "0,0,-5",
            "--dir",
            "0,2,1",
            "--bundle-to",
            "0,3,1",
        ],
        ALONG_Y,
        &[
            "--origin",
            "0,0,0",
            "--dir",
            "0.1,0.05,1",
            "--bundle-to",
            "0.4,0.05,1",
        ],
    ];
    for args in cases {
        let c = figure(args);
        let p = p_at(&c);
        // The label boxes of the left panel (as the labeller pads them), and the plates.
        let mut boxes: Vec<[f32; 4]> = c
            .display
            .iter()
            .filter_map(|q| match q {
                Prim::Text {
                    at,
                    text,
                    size,
                    anchor,
                    ..
                } if at[0] < 480.0 && at[1] > LEFT.1 && at[1] < LEFT.3 => {
                    let w = Canvas::text_width(text, *size);
                    let x = match anchor {
                        Anchor::Left => at[0],
                        Anchor::Center => at[0] - w / 2.0,
                        Anchor::Right => at[0] - w,
                    };
                    let h = size * 0.62;
                    Some([x, at[1] - h, x + w, at[1] + h])
                }
                _ => None,
            })
            .collect();
        boxes.extend(c.display.iter().filter_map(|q| match q {
            Prim::Rect {
                min,
                size,
                stroke: None,
                ..
            } if min[0] < 480.0 => Some([min[0], min[1], min[0] + size[0], min[1] + size[1]]),
            _ => None,
        }));
        assert!(boxes.len() >= 2, "{args:?}: {boxes:?}");
        let rays = rays_from(&c, p);
        assert!(!rays.is_empty(), "{args:?}");
        let covers =
            |b: &[f32; 4], q: [f32; 2]| b[0] < q[0] && q[0] < b[2] && b[1] < q[1] && q[1] < b[3];
        for b in &boxes {
            assert!(!covers(b, p), "{args:?}: {b:?} covers P at {p:?}");
            for (a, e) in &rays {
                let len = (e[0] - a[0]).hypot(e[1] - a[1]);
                for i in 1..=40 {
                    let f = (i as f32).min(len) / len;
                    let q = [a[0] + (e[0] - a[0]) * f, a[1] + (e[1] - a[1]) * f];
                    assert!(
                        !covers(b, q),
                        "{args:?}: label {b:?} covers the ray from P at {q:?}"
                    );
                }
            }
        }
        // The exit bound is still named, here near P.
        if args[3] == "0,2,1" {
            assert!(has_text(&c, "t = exit bound"), "{:?}", c.texts());
        }
    }
}

/// A direction that is 0 along an axis for every ray is +0 (the command's lerp makes −0
/// +0): the walk's 1/d counts it as positive, but a zero is not "positive".
#[test]
fn a_zero_direction_is_not_called_positive() {
    let text = run(&[
        "--origin",
        "0,0,-5",
        "--dir",
        "-1e-300,0,1",
        "--bundle-to",
        "1e-300,0,1",
    ]);
    assert!(
        text.contains(
            "y: dy = 0 for every ray (+0, which the walk's 1/d counts as positive); unused"
        ),
        "{text}"
    );
    assert!(
        !text.contains("dy = 0 for every ray, one sign (positive)"),
        "{text}"
    );
    assert!(
        text.contains("z: dz = 1 for every ray, one sign (positive); unused"),
        "{text}"
    );
    // −0, through the library: counted negative, and said so.
    use glam::DVec3;
    use rtlab::math::Ray;
    let o = DVec3::new(0.0, 0.0, -5.0);
    let rays = [
        Ray::new(o, DVec3::new(-0.1, -0.0, 1.0)),
        Ray::new(o, DVec3::new(0.2, -0.0, 1.0)),
    ];
    let b = rtlab::shapes::Aabb::new(DVec3::splat(-1.0), DVec3::splat(1.0));
    let w = rtlab::accel::bundle_working(&rays, &b);
    let text = rtlab::cli::intersect_bundle::text(&rays, &w);
    assert!(
        text.contains("dy = 0 for every ray (−0, which the walk's 1/d counts as negative)"),
        "{text}"
    );
}

#[test]
fn the_key_explains_red_dots_only_when_some_ray_enters() {
    let culled = figure(BOOK_CULLED);
    assert!(!has_text(&culled, "Red dots"), "{:?}", culled.texts());
    assert!(
        has_text(&culled, "no ray's own slab test enters it"),
        "{:?}",
        culled.texts()
    );
    let kept = figure(BOOK_KEPT);
    assert!(has_text(
        &kept,
        "Red dots: where each ray's own slab test says it enters"
    ));
}
