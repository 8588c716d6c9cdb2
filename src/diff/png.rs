//! Reading the images `diff` compares: 8-bit RGB PNGs, nothing else, each refusal saying what
//! the file is and what was expected.

use crate::error::{Error, Result};
use image::{ColorType, ImageFormat, RgbImage};
use std::path::Path;

/// What `diff` accepts, said in every refusal.
const EXPECTED: &str = "expected an 8-bit RGB PNG (3 channels, no alpha), as `rtlab render` writes";

/// Reads an 8-bit RGB PNG. A missing file, another format, a grey, 16-bit or alpha image are
/// each an error naming the file and what it is instead.
pub fn read_rgb8(path: &Path) -> Result<RgbImage> {
    if path.is_dir() {
        return Err(Error::io(path, format!("is a directory; {EXPECTED}")));
    }
    let bytes = crate::input::read_limited(path, crate::input::IMAGE_LIMIT).map_err(|e| {
        let why = match e.kind() {
            std::io::ErrorKind::NotFound => "no such file".to_string(),
            std::io::ErrorKind::PermissionDenied => "permission denied".to_string(),
            _ => e.to_string(),
        };
        Error::io(path, format!("cannot read the image: {why}"))
    })?;
    decode(path, &bytes)
}

/// [`read_rgb8`] on bytes already in memory (`path` only names them in errors).
pub fn decode(path: &Path, bytes: &[u8]) -> Result<RgbImage> {
    if bytes.is_empty() {
        return Err(Error::io(path, format!("the file is empty; {EXPECTED}")));
    }
    match image::guess_format(bytes) {
        Ok(ImageFormat::Png) => {}
        Ok(other) => {
            return Err(Error::io(
                path,
                format!("is a {other:?} image, not a PNG; {EXPECTED}"),
            ))
        }
        Err(_) => return Err(Error::io(path, format!("is not an image; {EXPECTED}"))),
    }
    let img = image::load_from_memory_with_format(bytes, ImageFormat::Png).map_err(|e| {
        let why = match e {
            image::ImageError::IoError(io) if io.kind() == std::io::ErrorKind::UnexpectedEof => {
                "the file is truncated".to_string()
            }
            other => other.to_string(),
        };
        Error::io(path, format!("cannot decode the PNG: {why}; {EXPECTED}"))
    })?;
    let what = match img.color() {
        ColorType::Rgb8 => return Ok(img.into_rgb8()),
        ColorType::Rgba8 => "an 8-bit RGB image with an alpha channel (RGBA)",
        ColorType::L8 => "an 8-bit grey image",
        ColorType::La8 => "an 8-bit grey image with an alpha channel",
        ColorType::Rgb16 => "a 16-bit RGB image",
        ColorType::Rgba16 => "a 16-bit RGBA image",
        ColorType::L16 | ColorType::La16 => "a 16-bit grey image",
        _ => "an image of another pixel format",
    };
    Err(Error::io(path, format!("is {what}; {EXPECTED}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn png(img: image::DynamicImage) -> Vec<u8> {
        let mut v = Vec::new();
        img.write_to(&mut std::io::Cursor::new(&mut v), ImageFormat::Png)
            .unwrap();
        v
    }

    #[test]
    fn accepts_rgb8_and_names_every_other_kind() {
        let p = Path::new("x.png");
        let rgb = image::DynamicImage::ImageRgb8(RgbImage::new(3, 2));
        assert_eq!(decode(p, &png(rgb)).unwrap().dimensions(), (3, 2));
        let cases: Vec<(image::DynamicImage, &str)> = vec![
            (
                image::DynamicImage::ImageRgba8(image::RgbaImage::new(3, 2)),
                "alpha channel",
            ),
            (
                image::DynamicImage::ImageLuma8(image::GrayImage::new(3, 2)),
                "8-bit grey",
            ),
            (
                image::DynamicImage::ImageRgb16(image::ImageBuffer::new(3, 2)),
                "16-bit RGB",
            ),
        ];
        for (img, says) in cases {
            let e = decode(p, &png(img)).unwrap_err().to_string();
            assert!(e.contains(says) && e.contains("8-bit RGB PNG"), "{e}");
        }
        let e = decode(p, b"{\"not\": \"an image\"}")
            .unwrap_err()
            .to_string();
        assert!(e.contains("not an image"), "{e}");
        let e = decode(p, &[]).unwrap_err().to_string();
        assert!(e.contains("empty"), "{e}");
    }
}
