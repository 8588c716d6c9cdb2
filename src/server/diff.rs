//! `POST /api/diff?[tolerance=N][&max-percent=P][&format=json|png]&<render options>`: the
//! body is your PNG; the answer is exactly what `rtlab diff SCENE YOURS.png --format json`
//! prints for the same options (or, with `format=png`, its `-o` figure). The upload is read
//! from the request, never from a path, and is bounded by [`MAX_UPLOAD`].

use super::routes::{query, run, Answer, Fail, St};
use crate::diff::{self, report, Options};
use crate::error::Error;
use axum::body::Bytes;
use axum::extract::RawQuery;
use axum::http::StatusCode;
use axum::response::Response;
use std::path::Path;

/// The largest image a page may send (a 1024×768 PNG is at most about 2.4 MB).
pub const MAX_UPLOAD: usize = 16 << 20;

pub async fn diff(
    axum::extract::State(state): St,
    RawQuery(raw): RawQuery,
    body: Result<Bytes, axum::extract::rejection::BytesRejection>,
) -> Response {
    let body = match body {
        Ok(b) => b,
        Err(e) if e.status() == axum::http::StatusCode::PAYLOAD_TOO_LARGE => {
            return super::security::refuse(
                e.status(),
                &format!("the upload is larger than {} MiB", MAX_UPLOAD >> 20),
            )
        }
        Err(e) => return super::security::refuse(e.status(), &e.body_text()),
    };
    let q = match query(&raw, &["tolerance", "max-percent", "format"]) {
        Ok(q) => q,
        Err(r) => return r,
    };
    // Stopped within a few rays when the client goes (the mistake search renders a lot).
    let (cancel, _running) = super::routes::Running::alone(&state);
    run(state, move |st| -> Answer {
        let tolerance = match q.own.get("tolerance") {
            Some(_) => u8::try_from(q.number("tolerance", "tolerance=2")?).map_err(|_| {
                Error::arg("tolerance", "expected a number of levels from 0 to 255")
            })?,
            None => 2,
        };
        let max_percent = match q.own.get("max-percent") {
            Some(v) => v
                .parse::<f64>()
                .ok()
                .filter(|p| p.is_finite() && (0.0..=100.0).contains(p))
                .ok_or_else(|| {
                    Error::arg(
                        "max-percent",
                        format!("{v} is not a percentage (expected 0 to 100)"),
                    )
                })?,
            None => 1.0,
        };
        let format = q.own.get("format").map_or("json", String::as_str);
        if format != "json" && format != "png" {
            return Err(Error::arg(
                "format",
                format!("unknown format \"{format}\" (expected json or png)"),
            )
            .into());
        }
        let scene = super::routes::watched(&*st.scene(&q.words)?, &cancel);
        // A bad upload is a bad request (400), like an image of the wrong size, not a scene
        // that does not load (422).
        let yours = diff::png::decode(Path::new("your image"), &body)
            .map_err(|e| Fail::Status(StatusCode::BAD_REQUEST, e.to_string()))?;
        let out = crate::sampling::render(&scene, &scene.render, false, None);
        if out.cancelled {
            return Err(super::routes::superseded());
        }
        let expected = out.image.to_rgb8_for(&scene.render);
        let opts = Options {
            tolerance,
            max_percent,
            explain: format!(
                "rtlab explain {}",
                crate::report::shell_word(&st.scene_path.display().to_string())
            ),
            explain_flags: (st.flags)(&q.words)?,
            ..Options::default()
        };
        let rep = diff::diff(&scene, &expected, &yours, &opts)?;
        if cancel.is_cancelled() {
            return Err(super::routes::superseded());
        }
        if format == "png" {
            let fig = crate::viz::diff::figure(&scene, &expected, &yours, &rep);
            return Ok(("image/png", fig.png_bytes()?));
        }
        let text = serde_json::to_string_pretty(&report::to_json(&scene, &rep))
            .expect("serialisable")
            + "\n";
        Ok(("application/json", text.into_bytes()))
    })
    .await
}
