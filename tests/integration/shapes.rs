//! Each intersection routine against hand computations.

use glam::{DMat4, DVec3};
use rtlab::math::{Ray, Transform};
use rtlab::shapes::*;

fn ray(o: [f64; 3], d: [f64; 3]) -> Ray {
    Ray::new(DVec3::from(o), DVec3::from(d))
}

fn run(shape: &Shape, r: &Ray) -> (Option<LocalHit>, Working) {
    let mut w = Working::default();
    let hit = shape.intersect(r, 0.0, f64::INFINITY, &mut w);
    w.conclude(hit.map(|h| h.t), f64::INFINITY);
    (hit, w)
}

fn close(a: DVec3, b: [f64; 3]) -> bool {
    (a - DVec3::from(b)).length() < 1e-9
}

#[test]
fn lecture_circle_as_a_sphere_slice_is_tangent_at_t3() {
    let s = Shape::Sphere(Sphere {
        center: DVec3::ZERO,
        radius: 1.0,
    });
    let (hit, w) = run(&s, &ray([-3.0, 1.0, 0.0], [0.8, -0.6, 0.0]));
    let q = w.quadratics[0].1;
    assert_eq!(q.roots, Roots::Tangent, "D = {}", q.discriminant);
    assert!(q.discriminant.abs() < 1e-13);
    let h = hit.expect("a tangent ray touches the circle");
    assert!((h.t - 3.0).abs() < 1e-9);
    assert!(close(h.point, [-0.6, -0.8, 0.0]));
    assert_eq!(w.candidates.len(), 1, "a tangent ray gives one candidate");
}

#[test]
fn sphere_two_roots_and_inside() {
    let s = Shape::Sphere(Sphere {
        center: DVec3::ZERO,
        radius: 1.0,
    });
    let (hit, w) = run(&s, &ray([0.0, 0.0, -5.0], [0.0, 0.0, 1.0]));
    let q = w.quadratics[0].1;
    assert_eq!((q.a, q.b, q.c, q.discriminant), (1.0, -10.0, 24.0, 4.0));
    let h = hit.unwrap();
    assert_eq!(h.t, 4.0);
    assert!(close(h.normal, [0.0, 0.0, -1.0]));
    assert!(w.candidates[1].note.starts_with("tossed"));
    // From the centre: t = -1 is behind, t = 1 is the hit.
    let (hit, w) = run(&s, &ray([0.0, 0.0, 0.0], [0.0, 1.0, 0.0]));
    assert_eq!(hit.unwrap().t, 1.0);
    assert!(!w.candidates[0].in_front && w.candidates[0].note.contains("behind"));
    // A miss: D < 0.
    let (hit, w) = run(&s, &ray([0.0, 2.0, -5.0], [0.0, 0.0, 1.0]));
    assert!(hit.is_none() && w.quadratics[0].1.roots == Roots::None && w.candidates.is_empty());
}

#[test]
fn cylinder_case_by_case() {
    let c = Shape::Cylinder(Cylinder {
        radius: 1.0,
        y_min: -1.0,
        y_max: 1.0,
        capped: true,
    });
    // P(t) = (0, 3 - t, -2 + t): body roots t = 1 (y = 2, tossed) and t = 3 (y = 0, on shape);
    // top cap t = 2 (x² + z² = 0, inside: kept), bottom cap t = 4 (x² + z² = 4: tossed).
    let (hit, w) = run(&c, &ray([0.0, 3.0, -2.0], [0.0, -1.0, 1.0]));
    let h = hit.unwrap();
    assert_eq!((h.t, h.surface), (2.0, "top-cap"));
    assert!(close(h.normal, [0.0, 1.0, 0.0]));
    let ts: Vec<(f64, &str, bool)> = w
        .candidates
        .iter()
        .map(|c| (c.t, c.surface, c.on_shape))
        .collect();
    assert_eq!(
        ts,
        vec![
            (1.0, "body", false),
            (2.0, "top-cap", true),
            (3.0, "body", true),
            (4.0, "bottom-cap", false)
        ]
    );
    assert!(w.candidates[0].note.contains("y = 2"));
    // Straight down the axis: the body equation degenerates (a = 0, b = 0): only the caps.
    let (hit, w) = run(&c, &ray([0.5, 5.0, 0.0], [0.0, -1.0, 0.0]));
    assert_eq!(w.quadratics[0].1.roots, Roots::None);
    assert_eq!(hit.unwrap().t, 4.0);
    // Open cylinder: no caps tried, the ray goes in through the open top and hits the inside wall.
    let open = Shape::Cylinder(Cylinder {
        radius: 1.0,
        y_min: -1.0,
        y_max: 1.0,
        capped: false,
    });
    let (hit, _) = run(&open, &ray([0.0, 3.0, -2.0], [0.0, -1.0, 1.0]));
    assert_eq!(hit.unwrap().t, 3.0);
}

#[test]
fn cylinder_rim_counts_as_on_shape() {
    // P(t) = (0, 4 - t, -4 + t) meets the top rim (y = 1, z = -1) at t = 3 exactly.
    let c = Shape::Cylinder(Cylinder {
        radius: 1.0,
        y_min: -1.0,
        y_max: 1.0,
        capped: true,
    });
    let (hit, _) = run(&c, &ray([0.0, 4.0, -4.0], [0.0, -1.0, 1.0]));
    assert!((hit.unwrap().t - 3.0).abs() < 1e-12);
}

#[test]
fn cone_body_and_normal() {
    let c = Shape::Cone(Cone {
        slope: 1.0,
        y_min: -1.0,
        y_max: 1.0,
        capped: true,
    });
    let (hit, w) = run(&c, &ray([0.0, 0.5, -5.0], [0.0, 0.0, 1.0]));
    let h = hit.unwrap();
    assert!((h.t - 4.5).abs() < 1e-12);
    // Gradient of x² + z² − y² at (0, 0.5, −0.5): (0, −1, −1)/√2.
    assert!(close(
        h.normal,
        [
            0.0,
            -std::f64::consts::FRAC_1_SQRT_2,
            -std::f64::consts::FRAC_1_SQRT_2
        ]
    ));
    assert_eq!(w.candidates.len(), 2);
}

#[test]
fn box_slabs_and_plane() {
    let b = Shape::Box(Cuboid {
        min: DVec3::splat(-1.0),
        max: DVec3::ONE,
    });
    let (hit, w) = run(&b, &ray([-5.0, 0.5, 0.2], [1.0, 0.0, 0.0]));
    let h = hit.unwrap();
    assert_eq!((h.t, h.surface), (4.0, "x-min"));
    assert!(close(h.normal, [-1.0, 0.0, 0.0]));
    assert_eq!(
        w.candidates.len(),
        2,
        "parallel to y and z slabs: only the x planes give roots"
    );
    // A ray beside the box hits the x planes outside the face.
    let (hit, w) = run(&b, &ray([-5.0, 3.0, 0.0], [1.0, 0.0, 0.0]));
    assert!(hit.is_none() && w.candidates.iter().all(|c| !c.on_shape));

    let p = Shape::Plane(Plane {
        point: DVec3::ZERO,
        normal: DVec3::Y,
    });
    assert_eq!(
        run(&p, &ray([0.0, 5.0, 0.0], [0.0, -1.0, 0.0]))
            .0
            .unwrap()
            .t,
        5.0
    );
    assert!(
        run(&p, &ray([0.0, 5.0, 0.0], [1.0, 0.0, 0.0])).0.is_none(),
        "parallel ray"
    );
    assert!(
        run(&p, &ray([0.0, 5.0, 0.0], [0.0, 1.0, 0.0])).0.is_none(),
        "plane behind the origin"
    );
}

#[test]
fn triangle_outside_still_reports_weights() {
    let t = Shape::Triangle(Triangle::new([DVec3::ZERO, DVec3::X, DVec3::Y]));
    let (hit, w) = run(&t, &ray([0.8, 0.8, 1.0], [0.0, 0.0, -1.0]));
    assert!(hit.is_none());
    let b = w.barycentric.unwrap();
    assert!(
        (b.beta - 0.8).abs() < 1e-12
            && (b.gamma - 0.8).abs() < 1e-12
            && (b.alpha + 0.6).abs() < 1e-12
    );
    assert!(!w.candidates[0].on_shape && w.candidates[0].note.contains("beta + gamma"));
    let (hit, _) = run(&t, &ray([0.2, 0.3, 1.0], [0.0, 0.0, -1.0]));
    let h = hit.unwrap();
    assert_eq!(h.barycentric.map(|b| (b[1] * 1e9).round() / 1e9), Some(0.2));
}

#[test]
fn object_space_with_transform_shares_t_and_normals_use_inverse_transpose() {
    // A unit sphere stretched to an ellipsoid with semi-axes (2, 1, 1), then moved to x = 3.
    let m = DMat4::from_translation(DVec3::new(3.0, 0.0, 0.0))
        * DMat4::from_scale(DVec3::new(2.0, 1.0, 1.0));
    let tr = Transform::new(m).unwrap();
    let s = Shape::Sphere(Sphere {
        center: DVec3::ZERO,
        radius: 1.0,
    });
    let world = ray([-5.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
    let local = tr.ray_to_object(&world);
    let h = s
        .intersect(&local, 0.0, f64::INFINITY, &mut NoObserver)
        .unwrap();
    assert!(
        (h.t - 6.0).abs() < 1e-12,
        "world hit at x = 1 is 6 units from x = -5"
    );
    assert!((world.at(h.t) - DVec3::new(1.0, 0.0, 0.0)).length() < 1e-12);
    // At the object-space point (1, 1, 0)/√2 the world normal is (1/2, 1, 0) normalised.
    let n = tr.normal_to_world(DVec3::new(1.0, 1.0, 0.0).normalize());
    assert!((n - DVec3::new(0.5, 1.0, 0.0).normalize()).length() < 1e-12);
}
