//! Ray generation, exactly as the lecture builds it, each stage a named step:
//! sample position in the pixel → normalised film point (x, y in [−1, 1], z = −1 on the far
//! plane of the canonical view frustum) → world space through the inverse of the normalising
//! transformation → direction = world film point − eye (then made unit length).

use crate::math::lanes::{Lanes, Real, TransformPoint, V2, V3};
use crate::math::{Ray, Rng};
use crate::mistakes::{Mistake, Mistakes};
use glam::{DMat4, DVec2, DVec3, DVec4};
use serde::Serialize;
use std::ops::{Div, Mul, Sub};

/// A pinhole camera (a thin lens when `aperture` > 0), validated: unit basis, 0 < fov < 180.
#[derive(Debug, Clone, PartialEq)]
pub struct Camera {
    pub position: DVec3,
    pub look_at: DVec3,
    pub up: DVec3,
    /// Full vertical field of view, degrees.
    pub fov_y: f64,
    pub width: u32,
    pub height: u32,
    /// Lens diameter for depth of field (0: pinhole).
    pub aperture: f64,
    /// Distance from the eye to the plane in focus.
    pub focal_distance: f64,
    /// Inverse of the normalising transformation: canonical frustum → world.
    pub world_from_canonical: DMat4,
    /// Camera basis: u right, v up, w backwards (the camera looks down −w).
    pub basis: [DVec3; 3],
}

/// Every stage of generating one ray, for `explain` (DESIGN §3 `camera`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RayGeneration {
    /// Sample position in pixel units (x from the left, y from the top).
    pub film: DVec2,
    /// Normalised device coordinates: x, y in [−1, 1], y up.
    pub ndc: DVec2,
    /// The point on the canonical frustum's far plane, (x, y, −1).
    pub film_point: DVec3,
    /// That point taken back to world space.
    pub world_point: DVec3,
    pub origin: DVec3,
    /// Unit direction of the ray.
    pub direction: DVec3,
}

/// The stages of [`Camera::generate_in`] (of one ray, or of many side by side): what
/// [`RayGeneration`] records of one ray, but its film position.
#[derive(Debug, Clone, Copy)]
pub struct Stages<T> {
    /// Normalised device coordinates: x, y in [−1, 1], y up.
    pub ndc: V2<T>,
    /// The point on the canonical frustum's far plane, (x, y, −1).
    pub film_point: V3<T>,
    /// That point taken back to world space.
    pub world_point: V3<T>,
    pub origin: V3<T>,
    /// Unit direction of the ray.
    pub direction: V3<T>,
}

impl Camera {
    /// Builds the camera. Fails with a reason when the view is degenerate.
    pub fn new(
        position: DVec3,
        look_at: DVec3,
        up: DVec3,
        fov_y: f64,
        width: u32,
        height: u32,
    ) -> Result<Camera, String> {
        Self::from_look(position, look_at - position, up, fov_y, width, height)
    }

    /// As [`Camera::new`], from a view *direction* instead of a point.
    pub fn from_look(
        position: DVec3,
        look: DVec3,
        up: DVec3,
        fov_y: f64,
        width: u32,
        height: u32,
    ) -> Result<Camera, String> {
        if !(fov_y > 0.0 && fov_y < 180.0) {
            return Err(format!(
                "field of view must be between 0 and 180 degrees (exclusive), found {fov_y}"
            ));
        }
        let w = -look
            .try_normalize()
            .ok_or("the camera looks at its own position: the view direction is zero")?;
        let up_n = up.try_normalize().ok_or("the up vector is zero")?;
        if up_n.cross(w).length() < 1e-9 {
            return Err(
                "the up vector is parallel to the view direction: the image has no 'up'".into(),
            );
        }
        let v = (up_n - up_n.dot(w) * w).normalize();
        let u = v.cross(w);
        let mut cam = Camera {
            position,
            look_at: position + look,
            up,
            fov_y,
            width,
            height,
            aperture: 0.0,
            focal_distance: look.length(),
            world_from_canonical: DMat4::IDENTITY,
            basis: [u, v, w],
        };
        cam.update_size(width, height);
        Ok(cam)
    }

    /// Sets the image size (the horizontal field of view follows from the aspect ratio).
    pub fn update_size(&mut self, width: u32, height: u32) {
        self.width = width;
        self.height = height;
        let (tan_w, tan_h) = self.tan_half_angles(Mistakes::NONE);
        let [u, v, w] = self.basis;
        // ANCHOR: normalising
        // The normalising transformation is S · R · T: translate the eye to the origin, rotate
        // the basis (u, v, w) onto (x, y, z), scale so the far plane (at distance 1) spans
        // [−1, 1]². Its inverse T⁻¹ · R⁻¹ · S⁻¹ takes a film point back into the world.
        let translate_inv = DMat4::from_translation(self.position);
        let rotate_inv = DMat4::from_cols(u.extend(0.0), v.extend(0.0), w.extend(0.0), DVec4::W);
        let scale_inv = DMat4::from_scale(DVec3::new(tan_w, tan_h, 1.0));
        self.world_from_canonical = translate_inv * rotate_inv * scale_inv;
        // ANCHOR_END: normalising
    }

    /// tan(θw/2) and tan(θh/2) of the film: tan(θw/2) = (W/H)·tan(θh/2). The catalogue's
    /// `fov-width-angle` takes θw = (W/H)·θh instead, `aspect-ignored` a square film.
    fn tan_half_angles(&self, mistakes: Mistakes) -> (f64, f64) {
        let half_h = self.fov_y.to_radians() / 2.0;
        let tan_h = half_h.tan();
        let aspect = self.width as f64 / self.height as f64;
        let tan_w = if mistakes.has(Mistake::AspectIgnored) {
            tan_h
        } else if mistakes.has(Mistake::FovWidthAngle) {
            // Kept below 90° so the film stays finite, as wrong as the student's.
            (aspect * half_h).min(89.5f64.to_radians()).tan()
        } else {
            tan_h * aspect
        };
        (tan_w, tan_h)
    }

    /// tan(θw/2) under the width mistakes over the right one: how much the mistaken film
    /// is wider.
    fn wrong_width(&self, mistakes: Mistakes) -> f64 {
        self.tan_half_angles(mistakes).0 / self.tan_half_angles(Mistakes::NONE).0
    }

    /// The ray through film position `film` (pixel units, y down), with every stage recorded.
    /// `lens` is a point in the unit square for depth of field (ignored for a pinhole).
    pub fn generate(&self, film: DVec2, lens: Option<DVec2>) -> (Ray, RayGeneration) {
        self.generate_as(film, lens, Mistakes::NONE)
    }

    /// The ray of [`Camera::generate_as`] alone: what `render` traces for one sample.
    pub fn ray_as(&self, film: DVec2, lens: Option<DVec2>, mistakes: Mistakes) -> Ray {
        let g = self.generate_in(V2::splat(film), lens.map(V2::splat), mistakes);
        Ray::new(g.origin.glam(), g.direction.glam())
    }

    /// [`Camera::generate`] under the catalogue's camera mistakes (none: the lecture's).
    pub fn generate_as(
        &self,
        film: DVec2,
        lens: Option<DVec2>,
        mistakes: Mistakes,
    ) -> (Ray, RayGeneration) {
        let g = self.generate_in(V2::splat(film), lens.map(V2::splat), mistakes);
        let generation = RayGeneration {
            film,
            ndc: g.ndc.glam(),
            film_point: g.film_point.glam(),
            world_point: g.world_point.glam(),
            origin: g.origin.glam(),
            direction: g.direction.glam(),
        };
        (
            Ray::new(generation.origin, generation.direction),
            generation,
        )
    }

    /// The rays of [`Camera::ray_as`] for `N` samples at once, made side by side: lane i of
    /// the film positions (and of the lens samples, for a thin lens) gives lane i of the
    /// origins and directions, bit for bit the ray `ray_as` makes of it alone. A bundle's
    /// camera rays are made this way ([`crate::trace::camera_rays`]).
    #[inline(always)]
    pub fn rays_as<const N: usize>(
        &self,
        film: V2<Lanes<N>>,
        lens: Option<V2<Lanes<N>>>,
        mistakes: Mistakes,
    ) -> (V3<Lanes<N>>, V3<Lanes<N>>) {
        let g = self.generate_in(film, lens, mistakes);
        (g.origin, g.direction)
    }

    // ANCHOR: generate
    /// Every stage of the ray through `film` under `mistakes`, on one number or on many side
    /// by side ([`Real`]: the same operations either way, so the same bits).
    #[inline(always)]
    pub fn generate_in<T: Real>(
        &self,
        film: V2<T>,
        lens: Option<V2<T>>,
        mistakes: Mistakes,
    ) -> Stages<T>
    where
        f64: Mul<T, Output = T> + Sub<T, Output = T> + Div<T, Output = T>,
    {
        // `pixel-corner`: the sample's position taken from the pixel's corner, not its centre.
        let at = if mistakes.has(Mistake::PixelCorner) {
            film - DVec2::splat(0.5)
        } else {
            film
        };
        let mut ndc = V2 {
            x: 2.0 * at.x / self.width as f64 - 1.0,
            y: 1.0 - 2.0 * at.y / self.height as f64,
        };
        if mistakes.has(Mistake::ImageFlipped) {
            ndc.y = -ndc.y; // row 0 taken as the bottom of the film
        }
        if mistakes.has(Mistake::FovWidthAngle) || mistakes.has(Mistake::AspectIgnored) {
            // The normalising transformation holds the right width; scale x to the wrong one.
            ndc.x *= self.wrong_width(mistakes);
        }
        let film_point = V3 {
            x: ndc.x,
            y: ndc.y,
            z: T::splat(-1.0),
        };
        let world_point = self.world_from_canonical.transform_point(film_point);
        let eye = V3::splat(self.position); // the camera's position, in every lane
        let mut origin = eye;
        let mut direction = (world_point - eye).normalize();
        if let (Some(lens), true) = (lens, self.aperture > 0.0) {
            // Thin lens: start on the aperture disc, aim at the point of the primary ray that
            // lies on the plane in focus.
            let [u, v, w] = self.basis.map(V3::splat);
            let focus = eye + direction * (self.focal_distance / direction.dot(-w));
            let (r, phi) = (
                lens.x.sqrt() * self.aperture / 2.0,
                lens.y * std::f64::consts::TAU,
            );
            origin = eye + u * (r * phi.cos()) + v * (r * phi.sin());
            direction = (focus - origin).normalize();
        }
        Stages {
            ndc,
            film_point,
            world_point,
            origin,
            direction,
        }
    }
    // ANCHOR_END: generate

    /// The lens sample for a given random stream, `None` for a pinhole.
    #[inline]
    pub fn lens_sample(&self, enabled: bool, rng: &mut Rng) -> Option<DVec2> {
        (enabled && self.aperture > 0.0).then(|| DVec2::new(rng.next_f64(), rng.next_f64()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lecture's steps written with glam's own vectors and matrix, as `generate` was
    /// before it ran on [`Real`]s: the oracle the generic code must match bit for bit.
    fn glam_ray(cam: &Camera, film: DVec2, lens: DVec2) -> Ray {
        let ndc = DVec2::new(
            2.0 * film.x / cam.width as f64 - 1.0,
            1.0 - 2.0 * film.y / cam.height as f64,
        );
        let world_point = cam
            .world_from_canonical
            .transform_point3(DVec3::new(ndc.x, ndc.y, -1.0));
        let direction = (world_point - cam.position).normalize();
        if cam.aperture <= 0.0 {
            return Ray::new(cam.position, direction);
        }
        let focus = cam.position + direction * (cam.focal_distance / direction.dot(-cam.basis[2]));
        let (r, phi) = (
            lens.x.sqrt() * cam.aperture / 2.0,
            lens.y * std::f64::consts::TAU,
        );
        let origin = cam.position + cam.basis[0] * (r * phi.cos()) + cam.basis[1] * (r * phi.sin());
        Ray::new(origin, (focus - origin).normalize())
    }

    /// Rays made side by side (`rays_as`, as bundles make them) are bit for bit the rays made
    /// one at a time, under every camera mistake, with and without a thin lens; and without
    /// a mistake, bit for bit what glam's own vectors compute.
    #[test]
    fn rays_side_by_side_are_the_rays_one_at_a_time() {
        let mut cam = Camera::new(
            DVec3::new(0.3, 1.7, 5.1),
            DVec3::new(-0.2, 0.4, 0.0),
            DVec3::new(0.1, 1.0, 0.0),
            37.0,
            61,
            47,
        )
        .unwrap();
        let mut rng = Rng::new(&[3, 1230]);
        let films: Vec<DVec2> = (0..16)
            .map(|_| DVec2::new(rng.next_f64() * 61.0, rng.next_f64() * 47.0))
            .collect();
        let lenses: Vec<DVec2> = (0..16)
            .map(|_| DVec2::new(rng.next_f64(), rng.next_f64()))
            .collect();
        let lanes = |v: &[DVec2]| V2 {
            x: Lanes::<16>::from_fn(|i| v[i].x),
            y: Lanes::<16>::from_fn(|i| v[i].y),
        };
        let camera_mistakes = [
            Mistakes::NONE,
            Mistakes::one(Mistake::PixelCorner),
            Mistakes::one(Mistake::ImageFlipped),
            Mistakes::one(Mistake::FovWidthAngle),
            Mistakes::one(Mistake::AspectIgnored),
        ];
        for aperture in [0.0, 0.25] {
            cam.aperture = aperture;
            for m in camera_mistakes {
                let (o, d) = cam.rays_as(lanes(&films), Some(lanes(&lenses)), m);
                let bits = |v: DVec3| v.to_array().map(f64::to_bits);
                for i in 0..16 {
                    let one = cam.ray_as(films[i], Some(lenses[i]), m);
                    assert_eq!(bits(o.lane(i)), bits(one.origin), "{m:?} {i}");
                    assert_eq!(bits(d.lane(i)), bits(one.dir), "{m:?} {i}");
                    if m == Mistakes::NONE {
                        let glam = glam_ray(&cam, films[i], lenses[i]);
                        assert_eq!(bits(one.origin), bits(glam.origin), "{i}");
                        assert_eq!(bits(one.dir), bits(glam.dir), "{i}");
                    }
                }
            }
        }
    }
    #[test]
    fn centre_pixel_looks_at_target_and_corners_span_fov() {
        let cam = Camera::new(
            DVec3::new(0.0, 0.0, 5.0),
            DVec3::ZERO,
            DVec3::Y,
            90.0,
            100,
            100,
        )
        .unwrap();
        let (ray, g) = cam.generate(DVec2::new(50.0, 50.0), None);
        assert!((ray.dir - DVec3::NEG_Z).length() < 1e-12);
        assert_eq!(g.film_point, DVec3::new(0.0, 0.0, -1.0));
        // Top-left corner of the film: ndc (-1, 1); 90° fov puts it at 45° in both axes.
        let (ray, g) = cam.generate(DVec2::new(0.0, 0.0), None);
        assert_eq!(g.ndc, DVec2::new(-1.0, 1.0));
        assert!((g.world_point - DVec3::new(-1.0, 1.0, 4.0)).length() < 1e-12);
        assert!((ray.dir - DVec3::new(-1.0, 1.0, -1.0).normalize()).length() < 1e-12);
    }
    #[test]
    fn degenerate_cameras_are_refused() {
        assert!(Camera::new(DVec3::ZERO, DVec3::ZERO, DVec3::Y, 45.0, 10, 10).is_err());
        assert!(Camera::new(DVec3::Y, DVec3::ZERO, DVec3::Y, 45.0, 10, 10).is_err());
        assert!(Camera::new(DVec3::Z, DVec3::ZERO, DVec3::Y, 180.0, 10, 10).is_err());
        assert!(Camera::new(DVec3::Z, DVec3::ZERO, DVec3::Y, 0.0, 10, 10).is_err());
    }
}
