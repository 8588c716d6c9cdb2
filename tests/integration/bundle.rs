//! Bundles of camera rays (`--traversal bundle`) find exactly the hits single rays find:
//! the same bytes on every scene and every sampler, the same AOVs, and the cost AOV and
//! `--stats` count the bundle's work.

use super::common::*;
use rtlab::accel::Traversal;
use rtlab::sampling::aov::{render_aov, Aov};
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

#[test]
fn every_sampler_same_image_single_or_bundle() {
    for file in [
        "scenes/whitted.json",
        "scenes/teapot.json",
        "scenes/triangles.json",
    ] {
        let mut scene = scene(file);
        scene.camera.update_size(37, 29);
        for (kind, spp) in [
            (SamplerKind::Center, 1),
            (SamplerKind::Grid, 4),
            (SamplerKind::Corners, 5),
            (SamplerKind::Jittered, 4),
            (SamplerKind::Random, 3),
            (SamplerKind::Adaptive, 16),
        ] {
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
        let depth = render_aov(&scene, &s, Aov::Depth).image;
        let normal = render_aov(&scene, &s, Aov::Normal).image;
        let cost = render_aov(&scene, &s, Aov::Cost).image;
        images.push((depth, normal, cost));
    }
    assert!(images[0].0 == images[1].0, "depth");
    assert!(images[0].1 == images[1].1, "normal");
    // The cost is a heat map of real work in both, not a blank image.
    for (_, _, cost) in &images {
        let distinct: std::collections::BTreeSet<_> = cost.pixels().map(|p| p.0).collect();
        assert!(distinct.len() > 5);
    }
}

#[test]
fn stats_count_bundles_and_rays_alike() {
    let mut scene = scene("scenes/teapot.json");
    scene.camera.update_size(64, 48);
    let mut s = scene.render.clone();
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
