//! [`AppError`]: every error the API returns, as `{"error": "...", "path": "methods[1].alpha"}`
//! with a fitting status: 400 for a body that is not the JSON we read (syntax, types,
//! unknown fields), 422 for well-formed input that is wrong (unknown names, lengths,
//! ranges, limits), 413 for an oversized body, 415 for a body not sent as JSON, 503 (with
//! `Retry-After`) when every simulation slot is taken or the server is shutting down, 500
//! for our own faults.

use axum::Json;
use axum::extract::rejection::BytesRejection;
use axum::http::{HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use nhlab_core::{InputError, Short};
use serde::Serialize;
use utoipa::ToSchema;

/// Seconds a client should wait before retrying a 503 (simulations take milliseconds to
/// seconds; a stream may hold its slot longer, and the client then retries again).
pub const RETRY_AFTER_SECS: u32 = 1;

/// An error response.
#[derive(Debug, Clone, PartialEq)]
pub struct AppError {
    /// HTTP status.
    pub status: StatusCode,
    /// What is wrong and what is allowed.
    pub message: String,
    /// The offending field of the request body, e.g. `methods[1].alpha`; `None` when the
    /// error concerns no one field.
    pub path: Option<String>,
}

/// The JSON body of an error.
#[derive(Debug, Serialize, ToSchema)]
pub struct ErrorBody {
    /// What is wrong and what is allowed.
    pub error: String,
    /// The offending field, e.g. `methods[1].alpha` (null when no one field is at fault).
    pub path: Option<String>,
}

impl AppError {
    /// A 422 about the field at `path`.
    pub fn invalid(path: impl Into<String>, message: impl Into<String>) -> Self {
        Self {
            status: StatusCode::UNPROCESSABLE_ENTITY,
            message: message.into(),
            path: Some(path.into()),
        }
    }

    /// A 500: our fault, not the request's.
    pub fn internal(message: impl Into<String>) -> Self {
        Self { status: StatusCode::INTERNAL_SERVER_ERROR, message: message.into(), path: None }
    }

    /// A 503: busy or shutting down; the response says when to retry (`Retry-After`).
    pub fn unavailable(message: impl Into<String>) -> Self {
        Self { status: StatusCode::SERVICE_UNAVAILABLE, message: message.into(), path: None }
    }

    /// A 415 for a body sent without a JSON `Content-Type` (`given`, if any).
    pub fn unsupported_media_type(given: Option<&str>) -> Self {
        let given = match given {
            Some(v) => format!("got Content-Type: {}", v.chars().take(80).collect::<String>()),
            None => "got no Content-Type".to_owned(),
        };
        Self {
            status: StatusCode::UNSUPPORTED_MEDIA_TYPE,
            message: format!(
                "the body must be sent with Content-Type: application/json ({given}); with \
                 curl: --json '{{...}}', or -H 'content-type: application/json' -d '{{...}}'"
            ),
            path: None,
        }
    }

    /// A 405 for a method a route does not take.
    pub fn method_not_allowed(method: &str, path: &str) -> Self {
        Self {
            status: StatusCode::METHOD_NOT_ALLOWED,
            message: format!(
                "{path} does not take {method}; the API is GET /systems, POST /simulate, \
                 POST /scorecard, POST /work-precision, GET /openapi.json, GET /health"
            ),
            path: None,
        }
    }

    /// A 404 for a path the server does not serve.
    pub fn not_found(path: &str) -> Self {
        Self {
            status: StatusCode::NOT_FOUND,
            message: format!(
                "no such resource: {path}; the API is GET /systems, POST /simulate, \
                 POST /scorecard, POST /work-precision, GET /openapi.json, GET /health, and the \
                 page is at /"
            ),
            path: None,
        }
    }
}

impl From<InputError> for AppError {
    fn from(e: InputError) -> Self {
        Self::invalid(e.field(), e.to_string())
    }
}

impl From<serde_path_to_error::Error<serde_json::Error>> for AppError {
    fn from(e: serde_path_to_error::Error<serde_json::Error>) -> Self {
        let inner = e.inner();
        let message = shorten_numbers(&inner.to_string());
        let mut path = e.path().to_string();
        // serde reports a missing or unknown field at the object holding it; point at the
        // field itself.
        // (An unknown field is already in the path.)
        if let Some(field) = backticked(&message, "missing field `") {
            path = if path == "." { field.to_owned() } else { format!("{path}.{field}") };
        }
        // serde_path_to_error writes `.` for the root and `?` for an unknown position.
        let path = (!matches!(path.as_str(), "." | "?")).then_some(path);
        let hint = if message.starts_with("number out of range") {
            "numbers must be finite (|x| < 1.8e308): "
        } else if inner.is_syntax() || inner.is_eof() {
            "malformed JSON (the body must be a JSON object such as \
             {\"system\": \"knife_edge\"}; NaN and Infinity are not JSON): "
        } else {
            ""
        };
        Self { status: StatusCode::BAD_REQUEST, message: format!("{hint}{message}"), path }
    }
}

impl AppError {
    /// A 400 for a body that is JSON but not an object.
    pub fn not_an_object(value: &serde_json::Value) -> Self {
        let kind = match value {
            serde_json::Value::Array(_) => "an array",
            serde_json::Value::String(_) => "a string",
            serde_json::Value::Number(_) => "a number",
            serde_json::Value::Bool(_) => "a boolean",
            serde_json::Value::Null => "null",
            serde_json::Value::Object(_) => "an object",
        };
        Self {
            status: StatusCode::BAD_REQUEST,
            message: format!(
                "the body must be a JSON object such as {{\"system\": \"knife_edge\"}}, not {kind}"
            ),
            path: None,
        }
    }

    /// A 400 for a body that is not one JSON document (e.g. trailing characters).
    pub fn malformed(e: &serde_json::Error) -> Self {
        Self {
            status: StatusCode::BAD_REQUEST,
            message: format!("malformed JSON (the body must be one JSON object): {e}"),
            path: None,
        }
    }

    /// The error of a body that could not be read (too large: 413 naming the limit).
    pub fn body(e: BytesRejection, max_body_bytes: usize) -> Self {
        let message = if e.status() == StatusCode::PAYLOAD_TOO_LARGE {
            format!("the request body exceeds the limit of {max_body_bytes} bytes")
        } else {
            e.body_text()
        };
        Self { status: e.status(), message, path: None }
    }
}

/// The message with every run of more than 17 digits (serde prints a float such as 1e308 in
/// full, 309 digits) written as a short number with an exponent.
fn shorten_numbers(message: &str) -> String {
    let mut out = String::with_capacity(message.len());
    let mut rest = message;
    while let Some(start) = rest.find(|c: char| c.is_ascii_digit()) {
        out.push_str(&rest[..start]);
        let len = rest[start..]
            .find(|c: char| !(c.is_ascii_digit() || c == '.'))
            .unwrap_or(rest.len() - start);
        let number = &rest[start..start + len];
        let digits = number.bytes().filter(u8::is_ascii_digit).count();
        match number.trim_end_matches('.').parse::<f64>() {
            Ok(x) if digits > 17 => out.push_str(&Short(x).to_string()),
            _ => out.push_str(number),
        }
        rest = &rest[start + len..];
    }
    out.push_str(rest);
    out
}

impl AppError {
    /// A 408: the request (its body) did not arrive in time.
    pub fn timeout(message: impl Into<String>) -> Self {
        Self { status: StatusCode::REQUEST_TIMEOUT, message: message.into(), path: None }
    }

    /// A 400 about the request as a whole rather than a field of its body (e.g. a missing
    /// `Host` header).
    pub fn bad_request(message: impl Into<String>) -> Self {
        Self { status: StatusCode::BAD_REQUEST, message: message.into(), path: None }
    }
}

fn backticked<'a>(message: &'a str, prefix: &str) -> Option<&'a str> {
    let rest = message.strip_prefix(prefix)?;
    rest.split('`').next()
}

impl IntoResponse for AppError {
    fn into_response(self) -> Response {
        let body = ErrorBody { error: self.message, path: self.path };
        let mut response = (self.status, Json(body)).into_response();
        if self.status == StatusCode::SERVICE_UNAVAILABLE {
            response.headers_mut().insert(header::RETRY_AFTER, HeaderValue::from(RETRY_AFTER_SECS));
        }
        response
    }
}
