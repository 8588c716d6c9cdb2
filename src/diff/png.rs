//! Reading the images `diff` compares: 8-bit RGB PNGs, nothing else, each refusal saying what
//! the file is and what was expected.

use crate::error::{Error, Result};
use crate::scene::MAX_PIXELS;
use image::codecs::png::PngDecoder;
use image::{ColorType, ImageDecoder, ImageFormat, RgbImage};
use std::io::Read;
use std::path::Path;

/// What `diff` accepts, said in every refusal.
const EXPECTED: &str = "expected an 8-bit RGB PNG (3 channels, no alpha), as `rtlab render` writes";

/// Reads an 8-bit RGB PNG. A missing file, another format, a grey, 16-bit or alpha image are
/// each an error naming the file and what it is instead. The first bytes are read alone, so
/// a file that is not a PNG at all (`/dev/zero`) is refused before the rest is read.
pub fn read_rgb8(path: &Path) -> Result<RgbImage> {
    if path.is_dir() {
        return Err(Error::io(path, format!("is a directory; {EXPECTED}")));
    }
    let cannot_read = |e: std::io::Error| {
        let why = match e.kind() {
            std::io::ErrorKind::NotFound => "no such file".to_string(),
            std::io::ErrorKind::PermissionDenied => "permission denied".to_string(),
            _ => e.to_string(),
        };
        Error::io(path, format!("cannot read the image: {why}"))
    };
    let mut start = Vec::with_capacity(SIGNATURE.len());
    std::fs::File::open(path)
        .and_then(|f| f.take(SIGNATURE.len() as u64).read_to_end(&mut start))
        .map_err(cannot_read)?;
    if start != SIGNATURE {
        return decode(path, &start);
    }
    let bytes = crate::input::read_limited(path, crate::input::IMAGE_LIMIT).map_err(cannot_read)?;
    decode(path, &bytes)
}

/// The eight bytes every PNG file begins with.
const SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', b'\r', b'\n', 0x1a, b'\n'];

/// [`read_rgb8`] on bytes already in memory (`path` only names them in errors). The size and
/// pixel format are read from the PNG's header first: an image of another format, or larger
/// than any image rtlab renders ([`MAX_PIXELS`]), is refused before it is decoded.
pub fn decode(path: &Path, bytes: &[u8]) -> Result<RgbImage> {
    if bytes.is_empty() {
        return Err(Error::io(path, format!("the file is empty; {EXPECTED}")));
    }
    if bytes.len() < SIGNATURE.len() && SIGNATURE.starts_with(bytes) {
        return Err(Error::io(
            path,
            format!("the file is truncated; {EXPECTED}"),
        ));
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
    let broken = |e: image::ImageError| {
        let why = match e {
            image::ImageError::IoError(io) if io.kind() == std::io::ErrorKind::UnexpectedEof => {
                "the file is truncated".to_string()
            }
            other => other.to_string(),
        };
        Error::io(path, format!("cannot decode the PNG: {why}; {EXPECTED}"))
    };
    let decoder = PngDecoder::new(std::io::Cursor::new(bytes)).map_err(broken)?;
    let what = match decoder.color_type() {
        ColorType::Rgb8 => None,
        ColorType::Rgba8 => Some("an 8-bit RGB image with an alpha channel (RGBA)"),
        ColorType::L8 => Some("an 8-bit grey image"),
        ColorType::La8 => Some("an 8-bit grey image with an alpha channel"),
        ColorType::Rgb16 => Some("a 16-bit RGB image"),
        ColorType::Rgba16 => Some("a 16-bit RGBA image"),
        ColorType::L16 | ColorType::La16 => Some("a 16-bit grey image"),
        _ => Some("an image of another pixel format"),
    };
    if let Some(what) = what {
        return Err(Error::io(path, format!("is {what}; {EXPECTED}")));
    }
    let (w, h) = decoder.dimensions();
    if u64::from(w) * u64::from(h) > MAX_PIXELS {
        return Err(Error::io(
            path,
            format!(
                "is {w}×{h} pixels, larger than any image rtlab renders (at most {MAX_PIXELS} pixels)"
            ),
        ));
    }
    Ok(image::DynamicImage::from_decoder(decoder)
        .map_err(broken)?
        .into_rgb8())
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
    /// The CRC-32 of a PNG chunk (its type and data), to forge a header in a test.
    fn crc32(bytes: &[u8]) -> u32 {
        let mut c = !0u32;
        for &b in bytes {
            c ^= u32::from(b);
            for _ in 0..8 {
                c = if c & 1 == 1 {
                    0xedb8_8320 ^ (c >> 1)
                } else {
                    c >> 1
                };
            }
        }
        !c
    }

    #[test]
    fn a_huge_image_is_refused_from_its_header_saying_its_size() {
        let mut bytes = png(image::DynamicImage::ImageRgb8(RgbImage::new(1, 1)));
        // The IHDR chunk: length at 8, type at 12, width and height at 16 and 20, CRC at 29.
        bytes[16..20].copy_from_slice(&100_000u32.to_be_bytes());
        bytes[20..24].copy_from_slice(&100_000u32.to_be_bytes());
        let crc = crc32(&bytes[12..29]);
        bytes[29..33].copy_from_slice(&crc.to_be_bytes());
        let e = decode(Path::new("bomb.png"), &bytes)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("100000×100000 pixels") && e.contains("at most"),
            "{e}"
        );
    }

    #[test]
    fn a_file_that_is_not_a_png_is_refused_from_its_first_bytes() {
        // /dev/zero never ends: only its first eight bytes may be read.
        let e = read_rgb8(Path::new("/dev/zero")).unwrap_err().to_string();
        assert!(e.contains("not an image"), "{e}");
        let e = decode(Path::new("x.png"), &SIGNATURE[..6])
            .unwrap_err()
            .to_string();
        assert!(e.contains("truncated"), "{e}");
    }
}
