use crate::math::Rng;
use crate::scene::SamplerKind;
use glam::DVec2;

/// Checks that `spp` suits the sampler (grids need a square number).
pub fn validate_spp(kind: SamplerKind, spp: u32) -> Result<(), String> {
    if spp == 0 {
        return Err("samples per pixel must be at least 1".into());
    }
    if spp > 65536 {
        return Err(format!(
            "{spp} samples per pixel is more than the limit of 65536"
        ));
    }
    if matches!(kind, SamplerKind::Grid | SamplerKind::Jittered) {
        let n = (spp as f64).sqrt().round() as u32;
        if n * n != spp {
            return Err(format!(
                "the {} sampler needs a square number of samples (1, 4, 9, 16, ...), found {spp}",
                kind.name()
            ));
        }
    }
    Ok(())
}

// ANCHOR: samplers
/// The film positions (pixel units, y down) of every sample of pixel (x, y), in sample-index
/// order. Random positions come from (seed, pixel, sample index) alone, so any one sample can
/// be replayed without the others.
pub fn pixel_samples(kind: SamplerKind, spp: u32, seed: u64, x: u32, y: u32) -> Vec<DVec2> {
    let corner = DVec2::new(x as f64, y as f64);
    let rng = |k: u32| Rng::new(&[seed, x as u64, y as u64, k as u64, 0x5A3B]);
    match kind {
        SamplerKind::Center => vec![corner + DVec2::splat(0.5)],
        SamplerKind::Grid | SamplerKind::Jittered => {
            let n = (spp as f64).sqrt().round() as u32;
            (0..n * n)
                .map(|k| {
                    let (i, j) = (k % n, k / n);
                    let offset = if kind == SamplerKind::Grid {
                        DVec2::splat(0.5)
                    } else {
                        let mut r = rng(k);
                        DVec2::new(r.next_f64(), r.next_f64())
                    };
                    corner + (DVec2::new(i as f64, j as f64) + offset) / n as f64
                })
                .collect()
        }
        SamplerKind::Random => (0..spp)
            .map(|k| {
                let mut r = rng(k);
                corner + DVec2::new(r.next_f64(), r.next_f64())
            })
            .collect(),
        // Corner samples lie on the pixel's border and are shared with the neighbours; the
        // centre is the pixel's own. Sample 0 is the centre, 1..4 the corners.
        SamplerKind::Corners => vec![
            corner + DVec2::splat(0.5),
            corner,
            corner + DVec2::new(1.0, 0.0),
            corner + DVec2::new(0.0, 1.0),
            corner + DVec2::new(1.0, 1.0),
        ],
        SamplerKind::Adaptive => vec![corner + DVec2::splat(0.5)],
    }
}
// ANCHOR_END: samplers

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn samples_stay_in_their_pixel_and_strata() {
        for kind in [
            SamplerKind::Grid,
            SamplerKind::Jittered,
            SamplerKind::Random,
        ] {
            let s = pixel_samples(kind, 16, 7, 3, 5);
            assert_eq!(s.len(), 16);
            for p in &s {
                assert!(
                    p.x >= 3.0 && p.x < 4.0 && p.y >= 5.0 && p.y < 6.0,
                    "{kind:?} {p}"
                );
            }
        }
        // Jittered: exactly one sample per 4x4 stratum.
        let s = pixel_samples(SamplerKind::Jittered, 16, 7, 0, 0);
        for (k, p) in s.iter().enumerate() {
            let (i, j) = ((p.x * 4.0) as usize, (p.y * 4.0) as usize);
            assert_eq!(j * 4 + i, k);
        }
        assert!(validate_spp(SamplerKind::Grid, 8).is_err());
        assert!(validate_spp(SamplerKind::Random, 0).is_err());
    }
}
