//! The figure of `rtlab intersect box --bundle-to`: a bundle of rays against one box of a
//! BVH node. Left, the rays and the box seen along the axis from which the rays' fan looks widest
//! (y when that is a tie), with the interval test's two bounds drawn where they fall on every
//! ray; right, the same test along t: each axis's bounds as a bar (or, for a bundle that is
//! not sign-coherent, which axes change sign), the three together, and each ray's own
//! entry.

use super::canvas::{Anchor, Canvas};
use super::labels::{text_box, Labels};
use super::style;
use crate::accel::BundleWorking;
use crate::math::Ray;
use glam::DVec2;

mod times;
mod view;
use times::times;
use view::View;

const W: f32 = 960.0;
const H: f32 = 500.0;
const MARGIN: f32 = 24.0;
const TOP: f32 = 96.0;
const BOTTOM: f32 = 40.0;
const GAP: f32 = 40.0;

/// The figure for `rays` and their `working` (from [`crate::accel::bundle_working`]).
pub fn figure(rays: &[Ray], w: &BundleWorking) -> Canvas {
    let mut c = Canvas::new(W as u32, H as u32, style::background());
    let n = rays.len();
    let entering = w.rays.iter().filter(|v| v.lane.unwrap_or(v.own)).count();
    c.text(
        (MARGIN, 22.0),
        &format!("The interval test: a bundle of {n} rays against one box of a BVH node"),
        15.0,
        style::ink(),
        Anchor::Left,
    );
    let verdict = match w.kept {
        None => format!(
            "not sign-coherent: the directions change sign along {}, so no interval test for the box; each ray goes alone",
            w.mixed_axes()
        ),
        Some(true) => format!(
            "kept: the bounds leave room for a ray to enter; then the lane test: {entering} of {n} rays enter"
        ),
        Some(false) => format!(
            "culled: the bundle's entry bound comes after its exit bound, so all {n} rays miss ({entering} enter by their own tests)"
        ),
    };
    c.text((MARGIN, 44.0), &verdict, 12.0, style::ink(), Anchor::Left);
    let split = (W - GAP) / 2.0;
    let view = View::new(rays, w, (MARGIN, TOP, split, H - BOTTOM));
    let [along, right, up] = view.axes.map(|k| AXES[k]);
    // Each panel's caption above it, the left one naming the axis it is seen along.
    let caption = format!(
        "Seen along {along} ({right} to the right, {up} up), the view in which the rays fan out most"
    );
    let caption = if Canvas::text_width(&caption, 11.0) <= split - MARGIN {
        caption
    } else {
        format!("Seen along {along} ({right} to the right, {up} up)")
    };
    c.text(
        (MARGIN, TOP - 12.0),
        &caption,
        11.0,
        style::muted(),
        Anchor::Left,
    );
    c.text(
        (split + GAP, TOP - 12.0),
        "The same test along t, the distance along each ray (P + t·d)",
        11.0,
        style::muted(),
        Anchor::Left,
    );
    let bounds = w.together;
    space(&mut c, rays, w, bounds, &view);
    times(
        &mut c,
        rays,
        w,
        bounds,
        (split + GAP, TOP, W - MARGIN, H - BOTTOM),
    );
    let note = if bounds.is_some() {
        " The bounds hold for every ray at once."
    } else {
        " Without the interval test, each ray's own test decides."
    };
    // The dots are explained only where there are some.
    let key = if w.rays.iter().any(|r| r.own) {
        "Red dots: where each ray's own slab test says it enters. Grey rays miss the box."
    } else {
        "Grey rays miss the box: no ray's own slab test enters it."
    };
    c.text(
        (MARGIN, H - 16.0),
        &format!("{key}{note}"),
        11.0,
        style::ink(),
        Anchor::Left,
    );
    c
}

const AXES: [&str; 3] = BundleWorking::AXES;

fn pt(p: DVec2) -> (f32, f32) {
    (p.x as f32, p.y as f32)
}

/// Left panel: box, rays, entry dots, and the two bounds as fronts across the rays.
fn space(c: &mut Canvas, rays: &[Ray], w: &BundleWorking, bounds: Option<(f32, f32)>, v: &View) {
    let (x0, y0, x1, y1) = v.rect;
    c.rect(
        (x0 as f32, y0 as f32),
        ((x1 - x0) as f32, (y1 - y0) as f32),
        Some((style::grid(), 1.0)),
        None,
    );
    // The box.
    let (a, b) = (
        v.px(w.min.map(f64::from).into()),
        v.px(w.max.map(f64::from).into()),
    );
    let (corner, far) = (a.min(b), a.max(b));
    let size = pt(far - corner);
    // The box's corners in order round it: its edges join each to the next.
    let corners = [
        corner,
        DVec2::new(far.x, corner.y),
        far,
        DVec2::new(corner.x, far.y),
    ];
    let edge = |i: usize| (pt(corners[i]), pt(corners[(i + 1) % 4]));
    if w.kept == Some(false) {
        for i in 0..4 {
            let (p, q) = edge(i);
            c.line(p, q, style::tossed(), 1.6, true);
        }
    } else {
        c.rect(
            pt(corner),
            size,
            Some((style::shape_stroke(), 1.6)),
            Some(style::shape_fill()),
        );
    }
    // Labels are kept off each other, off P and off the rays where they leave P (a label
    // there, on its plate, made the rays seem to start away from P): `labels` holds what
    // is taken so far.
    let o = v.px(rays[0].origin);
    let (x0, y0, x1, y1) = v.rect;
    let mut labels = Labels::new([x0 as f32, y0 as f32, x1 as f32, y1 as f32]);
    labels.block_point(pt(o), 5.0);
    let drawn: Vec<Option<(DVec2, DVec2)>> = rays
        .iter()
        .map(|r| {
            v.leave(r)
                .and_then(|t| v.clip(v.px(r.origin), v.px(r.at(t))))
        })
        .collect();
    for seg in &drawn {
        match seg {
            Some((a, b)) => {
                let end = *a + (*b - *a).clamp_length_max(NEAR_P);
                labels.block_segment(pt(*a), pt(end), 2.5);
            }
            None => labels.block_point(pt(o), 9.0),
        }
    }
    // P's label under it, else above, right or left of it: wherever the rays are not.
    let p_tries = [
        (pt(o + DVec2::new(0.0, 14.0)), Anchor::Center),
        (pt(o + DVec2::new(0.0, -14.0)), Anchor::Center),
        (pt(o + DVec2::new(9.0, 0.0)), Anchor::Left),
        (pt(o + DVec2::new(-9.0, 0.0)), Anchor::Right),
    ];
    let (p_label, p_anchor) = labels
        .reserve(&p_tries, "P", 12.0, true)
        .unwrap_or(p_tries[0]);
    let dots: Vec<DVec2> = rays
        .iter()
        .zip(&w.rays)
        .filter(|(_, verdict)| verdict.own)
        .map(|(r, verdict)| v.px(r.at(verdict.t_enter as f64)))
        .collect();
    for d in &dots {
        labels.block_point(pt(*d), 4.0);
    }
    // Outside the box, under it if that is clear: a label inside would cover the entry
    // dots of the rays that enter through its sides.
    let box_label = [
        (pt(DVec2::new(far.x, far.y + 9.0)), Anchor::Right),
        (pt(DVec2::new(corner.x, far.y + 9.0)), Anchor::Left),
        (pt(DVec2::new(far.x, corner.y - 9.0)), Anchor::Right),
        (pt(DVec2::new(corner.x, corner.y - 9.0)), Anchor::Left),
    ];
    labels.place_any(c, &box_label, "box", 11.0, style::muted());
    // Each ray from its origin to where it leaves the panel; a ray seen end-on as a ring.
    for ((r, verdict), seg) in rays.iter().zip(&w.rays).zip(&drawn) {
        let color = if verdict.lane.unwrap_or(verdict.own) {
            style::ray(crate::trace::RayKind::Camera)
        } else {
            style::tossed()
        };
        match *seg {
            Some((a, b)) => c.line(pt(a), pt(b), color, 1.0, false),
            None => c.circle(pt(v.px(r.origin)), 7.0, Some((color, 1.0)), None),
        }
    }
    // The bounds: where each ray is at t = bound, joined across the bundle; left out when
    // some ray is out of the panel by then, or when the front is a point (t = 0 at a
    // shared P: the right panel shows it).
    // And off the box's edges, wherever they go: a plate on an edge cuts the box open.
    for i in 0..4 {
        let (p, q) = edge(i);
        labels.block_segment(p, q, 1.5);
    }
    let mut off_rays = labels.clone();
    for (a, b) in drawn.iter().flatten() {
        off_rays.block_segment(pt(*a), pt(*b), 2.0);
    }
    if let Some((entry, exit)) = bounds {
        for (t, name) in [(entry, "entry bound"), (exit, "exit bound")] {
            let t = t as f64;
            if !t.is_finite() {
                continue;
            }
            let pts: Vec<DVec2> = rays.iter().map(|r| v.px(r.at(t))).collect();
            let spread = pts
                .iter()
                .map(|p| (*p - pts[0]).length())
                .fold(0.0, f64::max);
            if !pts.iter().all(|p| v.inside(*p)) || spread < 3.0 {
                continue;
            }
            for p in pts.windows(2) {
                if let Some((a, b)) = v.clip(p[0], p[1]) {
                    c.line(pt(a), pt(b), style::ink(), 1.4, true);
                }
            }
            // The entry bound's label above the front, the exit bound's below it; else
            // beside it, wherever it is clear of the other labels and inside the panel.
            let extreme = |key: fn(DVec2) -> f64| {
                pts.iter()
                    .copied()
                    .fold(pts[0], |m, p| if key(p) < key(m) { p } else { m })
            };
            let (top, low) = (extreme(|p| p.y), extreme(|p| -p.y));
            let (left, right) = (extreme(|p| p.x), extreme(|p| -p.x));
            let above = (pt(top + DVec2::new(0.0, -12.0)), Anchor::Center);
            let below = (pt(low + DVec2::new(0.0, 12.0)), Anchor::Center);
            let mut tries = if name == "entry bound" {
                vec![above, below]
            } else {
                vec![below, above]
            };
            tries.extend([
                (pt(right + DVec2::new(8.0, 0.0)), Anchor::Left),
                (pt(left + DVec2::new(-8.0, 0.0)), Anchor::Right),
            ]);
            // Off every ray if some place near the front is (beside its ends or further
            // from it, if need be); else on its plate over the rays, but never near P.
            let mut apart = tries.clone();
            apart.extend([
                (pt(low + DVec2::new(6.0, 12.0)), Anchor::Left),
                (pt(low + DVec2::new(-6.0, 12.0)), Anchor::Right),
                (pt(top + DVec2::new(-6.0, -12.0)), Anchor::Right),
                (pt(top + DVec2::new(6.0, -12.0)), Anchor::Left),
            ]);
            // Further from the front, a step at a time, when the rays crowd its ends.
            for step in [24.0, 36.0] {
                apart.extend([
                    (pt(top + DVec2::new(0.0, -step)), Anchor::Center),
                    (pt(low + DVec2::new(0.0, step)), Anchor::Center),
                    (pt(low + DVec2::new(-6.0, step)), Anchor::Right),
                    (pt(low + DVec2::new(6.0, step)), Anchor::Left),
                    (pt(top + DVec2::new(-6.0, -step)), Anchor::Right),
                    (pt(top + DVec2::new(6.0, -step)), Anchor::Left),
                ]);
            }
            let text = format!("t = {name}");
            let pick = off_rays
                .reserve(&apart, &text, 11.0, false)
                .or_else(|| labels.reserve(&tries, &text, 11.0, false));
            if let Some((at, anchor)) = pick {
                let taken = text_box(at, &text, 11.0, anchor);
                labels.block(taken);
                off_rays.block(taken);
                // On a plate of the background, so that the rays under it do not cross it.
                let [bx0, by0, bx1, by1] = taken;
                c.rect(
                    (bx0, by0),
                    (bx1 - bx0, by1 - by0),
                    None,
                    Some(style::background()),
                );
                c.text(at, &text, 11.0, style::ink(), anchor);
            }
        }
    }
    for d in dots {
        c.circle(
            pt(d),
            3.5,
            Some((style::background(), 1.2)),
            Some(style::hit()),
        );
    }
    c.circle(pt(o), 3.0, None, Some(style::ink()));
    c.text(p_label, "P", 12.0, style::ink(), p_anchor);
}

/// How far from P, in pixels, the rays are kept clear of labels.
const NEAR_P: f64 = 48.0;
