//! The image built up step by step (DESIGN §6): ray casting (which object, how far, which way
//! it faces), then the lighting equation term by term, shadows, each level of reflection,
//! refraction, and the final image. Every frame is the one tracer run with different
//! [`RenderSettings`] switches (or an AOV recorder); nothing here shades anything itself.

use super::canvas::{Anchor, Canvas};
use super::style;
use crate::error::{Error, Result};
use crate::sampling::aov::{render_aov, Aov};
use crate::sampling::render;
use crate::scene::{RenderSettings, Scene};
use crate::shading::LightKind;
use crate::trace::RayNode;
use std::path::Path;

/// How a step's picture is made.
#[derive(Debug, Clone, PartialEq)]
pub enum StepKind {
    /// An AOV of the camera rays (visibility, depth, normals).
    Aov(Aov),
    /// The colour image under these settings.
    Render(RenderSettings),
}

/// One planned step: a file name stem, its caption, and how to make it.
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    pub name: String,
    pub caption: String,
    pub kind: StepKind,
}

/// A step that will not be drawn, and why.
#[derive(Debug, Clone, PartialEq)]
pub struct Skipped {
    pub name: String,
    pub caption: String,
    pub reason: String,
}

/// The steps for a scene, in lecture order, and those left out because the scene (or a
/// `--no-…` switch) has nothing to add there. The last step is always the final image, with
/// exactly the settings `rtlab render` uses.
pub fn plan(scene: &Scene) -> (Vec<Step>, Vec<Skipped>) {
    let base = &scene.render;
    let mut steps = Vec::new();
    let mut skipped = Vec::new();
    let mut add = |name: &str, caption: &str, kind: StepKind| {
        steps.push(Step {
            name: name.into(),
            caption: caption.into(),
            kind,
        })
    };
    add(
        "visibility",
        "visibility: which object each camera ray hits first (ray casting)",
        StepKind::Aov(Aov::ObjectId),
    );
    add(
        "depth",
        "depth: distance t to that hit (near light, far dark, by 1/t)",
        StepKind::Aov(Aov::Depth),
    );
    add(
        "normals",
        "normals n at the hit, drawn as 0.5 + 0.5·n",
        StepKind::Aov(Aov::Normal),
    );
    // The local lighting model, one term at a time, no secondary rays.
    let mut local = base.clone();
    local.shadows = false;
    local.reflections = false;
    local.refractions = false;
    let ambient = RenderSettings {
        diffuse: false,
        specular: false,
        ..local.clone()
    };
    add("ambient", "ambient: ka·La·Oa", StepKind::Render(ambient));
    let diffuse = RenderSettings {
        specular: false,
        ..local.clone()
    };
    add(
        "diffuse",
        "+ diffuse: Σ f_att·L·kd·Od·(n·l), no shadows yet",
        StepKind::Render(diffuse),
    );
    add(
        "specular",
        "+ specular: Σ f_att·L·ks·Os·(r·v)^n",
        StepKind::Render(local.clone()),
    );
    let mut current = local;
    let soft = scene
        .lights
        .iter()
        .any(|l| matches!(l.kind, LightKind::Area { .. }));
    let shadows_caption = if soft {
        "+ shadows: shadow rays to each light (area lights sampled: soft)"
    } else {
        "+ hard shadows: one shadow ray per light"
    };
    if base.shadows && !scene.lights.is_empty() {
        current.shadows = true;
        add(
            "shadows",
            shadows_caption,
            StepKind::Render(current.clone()),
        );
    } else {
        let reason = if scene.lights.is_empty() {
            "the scene has no lights"
        } else {
            "shadows are switched off (--no-shadows)"
        };
        skipped.push(skip("shadows", shadows_caption, reason));
    }
    let ks = scene.global.ks;
    let reflective = ks > 0.0
        && scene
            .materials
            .iter()
            .any(|m| m.reflective.max_element() > 0.0);
    let transparent = scene.global.kt > 0.0
        && scene
            .materials
            .iter()
            .any(|m| m.transparent.max_element() > 0.0);
    if reflective && base.reflections && base.max_depth > 0 {
        current.reflections = true;
        for k in 1..=base.max_depth {
            current.max_depth = k;
            add(
                &format!("reflection-{k}"),
                &format!("+ reflection rays, depth {k}: ks·Or·I_r"),
                StepKind::Render(current.clone()),
            );
        }
    } else {
        let reason = if !reflective {
            "nothing in the scene is reflective"
        } else if !base.reflections {
            "reflections are switched off (--no-reflections)"
        } else {
            "--max-depth is 0 (ray casting)"
        };
        skipped.push(skip("reflection", "+ reflection rays", reason));
    }
    let refraction_caption = "+ refraction and transparency: kt·Ot·I_t (Snell's law)";
    if transparent && base.refractions && base.max_depth > 0 {
        current.refractions = true;
        current.max_depth = base.max_depth;
        add("refraction", refraction_caption, StepKind::Render(current));
    } else {
        let reason = if !transparent {
            "nothing in the scene is transparent"
        } else if !base.refractions {
            "refraction is switched off (--no-refractions)"
        } else {
            "--max-depth is 0 (ray casting)"
        };
        skipped.push(skip("refraction", refraction_caption, reason));
    }
    add(
        "final",
        "final image (the same bytes as rtlab render)",
        StepKind::Render(base.clone()),
    );
    (steps, skipped)
}

fn skip(name: &str, caption: &str, reason: &str) -> Skipped {
    Skipped {
        name: name.into(),
        caption: caption.into(),
        reason: reason.into(),
    }
}

/// A rendered frame.
#[derive(Debug, Clone)]
pub struct Frame {
    pub name: String,
    pub caption: String,
    pub image: image::RgbImage,
    /// The image already carries its caption (the storyboard's slice figures).
    pub labelled: bool,
}

/// Renders the planned steps. A step whose image is identical to the previous frame's adds
/// nothing visible and is moved to the skipped list (the final image is always kept).
pub fn render_frames(scene: &Scene, steps: &[Step], skipped: &mut Vec<Skipped>) -> Vec<Frame> {
    let mut frames: Vec<Frame> = Vec::new();
    for (i, step) in steps.iter().enumerate() {
        let image = match &step.kind {
            // Cancelled: a black frame, as a cancelled render's; the caller throws them away.
            StepKind::Aov(aov) => render_aov(scene, &scene.render, *aov).map_or_else(
                || image::RgbImage::new(scene.camera.width, scene.camera.height),
                |a| a.image,
            ),
            StepKind::Render(settings) => render(scene, settings, false, None)
                .image
                .to_rgb8_for(settings),
        };
        let last = i + 1 == steps.len();
        if !last && frames.last().is_some_and(|f| f.image == image) {
            let why = match step.name.as_str() {
                "shadows" => "no shadow ray is blocked anywhere in the image",
                n if n.starts_with("reflection") => {
                    "no pixel changes (no reflection ray gets this deep, or what it brings back is too faint to change a byte)"
                }
                _ => "no pixel changes",
            };
            skipped.push(skip(&step.name, &step.caption, why));
            continue;
        }
        frames.push(Frame {
            name: step.name.clone(),
            caption: step.caption.clone(),
            image,
            labelled: false,
        });
    }
    frames
}

/// The file name of frame `i` (0-based): `NNN-name.png`, numbered from 1.
pub fn file_name(i: usize, frame: &Frame) -> String {
    format!("{:03}-{}.png", i + 1, frame.name)
}

/// Height of the caption strip under a frame of this width.
fn strip_height(width: u32) -> u32 {
    (width / 22).clamp(16, 32)
}

/// The frame with its caption in a strip underneath (the image itself is untouched).
pub fn captioned(frame: &Frame, number: usize, total: usize) -> image::RgbImage {
    if frame.labelled {
        return frame.image.clone();
    }
    let (w, h) = frame.image.dimensions();
    let sh = strip_height(w);
    let mut c = Canvas::new(w, h + sh, style::ink());
    c.image((0, 0), &frame.image, 1);
    let text = format!("{number}/{total}  {}", frame.caption);
    let pad = sh as f32 * 0.35;
    let mut size = sh as f32 * 0.6;
    let room = w as f32 - 2.0 * pad;
    let tw = Canvas::text_width(&text, size);
    if tw > room {
        size *= room / tw;
    }
    c.text(
        (pad, h as f32 + sh as f32 / 2.0),
        &text,
        size,
        style::background(),
        Anchor::Left,
    );
    c.to_rgb()
}

/// All frames (or those named in `only`) on one sheet, `columns` across, each captioned.
pub fn contact_sheet(frames: &[Frame], only: &[String], columns: usize) -> Result<image::RgbImage> {
    for name in only {
        if !frames.iter().any(|f| &f.name == name) {
            let names: Vec<&str> = frames.iter().map(|f| f.name.as_str()).collect();
            return Err(Error::arg(
                "--frames",
                format!(
                    "this scene has no frame \"{name}\" (its frames: {})",
                    names.join(", ")
                ),
            ));
        }
    }
    let chosen: Vec<(usize, &Frame)> = frames
        .iter()
        .enumerate()
        .filter(|(_, f)| only.is_empty() || only.contains(&f.name))
        .collect();
    let tiles: Vec<image::RgbImage> = chosen
        .iter()
        .map(|(i, f)| captioned(f, i + 1, frames.len()))
        .collect();
    let (tw, th) = tiles[0].dimensions();
    let cols = columns.clamp(1, tiles.len());
    let rows = tiles.len().div_ceil(cols);
    let gap = 6;
    let (w, h) = (
        cols as u32 * (tw + gap) - gap,
        rows as u32 * (th + gap) - gap,
    );
    let mut c = Canvas::new(w, h, style::background());
    for (k, t) in tiles.iter().enumerate() {
        let (col, row) = ((k % cols) as u32, (k / cols) as u32);
        c.image(((col * (tw + gap)) as i32, (row * (th + gap)) as i32), t, 1);
    }
    Ok(c.to_rgb())
}

/// The captioned frames as an animated GIF that loops forever: 1.2 s a frame, the final
/// image held for 3 s. The encoder's colour quantisation is deterministic.
pub fn gif(frames: &[Frame], path: &Path) -> Result<Vec<u8>> {
    use image::codecs::gif::{GifEncoder, Repeat};
    use image::{Delay, Frame as GifFrame, RgbaImage};
    let mut bytes = Vec::new();
    {
        let mut enc = GifEncoder::new_with_speed(&mut bytes, 10);
        enc.set_repeat(Repeat::Infinite)
            .map_err(|e| Error::io(path, format!("cannot encode GIF: {e}")))?;
        for (i, f) in frames.iter().enumerate() {
            let rgb = captioned(f, i + 1, frames.len());
            let rgba: RgbaImage = image::DynamicImage::ImageRgb8(rgb).to_rgba8();
            let ms = if i + 1 == frames.len() { 3000 } else { 1200 };
            enc.encode_frame(GifFrame::from_parts(
                rgba,
                0,
                0,
                Delay::from_numer_denom_ms(ms, 1),
            ))
            .map_err(|e| Error::io(path, format!("cannot encode GIF: {e}")))?;
        }
    }
    Ok(bytes)
}

/// One line for event `k` of a pixel's ray tree (preorder, as [`super::slice`] counts them).
pub fn describe_event(node: &RayNode) -> String {
    use crate::trace::{End, RayKind};
    let kind = match node.kind {
        RayKind::Camera => "camera ray",
        RayKind::Shadow => "shadow ray",
        RayKind::Reflection => "reflection ray",
        RayKind::Refraction => "refraction ray",
        RayKind::Transmission => "transmission ray",
    };
    let depth = if node.depth > 0 && node.kind != RayKind::Shadow {
        format!(" (depth {})", node.depth)
    } else {
        String::new()
    };
    let mut s = match (&node.hit, node.kind, node.end) {
        (Some(h), RayKind::Shadow, _) => {
            format!(
                "{kind} blocked by {} at t = {:.3}: in shadow",
                h.object, h.t
            )
        }
        (None, RayKind::Shadow, _) => format!("{kind} reaches its light: lit"),
        (Some(h), _, _) => format!("{kind}{depth} hits {} at t = {:.3}", h.object, h.t),
        (None, _, _) => format!("{kind}{depth} hits nothing: background colour"),
    };
    match node.end {
        End::MaxDepth => s += "; max depth reached, no further rays",
        End::TotalInternalReflection => s += "; total internal reflection",
        End::Cutoff => s += "; a further ray would be too faint (cutoff)",
        End::RayBudget => s += "; cut: ray budget reached",
        _ => {}
    }
    s
}

/// The events of a ray tree in the order the tracer cast them (depth first).
pub fn events(tree: &RayNode) -> Vec<&RayNode> {
    fn walk<'a>(n: &'a RayNode, out: &mut Vec<&'a RayNode>) {
        out.push(n);
        for c in &n.children {
            walk(c, out);
        }
    }
    let mut out = Vec::new();
    walk(tree, &mut out);
    out
}

/// The storyboard of one pixel: frame k draws the first k events of its ray tree on the
/// slice figure of [`super::slice`], the newest one emphasised.
pub fn storyboard(
    scene: &Scene,
    tree: &RayNode,
    pixel: (u32, u32),
    plane: super::slice::SlicePlane,
    color: glam::DVec3,
) -> Result<Vec<Frame>> {
    let all = events(tree);
    debug_assert_eq!(all.len(), super::slice::event_count(tree));
    let n = all.len();
    let mut frames = Vec::with_capacity(n);
    for (k, node) in all.iter().enumerate() {
        let mut caption = describe_event(node);
        if k + 1 == n {
            caption += &format!(
                "; pixel colour ({:.3}, {:.3}, {:.3})",
                color.x, color.y, color.z
            );
        }
        let opts = super::slice::SliceOptions {
            plane,
            events: Some(k + 1),
            // The slice's own title line is short; the event is told in the strip below.
            caption: Some(format!("pixel ({}, {})", pixel.0, pixel.1)),
            ..Default::default()
        };
        let image = super::slice::draw(scene, tree, &opts)?.to_rgb();
        let name = format!("{:?}", node.kind).to_ascii_lowercase();
        frames.push(Frame {
            name,
            caption,
            image,
            labelled: false,
        });
    }
    Ok(frames)
}
