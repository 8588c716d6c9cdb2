//! The film's result: a linear-colour image, and its bytes under an encoding.

use crate::mistakes::{Mistake, Mistakes};
use crate::scene::{Encoding, RenderSettings};
use glam::DVec3;

/// A linear-colour image, row-major from the top-left.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<DVec3>,
}

impl Image {
    /// The image whose pixel (x, y) is `color(x, y)`, rows computed in parallel straight
    /// into their place. (Collecting a parallel iterator of unknown length instead grew a
    /// vector by doubling on each thread and then joined the threads' pieces: the image was
    /// copied about twice over, into memory faulted in afresh each time.)
    pub fn from_fn(width: u32, height: u32, color: impl Fn(u32, u32) -> DVec3 + Sync) -> Image {
        Image::from_fn_until(width, height, &|| false, color).expect("never stopped")
    }

    /// [`Image::from_fn`] that gives up (`None`) once `stop()` says so, asked before each
    /// row: a reconstruction can take longer than the trace (a filter stretched by
    /// `--subsample` over thousands of samples a pixel), and a time budget or a cancelled
    /// render must not wait for it.
    pub fn from_fn_until(
        width: u32,
        height: u32,
        stop: &(dyn Fn() -> bool + Sync),
        color: impl Fn(u32, u32) -> DVec3 + Sync,
    ) -> Option<Image> {
        use rayon::prelude::*;
        let stopped = std::sync::atomic::AtomicBool::new(false);
        let mut pixels = vec![DVec3::ZERO; width as usize * height as usize];
        if width > 0 {
            pixels
                .par_chunks_mut(width as usize)
                .enumerate()
                .for_each(|(y, row)| {
                    if stopped.load(std::sync::atomic::Ordering::Relaxed) || stop() {
                        stopped.store(true, std::sync::atomic::Ordering::Relaxed);
                        return;
                    }
                    for (x, p) in row.iter_mut().enumerate() {
                        *p = color(x as u32, y as u32);
                    }
                });
        }
        (!stopped.into_inner()).then_some(Image {
            width,
            height,
            pixels,
        })
    }

    pub fn get(&self, x: u32, y: u32) -> DVec3 {
        self.pixels[(y * self.width + x) as usize]
    }
    /// The bytes of this image under an encoding (RGB, 3 bytes a pixel).
    pub fn to_rgb8(&self, encoding: Encoding) -> image::RgbImage {
        let mut out = image::RgbImage::new(self.width, self.height);
        for (p, c) in out.pixels_mut().zip(&self.pixels) {
            *p = image::Rgb(encode(*c, encoding));
        }
        out
    }

    /// The bytes of this image as the settings encode them: their encoding, and the
    /// catalogue's byte mistakes (`srgb-gamma`, `round-bytes`) when they are on.
    pub fn to_rgb8_for(&self, settings: &RenderSettings) -> image::RgbImage {
        if settings.mistakes.is_empty() {
            return self.to_rgb8(settings.encoding);
        }
        let mut out = image::RgbImage::new(self.width, self.height);
        for (p, c) in out.pixels_mut().zip(&self.pixels) {
            *p = image::Rgb(encode_as(*c, settings.encoding, settings.mistakes));
        }
        out
    }
}

/// One pixel's bytes. `Clamp`: floor(255·min(max(c, 0), 1)), no gamma, as the course's
/// reference images are made. `Srgb`: the sRGB transfer curve, rounded.
pub fn encode(c: DVec3, encoding: Encoding) -> [u8; 3] {
    encode_as(c, encoding, Mistakes::NONE)
}

// ANCHOR: encode
/// [`encode`] under the catalogue's byte mistakes: `srgb-gamma` applies the sRGB curve to the
/// course's linear encoding, `round-bytes` rounds instead of truncating.
pub fn encode_as(c: DVec3, encoding: Encoding, mistakes: Mistakes) -> [u8; 3] {
    let f = |x: f64| -> u8 {
        let x = if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) };
        let srgb = |x: f64| {
            if x >= 1.0 {
                1.0 // not 1.055 − 0.055, a hair below 1
            } else if x <= 0.003_130_8 {
                12.92 * x
            } else {
                1.055 * x.powf(1.0 / 2.4) - 0.055
            }
        };
        match encoding {
            Encoding::Clamp => {
                let x = if mistakes.has(Mistake::SrgbGamma) {
                    srgb(x)
                } else {
                    x
                };
                if mistakes.has(Mistake::RoundBytes) {
                    (255.0 * x).round() as u8
                } else {
                    (255.0 * x).floor() as u8
                }
            }
            Encoding::Srgb => (255.0 * srgb(x)).round() as u8,
        }
    };
    [f(c.x), f(c.y), f(c.z)]
}
// ANCHOR_END: encode

#[cfg(test)]
mod tests {
    use super::*;

    /// `Image::from_fn` puts pixel (x, y) at row y, column x, whatever the thread count, and
    /// makes an empty image of a zero width or height.
    #[test]
    fn from_fn_puts_each_pixel_in_its_place() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap();
        let image =
            pool.install(|| Image::from_fn(7, 5, |x, y| DVec3::new(x as f64, y as f64, 1.0)));
        assert_eq!((image.width, image.height, image.pixels.len()), (7, 5, 35));
        for y in 0..5 {
            for x in 0..7 {
                assert_eq!(
                    image.get(x, y),
                    DVec3::new(x as f64, y as f64, 1.0),
                    "({x}, {y})"
                );
            }
        }
        for (w, h) in [(0, 4), (4, 0), (0, 0)] {
            let empty = Image::from_fn(w, h, |_, _| DVec3::ONE);
            assert!(empty.pixels.is_empty(), "{w}×{h}");
        }
    }
}
