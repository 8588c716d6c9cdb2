use crate::mistakes::{Mistake, Mistakes};
use glam::{DVec2, DVec3};
use std::sync::Arc;

/// Where texels come from.
#[derive(Debug, Clone, PartialEq)]
pub enum TextureSource {
    /// An image, row-major from the top-left, linear values in [0, 1] (8-bit / 255).
    Image {
        width: u32,
        height: u32,
        texels: Arc<Vec<DVec3>>,
    },
    /// A procedural checkerboard of `squares` per unit of uv.
    Checker { squares: DVec2, a: DVec3, b: DVec3 },
}

/// How an image texture is looked up between texel centres.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TextureFilter {
    /// The texel the point falls in (the course's requirement; its required references).
    #[default]
    Nearest,
    /// The four texels around the point, weighted by distance to their centres (texel
    /// centres at half-integer image coordinates, wrapping around as the texture repeats).
    Bilinear,
}

impl TextureFilter {
    pub const NAMES: [&'static str; 2] = ["nearest", "bilinear"];
    pub fn parse(s: &str) -> Option<TextureFilter> {
        match s {
            "nearest" => Some(TextureFilter::Nearest),
            "bilinear" => Some(TextureFilter::Bilinear),
            _ => None,
        }
    }
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }
}

/// A texture and how it is mixed into the diffuse colour.
#[derive(Debug, Clone, PartialEq)]
pub struct Texture {
    pub source: TextureSource,
    /// 0: the material's diffuse colour; 1: the texel.
    pub blend: f64,
    /// Repeat counts along u and v.
    pub repeat: DVec2,
}

impl Texture {
    /// The texel at texture coordinate (u, v), nearest neighbour, with the course's
    /// convention: u to the right, v up; image rows counted from the top.
    pub fn texel(&self, uv: DVec2) -> DVec3 {
        self.texel_as(uv, Mistakes::NONE)
    }

    // ANCHOR: texel
    /// [`Texture::texel`] under the catalogue's texture mistakes (none: the course's lookup).
    pub fn texel_as(&self, uv: DVec2, mistakes: Mistakes) -> DVec3 {
        // `texture-u-mirrored` / `texture-v-flipped`: u or v run the wrong way.
        let mut uv = uv;
        if mistakes.has(Mistake::TextureUMirrored) {
            uv.x = 1.0 - uv.x;
        }
        if mistakes.has(Mistake::TextureVFlipped) {
            uv.y = 1.0 - uv.y;
        }
        // `texture-off-by-one`: the index rounded instead of floored.
        let index = |x: f64| {
            if mistakes.has(Mistake::TextureOffByOne) {
                x.round()
            } else {
                x.floor()
            }
        };
        match &self.source {
            TextureSource::Image {
                width,
                height,
                texels,
            } => {
                let (w, h) = (*width as f64, *height as f64);
                let col = index(uv.x * self.repeat.x * w);
                let row = index((1.0 - uv.y) * self.repeat.y * h);
                let col = (col.rem_euclid(w) as u32).min(width - 1);
                let row = (row.rem_euclid(h) as u32).min(height - 1);
                texels[(row * width + col) as usize]
            }
            TextureSource::Checker { squares, a, b } => {
                let i = index(uv.x * self.repeat.x * squares.x) as i64;
                let j = index(uv.y * self.repeat.y * squares.y) as i64;
                if (i + j).rem_euclid(2) == 0 {
                    *a
                } else {
                    *b
                }
            }
        }
    }
    // ANCHOR_END: texel

    // ANCHOR: bilinear
    /// The texture at (u, v) with `filter`. Bilinear: image coordinates x = u·m·w − ½,
    /// y = (1 − v)·n·h − ½ (texel centres at integers), the four texels around (x, y) mixed
    /// by the fractional parts, indices wrapping as the texture repeats.
    pub fn lookup(&self, uv: DVec2, filter: TextureFilter) -> DVec3 {
        self.lookup_as(uv, filter, Mistakes::NONE)
    }
    // ANCHOR_END: bilinear

    /// [`Texture::lookup`] under the catalogue's texture mistakes: nearest lookups go through
    /// [`Texture::texel_as`]; a bilinear one mirrors u or v the same way (`texture-off-by-one`
    /// is a nearest-texel mistake).
    pub fn lookup_as(&self, uv: DVec2, filter: TextureFilter, mistakes: Mistakes) -> DVec3 {
        let TextureSource::Image {
            width,
            height,
            texels,
        } = &self.source
        else {
            return self.texel_as(uv, mistakes);
        };
        if filter == TextureFilter::Nearest {
            return self.texel_as(uv, mistakes);
        }
        let mut uv = uv;
        if mistakes.has(Mistake::TextureUMirrored) {
            uv.x = 1.0 - uv.x;
        }
        if mistakes.has(Mistake::TextureVFlipped) {
            uv.y = 1.0 - uv.y;
        }
        let (w, h) = (*width as f64, *height as f64);
        let x = uv.x * self.repeat.x * w - 0.5;
        let y = (1.0 - uv.y) * self.repeat.y * h - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let at = |cx: f64, cy: f64| {
            let c = (cx.rem_euclid(w) as u32).min(width - 1);
            let r = (cy.rem_euclid(h) as u32).min(height - 1);
            texels[(r * width + c) as usize]
        };
        let top = at(x0, y0) * (1.0 - fx) + at(x0 + 1.0, y0) * fx;
        let bottom = at(x0, y0 + 1.0) * (1.0 - fx) + at(x0 + 1.0, y0 + 1.0) * fx;
        top * (1.0 - fy) + bottom * fy
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2×2 image, rows from the top: [a b; c d].
    fn tex() -> Texture {
        let t = |r: f64| DVec3::splat(r);
        Texture {
            source: TextureSource::Image {
                width: 2,
                height: 2,
                texels: Arc::new(vec![t(0.0), t(0.4), t(0.8), t(1.0)]),
            },
            blend: 1.0,
            repeat: DVec2::ONE,
        }
    }

    #[test]
    fn bilinear_against_a_hand_computation() {
        let t = tex();
        // u = 0.5, v = 0.5: x = 0.5·2 − 0.5 = 0.5, y = 0.5; the mean of all four texels.
        let c = t.lookup(DVec2::new(0.5, 0.5), TextureFilter::Bilinear);
        assert!((c.x - (0.0 + 0.4 + 0.8 + 1.0) / 4.0).abs() < 1e-12, "{c}");
        // u = 0.375, v = 0.75: x = 0.25, y = 0.25·2 − 0.5 = 0 (top row exactly):
        // 0.75·a + 0.25·b = 0.75·0 + 0.25·0.4 = 0.1.
        let c = t.lookup(DVec2::new(0.375, 0.75), TextureFilter::Bilinear);
        assert!((c.x - 0.1).abs() < 1e-12, "{c}");
        // u = 0.375, v = 0.5: x = 0.25, y = 0.5:
        // top 0.1, bottom 0.75·0.8 + 0.25·1.0 = 0.85, mean 0.475.
        let c = t.lookup(DVec2::new(0.375, 0.5), TextureFilter::Bilinear);
        assert!((c.x - 0.475).abs() < 1e-12, "{c}");
        // Near u = 0 the left neighbour wraps to the right column: x = −0.5 + 0 → mixes
        // column 1 (x0 = −1) and column 0 equally; top row exactly at y = 0 (v = 0.75).
        let c = t.lookup(DVec2::new(0.0, 0.75), TextureFilter::Bilinear);
        assert!((c.x - 0.2).abs() < 1e-12, "{c}");
        // Nearest is the texel the point falls in, whatever the filter of `texel`.
        let c = t.lookup(DVec2::new(0.375, 0.5), TextureFilter::Nearest);
        assert_eq!(c, t.texel(DVec2::new(0.375, 0.5)));
        assert_eq!(c.x, 0.8);
    }
}
