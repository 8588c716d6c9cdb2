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
}
