//! The figure of `rtlab intersect box --bundle-to`: a bundle of rays against one box of a
//! BVH node. Left, the rays and the box seen along the axis in which the rays fan out most
//! (y when that is a tie), with the interval test's two bounds drawn where they fall on every
//! ray; right, the same test along t: each axis's bounds as a bar (or, for a bundle that is
//! not sign-coherent, which axes change sign), the three together, and each ray's own
//! entry.

use super::canvas::{Anchor, Canvas};
use super::labels::{text_box, Labels};
use super::style;
use crate::accel::BundleWorking;
use crate::math::Ray;
use crate::shapes::working::tiny;
use glam::DVec2;

mod view;
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
    c.text(
        (MARGIN, H - 16.0),
        &format!(
            "Red dots: where each ray's own slab test says it enters. Grey rays miss the box.{note}"
        ),
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
    if w.kept == Some(false) {
        let pts = [
            corner,
            DVec2::new(far.x, corner.y),
            far,
            DVec2::new(corner.x, far.y),
        ];
        for i in 0..4 {
            c.line(pt(pts[i]), pt(pts[(i + 1) % 4]), style::tossed(), 1.6, true);
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
                (pt(top + DVec2::new(0.0, -24.0)), Anchor::Center),
                (pt(low + DVec2::new(0.0, 24.0)), Anchor::Center),
            ]);
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

/// Right panel: the t axis, a row per slab, the three together, and the rays' own entries.
fn times(
    c: &mut Canvas,
    rays: &[Ray],
    w: &BundleWorking,
    bounds: Option<(f32, f32)>,
    (x0, y0, x1, y1): (f32, f32, f32, f32),
) {
    let label_w = 150.0;
    let (t0, t1) = (x0 + label_w + 40.0, x1 - 50.0);
    // The scale: from 0 (where the walk starts each ray) to past the bounds that decide and
    // every ray's entry, then on to the next tick; a bar beyond either end is cut there, its
    // true end written beside.
    let (t_max, ticks) = ticks(reach(rays, w, bounds) * 1.6, t1 - t0);
    let t_max = t_max as f32;
    let at = |t: f32| t0 + (t.clamp(0.0, t_max) / t_max) * (t1 - t0);
    let rows = 6.0;
    let row_h = ((y1 - y0) - 40.0) / rows;
    let row_y = |i: usize| y0 + 10.0 + row_h * (i as f32 + 0.5);
    let num = |t: f32| {
        if t.is_finite() {
            tiny(t as f64)
        } else {
            "∞".to_string()
        }
    };
    let bar = |c: &mut Canvas, y: f32, a: f32, b: f32| {
        let (xa, xb) = (at(a), at(b));
        c.rect(
            (xa, y - 8.0),
            (xb - xa, 16.0),
            Some((style::shape_stroke(), 1.4)),
            Some(style::shape_fill()),
        );
        let cut = |t: f32| {
            if (0.0..=t_max).contains(&t) {
                ""
            } else {
                " (cut)"
            }
        };
        c.text(
            (xa - 4.0, y),
            &format!("{}{}", num(a), cut(a)),
            10.0,
            style::ink(),
            Anchor::Right,
        );
        c.text(
            (xb + 4.0, y),
            &format!("{}{}", num(b), cut(b)),
            10.0,
            style::ink(),
            Anchor::Left,
        );
    };
    for (k, axis) in w.axes.iter().enumerate() {
        let y = row_y(k);
        let name = ["x", "y", "z"][k];
        let what = if w.kept.is_some() { ": bounds" } else { "" };
        c.text(
            (x0, y),
            &format!("{name} slab{what}"),
            12.0,
            style::ink(),
            Anchor::Left,
        );
        match axis {
            Some((a, b)) => bar(c, y, *a, *b),
            None if w.kept.is_some() => c.text(
                (t0, y),
                "no bound (some ray's 1/d is ±∞ along it)",
                11.0,
                style::muted(),
                Anchor::Left,
            ),
            // Not sign-coherent: which axes are to blame, and that no axis is tested.
            None => {
                let (lo, hi) = rays.iter().fold((f64::MAX, f64::MIN), |(lo, hi), r| {
                    (lo.min(r.dir[k]), hi.max(r.dir[k]))
                });
                let (first, second, color) = if w.coherent_axes[k] {
                    let values = if lo == hi {
                        format!("= {} for every ray", tiny(lo))
                    } else {
                        format!("from {} to {}", tiny(lo), tiny(hi))
                    };
                    (
                        format!("d{name} {values}: one sign,"),
                        "but unused: the bundle is mixed".to_string(),
                        style::muted(),
                    )
                } else {
                    (
                        format!("d{name} changes sign, from {} to {}:", tiny(lo), tiny(hi)),
                        format!("1/d{name} would pass ±∞, no bound"),
                        style::hit(),
                    )
                };
                c.text((t0, y - 7.0), &first, 11.0, color, Anchor::Left);
                c.text((t0, y + 7.0), &second, 11.0, color, Anchor::Left);
            }
        }
    }
    let y = row_y(3);
    c.text(
        (x0, y),
        "all three: entry–exit",
        12.0,
        style::ink(),
        Anchor::Left,
    );
    match (bounds, w.kept) {
        (Some((a, b)), Some(true)) => bar(c, y, a, b),
        (Some((a, b)), _) => {
            c.line((at(b), y), (at(a), y), style::hit(), 2.0, false);
            c.text(
                ((at(a) + at(b)) / 2.0, y - 14.0),
                "empty: entry after exit → culled",
                11.0,
                style::hit(),
                Anchor::Center,
            );
            c.text(
                (at(b) - 4.0, y),
                &format!("exit {}", num(b)),
                10.0,
                style::ink(),
                Anchor::Right,
            );
            c.text(
                (at(a) + 4.0, y),
                &format!("entry {}", num(a)),
                10.0,
                style::ink(),
                Anchor::Left,
            );
        }
        (None, _) => {
            c.text(
                (t0, y - 7.0),
                &format!("no interval test: mixed along {}", w.mixed_axes()),
                11.0,
                style::ink(),
                Anchor::Left,
            );
            c.text(
                (t0, y + 7.0),
                "each ray takes its own slab test",
                11.0,
                style::muted(),
                Anchor::Left,
            );
        }
    }
    let y = row_y(4);
    c.text(
        (x0, y),
        "each ray's own entry",
        12.0,
        style::ink(),
        Anchor::Left,
    );
    let own: Vec<f32> = w.rays.iter().filter(|v| v.own).map(|v| v.t_enter).collect();
    if own.is_empty() {
        c.text((t0, y), "none enters", 11.0, style::muted(), Anchor::Left);
    }
    for t in own {
        c.circle(
            (at(t), y),
            3.5,
            Some((style::background(), 1.2)),
            Some(style::hit()),
        );
    }
    // The t axis.
    let y = row_y(5);
    c.line((t0, y), (t1, y), style::ink(), 1.0, false);
    for (t, label) in ticks {
        let x = at(t as f32);
        c.line((x, y - 4.0), (x, y + 4.0), style::ink(), 1.0, false);
        c.text((x, y + 14.0), &label, TICK, style::ink(), Anchor::Center);
    }
    c.text((t1 + 6.0, y), "t", 12.0, style::ink(), Anchor::Left);
}

/// The tick labels' size.
const TICK: f32 = 10.0;

/// The largest t the right panel must show: the latest finite bound or entry shown. When the
/// exit bound is ∞ (no axis bounds the bundle), on to where the entering rays leave the box
/// (its far side), so that the axis spans the box; and when nothing shown is past 0, that far
/// side, or else 1: an axis from 0 to 0 has nothing to mark.
fn reach(rays: &[Ray], w: &BundleWorking, bounds: Option<(f32, f32)>) -> f64 {
    let shown = bounds
        .iter()
        .flat_map(|&(a, b)| [a, b])
        .chain(w.rays.iter().filter(|v| v.own).map(|v| v.t_enter))
        .filter(|t| t.is_finite())
        .fold(0.0f32, f32::max) as f64;
    let open = bounds.is_some_and(|(_, b)| !b.is_finite());
    if shown > 0.0 && !open {
        return shown;
    }
    let (min, max) = (w.min.map(f64::from), w.max.map(f64::from));
    let far = rays
        .iter()
        .zip(&w.rays)
        .filter(|(_, v)| v.own)
        .filter_map(|(r, _)| {
            (0..3)
                .filter(|&k| r.dir[k] != 0.0)
                .map(|k| {
                    let (a, b) = (
                        (min[k] - r.origin[k]) / r.dir[k],
                        (max[k] - r.origin[k]) / r.dir[k],
                    );
                    a.max(b)
                })
                .reduce(f64::min)
        })
        .filter(|t| t.is_finite())
        .fold(0.0, f64::max);
    match shown.max(far) {
        t if t > 0.0 && t.is_finite() => t,
        _ => 1.0,
    }
}

/// The t axis's ticks on an axis `width` pixels long, from 0 to at least `reach` (> 0): the
/// axis's end, and each tick's t and label. The ticks are multiples of a step of 1, 2 or 5
/// × 10^k, the axis ends at the first multiple at or past `reach`, and the step is the
/// smallest giving at most five intervals whose labels do not overlap (one interval, 0 and
/// the step, always fits). Labels are exact and short: "0.5", "20", "1.5e12", "3e-7"
/// (scientific notation from 10⁵ up, or for a step under 10⁻³).
fn ticks(reach: f64, width: f32) -> (f64, Vec<(f64, String)>) {
    let reach = if reach > 0.0 && reach.is_finite() {
        reach
    } else {
        1.0
    };
    let k0 = (reach / 5.0).log10().floor() as i32;
    let mut last = None;
    for k in k0..=k0 + 2 {
        for m in [1u64, 2, 5] {
            let step = m as f64 * 10f64.powi(k);
            if step * 5.0 < reach * (1.0 - 1e-9) {
                continue;
            }
            let n = ((reach / step) * (1.0 - 1e-12)).ceil().max(1.0) as u64;
            let end = step * n as f64;
            let sci = end >= 1e5 || k < -3;
            let ticks: Vec<(f64, String)> = (0..=n)
                .map(|i| (step * i as f64, tick_label(i * m, k, sci)))
                .collect();
            let gap = width / n as f32;
            let fits = ticks.windows(2).all(|p| {
                let half = |s: &str| Canvas::text_width(s, TICK) / 2.0;
                half(&p[0].1) + half(&p[1].1) + 6.0 <= gap
            });
            if fits || n == 1 {
                return (end, ticks);
            }
            last = Some((end, ticks));
        }
    }
    last.expect("a step")
}

/// v × 10^k, exactly: "0", "40", "0.25", or with `sci`, "2.5e12", "3e-7".
fn tick_label(v: u64, k: i32, sci: bool) -> String {
    if v == 0 {
        return "0".into();
    }
    let mut digits = v.to_string();
    let mut k = k;
    while digits.ends_with('0') {
        digits.pop();
        k += 1;
    }
    if sci {
        let exp = k + digits.len() as i32 - 1;
        let (lead, rest) = digits.split_at(1);
        let dot = if rest.is_empty() { "" } else { "." };
        return format!("{lead}{dot}{rest}e{exp}");
    }
    if k >= 0 {
        return digits + &"0".repeat(k as usize);
    }
    let places = (-k) as usize;
    let padded = format!("{digits:0>width$}", width = places + 1);
    let (int, frac) = padded.split_at(padded.len() - places);
    format!("{int}.{frac}")
}
