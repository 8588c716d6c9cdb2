//! The slice's plane (which one, and its frame) and the pixel mapping of the plot.

use super::SlicePlane;
use crate::scene::Scene;
use crate::shading::LightKind;
use crate::trace::{RayKind, RayNode};
use glam::DVec3;

#[derive(Debug, Clone, Copy)]
pub(in crate::viz) struct Frame {
    pub(in crate::viz) origin: DVec3,
    pub(in crate::viz) e1: DVec3,
    pub(in crate::viz) e2: DVec3,
    pub(in crate::viz) normal: DVec3,
}

impl Frame {
    fn new(origin: DVec3, along: DVec3, towards: DVec3) -> Option<Frame> {
        let e1 = along.try_normalize()?;
        let e2 = towards - e1 * towards.dot(e1);
        if e2.length() < 1e-6 * towards.length().max(1e-300) {
            return None;
        }
        let e2 = e2.normalize();
        Some(Frame {
            origin,
            e1,
            e2,
            normal: e1.cross(e2),
        })
    }
    /// The same plane, turned within itself so that the world's +y (projected) points up the
    /// figure: floors stay level. Unchanged when +y is (nearly) perpendicular to the plane.
    fn level(self) -> Frame {
        let y = DVec3::Y - self.normal * self.normal.dot(DVec3::Y);
        if y.length() < 0.2 {
            return self;
        }
        let e2 = y.normalize();
        let mut e1 = e2.cross(self.normal);
        if e1.dot(self.e1) < 0.0 {
            e1 = -e1;
        }
        Frame {
            origin: self.origin,
            e1,
            e2,
            normal: e1.cross(e2),
        }
    }
    pub(super) fn to2(&self, p: DVec3) -> (f64, f64) {
        let q = p - self.origin;
        (q.dot(self.e1), q.dot(self.e2))
    }
    pub(in crate::viz) fn to3(&self, u: f64, v: f64) -> DVec3 {
        self.origin + self.e1 * u + self.e2 * v
    }
    /// How far a direction leaves the plane: |sin| of its angle with the plane.
    pub(super) fn off_plane(&self, d: DVec3) -> f64 {
        d.normalize_or_zero().dot(self.normal).abs()
    }
}

/// The plane actually used and why.
pub(super) fn choose_frame(
    scene: &Scene,
    tree: &RayNode,
    plane: SlicePlane,
) -> (Frame, &'static str) {
    let up = scene.camera.basis[1];
    let camera = Frame::new(tree.origin, tree.direction, up)
        .or_else(|| Frame::new(tree.origin, tree.direction, scene.camera.basis[0]))
        .or_else(|| Frame::new(tree.origin, DVec3::NEG_Z, DVec3::Y))
        .expect("-z and +y span a plane")
        .level();
    if plane == SlicePlane::Bounce {
        // The bounce that carries the most (glass: the refraction; a mirror: the reflection).
        let bounce = tree
            .children
            .iter()
            .filter(|c| c.kind != RayKind::Shadow)
            .fold(None::<&RayNode>, |best, c| {
                let w = |n: &RayNode| n.weight.map_or(0.0, |w| w.max_element());
                match best {
                    Some(b) if w(b) >= w(c) => Some(b),
                    _ => Some(c),
                }
            });
        if let Some(b) = bounce {
            if let Some(mut f) = Frame::new(tree.origin, tree.direction, b.direction) {
                if f.e2.dot(up) < 0.0 {
                    f.e2 = -f.e2;
                    f.normal = -f.normal;
                }
                return (
                    f.level(),
                    "slice through the camera ray and its first bounce",
                );
            }
        }
        return (
            camera,
            "no bounce to follow: slice through the camera ray and the camera's up vector",
        );
    }
    (
        camera,
        "slice through the camera ray and the camera's up vector",
    )
}

/// Where a shadow ray ends: the light it was cast to (`Some(point)`) or a directional light
/// (`None`, infinitely far), with the light's name. Matched by direction, in scene order.
pub(super) fn shadow_target(scene: &Scene, ray: &RayNode) -> Option<(Option<DVec3>, String)> {
    let d = ray.direction.try_normalize()?;
    let o = ray.origin;
    for light in &scene.lights {
        let target = match &light.kind {
            LightKind::Point { position } | LightKind::Spot { position, .. } => {
                let to = (*position - o).try_normalize();
                to.filter(|t| t.dot(d) > 1.0 - 1e-9)
                    .map(|_| Some(*position))
            }
            LightKind::Directional { direction } => {
                let to = (-*direction).try_normalize();
                to.filter(|t| t.dot(d) > 1.0 - 1e-9).map(|_| None)
            }
            LightKind::Area {
                corner,
                edge_u,
                edge_v,
                ..
            } => {
                let n = edge_u.cross(*edge_v);
                let denom = n.dot(d);
                if denom.abs() < 1e-12 {
                    None
                } else {
                    let t = n.dot(*corner - o) / denom;
                    let p = o + d * t;
                    let q = p - *corner;
                    let (a, b) = (
                        q.dot(*edge_u) / edge_u.length_squared(),
                        q.dot(*edge_v) / edge_v.length_squared(),
                    );
                    let tol = 1e-6;
                    (t > 0.0 && a > -tol && a < 1.0 + tol && b > -tol && b < 1.0 + tol)
                        .then_some(Some(p))
                }
            }
        };
        if let Some(t) = target {
            return Some((t, light.name.clone()));
        }
    }
    None
}

/// Pixel mapping of the plot: world slice coordinates (u, v) ↔ pixels (y down).
#[derive(Debug, Clone, Copy)]
pub(in crate::viz) struct View {
    /// Plot rectangle [x0, y0, x1, y1] in pixels.
    pub(in crate::viz) rect: [f32; 4],
    pub(in crate::viz) center: (f64, f64),
    pub(in crate::viz) scale: f64,
}

impl View {
    pub(super) fn px(&self, (u, v): (f64, f64)) -> (f32, f32) {
        let cx = (self.rect[0] + self.rect[2]) as f64 / 2.0;
        let cy = (self.rect[1] + self.rect[3]) as f64 / 2.0;
        (
            (cx + (u - self.center.0) * self.scale) as f32,
            (cy - (v - self.center.1) * self.scale) as f32,
        )
    }
    pub(in crate::viz) fn uv(&self, (x, y): (f64, f64)) -> (f64, f64) {
        let cx = (self.rect[0] + self.rect[2]) as f64 / 2.0;
        let cy = (self.rect[1] + self.rect[3]) as f64 / 2.0;
        (
            self.center.0 + (x - cx) / self.scale,
            self.center.1 - (y - cy) / self.scale,
        )
    }
}

/// Clips segment a→b to a rectangle (Liang–Barsky); `None` when it lies outside.
pub(crate) fn clip(a: (f32, f32), b: (f32, f32), r: [f32; 4]) -> Option<((f32, f32), (f32, f32))> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f32, 1.0f32);
    for (p, q) in [
        (-dx, a.0 - r[0]),
        (dx, r[2] - a.0),
        (-dy, a.1 - r[1]),
        (dy, r[3] - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let t = q / p;
            if p < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
        }
    }
    (t0 <= t1).then_some((
        (a.0 + dx * t0, a.1 + dy * t0),
        (a.0 + dx * t1, a.1 + dy * t1),
    ))
}
