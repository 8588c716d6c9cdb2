//! Forward tracing, for comparison only: photons leave the lights and bounce around the scene;
//! the few that happen to pass through the eye's pupil land on the film. The lecture's point
//! is how few that is, next to backward tracing where every camera ray lands on its pixel.
//!
//! It uses the tracer's own intersection code ([`crate::accel::Accel::closest`]) and optics
//! (`reflect`, `refract`); the bounce is a random choice per photon (mirror with probability
//! mean(ks·Or), transmission mean(kt·Ot), diffuse mean(kd·Od), otherwise absorbed), with
//! diffuse directions cosine-weighted. Photon `i` draws its random numbers from (seed, i)
//! alone, so the counts do not depend on the thread count.

use crate::math::{Ray, Rng};
use crate::scene::Scene;
use crate::shading::optics::{reflect, refract};
use crate::shading::LightKind;
use crate::trace::NoRecorder;
use glam::{DVec2, DVec3};
use rayon::prelude::*;
use serde::Serialize;

/// What happened to the photons.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct ForwardCounts {
    pub photons: u64,
    /// Photons that hit at least one surface.
    pub hit_surface: u64,
    /// Photons that passed through the pupil, inside the field of view: they reach the film.
    pub reached_film: u64,
    /// Photons that passed through the pupil from outside the field of view.
    pub outside_view: u64,
    /// Photons that left the scene without reaching the eye.
    pub escaped: u64,
    /// Photons absorbed at a surface (or still bouncing after the last allowed bounce).
    pub absorbed: u64,
    /// Ray segments traced in all (each one an `Accel::closest` query).
    pub rays: u64,
}

/// Photons on the film: film position (pixel units) and colour.
#[derive(Debug, Clone, Default)]
pub struct ForwardResult {
    pub counts: ForwardCounts,
    pub splats: Vec<(DVec2, DVec3)>,
}

enum Fate {
    Film(DVec2, DVec3),
    OutsideView,
    Escaped,
    Absorbed,
}

/// Traces `photons` photons from the scene's lights (round robin), each bouncing at most
/// `max_bounces` times; the eye is a disc of radius `pupil` at the camera position.
pub fn trace_photons(
    scene: &Scene,
    photons: u64,
    pupil: f64,
    max_bounces: u32,
    seed: u64,
) -> ForwardResult {
    let mut result = ForwardResult::default();
    result.counts.photons = photons;
    if scene.lights.is_empty() {
        result.counts.escaped = photons;
        return result;
    }
    let per: Vec<(Fate, bool, u64)> = (0..photons)
        .into_par_iter()
        .map(|i| photon(scene, i, pupil, max_bounces, seed))
        .collect();
    for (fate, hit, rays) in per {
        let c = &mut result.counts;
        c.rays += rays;
        c.hit_surface += hit as u64;
        match fate {
            Fate::Film(p, color) => {
                c.reached_film += 1;
                result.splats.push((p, color));
            }
            Fate::OutsideView => c.outside_view += 1,
            Fate::Escaped => c.escaped += 1,
            Fate::Absorbed => c.absorbed += 1,
        }
    }
    result
}

fn unit_sphere(rng: &mut Rng) -> DVec3 {
    let z = 1.0 - 2.0 * rng.next_f64();
    let phi = std::f64::consts::TAU * rng.next_f64();
    let r = (1.0 - z * z).max(0.0).sqrt();
    DVec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// A cosine-weighted direction around unit `n`.
fn cosine_around(n: DVec3, rng: &mut Rng) -> DVec3 {
    let (a, b) = n.any_orthonormal_pair();
    let (r, phi) = (
        rng.next_f64().sqrt(),
        std::f64::consts::TAU * rng.next_f64(),
    );
    let z = (1.0 - r * r).max(0.0).sqrt();
    (a * (r * phi.cos()) + b * (r * phi.sin()) + n * z).normalize()
}

/// Where photon `i` starts and which way it goes.
fn emit(scene: &Scene, i: u64, rng: &mut Rng) -> (Ray, DVec3) {
    let light = &scene.lights[(i % scene.lights.len() as u64) as usize];
    let ray = match &light.kind {
        LightKind::Point { position } => Ray::new(*position, unit_sphere(rng)),
        LightKind::Spot {
            position,
            direction,
            angle,
            ..
        } => {
            // Uniform over the spherical cap of the cone.
            let cos_max = angle.cos();
            let z = 1.0 - rng.next_f64() * (1.0 - cos_max);
            let phi = std::f64::consts::TAU * rng.next_f64();
            let r = (1.0 - z * z).max(0.0).sqrt();
            let (a, b) = direction.any_orthonormal_pair();
            Ray::new(
                *position,
                a * (r * phi.cos()) + b * (r * phi.sin()) + *direction * z,
            )
        }
        LightKind::Directional { direction } => {
            // A disc upstream of the scene's bounding sphere, shining along `direction`.
            let (centre, radius) = bounding_sphere(scene);
            let (a, b) = direction.any_orthonormal_pair();
            let (r, phi) = (
                rng.next_f64().sqrt() * radius,
                std::f64::consts::TAU * rng.next_f64(),
            );
            let o =
                centre - *direction * (2.0 * radius) + a * (r * phi.cos()) + b * (r * phi.sin());
            Ray::new(o, *direction)
        }
        LightKind::Area {
            corner,
            edge_u,
            edge_v,
            ..
        } => {
            let o = *corner + *edge_u * rng.next_f64() + *edge_v * rng.next_f64();
            let mut n = edge_u.cross(*edge_v).normalize_or_zero();
            if rng.next_f64() < 0.5 {
                n = -n;
            }
            Ray::new(o, cosine_around(n, rng))
        }
    };
    (ray, light.color)
}

fn bounding_sphere(scene: &Scene) -> (DVec3, f64) {
    let b = scene
        .objects
        .iter()
        .filter_map(|o| o.bounds)
        .fold(crate::shapes::Aabb::EMPTY, |a, b| a.union(b));
    if b.is_empty() {
        (scene.camera.look_at, 10.0)
    } else {
        let c = (b.min + b.max) / 2.0;
        (c, ((b.max - b.min).length() / 2.0).clamp(1.0, 1e4))
    }
}

/// Follows one photon: (its fate, whether it hit any surface, ray segments traced).
fn photon(scene: &Scene, i: u64, pupil: f64, max_bounces: u32, seed: u64) -> (Fate, bool, u64) {
    let mut rng = Rng::new(&[seed, 0xF0_4A_7D, i]);
    let (mut ray, mut power) = emit(scene, i, &mut rng);
    let cam = &scene.camera;
    let w = cam.basis[2];
    let mut hit_any = false;
    let mut rays = 0;
    for bounce in 0..=max_bounces {
        rays += 1;
        let found = scene.accel.closest(
            &scene.objects,
            &ray,
            0.0,
            f64::INFINITY,
            &mut NoRecorder::default(),
        );
        // Does it pass through the pupil first? Only after a bounce: the renderer does not
        // draw the lights themselves.
        if bounce > 0 && ray.dir.dot(w) > 0.0 {
            let t_eye = (cam.position - ray.origin).dot(w) / ray.dir.dot(w);
            let through = t_eye > 0.0
                && (ray.at(t_eye) - cam.position).length() <= pupil
                && found.as_ref().is_none_or(|(_, h)| h.t > t_eye);
            if through {
                return match film_position(scene, ray.origin) {
                    Some(p) => (Fate::Film(p, power), hit_any, rays),
                    None => (Fate::OutsideView, hit_any, rays),
                };
            }
        }
        let Some((object, local)) = found else {
            return (Fate::Escaped, hit_any, rays);
        };
        hit_any = true;
        let o = &scene.objects[object];
        let m = scene.material_of(object);
        let g = scene.global;
        let point = ray.at(local.t);
        let normal = o.transform.normal_to_world(local.normal);
        let d = ray.dir.normalize();
        let entering = normal.dot(d) < 0.0;
        let n = if entering { normal } else { -normal };
        let eps = scene.render.epsilon * (1.0 + point.abs().max_element());
        let mirror = g.ks * m.reflective;
        let transmit = g.kt * m.transparent;
        let diffuse = g.kd * m.diffuse;
        let (pm, pt, pd) = (
            mean(mirror).min(1.0),
            mean(transmit).min(1.0),
            mean(diffuse).min(1.0),
        );
        let u = rng.next_f64();
        let (dir, from, tint, p) = if u < pm {
            (reflect(d, n), point + n * eps, mirror, pm)
        } else if u < pm + pt {
            let eta = if entering { 1.0 / m.ior.x } else { m.ior.x };
            match (m.refract, refract(d, n, eta)) {
                (false, _) => (d, point - n * eps, transmit, pt),
                (true, Some(t)) => (t, point - n * eps, transmit, pt),
                (true, None) => (reflect(d, n), point + n * eps, transmit, pt),
            }
        } else if u < pm + pt + pd * (1.0 - pm - pt).max(0.0) {
            (
                cosine_around(n, &mut rng),
                point + n * eps,
                diffuse,
                pd * (1.0 - pm - pt).max(0.0),
            )
        } else {
            return (Fate::Absorbed, hit_any, rays);
        };
        // The choice already carries the energy lost; the colour keeps the surface's hue.
        let _ = p;
        power *= tint / mean(tint).max(1e-12);
        ray = Ray::new(from, dir);
    }
    (Fate::Absorbed, hit_any, rays)
}

fn mean(c: DVec3) -> f64 {
    (c.x + c.y + c.z) / 3.0
}

/// The film position (pixel units) where a point in front of the camera is seen, if inside
/// the field of view: the camera's normalising transformation run forwards.
pub fn film_position(scene: &Scene, p: DVec3) -> Option<DVec2> {
    let cam = &scene.camera;
    let c = cam.world_from_canonical.inverse().transform_point3(p);
    if c.z >= 0.0 {
        return None;
    }
    let ndc = DVec2::new(c.x / -c.z, c.y / -c.z);
    if ndc.x.abs() > 1.0 || ndc.y.abs() > 1.0 {
        return None;
    }
    Some(DVec2::new(
        (ndc.x + 1.0) / 2.0 * cam.width as f64,
        (1.0 - ndc.y) / 2.0 * cam.height as f64,
    ))
}
