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
    // ANCHOR: texel
    /// The texel at texture coordinate (u, v), nearest neighbour, with the course's
    /// convention: u to the right, v up; image rows counted from the top.
    pub fn texel(&self, uv: DVec2) -> DVec3 {
        match &self.source {
            TextureSource::Image {
                width,
                height,
                texels,
            } => {
                let (w, h) = (*width as f64, *height as f64);
                let col = (uv.x * self.repeat.x * w).floor();
                let row = ((1.0 - uv.y) * self.repeat.y * h).floor();
                let col = (col.rem_euclid(w) as u32).min(width - 1);
                let row = (row.rem_euclid(h) as u32).min(height - 1);
                texels[(row * width + col) as usize]
            }
            TextureSource::Checker { squares, a, b } => {
                let i = (uv.x * self.repeat.x * squares.x).floor() as i64;
                let j = (uv.y * self.repeat.y * squares.y).floor() as i64;
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
