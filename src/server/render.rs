//! `GET /api/render.png`: the image `rtlab render` writes (a progressive pass, an AOV), on a
//! stream a newer render supersedes.

use super::params::Params;
use super::routes::{blocking, png, query, run, superseded, Fail, Running, St};
use super::state::State;
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
    // A request refused for its parameters supersedes nothing: the scene is loaded and the
    // pass and AOV checked first (on a blocking thread, outside the work slots, so that a
    // newer render never waits for a slot its stream's older one holds).
    let (st, params) = (state.clone(), q);
    let checked = move || checking_pool().install(|| prepare(&st, &params));
    let job = match blocking(checked).await {
        Ok(job) => job,
        Err(refused) => return refused,
    };
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
    let mut response = run(state, move |_| {
        let add = |name, value| {
            headers_out
                .lock()
                .expect("the headers' lock")
                .push((name, value))
        };
        let Job {
            scene: s,
            mut settings,
            aov,
            pass_options,
        } = job;
        // Stopped within a few rays once superseded or abandoned (its client gone).
        settings.cancel = settings.cancel.or(&cancel);
        if let Some(options) = pass_options {
            add(PASS_OPTIONS, options);
        }
        if let Some(aov) = aov {
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

/// The threads a render request is checked on (its scene loaded, its BVHs built): not
/// rayon's global pool, which may be busy with the very render the request is about to
/// supersede (a load queued behind it waited for it to finish).
fn checking_pool() -> &'static rayon::ThreadPool {
    static POOL: std::sync::OnceLock<rayon::ThreadPool> = std::sync::OnceLock::new();
    POOL.get_or_init(|| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .thread_name(|i| format!("rtlab-check-{i}"))
            .build()
            .expect("a thread pool")
    })
}

/// A render request checked and ready: its scene, the settings of the pass asked for, the
/// AOV, and pass K's options for the header.
struct Job {
    scene: Arc<crate::scene::Scene>,
    settings: crate::scene::RenderSettings,
    aov: Option<Aov>,
    pass_options: Option<String>,
}

/// Everything a render request is refused for, checked before it supersedes anything: the
/// AOV's name, the pass and whether it exists and fits, the render options and the scene.
fn prepare(st: &State, q: &Params) -> std::result::Result<Job, Fail> {
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
    let (w, h) = (s.camera.width, s.camera.height);
    let settings = match pass {
        Some(k) => crate::sampling::progressive::pass_settings(&s.render, w, h, k)
            .map_err(|m| Fail::from(Error::arg("pass", m)))?,
        None => s.render.clone(),
    };
    if let Some(k) = pass {
        super::state::check_count(
            super::state::samples(w, h, &settings),
            "pass",
            &format!("pass {k}, {},", super::state::render_words(w, h, &settings)),
            &format!("rtlab render --passes {k}"),
        )?;
    }
    if aov.is_some() {
        crate::sampling::aov::check_memory(w, h, &settings)
            .map_err(|m| Fail::from(Error::arg("aov", m)))?;
    }
    Ok(Job {
        pass_options: pass.map(|_| pass_options(&s.render, &settings)),
        scene: s,
        settings,
        aov,
    })
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
