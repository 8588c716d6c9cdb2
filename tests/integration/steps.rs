//! `rtlab steps`: every frame is the one tracer under other switches, each frame adds exactly
//! its term, the last frame is `render`'s image, and the outputs are deterministic. Also the
//! AOVs behind the first frames and the forward-tracing counts.

use super::common::*;
use glam::DVec3;
use rtlab::sampling::aov::{render_aov, trace_aov_samples, Aov, AovSample};
use rtlab::sampling::{render, RenderStats};
use rtlab::scene::{RenderSettings, Scene};
use rtlab::viz::steps::{plan, render_frames, Step, StepKind};

fn small(rel: &str, w: u32, h: u32) -> Scene {
    let mut s = scene(rel);
    s.camera.update_size(w, h);
    s
}

fn settings_of<'a>(steps: &'a [Step], name: &str) -> &'a RenderSettings {
    let s = steps
        .iter()
        .find(|s| s.name == name)
        .unwrap_or_else(|| panic!("no step {name}"));
    match &s.kind {
        StepKind::Render(r) => r,
        StepKind::Aov(_) => panic!("{name} is an AOV step"),
    }
}

fn linear(scene: &Scene, s: &RenderSettings) -> Vec<DVec3> {
    render(scene, s, false, None).image.pixels
}

/// The one sample of each pixel (the scenes used here have spp 1 and a box filter).
fn aov_samples(scene: &Scene, s: &RenderSettings) -> Vec<AovSample> {
    assert_eq!(s.spp, 1);
    trace_aov_samples(scene, s)
        .pixels
        .into_iter()
        .map(|p| p[0].1)
        .collect()
}

#[test]
fn frames_and_captions_per_scene() {
    let mut report = String::new();
    for p in all_scenes() {
        let mut scene = Scene::load(&p).unwrap();
        scene.camera.update_size(64, 40);
        let (steps, mut skipped) = plan(&scene);
        let frames = render_frames(&scene, &steps, &mut skipped);
        assert_eq!(frames.first().unwrap().name, "visibility");
        assert_eq!(frames.last().unwrap().name, "final");
        report += &format!("{}:\n", p.file_name().unwrap().to_string_lossy());
        for f in &frames {
            report += &format!("  - {}: {}\n", f.name, f.caption);
        }
        for s in &skipped {
            report += &format!("  # skipped {}: {}\n", s.name, s.reason);
        }
    }
    insta::with_settings!({
        description => "The frames `rtlab steps` makes for each scene at 64×40, with captions, and the steps it skips (nothing to add, or switched off).",
        omit_expression => true,
    }, {
        insta::assert_snapshot!("steps_frames_per_scene", report);
    });
}

#[test]
fn each_lighting_frame_adds_exactly_its_term() {
    let scene = small("scenes/spheres.json", 96, 72);
    let (steps, _) = plan(&scene);
    let ambient = linear(&scene, settings_of(&steps, "ambient"));
    let diffuse_s = settings_of(&steps, "diffuse");
    let diffuse = linear(&scene, diffuse_s);
    let specular_s = settings_of(&steps, "specular");
    let specular = linear(&scene, specular_s);
    let d_terms = aov_samples(&scene, diffuse_s);
    let s_terms = aov_samples(&scene, specular_s);
    let mut lit = 0;
    for i in 0..ambient.len() {
        let d = diffuse[i] - ambient[i];
        assert!(
            (d - d_terms[i].diffuse).abs().max_element() < 1e-12,
            "pixel {i}: + diffuse added {d}, the diffuse term is {}",
            d_terms[i].diffuse
        );
        assert_eq!(d_terms[i].specular, DVec3::ZERO, "no specular yet");
        let s = specular[i] - diffuse[i];
        assert!(
            (s - s_terms[i].specular).abs().max_element() < 1e-12,
            "pixel {i}: + specular added {s}, the specular term is {}",
            s_terms[i].specular
        );
        lit += (d.max_element() > 0.0) as usize;
    }
    assert!(
        lit > ambient.len() / 3,
        "diffuse light reached {lit} pixels"
    );
}

#[test]
fn shadows_frame_equals_specular_frame_where_no_light_is_blocked() {
    let scene = small("scenes/spheres.json", 96, 72);
    let (steps, _) = plan(&scene);
    let spec_s = settings_of(&steps, "specular");
    let shad_s = settings_of(&steps, "shadows");
    let enc = scene.render.encoding;
    let spec = render(&scene, spec_s, false, None).image.to_rgb8(enc);
    let shad = render(&scene, shad_s, false, None).image.to_rgb8(enc);
    let rays = aov_samples(&scene, shad_s);
    let (mut blocked, mut darker) = (0, 0);
    for (i, (a, b)) in spec.pixels().zip(shad.pixels()).enumerate() {
        let r = &rays[i];
        if r.shadow_reached == r.shadow_rays {
            assert_eq!(
                a, b,
                "pixel {i}: no shadow ray blocked, yet the frame changed"
            );
        } else {
            blocked += 1;
            assert!(
                (0..3).all(|k| b[k] <= a[k]),
                "pixel {i}: a shadow made it brighter"
            );
            darker += (a != b) as usize;
        }
    }
    assert!(blocked > 50, "only {blocked} pixels in shadow");
    assert!(
        darker * 10 > blocked * 9,
        "{darker} of {blocked} shadowed pixels changed"
    );
}

#[test]
fn reflection_frame_adds_the_reflected_term_only_on_mirrors() {
    let scene = small("scenes/spheres.json", 96, 72);
    let (steps, _) = plan(&scene);
    let before = linear(&scene, settings_of(&steps, "shadows"));
    let r1_s = settings_of(&steps, "reflection-1");
    assert_eq!(r1_s.max_depth, 1);
    let after = linear(&scene, r1_s);
    let terms = aov_samples(&scene, r1_s);
    let mut mirrored = 0;
    for i in 0..before.len() {
        let added = after[i] - before[i];
        assert!(
            (added - terms[i].reflection).abs().max_element() < 1e-12,
            "pixel {i}: added {added}, reflected term {}",
            terms[i].reflection
        );
        assert!(terms[i].ray_depth <= 1);
        if terms[i].ray_depth == 0 {
            assert_eq!(
                added,
                DVec3::ZERO,
                "pixel {i}: no reflection ray, yet changed"
            );
        } else {
            mirrored += 1;
        }
    }
    assert!(mirrored > 100, "{mirrored} pixels see the mirror");
}

#[test]
fn refraction_frame_changes_only_pixels_whose_rays_meet_glass() {
    let scene = small("scenes/glass.json", 80, 50);
    let (steps, _) = plan(&scene);
    let last_reflection = steps
        .iter()
        .rev()
        .find(|s| s.name.starts_with("reflection-"))
        .unwrap();
    let StepKind::Render(before_s) = &last_reflection.kind else {
        unreachable!()
    };
    let refr_s = settings_of(&steps, "refraction");
    let before = linear(&scene, before_s);
    let after = linear(&scene, refr_s);
    // Whether any ray of the pixel's tree hit a transparent object: watch it with the tree.
    let transparent: Vec<bool> = scene
        .objects
        .iter()
        .enumerate()
        .map(|(i, _)| scene.material_of(i).transparent.max_element() > 0.0)
        .collect();
    let mut changed = 0;
    for y in 0..50 {
        for x in 0..80 {
            let i = (y * 80 + x) as usize;
            let tree = rtlab::cli::explain::explain(&scene, x, y);
            let meets_glass = tree
                .samples
                .iter()
                .any(|s| touches(&s.ray, &scene, &transparent));
            if !meets_glass {
                assert_eq!(before[i], after[i], "pixel ({x}, {y}) never meets glass");
            } else if before[i] != after[i] {
                changed += 1;
            }
        }
    }
    assert!(changed > 100, "refraction changed {changed} pixels");
}

fn touches(node: &rtlab::trace::RayNode, scene: &Scene, transparent: &[bool]) -> bool {
    let hit_glass = node.hit.as_ref().is_some_and(|h| {
        (0..scene.objects.len()).any(|i| transparent[i] && scene.object_name(i) == h.object)
    });
    hit_glass || node.children.iter().any(|c| touches(c, scene, transparent))
}

#[test]
fn ambient_aov_is_the_ambient_frame() {
    let scene = small("scenes/spheres.json", 64, 48);
    let (steps, _) = plan(&scene);
    let frame = render(&scene, settings_of(&steps, "ambient"), false, None)
        .image
        .to_rgb8(scene.render.encoding);
    assert_eq!(
        render_aov(&scene, &scene.render, Aov::Ambient)
            .expect("not cancelled")
            .image,
        frame
    );
}

#[test]
fn camera_only_aovs_trace_one_ray_per_sample() {
    let scene = small("scenes/glass.json", 40, 25);
    for aov in [Aov::Depth, Aov::Normal, Aov::ObjectId] {
        let s = aov.settings(&scene.render);
        for px in trace_aov_samples(&scene, &s).pixels {
            let a = px[0].1;
            assert_eq!(a.ray_depth, 0);
            assert_eq!(a.shadow_rays, 0);
            if let Some(h) = a.hit {
                assert!((h.normal.length() - 1.0).abs() < 1e-9, "unit normal");
            }
        }
    }
}

fn run_steps(scene: &str, dir: &std::path::Path, extra: &[&str]) -> String {
    let _ = std::fs::remove_dir_all(dir);
    let mut args = vec!["steps", scene, "-o", dir.to_str().unwrap()];
    args.extend_from_slice(extra);
    let o = rtlab(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    String::from_utf8(o.stdout).unwrap()
}

#[test]
fn last_frame_is_renders_png_byte_for_byte() {
    let dir = tmp("steps-bare");
    let size = ["--width", "72", "--height", "48", "--max-depth", "3"];
    let mut extra = vec!["--no-captions"];
    extra.extend_from_slice(&size);
    run_steps("scenes/glass.json", &dir, &extra);
    let index: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("index.json")).unwrap()).unwrap();
    let list = index.as_array().unwrap();
    let last = list.last().unwrap()["file"].as_str().unwrap().to_string();
    assert!(last.ends_with("-final.png"), "{last}");
    let out = tmp("steps-render.png");
    let mut args = vec![
        "render",
        "scenes/glass.json",
        "-o",
        out.to_str().unwrap(),
        "-q",
    ];
    args.extend_from_slice(&size);
    let o = rtlab(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        std::fs::read(dir.join(&last)).unwrap(),
        std::fs::read(&out).unwrap(),
        "the final frame is not render's PNG"
    );
    // Every frame listed exists, numbered in order.
    for (i, e) in list.iter().enumerate() {
        let f = e["file"].as_str().unwrap();
        assert!(f.starts_with(&format!("{:03}-", i + 1)), "{f}");
        assert!(dir.join(f).exists(), "{f}");
        assert!(!e["caption"].as_str().unwrap().is_empty());
    }
}

#[test]
fn captioned_frames_keep_the_image_and_add_a_strip() {
    let (bare, cap) = (tmp("steps-b"), tmp("steps-c"));
    let size = ["--width", "64", "--height", "40"];
    let mut extra = vec!["--no-captions"];
    extra.extend_from_slice(&size);
    run_steps("scenes/spheres.json", &bare, &extra);
    run_steps("scenes/spheres.json", &cap, &size);
    let a = image::open(bare.join("001-visibility.png"))
        .unwrap()
        .to_rgb8();
    let b = image::open(cap.join("001-visibility.png"))
        .unwrap()
        .to_rgb8();
    assert_eq!(a.width(), b.width());
    assert!(b.height() > a.height());
    for (x, y, p) in a.enumerate_pixels() {
        assert_eq!(p, b.get_pixel(x, y));
    }
}

#[test]
fn gif_is_deterministic_on_any_thread_count() {
    let (d1, d2) = (tmp("steps-g1"), tmp("steps-g2"));
    let size = ["--width", "64", "--height", "40", "--gif"];
    let mut a1 = vec!["--threads", "1"];
    a1.extend_from_slice(&size);
    let mut a2 = vec!["--threads", "2"];
    a2.extend_from_slice(&size);
    run_steps("scenes/mirrors.json", &d1, &a1);
    run_steps("scenes/mirrors.json", &d2, &a2);
    let g1 = std::fs::read(d1.join("steps.gif")).unwrap();
    assert_eq!(g1, std::fs::read(d2.join("steps.gif")).unwrap());
    // One GIF frame per PNG frame.
    use image::AnimationDecoder;
    let dec = image::codecs::gif::GifDecoder::new(std::io::Cursor::new(g1)).unwrap();
    let n = dec.into_frames().count();
    let pngs = std::fs::read_dir(&d1)
        .unwrap()
        .filter(|e| {
            let e = e.as_ref().unwrap().file_name();
            e.to_string_lossy().ends_with(".png")
        })
        .count();
    assert_eq!(n, pngs);
}

#[test]
fn skipped_steps_are_reported() {
    let dir = tmp("steps-skip");
    let out = run_steps(
        "scenes/spheres.json",
        &dir,
        &["--width", "48", "--height", "32", "--no-shadows"],
    );
    assert!(
        out.contains("skipped shadows: shadows are switched off (--no-shadows)"),
        "{out}"
    );
    assert!(
        out.contains("skipped refraction: nothing in the scene is transparent"),
        "{out}"
    );
    assert!(!dir.join("007-shadows.png").exists());
}

#[test]
fn bad_arguments_exit_2() {
    let o = rtlab(&[
        "render",
        "scenes/spheres.json",
        "--aov",
        "colour",
        "-o",
        "/tmp/x.png",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("depth, normal"), "{}", stderr(&o));
    let f = write_tmp("steps-file", "x");
    let o = rtlab(&["steps", "scenes/spheres.json", "-o", f.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let o = rtlab(&[
        "steps",
        "scenes/spheres.json",
        "-o",
        "/tmp/s.png",
        "--frames",
        "nope",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("its frames: visibility"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn forward_tracing_counts_add_up_and_few_photons_reach_the_film() {
    use rtlab::trace::forward::{film_position, trace_photons};
    let scene = small("scenes/spheres.json", 96, 72);
    let a = trace_photons(&scene, 20_000, 0.1, 4, 0);
    let c = &a.counts;
    assert_eq!(
        c.reached_film + c.outside_view + c.escaped + c.absorbed,
        c.photons
    );
    assert!(c.hit_surface > c.photons / 4, "{c:?}");
    assert!(c.reached_film * 1000 < c.photons, "{c:?}");
    assert_eq!(a.splats.len() as u64, c.reached_film);
    // Same counts on one thread.
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let b = pool.install(|| trace_photons(&scene, 20_000, 0.1, 4, 0));
    assert_eq!(a.counts, b.counts);
    // Projecting a point of a camera ray lands back on the ray's film position.
    for film in [glam::DVec2::new(10.5, 20.5), glam::DVec2::new(95.0, 1.0)] {
        let (ray, _) = scene.camera.generate(film, None);
        let p = film_position(&scene, ray.at(3.7)).unwrap();
        assert!((p - film).length() < 1e-9, "{p} vs {film}");
    }
}

#[test]
fn pixel_storyboard_has_one_frame_per_event_of_the_ray_tree() {
    let dir = tmp("steps-pixel");
    let size = ["--width", "160", "--height", "100"];
    let mut extra = vec!["--pixel", "40,35", "--gif"];
    extra.extend_from_slice(&size);
    let out = run_steps("scenes/glass.json", &dir, &extra);
    let mut scene = scene("scenes/glass.json");
    scene.camera.update_size(160, 100);
    let e = rtlab::cli::explain::explain(&scene, 40, 35);
    let tree = &e.samples[0].ray;
    let n = rtlab::viz::slice::event_count(tree);
    assert!(n >= 4, "a glass pixel spawns several rays ({n})");
    let index: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("index.json")).unwrap()).unwrap();
    let list = index.as_array().unwrap();
    assert_eq!(list.len(), n, "{out}");
    assert_eq!(list[0]["file"], "001-camera.png");
    assert!(list[0]["caption"]
        .as_str()
        .unwrap()
        .starts_with("camera ray hits glass ball"));
    // Each frame's name is the kind of the ray it adds, in the tracer's order.
    let kinds: Vec<String> = rtlab::viz::steps::events(tree)
        .iter()
        .map(|r| format!("{:?}", r.kind).to_ascii_lowercase())
        .collect();
    for (i, e) in list.iter().enumerate() {
        assert_eq!(e["file"], format!("{:03}-{}.png", i + 1, kinds[i]));
    }
    let last = list.last().unwrap()["caption"].as_str().unwrap();
    assert!(
        last.contains(&format!("pixel colour ({:.3}, ", e.color.x)),
        "{last}"
    );
    // Consecutive frames differ (each adds a ray) and the GIF holds every frame.
    for i in 1..n {
        let a = std::fs::read(dir.join(list[i - 1]["file"].as_str().unwrap())).unwrap();
        let b = std::fs::read(dir.join(list[i]["file"].as_str().unwrap())).unwrap();
        assert_ne!(a, b, "frame {} adds nothing", i + 1);
    }
    let again = tmp("steps-pixel-2");
    run_steps("scenes/glass.json", &again, &extra);
    assert_eq!(
        std::fs::read(dir.join("steps.gif")).unwrap(),
        std::fs::read(again.join("steps.gif")).unwrap()
    );
}

#[test]
fn cost_aov_counts_what_stats_count() {
    // The cost AOV and `--stats` watch the same tracer: per pixel, the same work, including
    // the faces and BVH nodes inside meshes (the teapot), single rays or bundles (each
    // ray's share of its bundle's work).
    use rtlab::accel::Traversal;
    for (file, w, h, traversal) in [
        ("scenes/mirrors.json", 48, 30, Traversal::Single),
        ("scenes/mirrors.json", 48, 30, Traversal::Bundle),
        ("scenes/teapot.json", 64, 48, Traversal::Single),
        ("scenes/teapot.json", 64, 48, Traversal::Bundle),
    ] {
        let mut scene = small(file, w, h);
        scene.render.traversal = traversal;
        let counting = rtlab::sampling::Counting::PerPixel;
        let stats = rtlab::sampling::render_counting(&scene, &scene.render, counting, None)
            .stats
            .unwrap();
        let work = stats
            .per_pixel
            .clone()
            .expect("each pixel's work, as asked");
        let (tests, nodes) = (
            work.tests.iter().sum::<u64>(),
            work.nodes.iter().sum::<u64>(),
        );
        assert_eq!(
            (tests, nodes),
            (stats.tests, stats.nodes),
            "{file} {traversal:?}"
        );
        // `--stats` counts the totals alone: the same totals.
        let totals = render(&scene, &scene.render, true, None).stats.unwrap();
        assert_eq!(totals.per_pixel, None);
        assert_eq!(
            RenderStats {
                per_pixel: None,
                ..stats.clone()
            },
            totals,
            "{file} {traversal:?}"
        );
        let samples = trace_aov_samples(&scene, &scene.render);
        for (i, px) in samples.pixels.iter().enumerate() {
            let cost: u64 = px.iter().map(|s| s.1.cost).sum();
            assert_eq!(cost, work.cost(i), "{file} {traversal:?} pixel {i}");
            for (_, s) in px {
                assert!(s.ray_depth <= scene.render.max_depth);
            }
        }
        if file.contains("mirrors") {
            assert!(samples
                .pixels
                .iter()
                .any(|p| p[0].1.ray_depth == scene.render.max_depth));
        } else {
            // A pixel on the teapot costs more than testing the scene's few objects.
            let most = samples.pixels.iter().map(|p| p[0].1.cost).max().unwrap();
            assert!(most > 3 * scene.objects.len() as u64, "max cost {most}");
        }
    }
}

/// A storyboard keeps one view: frame 1 and the last frame put the eye's label at the same
/// place (the window is fitted to the whole ray tree, not to the rays drawn so far).
#[test]
fn storyboard_view_does_not_move_between_frames() {
    use rtlab::viz::slice::{draw, event_count, SliceOptions};
    use rtlab::viz::Prim;
    let scene = rtlab::scene::Scene::load(&path("scenes/glass.json")).unwrap();
    let report = rtlab::cli::explain::explain(&scene, 160, 140);
    let tree = &report.samples[0].ray;
    let n = event_count(tree);
    assert!(n > 3, "{n} events");
    let eye_at = |k: usize| {
        let opts = SliceOptions {
            events: Some(k),
            ..Default::default()
        };
        let c = draw(&scene, tree, &opts).unwrap();
        c.display
            .iter()
            .find_map(|p| match p {
                Prim::Text { at, text, .. } if text == "eye" => Some(*at),
                _ => None,
            })
            .expect("the eye is labelled")
    };
    let (first, last) = (eye_at(1), eye_at(n));
    assert_eq!(first, last);
}

#[test]
fn steps_replaces_its_own_frames_and_nothing_else() {
    let dir = tmp("steps-own-frames");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    // A student's file that looks like a frame but no run of steps listed.
    let theirs = dir.join("050-my-homework.png");
    std::fs::write(&theirs, b"mine").unwrap();
    let small = ["--width", "32", "--height", "24", "--quiet"];
    let d = dir.to_str().unwrap();
    let o = rtlab(&[&["steps", "scenes/mirrors.json", "-o", d][..], &small[..]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    let many = std::fs::read_dir(&dir).unwrap().count();
    // A shorter sequence into the same folder: the longer run's extra frames go (its
    // index.json lists them), the student's file stays.
    let o = rtlab(&[&["steps", "scenes/spheres.json", "-o", d][..], &small[..]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    let index: Vec<serde_json::Value> =
        serde_json::from_str(&std::fs::read_to_string(dir.join("index.json")).unwrap()).unwrap();
    assert_eq!(names.len(), index.len() + 2, "{names:?}"); // the frames, index.json, theirs
    assert!(names.len() < many, "{names:?}");
    assert_eq!(std::fs::read(&theirs).unwrap(), b"mine");

    // A name that cannot be written (a folder where index.json goes): exit 2, nothing written.
    let blocked = tmp("steps-blocked");
    let _ = std::fs::remove_dir_all(&blocked);
    std::fs::create_dir_all(blocked.join("index.json")).unwrap();
    let b = blocked.to_str().unwrap();
    let o = rtlab(&[&["steps", "scenes/spheres.json", "-o", b][..], &small[..]].concat());
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("index.json is a directory"),
        "{}",
        stderr(&o)
    );
    assert_eq!(
        std::fs::read_dir(&blocked).unwrap().count(),
        1,
        "frames were written"
    );
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_dir_all(&blocked);
}
