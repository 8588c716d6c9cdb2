//! Sampling: where samples go, how the filter weighs them, what supersampling buys (PSNR
//! against a reference), where the adaptive sampler spends its samples, soft shadows, and
//! `rtlab compare`.

use super::common::*;
use rtlab::cli::explain::explain;
use rtlab::sampling::{render, RenderOutput};
use rtlab::scene::{FilterKind, SamplerKind, Scene};
use rtlab::viz::compare::rmse_psnr;

/// Every reconstruction filter.
const FILTERS: [FilterKind; 4] = [
    FilterKind::Box,
    FilterKind::Tent,
    FilterKind::Gaussian,
    FilterKind::Mitchell,
];

fn with(scene: &Scene, sampler: SamplerKind, spp: u32) -> Scene {
    let mut s = scene.clone();
    s.render.sampler = sampler;
    s.render.spp = spp;
    s
}

fn run(scene: &Scene) -> RenderOutput {
    render(scene, &scene.render, true, None)
}

fn bytes(scene: &Scene) -> image::RgbImage {
    run(scene).image.to_rgb8(scene.render.encoding)
}

#[test]
fn psnr_improves_from_1_to_4_to_16_spp_on_the_aliasing_scene() {
    let mut base = scene("scenes/aliasing.json");
    base.camera.update_size(100, 75);
    let reference = bytes(&with(&base, SamplerKind::Jittered, 256));
    let mut last = 0.0;
    for (spp, sampler) in [
        (1, SamplerKind::Center),
        (4, SamplerKind::Jittered),
        (16, SamplerKind::Jittered),
    ] {
        let (_, psnr) = rmse_psnr(&bytes(&with(&base, sampler, spp)), &reference);
        let psnr = psnr.expect("differs from the reference");
        eprintln!("{spp} spp {sampler:?}: PSNR {psnr:.2} dB");
        assert!(
            psnr > last + 3.0,
            "{spp} spp: {psnr:.2} dB after {last:.2} dB"
        );
        last = psnr;
    }
    // The regular grid is better than one sample too, and so are corners (5 per pixel, ~2 traced).
    let one = rmse_psnr(&bytes(&with(&base, SamplerKind::Center, 1)), &reference)
        .1
        .unwrap();
    for (sampler, spp) in [(SamplerKind::Grid, 16), (SamplerKind::Corners, 5)] {
        let p = rmse_psnr(&bytes(&with(&base, sampler, spp)), &reference)
            .1
            .unwrap();
        assert!(
            p > one + 2.0,
            "{sampler:?}: {p:.2} dB vs {one:.2} dB at 1 spp"
        );
    }
}

#[test]
fn corners_trace_each_corner_once() {
    let mut base = scene("scenes/aliasing.json");
    base.camera.update_size(30, 20);
    let out = run(&with(&base, SamplerKind::Corners, 5));
    let traced: u32 = out.spp_map.unwrap().iter().sum();
    // One centre per pixel plus one sample per lattice corner: (w + 1)(h + 1).
    assert_eq!(traced, 30 * 20 + 31 * 21);
    assert_eq!(out.stats.unwrap().rays.camera, traced as u64);
    // With the box filter a pixel is the mean of its centre and its four corners.
    let s = with(&base, SamplerKind::Corners, 5);
    let e = explain(&s, 10, 10);
    assert_eq!(e.samples.len(), 5);
    for smp in &e.samples {
        assert!((smp.weight - 0.2).abs() < 1e-12);
    }
    assert_eq!(e.samples.iter().filter(|s| s.pixel != [10, 10]).count(), 3);
}

#[test]
fn wide_filters_reach_across_pixel_borders() {
    let mut base = scene("scenes/aliasing.json");
    base.camera.update_size(20, 15);
    for (filter, pixels) in [
        (FilterKind::Box, 1),
        (FilterKind::Tent, 9),
        (FilterKind::Mitchell, 25),
    ] {
        let mut s = with(&base, SamplerKind::Grid, 4);
        s.render.filter = filter;
        let e = explain(&s, 10, 7);
        let mut owners: Vec<[u32; 2]> = e.samples.iter().map(|s| s.pixel).collect();
        owners.sort();
        owners.dedup();
        assert_eq!(owners.len(), pixels, "{filter:?}");
        // Weights fall with distance from the pixel centre for the tent.
        if filter == FilterKind::Tent {
            for smp in &e.samples {
                let d = (smp.film - glam::DVec2::new(10.5, 7.5)).abs();
                let w = (1.0 - d.x) * (1.0 - d.y);
                let sum: f64 = e
                    .samples
                    .iter()
                    .map(|t| {
                        let d = (t.film - glam::DVec2::new(10.5, 7.5)).abs();
                        (1.0 - d.x) * (1.0 - d.y)
                    })
                    .sum();
                assert!((smp.weight - w / sum).abs() < 1e-12);
            }
        }
    }
}

#[test]
fn subsampling_traces_fewer_samples_and_fills_every_pixel() {
    let mut base = scene("scenes/aliasing.json");
    base.camera.update_size(40, 30);
    let mut s = with(&base, SamplerKind::Center, 1);
    s.render.subsample = 2;
    s.render.filter = FilterKind::Tent;
    let out = run(&s);
    // Even columns and rows, plus the last column and row (39 and 29).
    assert_eq!(out.spp_map.unwrap().iter().sum::<u32>(), 21 * 16);
    // Every pixel got a colour from the traced ones: the checker floor is never black-on-black
    // holes, i.e. pixel (1, 29) (untraced) lies between its traced neighbours.
    let img = out.image;
    let between = |a: f64, b: f64, v: f64| v >= a.min(b) - 1e-12 && v <= a.max(b) + 1e-12;
    for y in (1..29).step_by(2) {
        let v = img.get(1, y).x;
        let (l, r) = (img.get(0, y).x, img.get(2, y).x);
        let (u, d) = (img.get(1, y - 1).x, img.get(1, y + 1).x);
        assert!(
            between(l.min(u).min(r).min(d), l.max(u).max(r).max(d), v),
            "pixel (1, {y})"
        );
    }
}

#[test]
fn adaptive_sampler_spends_its_samples_on_edges() {
    let mut base = scene("scenes/aliasing.json");
    base.camera.update_size(80, 60);
    let out = run(&with(&base, SamplerKind::Adaptive, 16));
    let spp = out.spp_map.unwrap();
    let reference = bytes(&with(&base, SamplerKind::Jittered, 64));
    // Edge pixels: some 4-neighbour differs by more than 0.2 in the reference.
    let (w, h) = (80i64, 60i64);
    let px = |x: i64, y: i64| reference.get_pixel(x as u32, y as u32).0;
    let mut edge = (0u64, 0u64);
    let mut flat = (0u64, 0u64);
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            let c = px(x, y);
            let contrast = [(1, 0), (-1, 0), (0, 1), (0, -1)]
                .iter()
                .map(|(dx, dy)| {
                    let n = px(x + dx, y + dy);
                    (0..3)
                        .map(|i| (c[i] as i32 - n[i] as i32).abs())
                        .max()
                        .unwrap()
                })
                .max()
                .unwrap();
            let n = spp[(y * w + x) as usize] as u64;
            if contrast > 51 {
                edge = (edge.0 + n, edge.1 + 1);
            } else if contrast < 3 {
                flat = (flat.0 + n, flat.1 + 1);
            }
        }
    }
    let (edge_mean, flat_mean) = (edge.0 as f64 / edge.1 as f64, flat.0 as f64 / flat.1 as f64);
    eprintln!("adaptive: {edge_mean:.1} spp on edges, {flat_mean:.1} on flat pixels");
    assert!(
        edge.1 > 50 && flat.1 > 50,
        "both kinds present: {edge:?} {flat:?}"
    );
    // Not every edge pixel refines: an edge can slip between the first four samples (the
    // adaptive sampler's blind spot), but on average edges cost more than twice as much.
    assert!(
        edge_mean > 8.0 && edge_mean > 2.0 * flat_mean,
        "edges get refined: {edge_mean}"
    );
    assert!(flat_mean < 5.0, "flat pixels stay cheap: {flat_mean}");
    assert!(spp
        .iter()
        .all(|&n| n == 4 || n == 20 || (4..=20).contains(&n)));
    // The sky in the top-left corner is flat: the first level only.
    assert_eq!(spp[0], 4);
}

#[test]
fn renders_are_the_same_on_one_and_two_threads() {
    let mut base = scene("scenes/soft_shadows.json");
    base.camera.update_size(48, 36);
    for (sampler, spp, filter) in [
        (SamplerKind::Adaptive, 16, FilterKind::Mitchell),
        (SamplerKind::Jittered, 4, FilterKind::Gaussian),
        (SamplerKind::Corners, 5, FilterKind::Tent),
    ] {
        let mut s = with(&base, sampler, spp);
        s.render.filter = filter;
        let pool = |n| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap()
        };
        let a = pool(1).install(|| render(&s, &s.render, false, None).image);
        let b = pool(2).install(|| render(&s, &s.render, false, None).image);
        assert_eq!(a, b, "{sampler:?}");
    }
}

#[test]
fn soft_shadows_have_penumbrae() {
    let s = scene("scenes/soft_shadows.json");
    // Walk a row across the ball's shadow on the floor: visibility of the area light goes from
    // 1 (lit) through partial values (penumbra) to 0 (umbra).
    let (mut lit, mut penumbra, mut umbra) = (0, 0, 0);
    for x in (20..140).step_by(4) {
        let e = explain(&s, x, 120);
        let ray = &e.samples[0].ray;
        let Some(shading) = &ray.shading else {
            continue;
        };
        if ray.hit.as_ref().map(|h| h.object.as_str()) != Some("floor") {
            continue;
        }
        let v = shading.lights[0].visibility;
        if v >= 1.0 - 1e-12 {
            lit += 1;
        } else if v <= 1e-12 {
            umbra += 1;
        } else {
            penumbra += 1;
        }
    }
    assert!(
        lit > 0 && umbra > 0 && penumbra >= 3,
        "lit {lit}, penumbra {penumbra}, umbra {umbra}"
    );
    // Deterministic: the same pixel twice gives the same shadow rays.
    assert_eq!(explain(&s, 60, 120).color, explain(&s, 60, 120).color);
}

#[test]
fn compare_cli_prints_the_design_json_and_a_deterministic_figure() {
    let a = tmp("compare_a.png");
    let b = tmp("compare_b.png");
    let scene = path("scenes/aliasing.json");
    let args = |o: &std::path::Path, threads: &str| {
        rtlab(&[
            "compare",
            scene.to_str().unwrap(),
            "--spp",
            "1",
            "--spp",
            "4",
            "--reference-spp",
            "16",
            "--width",
            "60",
            "--height",
            "45",
            "--threads",
            threads,
            "--format",
            "json",
            "-o",
            o.to_str().unwrap(),
        ])
    };
    let o = args(&a, "1");
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["reference"]["spp"], 16);
    assert_eq!(v["reference"]["sampler"], "jittered");
    let runs = v["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 2);
    for (r, (spp, sampler)) in runs.iter().zip([(1, "center"), (4, "jittered")]) {
        assert_eq!(r["spp"], spp);
        assert_eq!(r["sampler"], sampler);
        assert_eq!(r["filter"], "box");
        for k in ["label", "rays", "seconds", "rmse", "psnr"] {
            assert!(!r[k].is_null(), "{k}");
        }
        assert_eq!(r["samples"], 60 * 45 * spp);
    }
    assert!(runs[1]["psnr"].as_f64() > runs[0]["psnr"].as_f64());
    let o = args(&b, "2");
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    let img = image::open(&a).unwrap();
    assert!(
        img.width() >= 3 * 180,
        "three columns of 60 px × 3: {}",
        img.width()
    );
}

#[test]
fn compare_errors_are_clear() {
    let s = path("scenes/aliasing.json");
    let s = s.to_str().unwrap();
    for (args, needle) in [
        (
            vec![
                "--spp",
                "1",
                "--spp",
                "4",
                "--sampler",
                "grid",
                "--sampler",
                "random",
                "--sampler",
                "center",
            ],
            "3 samplers for 2",
        ),
        (vec!["--spp", "8", "--sampler", "grid"], "square number"),
        (vec!["--crop", "190,0,20,20"], "not a region inside"),
        (vec!["--reference-spp", "10"], "square number"),
        (vec!["--sampler", "foo"], "unknown sampler"),
        (vec!["--format", "xml"], "unknown format"),
    ] {
        let o = rtlab(&[&["compare", s][..], &args[..]].concat());
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let e = stderr(&o);
        assert!(e.contains(needle), "{args:?}: {e}");
    }
    let o = rtlab(&[
        "render",
        s,
        "--sampler",
        "adaptive",
        "--spp",
        "8",
        "-o",
        "/tmp/x.png",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("power of four"), "{}", stderr(&o));
    let o = rtlab(&["render", s, "--subsample", "0", "-o", "/tmp/x.png"]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn samples_figure_and_explain_sample_checks() {
    let out = tmp("samples.png");
    let o = rtlab(&[
        "samples",
        "--sampler",
        "corners",
        "--sampler",
        "adaptive",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let img = image::open(&out).unwrap();
    assert!(img.width() > 2 * 192 && img.height() > 192);
    // A subsampled pixel that traces nothing has no sample to replay, and says why.
    let s = path("scenes/aliasing.json");
    let o = rtlab(&[
        "explain",
        s.to_str().unwrap(),
        "--pixel",
        "1,1",
        "--subsample",
        "2",
        "--sample",
        "0",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("traces no samples of its own"),
        "{}",
        stderr(&o)
    );
    // An adaptive pixel on the sphere's silhouette refines to 20 samples; the last one can be
    // replayed alone, and there is no 21st.
    let args = |k: &'static str| {
        let s = s.clone();
        rtlab(&[
            "explain",
            s.to_str().unwrap(),
            "--pixel",
            "130,40",
            "--sampler",
            "adaptive",
            "--spp",
            "16",
            "--sample",
            k,
            "--format",
            "json",
        ])
    };
    let o = args("19");
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["samples"].as_array().unwrap().len(), 1);
    assert_eq!(v["samples"][0]["index"], 19);
    let o = args("20");
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("has 20 sample(s)"), "{}", stderr(&o));
}

/// `--aov spp`: the adaptive sampler's map varies (edges get more), a fixed pattern's does not.
#[test]
fn spp_aov_shows_where_the_adaptive_sampler_spent_its_samples() {
    use rtlab::sampling::aov::{render_aov, Aov};
    use rtlab::scene::SamplerKind;
    let mut scene = rtlab::scene::Scene::load(&path("scenes/aliasing.json")).unwrap();
    scene.camera.update_size(40, 30);
    let mut s = scene.render.clone();
    s.spp = 16;
    s.sampler = SamplerKind::Adaptive;
    let adaptive = render_aov(&scene, &s, Aov::Spp)
        .expect("not cancelled")
        .image;
    let distinct = |img: &image::RgbImage| {
        let mut v: Vec<[u8; 3]> = img.pixels().map(|p| p.0).collect();
        v.sort();
        v.dedup();
        v.len()
    };
    assert!(distinct(&adaptive) > 1, "adaptive spp map is flat");
    s.sampler = SamplerKind::Grid;
    assert_eq!(
        distinct(
            &render_aov(&scene, &s, Aov::Spp)
                .expect("not cancelled")
                .image
        ),
        1
    );
}

/// An AOV stops as a render does once its settings' token is cancelled, and gives no image
/// (the server cancels a superseded one this way): cancelled before it starts, every AOV
/// gives none; cancelled midway, the walk over the samples stops within a few samples of
/// each thread, with either traversal.
#[test]
fn a_cancelled_aov_stops_and_gives_no_image() {
    use rtlab::accel::Traversal;
    use rtlab::interrupt::Cancel;
    use rtlab::sampling::aov::{render_aov, trace_kept, Aov};
    use rtlab::scene::SamplerKind;
    use std::sync::atomic::{AtomicUsize, Ordering};
    let scene = rtlab::scene::Scene::load(&path("scenes/blob.json")).unwrap();
    let settings = |cancel: &Cancel| rtlab::scene::RenderSettings {
        cancel: cancel.clone(),
        sampler: SamplerKind::Random,
        spp: 4,
        ..scene.render.clone()
    };
    let mut small = scene.clone();
    small.camera.update_size(8, 6);
    let running = Cancel::new();
    let cancelled = Cancel::new();
    cancelled.cancel();
    for &(aov, name, _) in Aov::ALL {
        assert!(
            render_aov(&small, &settings(&running), aov).is_some(),
            "{name}"
        );
        assert!(
            render_aov(&scene, &settings(&cancelled), aov).is_none(),
            "{name}"
        );
    }
    // Midway: the token is cancelled by the 100th sample kept; of the image's million, the
    // walk keeps at most a bundle's sample index (16) more on each thread after it.
    for traversal in [Traversal::Single, Traversal::Bundle] {
        let cancel = Cancel::new();
        let s = rtlab::scene::RenderSettings {
            traversal,
            ..settings(&cancel)
        };
        let seen = AtomicUsize::new(0);
        let kept = trace_kept(&scene, &s, |_| {
            if seen.fetch_add(1, Ordering::Relaxed) + 1 == 100 {
                cancel.cancel();
            }
        });
        let n: usize = kept.pixels.iter().map(Vec::len).sum();
        let threads = std::thread::available_parallelism()
            .map_or(1, |n| n.get())
            .max(2);
        assert!(
            n >= 100 && n <= 100 + 16 * threads,
            "{traversal:?}: {n} samples kept"
        );
    }
}

/// compare and steps refuse, before allocating, a render that cannot fit in memory (as
/// render does), and write nothing.
#[test]
fn compare_and_steps_refuse_renders_too_large_for_memory() {
    let s = path("scenes/spheres.json");
    let dir = tmp("too-large-steps");
    let _ = std::fs::remove_dir_all(&dir);
    for args in [
        vec![
            "compare",
            s.to_str().unwrap(),
            "--width",
            "4000",
            "--height",
            "4000",
        ],
        vec![
            "steps",
            s.to_str().unwrap(),
            "--width",
            "6000",
            "--height",
            "6000",
            "--spp",
            "64",
            "--sampler",
            "random",
            "-o",
            dir.to_str().unwrap(),
        ],
    ] {
        let o = rtlab(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(stderr(&o).contains("of memory"), "{}", stderr(&o));
    }
    assert!(!dir.exists(), "steps made its folder before refusing");
}

/// A subsampled render reconstructs each pixel from the traced pixels alone (it skips the
/// others, which own no samples). That is exactly the sum over every pixel in the filter's
/// reach, as `explain` takes it: compared bit for bit with `explain`'s colour, for every
/// pixel of small renders under each filter, several subsample factors and samplers (the
/// corner sampler's border samples and reach included).
#[test]
fn subsampled_reconstruction_skips_only_empty_pixels() {
    let mut base = scene("scenes/spheres.json");
    base.camera.update_size(23, 17);
    for filter in FILTERS {
        for (k, sampler, spp) in [
            (2, SamplerKind::Center, 1),
            (3, SamplerKind::Center, 1),
            (4, SamplerKind::Center, 1),
            (3, SamplerKind::Corners, 1),
            (2, SamplerKind::Jittered, 4),
        ] {
            let mut s = with(&base, sampler, spp);
            s.render.subsample = k;
            s.render.filter = filter;
            let img = run(&s).image;
            for y in 0..17 {
                for x in 0..23 {
                    let e = explain(&s, x, y);
                    assert_eq!(
                        e.color.to_array(),
                        img.get(x, y).to_array(),
                        "{filter:?}, {sampler:?}, subsample {k}, pixel ({x}, {y})"
                    );
                }
            }
        }
    }
}

/// The centre sampler keeps only each pixel's colour for the filter (its film position is the
/// pixel's centre); the grid sampler at 1 sample per pixel traces the same point and keeps
/// the whole sample record. Every filter, both traversals: the same image to the last bit.
#[test]
fn the_centre_samplers_kept_colours_reconstruct_as_full_samples() {
    for file in ["scenes/whitted.json", "scenes/teapot.json"] {
        let mut base = scene(file);
        base.camera.update_size(45, 34);
        for filter in FILTERS {
            for traversal in [
                rtlab::accel::Traversal::Single,
                rtlab::accel::Traversal::Bundle,
            ] {
                let mut centre = with(&base, SamplerKind::Center, 1);
                centre.render.filter = filter;
                centre.render.traversal = traversal;
                let mut grid = centre.clone();
                grid.render.sampler = SamplerKind::Grid;
                let (a, b) = (run(&centre), run(&grid));
                assert_eq!(a.image, b.image, "{file} {filter:?} {traversal:?}");
                assert_eq!(a.spp_map, b.spp_map, "{file} {filter:?} {traversal:?}");
            }
        }
    }
}
