//! The sampling comparison figure of `rtlab compare`: renders side by side with labels, a
//! magnified nearest-neighbour crop of each, an error heat map of each against a high-spp
//! reference, and a metrics table. Everything drawn is a function of the images and counts,
//! never of the clock (unless `show_time`), so the figure's bytes are deterministic.

use super::heatmap::{heat_map, spp_heat_map};
use super::{style, Anchor, Canvas};
use image::RgbImage;

/// One rendered column of the figure.
#[derive(Debug, Clone)]
pub struct Panel {
    /// e.g. "1 spp · center".
    pub label: String,
    pub image: RgbImage,
    pub samples: u64,
    pub rays: u64,
    pub seconds: f64,
    pub rmse: f64,
    pub psnr: Option<f64>,
    /// Samples traced per pixel ([`crate::sampling::RenderOutput::spp_map`]).
    pub spp_map: Vec<u32>,
}

/// The error that the heat maps draw brightest (errors above saturate).
pub const ERROR_SCALE: f64 = 0.25;

/// A crop rectangle in image pixels: x, y, width, height.
pub type Crop = (u32, u32, u32, u32);

// ANCHOR: metrics
/// Per-pixel error of `image` against `reference`: the root mean square over the three
/// channels, in [0, 1] (bytes / 255).
pub fn error_map(image: &RgbImage, reference: &RgbImage) -> Vec<f64> {
    image
        .pixels()
        .zip(reference.pixels())
        .map(|(a, b)| {
            let s: f64 = (0..3)
                .map(|c| ((a[c] as f64 - b[c] as f64) / 255.0).powi(2))
                .sum();
            (s / 3.0).sqrt()
        })
        .collect()
}

/// RMSE over every channel of every pixel (bytes / 255), and PSNR = 20·log10(1 / RMSE) in dB
/// (`None` when the images are identical: infinitely many dB).
pub fn rmse_psnr(image: &RgbImage, reference: &RgbImage) -> (f64, Option<f64>) {
    let e = error_map(image, reference);
    let mse = e.iter().map(|x| x * x).sum::<f64>() / e.len().max(1) as f64;
    let rmse = mse.sqrt();
    (rmse, (rmse > 0.0).then(|| 20.0 * (1.0 / rmse).log10()))
}
// ANCHOR_END: metrics

/// The crop of `width`×`height` whose summed error in `error` (a `image_w`-wide map) is
/// largest; the first such in reading order, scanning every `step` pixels.
pub fn worst_crop(error: &[f64], image_w: u32, image_h: u32, width: u32, height: u32) -> Crop {
    let (w, h) = (image_w as usize, image_h as usize);
    let (cw, ch) = (width.min(image_w) as usize, height.min(image_h) as usize);
    // Summed-area table: sat[(y)(w+1) + x] = Σ error over [0, x) × [0, y).
    let mut sat = vec![0.0; (w + 1) * (h + 1)];
    for y in 0..h {
        let mut row = 0.0;
        for x in 0..w {
            row += error[y * w + x] * error[y * w + x];
            sat[(y + 1) * (w + 1) + x + 1] = sat[y * (w + 1) + x + 1] + row;
        }
    }
    let sum = |x: usize, y: usize| {
        sat[(y + ch) * (w + 1) + x + cw] - sat[y * (w + 1) + x + cw] - sat[(y + ch) * (w + 1) + x]
            + sat[y * (w + 1) + x]
    };
    let mut best = (0, 0, f64::NEG_INFINITY);
    for y in 0..=(h - ch) {
        for x in 0..=(w - cw) {
            let s = sum(x, y);
            if s > best.2 + 1e-12 {
                best = (x, y, s);
            }
        }
    }
    (best.0 as u32, best.1 as u32, cw as u32, ch as u32)
}

fn crop_of(img: &RgbImage, c: Crop) -> RgbImage {
    image::imageops::crop_imm(img, c.0, c.1, c.2, c.3).to_image()
}

fn fmt_count(n: u64) -> String {
    crate::report::thousands(n)
}

/// Draws the comparison: one column per panel plus the reference, rows image / crop / error,
/// and, with `spp_row` (an adaptive run is shown), the samples each pixel traced.
pub fn figure(
    panels: &[Panel],
    reference: &RgbImage,
    reference_label: &str,
    crop: Crop,
    show_time: bool,
    spp_row: bool,
) -> Canvas {
    let (iw, ih) = reference.dimensions();
    // Images are shown at least ~220 px wide, magnified by a whole factor (nearest neighbour).
    let scale = (220 / iw).max(1);
    let (pw, ph) = (iw * scale, ih * scale);
    let zoom = (pw / crop.2.max(1)).max(1);
    let (cw, chh) = (crop.2 * zoom, crop.3 * zoom);
    let gap = 16u32;
    let margin = 16u32;
    let cols = panels.len() as u32 + 1;
    let label_h = 26u32;
    let row_title = 20u32;
    let table_row = 22u32;
    let table_h = table_row * (panels.len() as u32 + 1) + 16;
    let col_w = [170.0f32, 100.0, 110.0, 80.0, 90.0, 80.0];
    let table_w = col_w[..if show_time { 6 } else { 5 }].iter().sum::<f32>() as u32;
    let width = margin * 2 + (cols * pw + (cols - 1) * gap).max(table_w);
    let spp_h = if spp_row { row_title + ph } else { 0 };
    let height =
        margin + label_h + ph + row_title + chh + row_title + ph + spp_h + 34 + table_h + margin;
    let max_spp = panels
        .iter()
        .flat_map(|p| p.spp_map.iter())
        .copied()
        .max()
        .unwrap_or(1)
        .max(1);
    let mut c = Canvas::new(width, height, style::background());
    let ink = style::ink();
    let muted = style::muted();
    let mark = style::rgb(0, 200, 255);

    let errors: Vec<Vec<f64>> = panels
        .iter()
        .map(|p| error_map(&p.image, reference))
        .collect();
    // One fixed scale for every heat map, so columns (and figures) can be compared by eye;
    // errors of a quarter of the range and more are all bright yellow.
    let max_err = ERROR_SCALE;

    type Column<'a> = (&'a str, &'a RgbImage, Option<(&'a Vec<f64>, &'a Vec<u32>)>);
    let columns: Vec<Column> = panels
        .iter()
        .zip(&errors)
        .map(|(p, e)| (p.label.as_str(), &p.image, Some((e, &p.spp_map))))
        .chain(std::iter::once((reference_label, reference, None)))
        .collect();
    for (i, (label, img, err)) in columns.iter().enumerate() {
        let x0 = margin + i as u32 * (pw + gap);
        let mut y = margin;
        // Long labels shrink to fit their column.
        let size = (15.0 * (pw + gap / 2) as f32 / Canvas::text_width(label, 15.0)).min(15.0);
        c.text(
            ((x0 + pw / 2) as f32, (y + label_h / 2) as f32),
            label,
            size,
            ink,
            Anchor::Center,
        );
        y += label_h;
        c.image((x0 as i32, y as i32), img, scale);
        c.rect(
            (
                (x0 + crop.0 * scale) as f32 - 1.0,
                (y + crop.1 * scale) as f32 - 1.0,
            ),
            ((crop.2 * scale) as f32 + 2.0, (crop.3 * scale) as f32 + 2.0),
            Some((mark, 2.0)),
            None,
        );
        y += ph + row_title;
        if i == 0 {
            c.text(
                (x0 as f32, (y - row_title / 2) as f32),
                &format!(
                    "crop {}×{} at ({}, {}), ×{zoom}",
                    crop.2, crop.3, crop.0, crop.1
                ),
                12.0,
                muted,
                Anchor::Left,
            );
        }
        let cx = x0 + (pw - cw) / 2;
        c.image((cx as i32, y as i32), &crop_of(img, crop), zoom);
        c.rect(
            (cx as f32 - 1.0, y as f32 - 1.0),
            (cw as f32 + 2.0, chh as f32 + 2.0),
            Some((mark, 2.0)),
            None,
        );
        y += chh + row_title;
        if let Some((e, spp)) = err {
            if spp_row {
                let y = y + ph + row_title;
                if i == 0 {
                    c.text(
                        (x0 as f32, (y - row_title / 2) as f32),
                        &format!("samples per pixel (black 0, yellow {max_spp})"),
                        12.0,
                        muted,
                        Anchor::Left,
                    );
                }
                c.image(
                    (x0 as i32, y as i32),
                    &spp_heat_map(spp, iw, ih, max_spp),
                    scale,
                );
            }
            if i == 0 {
                c.text(
                    (x0 as f32, (y - row_title / 2) as f32),
                    &format!("error vs reference (black 0, yellow ≥ {max_err:.2})"),
                    12.0,
                    muted,
                    Anchor::Left,
                );
            }
            c.image((x0 as i32, y as i32), &heat_map(e, iw, ih, max_err), scale);
        } else {
            c.text(
                ((x0 + pw / 2) as f32, (y + ph / 2) as f32),
                "(the reference)",
                13.0,
                muted,
                Anchor::Center,
            );
        }
    }

    // The metrics table.
    let mut y = margin + label_h + ph + row_title + chh + row_title + ph + spp_h + 34;
    let mut headers = vec!["run", "samples", "rays", "RMSE", "PSNR (dB)"];
    if show_time {
        headers.push("time (s)");
    }
    let x_at = |k: usize| margin as f32 + col_w[..k].iter().sum::<f32>();
    for (k, h) in headers.iter().enumerate() {
        c.text(
            (x_at(k), (y + table_row / 2) as f32),
            h,
            13.0,
            ink,
            Anchor::Left,
        );
    }
    c.line(
        (margin as f32, (y + table_row) as f32),
        (x_at(headers.len()), (y + table_row) as f32),
        muted,
        1.0,
        false,
    );
    y += table_row + 4;
    for p in panels {
        let mut cells = vec![
            p.label.clone(),
            fmt_count(p.samples),
            fmt_count(p.rays),
            format!("{:.4}", p.rmse),
            p.psnr.map_or("∞".to_string(), |v| format!("{v:.2}")),
        ];
        if show_time {
            cells.push(format!("{:.3}", p.seconds));
        }
        for (k, t) in cells.iter().enumerate() {
            c.text(
                (x_at(k), (y + table_row / 2) as f32),
                t,
                13.0,
                ink,
                Anchor::Left,
            );
        }
        y += table_row;
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn metrics_and_worst_crop() {
        let a = RgbImage::from_pixel(8, 6, image::Rgb([0, 0, 0]));
        let mut b = a.clone();
        assert_eq!(rmse_psnr(&a, &b), (0.0, None));
        b.put_pixel(6, 4, image::Rgb([255, 255, 255]));
        let (rmse, psnr) = rmse_psnr(&a, &b);
        assert!((rmse - (1.0f64 / 48.0).sqrt()).abs() < 1e-12);
        assert!((psnr.unwrap() - 10.0 * 48f64.log10()).abs() < 1e-9);
        let e = error_map(&a, &b);
        let (x, y, w, h) = worst_crop(&e, 8, 6, 3, 2);
        assert!((x..x + w).contains(&6) && (y..y + h).contains(&4));
    }
}
