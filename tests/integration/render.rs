//! The render command end to end: every scene renders, output is deterministic.

use super::common::*;
use rtlab::sampling::render;

#[test]
fn every_scene_renders_small() {
    for p in all_scenes() {
        let mut scene =
            rtlab::scene::Scene::load(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        scene.camera.update_size(48, 36);
        let out = render(&scene, &scene.render, false, None);
        assert!(
            out.first_nan.is_none(),
            "{}: NaN sample {:?}",
            p.display(),
            out.first_nan
        );
        let lit = out
            .image
            .pixels
            .iter()
            .filter(|c| c.max_element() > 0.02)
            .count();
        assert!(
            lit > 48 * 36 / 10,
            "{}: the image is almost black ({lit} lit pixels)",
            p.display()
        );
    }
}

#[test]
fn same_bytes_on_any_thread_count() {
    let out1 = tmp("t1.png");
    let out2 = tmp("t2.png");
    let s = path("scenes/spheres.json");
    for (threads, out) in [("1", &out1), ("2", &out2)] {
        let o = rtlab(&[
            "render",
            s.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--threads",
            threads,
            "--width",
            "96",
            "--height",
            "72",
            "--quiet",
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    assert_eq!(std::fs::read(&out1).unwrap(), std::fs::read(&out2).unwrap());
}
