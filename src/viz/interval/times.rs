//! The right panel of the interval figure: the test along t, a bar per slab from its entry
//! bound to its exit bound, the three together, each ray's own entry, and the t axis.

use crate::accel::BundleWorking;
use crate::math::Ray;
use crate::shapes::working::tiny;
use crate::viz::canvas::{Anchor, Canvas};
use crate::viz::style;

/// Right panel: the t axis, a row per slab, the three together, and the rays' own entries.
pub(super) fn times(
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
    for &t in &own {
        c.circle(
            (at(t), y),
            3.5,
            Some((style::background(), 1.2)),
            Some(style::hit()),
        );
    }
    if let Some(note) = overlap_note(&own, at, num) {
        c.text((t0, y + 17.0), &note, 11.0, style::muted(), Anchor::Left);
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

/// Entries closer than a dot's width (7 px at `at`'s scale) draw as one dot, or as dots that
/// overlap: the note that says so when fewer dots than rays show (`num` writes a t).
fn overlap_note(
    own: &[f32],
    at: impl Fn(f32) -> f32,
    num: impl Fn(f32) -> String,
) -> Option<String> {
    let mut sorted = own.to_vec();
    sorted.sort_by(f32::total_cmp);
    let apart = sorted
        .windows(2)
        .filter(|p| at(p[1]) - at(p[0]) >= 7.0)
        .count();
    match (sorted.first(), sorted.last()) {
        (Some(&a), Some(&b)) if own.len() > 1 && num(a) == num(b) => Some(format!(
            "{} rays, one dot: {} enter at t = {}",
            own.len(),
            if own.len() == 2 { "both" } else { "all" },
            num(a)
        )),
        (Some(&a), Some(&b)) if apart + 1 < own.len() => Some(format!(
            "{} rays, overlapping dots: t = {a:.2} to {b:.2}",
            own.len()
        )),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::overlap_note;

    fn note(own: &[f32]) -> Option<String> {
        // 10 px a unit of t.
        overlap_note(own, |t| t * 10.0, |t| format!("{t}"))
    }

    #[test]
    fn a_note_only_when_fewer_dots_than_rays_show() {
        assert_eq!(note(&[]), None);
        assert_eq!(note(&[2.5]), None);
        assert_eq!(
            note(&[1.0, 2.0, 3.0]),
            None,
            "7 px or more apart: every dot shows"
        );
        assert_eq!(
            note(&[4.0, 4.0]).as_deref(),
            Some("2 rays, one dot: both enter at t = 4")
        );
        assert_eq!(
            note(&[4.0; 8]).as_deref(),
            Some("8 rays, one dot: all enter at t = 4")
        );
        assert_eq!(
            note(&[1.0, 1.5, 3.0]).as_deref(),
            Some("3 rays, overlapping dots: t = 1.00 to 3.00")
        );
    }
}
