//! Which term of the lighting ledger accounts for a region's difference: a least-squares fit
//! yours ≈ expected + Σ c_k·term_k over the region's pixels, terms chosen greedily (forward
//! selection), so the answer is the few terms that explain most of it.
//!
//! The terms come from the one tracer through [`LedgerRecorder`](super::pixels::LedgerRecorder):
//! the camera ray's ambient, each light's diffuse and specular, what each light's shadow
//! removes (the same pixel traced with shadows off, minus the lit one), the reflected and
//! transmitted colours, and the lights a course stage ignores.

use super::pixels::Ledger;
use crate::scene::{Encoding, Scene};
use glam::DVec3;
use serde::Serialize;

/// A kind of ledger term.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum TermKind {
    Ambient,
    Diffuse,
    Specular,
    /// Diffuse + specular of a light: all it adds.
    Light,
    /// What the light's shadow removes: the unshadowed term minus the shadowed one.
    Shadow,
    /// Diffuse + specular of a light the settings leave out (the Intersect stage's point
    /// and spot lights), unshadowed.
    Ignored,
    Reflected,
    Transmitted,
}

impl TermKind {
    pub fn name(self) -> &'static str {
        match self {
            TermKind::Ambient => "ambient",
            TermKind::Diffuse => "diffuse",
            TermKind::Specular => "specular",
            TermKind::Light => "light",
            TermKind::Shadow => "shadow",
            TermKind::Ignored => "ignored",
            TermKind::Reflected => "reflected",
            TermKind::Transmitted => "transmitted",
        }
    }
    fn per_light(self) -> bool {
        !matches!(
            self,
            TermKind::Ambient | TermKind::Reflected | TermKind::Transmitted
        )
    }
}

/// One candidate term: a kind, and for per-light kinds one light (`Some`) or the sum over
/// every light (`None`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Term {
    pub kind: TermKind,
    pub light: Option<usize>,
}

/// One term of a fit.
#[derive(Debug, Clone, PartialEq)]
pub struct TermFit {
    pub term: Term,
    pub coefficient: f64,
    /// The fraction of the region's squared difference this term removed when it was added
    /// (the terms' fractions add up to the fit's).
    pub explained: f64,
}

/// The terms chosen for a region.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Fit {
    pub terms: Vec<TermFit>,
    /// 1 − residual / difference, both summed squares over the region's channels.
    pub explained: f64,
}

/// Terms a fit may choose from for this scene. `shadows`: the settings cast shadow rays.
pub fn candidates(scene: &Scene, shadows: bool) -> Vec<Term> {
    let n = scene.lights.len();
    let ignored = scene.render.directional_only;
    let mut v = vec![Term {
        kind: TermKind::Ambient,
        light: None,
    }];
    let mut kinds = vec![TermKind::Diffuse, TermKind::Specular, TermKind::Light];
    if shadows {
        kinds.push(TermKind::Shadow);
    }
    if ignored {
        kinds.push(TermKind::Ignored);
    }
    for &kind in &kinds {
        for l in 0..n {
            v.push(Term {
                kind,
                light: Some(l),
            });
        }
        // Shadows summed over the lights reach into reflections too: worth a term of its own.
        if n > 1 || kind == TermKind::Shadow {
            v.push(Term { kind, light: None });
        }
    }
    v.push(Term {
        kind: TermKind::Reflected,
        light: None,
    });
    v.push(Term {
        kind: TermKind::Transmitted,
        light: None,
    });
    v
}

/// The filter-weighted sum of samples' ledgers (`n` lights).
pub fn weighted(samples: &[(f64, Ledger)], n: usize) -> Ledger {
    let mut out = Ledger {
        diffuse: vec![DVec3::ZERO; n],
        specular: vec![DVec3::ZERO; n],
        ignored: vec![DVec3::ZERO; n],
        ..Ledger::default()
    };
    for (w, s) in samples {
        out.ambient += *w * s.ambient;
        out.reflected += *w * s.reflected;
        out.transmitted += *w * s.transmitted;
        for l in 0..n {
            out.diffuse[l] += *w * s.diffuse[l];
            out.specular[l] += *w * s.specular[l];
            out.ignored[l] += *w * s.ignored[l];
        }
    }
    out
}

/// A term's value at one pixel, from its ledger and (for shadows) the unshadowed ledger.
pub fn value(term: Term, lit: &Ledger, unshadowed: Option<&Ledger>) -> DVec3 {
    let each = |f: &dyn Fn(usize) -> DVec3| -> DVec3 {
        match term.light {
            Some(l) => f(l),
            None => (0..lit.diffuse.len()).map(f).sum(),
        }
    };
    match term.kind {
        TermKind::Ambient => lit.ambient,
        TermKind::Reflected => lit.reflected,
        TermKind::Transmitted => lit.transmitted,
        TermKind::Diffuse => each(&|l| lit.diffuse[l]),
        TermKind::Specular => each(&|l| lit.specular[l]),
        TermKind::Light => each(&|l| lit.diffuse[l] + lit.specular[l]),
        TermKind::Ignored => each(&|l| lit.ignored[l]),
        // One light's shadow at the first hit; every shadow anywhere in the ray tree (those
        // seen in a mirror too) for the sum over the lights.
        TermKind::Shadow => match (unshadowed, term.light) {
            (Some(u), Some(l)) => u.diffuse[l] + u.specular[l] - lit.diffuse[l] - lit.specular[l],
            (Some(u), None) => u.color - lit.color,
            (None, _) => DVec3::ZERO,
        },
    }
}

/// A byte back to the linear value it encodes (the lower end of its step for `Clamp`;
/// the same offset on both images cancels in a difference).
pub fn linear(b: u8, encoding: Encoding) -> f64 {
    let s = b as f64 / 255.0;
    match encoding {
        Encoding::Clamp => s,
        Encoding::Srgb => {
            if s <= 0.040_45 {
                s / 12.92
            } else {
                ((s + 0.055) / 1.055).powf(2.4)
            }
        }
    }
}

/// Most terms a fit reports, and the least share of the difference a term must add.
const MAX_TERMS: usize = 3;
const MIN_GAIN: f64 = 0.05;

/// Fits `yours − expected` (bytes, decoded by `encoding`) at each pixel by the candidate
/// terms' values there (`values[pixel][candidate]`). A channel saturated (255) in either
/// image says only "at least this bright" and is left out, unless that would leave out most
/// of the region.
pub fn fit(
    yours: &[[u8; 3]],
    expected: &[[u8; 3]],
    values: &[Vec<DVec3>],
    candidates: &[Term],
    encoding: Encoding,
) -> Fit {
    let k = candidates.len();
    let mut d = Vec::new();
    let mut cols: Vec<Vec<f64>> = vec![Vec::new(); k];
    let push_all = |keep_saturated: bool, d: &mut Vec<f64>, cols: &mut Vec<Vec<f64>>| {
        for (p, (y, e)) in yours.iter().zip(expected).enumerate() {
            for c in 0..3 {
                if !keep_saturated && (y[c] == 255 || e[c] == 255) {
                    continue;
                }
                d.push(linear(y[c], encoding) - linear(e[c], encoding));
                for (j, col) in cols.iter_mut().enumerate() {
                    col.push(values[p][j][c]);
                }
            }
        }
    };
    push_all(false, &mut d, &mut cols);
    if d.len() * 3 < yours.len() * 3 {
        d.clear();
        cols.iter_mut().for_each(Vec::clear);
        push_all(true, &mut d, &mut cols);
    }
    let total: f64 = d.iter().map(|x| x * x).sum();
    if total <= 0.0 || d.is_empty() {
        return Fit::default();
    }
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    // A term that is zero over the region (a light that does not reach it) cannot explain it.
    let usable: Vec<bool> = cols
        .iter()
        .map(|c| dot(c, c) > 1e-12 * c.len() as f64)
        .collect();
    let gram: Vec<Vec<f64>> = (0..k)
        .map(|i| {
            (0..k)
                .map(|j| {
                    if usable[i] && usable[j] {
                        dot(&cols[i], &cols[j])
                    } else {
                        0.0
                    }
                })
                .collect()
        })
        .collect();
    let rhs: Vec<f64> = cols.iter().map(|c| dot(c, &d)).collect();
    // Residual sum of squares of the least-squares fit on `set`, and its coefficients.
    let solve = |set: &[usize]| -> Option<(f64, Vec<f64>)> {
        let n = set.len();
        let mut a: Vec<Vec<f64>> = set
            .iter()
            .map(|&i| {
                let mut row: Vec<f64> = set.iter().map(|&j| gram[i][j]).collect();
                row.push(rhs[i]);
                row
            })
            .collect();
        for col in 0..n {
            let piv = (col..n).max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs()))?;
            if a[piv][col].abs() < 1e-9 * gram[set[col]][set[col]].max(1e-300) {
                return None; // collinear with terms already chosen
            }
            a.swap(col, piv);
            // Row operations by index, as the elimination is written on paper.
            #[allow(clippy::needless_range_loop)]
            for r in 0..n {
                if r != col {
                    let f = a[r][col] / a[col][col];
                    for c in col..=n {
                        a[r][c] -= f * a[col][c];
                    }
                }
            }
        }
        let coef: Vec<f64> = (0..n).map(|i| a[i][n] / a[i][i]).collect();
        let explained: f64 = set.iter().zip(&coef).map(|(&i, c)| c * rhs[i]).sum();
        Some(((total - explained).max(0.0), coef))
    };
    let mut chosen: Vec<usize> = Vec::new();
    let mut gains = Vec::new();
    let mut residual = total;
    while chosen.len() < MAX_TERMS && residual > 0.02 * total {
        let best = (0..k)
            .filter(|j| usable[*j] && !chosen.contains(j))
            .filter_map(|j| {
                let mut set = chosen.clone();
                set.push(j);
                solve(&set).map(|(r, _)| (j, r))
            })
            .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
        match best {
            Some((j, r)) if (residual - r) / total >= MIN_GAIN => {
                chosen.push(j);
                gains.push((residual - r) / total);
                residual = r;
            }
            _ => break,
        }
    }
    let coef = if chosen.is_empty() {
        Vec::new()
    } else {
        solve(&chosen).expect("solved while choosing").1
    };
    Fit {
        terms: chosen
            .iter()
            .zip(coef)
            .zip(gains)
            .map(|((&j, coefficient), explained)| TermFit {
                term: candidates[j],
                coefficient,
                explained,
            })
            .collect(),
        explained: 1.0 - residual / total,
    }
}

/// The light a term names, for people: `` light `key` ``, or "every light".
fn light_words(scene: &Scene, term: Term) -> String {
    match term.light {
        Some(l) => format!("light `{}`", scene.lights[l].name),
        None => "every light".into(),
    }
}

/// The JSON name of a term's light: its name, `*` for the sum over every light, none for
/// terms that are not per light.
pub fn light_name(scene: &Scene, term: Term) -> Option<String> {
    match (term.kind.per_light(), term.light) {
        (false, _) => None,
        (true, Some(l)) => Some(scene.lights[l].name.clone()),
        (true, None) => Some("*".into()),
    }
}

/// One sentence a student reads: "−1.0 × specular of light `key`: your highlights are missing".
pub fn sentence(scene: &Scene, t: &TermFit) -> String {
    let c = t.coefficient;
    let whole = (c.abs() - 1.0).abs() < 0.15;
    let more = c > 0.0;
    let every = t.term.light.is_none();
    let what = match t.term.kind {
        TermKind::Ambient => "ambient".to_string(),
        TermKind::Reflected => "reflected colour".to_string(),
        TermKind::Transmitted => "transmitted colour".to_string(),
        TermKind::Diffuse => format!("diffuse of {}", light_words(scene, t.term)),
        TermKind::Specular => format!("specular of {}", light_words(scene, t.term)),
        TermKind::Light => format!("diffuse and specular of {}", light_words(scene, t.term)),
        TermKind::Shadow if t.term.light.is_none() => {
            "every shadow (in reflections too)".to_string()
        }
        TermKind::Shadow => format!("the shadow of {}", light_words(scene, t.term)),
        TermKind::Ignored => format!(
            "diffuse and specular of {} (which the course stage leaves out)",
            light_words(scene, t.term)
        ),
    };
    let meaning = match (t.term.kind, more) {
        (TermKind::Specular, false) if whole => "your highlights are missing",
        (TermKind::Specular, false) => "your highlights are too weak",
        (TermKind::Specular, true) => "your highlights are too strong",
        (TermKind::Diffuse, false) if whole && every => "the lights' diffuse shading is missing",
        (TermKind::Diffuse, false) if whole => "this light's diffuse shading is missing",
        (TermKind::Diffuse, false) => "your diffuse shading is too dark",
        (TermKind::Diffuse, true) => "your diffuse shading is too bright",
        (TermKind::Light, false) if whole && every => "no light reaches your surface",
        (TermKind::Light, false) if whole => "this light does not reach your surface",
        (TermKind::Light, false) if every => "the lights are too weak in your image",
        (TermKind::Light, false) => "this light is too weak in your image",
        (TermKind::Light, true) if every => "the lights are too strong in your image",
        (TermKind::Light, true) => "this light is too strong in your image",
        (TermKind::Ambient, false) => "your ambient term is too weak or missing",
        (TermKind::Ambient, true) => "your ambient term is too strong",
        (TermKind::Shadow, true) => "your image is lit where the expected one is in shadow",
        (TermKind::Shadow, false) => "your shadows are darker than expected",
        (TermKind::Reflected, false) => "your reflections are missing or too weak",
        (TermKind::Reflected, true) => "your reflections are too strong",
        (TermKind::Transmitted, false) => "what shows through is missing or too weak",
        (TermKind::Transmitted, true) => "what shows through is too strong",
        (TermKind::Ignored, true) => "you lit with lights this stage does not use",
        (TermKind::Ignored, false) => "the fit wants less than nothing of an ignored light",
    };
    format!("{} × {what}: {meaning}", signed(c))
}

/// "+1.0", "−0.5" (a real minus sign).
pub fn signed(c: f64) -> String {
    let s = format!("{:.1}", c.abs());
    if c < 0.0 && s != "0.0" {
        format!("−{s}")
    } else {
        format!("+{s}")
    }
}
