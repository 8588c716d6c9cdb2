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
/// Singles whose pairs are tried, and what a pair must add over its better half.
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
    let score = |set: Mistakes| -> f64 {
        let mut s = scene.render.clone();
        s.mistakes = set;
        let got = pixels::bytes(scene, &s, scored);
        1.0 - sq(&want, &got) / total
    };
    let mut singles: Vec<MistakeFit> = Mistake::ALL
        .iter()
        .filter(|m| !base.has(**m))
        .map(|&m| {
            let set = base.iter().chain([m]).collect();
            MistakeFit {
                mistakes: set,
                explained: score(set),
            }
        })
        .collect();
    singles.sort_by(|a, b| b.explained.total_cmp(&a.explained));
    let top: Vec<&MistakeFit> = singles
        .iter()
        .filter(|f| f.explained > 0.0)
        .take(PAIRED)
        .collect();
    let mut all = singles.clone();
    for i in 0..top.len() {
        for j in i + 1..top.len() {
            let set: Mistakes = top[i]
                .mistakes
                .iter()
                .chain(top[j].mistakes.iter())
                .collect();
            let explained = score(set);
            if explained >= top[i].explained.max(top[j].explained) + PAIR_GAIN {
                all.push(MistakeFit {
                    mistakes: set,
                    explained,
                });
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
