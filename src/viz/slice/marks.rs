//! What goes down before the rays: the marks labels must keep off, the objects' names and
//! the lights.

use super::frame::clip;
use super::{Drawn, Plot};
use crate::trace::RayKind;
use crate::viz::labels::around;
use crate::viz::section::Section;
use crate::viz::style;
use crate::viz::Anchor;

/// Keeps labels off the eye and every ray drawn (points along each segment).
pub(super) fn block_rays(plot: &mut Plot, eye: (f32, f32), events: &[Drawn]) {
    let Plot {
        labels,
        frame,
        view,
        ..
    } = plot;
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
}

/// The objects' names (an object a drawn ray hit in the ink of shapes, the others muted),
/// placed before the rays' labels so they take the spots next to the rays. Returns the
/// names that found a place.
pub(super) fn name_objects(plot: &mut Plot, sections: &[Section], events: &[Drawn]) -> Vec<String> {
    let Plot { canvas, labels, .. } = plot;
    let hit_names: Vec<&str> = events
        .iter()
        .filter_map(|e| e.node.hit.as_ref().map(|h| h.object.as_str()))
        .collect();
    let mut labelled: Vec<String> = Vec::new();
    for s in sections {
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
        if labels.place(canvas, &cands, &s.name, 13.0, color).is_some() {
            labelled.push(s.name.clone());
        }
    }
    labelled
}

/// Each light a shadow ray goes to, once, where it lies in the plot.
pub(super) fn draw_lights(plot: &mut Plot, events: &[Drawn]) {
    let Plot {
        canvas,
        labels,
        frame,
        view,
    } = plot;
    let rect = view.rect;
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
                    canvas,
                    &around(lp, 11.0),
                    &format!("light {name}"),
                    12.0,
                    style::ink(),
                );
            }
        }
    }
}
