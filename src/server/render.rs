//! `GET /api/render.png`: the image `rtlab render` writes (a progressive pass, an AOV), on a
//! stream a newer render supersedes.

use super::routes::{png, query, respond, run, superseded, Fail, Running, St};
use crate::error::Error;
use crate::sampling::aov::{render_aov, Aov};
use axum::extract::RawQuery;
use axum::http::{header, StatusCode};
use axum::response::Response;
use std::sync::Arc;

/// The longest stream name a render may give (the page's are a few characters).
const MAX_STREAM: usize = 64;

/// `GET /api/render.png?[aov=NAME][&pass=K][&stream=ID]&<render options>`: the bytes
/// `rtlab render` (with `--aov NAME`, `--passes K`) writes: pass K of the progressive
/// render (1: the preview, 2: the scene's own settings, more: more samples per pixel), the
/// page's preview and refinements. A newer render on the same stream cancels this one (409).
pub(super) async fn render(axum::extract::State(state): St, RawQuery(raw): RawQuery) -> Response {
    let q = match query(&raw, &["aov", "pass", "stream"]) {
        Ok(q) => q,
        Err(r) => return r,
    };
    let stream = q.own.get("stream").cloned();
    if let Some(id) = stream.as_ref().filter(|id| id.len() > MAX_STREAM) {
        return super::security::refuse(
            StatusCode::BAD_REQUEST,
            &format!(
                "argument stream: {} characters is too long (at most {MAX_STREAM})",
                id.chars().count()
            ),
        );
    }
    // A request refused for its parameters supersedes nothing: they are checked first.
    let checked = (|| -> std::result::Result<(), Error> {
        if let Some(a) = q.own.get("aov") {
            Aov::parse_arg(a)?;
        }
        if let Some(p) = q.own.get("pass") {
            crate::sampling::progressive::parse_pass(p).map_err(|m| Error::arg("pass", m))?;
        }
        (state.flags)(&q.words).map(|_| ())
    })();
    if let Err(e) = checked {
        return respond(Err(e.into()));
    }
    let cancel = state.supersede(stream.as_deref());
    let _running = Running {
        state: state.clone(),
        stream,
        token: cancel.clone(),
    };
    // Headers beside the image: an AOV's legend (how to read its colours, with the ranges
    // used: what `rtlab render --aov` prints on stderr), and pass K's settings as the options
    // that give them (for the page to explain the pixels of the image it shows).
    let headers = Arc::new(std::sync::Mutex::new(Vec::<(&'static str, String)>::new()));
    let headers_out = headers.clone();
    let mut response = run(state, move |st| {
        let add = |name, value| {
            headers_out
                .lock()
                .expect("the headers' lock")
                .push((name, value))
        };
        let aov = q.own.get("aov").map(|a| Aov::parse_arg(a)).transpose()?;
        let pass = q
            .own
            .get("pass")
            .map(|p| {
                crate::sampling::progressive::parse_pass(p)
                    .map_err(|m| Fail::from(Error::arg("pass", m)))
            })
            .transpose()?;
        let s = st.scene(&q.words)?;
        let mut settings = match pass {
            Some(k) => crate::sampling::progressive::pass_settings(
                &s.render,
                s.camera.width,
                s.camera.height,
                k,
            )
            .map_err(|m| Fail::from(Error::arg("pass", m)))?,
            None => s.render.clone(),
        };
        // Stopped within a few rays once superseded or abandoned (its client gone).
        settings.cancel = settings.cancel.or(&cancel);
        if let Some(k) = pass {
            add(PASS_OPTIONS, pass_options(&s.render, &settings));
            let (w, h) = (s.camera.width, s.camera.height);
            super::state::check_count(
                w as u64 * h as u64 * settings.spp as u64,
                "pass",
                &format!("pass {k}, {w}×{h} pixels × {} spp,", settings.spp),
                &format!("rtlab render --passes {k}"),
            )?;
        }
        if let Some(aov) = aov {
            crate::sampling::aov::check_memory(s.camera.width, s.camera.height, &settings)
                .map_err(|m| Fail::from(Error::arg("aov", m)))?;
            let made = render_aov(&s, &settings, aov).ok_or_else(superseded)?;
            add(AOV_LEGEND, made.legend);
            return png(&made.image);
        }
        let out = crate::sampling::render(&s, &settings, false, None);
        if out.cancelled {
            return Err(superseded());
        }
        // The bytes as the CLI writes them: the encoding, and the mistakes made in the bytes.
        png(&out.image.to_rgb8_for(&settings))
    })
    .await;
    if response.status().is_success() {
        for (name, text) in super::state::lock(&headers).drain(..) {
            // Form-encoded: a header is ASCII, and a legend has arrows and middle dots.
            let encoded: String = form_urlencoded::byte_serialize(text.as_bytes()).collect();
            if let Ok(value) = header::HeaderValue::from_str(&encoded) {
                response.headers_mut().insert(name, value);
            }
        }
    }
    response
}

/// The header of an AOV's legend on `/api/render.png?aov=NAME` (form-encoded UTF-8).
pub(super) const AOV_LEGEND: &str = "x-rtlab-aov-legend";

/// The header of `/api/render.png?pass=K`: the render options that give pass K's settings
/// (form-encoded, e.g. `subsample=4` or `sampler=grid&spp=16`; empty for pass 2), so that
/// `/api/explain` with them explains the pixels of that image, as `rtlab explain` with the
/// same options does.
pub(super) const PASS_OPTIONS: &str = "x-rtlab-pass-options";

/// The options that turn `base` into `pass` (what [`crate::sampling::progressive::pass_settings`]
/// changes: the subsample, the sampler and its samples per pixel).
fn pass_options(
    base: &crate::scene::RenderSettings,
    pass: &crate::scene::RenderSettings,
) -> String {
    let mut o = Vec::new();
    if pass.subsample != base.subsample {
        o.push(format!("subsample={}", pass.subsample));
    }
    if pass.sampler != base.sampler {
        o.push(format!("sampler={}", pass.sampler.name()));
    }
    if pass.spp != base.spp {
        o.push(format!("spp={}", pass.spp));
    }
    o.join("&")
}
