//! The 2D view each shape's figure is drawn in (the module above lists them), fitted around
//! the shape, the ray's origin and every candidate root.

use super::PLOT;
use crate::report::intersect::Report;
use crate::shapes::working::short;
use crate::shapes::Shape;
use glam::DVec3;

/// A 2D view: a projection of 3D points and the fitted pixel mapping.
pub(super) struct View {
    origin: DVec3,
    e1: DVec3,
    e2: DVec3,
    center: (f64, f64),
    pub(super) scale: f64,
}

impl View {
    fn new(origin: DVec3, e1: DVec3, e2: DVec3) -> View {
        View {
            origin,
            e1,
            e2,
            center: (0.0, 0.0),
            scale: 1.0,
        }
    }
    pub(super) fn uv(&self, p: DVec3) -> (f64, f64) {
        let q = p - self.origin;
        (q.dot(self.e1), q.dot(self.e2))
    }
    pub(super) fn px_uv(&self, (u, v): (f64, f64)) -> (f32, f32) {
        let cx = (PLOT[0] + PLOT[2]) as f64 / 2.0;
        let cy = (PLOT[1] + PLOT[3]) as f64 / 2.0;
        (
            (cx + (u - self.center.0) * self.scale) as f32,
            (cy - (v - self.center.1) * self.scale) as f32,
        )
    }
    pub(super) fn px(&self, p: DVec3) -> (f32, f32) {
        self.px_uv(self.uv(p))
    }
    /// Fits the plot around `pts` (in view coordinates) with a margin.
    fn fit(&mut self, pts: &[(f64, f64)]) {
        let b = pts
            .iter()
            .fold((f64::MAX, f64::MAX, f64::MIN, f64::MIN), |b, p| {
                (b.0.min(p.0), b.1.min(p.1), b.2.max(p.0), b.3.max(p.1))
            });
        let ext = (b.2 - b.0).max(b.3 - b.1).max(1e-9);
        let (w, h) = ((b.2 - b.0).max(ext * 0.3), (b.3 - b.1).max(ext * 0.3));
        let (w, h) = (w * 1.2 + ext * 0.05, h * 1.2 + ext * 0.05);
        self.center = ((b.0 + b.2) / 2.0, (b.1 + b.3) / 2.0);
        let (pw, ph) = ((PLOT[2] - PLOT[0]) as f64, (PLOT[3] - PLOT[1]) as f64);
        self.scale = (pw / w).min(ph / h);
    }
    /// The view-space rectangle the plot shows.
    pub(super) fn bounds(&self) -> (f64, f64, f64, f64) {
        let hw = (PLOT[2] - PLOT[0]) as f64 / 2.0 / self.scale;
        let hh = (PLOT[3] - PLOT[1]) as f64 / 2.0 / self.scale;
        (
            self.center.0 - hw,
            self.center.1 - hh,
            self.center.0 + hw,
            self.center.1 + hh,
        )
    }
}

fn perpendicular(v: DVec3) -> DVec3 {
    let seed = if v.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
    (seed - v * v.dot(seed)).normalize()
}

/// The side view's horizontal axis: the ray's horizontal direction (x when it is vertical).
fn side_axes(r: &Report) -> (DVec3, DVec3) {
    let d = r.ray3.dir;
    let h = DVec3::new(d.x, 0.0, d.z)
        .try_normalize()
        .unwrap_or(DVec3::X);
    let across = DVec3::new(-h.z, 0.0, h.x);
    (h, across)
}

/// How far the ray's vertical plane is from the axis.
pub(super) fn side_offset(r: &Report) -> f64 {
    let (_, across) = side_axes(r);
    r.ray3.origin.dot(across)
}

/// The two axes a box figure shows (dropping the one the ray moves least along).
pub(super) fn box_axes(r: &Report) -> (usize, usize, usize) {
    let d = r.ray3.dir.abs();
    let drop = if d.x <= d.y && d.x <= d.z {
        0
    } else if d.y <= d.z {
        1
    } else {
        2
    };
    match drop {
        0 => (2, 1, 0), // look along x: z right, y up
        1 => (0, 2, 1), // look along y: x right, z up
        _ => (0, 1, 2), // look along z: x right, y up
    }
}

/// The view of `r`'s figure, fitted (the shape's extent, the origin, every candidate), and
/// the figure's title.
pub(super) fn fitted(r: &Report) -> (View, String) {
    let (mut v, title) = view_for(r);
    let mut pts: Vec<(f64, f64)> = vec![v.uv(r.ray3.origin)];
    for cand in &r.candidates {
        let p = r.ray3.at(cand.t);
        pts.push(v.uv(p));
    }
    if let Some(h) = &r.hit {
        pts.push(v.uv(r.ray3.at(h.t)));
    }
    match &r.solid {
        Shape::Sphere(s) => {
            let c0 = v.uv(s.center);
            pts.push((c0.0 - s.radius, c0.1 - s.radius));
            pts.push((c0.0 + s.radius, c0.1 + s.radius));
        }
        Shape::Plane(_) => pts.push((0.0, 0.0)),
        Shape::Cylinder(cy) => {
            pts.push((-cy.radius, cy.y_min));
            pts.push((cy.radius, cy.y_max));
        }
        Shape::Cone(k) => {
            let w = k.slope * k.y_min.abs().max(k.y_max.abs());
            pts.push((-w, k.y_min));
            pts.push((w, k.y_max));
        }
        Shape::Box(b) => {
            pts.push(v.uv(b.min));
            pts.push(v.uv(b.max));
        }
        Shape::Triangle(t) => pts.extend(t.v.iter().map(|p| v.uv(*p))),
        Shape::Mesh(_) | Shape::Csg(_) | Shape::Blob(_) => {}
    }
    v.fit(&pts);
    (v, title)
}

/// The view that shows `r`'s working and the figure's title, before fitting.
fn view_for(r: &Report) -> (View, String) {
    let p = r.ray3.origin;
    let d = r.ray3.dir;
    match &r.solid {
        Shape::Sphere(_) if r.is_2d() => (
            View::new(DVec3::ZERO, DVec3::X, DVec3::Y),
            "circle: the ray P + t·d against (x − cx)² + (y − cy)² = r²".to_string(),
        ),
        Shape::Sphere(s) => {
            let e1 = d.normalize();
            let to_c = s.center - p;
            let e2 = (to_c - e1 * to_c.dot(e1))
                .try_normalize()
                .unwrap_or_else(|| perpendicular(e1));
            (
                View::new(p, e1, e2),
                "sphere, cut by the plane through the ray and the centre".to_string(),
            )
        }
        Shape::Plane(pl) => {
            let n = pl.normal;
            let h = (d - n * n.dot(d))
                .try_normalize()
                .unwrap_or_else(|| perpendicular(n));
            (
                View::new(pl.point, h, n),
                "plane, seen edge-on (the view contains the normal and the ray)".to_string(),
            )
        }
        Shape::Cylinder(_) | Shape::Cone(_) => {
            let (h, across) = side_axes(r);
            let what = if matches!(r.solid, Shape::Cylinder(_)) {
                "cylinder"
            } else {
                "cone"
            };
            let m = p.dot(across);
            (
                View::new(across * m, h, DVec3::Y),
                format!(
                    "{what}, side view: the vertical plane of the ray ({} from the axis)",
                    short(m.abs())
                ),
            )
        }
        Shape::Box(_) => {
            let (a1, a2, a0) = box_axes(r);
            let mut e1 = DVec3::ZERO;
            e1[a1] = 1.0;
            let mut e2 = DVec3::ZERO;
            e2[a2] = 1.0;
            let names = ["x", "y", "z"];
            (
                View::new(DVec3::ZERO, e1, e2),
                format!(
                    "box, looking along {} ({} right, {} up): a root counts where the slabs overlap",
                    names[a0], names[a1], names[a2]
                ),
            )
        }
        Shape::Triangle(t) => {
            let (e1, e2) = {
                let u = t.v[1] - t.v[0];
                let n = u.cross(t.v[2] - t.v[0]);
                match (u.try_normalize(), n.try_normalize()) {
                    (Some(e1), Some(n)) => (e1, n.cross(e1)),
                    _ => {
                        let e1 = [t.v[1] - t.v[0], t.v[2] - t.v[0], t.v[2] - t.v[1]]
                            .into_iter()
                            .max_by(|a, b| a.length().total_cmp(&b.length()))
                            .and_then(|e| e.try_normalize())
                            .unwrap_or(DVec3::X);
                        (e1, perpendicular(e1))
                    }
                }
            };
            (
                View::new(t.v[0], e1, e2),
                "triangle, in its own plane: each weight is the area opposite its corner"
                    .to_string(),
            )
        }
        Shape::Mesh(_) | Shape::Csg(_) | Shape::Blob(_) => {
            (View::new(DVec3::ZERO, DVec3::X, DVec3::Y), "mesh".into())
        }
    }
}
