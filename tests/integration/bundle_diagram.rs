//! `explain --bundle-diagram`: the figure draws the bundle the render traces, with the render's
//! options (its sampler, `--sample`, `--subsample`, image size), the very rays
//! `trace_bundled` makes; it refuses, writing nothing, where the render traces no bundle;
//! and everything it draws stays inside its panels.

use super::common::*;
use rtlab::accel::Traversal;
use rtlab::sampling::bundles::{bundle_of, trace_bundled, BundleTally, NoBundle, TilePlan};
use rtlab::scene::SamplerKind;
use rtlab::viz::canvas::Prim;

/// `explain scenes/teapot.json` with `args`, the figure to `out`.
fn explain_bundle(out: &std::path::Path, args: &[&str]) -> std::process::Output {
    let mut all = vec!["explain", "scenes/teapot.json"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["--bundle-diagram", out.to_str().unwrap()]);
    rtlab(&all)
}

/// Where the render traces no bundle holding the pixel's sample, the figure is refused: exit
/// 2, one message naming --bundle-diagram and the reason, no file (nor --diagram's).
#[test]
fn refused_where_the_render_traces_no_bundle() {
    for (what, args, reason) in [
        (
            "single traversal",
            vec!["--pixel", "320,240", "--traversal", "single"],
            "with --traversal single every camera ray walks the BVHs alone",
        ),
        (
            "adaptive sampler",
            vec!["--pixel", "320,240", "--sampler", "adaptive", "--spp", "4"],
            "the adaptive sampler decides its samples while it traces, so the render's \
             camera rays go alone even with --traversal bundle",
        ),
        (
            "a mistake that changes hits",
            vec!["--pixel", "320,240", "--mistake", "cap-radius"],
            "a mistake that changes which object a ray hits is on",
        ),
        (
            "a pixel --subsample skips",
            vec!["--pixel", "321,241", "--subsample", "2"],
            "pixel (321, 241) traces no samples of its own (it is filled in by --subsample): \
             no bundle to draw; pick a traced pixel",
        ),
    ] {
        let out = tmp(&format!("refused-{}.png", what.replace(' ', "-")));
        let o = explain_bundle(&out, &args);
        assert_eq!(o.status.code(), Some(2), "{what}: {}", stderr(&o));
        let err = stderr(&o);
        assert!(
            err.contains("argument --bundle-diagram: ") && err.contains(reason),
            "{what}: {err}"
        );
        assert_eq!(err.trim().lines().count(), 1, "{what}: one message: {err}");
        assert!(!out.exists(), "{what}: a refused figure writes no file");
    }
    // Asked for both figures at an untraced pixel: neither is written.
    let (fig, slice) = (tmp("both-bundle.png"), tmp("both-slice.png"));
    let o = explain_bundle(
        &fig,
        &[
            "--pixel",
            "321,241",
            "--subsample",
            "2",
            "--diagram",
            slice.to_str().unwrap(),
        ],
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(!fig.exists() && !slice.exists());
    // A --sample the pixel does not have: refused before any figure is written.
    let bad = tmp("bad-sample.png");
    let o = explain_bundle(&bad, &["--pixel", "320,240", "--sample", "1"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("--sample") && !bad.exists());
}

/// The figure follows the render's options: another sample of a grid sampler, a subsampled
/// block, another image size each give another figure; the same options the same bytes.
#[test]
fn the_figure_follows_the_render_options() {
    let draw = |name: &str, args: &[&str]| {
        let out = tmp(name);
        let o = explain_bundle(&out, args);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        std::fs::read(&out).unwrap()
    };
    let small = ["--width", "64", "--height", "48", "--max-depth", "0"];
    let with = |more: &[&'static str]| [&small[..], &["--pixel", "33,24"], more].concat();
    let centre = draw("follow-centre.png", &with(&[]));
    assert_eq!(centre, draw("follow-centre-again.png", &with(&[])));
    let grid = |k: &'static str| {
        draw(
            &format!("follow-grid-{k}.png"),
            &with(&["--sampler", "grid", "--spp", "4", "--sample", k]),
        )
    };
    let (g0, g3) = (grid("0"), grid("3"));
    assert_ne!(g0, g3, "sample 3's rays are not sample 0's");
    assert_ne!(g0, centre, "a grid sample is not the pixel centre");
    let sub = draw("follow-sub.png", &with(&["--subsample", "3"]));
    assert_ne!(
        sub, centre,
        "a subsampled block holds only its traced pixels"
    );
}

/// A block cut by the image's edge: an 11×9 image's pixel (10, 7) is in the block of columns
/// 8–10 (there is no column 11) and rows 4–7, 12 rays; the title says so, and every ray,
/// box and dot lies inside its panel's frame.
#[test]
fn a_clipped_block_is_captioned_by_its_pixels_and_drawn_inside_its_panels() {
    let mut scene = scene("scenes/teapot.json");
    scene.camera.update_size(11, 9);
    let b = bundle_of(&scene, &scene.render, (10, 7), 0).unwrap();
    let want: Vec<(u32, u32)> = (4..8).flat_map(|y| (8..11).map(move |x| (x, y))).collect();
    assert_eq!(b.pixels, want);
    let c = rtlab::viz::bundle::draw(&scene, 10, 7, 0).unwrap();
    let all = c.texts().join("\n");
    assert!(
        all.contains("A bundle of 12 camera rays")
            && all.contains("sample 0 of pixels x 8–10, y 4–7"),
        "{all}"
    );
    assert!(!all.contains("8–11"), "{all}");
    in_frames(&c);
    // Subsampled by 2, the block holds four traced columns and rows, every other one: a
    // full bundle over 8×8 pixels.
    let mut sub = scene_teapot();
    sub.render.subsample = 2;
    let all = rtlab::viz::bundle::draw(&sub, 320, 240, 0)
        .unwrap()
        .texts()
        .join("\n");
    assert!(
        all.contains("A bundle of 16 camera rays")
            && all.contains("sample 0 of pixels x 320–326 and y 240–246, every 2nd"),
        "{all}"
    );
    // The teapot at its own size: the rays come from below the mesh, clipped to the frame.
    let scene = scene_teapot();
    in_frames(&rtlab::viz::bundle::draw(&scene, 320, 240, 0).unwrap());
}

/// The panels' headings say what the walk did at each level: the root's real number of
/// children, and, where the bundle opened no box one level down, why: the boxes entered were
/// leaves (the prism's root holds two leaves), or one ray entered them and went on
/// alone (a 1×1 image's single ray); "nothing to test" only where no ray entered a box.
#[test]
fn the_headings_say_what_the_walk_did() {
    let texts = |c: &rtlab::viz::canvas::Canvas| c.texts().join("\n");
    let root_children = |s: &rtlab::scene::Scene| {
        let root = &first_mesh(s).bvh.nodes[0];
        (0..rtlab::accel::WIDTH)
            .filter(|&l| root.planes[0][0][l] <= root.planes[1][0][l])
            .count()
    };

    // The prism: a root of two leaves, one entered.
    let prism = scene("scenes/prism.json");
    assert_eq!(root_children(&prism), 2);
    let all = texts(&rtlab::viz::bundle::draw(&prism, 100, 100, 3).unwrap());
    assert!(
        all.contains("1. The root's 2 children: 1 entered, 1 culled"),
        "{all}"
    );
    assert!(!all.contains("four children"), "{all}");
    assert!(
        all.contains("2. One level down: no box opened")
            && all.contains("The box entered is a leaf: its triangles are tested"),
        "{all}"
    );
    assert!(!all.contains("nothing to test"), "{all}");

    // A 1×1 image: one ray, which enters two of the root's four children and walks them
    // alone.
    let mut one = scene_teapot();
    one.camera.update_size(1, 1);
    assert_eq!(root_children(&one), 4);
    let all = texts(&rtlab::viz::bundle::draw(&one, 0, 0, 0).unwrap());
    assert!(
        all.contains("1. The root's 4 children: 2 entered, 2 culled"),
        "{all}"
    );
    assert!(
        all.contains("2. One level down: no box opened")
            && all.contains("Both boxes entered had one ray each: each went on alone"),
        "{all}"
    );
    assert!(!all.contains("nothing to test"), "{all}");

    // A bundle whose directions change sign (the prism's image 66 wide: its block of columns
    // 32–35 straddles the middle) never opens the root: each ray walks alone from it.
    let mut mixed = scene("scenes/prism.json");
    mixed.camera.update_size(66, 50);
    let all = texts(&rtlab::viz::bundle::draw(&mixed, 32, 24, 0).unwrap());
    assert!(
        all.contains("1. The root's 2 children: not tested by the bundle")
            && all.contains("The bundle never opened the root")
            && all.contains("2. One level down: the rays walked alone"),
        "{all}"
    );
    assert!(!all.contains("nothing to test"), "{all}");

    // The teapot's centre: the bundle opens one of the two children entered; the other it
    // never reaches (its rays hit nearer), and the heading says so.
    let all = texts(&rtlab::viz::bundle::draw(&scene_teapot(), 320, 240, 0).unwrap());
    assert!(
        all.contains("2. One level down, in the boxes opened: ")
            && !all.contains("nothing to test"),
        "{all}"
    );
}

/// Singular for one: a 1×1 image's bundle is "1 camera ray", and its hit "the ray hits";
/// a bundle of sixteen keeps its plurals.
#[test]
fn one_ray_is_singular() {
    let mut one = scene_teapot();
    one.camera.update_size(1, 1);
    let all = rtlab::viz::bundle::draw(&one, 0, 0, 0)
        .unwrap()
        .texts()
        .join("\n");
    assert!(
        all.contains("A bundle of 1 camera ray walking")
            && all.contains("the ray comes from the camera")
            && all.contains("the ray hits (red dot)")
            && all.contains("its ray made 4 slab tests"),
        "{all}"
    );
    assert!(
        !all.contains("1 camera rays") && !all.contains("of 1 rays"),
        "{all}"
    );
    let all = rtlab::viz::bundle::draw(&scene_teapot(), 320, 240, 0)
        .unwrap()
        .texts()
        .join("\n");
    assert!(
        all.contains("A bundle of 16 camera rays walking")
            && all.contains("16 of 16 rays hit (red dots)"),
        "{all}"
    );
}

/// Every text of the figure lies within the canvas (its width measured as drawn) and no two
/// overlap, for subsampled bundles whose pixels span a wide lattice: the title names the
/// lattice ("x 320–332 and y 240–252, every 4th"), and wraps where even that is too long.
#[test]
fn the_title_fits_the_canvas() {
    for (size, k, at, caption) in [
        (
            640,
            4,
            (320, 240),
            "pixels x 320–332 and y 240–252, every 4th",
        ),
        (
            640,
            2,
            (320, 240),
            "pixels x 320–326 and y 240–246, every 2nd",
        ),
        (
            10000,
            3,
            (4992, 4992),
            "pixels x 4992–5001 and y 4992–5001, every 3rd",
        ),
    ] {
        let mut s = scene_teapot();
        if size != 640 {
            s.camera.update_size(size, size);
        }
        s.render.subsample = k;
        let c = rtlab::viz::bundle::draw(&s, at.0, at.1, 0).unwrap();
        let all = c.texts().join("\n");
        assert!(all.contains(caption), "--subsample {k}: {all}");
        assert!(!all.contains('/'), "--subsample {k}: {all}");
        texts_fit(&c);
        in_frames(&c);
    }
}

/// Every text of `c` (left-anchored, as the figure draws them) ends inside the canvas, and no
/// two texts' boxes (their measured width, their size tall) overlap.
fn texts_fit(c: &rtlab::viz::canvas::Canvas) {
    use rtlab::viz::canvas::{Anchor, Canvas};
    let boxes: Vec<(String, [f32; 4])> = drawn_texts(c)
        .into_iter()
        .filter(|t| t.3 == Anchor::Left)
        .map(|(text, at, size, _)| {
            let right = at[0] + Canvas::text_width(&text, size);
            let b = [at[0], at[1] - size / 2.0, right, at[1] + size / 2.0];
            (text, b)
        })
        .collect();
    assert!(boxes.len() > 5);
    for (text, b) in &boxes {
        assert!(
            b[0] >= 0.0 && b[1] >= 0.0 && b[2] <= c.width() && b[3] <= c.height(),
            "{text:?} leaves the {}×{} canvas: {b:?}",
            c.width(),
            c.height()
        );
    }
    for (i, (t, a)) in boxes.iter().enumerate() {
        for (u, b) in &boxes[i + 1..] {
            let apart = a[2] <= b[0] || b[2] <= a[0] || a[3] <= b[1] || b[3] <= a[1];
            assert!(apart, "{t:?} {a:?} overlaps {u:?} {b:?}");
        }
    }
}

/// The scene's first mesh (the one the bundle figure draws).
fn first_mesh(s: &rtlab::scene::Scene) -> &rtlab::shapes::Mesh {
    s.objects
        .iter()
        .find_map(|o| match &o.shape {
            rtlab::shapes::Shape::Mesh(m) => Some(m),
            _ => None,
        })
        .expect("a mesh")
}

fn scene_teapot() -> rtlab::scene::Scene {
    scene("scenes/teapot.json")
}

/// How many frames (the rectangles drawn in the grid colour) `c` draws.
fn frames(c: &rtlab::viz::canvas::Canvas) -> usize {
    c.display
        .iter()
        .filter(|p| matches!(p, Prim::Rect { stroke: Some(s), fill: None, .. } if s == "#e4e4ea"))
        .count()
}

/// The book's bundle (the teapot at 48×36, pixel (22, 17)) opens two of the root's
/// children: panel 1 letters them A and B, and panel 2 draws each on its own, in a frame
/// of its own, captioned with its children's counts, which add up to the panel's heading.
#[test]
fn panel_two_draws_each_box_opened_on_its_own() {
    let mut small = scene_teapot();
    small.camera.update_size(48, 36);
    let c = rtlab::viz::bundle::draw(&small, 22, 17, 0).unwrap();
    let texts = c.texts();
    let all = texts.join("\n");
    assert_eq!(frames(&c), 3, "panel 1, and A and B: {all}");
    assert!(texts.contains(&"A") && texts.contains(&"B"), "{all}");
    let counts = |prefix: &str| -> (usize, usize) {
        let t = texts
            .iter()
            .find(|t| t.starts_with(prefix))
            .unwrap_or_else(|| panic!("no {prefix:?} in {all}"));
        let n: Vec<usize> = t
            .split(|ch: char| !ch.is_ascii_digit())
            .filter_map(|w| w.parse().ok())
            .collect();
        (n[n.len() - 2], n[n.len() - 1])
    };
    let (a, b) = (counts("A: "), counts("B: "));
    let heading = counts("2. One level down, in the boxes opened: ");
    assert_eq!((a.0 + b.0, a.1 + b.1), heading, "{all}");
    // A's children are the node it opened: as many as that node has boxes.
    let nodes = &first_mesh(&small).bvh.nodes;
    let opened: Vec<usize> = (0..rtlab::accel::WIDTH)
        .filter(|&s| !nodes[0].is_empty(s) && nodes[0].count[s] == 0)
        .map(|s| nodes[0].child[s] as usize)
        .collect();
    let boxes = |n: usize| {
        (0..rtlab::accel::WIDTH)
            .filter(|&s| !nodes[n].is_empty(s))
            .count()
    };
    assert!(
        opened.iter().any(|&n| boxes(n) == a.0 + a.1),
        "A's counts are one opened node's boxes: {all}"
    );
}

/// A soup of small triangles in a cube: the root's children overlap, or coincide seen from
/// above (split along y), yet panel 1 shows the letter of every box panel 2 draws, no two
/// letters and not the root's name on top of each other; and a camera looking straight
/// down says its rays come from above, not from a side.
#[test]
fn every_opened_box_is_lettered_apart_in_panel_one() {
    let obj = tmp("bundle-soup.obj");
    let mut text = String::new();
    let mut seed = 12345u64;
    let mut next = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    for _ in 0..3000 {
        let c = [next(), next(), next()];
        for _ in 0..3 {
            let v: Vec<f64> = c.iter().map(|x| x + 0.08 * next()).collect();
            text += &format!("v {} {} {}\n", v[0], v[1], v[2]);
        }
    }
    for f in 0..3000 {
        text += &format!("f {} {} {}\n", 3 * f + 1, 3 * f + 2, 3 * f + 3);
    }
    std::fs::write(&obj, text).unwrap();
    for (name, position) in [("side", [0.0, 0.8, 4.0]), ("down", [0.0, 4.0, 0.0001])] {
        let json = serde_json::json!({
            "camera": {"position": position, "look_at": [0, 0, 0], "fov_y": 40,
                       "width": 64, "height": 48, "up": [0, 0, -1]},
            "objects": [{"shape": "mesh", "file": obj}]
        });
        let file = tmp(&format!("bundle-soup-{name}.json"));
        std::fs::write(&file, json.to_string()).unwrap();
        let scene = rtlab::scene::Scene::load(&file).unwrap();
        let c = rtlab::viz::bundle::draw(&scene, 32, 24, 0).unwrap();
        let all = c.texts().join(" ");
        let drawn = drawn_texts(&c);
        let captions: Vec<String> = drawn
            .iter()
            .filter(|t| t.0.len() > 3 && t.0.as_bytes()[1] == b':' && t.0.contains(" entered, "))
            .map(|t| t.0[..1].to_string())
            .collect();
        assert!(
            captions.len() >= 2,
            "{name}: panel 2 draws two boxes or more: {all}"
        );
        let boxes: Vec<(String, [f32; 4])> = drawn
            .iter()
            .filter(|t| t.0 == "root" || captions.contains(&t.0))
            .map(|(t, at, size, anchor)| {
                let b = rtlab::viz::labels::text_box((at[0], at[1]), t, *size, *anchor);
                (t.clone(), b)
            })
            .collect();
        for letter in &captions {
            assert!(
                boxes.iter().any(|(t, _)| t == letter),
                "{name}: {letter} is in panel 2 but not in panel 1: {all}"
            );
        }
        for (i, (t, a)) in boxes.iter().enumerate() {
            for (u, b) in &boxes[i + 1..] {
                let apart = a[2] <= b[0] || b[2] <= a[0] || a[3] <= b[1] || b[3] <= a[1];
                assert!(apart, "{name}: {t:?} {a:?} overlaps {u:?} {b:?}");
            }
        }
        let from = if name == "down" {
            "the rays come from the camera (above the figure, looking down)"
        } else {
            "the rays come from the camera (bottom)"
        };
        assert!(all.contains(from), "{name}: {all}");
    }
}

/// Every line, dot and frustum of `c` lies inside one of its panel frames (the rectangles
/// drawn in the grid colour), up to half a line's width.
fn in_frames(c: &rtlab::viz::canvas::Canvas) {
    let frames: Vec<([f32; 2], [f32; 2])> = c
        .display
        .iter()
        .filter_map(|p| match p {
            Prim::Rect {
                min,
                size,
                stroke: Some(s),
                fill: None,
            } if s == "#e4e4ea" => Some((*min, *size)),
            _ => None,
        })
        .collect();
    let zoomed = c
        .texts()
        .iter()
        .filter(|t| t.len() > 3 && t.as_bytes()[1] == b':' && t.contains(" entered, "))
        .count();
    assert_eq!(
        frames.len(),
        if zoomed == 0 { 2 } else { 1 + zoomed },
        "a frame for panel 1, and one per box panel 2 draws (or panel 2's own)"
    );
    let inside = |p: [f32; 2], slack: f32| {
        frames.iter().any(|(min, size)| {
            p[0] >= min[0] - slack
                && p[0] <= min[0] + size[0] + slack
                && p[1] >= min[1] - slack
                && p[1] <= min[1] + size[1] + slack
        })
    };
    let (mut lines, mut dots) = (0, 0);
    for p in &c.display {
        match p {
            // The legend's sample line sits above the panels; everything below them is text.
            Prim::Line { from, to, .. } if from[1] > frames[0].0[1] - 1.0 => {
                assert!(
                    inside(*from, 0.2) && inside(*to, 0.2),
                    "{p:?} leaves its panel"
                );
                lines += 1;
            }
            Prim::Circle { center, .. } => {
                assert!(inside(*center, 0.0), "{p:?} outside the panels");
                dots += 1;
            }
            // The frustums.
            Prim::Polygon { points, .. } => {
                assert!(
                    points.iter().all(|q| inside(*q, 0.2)),
                    "{p:?} leaves its panel"
                );
            }
            Prim::Rect {
                min, size, fill, ..
            } if fill.is_some() && min[1] > frames[0].0[1] - 1.0 => {
                let max = [min[0] + size[0], min[1] + size[1]];
                assert!(
                    inside(*min, 1.0) && inside(max, 1.0),
                    "{p:?} leaves its panel"
                );
            }
            _ => {}
        }
    }
    assert!(lines > 0 && dots > 0, "rays and hits drawn");
}

/// The figure's bundle is the render's: for sample `k` of a pixel, `bundle_of` gives exactly
/// the pixels and camera rays (to the bit) `trace_bundled` traces together for its tile, with
/// a grid sampler and subsampling on an image whose edge cuts the blocks.
#[test]
fn bundle_of_is_the_bundle_the_render_traces() {
    let mut scene = scene_teapot();
    scene.camera.update_size(37, 29);
    for (sampler, spp, subsample) in [
        (SamplerKind::Center, 1, 1),
        (SamplerKind::Grid, 4, 1),
        (SamplerKind::Jittered, 4, 2),
        (SamplerKind::Corners, 1, 1),
        (SamplerKind::Center, 1, 3),
    ] {
        let mut s = scene.render.clone();
        (s.sampler, s.spp, s.subsample, s.traversal) = (sampler, spp, subsample, Traversal::Bundle);
        let (w, h) = (scene.camera.width, scene.camera.height);
        for tile in rtlab::sampling::tiles(w, h) {
            let plan = TilePlan::new(&s, w, h, &tile).unwrap();
            // The bundles as traced: runs of one sample index within a block (a block's end
            // marked by an empty bundle, so that the next block starts a new one).
            let traced = std::cell::RefCell::new(vec![(u32::MAX, vec![], vec![])]);
            trace_bundled(
                &scene,
                &s,
                &tile,
                &plan,
                &mut BundleTally::default(),
                |_, xy, k, cam, _| {
                    let mut t = traced.borrow_mut();
                    if t.last().unwrap().0 != k {
                        t.push((k, vec![], vec![]));
                    }
                    let b = t.last_mut().unwrap();
                    b.1.push(xy);
                    b.2.push(cam.ray);
                },
                |_| {
                    traced.borrow_mut().push((u32::MAX, vec![], vec![]));
                    true
                },
            );
            let mut traced = traced.into_inner();
            traced.retain(|b| b.0 != u32::MAX);
            for (k, pixels, rays) in &traced {
                for &xy in pixels.iter().step_by(3) {
                    let b = bundle_of(&scene, &s, xy, *k).unwrap();
                    assert_eq!(&b.pixels, pixels, "{sampler:?} {xy:?} sample {k}");
                    assert_eq!(b.sample, *k);
                    assert_eq!(b.rays.len(), rays.len());
                    for (a, r) in b.rays.iter().zip(rays) {
                        assert!(
                            a.origin == r.origin && a.dir == r.dir,
                            "{sampler:?} {xy:?} sample {k}: another ray"
                        );
                    }
                }
            }
        }
        // An untraced pixel has no bundle.
        if subsample > 1 {
            assert_eq!(
                bundle_of(&scene, &s, (1, 1), 0).unwrap_err(),
                NoBundle::NoSample
            );
        }
    }
}

/// A bundle whose rays all pass beside the mesh's box (seen from above) leaves the panels
/// without a line: they say so instead of staying blank, readably (texts_fit), and a
/// bundle whose rays cross the view does not.
#[test]
fn panels_the_rays_do_not_cross_say_so() {
    let whitted = scene("scenes/whitted.json");
    let beside = rtlab::viz::bundle::draw(&whitted, 100, 100, 0).unwrap();
    let said = beside
        .texts()
        .iter()
        .filter(|t| t.contains("No ray of the bundle crosses this view"))
        .count();
    assert_eq!(said, 2, "one per panel: {:?}", beside.texts());
    texts_fit(&beside);
    let through = rtlab::viz::bundle::draw(&scene_teapot(), 320, 240, 0).unwrap();
    assert!(!through.texts().join(" ").contains("No ray of the bundle"));
}

/// Each panel shades the bundle's frustum: one convex region per panel, inside the panel's
/// frame, that holds every ray drawn (the lines of width 1, from where a ray enters the
/// panel to its hit), on the book's figure and on a block the image's edge cuts.
#[test]
fn each_panel_shades_the_frustum_around_every_ray() {
    let mut small = scene_teapot();
    small.camera.update_size(48, 36);
    let mut clipped = scene_teapot();
    clipped.camera.update_size(11, 9);
    // A mesh scaled up (5 × its file's size, fifty times the teapot scene's): in its own
    // space a camera ray's direction is a fifth of unit length, and the rays, hits and
    // frustum are drawn all the same.
    let big = tmp("bundle-big-teapot.json");
    let obj = path("scenes/meshes/teapot.obj");
    let json = serde_json::json!({
        "camera": {"position": [0, 130, 260], "look_at": [0, 39.4, 0], "fov_y": 35,
                   "width": 48, "height": 36},
        "objects": [{"shape": "mesh", "file": obj, "transform": [{"scale": 5}]}]
    });
    std::fs::write(&big, json.to_string()).unwrap();
    let big = rtlab::scene::Scene::load(&big).unwrap();
    let all = rtlab::viz::bundle::draw(&big, 22, 17, 0)
        .unwrap()
        .texts()
        .join("\n");
    assert!(!all.contains("No ray of the bundle"), "{all}");
    assert!(all.contains("rays hit (red dots)"), "{all}");
    // A mesh stretched tall (its top far above the middle of its box), seen from near its
    // top: the hits lie far from the box's centre, and inside the frustum still.
    let tall = tmp("bundle-tall-teapot.json");
    let json = serde_json::json!({
        "camera": {"position": [0, 40, 6], "look_at": [0, 30, 0], "fov_y": 35,
                   "width": 48, "height": 36},
        "objects": [{"shape": "mesh", "file": obj, "transform": [{"scale": [0.2, 4, 0.2]}]}]
    });
    std::fs::write(&tall, json.to_string()).unwrap();
    let tall = rtlab::scene::Scene::load(&tall).unwrap();
    for (scene, (x, y)) in [
        (&small, (22, 17)),
        (&clipped, (10, 7)),
        (&big, (22, 17)),
        (&tall, (24, 18)),
    ] {
        let c = rtlab::viz::bundle::draw(scene, x, y, 0).unwrap();
        let frustums: Vec<&Vec<[f32; 2]>> = c
            .display
            .iter()
            .filter_map(|p| match p {
                Prim::Polygon {
                    points,
                    stroke: None,
                    fill: Some(_),
                } => Some(points),
                _ => None,
            })
            .collect();
        assert_eq!(
            frustums.len(),
            frames(&c),
            "one frustum per frame (panel 1, and each box panel 2 zooms in on) at ({x}, {y})"
        );
        // Inside a convex polygon: on one side of every edge (either winding), within `slack`.
        let inside = |poly: &[[f32; 2]], p: [f32; 2], slack: f32| {
            let sides: Vec<f32> = (0..poly.len())
                .map(|i| {
                    let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
                    let (ex, ey) = (b[0] - a[0], b[1] - a[1]);
                    let len = (ex * ex + ey * ey).sqrt().max(1e-6);
                    (ex * (p[1] - a[1]) - ey * (p[0] - a[0])) / len
                })
                .collect();
            sides.iter().all(|&d| d >= -slack) || sides.iter().all(|&d| d <= slack)
        };
        let mut rays = 0;
        for p in &c.display {
            if let Prim::Line {
                from, to, width, ..
            } = p
            {
                if *width == 1.0 {
                    assert!(
                        frustums
                            .iter()
                            .any(|f| inside(f, *from, 0.5) && inside(f, *to, 0.5)),
                        "ray {p:?} outside the frustums at ({x}, {y})"
                    );
                    rays += 1;
                }
            }
        }
        assert!(rays > 0, "rays drawn at ({x}, {y})");
        in_frames(&c);
    }
}

/// A mesh flat in z (one triangle standing in the plane z = 0, seen from the front) is a line
/// from above: its panels still get a band to draw the rays across, every ray and hit of a
/// bundle that hits it is drawn inside the frames, and no text overlaps another.
#[test]
fn a_mesh_flat_in_the_view_from_above_still_gets_panels_to_draw_in() {
    let obj = tmp("bundle-flat-triangle.obj");
    std::fs::write(&obj, "v -1 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let json = serde_json::json!({
        "camera": {"position": [0, 0.5, 3], "look_at": [0, 0.5, 0], "fov_y": 40,
                   "width": 32, "height": 24},
        "objects": [{"shape": "mesh", "file": obj}]
    });
    let file = tmp("bundle-flat-triangle.json");
    std::fs::write(&file, json.to_string()).unwrap();
    let scene = rtlab::scene::Scene::load(&file).unwrap();
    let c = rtlab::viz::bundle::draw(&scene, 16, 12, 0).unwrap();
    let all = c.texts().join("\n");
    assert!(all.contains("16 of 16 rays hit"), "{all}");
    assert!(!all.contains("No ray of the bundle"), "{all}");
    let frames: Vec<[f32; 2]> = c
        .display
        .iter()
        .filter_map(|p| match p {
            Prim::Rect {
                size,
                stroke: Some(s),
                fill: None,
                ..
            } if s == "#e4e4ea" => Some(*size),
            _ => None,
        })
        .collect();
    assert_eq!(frames.len(), 2, "{frames:?}");
    for size in &frames {
        assert!(size[1] >= 0.2 * size[0], "a band, not a line: {size:?}");
    }
    let dots = c
        .display
        .iter()
        .filter(|p| matches!(p, Prim::Circle { .. }))
        .count();
    assert_eq!(dots, 32, "every hit drawn in both panels");
    texts_fit(&c);
    in_frames(&c);
}
