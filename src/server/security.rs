//! The guards of a local server: only GET (and HEAD), only to a `Host` this server is
//! (a page on another site that rebinds its name to 127.0.0.1 sends its own name: refused),
//! not from pages of other sites (`Sec-Fetch-Site: cross-site`, a foreign `Origin`), and
//! short request targets. The one body the server reads is `POST /api/diff`'s PNG.

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
    let mut hosts = req.headers().get_all(header::HOST).iter();
    let (first, second) = (hosts.next(), hosts.next());
    if second.is_some() {
        return refuse(StatusCode::BAD_REQUEST, "more than one Host header");
    }
    let host = match first.map(|h| h.to_str()) {
        None => return refuse(StatusCode::BAD_REQUEST, "a Host header is required"),
        Some(Err(_)) => return refuse(StatusCode::BAD_REQUEST, "the Host header is not valid"),
        Some(Ok(h)) => h.to_ascii_lowercase(),
    };
    if !state.allowed_hosts.contains(&host) {
        return refuse(
            StatusCode::FORBIDDEN,
            &format!(
                "Host \"{host}\" is not this server (DNS rebinding guard); use {}",
                state.allowed_hosts[0]
            ),
        );
    }
    // A page of another site may make the browser send requests here (it cannot read the
    // answers, but it could start renders): browsers say so, in Sec-Fetch-Site and Origin.
    let cross_site = req
        .headers()
        .get("sec-fetch-site")
        .is_some_and(|v| v.as_bytes().eq_ignore_ascii_case(b"cross-site"));
    let foreign_origin = req.headers().get(header::ORIGIN).is_some_and(|o| {
        let own = o
            .to_str()
            .ok()
            .and_then(|o| o.strip_prefix("http://"))
            .map(str::to_ascii_lowercase);
        !own.is_some_and(|o| state.allowed_hosts.contains(&o))
    });
    if cross_site || foreign_origin {
        return refuse(
            StatusCode::FORBIDDEN,
            "requests from pages of other sites are refused; open the lab at its own address",
        );
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

/// The one-line answer of a refused request: `error: ` and the message, its control
/// characters escaped (a value echoed back may hold a newline or a terminal's escape codes).
pub fn refuse(status: StatusCode, msg: &str) -> Response {
    (
        status,
        [(header::CONTENT_TYPE, "text/plain; charset=utf-8")],
        format!("error: {}\n", crate::error::printable(msg)),
    )
        .into_response()
}

/// `/api/diff` asked for with a method other than POST.
pub async fn not_post() -> Response {
    refuse(
        StatusCode::METHOD_NOT_ALLOWED,
        "only GET requests (and POST /api/diff with a PNG)",
    )
}
