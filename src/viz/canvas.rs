//! A drawing surface: tiny-skia for shapes, fontdue for text from the embedded DejaVu Sans.
//! Coordinates are pixels, y down. Every call takes all its state explicitly.

use crate::error::Result;
use serde::Serialize;
use std::path::Path;
use std::sync::OnceLock;
use tiny_skia::{
    Color, FillRule, LineCap, Paint, PathBuilder, Pixmap, Rect, Stroke, StrokeDash, Transform,
};

static FONT_BYTES: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

fn font() -> &'static fontdue::Font {
    static FONT: OnceLock<fontdue::Font> = OnceLock::new();
    FONT.get_or_init(|| {
        fontdue::Font::from_bytes(FONT_BYTES, fontdue::FontSettings::default())
            .expect("the embedded font is valid")
    })
}

/// Where a text's position sits relative to the text.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Anchor {
    /// Left end of the baseline... measured at the text's vertical middle.
    Left,
    Center,
    Right,
}

/// One drawing primitive, as kept in the display list.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "prim", rename_all = "kebab-case")]
pub enum Prim {
    Line {
        from: [f32; 2],
        to: [f32; 2],
        color: String,
        width: f32,
        dashed: bool,
    },
    Arrow {
        from: [f32; 2],
        to: [f32; 2],
        color: String,
        width: f32,
    },
    Circle {
        center: [f32; 2],
        radius: f32,
        stroke: Option<String>,
        fill: Option<String>,
    },
    Polygon {
        points: Vec<[f32; 2]>,
        stroke: Option<String>,
        fill: Option<String>,
    },
    Rect {
        min: [f32; 2],
        size: [f32; 2],
        stroke: Option<String>,
        fill: Option<String>,
    },
    Text {
        at: [f32; 2],
        text: String,
        size: f32,
        color: String,
        anchor: Anchor,
    },
    Image {
        at: [f32; 2],
        size: [u32; 2],
        scale: u32,
    },
    /// A colour blended over a set of pixels (object sections sampled by rays): kept in the
    /// display list by what it covers, `pixels` counted and `bounds` as [x0, y0, x1, y1].
    Mask {
        what: String,
        color: String,
        pixels: u32,
        bounds: [u32; 4],
    },
}

fn hex(c: Color) -> String {
    let c = c.to_color_u8();
    if c.alpha() == 255 {
        format!("#{:02x}{:02x}{:02x}", c.red(), c.green(), c.blue())
    } else {
        format!(
            "#{:02x}{:02x}{:02x}{:02x}",
            c.red(),
            c.green(),
            c.blue(),
            c.alpha()
        )
    }
}

fn r2(p: (f32, f32)) -> [f32; 2] {
    [(p.0 * 10.0).round() / 10.0, (p.1 * 10.0).round() / 10.0]
}

/// A figure being drawn.
pub struct Canvas {
    pub pixmap: Pixmap,
    pub display: Vec<Prim>,
}

fn paint(c: Color) -> Paint<'static> {
    let mut p = Paint::default();
    p.set_color(c);
    p.anti_alias = true;
    p
}

impl Canvas {
    /// A blank canvas. Sizes are clamped to at least 1×1.
    pub fn new(width: u32, height: u32, background: Color) -> Canvas {
        let mut pixmap = Pixmap::new(width.max(1), height.max(1)).expect("non-zero size");
        pixmap.fill(background);
        Canvas {
            pixmap,
            display: Vec::new(),
        }
    }

    pub fn width(&self) -> f32 {
        self.pixmap.width() as f32
    }
    pub fn height(&self) -> f32 {
        self.pixmap.height() as f32
    }

    fn stroke_path(&mut self, pb: PathBuilder, color: Color, width: f32, dashed: bool) {
        if let Some(path) = pb.finish() {
            let mut s = Stroke {
                width,
                line_cap: LineCap::Round,
                ..Stroke::default()
            };
            if dashed {
                s.dash = StrokeDash::new(vec![width * 3.0, width * 2.5], 0.0);
            }
            self.pixmap
                .stroke_path(&path, &paint(color), &s, Transform::identity(), None);
        }
    }

    pub fn line(&mut self, a: (f32, f32), b: (f32, f32), color: Color, width: f32, dashed: bool) {
        let mut pb = PathBuilder::new();
        pb.move_to(a.0, a.1);
        pb.line_to(b.0, b.1);
        self.stroke_path(pb, color, width, dashed);
        self.display.push(Prim::Line {
            from: r2(a),
            to: r2(b),
            color: hex(color),
            width,
            dashed,
        });
    }

    /// A line with an arrow head at `b`.
    pub fn arrow(&mut self, a: (f32, f32), b: (f32, f32), color: Color, width: f32) {
        let mut pb = PathBuilder::new();
        pb.move_to(a.0, a.1);
        pb.line_to(b.0, b.1);
        self.stroke_path(pb, color, width, false);
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let len = (dx * dx + dy * dy).sqrt();
        if len > 0.0 {
            let (ux, uy) = (dx / len, dy / len);
            let h = 5.0 + 2.5 * width;
            let mut head = PathBuilder::new();
            head.move_to(b.0, b.1);
            head.line_to(b.0 - ux * h - uy * h * 0.45, b.1 - uy * h + ux * h * 0.45);
            head.line_to(b.0 - ux * h + uy * h * 0.45, b.1 - uy * h - ux * h * 0.45);
            head.close();
            if let Some(p) = head.finish() {
                self.pixmap.fill_path(
                    &p,
                    &paint(color),
                    FillRule::Winding,
                    Transform::identity(),
                    None,
                );
            }
        }
        self.display.push(Prim::Arrow {
            from: r2(a),
            to: r2(b),
            color: hex(color),
            width,
        });
    }

    pub fn circle(
        &mut self,
        c: (f32, f32),
        r: f32,
        stroke: Option<(Color, f32)>,
        fill: Option<Color>,
    ) {
        if let Some(path) = PathBuilder::from_circle(c.0, c.1, r.max(0.01)) {
            if let Some(f) = fill {
                self.pixmap.fill_path(
                    &path,
                    &paint(f),
                    FillRule::Winding,
                    Transform::identity(),
                    None,
                );
            }
            if let Some((sc, w)) = stroke {
                let s = Stroke {
                    width: w,
                    ..Stroke::default()
                };
                self.pixmap
                    .stroke_path(&path, &paint(sc), &s, Transform::identity(), None);
            }
        }
        self.display.push(Prim::Circle {
            center: r2(c),
            radius: (r * 10.0).round() / 10.0,
            stroke: stroke.map(|s| hex(s.0)),
            fill: fill.map(hex),
        });
    }

    pub fn polygon(
        &mut self,
        pts: &[(f32, f32)],
        stroke: Option<(Color, f32)>,
        fill: Option<Color>,
    ) {
        let mut pb = PathBuilder::new();
        for (i, p) in pts.iter().enumerate() {
            if i == 0 {
                pb.move_to(p.0, p.1);
            } else {
                pb.line_to(p.0, p.1);
            }
        }
        pb.close();
        if let Some(path) = pb.finish() {
            if let Some(f) = fill {
                self.pixmap.fill_path(
                    &path,
                    &paint(f),
                    FillRule::Winding,
                    Transform::identity(),
                    None,
                );
            }
            if let Some((sc, w)) = stroke {
                let s = Stroke {
                    width: w,
                    line_join: tiny_skia::LineJoin::Round,
                    ..Stroke::default()
                };
                self.pixmap
                    .stroke_path(&path, &paint(sc), &s, Transform::identity(), None);
            }
        }
        self.display.push(Prim::Polygon {
            points: pts.iter().map(|p| r2(*p)).collect(),
            stroke: stroke.map(|s| hex(s.0)),
            fill: fill.map(hex),
        });
    }

    pub fn rect(
        &mut self,
        min: (f32, f32),
        size: (f32, f32),
        stroke: Option<(Color, f32)>,
        fill: Option<Color>,
    ) {
        if let Some(r) = Rect::from_xywh(min.0, min.1, size.0.max(0.01), size.1.max(0.01)) {
            if let Some(f) = fill {
                self.pixmap
                    .fill_rect(r, &paint(f), Transform::identity(), None);
            }
            if let Some((sc, w)) = stroke {
                let path = PathBuilder::from_rect(r);
                let s = Stroke {
                    width: w,
                    ..Stroke::default()
                };
                self.pixmap
                    .stroke_path(&path, &paint(sc), &s, Transform::identity(), None);
            }
        }
        self.display.push(Prim::Rect {
            min: r2(min),
            size: r2(size),
            stroke: stroke.map(|s| hex(s.0)),
            fill: fill.map(hex),
        });
    }

    /// Every text drawn so far, in order (from the display list: for tests and checks).
    pub fn texts(&self) -> Vec<&str> {
        self.display
            .iter()
            .filter_map(|p| match p {
                Prim::Text { text, .. } => Some(text.as_str()),
                _ => None,
            })
            .collect()
    }

    /// Width of `text` at `size` pixels.
    pub fn text_width(text: &str, size: f32) -> f32 {
        let f = font();
        let mut w = 0.0;
        let mut prev = None;
        for ch in text.chars() {
            if let Some(p) = prev {
                w += f.horizontal_kern(p, ch, size).unwrap_or(0.0);
            }
            w += f.metrics(ch, size).advance_width;
            prev = Some(ch);
        }
        w
    }

    /// Draws `text` with its vertical middle at `at.1`, anchored horizontally by `anchor`.
    pub fn text(&mut self, at: (f32, f32), text: &str, size: f32, color: Color, anchor: Anchor) {
        let f = font();
        let width = Self::text_width(text, size);
        let mut x = match anchor {
            Anchor::Left => at.0,
            Anchor::Center => at.0 - width / 2.0,
            Anchor::Right => at.0 - width,
        };
        let lm = f.horizontal_line_metrics(size).expect("horizontal font");
        let baseline = at.1 + (lm.ascent + lm.descent) / 2.0;
        let c = color.to_color_u8();
        let (pw, ph) = (self.pixmap.width() as i32, self.pixmap.height() as i32);
        let mut prev = None;
        for ch in text.chars() {
            if let Some(p) = prev {
                x += f.horizontal_kern(p, ch, size).unwrap_or(0.0);
            }
            let (m, bitmap) = f.rasterize(ch, size);
            let gx = (x + m.xmin as f32).round() as i32;
            let gy = (baseline - m.height as f32 - m.ymin as f32).round() as i32;
            let data = self.pixmap.data_mut();
            for row in 0..m.height as i32 {
                for col in 0..m.width as i32 {
                    let (px, py) = (gx + col, gy + row);
                    if px < 0 || py < 0 || px >= pw || py >= ph {
                        continue;
                    }
                    let cov = bitmap[(row * m.width as i32 + col) as usize] as u32
                        * c.alpha() as u32
                        / 255;
                    if cov == 0 {
                        continue;
                    }
                    // Premultiplied source-over blend.
                    let i = ((py * pw + px) * 4) as usize;
                    let inv = 255 - cov;
                    for (k, s) in [c.red(), c.green(), c.blue()].into_iter().enumerate() {
                        data[i + k] =
                            ((s as u32 * cov + data[i + k] as u32 * inv + 127) / 255) as u8;
                    }
                    data[i + 3] = ((255 * cov + data[i + 3] as u32 * inv + 127) / 255) as u8;
                }
            }
            x += m.advance_width;
            prev = Some(ch);
        }
        self.display.push(Prim::Text {
            at: r2(at),
            text: text.to_string(),
            size,
            color: hex(color),
            anchor,
        });
    }

    /// Copies an RGB image onto the canvas, each source pixel a `scale`×`scale` block
    /// (nearest neighbour: magnified crops show real pixels).
    pub fn image(&mut self, at: (i32, i32), img: &image::RgbImage, scale: u32) {
        let (pw, ph) = (self.pixmap.width() as i32, self.pixmap.height() as i32);
        let s = scale.max(1) as i32;
        let data = self.pixmap.data_mut();
        for (x, y, p) in img.enumerate_pixels() {
            for dy in 0..s {
                for dx in 0..s {
                    let (px, py) = (at.0 + x as i32 * s + dx, at.1 + y as i32 * s + dy);
                    if px < 0 || py < 0 || px >= pw || py >= ph {
                        continue;
                    }
                    let i = ((py * pw + px) * 4) as usize;
                    data[i..i + 4].copy_from_slice(&[p[0], p[1], p[2], 255]);
                }
            }
        }
        self.display.push(Prim::Image {
            at: [at.0 as f32, at.1 as f32],
            size: [img.width(), img.height()],
            scale,
        });
    }

    /// Blends `color` over every pixel where `mask` (row-major, the canvas's size) is set.
    /// `what` names the layer in the display list. An empty mask draws and lists nothing.
    pub fn mask(&mut self, what: &str, mask: &[bool], color: Color) {
        let w = self.pixmap.width();
        let c = color.to_color_u8();
        let a = c.alpha() as u32;
        let (mut n, mut b) = (0u32, [u32::MAX, u32::MAX, 0, 0]);
        let data = self.pixmap.data_mut();
        for (i, _) in mask.iter().enumerate().filter(|(_, m)| **m) {
            let (x, y) = (i as u32 % w, i as u32 / w);
            if 4 * i + 3 >= data.len() {
                break;
            }
            n += 1;
            b = [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)];
            let inv = 255 - a;
            for (k, s) in [c.red(), c.green(), c.blue()].into_iter().enumerate() {
                let d = &mut data[4 * i + k];
                *d = ((s as u32 * a + *d as u32 * inv + 127) / 255) as u8;
            }
            let d = &mut data[4 * i + 3];
            *d = ((255 * a + *d as u32 * inv + 127) / 255) as u8;
        }
        if n > 0 {
            self.display.push(Prim::Mask {
                what: what.to_string(),
                color: hex(color),
                pixels: n,
                bounds: b,
            });
        }
    }

    /// Encodes the figure as PNG bytes (the same bytes [`Canvas::write_png`] writes).
    pub fn png_bytes(&self) -> Result<Vec<u8>> {
        let mut buf = std::io::Cursor::new(Vec::new());
        self.to_rgb()
            .write_to(&mut buf, image::ImageFormat::Png)
            .map_err(|e| crate::error::Error::Other(format!("cannot encode PNG: {e}")))?;
        Ok(buf.into_inner())
    }

    /// The canvas as an opaque RGB image.
    pub fn to_rgb(&self) -> image::RgbImage {
        let (w, h) = (self.pixmap.width(), self.pixmap.height());
        let mut out = image::RgbImage::new(w, h);
        for (i, p) in self.pixmap.pixels().iter().enumerate() {
            let c = p.demultiply();
            out.put_pixel(
                i as u32 % w,
                i as u32 / w,
                image::Rgb([c.red(), c.green(), c.blue()]),
            );
        }
        out
    }

    /// Writes the figure as a PNG (atomically).
    pub fn write_png(&self, path: &Path) -> Result<()> {
        crate::output::write_png(path, &self.to_rgb())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn text_is_drawn_and_listed() {
        let mut c = Canvas::new(120, 40, Color::WHITE);
        c.text(
            (60.0, 20.0),
            "D = b² − 4ac",
            16.0,
            Color::BLACK,
            Anchor::Center,
        );
        let dark = c.pixmap.pixels().iter().filter(|p| p.red() < 128).count();
        assert!(dark > 30, "glyphs were rasterised ({dark} dark pixels)");
        assert_eq!(c.display.len(), 1);
        assert!(Canvas::text_width("abc", 16.0) > 15.0);
    }
}
