//! The API's handlers. Each parses its query ([`super::params`]), then does its work on a
//! blocking thread (at most [`State::jobs`] at once), and answers with the bytes the CLI
//! would write, or with the CLI's one-line message: 400 for a bad parameter, 422 for a scene
//! that does not load, 409 for a render a newer one superseded, 500 if anything panicked.

use super::params::{self, Params};
use super::state::{Frames, State};
use crate::error::Error;
use crate::sampling::aov::{render_aov, Aov};
use crate::scene::Scene;
use axum::body::Body;
use axum::extract::{RawQuery, Request};
use axum::http::{header, StatusCode};
use axum::response::sse::{Event, KeepAlive, Sse};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::Router;
use std::sync::Arc;

pub(super) type St = axum::extract::State<Arc<State>>;

/// What a handler's work produced: (content type, bytes) or an answer with a status.
pub(super) type Answer = std::result::Result<(&'static str, Vec<u8>), Fail>;

pub enum Fail {
    Error(Error),
    Status(StatusCode, String),
}

impl From<Error> for Fail {
    fn from(e: Error) -> Fail {
        Fail::Error(e)
    }
}

pub fn router(state: Arc<State>) -> Router {
    Router::new()
        .route("/api/scene", get(scene))
        .route("/api/options", get(options))
        .route("/api/status", get(status))
        .route("/api/explain", get(explain))
        .route("/api/diagram.png", get(diagram))
        .route("/api/render.png", get(render))
        .route("/api/steps", get(steps))
        .route("/api/steps/frame.png", get(step_frame))
        .route("/api/events", get(events))
        .route(
            "/api/diff",
            axum::routing::post(super::diff::diff)
                .fallback(super::security::not_post)
                .layer(axum::extract::DefaultBodyLimit::max(
                    super::diff::MAX_UPLOAD,
                )),
        )
        .fallback(asset)
        .layer(axum::middleware::from_fn_with_state(
            state.clone(),
            super::security::guard,
        ))
        .with_state(state)
}

async fn asset(req: Request<Body>) -> Response {
    match super::assets::get(req.uri().path()) {
        Some((kind, body)) => ([(header::CONTENT_TYPE, kind)], body).into_response(),
        None => super::security::refuse(StatusCode::NOT_FOUND, "no such page"),
    }
}

/// Runs `work` on a blocking thread and turns its result into a response. The work keeps
/// its slot among [`State::jobs`] until it ends, even when the client has gone away (a render
/// then stops early: its token is cancelled when the request is dropped, [`Running`]).
pub(super) async fn run<F>(state: Arc<State>, work: F) -> Response
where
    F: FnOnce(&State) -> Answer + Send + 'static,
{
    let Ok(permit) = state.jobs.clone().acquire_owned().await else {
        return super::security::refuse(StatusCode::SERVICE_UNAVAILABLE, "shutting down");
    };
    let st = state.clone();
    let work = move || {
        let _permit = permit;
        work(&st)
    };
    match tokio::task::spawn_blocking(work).await {
        Ok(answer) => respond(answer),
        Err(_) => super::security::refuse(
            StatusCode::INTERNAL_SERVER_ERROR,
            "the request failed unexpectedly (a bug in rtlab)",
        ),
    }
}

/// The response for a handler's answer.
fn respond(answer: Answer) -> Response {
    match answer {
        Ok((kind, bytes)) => (
            [
                (header::CONTENT_TYPE, kind),
                (header::CACHE_CONTROL, "no-store"),
            ],
            bytes,
        )
            .into_response(),
        Err(Fail::Status(code, msg)) => super::security::refuse(code, &msg),
        Err(Fail::Error(e)) => {
            let code = match e {
                Error::Input { .. } | Error::Io { .. } => StatusCode::UNPROCESSABLE_ENTITY,
                _ => StatusCode::BAD_REQUEST,
            };
            super::security::refuse(code, &e.to_string())
        }
    }
}

/// A render in progress: released ([`State::release`]) when its request ends, answered or
/// dropped because the client went away, so an abandoned render stops instead of running on.
pub(super) struct Running {
    state: Arc<State>,
    stream: Option<String>,
    token: crate::interrupt::Cancel,
}

impl Running {
    /// A request's work on no stream (nothing supersedes it), stopped when its client goes:
    /// its token, and the guard that cancels it when the request is dropped.
    pub(super) fn alone(state: &Arc<State>) -> (crate::interrupt::Cancel, Running) {
        let token = state.supersede(None);
        let running = Running {
            state: state.clone(),
            stream: None,
            token: token.clone(),
        };
        (token, running)
    }
}

/// A copy of `scene` whose renders stop when `cancel` is cancelled (or the scene's own token).
pub(super) fn watched(scene: &Scene, cancel: &crate::interrupt::Cancel) -> Scene {
    let mut s = scene.clone();
    s.render.cancel = s.render.cancel.or(cancel);
    s
}

impl Drop for Running {
    fn drop(&mut self) {
        self.state.release(self.stream.as_deref(), &self.token);
    }
}

/// Parses the query, answering 400 on a bad one.
// The error is the response itself, handed straight back to axum: boxing it buys nothing.
#[allow(clippy::result_large_err)]
pub(super) fn query(raw: &Option<String>, own: &[&str]) -> std::result::Result<Params, Response> {
    params::parse(raw.as_deref(), own)
        .map_err(|e| super::security::refuse(StatusCode::BAD_REQUEST, &e.to_string()))
}

fn json(v: &impl serde::Serialize) -> Answer {
    Ok((
        "application/json",
        (serde_json::to_string_pretty(v).expect("serialisable") + "\n").into_bytes(),
    ))
}

fn png(img: &image::RgbImage) -> Answer {
    crate::output::png_bytes(img)
        .map(|b| ("image/png", b))
        .map_err(|m| Fail::Status(StatusCode::INTERNAL_SERVER_ERROR, m))
}

fn lower_debug(v: impl std::fmt::Debug) -> String {
    let s = format!("{v:?}");
    let word: String = s.chars().take_while(|c| c.is_alphanumeric()).collect();
    word.to_ascii_lowercase()
}

/// `GET /api/scene`: the objects, lights, materials and size of the scene (with options).
async fn scene(axum::extract::State(state): St, RawQuery(raw): RawQuery) -> Response {
    let q = match query(&raw, &[]) {
        Ok(q) => q,
        Err(r) => return r,
    };
    run(state, move |st| {
        let s = st.scene(&q.words)?;
        json(&describe(&s))
    })
    .await
}

fn describe(s: &Scene) -> serde_json::Value {
    let r = &s.render;
    serde_json::json!({
        "file": s.path.display().to_string(),
        "format": lower_debug(s.format),
        "width": s.camera.width,
        "height": s.camera.height,
        "objects": s.objects.iter().map(|o| serde_json::json!({
            "name": o.name,
            "shape": lower_debug(&o.shape),
            "material": s.materials.get(o.material).map(|m| m.name.clone()),
        })).collect::<Vec<_>>(),
        "lights": s.lights.iter().map(|l| serde_json::json!({
            "name": l.name,
            "kind": lower_debug(&l.kind),
            "color": l.color,
            "attenuation": l.attenuation,
        })).collect::<Vec<_>>(),
        "materials": s.materials.iter().map(|m| serde_json::json!({
            "name": m.name,
            "ambient": m.ambient,
            "diffuse": m.diffuse,
            "specular": m.specular,
            "shininess": m.shininess,
            "reflective": m.reflective,
            "transparent": m.transparent,
            "ior": m.ior,
            "textured": m.texture.is_some(),
        })).collect::<Vec<_>>(),
        "ambient_light": s.ambient_light,
        "render": {
            "spp": r.spp,
            "sampler": lower_debug(r.sampler),
            "filter": lower_debug(r.filter),
            "max_depth": r.max_depth,
            "shadows": r.shadows,
            "reflections": r.reflections,
            "refractions": r.refractions,
            "textures": r.textures,
            "subsample": r.subsample,
            "encoding": lower_debug(r.encoding),
        },
    })
}

/// `GET /api/options`: the render options the page offers as controls, and the AOV names.
async fn options(axum::extract::State(state): St) -> Response {
    // Light work: answered at once, never queued behind renders.
    respond(json(
        &serde_json::json!({"render": state.options, "aov": Aov::names()}),
    ))
}

/// `GET /api/status`: the live scene's version and error.
async fn status(axum::extract::State(state): St) -> Response {
    respond(json(&state.status()))
}

/// `GET /api/explain?x=X&y=Y&<render options>`: `rtlab explain --format json`.
async fn explain(axum::extract::State(state): St, RawQuery(raw): RawQuery) -> Response {
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
async fn diagram(axum::extract::State(state): St, RawQuery(raw): RawQuery) -> Response {
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

/// The longest stream name a render may give (the page's are a few characters).
const MAX_STREAM: usize = 64;

/// `GET /api/render.png?[aov=NAME][&pass=K][&stream=ID]&<render options>`: the bytes
/// `rtlab render` (with `--aov NAME`, `--passes K`) writes: pass K of the progressive
/// render (1: the preview, 2: the scene's own settings, more: more samples per pixel), the
/// page's preview and refinements. A newer render on the same stream cancels this one (409).
async fn render(axum::extract::State(state): St, RawQuery(raw): RawQuery) -> Response {
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

/// A render stopped by its token: a newer one on its stream took over (or its client left,
/// and nobody reads the answer).
pub(super) fn superseded() -> Fail {
    Fail::Status(
        StatusCode::CONFLICT,
        "superseded by a newer render on the same stream".into(),
    )
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

/// The steps frames of the scene with these options (rendered once, then kept).
fn frames(
    st: &State,
    q: &Params,
    cancel: &crate::interrupt::Cancel,
) -> std::result::Result<Frames, Fail> {
    let s = st.scene(&q.words)?;
    if let Some((scene, f)) = super::state::lock(&st.steps).as_ref() {
        if Arc::ptr_eq(scene, &s) {
            return Ok(f.clone());
        }
    }
    // The frames render a copy whose settings watch the request's token (the cached scene
    // is shared), so they stop within a few rays once the client has gone.
    let watched = watched(&s, cancel);
    let (plan, mut skipped) = crate::viz::steps::plan(&watched);
    let (w, h, spp) = (s.camera.width, s.camera.height, s.render.spp);
    super::state::check_count(
        w as u64 * h as u64 * spp as u64 * plan.len() as u64,
        "--width/--height/--spp",
        &format!("{} frames of {w}×{h} pixels × {spp} spp", plan.len()),
        "rtlab steps",
    )?;
    let frames = crate::viz::steps::render_frames(&watched, &plan, &mut skipped);
    if cancel.is_cancelled() {
        return Err(superseded()); // half-made frames: never kept
    }
    let n = frames.len();
    let mut out = Vec::with_capacity(n);
    for (i, f) in frames.iter().enumerate() {
        let img = crate::viz::steps::captioned(f, i + 1, n);
        let bytes = crate::output::png_bytes(&img)
            .map_err(|m| Fail::Status(StatusCode::INTERNAL_SERVER_ERROR, m))?;
        out.push((f.caption.clone(), bytes));
    }
    let out = Arc::new(out);
    *super::state::lock(&st.steps) = Some((s, out.clone()));
    Ok(out)
}

/// `GET /api/steps?<render options>`: the captions of `rtlab steps`' frames, in order.
async fn steps(axum::extract::State(state): St, RawQuery(raw): RawQuery) -> Response {
    let q = match query(&raw, &[]) {
        Ok(q) => q,
        Err(r) => return r,
    };
    let (cancel, _running) = Running::alone(&state);
    run(state, move |st| {
        let f = frames(st, &q, &cancel)?;
        let list: Vec<_> = f
            .iter()
            .enumerate()
            .map(|(i, (c, _))| serde_json::json!({"index": i, "caption": c}))
            .collect();
        json(&list)
    })
    .await
}

/// `GET /api/steps/frame.png?i=K&<render options>`: frame K of `rtlab steps`, captioned.
async fn step_frame(axum::extract::State(state): St, RawQuery(raw): RawQuery) -> Response {
    let q = match query(&raw, &["i"]) {
        Ok(q) => q,
        Err(r) => return r,
    };
    let (cancel, _running) = Running::alone(&state);
    run(state, move |st| {
        let i = q.number("i", "i=0")? as usize;
        let f = frames(st, &q, &cancel)?;
        match f.get(i) {
            Some((_, png)) => Ok(("image/png", png.clone())),
            None => Err(Error::arg(
                "i",
                format!("frame {i} does not exist (there are {})", f.len()),
            )
            .into()),
        }
    })
    .await
}

/// `GET /api/events`: server-sent events; `scene` with `{"version", "error"}` when the scene
/// file changes (and once on connecting).
async fn events(axum::extract::State(state): St) -> Response {
    use tokio_stream::StreamExt;
    let first = serde_json::to_string(&state.status()).unwrap_or_default();
    let rx = tokio_stream::wrappers::BroadcastStream::new(state.events.subscribe());
    let stream = tokio_stream::once(first)
        .chain(rx.filter_map(|r| r.ok()))
        .map(|s| Ok::<_, std::convert::Infallible>(Event::default().event("scene").data(s)));
    Sse::new(stream)
        .keep_alive(KeepAlive::default())
        .into_response()
}
