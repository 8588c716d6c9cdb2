//! The bundle figure: one 4×4 bundle of camera rays over a mesh's BVH, seen from above
//! (the mesh's own x–z plane, y dropped): the boxes the bundle opened, the ones it culled
//! because every one of its rays missed them, and the rays up to their hits.

use super::canvas::{Anchor, Canvas};
use super::style;
use crate::accel::{BundleWork, BUNDLE};
use crate::math::Ray;
use crate::sampling::bundles::SIDE;
use crate::scene::Scene;
use crate::shapes::{Aabb, Shape};
use crate::trace::camera_ray;
use glam::{DVec2, DVec3};

/// Figure size in pixels.
const W: f32 = 760.0;
const H: f32 = 620.0;
/// Levels of the tree drawn below the root (deeper boxes are too small to read).
const LEVELS: usize = 2;

/// Draws the bundle of pixel (x, y): the 4×4 block of pixels holding it, one camera ray
/// through each pixel centre, walking the first mesh of the scene.
pub fn draw(scene: &Scene, x: u32, y: u32) -> Result<Canvas, String> {
    let (object, mesh) = scene
        .objects
        .iter()
        .find_map(|o| match &o.shape {
            Shape::Mesh(m) => Some((o, m)),
            _ => None,
        })
        .ok_or("the bundle figure needs a scene with a mesh")?;
    let (w, h) = (scene.camera.width, scene.camera.height);
    let (x0, y0) = (x / SIDE * SIDE, y / SIDE * SIDE);
    let mut rays: Vec<Ray> = Vec::with_capacity(BUNDLE);
    for py in y0..(y0 + SIDE).min(h) {
        for px in x0..(x0 + SIDE).min(w) {
            let film = DVec2::new(px as f64 + 0.5, py as f64 + 0.5);
            let world = camera_ray(scene, &scene.render, px, py, 0, film).ray;
            rays.push(object.transform.ray_to_object(&world));
        }
    }
    let n = rays.len();
    // The walk itself, recording every tested child: (node, lane) -> rays that entered it.
    let mut tested: Vec<(usize, usize, u32)> = Vec::new();
    let mut work = BundleWork::default();
    let mut tests = [0u32; BUNDLE];
    let mut hits = [None; BUNDLE];
    mesh.intersect_bundle_seen(
        &rays,
        (1u32 << n) - 1,
        0.0,
        [f64::INFINITY; BUNDLE],
        &mut work,
        &mut tests,
        |node, lane, mask| tested.push((node, lane, mask)),
        |i, hit| hits[i] = Some(hit),
    );
    // Depth of each node (root 0), from the tree itself.
    let nodes = &mesh.bvh.nodes;
    let mut depth = vec![usize::MAX; nodes.len()];
    if !nodes.is_empty() {
        depth[0] = 0;
        for i in 0..nodes.len() {
            for lane in 0..crate::accel::WIDTH {
                if !nodes[i].is_empty(lane) && nodes[i].count[lane] == 0 {
                    depth[nodes[i].child[lane] as usize] = depth[i] + 1;
                }
            }
        }
    }

    // The view: the mesh's box, with a margin, in object x (right) and z (down).
    let b = mesh.bounds;
    let (lo, hi) = (DVec2::new(b.min.x, b.min.z), DVec2::new(b.max.x, b.max.z));
    let (top, side, bottom) = (96.0f32, 30.0f32, 70.0f32);
    let span = (hi - lo).max_element() * 1.15;
    let scale = ((W - 2.0 * side) as f64 / span).min((H - top - bottom) as f64 / span);
    let centre = (lo + hi) * 0.5;
    let mid = ((W / 2.0) as f64, ((top + H - bottom) / 2.0) as f64);
    let map = |p: DVec3| -> (f32, f32) {
        (
            (mid.0 + (p.x - centre.x) * scale) as f32,
            (mid.1 + (p.z - centre.y) * scale) as f32,
        )
    };
    let mut c = Canvas::new(W as u32, H as u32, style::background());
    let culled_color = style::tossed();
    let opened_color = style::shape_stroke();
    let draw_box = |c: &mut Canvas, bx: &Aabb, opened: bool, d: usize| {
        let a = map(bx.min);
        let z = map(bx.max);
        let (min, size) = (
            (a.0.min(z.0), a.1.min(z.1)),
            ((z.0 - a.0).abs(), (z.1 - a.1).abs()),
        );
        if opened {
            let fill = style::rgba(90, 140, 200, 22 + 10 * d as u8);
            c.rect(min, size, Some((opened_color, 1.6)), Some(fill));
        } else {
            let (x1, y1) = (min.0 + size.0, min.1 + size.1);
            for (p, q) in [
                ((min.0, min.1), (x1, min.1)),
                ((x1, min.1), (x1, y1)),
                ((x1, y1), (min.0, y1)),
                ((min.0, y1), (min.0, min.1)),
            ] {
                c.line(p, q, culled_color, 1.3, true);
            }
        }
    };
    // The root, then the tested children down to LEVELS: culled ones first, under the opened.
    draw_box(&mut c, &b, true, 0);
    let shown = |&&(node, _, _): &&(usize, usize, u32)| depth[node] < LEVELS;
    let (mut opened, mut culled) = (0, 0);
    for &(node, lane, mask) in tested.iter().filter(shown) {
        if mask == 0 {
            draw_box(&mut c, &nodes[node].bounds(lane), false, depth[node] + 1);
            culled += 1;
        }
    }
    for &(node, lane, mask) in tested.iter().filter(shown) {
        if mask != 0 {
            draw_box(&mut c, &nodes[node].bounds(lane), true, depth[node] + 1);
            opened += 1;
        }
    }
    // The rays: from where they enter the view to their hit (or across the view).
    let ray_color = style::ray(crate::trace::RayKind::Camera);
    let far = span * 3.0;
    for (i, r) in rays.iter().enumerate() {
        let t_end = hits[i].map_or(far + r.origin.distance(b.centroid()), |h| h.t);
        // Enter the drawn square (the view's x–z extent) by a 2D slab test.
        let half = span / 2.0 * 1.05;
        let (mut t_start, mut t_stop) = (0.0f64, f64::INFINITY);
        for (o, d, c) in [
            (r.origin.x, r.dir.x, centre.x),
            (r.origin.z, r.dir.z, centre.y),
        ] {
            let (a, z) = ((c - half - o) / d, (c + half - o) / d);
            t_start = t_start.max(a.min(z));
            t_stop = t_stop.min(a.max(z));
        }
        let t_end = t_end.min(t_stop);
        if t_start >= t_end {
            continue;
        }
        c.line(map(r.at(t_start)), map(r.at(t_end)), ray_color, 1.0, false);
        if let Some(hit) = hits[i].filter(|h| h.t <= t_stop) {
            c.circle(
                map(r.at(hit.t)),
                3.0,
                Some((ray_color, 1.0)),
                Some(ray_color),
            );
        }
    }
    // Title and legend.
    let hit_count = hits.iter().flatten().count();
    c.text(
        (side, 22.0),
        &format!(
            "A bundle of {n} camera rays (pixels {x0}..{}, {y0}..{}) over the mesh's BVH, seen from above",
            x0 + SIDE - 1,
            y0 + SIDE - 1
        ),
        15.0,
        style::ink(),
        Anchor::Left,
    );
    c.text(
        (side, 44.0),
        &format!(
            "object-space x (right) and z (down); the root box and {LEVELS} levels below it; {hit_count} of {n} rays hit"
        ),
        12.0,
        style::muted(),
        Anchor::Left,
    );
    let (lx, ly) = (side, 70.0);
    c.rect(
        (lx, ly - 6.0),
        (22.0, 12.0),
        Some((opened_color, 1.6)),
        Some(style::rgba(90, 140, 200, 40)),
    );
    c.text(
        (lx + 30.0, ly),
        &format!("opened: some ray of the bundle enters it ({opened})"),
        12.0,
        style::ink(),
        Anchor::Left,
    );
    let lx2 = lx + 330.0;
    c.line((lx2, ly), (lx2 + 22.0, ly), culled_color, 1.3, true);
    c.text(
        (lx2 + 30.0, ly),
        &format!("culled: every ray misses it ({culled})"),
        12.0,
        style::ink(),
        Anchor::Left,
    );
    c.text(
        (W - side, H - 14.0),
        &format!(
            "whole walk: {} nodes opened for the bundle, {} slab tests of single rays",
            work.opened,
            work.ray_nodes.iter().sum::<u32>()
        ),
        12.0,
        style::muted(),
        Anchor::Right,
    );
    c.text(
        (side, H - 14.0),
        "the rays come from the camera (bottom)",
        12.0,
        style::muted(),
        Anchor::Left,
    );
    Ok(c)
}
