//! Some pixels of an image, traced exactly as `render` traces them (same samples, same filter,
//! same reconstruction), each sample watched by a recorder: `diff` traces only the pixels of
//! a region, under the scene's settings or a mistake's, instead of whole images.

use crate::math::Ray;
use crate::sampling::{render_reconstruct, sample_pixel, Filter};
use crate::scene::{RenderSettings, Scene};
use crate::shading::LightTerm;
use crate::shapes::NoObserver;
use crate::trace::{trace_sample, HitInfo, RayKind, Recorder};
use glam::{DVec2, DVec3};
use rayon::prelude::*;

// ANCHOR: trace_pixels
/// One traced pixel: its colour and, for each sample that reached it, the sample's normalised
/// filter weight and what the recorder kept.
pub struct TracedPixel<T> {
    pub color: DVec3,
    pub samples: Vec<(f64, T)>,
}

/// Traces `pixels` of the scene's image under `settings`. Every sample gets a fresh recorder
/// from `recorder`, and `keep` takes what it saw. Samples of neighbours the filter reaches
/// are traced too, each once; a colour is bit for bit the one `render` gives the pixel (a
/// non-finite sample counts as black there too). Parallel, gathered in order: the result does
/// not depend on the thread count.
pub fn trace_pixels<R: Recorder, T: Send + Sync + Clone>(
    scene: &Scene,
    settings: &RenderSettings,
    pixels: &[(u32, u32)],
    recorder: impl Fn() -> R + Sync,
    keep: impl Fn(&mut R) -> T + Sync,
) -> Vec<TracedPixel<T>> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let filter = Filter::for_settings(settings);
    let reach = filter.reach();
    let mut need: Vec<(u32, u32)> = Vec::new();
    for &(x, y) in pixels {
        for qy in (y as i64 - reach).max(0)..=(y as i64 + reach).min(h as i64 - 1) {
            for qx in (x as i64 - reach).max(0)..=(x as i64 + reach).min(w as i64 - 1) {
                need.push((qy as u32, qx as u32));
            }
        }
    }
    need.sort_unstable();
    need.dedup();
    type Sample<T> = (DVec2, DVec3, f64, T);
    let traced: Vec<Vec<Sample<T>>> = need
        .par_iter()
        .map(|&(y, x)| {
            let mut kept = Vec::new();
            let samples = sample_pixel(settings, w, h, x, y, |k, film| {
                let mut rec = recorder();
                // Cancelled (the server's client gone): the rest is not traced, and the
                // caller throws the answer away.
                let c = match settings.cancel.is_cancelled() {
                    true => DVec3::ZERO,
                    false => trace_sample(scene, settings, x, y, k, film, &mut rec).color,
                };
                kept.push(keep(&mut rec));
                if c.is_finite() {
                    c
                } else {
                    DVec3::ZERO
                }
            });
            samples
                .into_iter()
                .zip(kept)
                .map(|(s, t)| (s.film, s.color, s.area, t))
                .collect()
        })
        .collect();
    let at = |qx: u32, qy: u32| &traced[need.binary_search(&(qy, qx)).expect("traced")];
    pixels
        .par_iter()
        .map(|&(x, y)| {
            let (color, weights) = render_reconstruct(&filter, x, y, w, h, |qx, qy| {
                at(qx, qy).iter().map(|s| (s.0, s.1, s.2))
            });
            let samples = weights
                .into_iter()
                .map(|(qx, qy, k, wt)| (wt, at(qx, qy)[k].3.clone()))
                .collect();
            TracedPixel { color, samples }
        })
        .collect()
}
// ANCHOR_END: trace_pixels

/// What the camera ray's own hit saw, term by term: the lighting ledger of one sample, as
/// `explain`'s shading node shows it.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Ledger {
    /// The object the camera ray hit and the surface of it (`body`, `cap`, `face`, ...).
    pub hit: Option<(usize, &'static str)>,
    pub ambient: DVec3,
    /// Per light, in scene order (zero where the light is blocked or faces away).
    pub diffuse: Vec<DVec3>,
    pub specular: Vec<DVec3>,
    /// Per light, diffuse + specular of a light the settings leave out (`directional_only`).
    pub ignored: Vec<DVec3>,
    pub reflected: DVec3,
    pub transmitted: DVec3,
    /// The pixel's whole colour (every ray of the tree), for terms that are not the first
    /// hit's alone; filled in per pixel by whoever reconstructs it.
    pub color: DVec3,
}

/// Keeps the [`Ledger`] of the camera ray's hit (events while exactly one ray is open, as
/// its [`HitRecorder`] tells).
#[derive(Debug, Default)]
pub struct LedgerRecorder {
    pub ledger: Ledger,
    camera: HitRecorder,
}

impl LedgerRecorder {
    pub fn new(lights: usize) -> Self {
        let z = vec![DVec3::ZERO; lights];
        LedgerRecorder {
            ledger: Ledger {
                diffuse: z.clone(),
                specular: z.clone(),
                ignored: z,
                ..Ledger::default()
            },
            ..LedgerRecorder::default()
        }
    }
}

impl Recorder for LedgerRecorder {
    type Obs = NoObserver;
    const ACTIVE: bool = true;
    fn observer(&mut self) -> &mut NoObserver {
        self.camera.observer()
    }
    fn begin_ray(&mut self, kind: RayKind, depth: u32, ray: &Ray) {
        self.camera.begin_ray(kind, depth, ray);
    }
    fn end_ray(&mut self, c: DVec3, end: crate::trace::End, clamped: bool) {
        self.camera.end_ray(c, end, clamped);
    }
    fn hit(&mut self, hit: &HitInfo) {
        self.camera.hit(hit);
        self.ledger.hit = self.camera.hit;
    }
    fn ambient(&mut self, c: DVec3) {
        if self.camera.at_camera_ray() {
            self.ledger.ambient += c;
        }
    }
    fn light(&mut self, t: &LightTerm) {
        if self.camera.at_camera_ray() {
            self.ledger.diffuse[t.light] += t.diffuse;
            self.ledger.specular[t.light] += t.specular;
        }
    }
    fn ignored_light(&mut self, t: &LightTerm) {
        if self.camera.at_camera_ray() {
            self.ledger.ignored[t.light] += t.diffuse + t.specular;
        }
    }
    fn reflected(&mut self, c: DVec3) {
        if self.camera.at_camera_ray() {
            self.ledger.reflected += c;
        }
    }
    fn transmitted(&mut self, c: DVec3) {
        if self.camera.at_camera_ray() {
            self.ledger.transmitted += c;
        }
    }
}

/// Just the colours of `pixels`, as `render` makes them (the zero-cost recorder).
pub fn colors(scene: &Scene, settings: &RenderSettings, pixels: &[(u32, u32)]) -> Vec<DVec3> {
    trace_pixels(
        scene,
        settings,
        pixels,
        crate::trace::NoRecorder::default,
        |_| (),
    )
    .into_iter()
    .map(|p| p.color)
    .collect()
}

/// Keeps only the camera ray's hit: which object, which surface of it.
#[derive(Debug, Default)]
pub struct HitRecorder {
    pub hit: Option<(usize, &'static str)>,
    open: u32,
    obs: NoObserver,
}

impl Recorder for HitRecorder {
    type Obs = NoObserver;
    const ACTIVE: bool = true;
    fn observer(&mut self) -> &mut NoObserver {
        &mut self.obs
    }
    fn begin_ray(&mut self, _kind: RayKind, _depth: u32, _ray: &Ray) {
        self.open += 1;
    }
    fn end_ray(&mut self, _c: DVec3, _end: crate::trace::End, _clamped: bool) {
        self.open -= 1;
    }
    fn hit(&mut self, hit: &HitInfo) {
        if self.at_camera_ray() {
            self.hit = Some((hit.object, hit.local.surface));
        }
    }
}

impl HitRecorder {
    /// Is the camera ray the only one open (are events about its own hit)?
    fn at_camera_ray(&self) -> bool {
        self.open == 1
    }
}

/// The object and surface under each of `pixels`: what the camera rays of most of the
/// pixel's (filter-weighted) samples hit; `None` for the background. Ray casting only.
pub fn hits(
    scene: &Scene,
    settings: &RenderSettings,
    pixels: &[(u32, u32)],
) -> Vec<Option<(usize, &'static str)>> {
    let cast = crate::sampling::aov::Aov::ObjectId.settings(settings);
    trace_pixels(scene, &cast, pixels, HitRecorder::default, |r| r.hit)
        .into_iter()
        .map(|p| {
            let mut votes: Vec<(Option<(usize, &'static str)>, f64)> = Vec::new();
            for (w, h) in p.samples {
                match votes.iter_mut().find(|v| v.0 == h) {
                    Some(v) => v.1 += w,
                    None => votes.push((h, w)),
                }
            }
            // The heaviest; the first seen on a tie.
            let mut best: Option<(Option<(usize, &'static str)>, f64)> = None;
            for v in votes {
                if best.is_none_or(|b| v.1 > b.1 + 1e-12) {
                    best = Some(v);
                }
            }
            best.and_then(|b| b.0)
        })
        .collect()
}

/// The bytes of `pixels` as `render` writes them under `settings`.
pub fn bytes(scene: &Scene, settings: &RenderSettings, pixels: &[(u32, u32)]) -> Vec<[u8; 3]> {
    colors(scene, settings, pixels)
        .into_iter()
        .map(|c| crate::sampling::encode_as(c, settings.encoding, settings.mistakes))
        .collect()
}
