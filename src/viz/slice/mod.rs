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

mod frame;
mod legend;
mod marks;
mod rays;
mod window;

pub(crate) use frame::clip;
pub(in crate::viz) use frame::{Frame, View};

use super::labels::Labels;
use super::section::sections;
use super::style;
use super::{Anchor, Canvas};
use crate::error::{Error, Result};
use crate::scene::Scene;
use crate::trace::{RayKind, RayNode};
use frame::{choose_frame, shadow_target};
use glam::DVec3;
use legend::{draw_legend, scale_bar};

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

/// The figure being drawn: the canvas, the labels placed so far (and the marks they must
/// keep off), and the slice's plane with its pixel mapping.
struct Plot {
    canvas: Canvas,
    labels: Labels,
    frame: Frame,
    view: View,
}

/// Draws the ray tree `tree` (from explain's `TreeRecorder`) of `scene` in a slice.
///
/// Fails only on a figure size outside 160×120 to 8192×8192. Deterministic: same inputs,
/// same pixels.
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
    let (center, w, h) = window::window(scene, &frame, tree, &every);

    // The legend first: it decides how tall the bottom band is.
    let (fw, fh) = (opts.width as f32, opts.height as f32);
    let legend_rows = legend::legend(&every, &frame, fw - 20.0);
    let legend_h = 18.0 * legend_rows.len() as f32 + 8.0;
    let rect = [10.0, 34.0, fw - 10.0, fh - legend_h - 6.0];
    let (pw, ph) = ((rect[2] - rect[0]) as f64, (rect[3] - rect[1]) as f64);
    let view = View {
        rect,
        center,
        scale: (pw / w).min(ph / h),
    };

    let mut plot = Plot {
        canvas: Canvas::new(opts.width, opts.height, style::background()),
        labels: Labels::new([rect[0], rect[1], rect[2], rect[3]]),
        frame,
        view,
    };

    // Objects cut by the plane.
    let sections = sections(scene, &frame, &view, opts.width, opts.height);
    for s in &sections {
        plot.canvas
            .mask(&format!("{} (inside)", s.name), &s.fill, s.fill_color);
    }
    for s in &sections {
        plot.canvas
            .mask(&format!("{} (cut)", s.name), &s.edge, s.edge_color);
    }

    let eye = view.px(frame.to2(tree.origin));
    marks::block_rays(&mut plot, eye, events);
    let eye_label = [
        ((eye.0 - 9.0, eye.1), Anchor::Right),
        ((eye.0, eye.1 + 13.0), Anchor::Center),
        ((eye.0, eye.1 - 13.0), Anchor::Center),
    ];
    plot.labels
        .place_any(&mut plot.canvas, &eye_label, "eye", 12.0, style::ink());
    let labelled = marks::name_objects(&mut plot, &sections, events);
    marks::draw_lights(&mut plot, events);
    rays::draw_rays(&mut plot, events, opts, &labelled);

    let mut canvas = plot.canvas;
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
