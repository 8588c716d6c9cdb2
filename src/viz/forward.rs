//! The forward-against-backward figure: photons from the lights that reached the film (left)
//! next to the backward-traced image (right), with the counts.

use super::canvas::{Anchor, Canvas};
use super::style;
use crate::trace::forward::ForwardResult;
use glam::DVec3;

/// Draws the figure. `backward` is the rendered image, `camera_rays` and `total_rays` what it
/// traced.
pub fn figure(
    fwd: &ForwardResult,
    backward: &image::RgbImage,
    camera_rays: u64,
    total_rays: u64,
    pupil: f64,
) -> Canvas {
    let (w, h) = backward.dimensions();
    let margin = 14.0f32;
    let title = (w as f32 / 26.0).clamp(12.0, 20.0);
    let small = title * 0.8;
    let top = margin + title * 2.6;
    let bottom = small * 4.4 + margin;
    let cw = (2 * w) as f32 + 3.0 * margin;
    let ch = top + h as f32 + bottom;
    let mut c = Canvas::new(cw.ceil() as u32, ch.ceil() as u32, style::background());
    let left = (margin, top);
    let right = (2.0 * margin + w as f32, top);

    let n = &fwd.counts;
    c.text(
        (left.0, margin + title * 0.6),
        "forward tracing: from the lights",
        title,
        style::ink(),
        Anchor::Left,
    );
    c.text(
        (left.0, margin + title * 1.75),
        &format!("{} photons, bounced until absorbed or lost", n.photons),
        small,
        style::muted(),
        Anchor::Left,
    );
    c.text(
        (right.0, margin + title * 0.6),
        "backward tracing: from the eye",
        title,
        style::ink(),
        Anchor::Left,
    );
    c.text(
        (right.0, margin + title * 1.75),
        &format!("{camera_rays} camera rays, one per pixel sample"),
        small,
        style::muted(),
        Anchor::Left,
    );

    // Left: black film with a dot per photon that made it.
    c.rect(left, (w as f32, h as f32), None, Some(style::rgb(0, 0, 0)));
    let r = (w as f32 / 160.0).max(2.0);
    for (p, color) in &fwd.splats {
        let m = color.max_element();
        let k = if m > 0.0 { *color / m } else { DVec3::ONE };
        let k = k.max(DVec3::splat(0.25));
        let col = style::rgb(
            (k.x * 255.0) as u8,
            (k.y * 255.0) as u8,
            (k.z * 255.0) as u8,
        );
        c.circle(
            (left.0 + p.x as f32, left.1 + p.y as f32),
            r,
            None,
            Some(col),
        );
    }
    c.image((right.0 as i32, right.1 as i32), backward, 1);
    c.rect(
        left,
        (w as f32, h as f32),
        Some((style::muted(), 1.0)),
        None,
    );
    c.rect(
        right,
        (w as f32, h as f32),
        Some((style::muted(), 1.0)),
        None,
    );

    let pct = 100.0 * n.reached_film as f64 / n.photons.max(1) as f64;
    let y = top + h as f32 + small * 1.1;
    c.text(
        (left.0, y),
        &format!("{} reached the film ({:.4} %)", n.reached_film, pct),
        title * 0.9,
        style::hit(),
        Anchor::Left,
    );
    c.text(
        (right.0, y),
        "every camera ray lands on its pixel (100 %)",
        title * 0.9,
        style::ink(),
        Anchor::Left,
    );
    let room = cw - 2.0 * margin;
    let lines = [
        format!(
            "forward: {} lost to the sky, {} absorbed, {} passed the eye outside the view; {} ray segments; eye pupil radius {}",
            n.escaped, n.absorbed, n.outside_view, n.rays, crate::error::number(pupil)
        ),
        format!(
            "backward: {total_rays} rays in all (camera, shadow, reflection and refraction rays)"
        ),
    ];
    for (k, line) in lines.iter().enumerate() {
        let size = small.min(small * room / Canvas::text_width(line, small).max(1.0));
        c.text(
            (left.0, y + small * (1.5 + 1.2 * k as f32)),
            line,
            size,
            style::muted(),
            Anchor::Left,
        );
    }
    c
}
