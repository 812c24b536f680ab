//! [`JsonObject`]: the extractor of every request body the API reads. It reads the body
//! within the size limit (`max_body_bytes`, set on the router by `DefaultBodyLimit`), refuses
//! anything but one JSON object, and reads the object with `serde_path_to_error`, so that a
//! wrong type or an unknown field is reported with its path. Its rejection is the API's
//! [`AppError`]: 413 for an oversized body (naming the limit), 400 for a body that is not one
//! JSON object of the right shape. The body must come with a JSON `Content-Type`
//! (`application/json` or `application/…+json`), else 415: a page of another site may post
//! `text/plain` without a preflight, and must not start simulations that way.

use crate::error::AppError;
use crate::state::AppState;
use axum::body::Bytes;
use axum::extract::{FromRequest, Request};
use axum::http::{HeaderValue, header};
use serde::de::DeserializeOwned;

/// A request body read as one JSON object into `T`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct JsonObject<T>(pub T);

impl<T: DeserializeOwned + Send> FromRequest<AppState> for JsonObject<T> {
    type Rejection = AppError;

    async fn from_request(req: Request, state: &AppState) -> Result<Self, AppError> {
        check_content_type(req.headers().get(header::CONTENT_TYPE))?;
        // A body that trickles in is refused with 408 once `body_timeout` has passed.
        let limit = state.config.body_timeout;
        let body = tokio::time::timeout(limit, Bytes::from_request(req, state))
            .await
            .map_err(|_| {
                AppError::timeout(format!(
                    "the request body did not arrive within {} s (limit body_timeout)",
                    limit.as_secs_f64()
                ))
            })?
            .map_err(|e| AppError::body(e, state.config.max_body_bytes))?;
        read_object(&body).map(Self)
    }
}

/// Reads a request body that must be one JSON object, naming the offending path on failure.
///
/// serde's derived structs also accept an array of the fields in order, so `["cvt"]` would be
/// read as `{"system": "cvt"}` and `[]` as `{}` (all defaults: a whole scorecard); any JSON
/// that is not an object is refused here first.
pub fn read_object<T: DeserializeOwned>(body: &[u8]) -> Result<T, AppError> {
    let first = body.iter().find(|b| !matches!(b, b' ' | b'\t' | b'\n' | b'\r'));
    if first.is_some_and(|&b| b != b'{')
        && let Ok(value) = serde_json::from_slice::<serde_json::Value>(body)
    {
        return Err(AppError::not_an_object(&value));
    }
    let de = &mut serde_json::Deserializer::from_slice(body);
    let req: T = serde_path_to_error::deserialize(&mut *de)?;
    // Nothing but whitespace may follow the object (`{…} {` is not one JSON document).
    de.end().map_err(|e| AppError::malformed(&e))?;
    Ok(req)
}

/// Refuses a body whose `Content-Type` is missing or not JSON (415).
fn check_content_type(value: Option<&HeaderValue>) -> Result<(), AppError> {
    let given = value.map(|v| String::from_utf8_lossy(v.as_bytes()).into_owned());
    let essence = given
        .as_deref()
        .map(|v| v.split(';').next().unwrap_or_default().trim().to_ascii_lowercase());
    match essence.as_deref() {
        Some("application/json") => Ok(()),
        Some(e) if e.starts_with("application/") && e.ends_with("+json") => Ok(()),
        _ => Err(AppError::unsupported_media_type(given.as_deref())),
    }
}
