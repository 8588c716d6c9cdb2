//! "For fast results, take as many samples as time permits": progressive rendering.
//!
//! A render is a sequence of passes, each a complete image made by the ordinary renderer
//! ([`super::render`]) with settings derived from the scene's ([`pass_settings`]):
//!
//! | pass | what it traces |
//! |------|----------------|
//! | 1 | a preview: `subsample` 4 times the scene's, at most 64 (one pixel in 4×4 traces, the stretched filter fills in the rest) |
//! | 2 | the scene's own settings: the image `rtlab render` makes without `--passes` |
//! | k > 2 | 4ᵏ⁻² times the scene's samples per pixel (the grid and jittered samplers twice as many strata per side; center and corners continue as the grid sampler, of which the centre sample is the 1×1 case) |
//!
//! Each pass's image depends only on the scene and its pass number, never on how long the
//! earlier passes took, so a render that stopped at a time budget after pass K has exactly
//! the bytes of `rtlab render --passes K`. Each pass starts from scratch: the samples of pass
//! k are not kept for pass k + 1 (the grid and jittered patterns move when they get finer).
//! As pass k + 1 costs about four times pass k, the passes before the one written cost about
//! a third of it; under a time budget the pass abandoned when the time ran out is lost too.

use super::film::{check_memory, render_until, Counting, RenderOutput};
use super::validate_spp;
use crate::scene::{RenderSettings, SamplerKind, Scene};
use std::time::Instant;

/// The most `subsample` can be ([`RenderSettings::subsample`]'s own limit on the CLI).
const MAX_SUBSAMPLE: u32 = 64;

/// The settings of pass `k` (1-based) of a progressive render of a `width`×`height` image
/// from `base` (the scene's settings), or why there is no such pass: more samples per pixel
/// than the samplers allow, or more memory than a render may take.
pub fn pass_settings(
    base: &RenderSettings,
    width: u32,
    height: u32,
    k: u32,
) -> Result<RenderSettings, String> {
    let mut s = base.clone();
    match k {
        0 => return Err("passes are numbered from 1".into()),
        1 => s.subsample = (base.subsample.max(1) * 4).min(MAX_SUBSAMPLE),
        2 => {}
        _ => {
            let grow = 4u64.checked_pow(k - 2).unwrap_or(u64::MAX);
            let (sampler, spp) = match base.sampler {
                SamplerKind::Center | SamplerKind::Corners => (SamplerKind::Grid, 1),
                kind => (kind, base.spp.max(1) as u64),
            };
            let spp = spp
                .checked_mul(grow)
                .and_then(|n| u32::try_from(n).ok())
                .ok_or_else(|| too_many(k, spp))?;
            validate_spp(sampler, spp).map_err(|m| format!("pass {k}: {m}"))?;
            s.sampler = sampler;
            s.spp = spp;
        }
    }
    check_memory(width, height, s.sampler, s.spp, s.subsample)
        .map_err(|m| format!("pass {k}: {m}"))?;
    Ok(s)
}

/// A pass number as typed (`--passes K`, the server's `pass=K`): 1 or more.
pub fn parse_pass(s: &str) -> Result<u32, String> {
    let t = s.trim();
    // Digits, after one sign at most.
    let digits = t.strip_prefix(['+', '-']).unwrap_or(t);
    let whole = !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit());
    match t.parse::<i64>() {
        Ok(k) if k < 1 => Err("passes are numbered from 1".into()),
        Err(_) if whole && t.starts_with('-') => Err("passes are numbered from 1".into()),
        Ok(_) | Err(_) if whole => t
            .trim_start_matches('+')
            .parse::<u32>()
            .map_err(|_| format!("{t} is not a pass number (at most {})", u32::MAX)),
        _ => Err(format!("\"{s}\" is not a pass number (1, 2, 3, ...)")),
    }
}

/// `--time-budget`'s seconds: a finite number above 0, said back as typed when it is not.
pub fn parse_seconds(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(t) if t.is_finite() && t > 0.0 => Ok(t),
        _ => Err(format!(
            "\"{s}\" is not a time (expected seconds > 0, e.g. 2.5)"
        )),
    }
}

/// Pass `k` of a render of `spp` samples per pixel (at pass 2) asks for more than any count
/// the samplers take: said as the power it is, not as the number it overflows.
fn too_many(k: u32, spp: u64) -> String {
    format!(
        "pass {k} would take {spp} × 4^{} samples per pixel, more than the limit of {}",
        k - 2,
        super::sampler::MAX_SPP
    )
}

/// What one pass of [`progressive`] made (`T`: its image, a [`RenderOutput`] or, with
/// [`progressive_with`], whatever its renderer makes: an AOV's image).
pub struct PassOf<T> {
    /// Its number, from 1.
    pub index: u32,
    /// The settings it rendered with ([`pass_settings`]).
    pub settings: RenderSettings,
    pub output: T,
    /// Seconds since the progressive render began, when this pass was complete.
    pub finished: f64,
}

/// A pass of the colour render.
pub type Pass = PassOf<RenderOutput>;

/// Renders passes 1, 2, … ([`pass_settings`]) until `max_passes` are done, the sequence ends
/// (the next pass would exceed the sample or memory limits) or `stop(k)` says to stop while
/// pass k is running or before it starts. `stop` is asked before every tile, every pixel
/// (block of pixels, with bundles) and every row of its reconstruction, so a stopped pass
/// ends within a pixel's (or a row's) time;
/// its partial image is thrown away. It should be cheap (a flag, not a clock). A pass whose
/// settings' token (`base.cancel`) is cancelled stops sooner, within a few rays, and is
/// thrown away too: a time budget sets both. `each` sees every
/// completed pass as it is done (a progressive preview shows them). Returns the last
/// completed pass: `None` only if the first one was stopped (or Ctrl-C was pressed).
///
/// `count` records rays, tests and nodes per pass, as `render --stats` does.
pub fn progressive(
    scene: &Scene,
    base: &RenderSettings,
    count: bool,
    max_passes: Option<u32>,
    stop: &(dyn Fn(u32) -> bool + Sync),
    each: impl FnMut(&Pass),
) -> Option<Pass> {
    let counting = Counting::totals_if(count);
    let render = |settings: &RenderSettings, stop: &(dyn Fn() -> bool + Sync)| {
        colour_pass(scene, settings, counting, None, stop)
    };
    progressive_with(scene, base, max_passes, stop, render, each)
}

/// One pass of the colour render, as [`progressive_with`] asks for it: `None` when `stop`
/// stopped it or its settings' token (a caller's, or a time budget's) was cancelled.
/// `progress` (a terminal's bar) advances pixel by pixel, as for any render.
pub fn colour_pass(
    scene: &Scene,
    settings: &RenderSettings,
    counting: Counting,
    progress: Option<&indicatif::ProgressBar>,
    stop: &(dyn Fn() -> bool + Sync),
) -> Option<RenderOutput> {
    render_until(scene, settings, counting, progress, stop).filter(|o| !o.cancelled)
}

/// [`progressive`], each pass made by `render` from its settings (watching their token) and a
/// stop to ask as often as it can: `None` when it stopped before its image was complete.
/// An AOV's passes are made this way ([`crate::sampling::aov::render_aov`]).
pub fn progressive_with<T>(
    scene: &Scene,
    base: &RenderSettings,
    max_passes: Option<u32>,
    stop: &(dyn Fn(u32) -> bool + Sync),
    mut render: impl FnMut(&RenderSettings, &(dyn Fn() -> bool + Sync)) -> Option<T>,
    mut each: impl FnMut(&PassOf<T>),
) -> Option<PassOf<T>> {
    let start = Instant::now();
    let (w, h) = (scene.camera.width, scene.camera.height);
    let mut last: Option<PassOf<T>> = None;
    for k in 1..=max_passes.unwrap_or(u32::MAX) {
        let Ok(settings) = pass_settings(base, w, h, k) else {
            break;
        };
        if stop(k) {
            break;
        }
        let output = render(&settings, &|| stop(k));
        if crate::interrupt::requested() {
            return None;
        }
        let Some(output) = output else {
            break;
        };
        let pass = PassOf {
            index: k,
            settings,
            output,
            finished: start.elapsed().as_secs_f64(),
        };
        each(&pass);
        last = Some(pass);
    }
    last
}

/// A short description of a pass's settings, for messages: "subsample 4, 1 spp center", the
/// samples each pixel's filter takes ([`super::filter_samples`]).
pub fn describe(s: &RenderSettings) -> String {
    let sub = if s.subsample > 1 {
        format!("subsample {}, ", s.subsample)
    } else {
        String::new()
    };
    let spp = super::filter_samples(s.sampler, s.spp);
    format!("{sub}{spp} spp {}", s.sampler.name())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pass_numbers_are_whole_numbers_from_1_with_one_sign_at_most() {
        assert_eq!(parse_pass(" +7 "), Ok(7));
        assert_eq!(parse_pass("4294967295"), Ok(u32::MAX));
        assert!(parse_pass("4294967296")
            .unwrap_err()
            .contains("at most 4294967295"));
        assert!(parse_pass("18446744073709551616")
            .unwrap_err()
            .contains("at most"));
        for low in ["0", "-3", "-99999999999999999999"] {
            assert_eq!(
                parse_pass(low).unwrap_err(),
                "passes are numbered from 1",
                "{low}"
            );
        }
        for bad in ["+", "-", "++5", "+-5", "-+5", "1.5", "abc", ""] {
            let e = parse_pass(bad).unwrap_err();
            assert!(
                e.contains("is not a pass number (1, 2, 3, ...)"),
                "{bad}: {e}"
            );
        }
    }

    fn base(kind: SamplerKind, spp: u32) -> RenderSettings {
        RenderSettings {
            sampler: kind,
            spp,
            ..RenderSettings::default()
        }
    }

    #[test]
    fn passes_preview_then_the_scene_then_four_times_the_samples() {
        let b = base(SamplerKind::Jittered, 4);
        let p1 = pass_settings(&b, 64, 48, 1).unwrap();
        assert_eq!(
            (p1.subsample, p1.spp, p1.sampler),
            (4, 4, SamplerKind::Jittered)
        );
        assert_eq!(pass_settings(&b, 64, 48, 2).unwrap(), b);
        let p4 = pass_settings(&b, 64, 48, 4).unwrap();
        assert_eq!(
            (p4.subsample, p4.spp, p4.sampler),
            (1, 64, SamplerKind::Jittered)
        );
        // The centre sample is the 1×1 grid: later passes refine it as a grid.
        let c = pass_settings(&base(SamplerKind::Center, 1), 64, 48, 3).unwrap();
        assert_eq!((c.spp, c.sampler), (4, SamplerKind::Grid));
        // The sequence ends at the samplers' limit (65536 = 4⁸), never with a bad spp.
        let r = base(SamplerKind::Random, 1);
        assert!(pass_settings(&r, 2, 2, 10).is_ok());
        assert!(pass_settings(&r, 2, 2, 11).is_err());
        assert!(pass_settings(&r, 2, 2, 0).is_err());
        assert!(pass_settings(&r, 2, 2, 200).is_err());
        // Past what any integer holds, the count is said as the power it is.
        let far = pass_settings(&base(SamplerKind::Jittered, 3), 2, 2, 99).unwrap_err();
        assert_eq!(
            far,
            "pass 99 would take 3 × 4^97 samples per pixel, more than the limit of 65536"
        );
        // Memory: a big image ends the sequence earlier.
        assert!(pass_settings(&r, 1280, 720, 7).is_err());
    }
    #[test]
    fn a_pass_is_described_by_the_samples_a_pixel_takes() {
        let p1 = pass_settings(&base(SamplerKind::Center, 1), 64, 48, 1).unwrap();
        assert_eq!(describe(&p1), "subsample 4, 1 spp center");
        assert_eq!(describe(&base(SamplerKind::Grid, 16)), "16 spp grid");
        // Corners takes its centre and four corners whether the scene says spp 1 or 5.
        for spp in [1, 5] {
            assert_eq!(describe(&base(SamplerKind::Corners, spp)), "5 spp corners");
        }
    }
}
