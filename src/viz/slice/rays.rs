//! The rays, in the order they were cast: each clipped to the plot, dashed where it leaves
//! the plane, with its t, its hit and normal, and a blocked shadow ray's blocker.

use super::frame::clip;
use super::{t_label, Drawn, Plot, SliceOptions};
use crate::trace::{End, RayKind};
use crate::viz::labels::{around, beside};
use crate::viz::style;

/// Draws `events` (a storyboard's last one, or the highlighted one, in bold). `labelled`:
/// the objects whose names are already in the figure (a t label names the others).
pub(super) fn draw_rays(
    plot: &mut Plot,
    events: &[Drawn],
    opts: &SliceOptions,
    labelled: &[String],
) {
    let Plot {
        canvas,
        labels,
        frame,
        view,
    } = plot;
    let rect = view.rect;
    let (fw, fh) = (opts.width as f32, opts.height as f32);
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
                labels.place(canvas, &beside(ca, cb, 8.0), &text, 12.0, color);
            } else if let (true, Some((Some(_), name))) = (cut, &e.light) {
                // The light is beyond the figure's edge.
                labels.place(
                    canvas,
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
                labels.place(canvas, &cands, "miss", 12.0, color);
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
                    canvas,
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
                        canvas,
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
}
