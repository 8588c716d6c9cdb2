//! `rtlab beam`'s output after a QA pass: the text prints no rounding noise and tells apart
//! what differs; its messages name the limits; the figure frames what the beam reaches,
//! shows the mirrored eye its subtitle names, and keeps its labels clear and in the frame.

use crate::common::{drawn_texts, rtlab, stderr};
use rtlab::cli::beam::{parse, Args};
use rtlab::viz::canvas::{Canvas, Prim};
use rtlab::viz::labels::{text_box, Box2};

fn run(args: &[&str]) -> String {
    let mut all = vec!["beam"];
    all.extend(args);
    let o = rtlab(&all);
    assert!(o.status.success(), "{}", stderr(&o));
    String::from_utf8(o.stdout).unwrap()
}

fn fails(args: &[&str]) -> String {
    let mut all = vec!["beam"];
    all.extend(args);
    let o = rtlab(&all);
    assert!(!o.status.success(), "{args:?} should fail");
    stderr(&o)
}

#[test]
fn the_text_prints_no_rounding_noise_and_json_agrees() {
    // The wall's end lies exactly at x = 0, which the beam's edge computes as -2.2e-16.
    let args = [
        "--eye", "1,0", "--from", "1,3", "--to", "-1,3", "--wall", "0,3,2,3",
    ];
    let text = run(&args);
    assert!(
        text.contains("wall 1 sees it, from (2, 3) to (0, 3)"),
        "{text}"
    );
    assert!(!text.contains("e-16"), "{text}");
    let mut json = args.to_vec();
    json.extend(["--format", "json"]);
    let out = run(&json);
    assert!(!out.contains("e-16") && !out.contains("e-17"), "{out}");
    let doc: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(
        doc["pieces"][0]["seen_by"]["points"][1],
        serde_json::json!([0.0, 3.0])
    );
    // A piece's edge pointing straight up is (0, 1), not (1.1e-16, 1).
    let out = run(&[
        "--from", "1,1", "--to", "-1,1", "--wall", "0,2,1,2", "--format", "json",
    ]);
    let doc: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(doc["pieces"][1]["to"], serde_json::json!([0.0, 1.0]));
}

#[test]
fn a_piece_that_meets_nothing_says_so() {
    let text = run(&["--from", "1,1", "--to", "-1,1", "--wall", "0,2,1,2"]);
    assert!(
        text.contains("piece 3: 45° wide, meets no segment"),
        "{text}"
    );
    assert!(!text.contains("passes every segment"), "{text}");
}

#[test]
fn widths_and_directions_print_enough_digits_to_be_told_apart() {
    // 179.99999989° is less than the widest a beam may be, 179.9999999°, and must read so.
    let text = run(&["--from", "1,0", "--to", "-1,1.9e-9", "--wall", "-3,1,3,1"]);
    assert!(text.contains("(179.99999989° wide)"), "{text}");
    assert!(!text.contains("180°"), "{text}");
    let text = run(&["--from", "1,1", "--to", "1,1.000001", "--wall", "0,3,3,0"]);
    assert!(
        text.contains("from direction (1, 1) to (1, 1.000001)"),
        "{text}"
    );
    assert!(
        text.contains("from (1.5, 1.5) to (1.499999, 1.500001)"),
        "{text}"
    );
}

#[test]
fn messages_name_the_limits() {
    for depth in ["-1", "4"] {
        let e = fails(&[
            "--from", "1,0", "--to", "0,1", "--wall", "0,1,1,0", "--depth", depth,
        ]);
        assert!(e.contains(&format!("{depth} is not in 0..=3")), "{e}");
    }
    let e = fails(&[
        "--from",
        "-1,1",
        "--to",
        "1,1",
        "--mirror",
        "-1e-13,2,1e-13,2",
    ]);
    assert!(
        e.contains("mirror 1 is 2.0e-13 long: a segment must be longer than 2.0e-12"),
        "{e}"
    );
}

#[test]
fn a_width_refused_reads_as_breaking_the_rule_it_states() {
    // 179.99999994° is under 180°: the rule it breaks is the one stated, to the digits shown.
    let e = fails(&["--from", "1,0", "--to", "-1,1e-9", "--wall", "-5,1,5,1"]);
    assert!(
        e.contains("the two directions are 179.99999994° apart: a beam must be less than 179.9999999° wide"),
        "{e}"
    );
    let e = fails(&[
        "--from",
        "1,1",
        "--to",
        "1,1.0000000001",
        "--wall",
        "-5,3,5,3",
    ]);
    assert!(
        e.contains("the two directions are 2.9e-9° apart: a beam must be more than 1.0e-7° wide"),
        "{e}"
    );
    assert!(!e.contains(" 0°"), "{e}");
}

fn beam_args(
    eye: &str,
    from: &str,
    to: &str,
    walls: &[&str],
    mirrors: &[&str],
    depth: u32,
) -> Args {
    Args {
        eye: eye.into(),
        from: from.into(),
        to: to.into(),
        wall: walls.iter().map(|s| s.to_string()).collect(),
        mirror: mirrors.iter().map(|s| s.to_string()).collect(),
        depth,
        format: "text".into(),
        output: None,
    }
}

fn draw(a: &Args) -> Canvas {
    let (beam, segments) = parse(a).unwrap();
    let pieces = rtlab::accel::beam::trace(&beam, &segments, a.depth);
    rtlab::viz::beam::figure(&beam, &segments, &pieces)
}

/// The frame: the one rectangle stroked in the grid colour.
fn frame(c: &Canvas) -> Box2 {
    c.display
        .iter()
        .find_map(|p| match p {
            Prim::Rect {
                min,
                size,
                stroke: Some(_),
                ..
            } => Some([min[0], min[1], min[0] + size[0], min[1] + size[1]]),
            _ => None,
        })
        .expect("a frame")
}

/// The eye: the one filled dot with no outline.
fn eye(c: &Canvas) -> [f32; 2] {
    c.display
        .iter()
        .find_map(|p| match p {
            Prim::Circle {
                center,
                stroke: None,
                fill: Some(_),
                ..
            } => Some(*center),
            _ => None,
        })
        .expect("the eye")
}

/// The mirrored eyes: hollow dots.
fn apexes(c: &Canvas) -> Vec<[f32; 2]> {
    c.display
        .iter()
        .filter_map(|p| match p {
            Prim::Circle {
                center,
                stroke: Some(_),
                ..
            } => Some(*center),
            _ => None,
        })
        .collect()
}

/// The walls and mirrors, as drawn (the thick lines).
fn segments(c: &Canvas) -> Vec<([f32; 2], [f32; 2])> {
    c.display
        .iter()
        .filter_map(|p| match p {
            Prim::Line {
                from, to, width, ..
            } if *width > 3.0 => Some((*from, *to)),
            _ => None,
        })
        .collect()
}

/// The labels in the drawing (between the title and the legend) and their boxes.
fn labels(c: &Canvas) -> Vec<(String, Box2)> {
    drawn_texts(c)
        .into_iter()
        .filter(|t| t.1[1] > 80.0 && t.1[1] < 560.0)
        .map(|(text, at, size, anchor)| {
            let b = text_box((at[0], at[1]), &text, size, anchor);
            (text, b)
        })
        .collect()
}

fn inside(b: &Box2, p: [f32; 2]) -> bool {
    p[0] >= b[0] && p[0] <= b[2] && p[1] >= b[1] && p[1] <= b[3]
}

fn overlaps(a: &Box2, b: &Box2) -> bool {
    a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3]
}

#[test]
fn a_mirror_a_trillion_long_does_not_shrink_the_beam() {
    let c = draw(&beam_args(
        "0,0",
        "-1,1",
        "1,1",
        &[],
        &["-1e12,2,1e12,2"],
        1,
    ));
    let f = frame(&c);
    let e = eye(&c);
    let mirror = segments(&c)[0];
    // The mirror is cut at the frame, and the eye is well away from it.
    assert!((mirror.0[0] - f[0]).abs() < 1.0 && (mirror.1[0] - f[2]).abs() < 1.0);
    assert!(e[1] - mirror.0[1] > 150.0, "eye {e:?}, mirror {mirror:?}");
    // The mirrored eye the subtitle names is drawn, in the frame, and named.
    let apex = apexes(&c);
    assert_eq!(apex.len(), 1);
    assert!(inside(&f, apex[0]), "{apex:?} outside {f:?}");
    assert!(c.texts().join("\n").contains("eye mirrored in mirror 1"));
}

#[test]
fn the_mirrored_eye_behind_a_mirror_is_framed_and_named() {
    let c = draw(&beam_args(
        "1,1",
        "1,0.2",
        "1,2",
        &["2,2.5,2.5,2.8", "0,-2,0,5"],
        &["3,0,3,4"],
        1,
    ));
    let f = frame(&c);
    let apex = apexes(&c);
    assert_eq!(apex.len(), 1);
    assert!(inside(&f, apex[0]), "{apex:?} outside {f:?}");
    let all = c.texts().join("\n");
    assert!(all.contains("eye mirrored in mirror 1"), "{all}");
    assert!(all.contains("where the dashed lines meet"), "{all}");
}

#[test]
fn a_room_without_reflections_does_not_mention_them() {
    let c = draw(&beam_args("0,0", "-1,1", "1,1", &["-1,2,1,2"], &[], 1));
    let all = c.texts().join("\n");
    assert!(!all.contains("dashed") && !all.contains("Green"), "{all}");
    assert!(apexes(&c).is_empty());
    let c = draw(&beam_args("0,0", "-1,1", "1,1", &[], &["-1,2,1,2"], 0));
    let all = c.texts().join("\n");
    assert!(all.contains("--depth 0 follows no reflection"), "{all}");
    assert!(!all.contains("dashed"), "{all}");
}

#[test]
fn three_reflections_in_a_box_of_mirrors_stay_readable() {
    let c = draw(&beam_args(
        "0.1,0.2",
        "1,0.3",
        "-0.2,1",
        &[],
        &["-2,-2,2,-2", "2,-2,2,2", "2,2,-2,2", "-2,2,-2,-2"],
        3,
    ));
    let e = eye(&c);
    let segs = segments(&c);
    let labels = labels(&c);
    assert!(labels.len() > 8, "{labels:?}");
    for (i, (text, b)) in labels.iter().enumerate() {
        // Whole, inside the figure, off the eye, off the mirrors and off each other.
        assert!(b[0] >= 0.0 && b[2] <= 960.0, "{text} cut off: {b:?}");
        assert!(
            !overlaps(b, &[e[0] - 4.5, e[1] - 4.5, e[0] + 4.5, e[1] + 4.5]),
            "{text} on the eye"
        );
        for (p, q) in &segs {
            for k in 0..=100 {
                let t = k as f32 / 100.0;
                let x = [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])];
                assert!(!inside(b, x), "{text} on a mirror");
            }
        }
        for (other, d) in &labels[i + 1..] {
            assert!(!overlaps(b, d), "{text} and {other} overlap");
        }
        // The third reflection's pieces are left to the printed list.
        assert!(text.matches('.').count() < 3, "{text}");
    }
    assert!(c
        .texts()
        .join("\n")
        .contains("Pieces without a number are in the printed list."));
    // The first beam is drawn over its reflections: every blue fill after every green one.
    let fills: Vec<&str> = c
        .display
        .iter()
        .filter_map(|p| match p {
            Prim::Polygon { fill: Some(f), .. } => Some(f.as_str()),
            _ => None,
        })
        .collect();
    let last_green = fills
        .iter()
        .rposition(|f| f.starts_with("#2ca02c"))
        .unwrap();
    let first_blue = fills.iter().position(|f| f.starts_with("#1f77b4")).unwrap();
    assert!(first_blue > last_green, "{fills:?}");
}

/// Every segment a piece meets, at any depth, is drawn inside the frame, clear of its edge,
/// and named, though the first beam reaches only a short way.
#[test]
fn a_wall_that_a_deep_reflection_meets_is_drawn_and_named() {
    let c = draw(&beam_args(
        "0,0",
        "0.5,1",
        "1,1",
        &["5,-1,5,1"],
        &["-5,1,5,1", "-5,-1,5,-1"],
        3,
    ));
    let f = frame(&c);
    // The wall is the one upright thick line.
    let wall = segments(&c)
        .into_iter()
        .find(|(a, b)| (a[0] - b[0]).abs() < 0.5 && (a[1] - b[1]).abs() > 10.0)
        .expect("the wall at x = 5 is drawn");
    for p in [wall.0, wall.1] {
        assert!(
            p[0] > f[0] + 10.0 && p[0] < f[2] - 10.0 && p[1] > f[1] && p[1] < f[3],
            "{wall:?} on the edge of {f:?}"
        );
    }
    let labels = labels(&c);
    let (_, b) = labels
        .iter()
        .find(|(t, _)| t == "wall 1")
        .expect("the wall is named");
    // Beside the wall, not somewhere else.
    assert!(
        (b[0] - wall.0[0]).abs() < 30.0 || (b[2] - wall.0[0]).abs() < 30.0,
        "{b:?}"
    );
}

/// The eye's label keeps off the beam's edges where they leave the eye, so the apex shows.
#[test]
fn the_eye_label_leaves_the_apex_of_the_beam_clear() {
    for (from, to) in [
        ("1,0.2", "1,-0.2"),
        ("-1,0.2", "-1,-0.2"),
        ("0.2,1", "-0.2,1"),
        ("1,1", "-1,1"),
    ] {
        let c = draw(&beam_args(
            "1,0",
            from,
            to,
            &["3,-1,3,1", "-1,-1,-1,1", "-1,2,3,2"],
            &[],
            1,
        ));
        let e = eye(&c);
        let (_, b) = labels(&c)
            .into_iter()
            .find(|(t, _)| t == "eye")
            .expect("the eye is named");
        // The beam's edges: the thin lines that start at the eye.
        let edges: Vec<_> = c
            .display
            .iter()
            .filter_map(|p| match p {
                Prim::Line {
                    from, to, width, ..
                } if *width < 2.0 && (from[0] - e[0]).hypot(from[1] - e[1]) < 0.5 => Some(*to),
                _ => None,
            })
            .collect();
        assert!(edges.len() >= 2, "{from} {to}: {edges:?}");
        for q in edges {
            let len = (q[0] - e[0]).hypot(q[1] - e[1]);
            for k in 0..=60 {
                let t = (k as f32).min(len) / len;
                let x = [e[0] + t * (q[0] - e[0]), e[1] + t * (q[1] - e[1])];
                assert!(
                    !inside(&b, x),
                    "{from} {to}: the eye's label {b:?} on the edge at {x:?}"
                );
            }
        }
    }
}

/// In the book's figure (chapter 13) the walls' and mirrors' names sit inside the frame or
/// wholly outside it, never across its edge ("wall 3", beside a wall near the frame's right
/// edge, once broke the frame's line).
#[test]
fn the_segments_names_do_not_cross_the_frame() {
    let c = draw(&beam_args(
        "0,0",
        "-0.6,1",
        "1.3,1",
        &["-0.7,1.4,-0.1,1.4", "-1,3.6,2,3.6", "3.2,1,3.2,3.4"],
        &["0.6,1.7,1.4,2.3"],
        1,
    ));
    let f = frame(&c);
    let names: Vec<_> = labels(&c)
        .into_iter()
        .filter(|(t, _)| t.starts_with("wall ") || t.starts_with("mirror "))
        .collect();
    assert_eq!(names.len(), 4, "{names:?}");
    for (t, b) in &names {
        let within = b[0] >= f[0] && b[1] >= f[1] && b[2] <= f[2] && b[3] <= f[3];
        assert!(
            within || !overlaps(b, &f),
            "{t:?} {b:?} crosses the frame {f:?}"
        );
    }
    // The mirrored eye's label stays by its dot (within the rings of places around it),
    // rather than wandering off into the frame.
    let [apex] = apexes(&c)[..] else {
        panic!("one mirrored eye")
    };
    let (_, b) = labels(&c)
        .into_iter()
        .find(|(t, _)| t == "eye mirrored in mirror 1")
        .expect("the mirrored eye's label");
    let dx = (b[0] - apex[0]).max(apex[0] - b[2]).max(0.0);
    let dy = (b[1] - apex[1]).max(apex[1] - b[3]).max(0.0);
    assert!(dx.hypot(dy) <= 16.0, "{b:?} is far from its dot {apex:?}");
}
