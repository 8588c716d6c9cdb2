//! The legend under the plot (what each mark means, only those the tree uses) and the
//! scale bar in its corner.

use super::frame::{Frame, View};
use super::Drawn;
use crate::trace::{End, RayKind};
use crate::viz::style;
use crate::viz::{Anchor, Canvas};
use tiny_skia::Color;

/// The legend's rows for a figure `width` pixels wide. Its entries cover the whole tree, so
/// a storyboard's frames keep one layout (and the legend says what is coming).
pub(super) fn legend(every: &[Drawn], frame: &Frame, width: f32) -> Vec<Vec<(LegendMark, String)>> {
    let mut kinds: Vec<RayKind> = Vec::new();
    let (mut any_blocked, mut any_off, mut any_hit) = (false, false, false);
    for e in every {
        if !kinds.contains(&e.node.kind) {
            kinds.push(e.node.kind);
        }
        any_blocked |= e.node.end == End::Blocked;
        any_off |= frame.off_plane(e.node.direction) > 0.03;
        any_hit |= e.node.hit.is_some() && e.node.kind != RayKind::Shadow;
    }
    kinds.sort_by_key(|k| *k as u8);
    let legend = legend_items(&kinds, any_blocked, any_off, any_hit);
    layout_legend(&legend, width)
}

/// A "1 unit" style bar in the plot's lower-left corner, with a round length.
pub(super) fn scale_bar(canvas: &mut Canvas, view: &View) {
    let target = 90.0 / view.scale;
    let p = 10f64.powf(target.log10().floor());
    let len = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * p)
        .rfind(|l| l * view.scale <= 120.0)
        .unwrap_or(p);
    let px = (len * view.scale) as f32;
    let (x, y) = (view.rect[0] + 8.0, view.rect[3] - 8.0);
    canvas.line((x, y), (x + px, y), style::ink(), 1.5, false);
    canvas.line((x, y - 4.0), (x, y + 1.0), style::ink(), 1.5, false);
    canvas.line(
        (x + px, y - 4.0),
        (x + px, y + 1.0),
        style::ink(),
        1.5,
        false,
    );
    let units = if len == 1.0 { "unit" } else { "units" };
    canvas.text(
        (x + px + 6.0, y - 2.0),
        &format!("{} {units}", crate::shapes::working::short(len)),
        11.0,
        style::ink(),
        Anchor::Left,
    );
}

#[derive(Debug, Clone)]
pub(super) enum LegendMark {
    Ray(Color, bool),
    Cross,
    Normal,
    Dot,
}

fn legend_items(
    kinds: &[RayKind],
    blocked: bool,
    off: bool,
    hit: bool,
) -> Vec<(LegendMark, String)> {
    let mut v: Vec<(LegendMark, String)> = kinds
        .iter()
        .map(|k| {
            let name = match k {
                RayKind::Camera => "camera ray",
                RayKind::Shadow => "shadow ray",
                RayKind::Reflection => "reflection",
                RayKind::Refraction => "refraction",
                RayKind::Transmission => "transmission",
            };
            (LegendMark::Ray(style::ray(*k), false), name.to_string())
        })
        .collect();
    if hit {
        v.push((LegendMark::Dot, "hit".into()));
        v.push((LegendMark::Normal, "normal".into()));
    }
    if blocked {
        v.push((LegendMark::Cross, "shadow ray blocked".into()));
    }
    if off {
        v.push((
            LegendMark::Ray(style::muted(), true),
            "leaves the slice (projected)".into(),
        ));
    }
    v
}

const LEGEND_SIZE: f32 = 12.0;

fn item_width(text: &str) -> f32 {
    30.0 + Canvas::text_width(text, LEGEND_SIZE) + 16.0
}

fn layout_legend(items: &[(LegendMark, String)], width: f32) -> Vec<Vec<(LegendMark, String)>> {
    let mut rows: Vec<Vec<(LegendMark, String)>> = vec![Vec::new()];
    let mut x = 0.0;
    for it in items {
        let w = item_width(&it.1);
        if x + w > width && !rows.last().expect("a row").is_empty() {
            rows.push(Vec::new());
            x = 0.0;
        }
        x += w;
        rows.last_mut().expect("a row").push(it.clone());
    }
    rows
}

pub(super) fn draw_legend(canvas: &mut Canvas, rows: &[Vec<(LegendMark, String)>], top: f32) {
    for (r, row) in rows.iter().enumerate() {
        let total: f32 = row.iter().map(|i| item_width(&i.1)).sum::<f32>() - 16.0;
        let mut x = (canvas.width() - total) / 2.0;
        let y = top + 9.0 + 18.0 * r as f32;
        for (mark, text) in row {
            match mark {
                LegendMark::Ray(c, dashed) => {
                    if *dashed {
                        canvas.line((x, y), (x + 24.0, y), *c, 2.0, true);
                    } else {
                        canvas.arrow((x, y), (x + 24.0, y), *c, 2.0);
                    }
                }
                LegendMark::Cross => {
                    let (cx, s) = (x + 12.0, 4.5);
                    canvas.line((cx - s, y - s), (cx + s, y + s), style::hit(), 2.2, false);
                    canvas.line((cx - s, y + s), (cx + s, y - s), style::hit(), 2.2, false);
                }
                LegendMark::Normal => {
                    canvas.arrow((x + 2.0, y), (x + 22.0, y), style::normal(), 1.6)
                }
                LegendMark::Dot => canvas.circle((x + 12.0, y), 4.0, None, Some(style::hit())),
            }
            canvas.text((x + 30.0, y), text, LEGEND_SIZE, style::ink(), Anchor::Left);
            x += item_width(text);
        }
    }
}
