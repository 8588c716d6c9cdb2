//! `GET /api/explain`, `GET /api/diagram.png` and `GET /api/bundle.png`: one pixel
//! explained, as `rtlab explain` explains it, within the bounds a server keeps to.

use super::routes::{query, run, St};
use crate::error::Error;
use crate::scene::Scene;
use axum::extract::RawQuery;
use axum::response::Response;

/// `GET /api/explain?x=X&y=Y&<render options>`: `rtlab explain --format json`.
pub(super) async fn explain(axum::extract::State(state): St, RawQuery(raw): RawQuery) -> Response {
    let q = match query(&raw, &["x", "y"]) {
        Ok(q) => q,
        Err(r) => return r,
    };
    run(state, move |st| {
        let s = st.scene(&q.words)?;
        let (x, y) = q.pixel(s.camera.width, s.camera.height)?;
        let e = explained(&s, x, y)?;
        let text = crate::report::mistakes::to_json(&s, x, y, None, &e);
        Ok(("application/json", text.into_bytes()))
    })
    .await
}

/// The most samples one explanation traces and answers on the server: every sample that
/// reaches the pixel is in its document, each a few kilobytes with its ray tree (65,536 of
/// them, one pixel at `spp=65536`, made 430 MB).
pub const MAX_EXPLAINED: u64 = 4096;

/// The most rays one explanation on the server keeps between all its samples: each ray
/// is kept with every test and term, a few kilobytes a ray in memory and more as JSON
/// (4,102 rays of `scenes/glass.json` made 40 MB of JSON at a peak of 150 MB).
pub const MAX_EXPLAINED_RAYS: u64 = 16_384;

/// Pixel (x, y) explained ([`check_explained`]), unless its samples trace more than
/// [`MAX_EXPLAINED_RAYS`] rays (a deep tree of mirrors and glass, many samples): refused
/// then, before the memory it would take.
fn explained(
    s: &Scene,
    x: u32,
    y: u32,
) -> crate::error::Result<crate::report::explain::Explanation> {
    check_explained(s, x, y)?;
    crate::report::explain::explain_within(s, x, y, MAX_EXPLAINED_RAYS).ok_or_else(|| {
        Error::arg(
            "pixel",
            format!(
                "explaining pixel ({x}, {y}) traces more than {MAX_EXPLAINED_RAYS} rays between its samples, more than the page explains; use rtlab explain --pixel {x},{y} --sample K for one of them"
            ),
        )
    })
}

/// Refuses to explain a pixel whose document would hold more than [`MAX_EXPLAINED`] samples:
/// the pixel's own and those of its neighbours that the filter reaches.
fn check_explained(s: &Scene, x: u32, y: u32) -> crate::error::Result<()> {
    let reach = crate::sampling::Filter::for_settings(&s.render).reach() as u64;
    let span = |c: u32, n: u32| {
        let (c, n) = (u64::from(c), u64::from(n));
        (c + reach).min(n - 1) - c.saturating_sub(reach) + 1
    };
    let pixels = span(x, s.camera.width) * span(y, s.camera.height);
    let n = pixels * u64::from(s.render.spp);
    if n > MAX_EXPLAINED {
        return Err(Error::arg(
            "--spp",
            format!(
                "explaining pixel ({x}, {y}) would trace {n} samples ({} spp × {pixels} pixel(s) the filter reaches), more than the page explains ({MAX_EXPLAINED}); use rtlab explain --pixel {x},{y} --sample K for one of them",
                s.render.spp
            ),
        ));
    }
    Ok(())
}

/// `GET /api/diagram.png?x=X&y=Y[&sample=I][&plane=camera|bounce][&highlight=K]&<render
/// options>`: the figure of `rtlab explain --diagram` for the I-th of the samples the pixel's
/// explanation lists (else its own first), ray K (preorder, 0-based) in bold.
pub(super) async fn diagram(axum::extract::State(state): St, RawQuery(raw): RawQuery) -> Response {
    let q = match query(&raw, &["x", "y", "plane", "highlight", "sample"]) {
        Ok(q) => q,
        Err(r) => return r,
    };
    run(state, move |st| {
        let plane_name = q.own.get("plane").map_or("camera", String::as_str);
        let plane = crate::viz::slice::SlicePlane::parse(plane_name).ok_or_else(|| {
            Error::arg(
                "--diagram-plane",
                format!("unknown plane \"{plane_name}\" (expected camera or bounce)"),
            )
        })?;
        let highlight = match q.own.contains_key("highlight") {
            true => Some(q.number("highlight", "highlight=0")? as usize),
            false => None,
        };
        let s = st.scene(&q.words)?;
        let (x, y) = q.pixel(s.camera.width, s.camera.height)?;
        let e = explained(&s, x, y)?;
        // `sample=i`: the i-th of the samples the pixel is made of, in `/api/explain`'s order
        // (the page's selected row; a neighbour's under a wide filter); else its own first.
        let chosen = match q.own.contains_key("sample") {
            true => {
                let i = q.number("sample", "sample=0")? as usize;
                let n = e.samples.len();
                Some(e.samples.get(i).ok_or_else(|| {
                    Error::arg(
                        "sample",
                        format!(
                            "sample {i} does not exist (pixel ({x}, {y}) is made of {n} sample(s), 0..{})",
                            n.saturating_sub(1)
                        ),
                    )
                })?)
            }
            false => e.samples.iter().find(|k| k.pixel == [x, y]),
        };
        let Some(sample) = chosen else {
            return Err(Error::arg(
                "x/y",
                format!(
                    "{}: no ray to draw; pick a traced pixel",
                    crate::report::explain::not_traced(x, y)
                ),
            )
            .into());
        };
        let rays = crate::viz::slice::event_count(&sample.ray);
        if let Some(k) = highlight.filter(|&k| k >= rays) {
            return Err(Error::arg(
                "highlight",
                format!(
                    "ray {k} does not exist (pixel ({x}, {y})'s tree has {rays}, 0..{})",
                    rays - 1
                ),
            )
            .into());
        }
        let opts = crate::viz::slice::SliceOptions {
            plane,
            caption: Some(format!(
                "pixel ({}, {}), sample {}",
                sample.pixel[0], sample.pixel[1], sample.index
            )),
            highlight,
            ..Default::default()
        };
        let canvas = crate::viz::slice::draw(&s, &sample.ray, &opts)?;
        Ok(("image/png", canvas.png_bytes()?))
    })
    .await
}

/// The most samples the bundle figure may plan: it draws one bundle, but plans the pixel's
/// whole 16×16 tile as the render does ([`crate::sampling::bundles::bundle_of`]), 16 bytes a
/// sample (a 16×16 tile at 4,096 spp).
pub const MAX_BUNDLE_PLAN: u64 = 1 << 20;

/// `GET /api/bundle.png?x=X&y=Y[&index=K]&<render options>`: the figure of `rtlab explain
/// --bundle-diagram` (`--sample K`, else 0): the bundle of camera rays in which the render
/// traces sample K of pixel (x, y), over the first mesh's BVH. Refused, with the CLI's
/// message, where the render traces no bundle, the scene has no mesh or the pixel has no
/// sample K; and where the pixel's tile would plan more than [`MAX_BUNDLE_PLAN`] samples.
pub(super) async fn bundle(axum::extract::State(state): St, RawQuery(raw): RawQuery) -> Response {
    let q = match query(&raw, &["x", "y", "index"]) {
        Ok(q) => q,
        Err(r) => return r,
    };
    run(state, move |st| {
        let asked = q.own.contains_key("index");
        let k = if asked {
            q.number("index", "index=0")?
        } else {
            0
        };
        let s = st.scene(&q.words)?;
        let (x, y) = q.pixel(s.camera.width, s.camera.height)?;
        // As `explain --sample K` checks it, when asked: against the samples the sampler plans
        // for the pixel, or, under the adaptive sampler, which decides while it traces, those
        // the pixel's explanation traced (bounded as `/api/explain` is). A pixel too big to
        // explain skips the check: the figure refuses the adaptive sampler whatever the sample.
        if asked {
            let traced = match s.render.sampler {
                crate::scene::SamplerKind::Adaptive => {
                    explained(&s, x, y).ok().map(|e| e.own_samples())
                }
                _ => Some(0),
            };
            if let Some(traced) = traced {
                crate::report::explain::check_sample(&s, (x, y), k, traced)
                    .map_err(|m| Error::arg("--sample", m))?;
            }
        }
        let canvas = crate::viz::bundle::draw_within(&s, x, y, k, MAX_BUNDLE_PLAN)
            .map_err(|m| Error::arg("--bundle-diagram", m))?;
        Ok(("image/png", canvas.png_bytes()?))
    })
    .await
}
