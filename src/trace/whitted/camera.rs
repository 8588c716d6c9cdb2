//! A sample's camera ray: made from (seed, pixel, sample index), then traced.

use super::Tracer;
use crate::accel::isa::{self, Kernel, Wide};
use crate::accel::BUNDLE;
use crate::camera::RayGeneration;
use crate::math::lanes::{Lanes, V2};
use crate::math::{Ray, Rng};
use crate::scene::{RenderSettings, Scene};
use crate::trace::{RayKind, Recorder};
use glam::{DVec2, DVec3};

/// One traced sample: where it was on the film and what colour it brought back. (How its
/// camera ray was generated is [`CameraRay::generation`].)
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampleResult {
    pub film: DVec2,
    pub color: DVec3,
    /// Rays the sample traced, of every kind.
    pub rays: u64,
    /// The ray budget (`settings.max_rays`) cut the tree: some node ends with
    /// [`crate::trace::End::RayBudget`] (or the render was cancelled).
    pub cut: bool,
}

/// Traces sample `index` at film position `film` of pixel (`px`, `py`). The sample's random
/// numbers (lens, area lights) come from (seed, pixel, sample index) alone.
pub fn trace_sample<R: Recorder>(
    scene: &Scene,
    settings: &RenderSettings,
    px: u32,
    py: u32,
    index: u32,
    film: DVec2,
    rec: &mut R,
) -> SampleResult {
    let mut camera = camera_ray(scene, settings, px, py, index, film);
    trace_camera(scene, settings, &mut camera, None, rec)
}

/// A sample's camera ray, made but not yet traced: the ray, where it was on the film and the
/// lens sample it was made from, and the sample's random stream after the lens sample. It is
/// kept small (a block of them is made, walked and traced per bundle); how it was generated,
/// stage by stage, is [`CameraRay::generation`].
#[derive(Debug, Clone)]
pub struct CameraRay {
    pub ray: Ray,
    pub film: DVec2,
    pub lens: Option<DVec2>,
    pub rng: Rng,
}

impl CameraRay {
    /// Every stage of this ray's generation (ndc, film point, world point, …), for `explain`:
    /// the camera's one [`crate::camera::Camera::generate_as`] run again on the same film
    /// position and lens sample, so the ray it ends in is this one.
    pub fn generation(&self, scene: &Scene, settings: &RenderSettings) -> RayGeneration {
        scene
            .camera
            .generate_as(self.film, self.lens, settings.mistakes)
            .1
    }
}

/// A camera ray's closest hit found in a bundle ([`crate::sampling::bundles`]): exactly what
/// `Accel::closest` returns for it (borrowed from the bundle's results, not copied), with
/// its share of the work (intersection tests, nodes it was tested at).
#[derive(Debug, Clone, Copy)]
pub struct Found<'h> {
    pub hit: Option<&'h (usize, crate::shapes::LocalHit)>,
    pub tests: u32,
    pub nodes: u32,
}

/// The camera ray of sample `index` at `film` of pixel (`px`, `py`); its random numbers (lens,
/// then area lights) come from (seed, pixel, sample index) alone. (Inlined: made where the
/// caller keeps it, not returned and copied.)
#[inline]
pub fn camera_ray(
    scene: &Scene,
    settings: &RenderSettings,
    px: u32,
    py: u32,
    index: u32,
    film: DVec2,
) -> CameraRay {
    let (lens, rng) = lens_and_stream(scene, settings, px, py, index);
    let ray = scene.camera.ray_as(film, lens, settings.mistakes);
    CameraRay {
        ray,
        film,
        lens,
        rng,
    }
}

/// Sample `index` of pixel (`px`, `py`)'s lens sample (`None` for a pinhole) and its random
/// stream after it, for the area lights: from (seed, pixel, sample index) alone.
#[inline(always)]
fn lens_and_stream(
    scene: &Scene,
    settings: &RenderSettings,
    px: u32,
    py: u32,
    index: u32,
) -> (Option<DVec2>, Rng) {
    let mut rng = Rng::keyed([settings.seed, px as u64, py as u64, index as u64]);
    let lens = scene.camera.lens_sample(settings.depth_of_field, &mut rng);
    (lens, rng)
}

/// The camera rays of up to [`BUNDLE`] samples, `samples[i]` = (pixel x, y, sample index,
/// film position), written to `out[i]`: each exactly what [`camera_ray`] makes of it (its
/// random stream and lens sample drawn the same way), the rays generated side by side
/// ([`crate::camera::Camera::rays_as`]) rather than one after another, compiled for the
/// widest SIMD the processor has ([`isa::run`]: the same IEEE operations lane by lane, so
/// the same bits at every level).
pub fn camera_rays(
    scene: &Scene,
    settings: &RenderSettings,
    samples: &[(u32, u32, u32, DVec2)],
    out: &mut [CameraRay],
) {
    isa::run(MakeRays {
        scene,
        settings,
        samples,
        out,
    })
}

/// [`camera_rays`]' work, compiled at each SIMD level.
struct MakeRays<'a> {
    scene: &'a Scene,
    settings: &'a RenderSettings,
    samples: &'a [(u32, u32, u32, DVec2)],
    out: &'a mut [CameraRay],
}

impl Kernel for MakeRays<'_> {
    type Output = ();
    #[inline(always)]
    fn run<W: Wide>(self, _: W) {
        make_rays(self.scene, self.settings, self.samples, self.out)
    }
}

#[inline(always)]
fn make_rays(
    scene: &Scene,
    settings: &RenderSettings,
    samples: &[(u32, u32, u32, DVec2)],
    out: &mut [CameraRay],
) {
    let n = samples.len();
    assert!(
        (1..=BUNDLE).contains(&n) && out.len() >= n,
        "a block holds 1 to {BUNDLE} camera rays, not {n}"
    );
    let mut lenses = [None; BUNDLE];
    // The film positions lane by lane; lanes past the last sample repeat it (their rays are
    // not kept).
    let last = samples[n - 1].3;
    let mut film = V2 {
        x: Lanes::<BUNDLE>([last.x; BUNDLE]),
        y: Lanes::<BUNDLE>([last.y; BUNDLE]),
    };
    for (i, &(px, py, index, at)) in samples.iter().enumerate() {
        let (lens, rng) = lens_and_stream(scene, settings, px, py, index);
        lenses[i] = lens;
        out[i].film = at;
        out[i].rng = rng;
        film.x.0[i] = at.x;
        film.y.0[i] = at.y;
    }
    let lane = |i: usize| i.min(n - 1);
    // Every sample draws a lens sample, or none does (the camera and settings decide).
    let lens = lenses[0].map(|_| {
        let at = |i: usize| lenses[lane(i)].unwrap_or_default();
        V2 {
            x: Lanes::from_fn(|i| at(i).x),
            y: Lanes::from_fn(|i| at(i).y),
        }
    });
    let (origin, dir) = scene.camera.rays_as(film, lens, settings.mistakes);
    for (i, cam) in out[..n].iter_mut().enumerate() {
        cam.ray = Ray::new(origin.lane(i), dir.lane(i));
        cam.lens = lenses[i];
    }
}

/// Traces a camera ray ([`camera_ray`]); with its hit `found` already (by a bundle), the
/// recorder hears the bundle's share of the work ([`Recorder::bundled`]) instead of the walk.
/// The camera ray is borrowed, not moved: a block's bundled rays are traced where they lie.
/// (Inlined always: with the counting recorder of `--stats` the compiler called it, and
/// the call and its return cost the bundled render a tenth of its speed.)
#[inline(always)]
pub fn trace_camera<R: Recorder>(
    scene: &Scene,
    settings: &RenderSettings,
    camera: &mut CameraRay,
    found: Option<Found>,
    rec: &mut R,
) -> SampleResult {
    let CameraRay { ray, film, rng, .. } = camera;
    let tracer = Tracer::new(scene, settings);
    let color = tracer.trace_found(ray, RayKind::Camera, 0, DVec3::ONE, rng, rec, found);
    SampleResult {
        film: *film,
        color,
        rays: tracer.budget.rays(),
        cut: tracer.budget.cut(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A block's camera rays, made side by side at every SIMD level this processor has, are
    /// bit for bit the rays made one at a time ([`camera_ray`]), with and without a lens, and
    /// for a block short of sixteen.
    #[test]
    fn a_blocks_rays_at_every_level_are_the_rays_made_alone() {
        let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/spheres.json");
        let mut scene = Scene::load(&file).unwrap();
        let mut settings = scene.render.clone();
        let mut rng = Rng::new(&[5, 1230]);
        let samples: Vec<(u32, u32, u32, DVec2)> = (0..16u32)
            .map(|i| {
                let (x, y) = (17 + i % 4, 9 + i / 4);
                let at = DVec2::new(x as f64 + rng.next_f64(), y as f64 + rng.next_f64());
                (x, y, i % 3, at)
            })
            .collect();
        let bits = |r: &Ray| [r.origin, r.dir].map(|v| v.to_array().map(f64::to_bits));
        let mut compared = 0;
        for aperture in [0.0, 0.2] {
            scene.camera.aperture = aperture;
            settings.depth_of_field = aperture > 0.0;
            for n in [16, 11] {
                let samples = &samples[..n];
                let alone: Vec<CameraRay> = samples
                    .iter()
                    .map(|&(x, y, k, at)| camera_ray(&scene, &settings, x, y, k, at))
                    .collect();
                for level in isa::levels() {
                    let mut out: Vec<CameraRay> = alone.iter().map(|_| alone[0].clone()).collect();
                    let (scene, settings) = (&scene, &settings);
                    let out_ = &mut out[..];
                    isa::run_at(
                        level,
                        MakeRays {
                            scene,
                            settings,
                            samples,
                            out: out_,
                        },
                    );
                    for (i, (a, b)) in alone.iter().zip(&out).enumerate() {
                        let what = format!("{level:?}, aperture {aperture}, {n} rays, ray {i}");
                        assert_eq!(bits(&a.ray), bits(&b.ray), "{what}");
                        assert_eq!(a.film, b.film, "{what}");
                        assert_eq!(a.lens, b.lens, "{what}");
                        compared += 1;
                    }
                }
            }
        }
        assert!(compared >= 2 * 27, "{compared}");
    }
}
