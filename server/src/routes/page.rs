//! [`Page`]: the web page (`web/dist/`, built by `build.rs`), embedded in the binary so it
//! runs from any directory, served at `/` and its asset paths. Only embedded files are
//! served: a path is a key into the embedded set, never a file-system path. The page's
//! files carry a Content-Security-Policy: scripts, styles and connections only from this
//! origin, no framing by other sites.
//!
//! Caching: the script and the style sheet are named by their content (`app-<hash>.js`), so a
//! browser keeps them for a year (`immutable`); `index.html`, which names them, is checked on
//! every load (`no-cache`) against its ETag (its content's hash), a 304 when unchanged. The
//! router compresses the files (gzip, [`app`](crate::app)). Source maps are served by a debug
//! build only (a release build's page is built without them).

use crate::error::AppError;
use axum::http::{HeaderMap, HeaderValue, Method, StatusCode, Uri, header};
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

/// How long a browser keeps a file named by its content: a year, never revalidated.
pub const IMMUTABLE: &str = "public, max-age=31536000, immutable";

/// Serves an embedded file (`/` is `index.html`), a 304 where the client's copy is current,
/// or a 404 JSON error.
pub async fn page(method: Method, uri: Uri, request: HeaderMap) -> Response {
    if method != Method::GET && method != Method::HEAD {
        return AppError::not_found(uri.path()).into_response();
    }
    let path = uri.path().trim_start_matches('/');
    let path = if path.is_empty() { "index.html" } else { path };
    if cfg!(not(debug_assertions)) && path.ends_with(".map") {
        return AppError::not_found(uri.path()).into_response();
    }
    let Some(file) = Page::get(path) else {
        return AppError::not_found(uri.path()).into_response();
    };
    let hash = file.metadata.sha256_hash();
    let etag = format!("\"{}\"", hash[..12].iter().map(|b| format!("{b:02x}")).collect::<String>());
    let etag = HeaderValue::from_str(&etag).unwrap_or(HeaderValue::from_static("\"nhlab\""));
    let cache = HeaderValue::from_static(if content_named(path) { IMMUTABLE } else { "no-cache" });
    let current = request.get_all(header::IF_NONE_MATCH).iter().filter_map(|v| v.to_str().ok());
    if current.flat_map(|v| v.split(',')).any(|tag| {
        let tag = tag.trim();
        tag == "*" || tag.trim_start_matches("W/") == etag
    }) {
        let headers = [(header::ETAG, etag), (header::CACHE_CONTROL, cache)];
        return (StatusCode::NOT_MODIFIED, headers).into_response();
    }
    let mime = content_type(path, file.metadata.mimetype());
    let mime = HeaderValue::from_str(&mime)
        .unwrap_or(HeaderValue::from_static("application/octet-stream"));
    let headers = [
        (header::CONTENT_TYPE, mime),
        (header::CACHE_CONTROL, cache),
        (header::ETAG, etag),
        (header::CONTENT_SECURITY_POLICY, HeaderValue::from_static(CSP)),
        (header::REFERRER_POLICY, HeaderValue::from_static("no-referrer")),
    ];
    (StatusCode::OK, headers, file.data).into_response()
}

/// Whether a file is named by its content (`app-6ULMKYOM.js`: esbuild's eight-character hash
/// before the extension), so that a new build has new names.
fn content_named(path: &str) -> bool {
    let stem = path.rsplit_once('.').map_or(path, |(stem, _)| stem);
    stem.rsplit_once('-').is_some_and(|(_, hash)| {
        hash.len() == 8 && hash.bytes().all(|b| b.is_ascii_uppercase() || b.is_ascii_digit())
    })
}

/// The guessed type, with source maps as JSON and text in UTF-8 (the page's encoding).
fn content_type(path: &str, guessed: &str) -> String {
    let mime = if path.ends_with(".map") { "application/json" } else { guessed };
    let text = mime.starts_with("text/") || mime.ends_with("javascript") || mime.ends_with("json");
    if text { format!("{mime}; charset=utf-8") } else { mime.to_owned() }
}
