//! Bundles of camera rays (`--traversal bundle`) find exactly the hits single rays find:
//! the same bytes on every scene and every sampler, the same AOVs, and the cost AOV and
//! `--stats` count the bundle's work.

use super::common::*;
use rtlab::accel::Traversal;
use rtlab::sampling::aov::{render_aov, trace_aov_samples, Aov};
use rtlab::sampling::render;
use rtlab::scene::SamplerKind;

fn both_ways(scene: &rtlab::scene::Scene, what: &str) {
    let mut s = scene.render.clone();
    s.traversal = Traversal::Single;
    let single = render(scene, &s, false, None);
    s.traversal = Traversal::Bundle;
    let bundle = render(scene, &s, false, None);
    let enc = scene.render.encoding;
    assert!(
        single.image.to_rgb8(enc) == bundle.image.to_rgb8(enc),
        "{what}: the bundle's image differs"
    );
    // Not only the bytes: every linear value, to the last bit.
    assert_eq!(single.image, bundle.image, "{what}");
}

#[test]
fn every_scene_same_image_single_or_bundle() {
    for p in all_scenes() {
        let mut scene =
            rtlab::scene::Scene::load(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        scene.camera.update_size(45, 34); // not a multiple of the 4×4 blocks or 16×16 tiles
        both_ways(&scene, &p.display().to_string());
    }
}

/// Beyond `scenes/`: the course's own scene files (CS 1230's JSON, as the course gives them
/// and as rtlab's tests keep them), its `.ini` templates (the course stages' settings, through
/// the CLI, which reads them), and the mistakes gallery: the same PNG bytes both ways.
#[test]
fn course_files_and_the_gallery_same_image_single_or_bundle() {
    let mut files: Vec<String> = ["tests/cs1230/scenes", "scenes/mistakes"]
        .into_iter()
        .flat_map(json_files)
        .map(|p| p.to_string_lossy().into_owned())
        .collect();
    for rel in [
        "tests/cs1230/course/scenefiles/intersect/optional/recursive_sphere_9.json",
        "tests/cs1230/course/template_inis/intersect/lights.ini",
        "tests/cs1230/course/template_inis/illuminate/textures.ini",
    ] {
        files.push(path(rel).to_string_lossy().into_owned());
    }
    assert!(
        files.len() >= 10,
        "the course files and the gallery are there: {files:?}"
    );
    for (i, f) in files.iter().enumerate() {
        let out = |t: &str| tmp(&format!("course-{i}-{t}.png"));
        for t in ["single", "bundle"] {
            let o = out(t);
            let r = rtlab(&[
                "render",
                f,
                "-o",
                o.to_str().unwrap(),
                "--traversal",
                t,
                "-q",
            ]);
            assert!(r.status.success(), "{f} --traversal {t}: {}", stderr(&r));
        }
        let (a, b) = (
            std::fs::read(out("single")).unwrap(),
            std::fs::read(out("bundle")).unwrap(),
        );
        for t in ["single", "bundle"] {
            std::fs::remove_file(out(t)).ok();
        }
        assert!(
            a == b,
            "{f}: the bundled render's PNG differs from the single-ray one"
        );
    }
}

#[test]
fn every_sampler_same_image_single_or_bundle() {
    for file in [
        "scenes/whitted.json",
        "scenes/teapot.json",
        "scenes/triangles.json",
    ] {
        let mut scene = scene(file);
        scene.camera.update_size(37, 29);
        for (kind, spp) in EVERY_SAMPLER {
            scene.render.sampler = kind;
            scene.render.spp = spp;
            both_ways(&scene, &format!("{file} {kind:?}"));
            scene.render.subsample = 3;
            both_ways(&scene, &format!("{file} {kind:?} subsample 3"));
            scene.render.subsample = 1;
        }
    }
}

#[test]
fn aovs_agree_and_cost_counts_the_bundles_work() {
    let mut scene = scene("scenes/teapot.json");
    scene.camera.update_size(48, 36);
    let mut s = scene.render.clone();
    let mut images = Vec::new();
    for t in [Traversal::Single, Traversal::Bundle] {
        s.traversal = t;
        let depth = render_aov(&scene, &s, Aov::Depth)
            .expect("not cancelled")
            .image;
        let normal = render_aov(&scene, &s, Aov::Normal)
            .expect("not cancelled")
            .image;
        let cost = render_aov(&scene, &s, Aov::Cost)
            .expect("not cancelled")
            .image;
        images.push((depth, normal, cost));
    }
    assert!(images[0].0 == images[1].0, "depth");
    assert!(images[0].1 == images[1].1, "normal");
    // The cost is a heat map of real work in both, not a blank image.
    for (_, _, cost) in &images {
        let distinct: std::collections::BTreeSet<_> = cost.pixels().map(|p| p.0).collect();
        assert!(distinct.len() > 5);
    }
    // The adaptive sampler's rays go alone in the render, whatever the traversal: so do the
    // cost AOV's, and its image is the same both ways.
    s.sampler = SamplerKind::Adaptive;
    s.spp = 16;
    let costs: Vec<_> = [Traversal::Single, Traversal::Bundle]
        .map(|t| {
            s.traversal = t;
            render_aov(&scene, &s, Aov::Cost)
                .expect("not cancelled")
                .image
        })
        .into();
    assert!(costs[0] == costs[1], "adaptive cost");
}

/// Under `--subsample` (and so in every progressive preview, pass 1) an AOV traces the
/// same pixels both ways: the bundled AOV once traced only the subsampled pixels while the
/// single-ray one traced them all, and its preview came out mostly black. Every AOV (but the
/// cost, which counts each traversal's own work), every sampler.
#[test]
fn subsampled_aovs_agree_single_or_bundle() {
    let mut scene = scene("scenes/spheres.json");
    scene.camera.update_size(45, 34);
    for (kind, spp) in EVERY_SAMPLER {
        let mut s = scene.render.clone();
        s.sampler = kind;
        s.spp = spp;
        s.subsample = 3;
        for &(aov, name, _) in Aov::ALL {
            if aov == Aov::Cost {
                continue;
            }
            let [single, bundle] = [Traversal::Single, Traversal::Bundle].map(|t| {
                s.traversal = t;
                render_aov(&scene, &s, aov).expect("not cancelled").image
            });
            assert!(single == bundle, "{name}, {kind:?}, subsample 3");
        }
        // An AOV traces the render's own camera rays: the corners sampler's shared corners
        // once each, only the traced pixels under --subsample (the adaptive sampler, which
        // decides while it traces, gives an AOV its first level).
        if kind != SamplerKind::Adaptive {
            for subsample in [1, 3] {
                let s = rtlab::scene::RenderSettings {
                    subsample,
                    ..s.clone()
                };
                let traced: usize = trace_aov_samples(&scene, &s)
                    .pixels
                    .iter()
                    .map(Vec::len)
                    .sum();
                let rays = render(&scene, &s, true, None).stats.unwrap().rays.camera;
                assert_eq!(traced as u64, rays, "{kind:?}, subsample {subsample}");
            }
        }
        // And the traced pixels are the full image's: under the box filter, stretched 3 times,
        // a traced pixel is its own sample alone (the normal: the depth's grey scale depends
        // on the range of every hit).
        if kind == SamplerKind::Center {
            let full = render_aov(
                &scene,
                &rtlab::scene::RenderSettings {
                    subsample: 1,
                    ..s.clone()
                },
                Aov::Normal,
            )
            .expect("not cancelled")
            .image;
            let sub = render_aov(&scene, &s, Aov::Normal)
                .expect("not cancelled")
                .image;
            for (x, y, p) in sub.enumerate_pixels() {
                if x % 3 == 0 && y % 3 == 0 {
                    assert_eq!(p, full.get_pixel(x, y), "({x}, {y})");
                }
            }
        }
    }
}

#[test]
fn stats_count_bundles_and_rays_alike() {
    let mut scene = scene("scenes/teapot.json");
    scene.camera.update_size(64, 48);
    let mut s = scene.render.clone();
    s.traversal = Traversal::Single;
    let single = render(&scene, &s, true, None).stats.unwrap();
    s.traversal = Traversal::Bundle;
    let bundle = render(&scene, &s, true, None).stats.unwrap();
    assert_eq!(single.rays, bundle.rays);
    assert_eq!(single.bundles.bundles, 0);
    // 64×48 in 4×4 blocks, one sample each: 192 bundles, each opening at least the root.
    assert_eq!(bundle.bundles.bundles, 16 * 12);
    assert!(bundle.bundles.opened >= 192);
    // Opened once per bundle, a node serves several rays: fewer openings than ray visits.
    assert!(bundle.bundles.opened < bundle.nodes);
}

#[test]
fn bundle_diagram_is_drawn_for_a_mesh_and_refused_without_one() {
    let out = tmp("bundle-diagram.png");
    let teapot = path("scenes/teapot.json");
    let o = rtlab(&[
        "explain",
        teapot.to_str().unwrap(),
        "--pixel",
        "22,17",
        "--width",
        "48",
        "--height",
        "36",
        "--max-depth",
        "0",
        "--bundle-diagram",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let img = image::open(&out).unwrap().to_rgb8();
    assert!(img.width() > 400 && img.height() > 300);
    let spheres = path("scenes/spheres.json");
    let bad = tmp("no-mesh.png");
    let o = rtlab(&[
        "explain",
        spheres.to_str().unwrap(),
        "--pixel",
        "1,1",
        "--bundle-diagram",
        bad.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--bundle-diagram") && stderr(&o).contains("mesh"));
    assert!(!bad.exists());
}

/// Shadow rays in bundles (`Accel::occluded_bundle`) get exactly the verdicts single rays
/// get (`Accel::occluded`): on every scene, from each camera hit of a 45×34 image (in 4×4
/// blocks, as the bench groups them) towards points around the scene, from the ray's own
/// t_min, with distances both to the point and short of it.
#[test]
fn every_scene_same_shadow_verdicts_single_or_bundle() {
    use rtlab::accel::{BundleCost, BUNDLE};
    use rtlab::math::Ray;
    let mut blocked_seen = [0usize; 2];
    for p in all_scenes() {
        let mut scene =
            rtlab::scene::Scene::load(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        scene.camera.update_size(45, 34);
        let eye = scene
            .camera
            .generate(glam::DVec2::new(22.5, 17.0), None)
            .0
            .origin;
        let targets = [
            eye,
            eye + glam::DVec3::new(3.0, 5.0, 2.0),
            glam::DVec3::new(-4.0, 6.0, -3.0),
        ];
        let mut rec = rtlab::trace::NoRecorder::default();
        for target in targets {
            for by in (0..34).step_by(4) {
                for bx in (0..45).step_by(4) {
                    let (mut rays, mut t_max) = (Vec::new(), [0.0; BUNDLE]);
                    for y in by..(by + 4).min(34) {
                        for x in bx..(bx + 4).min(45) {
                            let film = glam::DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
                            let cam = scene.camera.generate(film, None).0;
                            let Some((_, h)) = scene.accel.closest(
                                &scene.objects,
                                &cam,
                                1e-9,
                                f64::INFINITY,
                                &mut rec,
                            ) else {
                                continue;
                            };
                            let p = cam.at(h.t);
                            let d = target - p;
                            let dist = d.length();
                            // Every other ray stops short of the target: t_max matters.
                            t_max[rays.len()] = if (x + y) % 2 == 0 { dist } else { 0.5 * dist };
                            rays.push(Ray::new(p, d / dist));
                        }
                    }
                    if rays.is_empty() {
                        continue;
                    }
                    let got = scene.accel.occluded_bundle(
                        &scene.objects,
                        &rays,
                        1e-6,
                        &t_max,
                        &mut BundleCost::default(),
                    );
                    for (j, ray) in rays.iter().enumerate() {
                        let single = scene
                            .accel
                            .occluded(&scene.objects, ray, 1e-6, t_max[j], &mut rec)
                            .is_some();
                        assert_eq!(
                            got >> j & 1 == 1,
                            single,
                            "{}: shadow ray {j} of block ({bx}, {by})",
                            p.display()
                        );
                        blocked_seen[single as usize] += 1;
                    }
                }
            }
        }
    }
    // Both verdicts were exercised, many times.
    assert!(
        blocked_seen[0] > 1000 && blocked_seen[1] > 1000,
        "{blocked_seen:?}"
    );
}

/// The bundle walks run at the widest SIMD level the processor has (AVX-512, AVX2, or the
/// portable one; `RTLAB_SIMD` caps it). Every level writes the same bytes as single rays,
/// on a mesh (shared-origin face tests), a scene of spheres and boxes (the scene's own BVH),
/// and with depth of field (rays from different points of the lens).
#[test]
fn every_simd_level_writes_the_same_image() {
    let teapot = path("scenes/meshes/teapot.obj");
    let lens = serde_json::json!({
        "camera": {"position": [0, 2.6, 5.2], "look_at": [0, 0.65, 0], "fov_y": 35,
                   "aperture": 0.3, "focal_distance": 5.0},
        "lights": [{"type": "point", "position": [-4, 6, 4]}],
        "objects": [{"shape": "plane"},
                    {"shape": "mesh", "file": teapot.to_str().unwrap(),
                     "transform": [{"scale": 0.1}, {"translate": [0, 0.7875, 0]}]}]
    });
    let lens = write_tmp("simd-lens.json", &lens.to_string());
    let lens = lens.to_str().unwrap();
    for (scene, extra) in [
        ("scenes/teapot.json", &[][..]),
        ("scenes/whitted.json", &[][..]),
        (lens, &["--spp", "4", "--sampler", "jittered"][..]),
    ] {
        let render = |simd: &str, traversal: &str| {
            let out = tmp(&format!(
                "simd-{}-{simd}-{traversal}.png",
                scene.replace('/', "_")
            ));
            let args = [
                &["render", scene, "-o", out.to_str().unwrap()][..],
                &[
                    "--width",
                    "61",
                    "--height",
                    "47",
                    "--quiet",
                    "--traversal",
                    traversal,
                ],
                extra,
            ]
            .concat();
            let o = rtlab_simd(simd, &args);
            assert!(o.status.success(), "{scene}: {}", stderr(&o));
            std::fs::read(&out).unwrap()
        };
        let single = render("base", "single");
        for simd in ["base", "avx2", "avx512"] {
            assert!(
                render(simd, "bundle") == single,
                "{scene}: --traversal bundle at SIMD level {simd} differs from single rays"
            );
        }
    }
}

/// `--stats json` says which lanes the bundles ran on, and `RTLAB_SIMD` caps it.
#[test]
fn stats_name_the_simd_level_the_bundles_ran_on() {
    for (cap, want) in [("base", "portable"), ("avx2", "avx2")] {
        let out = tmp(&format!("simd-stats-{cap}.png"));
        let o = rtlab_simd(
            cap,
            &[
                "render",
                "scenes/teapot.json",
                "-o",
                out.to_str().unwrap(),
                "--width",
                "32",
                "--height",
                "24",
                "--stats",
                "json",
            ],
        );
        assert!(o.status.success(), "{}", stderr(&o));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(v["traversal"], "bundle");
        let simd = v["bundles"]["simd"].as_str().unwrap();
        // A processor without AVX2 runs the portable lanes whatever the cap allows.
        assert!(simd == want || simd == "portable", "{cap}: {simd}");
        if cap == "base" {
            assert_eq!(simd, "portable");
        }
    }
}

/// Where bundles were asked for but none could be traced, `--stats` says so and why, rather
/// than printing "bundle traversal" over rays that all went alone.
#[test]
fn stats_say_why_no_bundles_were_traced() {
    let out = tmp("stats-bundles.png");
    let stats_of = |extra: &[&str]| {
        let mut args = vec!["render", "scenes/teapot.json", "-o", out.to_str().unwrap()];
        args.extend(["--width", "32", "--height", "24", "--stats"]);
        args.extend(extra);
        let o = rtlab(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        stderr(&o)
    };
    for (extra, why) in [
        (["--sampler", "adaptive"], "the adaptive sampler"),
        (["--mistake", "object-space-t"], "a mistake that changes"),
    ] {
        let err = stats_of(&extra);
        let said = err.contains(&format!("no bundles: {why}"));
        assert!(said && !err.contains(" bundles of "), "{err}");
        assert!(
            err.contains("bundle traversal asked, every ray alone"),
            "{err}"
        );
    }
    // With bundles traced, no such line.
    let err = stats_of(&[]);
    assert!(
        !err.contains("no bundles") && err.contains(" bundles of 16 ("),
        "{err}"
    );
    // JSON says it too, and with which subsample the pass written was traced.
    let json = |extra: &[&str]| -> serde_json::Value {
        let mut args = vec!["render", "scenes/teapot.json", "-o", out.to_str().unwrap()];
        args.extend(["--width", "32", "--height", "24", "--stats", "json"]);
        args.extend(extra);
        let o = rtlab(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        serde_json::from_slice(&o.stdout).unwrap()
    };
    let v = json(&["--sampler", "adaptive"]);
    assert!(v["bundles"].is_null(), "{v}");
    assert!(
        v["bundles_alone_because"]
            .as_str()
            .unwrap()
            .contains("adaptive sampler"),
        "{v}"
    );
    let v = json(&["--traversal", "single"]);
    assert!(v["bundles"].is_null(), "{v}");
    assert_eq!(
        v["bundles_alone_because"],
        "--traversal single sends every ray alone"
    );
    let v = json(&["--passes", "1"]);
    assert!(v["bundles_alone_because"].is_null() && v["bundles"]["count"].as_u64() > Some(0));
    assert_eq!(
        (v["passes"].as_u64(), v["subsample"].as_u64()),
        (Some(1), Some(4)),
        "{v}"
    );
}

/// Bundles find each ray's own closest face, bit for bit, where the order of the tests could
/// matter most: rays from one eye (camera rays, shared-origin face tests), from many points
/// (shadow-like rays) and in every direction (a bundle that walks ray by ray), aimed at a
/// heightfield's corners, where six faces meet, and at the midpoints of its edges, where
/// two do (the tie goes to the lower slot whichever face is tested first), and at random
/// points; full bundles and short ones, at the SIMD level this processor has.
#[test]
fn bundles_find_each_rays_own_face_on_corners_and_edges() {
    let n = 24;
    let mut rng = rtlab::math::Rng::new(&[21, 4]);
    let mut obj = String::new();
    let mut corners = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, z) = (i as f64 / n as f64 - 0.5, j as f64 / n as f64 - 0.5);
            let y = 0.08 * rng.next_f64() - 0.04;
            obj += &format!("v {x} {y} {z}\n");
            corners.push(glam::DVec3::new(x, y, z).as_vec3().as_dvec3());
        }
    }
    let at = |i: usize, j: usize| j * (n + 1) + i + 1;
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            obj += &format!("f {a} {b} {c}\nf {a} {c} {d}\n");
        }
    }
    let obj = write_tmp("heightfield.obj", &obj);
    let scene = serde_json::json!({
        "camera": {"position": [0.3, 1.2, 1.4], "look_at": [0, 0, 0], "fov_y": 40},
        "objects": [{"shape": "mesh", "file": obj.to_str().unwrap()}]
    });
    let scene = write_tmp("heightfield.json", &scene.to_string());
    let scene = rtlab::scene::Scene::load(&scene).unwrap();
    let eye = glam::DVec3::new(0.3, 1.2, 1.4);
    let mut targets = Vec::new();
    for (k, &c) in corners.iter().enumerate() {
        targets.push(c);
        if k + 1 < corners.len() {
            targets.push((c + corners[k + 1]) * 0.5);
        }
    }
    for _ in 0..200 {
        targets.push(glam::DVec3::new(
            rng.next_f64() - 0.5,
            0.0,
            rng.next_f64() - 0.5,
        ));
    }
    let mut compared = [0usize; 2];
    for (way, chunk) in [(0, 16), (1, 16), (2, 16), (0, 11), (1, 7)] {
        for aims in targets.chunks(chunk) {
            let rays: Vec<rtlab::math::Ray> = aims
                .iter()
                .map(|&p| {
                    let mut r = || rng.next_f64() - 0.5;
                    let origin = match way {
                        0 => eye,
                        1 => eye + glam::DVec3::new(r(), r(), r()) * 0.3,
                        _ => p + glam::DVec3::new(r(), r(), r()),
                    };
                    rtlab::math::Ray::new(origin, p - origin)
                })
                .collect();
            let mut cost = rtlab::accel::BundleCost::default();
            let together = scene
                .accel
                .closest_bundle(&scene.objects, &rays, 0.0, &mut cost);
            for (i, ray) in rays.iter().enumerate() {
                let mut no = rtlab::trace::NoRecorder::default();
                let alone = scene
                    .accel
                    .closest(&scene.objects, ray, 0.0, f64::INFINITY, &mut no);
                assert_eq!(
                    format!("{:?}", together[i]),
                    format!("{alone:?}"),
                    "way {way}, ray {i} of {}: {ray:?}",
                    rays.len()
                );
                compared[alone.is_some() as usize] += 1;
            }
        }
    }
    assert!(compared[1] > 2000, "{compared:?}");
}

/// The exact verdict of ray P + t·d (t ≥ 0) on a box, in f64: the oracle the bundle's f32
/// tests must never contradict by culling.
fn exact_enters(r: &rtlab::math::Ray, min: glam::DVec3, max: glam::DVec3) -> bool {
    let (mut near, mut far) = (0.0f64, f64::INFINITY);
    for k in 0..3 {
        let (o, d) = (r.origin[k], r.dir[k]);
        if d == 0.0 {
            if o < min[k] || o > max[k] {
                return false;
            }
            continue;
        }
        let (a, b) = ((min[k] - o) / d, (max[k] - o) / d);
        near = near.max(a.min(b));
        far = far.min(a.max(b));
    }
    near <= far
}

/// `bundle_working` (what `rtlab intersect box --bundle-to` shows) on random bundles, from
/// one point and from several, against random boxes: every lane says what its ray's own
/// slab test says, an interval-test cull happens only when no ray's own test enters, and
/// a ray the exact f64 test finds entering is never culled by either.
#[test]
fn the_interval_test_culls_only_boxes_every_ray_misses() {
    use glam::DVec3;
    use rtlab::accel::bundle_working;
    use rtlab::math::{Ray, Rng};
    let mut rng = Rng::new(&[21, 5]);
    let mut u = |lo: f64, hi: f64| lo + (hi - lo) * rng.next_f64();
    let (mut culled, mut kept, mut alone) = (0, 0, 0);
    for round in 0..4000 {
        let centre = DVec3::new(u(-3.0, 3.0), u(-3.0, 3.0), u(2.0, 8.0));
        let half = DVec3::new(u(0.05, 1.5), u(0.05, 1.5), u(0.05, 1.5));
        let (min, max) = (centre - half, centre + half);
        let n = 2 + (u(0.0, 15.0) as usize);
        let shared = round % 2 == 0;
        let spread = u(0.01, 0.6);
        let aim = DVec3::new(u(-0.5, 0.5), u(-0.5, 0.5), 1.0);
        let rays: Vec<Ray> = (0..n)
            .map(|_| {
                let origin = if shared {
                    DVec3::ZERO
                } else {
                    DVec3::new(u(-0.2, 0.2), u(-0.2, 0.2), u(-0.2, 0.2))
                };
                let d = aim + DVec3::new(u(-spread, spread), u(-spread, spread), 0.0);
                Ray::new(origin, d)
            })
            .collect();
        let w = bundle_working(&rays, &rtlab::shapes::Aabb::new(min, max));
        for (i, (r, v)) in rays.iter().zip(&w.rays).enumerate() {
            if exact_enters(r, min, max) {
                assert!(
                    v.own,
                    "round {round}, ray {i}: its own slab test culls a box it enters"
                );
            }
            if let Some(lane) = v.lane {
                assert_eq!(
                    lane, v.own,
                    "round {round}, ray {i}: the lane and its ray disagree"
                );
            }
        }
        match w.kept {
            Some(false) => {
                culled += 1;
                assert!(
                    w.rays.iter().all(|v| !v.own),
                    "round {round}: culled a box some ray enters"
                );
            }
            Some(true) => kept += 1,
            None => alone += 1,
        }
    }
    // The rounds exercise every verdict, culls above all.
    assert!(
        culled > 500 && kept > 200 && alone > 50,
        "{culled} {kept} {alone}"
    );
}

/// `rtlab intersect box --bundle-to`: the book's two examples, as JSON.
#[test]
fn intersect_box_bundle_to_reports_the_verdicts() {
    let json = |args: &[&str]| -> serde_json::Value {
        let mut all = vec!["intersect", "box", "--format", "json"];
        all.extend_from_slice(args);
        let o = rtlab(&all);
        assert!(o.status.success(), "{}", stderr(&o));
        serde_json::from_slice(&o.stdout).expect("JSON")
    };
    let lanes = |j: &serde_json::Value| -> Vec<Option<bool>> {
        j["rays"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| r["lane_test"].as_bool())
            .collect()
    };
    let culled = json(BOOK_CULLED);
    assert_eq!(culled["interval_test"]["kept"], false);
    assert_eq!(lanes(&culled), vec![Some(false); 6]);
    let z = &culled["interval_test"]["axes"][2];
    assert!((z["entry"].as_f64().unwrap() - 4.0).abs() < 1e-5, "{z}");
    let kept = json(BOOK_KEPT);
    assert_eq!(kept["interval_test"]["kept"], true);
    let entering = lanes(&kept).iter().filter(|l| **l == Some(true)).count();
    assert_eq!(entering, 8);
    // The bundle's bounds, widened: the verdict's own numbers, entry after exit when culled.
    let t = &culled["interval_test"]["together"];
    assert!(
        t["entry"].as_f64().unwrap() > t["exit"].as_f64().unwrap(),
        "{t}"
    );
    let t = &kept["interval_test"]["together"];
    assert!(
        t["entry"].as_f64().unwrap() <= t["exit"].as_f64().unwrap(),
        "{t}"
    );
    // From inside the box every ray is in it from the start, t = 0.
    let inside = json(&[
        "--origin",
        "0,0,0",
        "--dir",
        "0.1,0.05,1",
        "--bundle-to",
        "0.4,0.05,1",
    ]);
    assert_eq!(lanes(&inside), vec![Some(true); 16]);
    assert!(inside["rays"]
        .as_array()
        .unwrap()
        .iter()
        .all(|r| r["t_enter"] == 0.0));
    // No motion along y: that slab bounds nothing, and the others still decide.
    let flat = json(&[
        "--origin",
        "0,0,-5",
        "--dir",
        "0.1,0,1",
        "--bundle-to",
        "0.4,0,1",
    ]);
    assert!(flat["interval_test"]["axes"][1].is_null(), "{flat}");
    assert_eq!(flat["interval_test"]["kept"], true);
    let mixed = json(&[
        "--origin",
        "0,0,-5",
        "--dir",
        "-0.3,0.05,1",
        "--bundle-to",
        "0.1,0.05,1",
    ]);
    assert_eq!(mixed["sign_coherent"], false);
    assert!(mixed["interval_test"]["kept"].is_null());
    assert_eq!(lanes(&mixed), vec![None; 16]);
    // The first and last rays are --dir and --bundle-to exactly, a -0 too, which puts that
    // ray on the other side of x's sign from the rest (as the walk splits it).
    let signed = json(&[
        "--origin",
        "0,0,-5",
        "--dir",
        "-0,0,1",
        "--bundle-to",
        "0.3,0.2,1",
        "--rays",
        "2",
    ]);
    let first = &signed["rays"][0]["direction"][0];
    assert!(first.as_f64().unwrap().is_sign_negative(), "{signed}");
    assert_eq!(signed["sign_coherent"], false, "{signed}");
    // A -0 both ends share is every ray's, the rays between too: one sign, one bundle.
    let shared = json(&[
        "--origin",
        "0,0,-5",
        "--dir",
        "-0,0.1,1",
        "--bundle-to",
        "-0,0.3,1",
    ]);
    for r in shared["rays"].as_array().unwrap() {
        let x = r["direction"][0].as_f64().unwrap();
        assert!(x == 0.0 && x.is_sign_negative(), "{r}");
    }
    assert_eq!(shared["sign_coherent"], true, "{shared}");
}

/// `rtlab beam`: Heckbert and Hanrahan's beam in the plane. The pieces it prints tile the
/// beam, each is seen by the segment a ray through it meets first, a mirror's piece is
/// reflected from the mirrored eye, and `-o` draws it.
#[test]
fn beam_prints_the_pieces_of_a_clipped_beam_and_draws_them() {
    let fig = tmp("beam.png");
    let args = [
        "beam",
        "--from",
        "-0.6,1",
        "--to",
        "1.3,1",
        "--wall",
        "-0.7,1.4,-0.1,1.4",
        "--mirror",
        "0.6,1.7,1.4,2.3",
        "--wall",
        "-1,3.6,2,3.6",
        "--wall",
        "3.2,1,3.2,3.4",
        "-o",
    ];
    let mut all: Vec<&str> = args.to_vec();
    let f = fig.to_str().unwrap();
    all.push(f);
    let o = rtlab(&all);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8(o.stdout).unwrap();
    for line in [
        "(83.3952° wide)",
        "piece 1: 9.1671° wide, wall 3 sees it, from (3.2, 2.4615) to (3.2, 3.4)",
        "piece 2: 11.9356° wide, meets no segment",
        "piece 3: 11.8887° wide, mirror 1 sees it, from (1.4, 2.3) to (0.6, 1.7)",
        "reflected: a beam from (-1.2, 1.6) (the eye mirrored in mirror 1)",
        "piece 3.1: 11.8887° wide, wall 3 sees it",
        "piece 5: 22.4794° wide, wall 1 sees it, from (-0.1, 1.4) to (-0.7, 1.4)",
        "their widths add up to 83.3952°",
    ] {
        assert!(text.contains(line), "missing {line:?} in\n{text}");
    }
    let img = image::open(&fig).unwrap();
    assert_eq!((img.width(), img.height()), (960, 620));
    // The same pieces as JSON: their widths add up to the beam's, and the mirror's piece
    // carries its reflection.
    let mut json: Vec<&str> = args[..args.len() - 1].to_vec();
    json.extend(["--format", "json"]);
    let o = rtlab(&json);
    assert!(o.status.success(), "{}", stderr(&o));
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let pieces = doc["pieces"].as_array().unwrap();
    let sum: f64 = pieces.iter().map(|p| p["degrees"].as_f64().unwrap()).sum();
    assert!((sum - doc["degrees"].as_f64().unwrap()).abs() < 1e-9);
    assert_eq!(pieces[2]["seen_by"]["name"], "mirror 1");
    let apex = &pieces[2]["reflected"]["apex"];
    let near = |v: &serde_json::Value, x: f64| (v.as_f64().unwrap() - x).abs() < 1e-12;
    assert!(near(&apex[0], -1.2) && near(&apex[1], 1.6), "{apex}");
    assert!(pieces[1]["seen_by"].is_null());
    // With no reflection, the mirror's piece is not followed.
    let mut flat: Vec<&str> = args[..args.len() - 1].to_vec();
    flat.extend(["--depth", "0"]);
    let o = rtlab(&flat);
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(
        !text.contains("reflected:") && text.contains("not reflected further"),
        "{text}"
    );
}

#[test]
fn stats_say_how_many_rays_a_subsampled_bundle_held() {
    // 640×480 at --subsample 8: 81×61 traced pixels in 1200 tiles; the last column and row
    // are always traced, so the tiles that hold them have three traced lines, not two.
    let run = |extra: &[&str]| {
        let out = tmp("stats_subsample.png");
        let mut args = vec![
            "render",
            "scenes/teapot.json",
            "--no-shadows",
            "--max-depth",
            "0",
        ];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--stats", "-o", out.to_str().unwrap()]);
        let o = rtlab(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        stderr(&o) + &String::from_utf8_lossy(&o.stdout)
    };
    let full = run(&[]);
    // Every bundle full (640×480 is 4×4 blocks exactly): no average to give.
    assert!(full.contains("in 19200 bundles of 16 ("), "{full}");
    // An image whose edges cut blocks: the average says how full they were.
    let edges = run(&["--width", "50", "--height", "50"]);
    assert!(
        edges.contains("in 169 bundles of 14.8 rays on average (up to 16)"),
        "{edges}"
    );
    let k8 = run(&["--subsample", "8"]);
    assert!(
        k8.contains("in 1200 bundles of 4.1 rays on average (up to 9)"),
        "{k8}"
    );
    let out = tmp("stats_subsample_json.png");
    let o = rtlab(&[
        "render",
        "scenes/teapot.json",
        "--no-shadows",
        "--max-depth",
        "0",
        "--subsample",
        "16",
        "--stats",
        "json",
        "-o",
        out.to_str().unwrap(),
    ]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["bundles"]["rays"], 41 * 31);
    assert_eq!(v["bundles"]["most_rays"], 4);
    assert_eq!(v["bundles"]["count"], 1200);
}
