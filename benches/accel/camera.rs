//! The harness's camera, in rtlab: the same rays as `embree_bench.cpp` casts.

use crate::{H, W};
use rtlab::math::Ray;
use rtlab::scene::Scene;
use rtlab::shapes::Shape;

/// The harness's pinhole camera, computed in f32 exactly as embree_bench.cpp does (up to
/// the C++ compiler's freedom to fuse multiply-adds), so both trace the same rays.
pub struct HarnessCamera {
    pub eye: [f32; 3],
    pub fwd: [f32; 3],
    pub right: [f32; 3],
    pub upv: [f32; 3],
    pub hw: f32,
    pub hh: f32,
    pub light: [f32; 3],
    pub radius: f32,
}

pub type V = [f32; 3];
#[inline]
pub fn add(a: V, b: V) -> V {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
#[inline]
pub fn sub(a: V, b: V) -> V {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
#[inline]
pub fn mul(a: V, s: f32) -> V {
    [a[0] * s, a[1] * s, a[2] * s]
}
#[inline]
pub fn dot(a: V, b: V) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
#[inline]
pub fn cross(a: V, b: V) -> V {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
#[inline]
pub fn norm(a: V) -> V {
    mul(a, 1.0 / dot(a, a).sqrt())
}

impl HarnessCamera {
    pub fn new(scene: &Scene) -> HarnessCamera {
        let Shape::Mesh(mesh) = &scene.objects[0].shape else {
            panic!("a mesh scene")
        };
        let (mut lo, mut hi) = ([1e30f32; 3], [-1e30f32; 3]);
        for p in &mesh.positions {
            let p = [p.x as f32, p.y as f32, p.z as f32];
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let c = mul(add(lo, hi), 0.5);
        let radius = 0.5 * dot(sub(hi, lo), sub(hi, lo)).sqrt();
        let eye = add(c, mul(norm([0.6, 0.5, 1.0]), 2.0 * radius));
        let light = add(c, mul([1.0, 2.0, 1.5], radius));
        let fwd = norm(sub(c, eye));
        let right = norm(cross(fwd, [0.0, 1.0, 0.0]));
        let upv = cross(right, fwd);
        let hh = (0.5f32 * 40.0 * std::f32::consts::PI / 180.0).tan();
        let hw = hh * W as f32 / H as f32;
        HarnessCamera {
            eye,
            fwd,
            right,
            upv,
            hw,
            hh,
            light,
            radius,
        }
    }

    #[inline]
    pub fn ray(&self, x: usize, y: usize) -> Ray {
        let u = (2.0 * (x as f32 + 0.5) / W as f32 - 1.0) * self.hw;
        let v = (1.0 - 2.0 * (y as f32 + 0.5) / H as f32) * self.hh;
        let d = norm(add(add(self.fwd, mul(self.right, u)), mul(self.upv, v)));
        let w = |a: V| glam::DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64);
        Ray::new(w(self.eye), w(d))
    }
}
