//! `diff`'s outputs: the JSON for scripts and the few lines a student reads first.
//!
//! JSON (version 1):
//! `{"version": 1, "size": [w, h], "metrics": {"diff_percent", "psnr" (dB, null when
//! identical), "max" (levels), "tolerance" (levels), "differing" (pixels)}, "verdict":
//! "same"|"different", "regions_found", "regions": [{"bbox": [x0, y0, x1, y1], "pixels",
//! "objects": [{"name", "surfaces": [..], "pixels"}], "mean_difference": [r, g, b] (yours −
//! expected, levels), "pixel": [x, y], "explain", "terms": [{"term", "light", "coefficient",
//! "explained", "says"}], "terms_explained", "mistakes": [{"name", "names", "explained"}]}],
//! "diagnosis": [{"name", "names", "regions", "pixels"}]}` (each region's best mistake, summed
//! over the regions it explains).

use super::{terms, Report};
use crate::scene::Scene;
use serde_json::{json, Value};

fn round(x: f64, digits: i32) -> f64 {
    let f = 10f64.powi(digits);
    let r = (x * f).round() / f;
    if r == 0.0 {
        0.0
    } else {
        r
    }
}

/// The mistakes the regions point at, over the whole image: each region's best one, with
/// the regions (numbered from 1) and pixels it explains; most pixels first. Where mistakes tie
/// in a region (they make the same image there), the one that is best in the most pixels over
/// the image names it: one mistake made everywhere, rather than two that look alike.
pub fn diagnosis(scene: &Scene, r: &Report) -> Vec<(Vec<&'static str>, Vec<usize>, usize)> {
    // Per region, the names of its best suspects (all within a hair of the best).
    let tied: Vec<Vec<Vec<&'static str>>> = r
        .regions
        .iter()
        .map(|g| match g.mistakes.first() {
            None => Vec::new(),
            Some(best) => g
                .mistakes
                .iter()
                .filter(|f| f.explained >= best.explained - 1e-6)
                .map(|f| super::suspects::added(scene, f))
                .collect(),
        })
        .collect();
    let mut left: Vec<usize> = (0..r.regions.len())
        .filter(|&i| !tied[i].is_empty())
        .collect();
    let mut out: Vec<(Vec<&'static str>, Vec<usize>, usize)> = Vec::new();
    while !left.is_empty() {
        // The suspect best in the most pixels of the regions not yet named; the earlier
        // region's first on a tie.
        let mut pick: Option<(Vec<&'static str>, usize)> = None;
        for &i in &left {
            for names in &tied[i] {
                let pixels: usize = left
                    .iter()
                    .filter(|&&j| tied[j].contains(names))
                    .map(|&j| r.regions[j].members.len())
                    .sum();
                if pick.as_ref().is_none_or(|p| pixels > p.1) {
                    pick = Some((names.clone(), pixels));
                }
            }
        }
        let (names, pixels) = pick.expect("a region left has suspects");
        let regions: Vec<usize> = left
            .iter()
            .filter(|&&j| tied[j].contains(&names))
            .map(|j| j + 1)
            .collect();
        left.retain(|j| !tied[*j].contains(&names));
        out.push((names, regions, pixels));
    }
    out.sort_by_key(|d| std::cmp::Reverse(d.2));
    out
}

/// The report as JSON (rounded at the source: levels to 2 decimals, fractions to 3).
pub fn to_json(scene: &Scene, r: &Report) -> Value {
    let regions: Vec<Value> = r
        .regions
        .iter()
        .map(|g| {
            json!({
                "bbox": g.bbox,
                "pixels": g.members.len(),
                "objects": g.objects.iter().map(|o| json!({
                    "name": o.name, "surfaces": o.surfaces, "pixels": o.pixels,
                })).collect::<Vec<_>>(),
                "mean_difference": g.mean_difference.map(|v| round(v, 2)),
                "pixel": [g.pixel.0, g.pixel.1],
                "explain": g.explain,
                "terms": g.fit.terms.iter().map(|t| json!({
                    "term": t.term.kind.name(),
                    "light": terms::light_name(scene, t.term),
                    "coefficient": round(t.coefficient, 3),
                    "explained": round(t.explained, 3),
                    "says": terms::sentence(scene, t),
                })).collect::<Vec<_>>(),
                "terms_explained": round(g.fit.explained, 3),
                "mistakes": g.mistakes.iter().map(|f| {
                    let names = super::suspects::added(scene, f);
                    json!({"name": names.join(" + "), "names": names, "explained": round(f.explained, 3)})
                }).collect::<Vec<_>>(),
            })
        })
        .collect();
    json!({
        "version": 1,
        "size": [r.width, r.height],
        "metrics": {
            "diff_percent": round(r.metrics.diff_percent, 3),
            "psnr": r.metrics.psnr.map(|p| round(p, 2)),
            "max": r.metrics.max,
            "tolerance": r.metrics.tolerance,
            "differing": r.metrics.differing,
        },
        "verdict": if r.same { "same" } else { "different" },
        "regions_found": r.regions_found,
        "diagnosis": diagnosis(scene, r).into_iter().map(|(names, regions, pixels)| json!({
            "name": names.join(" + "), "names": names, "regions": regions, "pixels": pixels,
        })).collect::<Vec<_>>(),
        "regions": regions,
    })
}

/// A term fit that explains less than this share of a region is not shown to people (the
/// JSON still has it): the difference is not one of lighting.
pub const WELL_EXPLAINED: f64 = 0.5;

fn count(n: usize) -> String {
    crate::report::thousands(n as u64)
}

/// Where a region is, for people: "sphere (body, cap)".
pub fn objects_words(g: &super::Region) -> String {
    g.objects
        .iter()
        .take(3)
        .map(|o| {
            if o.surfaces.is_empty() {
                o.name.clone()
            } else {
                format!("{} ({})", o.name, o.surfaces.join(", "))
            }
        })
        .collect::<Vec<_>>()
        .join(", ")
        + if g.objects.len() > 3 { ", ..." } else { "" }
}

/// The mean difference, for people: "(−30.1, −30.0, −29.8)".
pub fn difference_words(d: [f64; 3]) -> String {
    let f = |v: f64| {
        let s = format!("{:.1}", v.abs());
        if v < 0.0 && s != "0.0" {
            format!("−{s}")
        } else if s != "0.0" {
            format!("+{s}")
        } else {
            s
        }
    };
    format!("({}, {}, {})", f(d[0]), f(d[1]), f(d[2]))
}

/// The few lines a student reads first.
pub fn to_text(scene: &Scene, r: &Report, max_percent: f64) -> String {
    let m = &r.metrics;
    let total = r.width as usize * r.height as usize;
    let psnr = m
        .psnr
        .map_or("identical".into(), |p| format!("PSNR {p:.1} dB"));
    let mut s = format!(
        "{}: {} of {} pixels ({:.2} %) differ by more than {} levels (largest difference {}, {psnr}); {} allows {max_percent} %\n",
        if r.same { "same" } else { "different" },
        count(m.differing),
        count(total),
        m.diff_percent,
        m.tolerance,
        m.max,
        if r.same { "the rule" } else { "the rule only" },
    );
    let d = diagnosis(scene, r);
    if !d.is_empty() {
        let parts: Vec<String> = d
            .iter()
            .map(|(names, regions, pixels)| {
                let list: Vec<String> = regions.iter().map(|k| k.to_string()).collect();
                format!(
                    "{} (region{} {}: {} pixels)",
                    names.join(" + "),
                    if regions.len() == 1 { "" } else { "s" },
                    list.join(", "),
                    count(*pixels)
                )
            })
            .collect();
        s += &format!("most likely: {}\n", parts.join("; "));
    }
    for (i, g) in r.regions.iter().enumerate() {
        s += &format!(
            "region {}: {} pixels in [{}, {}]–[{}, {}] on {}; yours − expected {} levels\n",
            i + 1,
            count(g.members.len()),
            g.bbox[0],
            g.bbox[1],
            g.bbox[2],
            g.bbox[3],
            objects_words(g),
            difference_words(g.mean_difference),
        );
        if g.fit.explained < WELL_EXPLAINED {
            s += "  term: no term of the lighting ledger explains most of it (the geometry, the camera or the bytes differ)\n";
        }
        for t in g
            .fit
            .terms
            .iter()
            .filter(|_| g.fit.explained >= WELL_EXPLAINED)
        {
            s += &format!(
                "  term: {} ({:.0} % of the difference)\n",
                terms::sentence(scene, t),
                100.0 * t.explained
            );
        }
        match g.mistakes.first() {
            Some(f) => {
                s += &format!(
                    "  mistake: {} ({:.0} % of the difference; `rtlab mistakes` says what the wrong code does)\n",
                    super::suspects::added(scene, f).join(" + "),
                    100.0 * f.explained
                );
            }
            None => s += "  mistake: none of the catalogue makes this difference\n",
        }
        s += &format!("  see what it should be: {}\n", g.explain);
    }
    if r.regions_found > r.regions.len() {
        s += &format!(
            "... and {} smaller regions (--format json lists the largest {})\n",
            r.regions_found - r.regions.len(),
            r.regions.len()
        );
    }
    s
}
