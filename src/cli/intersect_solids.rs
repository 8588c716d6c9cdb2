//! `rtlab intersect csg|blob --spec FILE`: one ray against a CSG solid or a blob described in
//! a small JSON file (written like a scene object; see [`crate::scene::load_solid`]).
//!
//! The same closest-hit routine `render` uses runs with the [`Working`] observer. Output
//! format (version 1), for `--format json`:
//!
//! ```text
//! { "shape": "csg"|"blob", "ray": {"origin": [..], "direction": [..]},
//!   "csg":  {"op", "children": [{"name", "shape", "spans": [{"enter": B, "exit": B}], "csg"?}],
//!            "combined": [..]}                        (csg only; B = {"t", "surface", "point", "normal"})
//!   "blob": {"threshold", "lipschitz", "segments", "samples": [[t, field]], "brackets",
//!            "steps": [{"method", "t", "field", "a", "b"}], "roots"}   (blob only)
//!   "candidates": [...as for the other shapes...],
//!   "hit": null | {"t", "point", "normal", "surface"} }
//! ```
//!
//! Spans and the blob's working are in the solid's own space (the spec's `transform` moves
//! the ray there; t is the same parameter). `-o FIG.png` draws the intervals (CSG) or the
//! field profile (blob) with [`crate::viz::solids`].

use crate::error::{Error, Result};
use crate::math::Ray;
use crate::shapes::working::{short, CandidateRecord, Working};
use crate::shapes::{NoObserver, Shape};
use glam::DVec3;
use serde::Serialize;
use std::io::Write;
use std::path::Path;

#[derive(Debug, Serialize)]
struct HitOut {
    t: f64,
    point: DVec3,
    normal: DVec3,
    surface: &'static str,
}

#[derive(Debug, Serialize)]
struct RayOut {
    origin: DVec3,
    direction: DVec3,
}

#[derive(Debug, Serialize)]
struct Report {
    shape: &'static str,
    ray: RayOut,
    #[serde(skip_serializing_if = "Option::is_none")]
    csg: Option<crate::shapes::working::CsgWorking>,
    #[serde(skip_serializing_if = "Option::is_none")]
    blob: Option<crate::shapes::working::BlobWorking>,
    candidates: Vec<CandidateRecord>,
    hit: Option<HitOut>,
}

/// Intersects the ray `origin + t·dir` with the solid in `spec_path` (`shape` is "csg" or
/// "blob"), prints text or JSON to `out`, and draws `figure` when asked.
pub fn run(
    shape: &str,
    spec_path: &Path,
    origin: DVec3,
    dir: DVec3,
    format_json: bool,
    figure: Option<&Path>,
    out: &mut dyn Write,
) -> Result<()> {
    if shape != "csg" && shape != "blob" {
        return Err(Error::arg(
            "SHAPE",
            format!("expected csg or blob, found \"{shape}\""),
        ));
    }
    if !(origin.is_finite() && dir.is_finite()) || dir.length_squared() == 0.0 {
        return Err(Error::arg(
            "--dir",
            "the direction must be a finite, non-zero vector",
        ));
    }
    let object = crate::scene::load_solid(spec_path, shape)?;
    let ray = Ray::new(origin, dir);
    let local = object.transform.ray_to_object(&ray);
    let mut w = Working::default();
    let local_hit = object.shape.intersect(&local, 0.0, f64::INFINITY, &mut w);
    w.conclude(local_hit.map(|h| h.t), f64::INFINITY);
    let hit = local_hit.map(|h| HitOut {
        t: h.t,
        point: ray.at(h.t),
        normal: object.transform.normal_to_world(h.normal),
        surface: h.surface,
    });
    // For the blob figure: every root along the ray ahead of the origin, not only the first.
    let all_roots = match &object.shape {
        Shape::Blob(b) => b.roots(&local, 0.0, f64::INFINITY, false, &mut NoObserver),
        _ => Vec::new(),
    };
    let report = Report {
        shape: object.shape.kind(),
        ray: RayOut {
            origin,
            direction: dir,
        },
        csg: w.csg.clone(),
        blob: w.blob.clone(),
        candidates: w.candidates.clone(),
        hit,
    };
    if let Some(path) = figure {
        let canvas = match &object.shape {
            Shape::Csg(_) => match &report.csg {
                Some(c) => crate::viz::solids::csg_figure(c, local_hit.map(|h| h.t)),
                None => unreachable_figure()?,
            },
            Shape::Blob(b) => crate::viz::solids::blob_figure(
                b,
                &local,
                report.blob.as_ref().expect("a blob search was observed"),
                &all_roots,
                local_hit.map(|h| h.t),
            ),
            _ => unreachable_figure()?,
        };
        canvas.write_png(path)?;
    }
    let text = if format_json {
        serde_json::to_string_pretty(&report).expect("serialisable") + "\n"
    } else {
        text(&report, &all_roots)
    };
    super::emit(out, &text)
}

fn unreachable_figure() -> Result<crate::viz::Canvas> {
    Err(Error::Other(
        "no working was recorded for the figure".into(),
    ))
}

fn text(r: &Report, all_roots: &[(f64, bool)]) -> String {
    use std::fmt::Write;
    let v3 = super::explain_text::v3;
    let mut o = String::new();
    let _ = writeln!(
        o,
        "{} along P + t·d, P = {}, d = {}",
        r.shape,
        v3(r.ray.origin),
        v3(r.ray.direction)
    );
    let len = r.ray.direction.length();
    if (len - 1.0).abs() > 1e-9 {
        let _ = writeln!(
            o,
            "note: |d| = {} is not 1, so t is not a distance (t is the parameter of P + t·d)",
            short(len)
        );
    }
    if let Some(c) = &r.csg {
        super::explain_text::csg_text(&mut o, c, "");
    }
    if let Some(b) = &r.blob {
        super::explain_text::blob_text(&mut o, b, "");
        if all_roots.len() > 1 {
            let ts: Vec<String> = all_roots.iter().map(|(t, _)| short(*t)).collect();
            let _ = writeln!(o, "all roots ahead of the origin: t = {}", ts.join(", "));
        }
    }
    match &r.hit {
        Some(h) => {
            let _ = writeln!(
                o,
                "hit: t = {} on {}, point {}, normal {}",
                short(h.t),
                h.surface,
                v3(h.point),
                v3(h.normal)
            );
        }
        None => {
            let _ = writeln!(o, "miss: no boundary of the solid at t ≥ 0");
        }
    }
    o
}
