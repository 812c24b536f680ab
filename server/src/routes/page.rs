//! [`Page`]: the web page (`web/dist/`, built by `build.rs`), embedded in the binary so it
//! runs from any directory, served at `/` and its asset paths. Only embedded files are
//! served: a path is a key into the embedded set, never a file-system path. The page's
//! files carry a Content-Security-Policy: scripts, styles and connections only from this
//! origin, no framing by other sites.

use crate::error::AppError;
use axum::http::{HeaderValue, Method, StatusCode, Uri, header};
use axum::response::{IntoResponse, Response};
use rust_embed::Embed;

/// The files of `web/dist/`.
#[derive(Embed)]
#[folder = "../web/dist/"]
pub struct Page;

/// The page's policy: its own scripts and styles (uPlot sets inline styles on its elements),
/// its own API, images from itself or `data:`/`blob:` URLs (the icon, exported plots).
pub const CSP: &str = "default-src 'self'; script-src 'self'; style-src 'self' 'unsafe-inline'; \
    img-src 'self' data: blob:; connect-src 'self'; object-src 'none'; base-uri 'none'; \
    form-action 'self'; frame-ancestors 'none'";

/// Serves an embedded file (`/` is `index.html`), or a 404 JSON error.
pub async fn page(method: Method, uri: Uri) -> Response {
    if method != Method::GET && method != Method::HEAD {
        return AppError::not_found(uri.path()).into_response();
    }
    let path = uri.path().trim_start_matches('/');
    let path = if path.is_empty() { "index.html" } else { path };
    let Some(file) = Page::get(path) else {
        return AppError::not_found(uri.path()).into_response();
    };
    let mime = content_type(path, file.metadata.mimetype());
    let mime = HeaderValue::from_str(&mime)
        .unwrap_or(HeaderValue::from_static("application/octet-stream"));
    let headers = [
        (header::CONTENT_TYPE, mime),
        (header::CACHE_CONTROL, HeaderValue::from_static("no-cache")),
        (header::CONTENT_SECURITY_POLICY, HeaderValue::from_static(CSP)),
        (header::REFERRER_POLICY, HeaderValue::from_static("no-referrer")),
    ];
    (StatusCode::OK, headers, file.data).into_response()
}

/// The guessed type, with source maps as JSON and text in UTF-8 (the page's encoding).
fn content_type(path: &str, guessed: &str) -> String {
    let mime = if path.ends_with(".map") { "application/json" } else { guessed };
    let text = mime.starts_with("text/") || mime.ends_with("javascript") || mime.ends_with("json");
    if text { format!("{mime}; charset=utf-8") } else { mime.to_owned() }
}
