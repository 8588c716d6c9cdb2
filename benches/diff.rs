//! How long a student waits for `rtlab diff` on a 1024×768 course scene with the whole
//! mistake catalogue searched (every mistake on each region's pixels, then pairs).
//!
//! For each of a few mistakes: the expected image and the "student's" image are rendered
//! first (not timed; `diff` renders the expected image once, timed separately below), then
//! `rtlab::diff::diff` is timed once. Prints every case, the median and the worst.
//! `cargo bench --bench diff` (a short run: one diff per case).

use rtlab::diff::{self, Options};
use rtlab::mistakes::{Mistake, Mistakes};
use rtlab::scene::Scene;
use std::time::Instant;

fn main() {
    let cases: &[(&str, &[Mistake])] = &[
        ("tests/cs1230/scenes/lights.json", &[Mistake::ShadowAcne]),
        ("tests/cs1230/scenes/lights.json", &[Mistake::NoAttenuation]),
        ("tests/cs1230/scenes/lights.json", &[Mistake::BlinnPhong]),
        (
            "tests/cs1230/scenes/lights.json",
            &[Mistake::SpotFullAngle, Mistake::ReflectSign],
        ),
        (
            "tests/cs1230/scenes/mirrors.json",
            &[Mistake::ReflectionWithoutKs],
        ),
        ("tests/cs1230/scenes/mirrors.json", &[Mistake::PixelCorner]),
    ];
    println!(
        "{:<40} {:>10} {:>9} {:>8} {:>10}  best mistake",
        "scene, mistake", "render s", "diff s", "regions", "differ %"
    );
    let mut times = Vec::new();
    for (path, ms) in cases {
        let mut scene = Scene::load(std::path::Path::new(path)).expect("scene loads");
        scene.camera.update_size(1024, 768);
        let t0 = Instant::now();
        let expected = rtlab::sampling::render(&scene, &scene.render, false, None)
            .image
            .to_rgb8_for(&scene.render);
        let render = t0.elapsed().as_secs_f64();
        let mut s = scene.render.clone();
        s.mistakes = ms.iter().copied().collect::<Mistakes>();
        let yours = rtlab::sampling::render(&scene, &s, false, None)
            .image
            .to_rgb8_for(&s);
        let t0 = Instant::now();
        let rep = diff::diff(&scene, &expected, &yours, &Options::default()).expect("same size");
        let t = t0.elapsed().as_secs_f64();
        times.push(t + render);
        let best = diff::report::diagnosis(&scene, &rep)
            .first()
            .map(|d| d.0.join(" + "))
            .unwrap_or_else(|| "-".into());
        let name = format!(
            "{} {}",
            path.rsplit('/').next().unwrap(),
            s.mistakes.names()
        );
        println!(
            "{name:<40} {render:>10.2} {t:>9.2} {:>8} {:>10.2}  {best}",
            rep.regions_found, rep.metrics.diff_percent
        );
    }
    times.sort_by(f64::total_cmp);
    println!(
        "render + diff (what `rtlab diff SCENE YOURS.png` costs): median {:.2} s, worst {:.2} s over {} cases, {} threads",
        times[times.len() / 2],
        times[times.len() - 1],
        times.len(),
        rayon::current_num_threads()
    );
}
