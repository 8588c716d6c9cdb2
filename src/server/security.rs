//! The guards of a local server: only GET (and HEAD), only to a `Host` this server is
//! (a page on another site that rebinds its name to 127.0.0.1 sends its own name: refused),
//! and short request targets. Requests have no body the server reads.

use super::state::State;
use axum::body::Body;
use axum::extract::Request;
use axum::http::{header, Method, StatusCode};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use std::sync::Arc;

/// Longest request target (path and query) accepted.
pub const MAX_TARGET: usize = 8192;

pub async fn guard(
    axum::extract::State(state): axum::extract::State<Arc<State>>,
    req: Request<Body>,
    next: Next,
) -> Response {
    let host = req
        .headers()
        .get(header::HOST)
        .and_then(|h| h.to_str().ok())
        .map(str::to_ascii_lowercase);
    match host {
        None => return refuse(StatusCode::BAD_REQUEST, "a Host header is required"),
        Some(h) if !state.allowed_hosts.contains(&h) => {
            return refuse(
                StatusCode::FORBIDDEN,
                &format!(
                    "Host \"{h}\" is not this server (DNS rebinding guard); use {}",
                    state.allowed_hosts[0]
                ),
            )
        }
        _ => {}
    }
    let upload = req.method() == Method::POST && req.uri().path() == "/api/diff";
    if req.method() != Method::GET && req.method() != Method::HEAD && !upload {
        return refuse(
            StatusCode::METHOD_NOT_ALLOWED,
            "only GET requests (and POST /api/diff with a PNG)",
        );
    }
    if req.uri().to_string().len() > MAX_TARGET {
        return refuse(StatusCode::URI_TOO_LONG, "the request target is too long");
    }
    next.run(req).await
}

pub fn refuse(status: StatusCode, msg: &str) -> Response {
    (
        status,
        [(header::CONTENT_TYPE, "text/plain; charset=utf-8")],
        format!("error: {msg}\n"),
    )
        .into_response()
}
