//! Does observing the tracer cost anything when nobody watches?
//!
//! Renders the same scenes with the zero-sized `NoRecorder` (what `render` uses) and with the
//! `Counter` recorder (what `--stats` uses), median of several runs each, interleaved so both
//! see the same machine load. `cargo bench --bench recorder`.

use rtlab::scene::Scene;
use rtlab::trace::{trace_sample, Counter, NoRecorder, Recorder};
use std::time::Instant;

fn trace_all<R: Recorder + Default>(scene: &Scene) -> (f64, f64) {
    let s = &scene.render;
    let start = Instant::now();
    let mut sum = 0.0;
    for y in 0..scene.camera.height {
        for x in 0..scene.camera.width {
            let mut rec = R::default();
            let film = glam::DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
            sum += trace_sample(scene, s, x, y, 0, film, &mut rec).color.x;
        }
    }
    (start.elapsed().as_secs_f64(), sum)
}

#[path = "shared/median.rs"]
mod shared_median;
use shared_median::median;

fn main() {
    assert_eq!(
        std::mem::size_of::<NoRecorder>(),
        0,
        "the render recorder must be zero-sized"
    );
    println!(
        "{:<22} {:>14} {:>14} {:>8}",
        "scene (single thread)", "NoRecorder ms", "Counter ms", "ratio"
    );
    for name in ["spheres", "glass", "teapot", "mirrors"] {
        let mut scene =
            Scene::load(std::path::Path::new(&format!("scenes/{name}.json"))).expect("scene loads");
        scene.camera.update_size(320, 240);
        let (mut a, mut b) = (Vec::new(), Vec::new());
        let mut check = (0.0, 0.0);
        for _ in 0..7 {
            let (t, s) = trace_all::<NoRecorder>(&scene);
            a.push(t);
            check.0 = s;
            let (t, s) = trace_all::<Counter>(&scene);
            b.push(t);
            check.1 = s;
        }
        assert_eq!(check.0, check.1, "both recorders see the same image");
        let (ma, mb) = (median(a) * 1e3, median(b) * 1e3);
        println!("{name:<22} {ma:>14.2} {mb:>14.2} {:>8.3}", mb / ma);
    }
    println!("ratio = Counter / NoRecorder; the no-op recorder is zero-sized and its calls are inlined away.");
}
