//! [`sse_event`]: one server-sent event of the stream, its payload (a scene, progress, points,
//! run, done or shutdown view) written as JSON in one piece.

use axum::response::sse::Event;
use serde::Serialize;

/// An event named `name` carrying `data` as JSON.
///
/// Serialized into one buffer first: axum's `Event::json_data` hands serde_json's every token
/// (each number, comma, bracket) to its line-splitting writer, a memchr and a copy per token,
/// which a long stream of `points` pays for every number it sends.
pub fn sse_event<T: Serialize>(name: &str, data: &T) -> Event {
    match serde_json::to_string(data) {
        Ok(json) => Event::default().event(name).data(json),
        Err(e) => {
            let message = format!("could not serialize the {name} event: {e}");
            let error = serde_json::json!({ "error": message }).to_string();
            Event::default().event("error").data(error)
        }
    }
}
