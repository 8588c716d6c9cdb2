//! The figure of `rtlab diff`: expected | yours | the difference as a heat map, each region
//! outlined and numbered on the last two, and a table saying per region where it is, how it
//! differs, the term and the mistake that explain it, and the command that explains a pixel.

use super::heatmap::heat_map;
use super::{style, Anchor, Canvas};
use crate::diff::{report, terms, Report};
use crate::scene::Scene;
use image::RgbImage;

/// The difference (largest channel, levels) drawn brightest: larger ones saturate.
pub const HEAT_LEVELS: f64 = 64.0;

/// Shown images are about this wide: small images magnified by a whole factor, large ones
/// shrunk.
const PANEL: u32 = 300;

/// What the table says of a region's best mistake.
pub fn best_mistake(scene: &Scene, g: &crate::diff::Region) -> String {
    g.mistakes
        .first()
        .map_or("(none of the catalogue)".into(), |f| {
            format!(
                "{} ({:.0} %)",
                crate::diff::suspects::added(scene, f).join(" + "),
                100.0 * f.explained
            )
        })
}

/// Draws the figure.
pub fn figure(scene: &Scene, expected: &RgbImage, yours: &RgbImage, rep: &Report) -> Canvas {
    let (iw, ih) = expected.dimensions();
    let diff: Vec<f64> = expected
        .pixels()
        .zip(yours.pixels())
        .map(|(a, b)| (0..3).map(|c| a[c].abs_diff(b[c])).max().unwrap_or(0) as f64)
        .collect();
    let heat = heat_map(&diff, iw, ih, HEAT_LEVELS);
    // Magnify by a whole factor, or shrink by one (box-filtered) to about PANEL pixels.
    let (up, down) = if iw <= PANEL {
        (((PANEL + iw / 2) / iw).max(1), 1)
    } else {
        (1, iw.div_ceil(PANEL))
    };
    let shown = |img: &RgbImage| -> RgbImage {
        if down == 1 {
            img.clone()
        } else {
            image::imageops::resize(
                img,
                (iw / down).max(1),
                (ih / down).max(1),
                image::imageops::FilterType::Triangle,
            )
        }
    };
    let f = up as f32 / down as f32; // displayed pixels per image pixel
    let (pw, ph) = (
        (iw as f32 * f).round() as u32,
        (ih as f32 * f).round() as u32,
    );
    let (margin, gap, label_h) = (16u32, 16u32, 26u32);
    let ink = style::ink();
    let muted = style::muted();
    let mark = style::rgb(0, 200, 255);

    // The table, measured first so the figure is as wide as it needs.
    let head = [
        "region",
        "pixels",
        "objects",
        "yours − expected",
        "best term",
        "best mistake",
    ];
    let rows: Vec<[String; 6]> = rep
        .regions
        .iter()
        .enumerate()
        .map(|(i, g)| {
            [
                (i + 1).to_string(),
                g.members.len().to_string(),
                report::objects_words(g),
                report::difference_words(g.mean_difference),
                match g.fit.terms.first() {
                    Some(t) if g.fit.explained >= report::WELL_EXPLAINED => {
                        format!(
                            "{} ({:.0} %)",
                            terms::sentence(scene, t),
                            100.0 * t.explained
                        )
                    }
                    _ => "(no lighting term explains it)".into(),
                },
                best_mistake(scene, g),
            ]
        })
        .collect();
    let size = 12.0f32;
    let col_w: Vec<f32> = (0..6)
        .map(|k| {
            rows.iter()
                .map(|r| Canvas::text_width(&r[k], size))
                .chain(std::iter::once(Canvas::text_width(head[k], size)))
                .fold(0.0, f32::max)
                + 18.0
        })
        .collect();
    let explain_w = rep
        .regions
        .iter()
        .map(|g| Canvas::text_width(&g.explain, 11.0) + col_w[0])
        .fold(0.0, f32::max);
    let table_w = col_w.iter().sum::<f32>().max(explain_w) as u32;
    let row_h = 34u32;
    let table_h = if rows.is_empty() {
        0
    } else {
        22 + row_h * rows.len() as u32 + 8
    };
    let title_h = 24u32;
    let width = margin * 2 + (3 * pw + 2 * gap).max(table_w);
    let height = margin + title_h + label_h + ph + 28 + table_h + margin;
    let mut c = Canvas::new(width, height, style::background());

    let m = &rep.metrics;
    let verdict = format!(
        "{}: {:.2} % of the pixels differ by more than {} levels (largest {}, {}); {} region{}",
        if rep.same { "same" } else { "different" },
        m.diff_percent,
        m.tolerance,
        m.max,
        m.psnr
            .map_or("identical".into(), |p| format!("PSNR {p:.1} dB")),
        rep.regions_found,
        if rep.regions_found == 1 { "" } else { "s" }
    );
    c.text(
        (margin as f32, (margin + title_h / 2) as f32),
        &verdict,
        14.0,
        ink,
        Anchor::Left,
    );
    let top = margin + title_h;
    let panels = [
        ("expected", shown(expected)),
        ("yours", shown(yours)),
        ("difference (black 0, yellow ≥ 64 levels)", shown(&heat)),
    ];
    for (i, (label, img)) in panels.iter().enumerate() {
        let x0 = margin + i as u32 * (pw + gap);
        let sz = (13.0 * pw as f32 / Canvas::text_width(label, 13.0)).min(13.0);
        c.text(
            ((x0 + pw / 2) as f32, (top + label_h / 2) as f32),
            label,
            sz,
            ink,
            Anchor::Center,
        );
        let y0 = top + label_h;
        c.image((x0 as i32, y0 as i32), img, up);
        if i == 0 {
            continue;
        }
        for (k, g) in rep.regions.iter().enumerate() {
            let b = g.bbox;
            let (rx, ry) = (x0 as f32 + b[0] as f32 * f, y0 as f32 + b[1] as f32 * f);
            let (rw, rh) = (
                ((b[2] - b[0] + 1) as f32 * f).max(3.0),
                ((b[3] - b[1] + 1) as f32 * f).max(3.0),
            );
            c.rect(
                (rx - 1.5, ry - 1.5),
                (rw + 3.0, rh + 3.0),
                Some((mark, 1.5)),
                None,
            );
            let n = (k + 1).to_string();
            let tw = Canvas::text_width(&n, 11.0) + 6.0;
            // The number on a tab at the box's top-left corner, inside the panel.
            let tx = (rx - 1.5).min((x0 + pw) as f32 - tw).max(x0 as f32);
            let ty = if ry - 15.0 >= y0 as f32 {
                ry - 15.0
            } else {
                ry
            };
            c.rect((tx, ty), (tw, 13.0), None, Some(mark));
            c.text(
                (tx + 3.0, ty + 6.5),
                &n,
                11.0,
                style::rgb(0, 0, 0),
                Anchor::Left,
            );
        }
    }

    if rows.is_empty() {
        return c;
    }
    let mut y = top + label_h + ph + 28;
    let x_at = |k: usize| margin as f32 + col_w[..k].iter().sum::<f32>();
    for (k, h) in head.iter().enumerate() {
        c.text((x_at(k), y as f32 + 8.0), h, size, ink, Anchor::Left);
    }
    c.line(
        (margin as f32, y as f32 + 18.0),
        (margin as f32 + table_w as f32, y as f32 + 18.0),
        muted,
        1.0,
        false,
    );
    y += 22;
    for (row, g) in rows.iter().zip(&rep.regions) {
        for (k, t) in row.iter().enumerate() {
            c.text((x_at(k), y as f32 + 9.0), t, size, ink, Anchor::Left);
        }
        c.text(
            (x_at(1), y as f32 + 24.0),
            &g.explain,
            11.0,
            muted,
            Anchor::Left,
        );
        y += row_h;
    }
    c
}
