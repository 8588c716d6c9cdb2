//! The BVH against the lecture's loop: it may only change which objects are tested, never
//! what a ray hits, so images are identical to the last bit; any-hit agrees with
//! closest-hit on occlusion.

use super::common::*;
use glam::DVec3;
use rtlab::accel::AccelKind;
use rtlab::math::{Ray, Rng};
use rtlab::sampling::render;
use rtlab::scene::Scene;
use rtlab::trace::NoRecorder;

fn with_accel(scene: &Scene, kind: AccelKind) -> Scene {
    let mut s = scene.clone();
    s.render.accel = kind;
    s.rebuild_accel();
    s
}

/// Linear and BVH renders of `scene` (at its size) must give the same linear colours.
fn assert_same_image(scene: &Scene, what: &str) {
    let linear = with_accel(scene, AccelKind::Linear);
    let bvh = with_accel(scene, AccelKind::Bvh);
    let a = render(&linear, &linear.render, false, None).image;
    let b = render(&bvh, &bvh.render, false, None).image;
    let differ = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .position(|(p, q)| p.to_array().map(f64::to_bits) != q.to_array().map(f64::to_bits));
    if let Some(i) = differ {
        let (x, y) = (i as u32 % a.width, i as u32 / a.width);
        panic!(
            "{what}: pixel ({x}, {y}) differs: linear {:?}, bvh {:?}; compare with rtlab explain --pixel {x},{y} --accel linear|bvh",
            a.pixels[i], b.pixels[i]
        );
    }
}

#[test]
fn bvh_and_linear_give_identical_images_on_every_scene() {
    for p in all_scenes() {
        let mut scene = Scene::load(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        scene.camera.update_size(96, 72);
        assert_same_image(&scene, &p.display().to_string());
    }
}

/// Many small objects make a deep top-level tree: spheres, boxes and triangles scattered
/// (some overlapping, some touching), a floor plane kept outside the BVH, shadows and a
/// mirror so secondary and shadow rays cross the tree too.
#[test]
fn bvh_and_linear_agree_on_a_crowded_scene() {
    let mut rng = Rng::new(&[42]);
    let mut objects =
        vec![serde_json::json!({"name": "floor", "shape": "plane", "material": "mirror"})];
    for i in 0..150 {
        let c = [
            rng.next_f64() * 8.0 - 4.0,
            rng.next_f64() * 3.0,
            rng.next_f64() * 8.0 - 6.0,
        ];
        let r = 0.1 + rng.next_f64() * 0.4;
        let o = match i % 3 {
            0 => {
                serde_json::json!({"shape": "sphere", "center": c, "radius": r, "material": "red"})
            }
            1 => {
                serde_json::json!({"shape": "box", "min": [c[0] - r, c[1] - r, c[2] - r], "max": [c[0] + r, c[1] + r, c[2] + r]})
            }
            _ => {
                serde_json::json!({"shape": "triangle", "vertices": [c, [c[0] + r, c[1], c[2]], [c[0], c[1] + r, c[2] + r]], "material": "red"})
            }
        };
        objects.push(o);
    }
    let json = serde_json::json!({
        "camera": {"position": [0, 3, 7], "look_at": [0, 1, -1], "width": 120, "height": 90},
        "lights": [{"type": "point", "position": [3, 6, 4]}, {"type": "directional", "direction": [-1, -2, -1], "color": [0.3, 0.3, 0.3]}],
        "materials": {"red": {"diffuse": [0.8, 0.2, 0.2], "specular": [0.5, 0.5, 0.5], "shininess": 20, "reflective": [0.3, 0.3, 0.3]},
                      "mirror": {"diffuse": [0.3, 0.3, 0.3], "reflective": [0.5, 0.5, 0.5]}},
        "objects": objects
    });
    let p = write_tmp("crowded.json", &json.to_string());
    let scene = Scene::load(&p).unwrap();
    assert!(scene.accel.bvh.nodes.len() > 50, "a deep tree");
    assert_same_image(&scene, "crowded scene");
}

/// Random segments through the Whitted scene (a mesh, spheres, a plane): a shadow ray's
/// any-hit query says "blocked" exactly when the closest-hit query finds something.
#[test]
fn any_hit_agrees_with_closest_hit() {
    let scene = scene("scenes/whitted.json");
    for kind in [AccelKind::Bvh, AccelKind::Linear] {
        let s = with_accel(&scene, kind);
        let mut rng = Rng::new(&[7]);
        let mut blocked = 0;
        for _ in 0..4000 {
            let mut point = || {
                DVec3::new(
                    rng.next_f64() * 4.0 - 2.0,
                    rng.next_f64() * 2.0,
                    rng.next_f64() * 3.0 - 1.5,
                )
            };
            let (from, to) = (point(), point());
            let ray = Ray::new(from, (to - from).normalize());
            let dist = (to - from).length();
            let any = s
                .accel
                .occluded(&s.objects, &ray, 0.0, dist, &mut NoRecorder::default());
            let closest = s
                .accel
                .closest(&s.objects, &ray, 0.0, dist, &mut NoRecorder::default());
            assert_eq!(
                any.is_some(),
                closest.is_some(),
                "{kind:?} {ray:?} to {dist}"
            );
            if let Some((_, h)) = any {
                assert!(h.t >= 0.0 && h.t <= dist);
            }
            blocked += any.is_some() as u32;
        }
        // Both outcomes must occur, or the test proves nothing.
        assert!(
            blocked > 200 && blocked < 3800,
            "{kind:?}: {blocked} of 4000 blocked"
        );
    }
}
