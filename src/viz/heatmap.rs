//! Heat maps: one number per pixel drawn as a colour, dark (low) to bright yellow (high).
//! Used for the adaptive sampler's samples-per-pixel map and for error images in
//! `rtlab compare`.

use image::{Rgb, RgbImage};

// ANCHOR: heat_colour
/// The colour of `t` in [0, 1] (clamped) on a perceptually ordered dark-blue → magenta →
/// orange → yellow scale (close to matplotlib's "inferno"), so that more is brighter even in
/// greyscale print.
pub fn heat_colour(t: f64) -> [u8; 3] {
    const STOPS: [[f64; 3]; 6] = [
        [0.0, 0.0, 4.0],
        [40.0, 11.0, 84.0],
        [101.0, 21.0, 110.0],
        [188.0, 55.0, 84.0],
        [249.0, 142.0, 9.0],
        [252.0, 255.0, 164.0],
    ];
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let f = t * (STOPS.len() - 1) as f64;
    let i = (f.floor() as usize).min(STOPS.len() - 2);
    let u = f - i as f64;
    let mut out = [0u8; 3];
    for c in 0..3 {
        out[c] = (STOPS[i][c] + (STOPS[i + 1][c] - STOPS[i][c]) * u).round() as u8;
    }
    out
}
// ANCHOR_END: heat_colour

/// A `width`×`height` heat map of `values` (row-major), `max` mapping to the top of the scale
/// (values above it saturate). `max` ≤ 0 draws everything at the bottom of the scale.
pub fn heat_map(values: &[f64], width: u32, height: u32, max: f64) -> RgbImage {
    let mut img = RgbImage::new(width, height);
    for (i, p) in img.pixels_mut().enumerate() {
        let v = values.get(i).copied().unwrap_or(0.0);
        let t = if max > 0.0 { v / max } else { 0.0 };
        *p = Rgb(heat_colour(t));
    }
    img
}

/// The samples-per-pixel map of a render ([`crate::sampling::RenderOutput::spp_map`]) as a
/// heat map, scaled so that `max_spp` (e.g. the adaptive sampler's most expensive pixel) is
/// the brightest colour.
pub fn spp_heat_map(spp: &[u32], width: u32, height: u32, max_spp: u32) -> RgbImage {
    let v: Vec<f64> = spp.iter().map(|&n| n as f64).collect();
    heat_map(&v, width, height, max_spp as f64)
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn scale_is_monotone_in_brightness() {
        let lum = |c: [u8; 3]| 0.2126 * c[0] as f64 + 0.7152 * c[1] as f64 + 0.0722 * c[2] as f64;
        let mut last = -1.0;
        for i in 0..=20 {
            let l = lum(heat_colour(i as f64 / 20.0));
            assert!(l > last, "brightness rises along the scale");
            last = l;
        }
        let img = spp_heat_map(&[4, 20], 2, 1, 20);
        assert_eq!(img.get_pixel(1, 0).0, heat_colour(1.0));
        assert_eq!(img.get_pixel(0, 0).0, heat_colour(0.2));
    }
}
