//! explain is the same tracer as render: its `encoded` bytes equal the rendered pixel, and
//! every node's colour is exactly the sum of its terms.

use super::common::*;
use rtlab::cli::explain::explain;
use rtlab::sampling::{encode, render};
use rtlab::trace::{RayKind, RayNode};

/// Checks color = ambient + Σ(diffuse + specular) + reflected + transmitted on every node.
fn check_sums(node: &RayNode, at: &str) {
    if let Some(s) = &node.shading {
        let mut sum = s.ambient + s.reflected + s.transmitted;
        for l in &s.lights {
            sum += l.diffuse + l.specular;
        }
        let expect = if node.clamped {
            sum.clamp(glam::DVec3::ZERO, glam::DVec3::ONE)
        } else {
            sum
        };
        assert!(
            (node.color - expect).abs().max_element() < 1e-12,
            "{at}: colour {} but terms add to {expect}",
            node.color
        );
    }
    // The parent's reflected and transmitted terms are its children's colours times their weights.
    if let Some(s) = &node.shading {
        let mut refl = glam::DVec3::ZERO;
        let mut trans = glam::DVec3::ZERO;
        for c in &node.children {
            let w = c.weight.unwrap_or(glam::DVec3::ZERO);
            match c.kind {
                RayKind::Reflection => refl += w * c.color,
                RayKind::Refraction | RayKind::Transmission => trans += w * c.color,
                _ => assert!(c.weight.is_none(), "{at}: a weight on a {:?} ray", c.kind),
            }
        }
        assert!(
            (s.reflected - refl).abs().max_element() < 1e-12,
            "{at}: reflected {} != Σ weight·colour {refl}",
            s.reflected
        );
        assert!(
            (s.transmitted - trans).abs().max_element() < 1e-12,
            "{at}: transmitted {} != Σ weight·colour {trans}",
            s.transmitted
        );
    }
    for (i, c) in node.children.iter().enumerate() {
        check_sums(c, &format!("{at}/{i}"));
    }
}

#[test]
fn explain_encoded_equals_render_on_many_pixels_of_every_scene() {
    for p in all_scenes() {
        let mut scene = rtlab::scene::Scene::load(&p).unwrap();
        scene.camera.update_size(40, 30);
        let img = render(&scene, &scene.render, false, None).image;
        for y in (0..30).step_by(3) {
            for x in (0..40).step_by(3) {
                let e = explain(&scene, x, y);
                let rendered = encode(img.get(x, y), scene.render.encoding);
                assert_eq!(e.encoded, rendered, "{} pixel ({x}, {y})", p.display());
                assert_eq!(
                    e.color,
                    img.get(x, y),
                    "{} pixel ({x}, {y}): linear colour",
                    p.display()
                );
                for s in &e.samples {
                    check_sums(
                        &s.ray,
                        &format!("{} ({x}, {y}) sample {}", p.display(), s.index),
                    );
                }
            }
        }
    }
}

#[test]
fn explain_cli_matches_rendered_png() {
    let out = tmp("explain_cli.png");
    let s = path("scenes/glass.json");
    let args = ["--width", "60", "--height", "60"];
    let o = rtlab(
        &[
            &[
                "render",
                s.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
                "--quiet",
            ],
            &args[..],
        ]
        .concat(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let png = image::open(&out).unwrap().to_rgb8();
    for (x, y) in [(30, 30), (12, 40), (45, 20), (29, 9)] {
        let px = format!("{x},{y}");
        let o = rtlab(
            &[
                &[
                    "explain",
                    s.to_str().unwrap(),
                    "--pixel",
                    &px,
                    "--format",
                    "json",
                ],
                &args[..],
            ]
            .concat(),
        );
        assert!(o.status.success(), "{}", stderr(&o));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        let enc: Vec<u8> = v["encoded"]
            .as_array()
            .unwrap()
            .iter()
            .map(|b| b.as_u64().unwrap() as u8)
            .collect();
        assert_eq!(enc, png.get_pixel(x, y).0.to_vec(), "pixel {px}");
    }
}

#[test]
fn explain_errors_are_clear() {
    let s = path("scenes/spheres.json");
    let s = s.to_str().unwrap();
    for (args, needle) in [
        (vec!["--pixel", "480,10"], "outside the 480×360 image"),
        (vec!["--pixel", "-1,10"], "outside"),
        (vec!["--pixel", "10"], "expected two whole numbers"),
        (vec!["--pixel", "a,b"], "expected two whole numbers"),
        (
            vec!["--pixel", "10,10", "--sample", "1"],
            "sample 1 does not exist",
        ),
        (
            vec!["--pixel", "10,10", "--format", "xml"],
            "unknown format",
        ),
    ] {
        let o = rtlab(&[&["explain", s][..], &args[..]].concat());
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let e = stderr(&o);
        assert!(e.contains(needle), "{args:?}: {e}");
        assert_eq!(e.trim().lines().count(), 1, "one line: {e}");
    }
}

const CASES: &[Case] = &[
    Case { name: "spheres_miss", scene: "scenes/spheres.json", pixel: (240, 20), depth: None, teaches: "a miss: every object is tested, nothing is hit, the background is returned" },
    Case { name: "spheres_diffuse", scene: "scenes/spheres.json", pixel: (70, 170), depth: None, teaches: "a diffuse hit on the red sphere: ambient + f_att·L·kd·Od·(n·l) + specular" },
    Case { name: "spheres_shadow", scene: "scenes/spheres.json", pixel: (174, 210), depth: None, teaches: "a shadowed floor point: the shadow ray to the key light is blocked by the mirror ball" },
    Case { name: "spheres_mirror", scene: "scenes/spheres.json", pixel: (240, 160), depth: None, teaches: "a mirror ball: the reflection ray carries ks·Or times what it sees" },
    Case { name: "mirrors_max_depth", scene: "scenes/mirrors.json", pixel: (10, 150), depth: Some(3), teaches: "a mirror chain bouncing between two mirrors until max_depth stops it" },
    Case { name: "glass_tir", scene: "scenes/glass.json", pixel: (424, 72), depth: Some(4), teaches: "a glass cube: inside, the ray meets a face beyond the critical angle (41.8° for ior 1.5) and is totally internally reflected" },
    Case { name: "glass_centre", scene: "scenes/glass.json", pixel: (185, 190), depth: Some(2), teaches: "refraction through the middle of a glass sphere by Snell's law, entering and leaving" },
    Case { name: "prism_dispersion", scene: "scenes/prism.json", pixel: (320, 160), depth: Some(1), teaches: "dispersion: the refraction splits into one ray per colour channel (r, g, b), each with its own index" },
    Case { name: "shapes_triangle", scene: "scenes/shapes.json", pixel: (330, 160), depth: None, teaches: "a triangle hit: Cramer's rule gives beta, gamma and t; inside because beta, gamma ≥ 0 and beta + gamma ≤ 1" },
    Case { name: "shapes_cylinder_cap", scene: "scenes/shapes.json", pixel: (242, 134), depth: None, teaches: "the capped cylinder's top cap: body roots tossed or farther, the cap root kept" },
    Case { name: "spotlights_edge", scene: "scenes/spotlights.json", pixel: (140, 240), depth: None, teaches: "the soft edge of a spot light: the smoothstep falloff between angle − penumbra and angle" },
    Case { name: "transparency_nonrefractive", scene: "scenes/transparency.json", pixel: (200, 120), depth: None, teaches: "non-refractive transparency: the local terms are scaled by (1 − kt·Ot) and a straight transmission ray adds kt·Ot·I_t" },
    Case { name: "teapot_mesh", scene: "scenes/teapot.json", pixel: (300, 250), depth: None, teaches: "a mesh: the BVH inside the mesh tests a few triangles; the winning triangle's barycentric weights" },
];

#[test]
fn snapshots_of_teaching_pixels() {
    for c in CASES {
        snapshot_explained(
            c,
            scene(c.scene),
            "snapshots/explain",
            c.name,
            |s| serde_json::json!({"scene": c.scene, "pixel": [c.pixel.0, c.pixel.1], "max_depth": s.render.max_depth, "spp": s.render.spp}),
        );
    }
}

/// Every sampler under every filter (and subsampling): explain's pixel is exactly the one
/// render wrote, neighbours' samples included, corner samples shared, adaptive decisions
/// replayed.
#[test]
fn explain_equals_render_for_every_sampler_and_filter() {
    use rtlab::scene::{FilterKind, SamplerKind};
    let mut base = scene("scenes/aliasing.json");
    base.camera.update_size(24, 18);
    let cases: Vec<(SamplerKind, u32, u32)> = vec![
        (SamplerKind::Center, 1, 1),
        (SamplerKind::Grid, 4, 1),
        (SamplerKind::Corners, 5, 1),
        (SamplerKind::Jittered, 4, 1),
        (SamplerKind::Random, 3, 1),
        (SamplerKind::Adaptive, 16, 1),
        (SamplerKind::Center, 1, 3),
        (SamplerKind::Jittered, 4, 2),
    ];
    for (sampler, spp, subsample) in cases {
        for filter in [
            FilterKind::Box,
            FilterKind::Tent,
            FilterKind::Gaussian,
            FilterKind::Mitchell,
        ] {
            let mut scene = base.clone();
            scene.render.sampler = sampler;
            scene.render.spp = spp;
            scene.render.subsample = subsample;
            scene.render.filter = filter;
            scene.render.adaptive_threshold = 0.05;
            let img = render(&scene, &scene.render, false, None).image;
            for (x, y) in [
                (0, 0),
                (23, 17),
                (5, 9),
                (12, 4),
                (17, 13),
                (1, 16),
                (9, 10),
            ] {
                let e = explain(&scene, x, y);
                let at = format!("{sampler:?} spp {spp} /{subsample} {filter:?} pixel ({x}, {y})");
                assert_eq!(e.color, img.get(x, y), "{at}");
                assert_eq!(
                    e.encoded,
                    encode(img.get(x, y), scene.render.encoding),
                    "{at}"
                );
                let total: f64 = e.samples.iter().map(|s| s.weight).sum();
                assert!((total - 1.0).abs() < 1e-9, "{at}: weights add to {total}");
            }
        }
    }
}

/// The heading says which pixels a subsampled render traces in words: "every 3rd", not "3th".
#[test]
fn the_heading_counts_subsampled_pixels_in_english() {
    for (k, word) in [
        (2, "every 2nd pixel"),
        (3, "every 3rd pixel"),
        (4, "every 4th pixel"),
    ] {
        let o = rtlab(&[
            "explain",
            "scenes/spheres.json",
            "--pixel",
            "0,0",
            "--subsample",
            &k.to_string(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let text = String::from_utf8_lossy(&o.stdout);
        assert!(text.contains(word), "{k}: {text}");
    }
}
