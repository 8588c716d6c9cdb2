//! Figures of the two solids that have no closed-form root: a CSG node's intervals (one bar
//! row per child, nested nodes indented, the combination last) and a blob's field profile
//! along the ray (the field, the threshold line, the search's samples and the roots).

use super::canvas::{Anchor, Canvas};
use super::style;
use crate::math::Ray;
use crate::shapes::working::{BlobWorking, CsgWorking, SpanRecord};
use crate::shapes::Blob;

const W: f32 = 1000.0;
const LEFT: f32 = 310.0; // bars start here; labels sit to the left
const RIGHT: f32 = 40.0;

/// A readable step for axis ticks covering `span`.
fn tick_step(span: f64) -> f64 {
    let raw = span / 8.0;
    let p = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * p)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * p)
}

fn t_label(t: f64) -> String {
    crate::shapes::working::short((t * 100.0).round() / 100.0)
}

/// Draws a t axis at height `y` for [t0, t1] mapped by `x`.
fn t_axis(c: &mut Canvas, y: f32, t0: f64, t1: f64, x: &dyn Fn(f64) -> f32) {
    c.line((LEFT, y), (W - RIGHT, y), style::ink(), 1.2, false);
    let step = tick_step(t1 - t0);
    let mut t = (t0 / step).ceil() * step;
    while t <= t1 + 1e-12 {
        c.line((x(t), y), (x(t), y + 5.0), style::ink(), 1.0, false);
        c.text(
            (x(t), y + 15.0),
            &t_label(t),
            12.0,
            style::ink(),
            Anchor::Center,
        );
        t += step;
    }
    c.text(
        (W - RIGHT, y + 32.0),
        "t along P + t·d",
        13.0,
        style::ink(),
        Anchor::Right,
    );
}

struct Row {
    label: String,
    depth: usize,
    spans: Vec<SpanRecord>,
    result: bool,
}

fn rows(node: &CsgWorking, depth: usize, out: &mut Vec<Row>) {
    for (i, ch) in node.children.iter().enumerate() {
        let role = if i == 0 {
            String::new()
        } else {
            format!("{} ", node.op.symbol())
        };
        if let Some(n) = &ch.csg {
            rows(n, depth + 1, out);
            out.push(Row {
                label: format!("{role}{} ({} of the rows above)", ch.name, n.op.name()),
                depth,
                spans: ch.spans.clone(),
                result: false,
            });
        } else {
            out.push(Row {
                label: format!("{role}{} ({})", ch.name, ch.shape),
                depth,
                spans: ch.spans.clone(),
                result: false,
            });
        }
    }
}

// ANCHOR: csg_figure
/// The intervals of each child of a CSG node along the ray and their combination: one row of
/// bars per child (nested nodes' children above them, indented), the result in red at the
/// bottom with its boundaries traced up through the rows, normals that were flipped marked,
/// and the hit.
pub fn csg_figure(w: &CsgWorking, hit: Option<f64>) -> Canvas {
    let mut list = Vec::new();
    rows(w, 0, &mut list);
    list.push(Row {
        label: format!("result: {}", w.op.name()),
        depth: 0,
        spans: w.combined.clone(),
        result: true,
    });
    let row_h = 44.0;
    let top = 70.0;
    let h = top + row_h * list.len() as f32 + 80.0;
    let mut c = Canvas::new(W as u32, h as u32, style::background());
    c.text(
        (20.0, 24.0),
        &format!(
            "CSG {}: where the ray is inside each solid, and inside the result",
            w.op.name()
        ),
        17.0,
        style::ink(),
        Anchor::Left,
    );
    let all: Vec<f64> = list
        .iter()
        .flat_map(|r| r.spans.iter().flat_map(|s| [s.enter.t, s.exit.t]))
        .chain(hit)
        .collect();
    let (mut t0, mut t1) = all
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), t| {
            (a.min(*t), b.max(*t))
        });
    if !t0.is_finite() {
        (t0, t1) = (0.0, 1.0);
    }
    let pad = 0.08 * (t1 - t0).max(1e-3);
    let (t0, t1) = (t0 - pad, t1 + pad);
    let x = |t: f64| LEFT + ((t - t0) / (t1 - t0)) as f32 * (W - LEFT - RIGHT);
    let row_y = |i: usize| top + row_h * i as f32 + row_h * 0.5;
    let bottom = row_y(list.len() - 1);

    // The result's boundaries, traced up through every row.
    for s in &w.combined {
        for t in [s.enter.t, s.exit.t] {
            c.line((x(t), top), (x(t), bottom), style::grid(), 1.0, true);
        }
    }
    for (i, r) in list.iter().enumerate() {
        let y = row_y(i);
        let indent = 16.0 * r.depth as f32;
        let (ink, size) = if r.result {
            (style::hit(), 14.0)
        } else {
            (style::ink(), 13.0)
        };
        c.text((20.0 + indent, y), &r.label, size, ink, Anchor::Left);
        c.line((LEFT, y), (W - RIGHT, y), style::grid(), 1.0, false);
        if r.spans.is_empty() {
            c.text(
                (LEFT + 6.0, y - 11.0),
                "(missed: no interval)",
                11.0,
                style::muted(),
                Anchor::Left,
            );
        }
        let (fill, stroke) = if r.result {
            (style::rgba(214, 39, 40, 70), style::hit())
        } else if r.label.contains(" of the rows above)") {
            (style::rgba(44, 160, 44, 60), style::normal())
        } else {
            (style::shape_fill(), style::shape_stroke())
        };
        for s in &r.spans {
            let (a, b) = (x(s.enter.t), x(s.exit.t));
            c.rect((a, y - 9.0), (b - a, 18.0), Some((stroke, 1.5)), Some(fill));
            c.text(
                (a, y + 17.0),
                &t_label(s.enter.t),
                11.0,
                style::ink(),
                Anchor::Center,
            );
            c.text(
                (b, y + 17.0),
                &t_label(s.exit.t),
                11.0,
                style::ink(),
                Anchor::Center,
            );
        }
    }
    // Flipped normals: a result boundary that its child had the other way round.
    let y = row_y(list.len() - 1);
    for s in &w.combined {
        for (b, entering) in [(s.enter, true), (s.exit, false)] {
            let flipped = list.iter().filter(|r| !r.result).any(|r| {
                r.spans.iter().any(|cs| {
                    let other = if entering { cs.exit } else { cs.enter };
                    (other.t - b.t).abs() <= 1e-9 * (1.0 + b.t.abs()) && other.surface == b.surface
                })
            });
            if flipped {
                c.text(
                    (x(b.t), y - 18.0),
                    &format!("{} normal flipped", b.surface),
                    11.0,
                    style::hit(),
                    Anchor::Center,
                );
            }
        }
    }
    if let Some(t) = hit {
        c.circle(
            (x(t), y),
            5.5,
            Some((style::ink(), 1.5)),
            Some(style::hit()),
        );
        c.text(
            (x(t) - 9.0, y),
            &format!("hit t = {}", t_label(t)),
            13.0,
            style::hit(),
            Anchor::Right,
        );
    }
    t_axis(&mut c, bottom + 36.0, t0, t1, &x);
    c
}
// ANCHOR_END: csg_figure

/// The field Σ s·f along the ray, sampled densely with the blob's own field function, the
/// threshold line, the pieces of the ray inside the spheres of influence, the samples the
/// root search evaluated, and the roots (entering / leaving).
pub fn blob_figure(
    blob: &Blob,
    ray: &Ray,
    w: &BlobWorking,
    roots: &[(f64, bool)],
    hit: Option<f64>,
) -> Canvas {
    let h = 460.0;
    let mut c = Canvas::new(W as u32, h as u32, style::background());
    c.text(
        (20.0, 24.0),
        "Blob: the field along the ray, the threshold, and the roots where they meet",
        17.0,
        style::ink(),
        Anchor::Left,
    );
    let (t0, t1) = match (w.segments.first(), w.segments.last()) {
        (Some(a), Some(b)) => (a[0], b[1]),
        _ => (0.0, 1.0),
    };
    let pad = 0.05 * (t1 - t0);
    let (t0, t1) = (t0 - pad, t1 + pad);
    let n = 600;
    let profile: Vec<(f64, f64)> = (0..=n)
        .map(|i| {
            let t = t0 + (t1 - t0) * i as f64 / n as f64;
            (t, blob.field(ray.at(t)).0)
        })
        .collect();
    let f_max = profile
        .iter()
        .map(|p| p.1)
        .fold(blob.threshold * 1.3, f64::max)
        * 1.1;
    let f_min = profile.iter().map(|p| p.1).fold(0.0, f64::min);
    let (py0, py1) = (60.0f32, h - 90.0);
    let x = |t: f64| LEFT + ((t - t0) / (t1 - t0)) as f32 * (W - LEFT - RIGHT);
    let y = |f: f64| py1 - ((f - f_min) / (f_max - f_min)) as f32 * (py1 - py0);
    // Spheres of influence.
    for s in &w.segments {
        c.rect(
            (x(s[0]), py0),
            (x(s[1]) - x(s[0]), py1 - py0),
            None,
            Some(style::rgba(90, 140, 200, 22)),
        );
    }
    c.text(
        (20.0, py0 + 10.0),
        "field Σ s·f(r)",
        13.0,
        style::ink(),
        Anchor::Left,
    );
    c.text(
        (20.0, py0 + 28.0),
        "shaded: inside a sphere",
        11.0,
        style::muted(),
        Anchor::Left,
    );
    c.text(
        (20.0, py0 + 42.0),
        "of influence",
        11.0,
        style::muted(),
        Anchor::Left,
    );
    c.line((LEFT, py0), (LEFT, py1), style::ink(), 1.2, false);
    c.line(
        (LEFT, y(0.0)),
        (W - RIGHT, y(0.0)),
        style::muted(),
        1.0,
        false,
    );
    c.text((LEFT - 6.0, y(0.0)), "0", 12.0, style::ink(), Anchor::Right);
    // Threshold.
    let ty = y(blob.threshold);
    c.line(
        (LEFT, ty),
        (W - RIGHT, ty),
        style::ray(crate::trace::RayKind::Shadow),
        1.5,
        true,
    );
    c.text(
        (LEFT - 6.0, ty),
        &format!("T = {}", t_label(blob.threshold)),
        12.0,
        style::ink(),
        Anchor::Right,
    );
    // The profile.
    for p in profile.windows(2) {
        c.line(
            (x(p[0].0), y(p[0].1)),
            (x(p[1].0), y(p[1].1)),
            style::shape_stroke(),
            2.0,
            false,
        );
    }
    // Samples of the search (only those inside the plotted range).
    let shown: Vec<&[f64; 2]> = w
        .samples
        .iter()
        .filter(|s| s[0] >= t0 && s[0] <= t1)
        .collect();
    for s in &shown {
        c.circle((x(s[0]), y(s[1])), 2.2, None, Some(style::muted()));
    }
    c.text(
        (W - RIGHT, py0 - 14.0),
        &format!(
            "grey dots: the {} field samples the root search made",
            shown.len()
        ),
        11.0,
        style::muted(),
        Anchor::Right,
    );
    for (k, (t, entering)) in roots.iter().enumerate() {
        let is_hit = hit == Some(*t);
        let color = if is_hit { style::hit() } else { style::ink() };
        if is_hit {
            c.line((x(*t), ty), (x(*t), py1), color, 1.0, true);
        }
        c.circle(
            (x(*t), ty),
            5.0,
            Some((color, 1.5)),
            is_hit.then(style::hit),
        );
        let label = format!(
            "{}{} t = {}",
            if is_hit { "hit: " } else { "" },
            if *entering { "enter" } else { "leave" },
            t_label(*t)
        );
        // Entries labelled to the right of their root, exits to the left: neighbours at a
        // thin gap (leave, then enter) never overlap.
        let (dx, anchor) = if *entering {
            (7.0, Anchor::Left)
        } else {
            (-7.0, Anchor::Right)
        };
        let dy = if k % 2 == 0 { -14.0 } else { 14.0 };
        c.text((x(*t) + dx, ty + dy), &label, 12.0, color, anchor);
    }
    t_axis(&mut c, py1 + 14.0, t0, t1, &x);
    c
}
