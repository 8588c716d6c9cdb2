//! `rtlab render` itself on the harness's view: its trace time, and its parts.

use crate::camera::{add, HarnessCamera};
use crate::passes::{each_block, per_tile};
use crate::{H, W};
use rtlab::math::Ray;
use rtlab::scene::Scene;
use std::path::Path;
use std::time::Instant;

/// The harness's view as an rtlab scene (its eye, centre and 40° vertical field of view,
/// 1280×720, the mesh white diffuse, no lights): what `rtlab render` itself traces.
pub fn render_view(obj: &Path, cam: &HarnessCamera, dir: &Path) -> Scene {
    let file = dir.join(format!(
        "{}-view.json",
        obj.file_stem().unwrap().to_string_lossy()
    ));
    let at = cam.eye.map(|x| x as f64);
    let look = add(cam.eye, cam.fwd).map(|x| x as f64);
    let json = serde_json::json!({
        "camera": {"position": at, "look_at": look, "up": [0, 1, 0], "fov_y": 40,
                   "width": W, "height": H},
        "objects": [{"shape": "mesh", "file": obj.to_string_lossy()}]
    });
    std::fs::write(&file, json.to_string()).expect("writable temp folder");
    Scene::load(&file).expect("the view loads")
}

/// Camera rays per second of `rtlab render`'s own trace time on the view.
pub fn render_mrays(
    view: &Scene,
    traversal: rtlab::accel::Traversal,
    pool: &rayon::ThreadPool,
) -> f64 {
    render_mrays_counting(view, traversal, false, pool)
}

/// [`render_mrays`], with `count`: counting rays, tests and nodes as `render --stats` does.
pub fn render_mrays_counting(
    view: &Scene,
    traversal: rtlab::accel::Traversal,
    count: bool,
    pool: &rayon::ThreadPool,
) -> f64 {
    let mut settings = view.render.clone();
    settings.traversal = traversal;
    let out = pool.install(|| rtlab::sampling::render(view, &settings, count, None));
    (W * H) as f64 / out.trace_seconds / 1e6
}

/// The bundled render's trace taken apart on its own view, through the functions `render`
/// itself calls, block by block of its tiles: seconds to make every camera ray
/// (`rtlab::trace::camera_rays`, which `render` uses), and to make them and walk them to
/// their hits (`Accel::closest_bundle_into`). What the render adds on top (shading each hit
/// and each miss, keeping its colour for the filter, the tile's plan) is its trace time
/// minus the second.
pub fn render_parts(view: &Scene, pool: &rayon::ThreadPool, walk: bool) -> f64 {
    use rtlab::accel::{BundleCost, BUNDLE};
    use rtlab::trace::{camera_rays, CameraRay};
    let settings = &view.render;
    let start = Instant::now();
    let traced = per_tile(pool, |tile| {
        let mut cams: [CameraRay; BUNDLE] = std::array::from_fn(|_| CameraRay {
            ray: Ray::new(glam::DVec3::ZERO, glam::DVec3::Z),
            film: glam::DVec2::ZERO,
            lens: None,
            rng: rtlab::math::Rng::keyed([0; 4]),
        });
        let mut rays = [Ray::new(glam::DVec3::ZERO, glam::DVec3::Z); BUNDLE];
        let mut hits = [None; BUNDLE];
        let mut samples = arrayvec::ArrayVec::<_, BUNDLE>::new();
        let mut found = 0u32;
        each_block(tile, |pixels| {
            samples.clear();
            for &(x, y, _) in pixels {
                let centre = glam::DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
                samples.push((x as u32, y as u32, 0, centre));
            }
            camera_rays(view, settings, &samples, &mut cams);
            let n = pixels.len();
            for (ray, cam) in rays.iter_mut().zip(&cams[..n]) {
                *ray = cam.ray;
            }
            if walk {
                let mut cost = BundleCost::default();
                view.accel.closest_bundle_into(
                    &view.objects,
                    &rays[..n],
                    0.0,
                    &mut cost,
                    &mut hits,
                );
                found += hits[..n].iter().filter(|h| h.is_some()).count() as u32;
            } else {
                found += std::hint::black_box(&rays[..n]).len() as u32;
            }
        });
        found
    });
    let seconds = start.elapsed().as_secs_f64();
    std::hint::black_box(traced);
    seconds
}
