//! The lighting equation and the camera against hand computations.

use super::common::*;
use glam::{DVec2, DVec3};
use rtlab::trace::{trace_sample, NoRecorder};

#[test]
fn single_light_pixel_matches_hand_computation() {
    // Camera at z = 5 looking at a unit sphere; the centre pixel hits (0, 0, 1) with n = (0, 0, 1).
    let scene = r#"{
      "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov_y": 30, "width": 9, "height": 9},
      "global": {"ka": 0.5, "kd": 0.8, "ks": 0.4, "kt": 1},
      "ambient_light": [1, 1, 1],
      "lights": [{"name": "l", "type": "point", "position": [0, 3, 4], "color": [1, 1, 1], "attenuation": [1, 0.1, 0]}],
      "materials": {"m": {"ambient": [0.2, 0.1, 0], "diffuse": [0.5, 0.5, 0.5], "specular": [1, 1, 1], "shininess": 10}},
      "objects": [{"shape": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"}]
    }"#;
    let p = write_tmp("hand.json", scene);
    let s = rtlab::scene::Scene::load(&p).unwrap();
    let c = trace_sample(
        &s,
        &s.render,
        4,
        4,
        0,
        DVec2::new(4.5, 4.5),
        &mut NoRecorder::default(),
    )
    .color;

    // By hand: l = (0, 3, 3)/√18, n·l = 1/√2; r = 2(n·l)n − l = (0, −1, 1)/√2; v = (0, 0, 1);
    // r·v = 1/√2, (r·v)^10 = 1/32; d = √18, f_att = 1/(1 + 0.1·√18).
    let (nl, rv_n) = (0.5f64.sqrt(), 1.0 / 32.0);
    let f_att = 1.0 / (1.0 + 0.1 * 18f64.sqrt());
    let grey = f_att * (0.8 * 0.5 * nl + 0.4 * rv_n);
    let expect = DVec3::new(0.5 * 0.2 + grey, 0.5 * 0.1 + grey, grey);
    assert!((c - expect).length() < 1e-12, "got {c}, expected {expect}");
}

#[test]
fn camera_ray_follows_the_course_formula() {
    // CS1230 §3: x = 2 tan(θw/2)((j + 0.5)/W − 0.5), y = 2 tan(θh/2)((H − 1 − i + 0.5)/H − 0.5), z = −1.
    let cam = rtlab::camera::Camera::new(
        DVec3::new(1.0, 2.0, 3.0),
        DVec3::new(0.0, 0.5, -1.0),
        DVec3::Y,
        30.0,
        1024,
        768,
    )
    .unwrap();
    let (i, j) = (100.0, 700.0);
    let (ray, g) = cam.generate(DVec2::new(j + 0.5, i + 0.5), None);
    let tan_h = (15f64).to_radians().tan();
    let tan_w = tan_h * 1024.0 / 768.0;
    let x = 2.0 * tan_w * ((j + 0.5) / 1024.0 - 0.5);
    let y = 2.0 * tan_h * ((768.0 - 1.0 - i + 0.5) / 768.0 - 0.5);
    let [u, v, w] = cam.basis;
    let expect = (u * x + v * y - w).normalize();
    assert!((ray.dir - expect).length() < 1e-12);
    assert!((g.ndc.x - x / tan_w).abs() < 1e-12 && (g.ndc.y - y / tan_h).abs() < 1e-12);
    assert_eq!(ray.origin, DVec3::new(1.0, 2.0, 3.0));
}

#[test]
fn no_acne_on_a_lit_sphere() {
    // A sphere lit from the camera's side: every visible point faces the light, so no pixel of
    // the sphere may be darker than its ambient term plus a small diffuse floor (acne would show
    // as black speckles where a shadow ray re-hits its own surface).
    let scene = r#"{
      "camera": {"position": [0, 0, 4], "fov_y": 40, "width": 64, "height": 64},
      "lights": [{"type": "point", "position": [0, 0, 50]}],
      "materials": {"m": {"diffuse": [1, 1, 1], "reflective": [0.3, 0.3, 0.3]}},
      "objects": [{"shape": "sphere", "radius": 1, "material": "m", "transform": [{"scale": [1.3, 0.7, 1]}, {"rotate": {"axis": [1, 1, 0], "degrees": 40}}]}]
    }"#;
    let p = write_tmp("acne.json", scene);
    let s = rtlab::scene::Scene::load(&p).unwrap();
    let img = rtlab::sampling::render(&s, &s.render, false, None).image;
    let mut hits = 0;
    for y in 0..64 {
        for x in 0..64 {
            let c = img.get(x, y);
            if c.x > 0.0 {
                hits += 1;
                assert!(c.x > 0.05, "speckle at ({x}, {y}): {c}");
            }
        }
    }
    assert!(hits > 300);
}

#[test]
fn energy_never_grows_with_depth_for_mirrors() {
    let s = scene("scenes/mirrors.json");
    let mut prev = f64::INFINITY;
    for d in [8, 4, 2, 1, 0] {
        let mut settings = s.render.clone();
        settings.max_depth = d;
        let mut small = s.clone();
        small.camera.update_size(40, 25);
        let sum: f64 = rtlab::sampling::render(&small, &settings, false, None)
            .image
            .pixels
            .iter()
            .map(|c| c.x + c.y + c.z)
            .sum();
        assert!(sum <= prev + 1e-9, "depth {d}: {sum} > {prev}");
        prev = sum;
    }
}
