//! The ray tree of one pixel drawn in a 2D slice of the scene (DESIGN §6).
//!
//! The slice is the plane through the camera ray and the camera's up vector (the default), or
//! through the camera ray and its first bounce. Every ray of the tree is projected onto it;
//! a ray that leaves the plane is drawn dashed. The objects are cut by the plane by *sampling
//! them with rays that lie in the plane*: one line per pixel row and one per pixel column of
//! the figure, each intersected with every object by the shape's own routine (the very code
//! the tracer runs), peeling one crossing after another. Closed solids are filled between
//! pairs of crossings; open surfaces, triangles and meshes are drawn as outlines.
//!
//! Public API (used by `explain --diagram` and by `steps` for its storyboard):
//! [`draw`], [`event_count`], [`SliceOptions`], [`SlicePlane`].

use super::labels::{around, beside, Labels};
use super::section::sections;
use super::style;
use super::{Anchor, Canvas};
use crate::error::{Error, Result};
use crate::scene::Scene;
use crate::shading::LightKind;
use crate::trace::{End, RayKind, RayNode};
use glam::DVec3;
use tiny_skia::Color;

/// Which plane the slice lies in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SlicePlane {
    /// Through the camera ray and the camera's up vector (a side view of the pixel's ray).
    #[default]
    Camera,
    /// Through the camera ray and the bounce it spawned that carries the most (the
    /// refraction of glass, the reflection of a mirror); falls back to `Camera` when there is
    /// no bounce or it continues straight on.
    Bounce,
}

impl SlicePlane {
    pub const NAMES: [&'static str; 2] = ["camera", "bounce"];
    pub fn parse(s: &str) -> Option<SlicePlane> {
        match s {
            "camera" => Some(SlicePlane::Camera),
            "bounce" => Some(SlicePlane::Bounce),
            _ => None,
        }
    }
}

/// How to draw a slice.
#[derive(Debug, Clone, PartialEq)]
pub struct SliceOptions {
    /// Figure size in pixels (each at least 160×120).
    pub width: u32,
    pub height: u32,
    pub plane: SlicePlane,
    /// Draw only the first k events of the ray tree (see [`event_count`]); `None`: all.
    /// The last event drawn is emphasised, so a storyboard shows what each frame added.
    pub events: Option<usize>,
    /// What the figure shows (e.g. "pixel (120, 80)"), written before the title line that
    /// says which plane this is.
    pub caption: Option<String>,
    /// Emphasise event k (0-based, counted as [`event_count`] counts them) among all those
    /// drawn: the ray a user picked in a ray tree (`rtlab serve`).
    pub highlight: Option<usize>,
}

impl Default for SliceOptions {
    fn default() -> Self {
        SliceOptions {
            width: 720,
            height: 480,
            plane: SlicePlane::Camera,
            events: None,
            caption: None,
            highlight: None,
        }
    }
}

/// The number of events of a ray tree: one per ray (the ray, with its hit or miss), counted
/// in the order the tracer cast them (depth first: a ray, then its shadow rays, reflection
/// and refraction subtrees). `events: Some(k)` draws the first k of them.
pub fn event_count(tree: &RayNode) -> usize {
    1 + tree.children.iter().map(event_count).sum::<usize>()
}

fn preorder<'a>(n: &'a RayNode, out: &mut Vec<&'a RayNode>) {
    out.push(n);
    for c in &n.children {
        preorder(c, out);
    }
}

/// An orthonormal frame of the slice plane: `origin` + u·e1 + v·e2.
#[derive(Debug, Clone, Copy)]
pub(super) struct Frame {
    pub(super) origin: DVec3,
    pub(super) e1: DVec3,
    pub(super) e2: DVec3,
    pub(super) normal: DVec3,
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
    fn to2(&self, p: DVec3) -> (f64, f64) {
        let q = p - self.origin;
        (q.dot(self.e1), q.dot(self.e2))
    }
    pub(super) fn to3(&self, u: f64, v: f64) -> DVec3 {
        self.origin + self.e1 * u + self.e2 * v
    }
    /// How far a direction leaves the plane: |sin| of its angle with the plane.
    fn off_plane(&self, d: DVec3) -> f64 {
        d.normalize_or_zero().dot(self.normal).abs()
    }
}

/// The plane actually used and why.
fn choose_frame(scene: &Scene, tree: &RayNode, plane: SlicePlane) -> (Frame, &'static str) {
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
fn shadow_target(scene: &Scene, ray: &RayNode) -> Option<(Option<DVec3>, String)> {
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
pub(super) struct View {
    /// Plot rectangle [x0, y0, x1, y1] in pixels.
    pub(super) rect: [f32; 4],
    pub(super) center: (f64, f64),
    pub(super) scale: f64,
}

impl View {
    fn px(&self, (u, v): (f64, f64)) -> (f32, f32) {
        let cx = (self.rect[0] + self.rect[2]) as f64 / 2.0;
        let cy = (self.rect[1] + self.rect[3]) as f64 / 2.0;
        (
            (cx + (u - self.center.0) * self.scale) as f32,
            (cy - (v - self.center.1) * self.scale) as f32,
        )
    }
    pub(super) fn uv(&self, (x, y): (f64, f64)) -> (f64, f64) {
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

/// A drawn ray: its node and where it starts and ends in the plane.
struct Drawn<'a> {
    node: &'a RayNode,
    start: DVec3,
    /// The hit (or the blocker of a shadow ray).
    end: Option<DVec3>,
    /// A shadow ray's light: its position (None for directional) and name.
    light: Option<(Option<DVec3>, String)>,
}

fn t_label(t: f64) -> String {
    format!("t = {}", crate::shapes::working::short(t))
}

/// Draws the ray tree `tree` (from explain's `TreeRecorder`) of `scene` in a slice.
///
/// Fails only on a figure size below 160×120. Deterministic: same inputs, same pixels.
pub fn draw(scene: &Scene, tree: &RayNode, opts: &SliceOptions) -> Result<Canvas> {
    if opts.width < 160 || opts.height < 120 || opts.width > 8192 || opts.height > 8192 {
        return Err(Error::arg(
            "--diagram",
            format!(
                "a slice figure is between 160×120 and 8192×8192 pixels, not {}×{}",
                opts.width, opts.height
            ),
        ));
    }
    let (frame, plane_note) = choose_frame(scene, tree, opts.plane);
    let mut all = Vec::new();
    preorder(tree, &mut all);
    let k = opts.events.unwrap_or(all.len()).min(all.len());
    let every: Vec<Drawn> = all
        .iter()
        .map(|n| Drawn {
            node: n,
            start: n.origin,
            end: n.hit.as_ref().map(|h| h.point),
            light: (n.kind == RayKind::Shadow)
                .then(|| shadow_target(scene, n))
                .flatten(),
        })
        .collect();
    let events = &every[..k];

    // The window: the eye, the camera ray's hit and the object it hit make the core; the
    // other rays' ends and lights join when they are not far outside it (rays to farther
    // points are cut at the figure's edge, which keeps the first hit readable).
    let bbox = |pts: &[(f64, f64)]| {
        pts.iter()
            .fold((f64::MAX, f64::MAX, f64::MIN, f64::MIN), |b, p| {
                (b.0.min(p.0), b.1.min(p.1), b.2.max(p.0), b.3.max(p.1))
            })
    };
    let eye2 = frame.to2(tree.origin);
    let mut pts: Vec<(f64, f64)> = vec![eye2];
    match &tree.hit {
        Some(h) => {
            pts.push(frame.to2(h.point));
            let reach = (h.point - tree.origin).length();
            if let Some(b) = scene
                .objects
                .iter()
                .find(|o| o.name == h.object)
                .and_then(|o| o.bounds)
            {
                let c: Vec<(f64, f64)> = b.corners().iter().map(|p| frame.to2(*p)).collect();
                let cb = bbox(&c);
                if (cb.2 - cb.0).max(cb.3 - cb.1) < 1.5 * reach {
                    pts.extend(c);
                }
            }
        }
        None => pts.push(frame.to2(tree.origin + tree.direction.normalize_or_zero() * 4.0)),
    }
    let core = bbox(&pts);
    let core_extent = (core.2 - core.0).max(core.3 - core.1).max(1e-6);
    let core_center = ((core.0 + core.2) / 2.0, (core.1 + core.3) / 2.0);
    let near =
        |p: (f64, f64)| (p.0 - core_center.0).hypot(p.1 - core_center.1) <= 1.3 * core_extent;
    // Every event, drawn or not: a storyboard (`events: Some(k)`) keeps one view throughout.
    for e in &every {
        let mut ends = vec![frame.to2(e.start)];
        if let Some(p) = e.end {
            ends.push(frame.to2(p));
        }
        if let Some((Some(p), _)) = &e.light {
            ends.push(frame.to2(*p));
        }
        pts.extend(ends.into_iter().filter(|p| near(*p)));
    }
    let b = bbox(&pts);
    let (mut w, mut h) = (b.2 - b.0, b.3 - b.1);
    let extent = w.max(h);
    let extent = if extent < 1e-6 { 4.0 } else { extent };
    w = w.max(extent * 0.35);
    h = h.max(extent * 0.35);
    let (w, h) = (w * 1.16 + extent * 0.04, h * 1.16 + extent * 0.04);
    let center = ((b.0 + b.2) / 2.0, (b.1 + b.3) / 2.0);

    // Legend entries first: they decide how tall the bottom band is. They cover the whole
    // tree, so a storyboard's frames keep one layout (and the legend says what is coming).
    let mut kinds: Vec<RayKind> = Vec::new();
    let (mut any_blocked, mut any_off, mut any_hit) = (false, false, false);
    for e in &every {
        if !kinds.contains(&e.node.kind) {
            kinds.push(e.node.kind);
        }
        any_blocked |= e.node.end == End::Blocked;
        any_off |= frame.off_plane(e.node.direction) > 0.03;
        any_hit |= e.node.hit.is_some() && e.node.kind != RayKind::Shadow;
    }
    kinds.sort_by_key(|k| *k as u8);
    let (fw, fh) = (opts.width as f32, opts.height as f32);
    let legend = legend_items(&kinds, any_blocked, any_off, any_hit);
    let legend_rows = layout_legend(&legend, fw - 20.0);
    let legend_h = 18.0 * legend_rows.len() as f32 + 8.0;
    let rect = [10.0, 34.0, fw - 10.0, fh - legend_h - 6.0];
    let (pw, ph) = ((rect[2] - rect[0]) as f64, (rect[3] - rect[1]) as f64);
    let view = View {
        rect,
        center,
        scale: (pw / w).min(ph / h),
    };

    let mut canvas = Canvas::new(opts.width, opts.height, style::background());
    let mut labels = Labels::new([rect[0], rect[1], rect[2], rect[3]]);

    // Objects cut by the plane.
    let sections = sections(scene, &frame, &view, opts.width, opts.height);
    for s in &sections {
        canvas.mask(&format!("{} (inside)", s.name), &s.fill, s.fill_color);
    }
    for s in &sections {
        canvas.mask(&format!("{} (cut)", s.name), &s.edge, s.edge_color);
    }

    // Ray marks that labels must avoid.
    let eye = view.px(frame.to2(tree.origin));
    labels.block_point(eye, 6.0);
    for e in events {
        let a = view.px(frame.to2(e.start));
        let bpt = match (e.end, &e.light) {
            (Some(p), _) => Some(view.px(frame.to2(p))),
            (None, Some((Some(p), _))) => Some(view.px(frame.to2(*p))),
            _ => None,
        };
        if let Some(bp) = bpt {
            labels.block_point(bp, 6.0);
            let n = ((bp.0 - a.0).hypot(bp.1 - a.1) / 10.0).ceil() as usize;
            for i in 1..n {
                let f = i as f32 / n as f32;
                labels.block_point((a.0 + (bp.0 - a.0) * f, a.1 + (bp.1 - a.1) * f), 2.0);
            }
        }
    }

    let eye_label = [
        ((eye.0 - 9.0, eye.1), Anchor::Right),
        ((eye.0, eye.1 + 13.0), Anchor::Center),
        ((eye.0, eye.1 - 13.0), Anchor::Center),
    ];
    labels.place_any(&mut canvas, &eye_label, "eye", 12.0, style::ink());

    // Object names, before ray labels so these take the spots next to the rays.
    let hit_names: Vec<&str> = events
        .iter()
        .filter_map(|e| e.node.hit.as_ref().map(|h| h.object.as_str()))
        .collect();
    let mut labelled: Vec<String> = Vec::new();
    for s in &sections {
        let Some(bb) = s.edge_bounds else { continue };
        let (x0, y0, x1, y1) = (
            bb[0] as f32,
            bb[1] as f32,
            bb[2] as f32 + 1.0,
            bb[3] as f32 + 1.0,
        );
        let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
        let cands = if s.is_plane {
            // Beside the line, near one of its ends.
            let (p, q) = (s.ends.0, s.ends.1);
            let (p, q) = (
                (p.0 as f32 + 0.5, p.1 as f32 + 0.5),
                (q.0 as f32 + 0.5, q.1 as f32 + 0.5),
            );
            let mut c = Vec::new();
            for (end, other) in [(p, q), (q, p)] {
                let (dx, dy) = (other.0 - end.0, other.1 - end.1);
                let len = dx.hypot(dy).max(1.0);
                let at = (end.0 + dx / len * 30.0, end.1 + dy / len * 30.0);
                let (nx, ny) = (dy / len, -dx / len);
                for sgn in [1.0f32, -1.0] {
                    let o = (at.0 + nx * 11.0 * sgn, at.1 + ny * 11.0 * sgn);
                    let anchor = if (nx * sgn) > 0.3 {
                        Anchor::Left
                    } else if (nx * sgn) < -0.3 {
                        Anchor::Right
                    } else {
                        Anchor::Center
                    };
                    c.push((o, anchor));
                }
            }
            c
        } else {
            vec![
                ((cx, cy), Anchor::Center),
                ((cx, y0 - 9.0), Anchor::Center),
                ((cx, y1 + 9.0), Anchor::Center),
                ((x1 + 4.0, cy), Anchor::Left),
                ((x0 - 4.0, cy), Anchor::Right),
            ]
        };
        let color = if hit_names.contains(&s.name.as_str()) {
            style::shape_stroke()
        } else {
            style::muted()
        };
        if labels
            .place(&mut canvas, &cands, &s.name, 13.0, color)
            .is_some()
        {
            labelled.push(s.name.clone());
        }
    }

    // Lights.
    let mut lights_drawn: Vec<String> = Vec::new();
    for e in events {
        if let Some((Some(p), name)) = &e.light {
            if lights_drawn.contains(name) {
                continue;
            }
            lights_drawn.push(name.clone());
            let lp = view.px(frame.to2(*p));
            if clip(lp, lp, rect).is_some() {
                canvas.circle(
                    lp,
                    7.0,
                    Some((style::ray(RayKind::Shadow), 1.5)),
                    Some(style::rgb(255, 214, 90)),
                );
                labels.block_point(lp, 8.0);
                labels.place_any(
                    &mut canvas,
                    &around(lp, 11.0),
                    &format!("light {name}"),
                    12.0,
                    style::ink(),
                );
            }
        }
    }

    // Rays, in the order they were cast.
    let far = (fw + fh) as f64 * 4.0 / view.scale;
    let mut blockers: Vec<String> = Vec::new();
    for (i, e) in events.iter().enumerate() {
        let n = e.node;
        let color = style::ray(n.kind);
        let last = (opts.events.is_some() && i + 1 == events.len() && events.len() > 1)
            || opts.highlight == Some(i);
        let width = match (last, n.kind) {
            (true, _) => 3.6,
            (_, RayKind::Camera) => 2.4,
            (_, RayKind::Shadow) => 1.6,
            _ => 2.0,
        };
        let dashed = frame.off_plane(n.direction) > 0.03;
        let a = view.px(frame.to2(e.start));
        let dir = n.direction.normalize_or_zero();
        let (end, label) = match (e.end, &e.light) {
            (Some(p), _) => (p, Some(t_label(n.hit.as_ref().map_or(0.0, |h| h.t)))),
            (None, Some((Some(p), _))) => (*p, None),
            _ => (e.start + dir * far, None),
        };
        let bpx = view.px(frame.to2(end));
        if (bpx.0 - a.0).hypot(bpx.1 - a.1) < 1.5 && e.end.is_none() {
            // Straight out of the slice: a ring at its origin.
            canvas.circle(a, 5.0, Some((color, 1.6)), None);
            continue;
        }
        if let Some((ca, cb)) = clip(a, bpx, rect) {
            if dashed {
                canvas.line(ca, cb, color, width, true);
                if e.end.is_none() && e.light.is_none() {
                    canvas.arrow(cb, cb, color, width);
                }
            } else {
                canvas.arrow(ca, cb, color, width);
            }
            let cut = (cb.0 - bpx.0).hypot(cb.1 - bpx.1) > 1.0;
            if let Some(l) = &label {
                let mut text = l.clone();
                if let Some(h) = &n.hit {
                    if cut || !labelled.contains(&h.object) {
                        text = format!("{text} ({})", h.object);
                    }
                }
                labels.place(&mut canvas, &beside(ca, cb, 8.0), &text, 12.0, color);
            } else if let (true, Some((Some(_), name))) = (cut, &e.light) {
                // The light is beyond the figure's edge.
                labels.place(
                    &mut canvas,
                    &around(cb, 10.0),
                    &format!("to light {name}"),
                    12.0,
                    color,
                );
            } else if e.end.is_none() && e.light.is_none() && n.kind != RayKind::Shadow {
                // Beside the line a little before its end (the arrow head is at the edge).
                let (dx, dy) = (cb.0 - ca.0, cb.1 - ca.1);
                let l = dx.hypot(dy).max(1.0);
                let (ux, uy) = (dx / l, dy / l);
                let back = |k: f32| (cb.0 - ux * k.min(l), cb.1 - uy * k.min(l));
                let mut cands = beside(back(34.0), back(18.0), 9.0);
                cands.truncate(2);
                cands.extend(around(cb, 12.0));
                labels.place(&mut canvas, &cands, "miss", 12.0, color);
            }
        }
        // A blocked shadow ray: the rest of the way to its light, dotted, and a cross.
        if n.end == End::Blocked {
            if let Some(p) = e.end {
                let light_end = match &e.light {
                    Some((Some(l), _)) => *l,
                    _ => p + dir * far,
                };
                let lp = view.px(frame.to2(light_end));
                if let Some((ca, cb)) = clip(bpx, lp, rect) {
                    canvas.line(ca, cb, style::muted(), 1.4, true);
                }
                let x = bpx;
                let s = 5.0;
                if clip(x, x, rect).is_none() {
                    continue;
                }
                canvas.line(
                    (x.0 - s, x.1 - s),
                    (x.0 + s, x.1 + s),
                    style::hit(),
                    2.4,
                    false,
                );
                canvas.line(
                    (x.0 - s, x.1 + s),
                    (x.0 + s, x.1 - s),
                    style::hit(),
                    2.4,
                    false,
                );
                let by = n.hit.as_ref().map_or("?", |h| h.object.as_str());
                if blockers.iter().any(|b| b == by) {
                    continue;
                }
                blockers.push(by.to_string());
                labels.place(
                    &mut canvas,
                    &around(x, 10.0),
                    &format!("blocked by {by}"),
                    12.0,
                    style::hit(),
                );
            }
        } else if n.kind == RayKind::Shadow {
            if let Some((None, name)) = &e.light {
                if let Some((_, cb)) = clip(a, bpx, rect) {
                    labels.place(
                        &mut canvas,
                        &around(cb, 10.0),
                        &format!("to {name}"),
                        12.0,
                        color,
                    );
                }
            }
        }
        // The hit and its normal.
        if let (Some(p), Some(h)) = (e.end, &n.hit) {
            if n.kind != RayKind::Shadow {
                let hp = view.px(frame.to2(p));
                if clip(hp, hp, rect).is_some() {
                    let tip = view.px(frame.to2(p + h.normal * (26.0 / view.scale)));
                    if (tip.0 - hp.0).hypot(tip.1 - hp.1) > 4.0 {
                        canvas.arrow(hp, tip, style::normal(), 1.6);
                    }
                    canvas.circle(
                        hp,
                        4.0,
                        Some((style::background(), 1.2)),
                        Some(style::hit()),
                    );
                }
            }
        }
    }

    // The eye, drawn over the rays that leave it.
    canvas.circle(eye, 4.5, None, Some(style::ink()));

    // Title, scale bar, legend.
    let mut title = plane_note.to_string();
    if let Some(k) = opts.events {
        title = format!("{} of {} events · {title}", k.min(all.len()), all.len());
    }
    if let Some(k) = opts.highlight.filter(|&k| k < all.len()) {
        title = format!("ray {} of {} in bold · {title}", k + 1, all.len());
    }
    if let Some(c) = &opts.caption {
        title = format!("{c} · {title}");
    }
    canvas.text((fw / 2.0, 17.0), &title, 13.0, style::ink(), Anchor::Center);
    scale_bar(&mut canvas, &view);
    draw_legend(&mut canvas, &legend_rows, fh - legend_h + 2.0);
    Ok(canvas)
}

/// A "1 unit" style bar in the plot's lower-left corner, with a round length.
fn scale_bar(canvas: &mut Canvas, view: &View) {
    let target = 90.0 / view.scale;
    let p = 10f64.powf(target.log10().floor());
    let len = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * p)
        .rfind(|l| l * view.scale <= 120.0)
        .unwrap_or(p);
    let px = (len * view.scale) as f32;
    let (x, y) = (view.rect[0] + 8.0, view.rect[3] - 8.0);
    canvas.line((x, y), (x + px, y), style::ink(), 1.5, false);
    canvas.line((x, y - 4.0), (x, y + 1.0), style::ink(), 1.5, false);
    canvas.line(
        (x + px, y - 4.0),
        (x + px, y + 1.0),
        style::ink(),
        1.5,
        false,
    );
    let units = if len == 1.0 { "unit" } else { "units" };
    canvas.text(
        (x + px + 6.0, y - 2.0),
        &format!("{} {units}", crate::shapes::working::short(len)),
        11.0,
        style::ink(),
        Anchor::Left,
    );
}

#[derive(Debug, Clone)]
enum LegendMark {
    Ray(Color, bool),
    Cross,
    Normal,
    Dot,
}

fn legend_items(
    kinds: &[RayKind],
    blocked: bool,
    off: bool,
    hit: bool,
) -> Vec<(LegendMark, String)> {
    let mut v: Vec<(LegendMark, String)> = kinds
        .iter()
        .map(|k| {
            let name = match k {
                RayKind::Camera => "camera ray",
                RayKind::Shadow => "shadow ray",
                RayKind::Reflection => "reflection",
                RayKind::Refraction => "refraction",
                RayKind::Transmission => "transmission",
            };
            (LegendMark::Ray(style::ray(*k), false), name.to_string())
        })
        .collect();
    if hit {
        v.push((LegendMark::Dot, "hit".into()));
        v.push((LegendMark::Normal, "normal".into()));
    }
    if blocked {
        v.push((LegendMark::Cross, "shadow ray blocked".into()));
    }
    if off {
        v.push((
            LegendMark::Ray(style::muted(), true),
            "leaves the slice (projected)".into(),
        ));
    }
    v
}

const LEGEND_SIZE: f32 = 12.0;

fn item_width(text: &str) -> f32 {
    30.0 + Canvas::text_width(text, LEGEND_SIZE) + 16.0
}

fn layout_legend(items: &[(LegendMark, String)], width: f32) -> Vec<Vec<(LegendMark, String)>> {
    let mut rows: Vec<Vec<(LegendMark, String)>> = vec![Vec::new()];
    let mut x = 0.0;
    for it in items {
        let w = item_width(&it.1);
        if x + w > width && !rows.last().expect("a row").is_empty() {
            rows.push(Vec::new());
            x = 0.0;
        }
        x += w;
        rows.last_mut().expect("a row").push(it.clone());
    }
    rows
}

fn draw_legend(canvas: &mut Canvas, rows: &[Vec<(LegendMark, String)>], top: f32) {
    for (r, row) in rows.iter().enumerate() {
        let total: f32 = row.iter().map(|i| item_width(&i.1)).sum::<f32>() - 16.0;
        let mut x = (canvas.width() - total) / 2.0;
        let y = top + 9.0 + 18.0 * r as f32;
        for (mark, text) in row {
            match mark {
                LegendMark::Ray(c, dashed) => {
                    if *dashed {
                        canvas.line((x, y), (x + 24.0, y), *c, 2.0, true);
                    } else {
                        canvas.arrow((x, y), (x + 24.0, y), *c, 2.0);
                    }
                }
                LegendMark::Cross => {
                    let (cx, s) = (x + 12.0, 4.5);
                    canvas.line((cx - s, y - s), (cx + s, y + s), style::hit(), 2.2, false);
                    canvas.line((cx - s, y + s), (cx + s, y - s), style::hit(), 2.2, false);
                }
                LegendMark::Normal => {
                    canvas.arrow((x + 2.0, y), (x + 22.0, y), style::normal(), 1.6)
                }
                LegendMark::Dot => canvas.circle((x + 12.0, y), 4.0, None, Some(style::hit())),
            }
            canvas.text((x + 30.0, y), text, LEGEND_SIZE, style::ink(), Anchor::Left);
            x += item_width(text);
        }
    }
}
