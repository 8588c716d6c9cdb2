//! The figure of `rtlab intersect box --bundle-to`: a bundle of rays against one box of a
//! BVH node. Left, the rays and the box seen along the axis the rays move along least (y
//! when that is a tie), with the interval test's two bounds drawn where they fall on every
//! ray; right, the same test along t: each axis's bounds as a bar (or, for a bundle that is
//! not sign-coherent, which axes change sign), the three together, and each ray's own
//! entry.

use super::canvas::{Anchor, Canvas};
use super::style;
use crate::accel::BundleWorking;
use crate::math::Ray;
use crate::shapes::working::{short, tiny};
use glam::DVec2;

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
            mixed_axes(w)
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

const AXES: [&str; 3] = ["x", "y", "z"];

/// The axes along which the directions change sign: "x", "x and y".
fn mixed_axes(w: &BundleWorking) -> String {
    let names: Vec<&str> = (0..3)
        .filter(|&k| !w.coherent_axes[k])
        .map(|k| AXES[k])
        .collect();
    match names.as_slice() {
        [] => "no axis".into(),
        [one] => one.to_string(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}

/// The left panel's projection: the scene seen along one axis, drawn in pixels, one scale
/// for both directions.
struct View {
    /// The axis seen along, then the axes drawn to the right and up.
    axes: [usize; 3],
    /// The panel, in pixels: (x0, y0, x1, y1).
    rect: (f64, f64, f64, f64),
    /// The point drawn at the panel's centre, (right, up), and pixels per unit.
    centre: DVec2,
    scale: f64,
}

impl View {
    /// Seen along the axis that shows the bundle best: of the views in which every ray
    /// is a clear line (at least half its length across the view; the axis in which the
    /// unit directions are smallest always qualifies, at worst with 0.58), the one in which
    /// the rays fan out most; y on ties (the book's view). To the right, of the other two
    /// axes, the one the rays move along most (on ties, the next after the view axis: z, x
    /// for y), so P + t·d reads left to right as on the t axis. The box and P fill the panel.
    fn new(rays: &[Ray], w: &BundleWorking, (x0, y0, x1, y1): (f32, f32, f32, f32)) -> View {
        let unit = |r: &Ray, k: usize| (r.dir[k] / r.dir.length()).abs();
        let most = |k: usize| rays.iter().map(|r| unit(r, k)).fold(0.0, f64::max);
        let mean = |k: usize| rays.iter().map(|r| unit(r, k)).sum::<f64>();
        let across = |k: usize, d: glam::DVec3| DVec2::new(d[(k + 1) % 3], d[(k + 2) % 3]);
        let clear = |k: usize| {
            rays.iter()
                .all(|r| across(k, r.dir).length() >= 0.5 * r.dir.length())
        };
        let fan = |k: usize| {
            let (a, b) = (across(k, rays[0].dir), across(k, rays[rays.len() - 1].dir));
            a.angle_to(b).abs()
        };
        // The first of the clear views that fans out most; never empty, but should it be,
        // the axis in which the directions are smallest.
        let along = [1, 0, 2]
            .into_iter()
            .filter(|&k| clear(k))
            .reduce(|best, k| if fan(k) > fan(best) + 1e-9 { k } else { best })
            .unwrap_or_else(|| {
                [1, 0, 2]
                    .into_iter()
                    .min_by(|&a, &b| most(a).total_cmp(&most(b)))
                    .expect("three axes")
            });
        let (mut right, mut up) = ((along + 1) % 3, (along + 2) % 3);
        if mean(up) > mean(right) {
            (right, up) = (up, right);
        }
        let flat = |p: [f64; 3]| DVec2::new(p[right], p[up]);
        let (bmin, bmax) = (flat(w.min.map(f64::from)), flat(w.max.map(f64::from)));
        let origin = flat(rays[0].origin.to_array());
        let (lo, hi) = (bmin.min(origin), bmax.max(origin));
        let pad = (hi - lo).max_element().max(1e-6) * 0.15;
        let (lo, hi) = (lo - pad, hi + pad);
        let rect = (x0 as f64, y0 as f64, x1 as f64, y1 as f64);
        let scale = ((rect.2 - rect.0) / (hi.x - lo.x)).min((rect.3 - rect.1) / (hi.y - lo.y));
        View {
            axes: [along, right, up],
            rect,
            centre: (lo + hi) * 0.5,
            scale,
        }
    }

    /// A 3D point in pixels.
    fn px(&self, p: glam::DVec3) -> DVec2 {
        let (x0, y0, x1, y1) = self.rect;
        DVec2::new(
            (x0 + x1) / 2.0 + (p[self.axes[1]] - self.centre.x) * self.scale,
            (y0 + y1) / 2.0 - (p[self.axes[2]] - self.centre.y) * self.scale,
        )
    }

    fn inside(&self, p: DVec2) -> bool {
        let (x0, y0, x1, y1) = self.rect;
        (x0..=x1).contains(&p.x) && (y0..=y1).contains(&p.y)
    }

    /// The part of segment a–b inside the panel (Liang–Barsky), or `None`.
    fn clip(&self, a: DVec2, b: DVec2) -> Option<(DVec2, DVec2)> {
        let (x0, y0, x1, y1) = self.rect;
        let d = b - a;
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        for (p, q) in [
            (-d.x, a.x - x0),
            (d.x, x1 - a.x),
            (-d.y, a.y - y0),
            (d.y, y1 - a.y),
        ] {
            if p == 0.0 {
                if q < 0.0 {
                    return None;
                }
            } else if p < 0.0 {
                t0 = t0.max(q / p);
            } else {
                t1 = t1.min(q / p);
            }
        }
        (t0 <= t1 && a.is_finite() && b.is_finite()).then(|| (a + d * t0, a + d * t1))
    }

    /// The t at which `r`, from P inside the panel, leaves it: `None` for a ray seen
    /// end-on (its motion across the view under 10⁻⁶ of its length; the choice of view
    /// rules that out, but the drawing must not depend on it). Such a ray has no such t:
    /// an unguarded ∞ here put 0·∞ = NaN into the drawing, which tiny-skia drew as a line
    /// towards the canvas's corner, through the title.
    fn leave(&self, r: &Ray) -> Option<f64> {
        let (x0, y0, x1, y1) = self.rect;
        let (o, d) = (
            self.px(r.origin),
            self.px(r.origin + r.dir) - self.px(r.origin),
        );
        // Across the view, in pixels per unit of t, against the whole direction's length.
        if d.length() < 1e-6 * r.dir.length() * self.scale {
            return None;
        }
        let mut t = f64::INFINITY;
        for (o, d, lo, hi) in [(o.x, d.x, x0, x1), (o.y, d.y, y0, y1)] {
            if d != 0.0 {
                t = t.min(((lo - o) / d).max((hi - o) / d));
            }
        }
        t.is_finite().then_some(t)
    }
}

fn pt(p: DVec2) -> (f32, f32) {
    (p.x as f32, p.y as f32)
}

/// A text's rectangle (x0, y0, x1, y1), as [`Canvas::text`] places it.
fn text_area(at: DVec2, text: &str, size: f32, anchor: Anchor) -> (f64, f64, f64, f64) {
    let w = Canvas::text_width(text, size) as f64;
    let x = match anchor {
        Anchor::Left => at.x,
        Anchor::Center => at.x - w / 2.0,
        Anchor::Right => at.x - w,
    };
    let h = size as f64 * 0.6;
    (x, at.y - h, x + w, at.y + h)
}

fn overlap(a: (f64, f64, f64, f64), b: (f64, f64, f64, f64)) -> bool {
    a.0 < b.2 && b.0 < a.2 && a.1 < b.3 && b.1 < a.3
}

/// A label's `area` is inside the panel and clear of every area `taken`.
fn free(v: &View, taken: &[(f64, f64, f64, f64)], area: (f64, f64, f64, f64)) -> bool {
    let (x0, y0, x1, y1) = v.rect;
    area.0 >= x0 + 2.0
        && area.2 <= x1 - 2.0
        && area.1 >= y0 + 2.0
        && area.3 <= y1 - 2.0
        && !taken.iter().any(|&t| overlap(t, area))
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
    // Labels are kept off each other and off P: `taken` holds what is written so far.
    let o = v.px(rays[0].origin);
    let p_label = o + DVec2::new(0.0, 14.0);
    let mut taken = vec![
        (o.x - 5.0, o.y - 5.0, o.x + 5.0, o.y + 5.0),
        text_area(p_label, "P", 12.0, Anchor::Center),
    ];
    let dots: Vec<DVec2> = rays
        .iter()
        .zip(&w.rays)
        .filter(|(_, verdict)| verdict.own)
        .map(|(r, verdict)| v.px(r.at(verdict.t_enter as f64)))
        .collect();
    taken.extend(
        dots.iter()
            .map(|d| (d.x - 4.0, d.y - 4.0, d.x + 4.0, d.y + 4.0)),
    );
    // Outside the box, under it if that is clear: a label inside would cover the entry
    // dots of the rays that enter through its sides.
    let box_label = [
        (DVec2::new(far.x, far.y + 9.0), Anchor::Right),
        (DVec2::new(corner.x, far.y + 9.0), Anchor::Left),
        (DVec2::new(far.x, corner.y - 9.0), Anchor::Right),
        (DVec2::new(corner.x, corner.y - 9.0), Anchor::Left),
    ]
    .into_iter()
    .find(|&(at, anchor)| free(v, &taken, text_area(at, "box", 11.0, anchor)))
    .unwrap_or((DVec2::new(far.x, far.y + 9.0), Anchor::Right));
    taken.push(text_area(box_label.0, "box", 11.0, box_label.1));
    c.text(pt(box_label.0), "box", 11.0, style::muted(), box_label.1);
    // Each ray from its origin to where it leaves the panel; a ray seen end-on as a ring.
    for (r, verdict) in rays.iter().zip(&w.rays) {
        let color = if verdict.lane.unwrap_or(verdict.own) {
            style::ray(crate::trace::RayKind::Camera)
        } else {
            style::tossed()
        };
        match v
            .leave(r)
            .and_then(|t| v.clip(v.px(r.origin), v.px(r.at(t))))
        {
            Some((a, b)) => c.line(pt(a), pt(b), color, 1.0, false),
            None => c.circle(pt(v.px(r.origin)), 7.0, Some((color, 1.0)), None),
        }
    }
    // The bounds: where each ray is at t = bound, joined across the bundle; left out when
    // some ray is out of the panel by then, or when the front is a point (t = 0 at a
    // shared P: the right panel shows it).
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
            let above = (top + DVec2::new(0.0, -12.0), Anchor::Center);
            let below = (low + DVec2::new(0.0, 12.0), Anchor::Center);
            let mut tries = if name == "entry bound" {
                vec![above, below]
            } else {
                vec![below, above]
            };
            tries.extend([
                (right + DVec2::new(8.0, 0.0), Anchor::Left),
                (left + DVec2::new(-8.0, 0.0), Anchor::Right),
            ]);
            let text = format!("t = {name}");
            let fits = |&(at, anchor): &(DVec2, Anchor)| {
                free(v, &taken, text_area(at, &text, 11.0, anchor))
            };
            if let Some((at, anchor)) = tries.iter().copied().find(fits) {
                // On a plate of the background, so that the rays under it do not cross it.
                let area = text_area(at, &text, 11.0, anchor);
                taken.push(area);
                c.rect(
                    (area.0 as f32 - 2.0, area.1 as f32),
                    ((area.2 - area.0) as f32 + 4.0, (area.3 - area.1) as f32),
                    None,
                    Some(style::background()),
                );
                c.text(pt(at), &text, 11.0, style::ink(), anchor);
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
    c.text(pt(p_label), "P", 12.0, style::ink(), Anchor::Center);
}

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
    // every ray's entry; a bar beyond either end is cut there, its true end written beside.
    let focus = bounds
        .iter()
        .flat_map(|&(a, b)| [a, b])
        .chain(w.rays.iter().filter(|v| v.own).map(|v| v.t_enter))
        .filter(|t| t.is_finite());
    let t_max = focus.fold(0.0f32, f32::max).max(1e-6) * 1.6;
    let at = |t: f32| t0 + (t.clamp(0.0, t_max) / t_max) * (t1 - t0);
    let rows = 6.0;
    let row_h = ((y1 - y0) - 40.0) / rows;
    let row_y = |i: usize| y0 + 10.0 + row_h * (i as f32 + 0.5);
    let num = |t: f32| {
        if t.is_finite() {
            short(t as f64)
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
                &format!("no interval test: mixed along {}", mixed_axes(w)),
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
    for i in 0..=4 {
        let t = t_max * i as f32 / 4.0;
        c.line((at(t), y - 4.0), (at(t), y + 4.0), style::ink(), 1.0, false);
        c.text(
            (at(t), y + 14.0),
            &num(t),
            10.0,
            style::ink(),
            Anchor::Center,
        );
    }
    c.text((t1 + 6.0, y), "t", 12.0, style::ink(), Anchor::Left);
}
