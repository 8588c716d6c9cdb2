//! Constructive solid geometry and blobs: interval algebra on real shapes, normals where a
//! subtracted surface bounds the result, transforms at every level, blob roots against a
//! brute-force scan, shadows through a hole, and one explained CSG pixel pinned.

use super::common::*;
use glam::DVec3;
use rtlab::cli::explain::{explain, rounded};
use rtlab::math::{Ray, Transform};
use rtlab::shapes::{
    Blob, Csg, CsgChild, CsgOp, Cuboid, NoObserver, Observer, Shape, Span, Sphere,
};
use rtlab::trace::NoRecorder;
use std::sync::Arc;

fn child(name: &str, shape: Shape, transform: Transform) -> CsgChild {
    CsgChild::new(name, shape, transform)
}

fn unit_box() -> Shape {
    Shape::Box(Cuboid {
        min: DVec3::splat(-1.0),
        max: DVec3::ONE,
    })
}

fn ts(spans: &[Span]) -> Vec<(f64, f64)> {
    spans.iter().map(|s| (s.enter.t, s.exit.t)).collect()
}

fn close(a: &[(f64, f64)], b: &[(f64, f64)]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| (x.0 - y.0).abs() < 1e-9 && (x.1 - y.1).abs() < 1e-9)
}

/// Box minus a sphere sitting in its top face: a dent.
fn dented_box() -> Csg {
    Csg {
        op: CsgOp::Difference,
        children: vec![
            child("box", unit_box(), Transform::IDENTITY),
            child(
                "dent",
                Shape::Sphere(Sphere {
                    center: DVec3::new(0.0, 1.0, 0.0),
                    radius: 0.8,
                }),
                Transform::IDENTITY,
            ),
        ],
    }
}

#[test]
fn subtracted_surface_normal_is_flipped_to_face_out_of_the_result() {
    let csg = dented_box();
    let ray = Ray::new(DVec3::new(0.0, 3.0, 0.0), DVec3::NEG_Y);
    // Box: y from 1 to -1 is t in [2, 4]; dent: y from 1.8 to 0.2 is t in [1.2, 2.8].
    let spans = csg.spans(&ray, &mut NoObserver);
    assert!(close(&ts(&spans), &[(2.8, 4.0)]), "{:?}", ts(&spans));
    let hit = csg
        .intersect(&ray, 0.0, f64::INFINITY, &mut NoObserver)
        .unwrap();
    assert_eq!(hit.surface, "sphere");
    // The sphere's own outward normal at its bottom is −y; as the floor of the dent it is +y.
    assert!((hit.normal - DVec3::Y).length() < 1e-12, "{}", hit.normal);
    assert!(
        hit.normal.dot(ray.dir) < 0.0,
        "the entry normal faces the ray"
    );
    // A ray beside the dent enters through the box's own top face, normal unchanged.
    let side = Ray::new(DVec3::new(0.9, 3.0, 0.9), DVec3::NEG_Y);
    let h = csg
        .intersect(&side, 0.0, f64::INFINITY, &mut NoObserver)
        .unwrap();
    assert_eq!((h.surface, h.normal), ("y-max", DVec3::Y));
    // From inside the dent's hollow, looking up: the ray leaves nothing, it is outside.
    let up = Ray::new(DVec3::new(0.0, 0.5, 0.0), DVec3::Y);
    assert!(csg
        .intersect(&up, 0.0, f64::INFINITY, &mut NoObserver)
        .is_none());
}

#[test]
fn touching_nested_and_empty_cases_with_real_shapes() {
    let along_x = Ray::new(DVec3::new(-5.0, 0.25, 0.25), DVec3::X);
    let shifted = |dx: f64| Transform::new(glam::DMat4::from_translation(DVec3::X * dx)).unwrap();
    // Two unit boxes sharing the face x = 1: their union is one piece with no inner wall.
    let touching = Csg {
        op: CsgOp::Union,
        children: vec![
            child("a", unit_box(), Transform::IDENTITY),
            child("b", unit_box(), shifted(2.0)),
        ],
    };
    assert!(close(
        &ts(&touching.spans(&along_x, &mut NoObserver)),
        &[(4.0, 8.0)]
    ));
    // Their intersection is empty (they only touch).
    let meet = Csg {
        op: CsgOp::Intersection,
        ..touching.clone()
    };
    assert!(meet.spans(&along_x, &mut NoObserver).is_empty());
    // A box with a smaller box removed from its middle: two pieces, inner walls flipped.
    let small = Transform::new(glam::DMat4::from_scale(DVec3::splat(0.5))).unwrap();
    let hollow = Csg {
        op: CsgOp::Difference,
        children: vec![
            child("outer", unit_box(), Transform::IDENTITY),
            child("inner", unit_box(), small),
        ],
    };
    let s = hollow.spans(&along_x, &mut NoObserver);
    assert!(close(&ts(&s), &[(4.0, 4.5), (5.5, 6.0)]), "{:?}", ts(&s));
    assert_eq!(s[0].exit.normal, DVec3::X, "inner x-min wall, flipped");
    assert_eq!(s[1].enter.normal, DVec3::NEG_X, "inner x-max wall, flipped");
    // A solid minus itself is empty, whatever the rounding of the shared faces.
    let nothing = Csg {
        op: CsgOp::Difference,
        children: vec![
            child("a", unit_box(), Transform::IDENTITY),
            child("a again", unit_box(), Transform::IDENTITY),
        ],
    };
    assert!(nothing.spans(&along_x, &mut NoObserver).is_empty());
}

#[test]
fn child_transforms_compose_like_object_transforms() {
    // A sphere placed by a child transform inside a node placed by another transform hits
    // exactly where a plain object with the composed transform does.
    let inner = Transform::new(
        glam::DMat4::from_translation(DVec3::new(0.3, -0.2, 0.1))
            * glam::DMat4::from_scale(DVec3::new(1.0, 2.0, 0.5)),
    )
    .unwrap();
    let outer = glam::DMat4::from_axis_angle(DVec3::new(1.0, 1.0, 0.0).normalize(), 0.7);
    let node = Shape::Csg(Arc::new(Csg {
        op: CsgOp::Union,
        children: vec![child(
            "s",
            Shape::Sphere(Sphere {
                center: DVec3::ZERO,
                radius: 1.0,
            }),
            inner,
        )],
    }));
    let node_t = Transform::new(outer).unwrap();
    let plain_t = Transform::new(outer * inner.world_from_object).unwrap();
    let sphere = Shape::Sphere(Sphere {
        center: DVec3::ZERO,
        radius: 1.0,
    });
    let mut hits = 0;
    for i in 0..200 {
        let a = i as f64 * 0.37;
        let origin = DVec3::new(4.0 * a.cos(), 1.5 * (a * 0.7).sin(), 4.0 * a.sin());
        let target = DVec3::new(0.3 * (a * 1.3).sin(), 0.4 * a.cos(), 0.2);
        let ray = Ray::new(origin, target - origin);
        let h1 = node.intersect(
            &node_t.ray_to_object(&ray),
            0.0,
            f64::INFINITY,
            &mut NoObserver,
        );
        let h2 = sphere.intersect(
            &plain_t.ray_to_object(&ray),
            0.0,
            f64::INFINITY,
            &mut NoObserver,
        );
        match (h1, h2) {
            (Some(a), Some(b)) => {
                hits += 1;
                assert!((a.t - b.t).abs() < 1e-9, "ray {i}: t {} vs {}", a.t, b.t);
                let na = node_t.normal_to_world(a.normal);
                let nb = plain_t.normal_to_world(b.normal);
                assert!((na - nb).length() < 1e-9, "ray {i}: normal {na} vs {nb}");
            }
            (None, None) => {}
            other => panic!("ray {i}: {other:?}"),
        }
    }
    assert!(hits > 100, "most rays aim at the sphere ({hits})");
}

/// The sign changes of F along the line found by sampling it very finely.
fn brute_force_roots(blob: &Blob, ray: &Ray, a: f64, b: f64, n: usize) -> Vec<f64> {
    let f = |t: f64| blob.field(ray.at(t)).0 - blob.threshold;
    let h = (b - a) / n as f64;
    let mut out = Vec::new();
    let mut prev = f(a);
    for i in 1..=n {
        let t = a + h * i as f64;
        let cur = f(t);
        if (cur > 0.0) != (prev > 0.0) {
            out.push(t - 0.5 * h);
        }
        prev = cur;
    }
    out
}

#[test]
fn blob_roots_match_a_fine_brute_force_scan() {
    let scene = scene("scenes/blob.json");
    let mut checked = 0;
    for o in &scene.objects {
        let Shape::Blob(blob) = &o.shape else {
            continue;
        };
        let bounds = blob.bounds().unwrap();
        let c = bounds.centroid();
        let size = (bounds.max - bounds.min).length();
        for i in 0..60 {
            let a = i as f64 * 0.61;
            let origin = c + size * DVec3::new(a.cos(), 0.4 * (a * 1.7).sin(), a.sin());
            let aim =
                c + 0.12 * size * DVec3::new((a * 2.3).sin(), (a * 1.1).cos(), (a * 0.9).sin());
            let ray = Ray::new(origin, aim - origin);
            let found = blob.roots(
                &ray,
                f64::NEG_INFINITY,
                f64::INFINITY,
                false,
                &mut NoObserver,
            );
            let (segments, _) = blob.segments(&ray);
            let mut scan = Vec::new();
            for [s0, s1] in segments {
                scan.extend(brute_force_roots(blob, &ray, s0, s1, 200_000));
            }
            let step = 2.0 * size / 200_000.0;
            assert_eq!(
                found.len(),
                scan.len(),
                "{} ray {i}: {found:?} vs scan {scan:?}",
                o.name
            );
            for ((t, _), s) in found.iter().zip(&scan) {
                assert!(
                    (t - s).abs() <= step,
                    "{} ray {i}: root {t} vs scan {s}",
                    o.name
                );
                let f = blob.field(ray.at(*t)).0 - blob.threshold;
                assert!(f.abs() < 1e-9, "F(root) = {f} at t = {t}");
            }
            // Roots alternate entering / leaving, starting with an entry from outside.
            for (k, (_, entering)) in found.iter().enumerate() {
                assert_eq!(*entering, k % 2 == 0, "{} ray {i}", o.name);
            }
            checked += found.len();
        }
    }
    assert!(checked > 100, "the rays found roots ({checked})");
}

#[test]
fn blob_thin_neck_is_not_missed() {
    // Two bumps pulled apart until the neck between them is a small fraction of a radius
    // thick: rays across the neck must still hit it.
    let sc = scene("scenes/blob.json");
    let o = sc.objects.iter().find(|o| o.name == "thin neck").unwrap();
    let Shape::Blob(blob) = &o.shape else {
        panic!()
    };
    // Neck radius along y at x = 0 (by bisection on the field), then rays just inside it.
    let f = |y: f64| blob.field(DVec3::new(0.0, y, 0.0)).0 - blob.threshold;
    assert!(f(0.0) > 0.0, "the neck exists");
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..80 {
        let m = 0.5 * (lo + hi);
        if f(m) > 0.0 {
            lo = m
        } else {
            hi = m
        }
    }
    let neck = lo;
    assert!(neck < 0.2, "a thin neck: radius {neck}");
    for k in 1..10 {
        let z = neck * k as f64 / 10.0;
        let ray = Ray::new(DVec3::new(0.0, -5.0, z), DVec3::Y);
        let hit = blob.intersect(&ray, 0.0, f64::INFINITY, &mut NoObserver);
        assert!(hit.is_some(), "ray at z = {z} (neck radius {neck}) missed");
    }
}

fn hole_scene() -> rtlab::scene::Scene {
    let json = r#"{
      "camera": {"position": [0, 8, 0.001], "look_at": [0, 0, 0], "width": 41, "height": 41, "fov_y": 30},
      "lights": [{"name": "top", "type": "point", "position": [0, 6, 0]}],
      "objects": [
        {"name": "floor", "shape": "plane"},
        {"name": "slab", "shape": "csg", "op": "difference",
         "transform": [{"translate": [0, 2, 0]}],
         "children": [
           {"shape": "box", "min": [-2, -0.2, -2], "max": [2, 0.2, 2]},
           {"name": "hole", "shape": "cylinder", "radius": 0.5, "y_min": -1, "y_max": 1}]}]}"#;
    rtlab::scene::Scene::load(&write_tmp("csg_hole.json", json)).unwrap()
}

#[test]
fn shadow_rays_pass_through_a_csg_hole_and_stop_at_its_solid_part() {
    let scene = hole_scene();
    let light = DVec3::new(0.0, 6.0, 0.0);
    let blocked = |p: DVec3| {
        let ray = Ray::new(p, light - p);
        scene
            .accel
            .occluded(
                &scene.objects[..],
                &ray,
                1e-6,
                1.0 - 1e-6,
                &mut NoRecorder::default(),
            )
            .map(|(i, _)| scene.objects[i].name.clone())
    };
    assert_eq!(blocked(DVec3::new(0.0, 0.0, 0.0)), None, "under the hole");
    assert_eq!(blocked(DVec3::new(0.2, 0.0, -0.1)), None, "under the hole");
    assert_eq!(blocked(DVec3::new(1.0, 0.0, 0.0)).as_deref(), Some("slab"));
    // The same through the tracer: explain the pixel at the image centre, which looks
    // through the hole at the floor; its light is visible.
    let e = explain(&scene, 20, 20);
    let ray = &e.samples[0].ray;
    assert_eq!(ray.hit.as_ref().unwrap().object, "floor");
    let light = &ray.shading.as_ref().unwrap().lights[0];
    assert!(light.visible, "lit through the hole");
    // Near the image edge the floor is under the slab: the camera sees the slab instead,
    // and a floor point there is in its shadow (checked above with occluded()).
    let e = explain(&scene, 20, 5);
    assert_eq!(e.samples[0].ray.hit.as_ref().unwrap().object, "slab");
}

#[test]
fn scene_errors_name_the_csg_child() {
    let cases = [
        (
            r#"{"shape": "csg", "op": "difference", "children": [{"shape": "box"}, {"shape": "sphere", "material": {"diffuse": 1}}]}"#,
            "objects[0].children[1].material",
            "no material of its own",
        ),
        (
            r#"{"shape": "csg", "children": [{"shape": "box"}, {"shape": "cylinder", "capped": false}]}"#,
            "objects[0].children[1]",
            "closed solid",
        ),
        (
            r#"{"shape": "csg", "children": [{"shape": "plane"}]}"#,
            "objects[0].children[0]",
            "closed solid",
        ),
        (
            r#"{"shape": "csg", "op": "diference", "children": [{"shape": "box"}]}"#,
            "objects[0].op",
            "did you mean \"difference\"",
        ),
        (
            r#"{"shape": "csg", "children": []}"#,
            "objects[0].children",
            "at least one child",
        ),
        (
            r#"{"shape": "csg", "children": [{"shape": "box"}], "left": {"shape": "box"}}"#,
            "objects[0].left",
            "not both",
        ),
        (
            r#"{"shape": "csg", "children": [{"shape": "csg", "children": [{"shape": "sphere", "radius": -1}]}]}"#,
            "objects[0].children[0].children[0].radius",
            "greater than 0",
        ),
        (
            r#"{"shape": "blob", "components": [{"center": [0, 0, 0], "strength": -1}]}"#,
            "objects[0].components",
            "positive strength",
        ),
        (
            r#"{"shape": "blob", "falloff": "cubic", "components": [{}]}"#,
            "objects[0].falloff",
            "wyvill or gaussian",
        ),
        (
            r#"{"shape": "blob", "threshold": 0, "components": [{}]}"#,
            "objects[0].threshold",
            "greater than 0",
        ),
    ];
    for (i, (object, at, needle)) in cases.iter().enumerate() {
        let json = format!(r#"{{"camera": {{"position": [0, 0, 5]}}, "objects": [{object}]}}"#);
        let p = write_tmp(&format!("csg_err_{i}.json"), &json);
        let o = rtlab(&["validate", p.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "case {i}");
        let e = stderr(&o);
        assert!(e.contains(at) && e.contains(needle), "case {i}: {e}");
    }
    // The binary form from DESIGN.md (left/right) is accepted.
    let json = r#"{"camera": {"position": [0, 0, 5]}, "objects": [{"shape": "csg", "op": "difference", "left": {"shape": "box"}, "right": {"shape": "sphere", "radius": 1.3}}]}"#;
    let p = write_tmp("csg_left_right.json", json);
    let o = rtlab(&["validate", p.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// Observes only the CSG calls, to check nesting is reported child by child.
#[derive(Default)]
struct Nesting(Vec<String>);
impl Observer for Nesting {
    const ACTIVE: bool = true;
    fn csg_begin(&mut self, op: CsgOp) {
        self.0.push(format!("begin {}", op.name()));
    }
    fn csg_child(&mut self, child: &CsgChild, spans: &[Span]) {
        self.0.push(format!("child {} {}", child.name, spans.len()));
    }
    fn csg_end(&mut self, combined: &[Span]) {
        self.0.push(format!("end {}", combined.len()));
    }
}

#[test]
fn explain_of_a_csg_pixel_reports_every_childs_intervals() {
    let scene = scene("scenes/csg.json");
    let nested = scene.objects.iter().find(|o| o.name == "nested").unwrap();
    // The camera ray of pixel (300, 170) goes through the nested tree.
    let e = explain(&scene, 300, 170);
    let ray = &e.samples[0].ray;
    let test = ray.tests.iter().find(|t| t.object == "nested").unwrap();
    let csg = test.csg.as_ref().expect("a csg test carries its intervals");
    assert_eq!(csg.children.len(), 2);
    assert!(csg.children[0].csg.is_some() && csg.children[1].csg.is_some());
    let hit = ray.hit.as_ref().unwrap();
    assert_eq!(hit.object, "nested");
    assert_eq!(Some(hit.t), csg.combined.first().map(|s| s.enter.t));
    // Same calls in the same order from a bare observer.
    let mut n = Nesting::default();
    let local = nested
        .transform
        .ray_to_object(&Ray::new(ray.origin, ray.direction));
    nested.shape.spans(&local, &mut n);
    assert_eq!(
        n.0,
        [
            "begin difference",
            "begin intersection",
            "child cube 1",
            "child ball 1",
            "end 1",
            "child rounded cube 1",
            "begin union",
            "child y tube 1",
            "child x tube 0",
            "child z tube 1",
            "end 2",
            "child cross 2",
            "end 1"
        ]
    );
}

#[test]
fn snapshot_of_an_explained_csg_pixel() {
    let mut scene = scene("scenes/csg.json");
    scene.render.max_depth = 1;
    let (x, y) = (300, 170);
    let e = explain(&scene, x, y);
    let v = rounded(&serde_json::to_value(&e).unwrap());
    let mut settings = insta::Settings::clone_current();
    settings.set_snapshot_path("snapshots/csg");
    settings.set_prepend_module_to_snapshot(false);
    settings.set_description("a CSG pixel: (rounded cube) − (three tubes); the ray enters the cube, but inside the y tube, so the first boundary of the result is the tube's wall with its normal flipped");
    settings.set_info(
        &serde_json::json!({"scene": "scenes/csg.json", "pixel": [x, y], "max_depth": 1, "spp": 1}),
    );
    settings.bind(|| insta::assert_yaml_snapshot!("csg_nested_tube_wall", v));
}

/// `rtlab intersect csg|blob --spec FILE` reaches the solids' own report (the figures are
/// lesson commands in lessons/05-csg-and-blobs.json, kept current by `lessons check`).
#[test]
fn intersect_routes_csg_and_blob_through_the_cli() {
    let spec = path("specs/dented-column.json");
    let o = rtlab(&[
        "intersect",
        "csg",
        "--spec",
        spec.to_str().unwrap(),
        "--origin",
        "-3,0.8,0.75",
        "--dir",
        "1,0,0",
        "--format",
        "json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["shape"], "csg");
    let no_spec = rtlab(&["intersect", "blob", "--origin", "0,0,0", "--dir", "1,0,0"]);
    assert_eq!(no_spec.status.code(), Some(2));
    assert!(stderr(&no_spec).contains("--spec"), "{}", stderr(&no_spec));
    let foreign = rtlab(&[
        "intersect",
        "sphere",
        "--spec",
        spec.to_str().unwrap(),
        "--origin",
        "0,0,5",
        "--dir",
        "0,0,-1",
    ]);
    assert_eq!(foreign.status.code(), Some(2));
    assert!(
        stderr(&foreign).contains("only csg and blob"),
        "{}",
        stderr(&foreign)
    );
}

#[test]
fn intersect_solids_json_reports_intervals_and_hit() {
    let mut buf = Vec::new();
    rtlab::cli::intersect_solids::run(
        "csg",
        &path("specs/dented-column.json"),
        DVec3::new(-3.0, 0.8, 0.75),
        DVec3::X,
        true,
        None,
        &mut buf,
    )
    .unwrap();
    let v: serde_json::Value = serde_json::from_slice(&buf).unwrap();
    assert_eq!(v["shape"], "csg");
    assert_eq!(v["csg"]["op"], "intersection");
    // Box − dent leaves [2, 2.6536] and [3.3464, 4]; the cylinder [2.0633, 3.9367] trims both.
    let r2 = 1.2f64 * 1.2 - 0.75 * 0.75;
    let dent = (0.85f64 * 0.85 - 0.2 * 0.2 - 0.75 * 0.75).sqrt();
    let combined = v["csg"]["combined"].as_array().unwrap();
    assert_eq!(combined.len(), 2);
    let t = |s: &serde_json::Value| s["t"].as_f64().unwrap();
    assert!((t(&combined[0]["enter"]) - (3.0 - r2.sqrt())).abs() < 1e-12);
    assert!((t(&combined[0]["exit"]) - (3.0 - dent)).abs() < 1e-12);
    assert_eq!(combined[0]["exit"]["surface"], "sphere");
    // The dent's wall bounds the result: its normal there points into the dent (+x at the
    // far side of the first piece), the opposite of the sphere's own outward normal.
    assert!(combined[0]["exit"]["normal"][0].as_f64().unwrap() > 0.0);
    assert_eq!(v["hit"]["surface"], "body");
    assert!((v["hit"]["t"].as_f64().unwrap() - (3.0 - r2.sqrt())).abs() < 1e-12);
    let nested = &v["csg"]["children"][0]["csg"];
    assert_eq!(nested["op"], "difference");

    let mut buf = Vec::new();
    rtlab::cli::intersect_solids::run(
        "blob",
        &path("specs/thin-neck.json"),
        DVec3::new(-3.0, 0.2, 0.0),
        DVec3::X,
        true,
        None,
        &mut buf,
    )
    .unwrap();
    let v: serde_json::Value = serde_json::from_slice(&buf).unwrap();
    let blob = &v["blob"];
    assert!(blob["samples"].as_array().unwrap().len() > 5);
    assert_eq!(
        blob["brackets"].as_array().unwrap().len(),
        1,
        "closest hit: one bracket"
    );
    let steps = blob["steps"].as_array().unwrap();
    let last = steps.last().unwrap();
    assert!((last["field"].as_f64().unwrap() - 0.5).abs() < 1e-12);
    assert_eq!(v["hit"]["t"], blob["roots"][0]["t"]);
    // Errors: wrong kind in the spec, unknown kind, a zero direction.
    let e = rtlab::cli::intersect_solids::run(
        "blob",
        &path("specs/dented-column.json"),
        DVec3::ZERO,
        DVec3::X,
        false,
        None,
        &mut Vec::new(),
    )
    .unwrap_err();
    assert!(e.to_string().contains("describes a csg"), "{e}");
    let e = rtlab::cli::intersect_solids::run(
        "torus",
        &path("specs/thin-neck.json"),
        DVec3::ZERO,
        DVec3::X,
        false,
        None,
        &mut Vec::new(),
    )
    .unwrap_err();
    assert!(e.to_string().contains("csg or blob"), "{e}");
    let e = rtlab::cli::intersect_solids::run(
        "blob",
        &path("specs/thin-neck.json"),
        DVec3::ZERO,
        DVec3::ZERO,
        false,
        None,
        &mut Vec::new(),
    )
    .unwrap_err();
    assert!(e.to_string().contains("non-zero"), "{e}");
}

#[test]
fn closed_meshes_are_csg_solids_and_open_ones_are_refused() {
    // The prism (a closed triangle mesh, circumradius 1, z from −1.5 to 1.5) minus a sphere
    // in its middle: a ray along z enters the end cap, leaves into the hole, re-enters, leaves.
    let meshes = path("scenes/meshes");
    let json = format!(
        r#"{{"camera": {{"position": [0, 0, 5]}}, "objects": [{{"name": "drilled", "shape": "csg", "op": "difference",
           "children": [{{"shape": "mesh", "file": "{}/prism.obj"}}, {{"shape": "sphere", "radius": 0.3}}]}}]}}"#,
        meshes.display()
    );
    let scene = rtlab::scene::Scene::load(&write_tmp("csg_mesh.json", &json)).unwrap();
    let Shape::Csg(csg) = &scene.objects[0].shape else {
        panic!()
    };
    let ray = Ray::new(DVec3::new(0.0, 0.1, -4.0), DVec3::Z);
    let s = csg.spans(&ray, &mut NoObserver);
    let hole = (0.3f64 * 0.3 - 0.1 * 0.1).sqrt();
    assert!(
        close(&ts(&s), &[(2.5, 4.0 - hole), (4.0 + hole, 5.5)]),
        "{:?}",
        ts(&s)
    );
    assert_eq!(s[0].enter.surface, "triangle");
    assert!(s[0].enter.normal.dot(ray.dir) < 0.0 && s[0].exit.normal.dot(ray.dir) > 0.0);
    // Each side face is two triangles split along a diagonal; at y = 0.25, z = 0 the ray
    // crosses both side faces exactly on those diagonals, where two triangles report the
    // same crossing: it still counts once, and the pieces are the prism's minus the hole.
    let along_x = Ray::new(DVec3::new(-3.0, 0.25, 0.0), DVec3::X);
    let s = csg.spans(&along_x, &mut NoObserver);
    // Half-width of the cross-section at y = 0.25; the file's 0.866025 as the mesh holds it
    // (vertex positions are single precision).
    let side = 0.866025f32 as f64 * 0.75 / 1.5;
    let hole = (0.3f64 * 0.3 - 0.25 * 0.25).sqrt();
    assert!(
        close(
            &ts(&s),
            &[(3.0 - side, 3.0 - hole), (3.0 + hole, 3.0 + side)]
        ),
        "{:?}",
        ts(&s)
    );
    // The teapot is not closed: refused as a CSG child.
    let json = format!(
        r#"{{"camera": {{"position": [0, 0, 5]}}, "objects": [{{"shape": "csg",
           "children": [{{"shape": "mesh", "file": "{}/teapot.obj"}}]}}]}}"#,
        meshes.display()
    );
    let err = rtlab::scene::Scene::load(&write_tmp("csg_teapot.json", &json)).unwrap_err();
    assert!(err.to_string().contains("not closed"), "{err}");
}
