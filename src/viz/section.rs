//! The objects of a scene cut by a slice plane, as pixel masks: sampled with one line per
//! pixel row and one per pixel column, each intersected with every object by the shape's own
//! routine (the very code the tracer runs), peeling one crossing after another.

use super::slice::{Frame, View};
use super::style;
use crate::math::Ray;
use crate::scene::{Object, Scene};
use crate::shapes::{NoObserver, Shape};
use tiny_skia::Color;

/// Every crossing of an infinite line with an object, smallest t first, found by the shape's
/// own intersection routine: ask for the closest hit after `t_min`, then move `t_min` past it.
fn crossings(object: &Object, ray: &Ray, limit: f64, eps: f64) -> Vec<f64> {
    let local = object.transform.ray_to_object(ray);
    let mut out = Vec::new();
    let mut t_min = -limit;
    for _ in 0..64 {
        match object
            .shape
            .intersect(&local, t_min, limit, &mut NoObserver)
        {
            Some(h) if h.t.is_finite() => {
                out.push(h.t);
                t_min = h.t + eps;
            }
            _ => break,
        }
    }
    out
}

/// True for shapes whose crossings alternate outside/inside along any line.
fn is_solid(shape: &Shape) -> bool {
    match shape {
        Shape::Sphere(_) | Shape::Box(_) | Shape::Csg(_) | Shape::Blob(_) => true,
        Shape::Cylinder(c) => c.capped,
        Shape::Cone(c) => c.capped,
        Shape::Plane(_) | Shape::Triangle(_) | Shape::Mesh(_) => false,
    }
}

/// One object's cut by the slice plane, as pixel masks.
pub(super) struct Section {
    pub(super) name: String,
    pub(super) fill: Vec<bool>,
    pub(super) edge: Vec<bool>,
    pub(super) fill_color: Color,
    pub(super) edge_color: Color,
    pub(super) is_plane: bool,
    pub(super) edge_bounds: Option<[u32; 4]>,
    /// The two extreme pixels of the cut along its longer direction (for labels).
    pub(super) ends: ((u32, u32), (u32, u32)),
}

/// Samples every object with the lines of the plot's pixel rows and columns.
pub(super) fn sections(
    scene: &Scene,
    frame: &Frame,
    view: &View,
    width: u32,
    height: u32,
) -> Vec<Section> {
    let [x0, y0, x1, y1] = view.rect.map(|v| v.round() as i64);
    let (w, h) = (width as i64, height as i64);
    let scale = view.scale;
    let extent = (x1 - x0).max(y1 - y0) as f64 / scale;
    let limit = 1e6 * extent.max(1.0);
    let eps = 1e-6 * extent;
    let mut out = Vec::new();
    for o in &scene.objects {
        let mut fill = vec![false; (w * h) as usize];
        let mut edge = vec![false; (w * h) as usize];
        let solid = is_solid(&o.shape);
        let mark = |m: &mut Vec<bool>, x: i64, y: i64| {
            if x >= x0 && x < x1 && y >= y0 && y < y1 {
                m[(y * w + x) as usize] = true;
            }
        };
        // Rows: lines along e1 through each pixel row's centre, starting at the left edge.
        for y in y0..y1 {
            let (u, v) = view.uv((x0 as f64, y as f64 + 0.5));
            let ray = Ray::new(frame.to3(u, v), frame.e1);
            let ts = crossings(o, &ray, limit, eps);
            for &t in &ts {
                let x = x0 as f64 + t * scale - 0.5;
                mark(&mut edge, x.floor() as i64, y);
                mark(&mut edge, x.floor() as i64 + 1, y);
            }
            if solid && ts.len().is_multiple_of(2) {
                for pair in ts.chunks(2) {
                    let a = (x0 as f64 + pair[0] * scale - 0.5).ceil() as i64;
                    let b = (x0 as f64 + pair[1] * scale - 0.5).floor() as i64;
                    for x in a.max(x0)..=b.min(x1 - 1) {
                        mark(&mut fill, x, y);
                    }
                }
            }
        }
        // Columns: lines along e2 (up) through each pixel column's centre, from the bottom.
        for x in x0..x1 {
            let (u, v) = view.uv((x as f64 + 0.5, y1 as f64));
            let ray = Ray::new(frame.to3(u, v), frame.e2);
            for t in crossings(o, &ray, limit, eps) {
                let y = y1 as f64 - t * scale - 0.5;
                mark(&mut edge, x, y.floor() as i64);
                mark(&mut edge, x, y.floor() as i64 + 1);
            }
        }
        let is_plane = matches!(o.shape, Shape::Plane(_));
        if let Shape::Plane(p) = &o.shape {
            // The side behind the plane (against its normal), lightly: "the floor".
            let q = o.transform.point_to_world(p.point);
            let n = o.transform.normal_to_world(p.normal);
            for y in y0..y1 {
                for x in x0..x1 {
                    let (u, v) = view.uv((x as f64 + 0.5, y as f64 + 0.5));
                    if n.dot(frame.to3(u, v) - q) < 0.0 {
                        mark(&mut fill, x, y);
                    }
                }
            }
        }
        let mut bounds: Option<[u32; 4]> = None;
        let mut ext = [(u32::MAX, 0u32), (0, 0), (0, u32::MAX), (0, 0)]; // min x, max x, min y, max y
        for (i, _) in edge.iter().enumerate().filter(|(_, e)| **e) {
            let (x, y) = ((i as i64 % w) as u32, (i as i64 / w) as u32);
            let b = bounds.get_or_insert([x, y, x, y]);
            *b = [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)];
            if x < ext[0].0 {
                ext[0] = (x, y);
            }
            if x > ext[1].0 {
                ext[1] = (x, y);
            }
            if y < ext[2].1 {
                ext[2] = (x, y);
            }
            if y > ext[3].1 {
                ext[3] = (x, y);
            }
        }
        let ends = match bounds {
            Some(b) if b[2] - b[0] >= b[3] - b[1] => (ext[0], ext[1]),
            _ => (ext[2], ext[3]),
        };
        if bounds.is_none() && !fill.iter().any(|f| *f) {
            continue;
        }
        let (fill_color, edge_color) = if is_plane {
            (style::rgba(120, 120, 130, 30), style::rgb(110, 110, 120))
        } else {
            (style::shape_fill(), style::shape_stroke())
        };
        out.push(Section {
            name: o.name.clone(),
            fill,
            edge,
            fill_color,
            edge_color,
            is_plane,
            edge_bounds: bounds,
            ends,
        });
    }
    out
}
