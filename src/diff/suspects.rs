//! Which mistake of the catalogue makes a region look as it does: the region's pixels (and a
//! few agreeing pixels around them) rendered under each mistake, and promising pairs, scored
//! by how much of the region's difference each removes.

use super::pixels;
use crate::mistakes::{Mistake, Mistakes};
use crate::scene::Scene;
use image::RgbImage;

/// One suspect: a mistake (or a pair) and how much of the difference it explains.
#[derive(Debug, Clone, PartialEq)]
pub struct MistakeFit {
    /// The mistakes added to the scene's settings.
    pub mistakes: Mistakes,
    /// 1 − Σ(yours − with the mistake)² / Σ(yours − expected)² over the scored pixels
    /// (bytes); 1: the mistake makes exactly your image there; ≤ 0: no better than correct.
    pub explained: f64,
}

/// Suspects reported per region, and the least share of the difference one must explain.
const REPORTED: usize = 3;
const MIN_EXPLAINED: f64 = 0.2;
/// Pairs tried: each of the `FORWARD` best singles, and of the `FORWARD` that point the most
/// the right way, with every other mistake, and the
/// `PAIRED` singles that point the most the right way with each other; a pair must add
/// `PAIR_GAIN` over its better half.
const FORWARD: usize = 2;
const PAIRED: usize = 4;
const PAIR_GAIN: f64 = 0.05;

/// Scores `base` ∪ each mistake (then pairs of the best) on `scored` pixels: the region's
/// differing pixels and some agreeing ones near it, so a mistake that changes too much is
/// marked down. Best first; ties in catalogue order.
pub fn search(
    scene: &Scene,
    expected: &RgbImage,
    yours: &RgbImage,
    scored: &[(u32, u32)],
) -> Vec<MistakeFit> {
    let base = scene.render.mistakes;
    let get = |img: &RgbImage| -> Vec<[u8; 3]> {
        scored.iter().map(|&(x, y)| img.get_pixel(x, y).0).collect()
    };
    let (want, was) = (get(yours), get(expected));
    let sq = |a: &[[u8; 3]], b: &[[u8; 3]]| -> f64 {
        a.iter()
            .zip(b)
            .map(|(p, q)| {
                (0..3)
                    .map(|c| (p[c] as f64 - q[c] as f64).powi(2))
                    .sum::<f64>()
            })
            .sum()
    };
    let total = sq(&want, &was);
    if total <= 0.0 {
        return Vec::new();
    }
    // How much of the difference a set removes, and how well the change it makes points
    // the right way (cos² between the change and the difference: a half of a pair of
    // mistakes points the right way without explaining it all).
    let score = |set: Mistakes| -> (f64, f64) {
        let mut s = scene.render.clone();
        s.mistakes = set;
        let got = pixels::bytes(scene, &s, scored);
        let (mut dot, mut moved) = (0.0, 0.0);
        for ((g, e), y) in got.iter().zip(&was).zip(&want) {
            for c in 0..3 {
                let m = g[c] as f64 - e[c] as f64;
                dot += m * (y[c] as f64 - e[c] as f64);
                moved += m * m;
            }
        }
        let cos2 = if moved > 0.0 && dot > 0.0 {
            dot * dot / (moved * total)
        } else {
            0.0
        };
        (1.0 - sq(&want, &got) / total, cos2)
    };
    let singles: Vec<(Mistake, f64, f64)> = Mistake::ALL
        .iter()
        .filter(|m| !base.has(**m))
        .map(|&m| {
            let (e, c) = score(base.with(m));
            (m, e, c)
        })
        .collect();
    let fit = |set: Mistakes, explained: f64| MistakeFit {
        mistakes: set,
        explained,
    };
    let mut all: Vec<MistakeFit> = singles.iter().map(|s| fit(base.with(s.0), s.1)).collect();
    let by = |key: fn(&(Mistake, f64, f64)) -> f64| {
        let mut v: Vec<&(Mistake, f64, f64)> = singles.iter().filter(|s| key(s) > 0.0).collect();
        v.sort_by(|a, b| key(b).total_cmp(&key(a)).then(a.0.cmp(&b.0)));
        v.into_iter().map(|s| s.0).collect::<Vec<Mistake>>()
    };
    let best = by(|s| s.1);
    if best
        .first()
        .is_none_or(|m| singles.iter().any(|s| s.0 == *m && s.1 < 0.98))
    {
        // Pairs: the best singles with every other mistake (forward selection), and the
        // singles that point the right way with each other.
        let mut pairs: Vec<(Mistake, Mistake)> = Vec::new();
        let pointing = by(|s| s.2);
        let leads = best
            .iter()
            .take(FORWARD)
            .chain(pointing.iter().take(FORWARD));
        for &a in leads {
            for s in &singles {
                pairs.push((a.min(s.0), a.max(s.0)));
            }
        }
        for (i, &a) in pointing.iter().take(PAIRED).enumerate() {
            for &b in pointing.iter().take(PAIRED).skip(i + 1) {
                pairs.push((a.min(b), a.max(b)));
            }
        }
        pairs.retain(|p| p.0 != p.1);
        pairs.sort();
        pairs.dedup();
        let alone = |m: Mistake| singles.iter().find(|s| s.0 == m).map_or(0.0, |s| s.1);
        for (a, b) in pairs {
            let set = base.with(a).with(b);
            let (explained, _) = score(set);
            if explained >= alone(a).max(alone(b)) + PAIR_GAIN {
                all.push(fit(set, explained));
            }
        }
    }
    all.sort_by(|a, b| b.explained.total_cmp(&a.explained));
    all.into_iter()
        .filter(|f| f.explained >= MIN_EXPLAINED)
        .take(REPORTED)
        .collect()
}

/// The mistakes of a fit beyond the scene's own, as `--mistake` names them.
pub fn added(scene: &Scene, f: &MistakeFit) -> Vec<&'static str> {
    f.mistakes
        .iter()
        .filter(|m| !scene.render.mistakes.has(*m))
        .map(Mistake::name)
        .collect()
}
