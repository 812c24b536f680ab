//! Helpers for the tests of nhlab against the real server: [`TestServer`] runs the app
//! in-process on 127.0.0.1 with a real TCP listener on a free port, and [`SseReader`] reads
//! the server-sent events of `POST /simulate` as they arrive.

use futures_util::StreamExt;
use futures_util::stream::BoxStream;
use nhlab_server::{AppState, Config, app, serve};
use serde_json::Value;

/// The app served on 127.0.0.1:<free port> by the binary's connection layer
/// ([`serve::serve`]), stopped when dropped.
#[derive(Debug)]
pub struct TestServer {
    /// `http://127.0.0.1:<port>`.
    pub url: String,
    /// The app's state (to watch its running simulations).
    pub state: AppState,
    task: tokio::task::JoinHandle<()>,
}

impl TestServer {
    /// Starts the app with the default limits.
    pub async fn start() -> Self {
        Self::with_config(Config::default()).await
    }

    /// Starts the app with `config`.
    pub async fn with_config(config: Config) -> Self {
        Self::with_options(config, serve::Options::default()).await
    }

    /// Starts the app with `config`, its connections served with `options`.
    pub async fn with_options(config: Config, options: serve::Options) -> Self {
        let listener =
            tokio::net::TcpListener::bind("127.0.0.1:0").await.expect("bind 127.0.0.1:0");
        let url = format!("http://{}", listener.local_addr().expect("local address"));
        let state = AppState::new(config);
        let router = app(state.clone());
        let task = tokio::spawn(serve::serve(listener, router, options, std::future::pending()));
        Self { url, state, task }
    }

    /// The URL of `path`.
    pub fn at(&self, path: &str) -> String {
        format!("{}{path}", self.url)
    }

    /// `GET /health`, read as JSON.
    pub async fn health(&self) -> Value {
        let response = reqwest::get(self.at("/health")).await.expect("request succeeds");
        response.json().await.expect("a JSON body")
    }

    /// `POST path` with a JSON body: the status and the JSON answer.
    pub async fn post_json(&self, path: &str, body: &Value) -> (u16, Value) {
        let response = reqwest::Client::new()
            .post(self.at(path))
            .json(body)
            .send()
            .await
            .expect("request succeeds");
        let status = response.status().as_u16();
        (status, response.json().await.expect("a JSON body"))
    }

    /// `POST path` with `body` as it is (any text, sent as `application/json`): the response,
    /// unread.
    pub async fn post_text(&self, path: &str, body: impl Into<reqwest::Body>) -> reqwest::Response {
        reqwest::Client::new()
            .post(self.at(path))
            .header("content-type", "application/json")
            .body(body)
            .send()
            .await
            .expect("request succeeds")
    }

    /// `POST path` with a JSON body, asking for server-sent events: the response, unread.
    pub async fn post_stream(&self, path: &str, body: &Value) -> reqwest::Response {
        reqwest::Client::new()
            .post(self.at(path))
            .header("accept", "text/event-stream")
            .json(body)
            .send()
            .await
            .expect("request succeeds")
    }

    /// Waits until no run computes and no slot is held, failing after `limit`; how long it
    /// took.
    pub async fn wait_idle(&self, limit: std::time::Duration) -> std::time::Duration {
        let start = std::time::Instant::now();
        while self.state.active_runs() > 0 || self.state.busy_slots() > 0 {
            assert!(start.elapsed() < limit, "runs still going after {limit:?}");
            tokio::time::sleep(std::time::Duration::from_millis(2)).await;
        }
        start.elapsed()
    }
}

impl TestServer {
    /// Posts `body` to `/simulate` and checks that it is a 422 at `path` whose message
    /// mentions each of `mentions`.
    pub async fn rejected(&self, body: &Value, path: &str, mentions: &[&str]) {
        let (status, error) = self.post_json("/simulate", body).await;
        assert_eq!(status, 422, "{body}: {error}");
        assert_eq!(error["path"], path, "{error}");
        let message = error["error"].as_str().unwrap();
        for m in mentions {
            assert!(message.contains(m), "'{message}' does not mention '{m}'");
        }
    }
}

/// `body` with `f` applied to its `system` object.
pub fn with_system(mut body: Value, f: impl FnOnce(&mut Value)) -> Value {
    f(&mut body["system"]);
    body
}

impl Drop for TestServer {
    fn drop(&mut self) {
        self.task.abort();
    }
}

/// One server-sent event.
#[derive(Debug, Clone, PartialEq)]
pub struct SseEvent {
    /// The `event:` name.
    pub event: String,
    /// The `data:` payload, parsed as JSON.
    pub data: Value,
}

/// Reads server-sent events from a response body, one at a time.
pub struct SseReader {
    body: BoxStream<'static, reqwest::Result<axum::body::Bytes>>,
    buffer: String,
}

impl SseReader {
    /// Reads the events of `response`.
    pub fn new(response: reqwest::Response) -> Self {
        Self { body: response.bytes_stream().boxed(), buffer: String::new() }
    }

    /// The next event, or `None` at the end of the stream.
    pub async fn next(&mut self) -> Option<SseEvent> {
        loop {
            if let Some(end) = self.buffer.find("\n\n") {
                let block: String = self.buffer.drain(..end + 2).collect();
                if let Some(event) = parse(&block) {
                    return Some(event);
                }
                continue; // a keep-alive comment
            }
            let chunk = self.body.next().await?.expect("the stream reads without error");
            self.buffer.push_str(std::str::from_utf8(&chunk).expect("events are UTF-8"));
        }
    }

    /// Every remaining event.
    pub async fn collect(mut self) -> Vec<SseEvent> {
        let mut out = Vec::new();
        while let Some(e) = self.next().await {
            out.push(e);
        }
        out
    }
}

fn parse(block: &str) -> Option<SseEvent> {
    let mut event = None;
    let mut data = String::new();
    for line in block.lines() {
        if let Some(name) = line.strip_prefix("event:") {
            event = Some(name.trim().to_owned());
        } else if let Some(d) = line.strip_prefix("data:") {
            data.push_str(d.strip_prefix(' ').unwrap_or(d));
        }
    }
    let event = event?;
    let data = serde_json::from_str(&data).expect("event data is JSON");
    Some(SseEvent { event, data })
}
