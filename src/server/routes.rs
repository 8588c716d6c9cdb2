//! The API's handlers. Each parses its query ([`super::params`]), then does its work on a
//! blocking thread (at most [`State::jobs`] at once), and answers with the bytes the CLI
//! would write, or with the CLI's one-line message: 400 for a bad parameter, 422 for a scene
//! that does not load, 409 for a render a newer one superseded, 500 if anything panicked.

use super::params::{self, Params};
use super::state::{Frames, State};
use crate::error::Error;
use crate::sampling::aov::Aov;
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
        .route("/api/explain", get(super::explain::explain))
        .route("/api/diagram.png", get(super::explain::diagram))
        .route("/api/bundle.png", get(super::explain::bundle))
        .route("/api/render.png", get(super::render::render))
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
    match blocking(work).await {
        Ok(answer) => respond(Ok(answer)),
        Err(refused) => refused,
    }
}

/// Runs `work` on a blocking thread, outside the work slots: its value, or the response
/// to give when it failed (its own answer, or a 500 if it panicked).
pub(super) async fn blocking<T, F>(work: F) -> std::result::Result<T, Response>
where
    T: Send + 'static,
    F: FnOnce() -> std::result::Result<T, Fail> + Send + 'static,
{
    match tokio::task::spawn_blocking(work).await {
        Ok(Ok(value)) => Ok(value),
        Ok(Err(fail)) => Err(respond(Err(fail))),
        Err(_) => Err(super::security::refuse(
            StatusCode::INTERNAL_SERVER_ERROR,
            "the request failed unexpectedly (a bug in rtlab)",
        )),
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
    pub(super) state: Arc<State>,
    pub(super) stream: Option<String>,
    pub(super) token: crate::interrupt::Cancel,
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

/// A render stopped by its token: a newer one on its stream took over (or its client left,
/// and nobody reads the answer).
pub(super) fn superseded() -> Fail {
    Fail::Status(
        StatusCode::CONFLICT,
        "superseded by a newer render on the same stream".into(),
    )
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

pub(super) fn png(img: &image::RgbImage) -> Answer {
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
    let (w, h) = (s.camera.width, s.camera.height);
    super::state::check_count(
        super::state::samples(w, h, &s.render) * plan.len() as u64,
        "--width/--height/--spp",
        &format!(
            "{} frames of {}",
            plan.len(),
            super::state::render_words(w, h, &s.render)
        ),
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
