//! The service under load and faults, against the real server (in-process, real TCP):
//! admission (a bounded number of simulations, 503 with `Retry-After` beyond), slots freed
//! within 100 ms when a client goes away, a panicking simulation failing alone, CORS off
//! unless configured, and no path outside the embedded page.
//! (`/health` under load has its own file, `responsive.rs`; shutdown is tested on the
//! binary in `server/tests/shutdown.rs`.)

use nhlab_server::Config;
use nhlab_tests::{SseReader, TestServer};
use serde_json::{Value, json};
use std::io::{Read, Write};
use std::time::{Duration, Instant};

/// 10⁸ steps of one method: minutes of work unless stopped.
fn long_stream() -> Value {
    json!({"system": "knife_edge", "step": 1e-6, "t_end": 100, "methods": ["leapfrog"]})
}

fn with_slots(n: usize) -> Config {
    Config { max_simulations: n, ..Config::default() }
}

/// Opens a long stream and waits for its first event (it is admitted and computing).
async fn open_stream(server: &TestServer) -> SseReader {
    let response = server.post_stream("/simulate", &long_stream()).await;
    assert_eq!(response.status(), 200);
    let mut events = SseReader::new(response);
    assert_eq!(events.next().await.unwrap().event, "scene");
    events
}

/// Polls `/health` until `simulations` is `n`; how long it took (fails after `limit`).
async fn until_simulations(server: &TestServer, n: u64, limit: Duration) -> Duration {
    let start = Instant::now();
    loop {
        if server.health().await["simulations"] == n {
            return start.elapsed();
        }
        assert!(start.elapsed() < limit, "still not {n} simulations after {limit:?}");
        tokio::time::sleep(Duration::from_millis(1)).await;
    }
}

async fn busy_answer(
    server: &TestServer,
    accept: &str,
    body: &Value,
) -> (u16, Option<String>, Value) {
    let response = reqwest::Client::new()
        .post(server.at("/simulate"))
        .header("accept", accept)
        .json(body)
        .send()
        .await
        .unwrap();
    let status = response.status().as_u16();
    let retry = response.headers().get("retry-after").map(|v| v.to_str().unwrap().to_owned());
    let content_type = response.headers()["content-type"].to_str().unwrap().to_owned();
    assert_eq!(content_type, "application/json");
    (status, retry, response.json().await.unwrap())
}

#[tokio::test]
async fn beyond_the_slots_requests_get_503_with_retry_after() {
    let server = TestServer::with_config(with_slots(2)).await;
    let first = open_stream(&server).await;
    let _second = open_stream(&server).await;
    let h = server.health().await;
    assert_eq!((h["simulations"].as_u64(), h["max_simulations"].as_u64()), (Some(2), Some(2)));

    let small = json!({"system": "knife_edge", "preset": "paper", "points": 10});
    for accept in ["application/json", "text/event-stream"] {
        let (status, retry, error) = busy_answer(&server, accept, &small).await;
        assert_eq!(status, 503, "{accept}: {error}");
        assert_eq!(retry.as_deref(), Some("1"));
        assert_eq!(error["path"], Value::Null);
        let message = error["error"].as_str().unwrap();
        assert!(message.contains("busy") && message.contains("max_simulations"), "{message}");
    }
    // The scorecard computes too: it goes through the same admission.
    let response = reqwest::Client::new()
        .post(server.at("/scorecard"))
        .json(&json!({"scenes": [{"system": "knife_edge"}]}))
        .send()
        .await
        .unwrap();
    assert_eq!(response.status(), 503);
    assert_eq!(response.headers()["retry-after"], "1");
    let error: Value = response.json().await.unwrap();
    assert!(error["error"].as_str().unwrap().contains("max_simulations"), "{error}");
    // A wrong request still learns what is wrong, busy or not.
    let (status, _, error) =
        busy_answer(&server, "application/json", &json!({"system": "knife"})).await;
    assert_eq!((status, error["path"].as_str()), (422, Some("system")));
    // The page, the listing and /health are no simulations.
    assert_eq!(reqwest::get(server.at("/systems")).await.unwrap().status(), 200);
    assert_eq!(reqwest::get(server.at("/")).await.unwrap().status(), 200);

    // A stream holds its slot until it ends; its client leaving ends it, and the slot is
    // free again within 100 ms.
    drop(first);
    let freed = until_simulations(&server, 1, Duration::from_millis(100)).await;
    eprintln!("slot free {freed:?} after the stream's client left");
    let (status, retry, body) = busy_answer(&server, "application/json", &small).await;
    assert_eq!((status, retry), (200, None), "{body}");
    assert_eq!(body["runs"].as_array().unwrap().len(), 5);
    assert_eq!(server.health().await["simulations"], 1);
}

#[tokio::test]
async fn a_finished_stream_frees_its_slot() {
    let server = TestServer::with_config(with_slots(1)).await;
    let request = json!({"system": "knife_edge", "preset": "paper", "points": 10});
    for _ in 0..3 {
        let response = server.post_stream("/simulate", &request).await;
        assert_eq!(response.status(), 200);
        let events = SseReader::new(response).collect().await;
        assert_eq!(events.last().unwrap().event, "done");
        // The slot is released after the last event, with the coordinating task.
        until_simulations(&server, 0, Duration::from_millis(100)).await;
    }
}

#[tokio::test]
async fn a_json_client_leaving_frees_its_slot_within_100_ms() {
    let server = TestServer::with_config(with_slots(1)).await;
    // 2·10⁷ steps: seconds of work, within the JSON limit.
    let request = json!({
        "system": "knife_edge", "step": 5e-6, "t_end": 100, "methods": ["leapfrog"]
    });
    let send = reqwest::Client::new().post(server.at("/simulate")).json(&request).send();
    let request = tokio::spawn(send);
    tokio::time::sleep(Duration::from_millis(300)).await;
    assert!(!request.is_finished(), "the run should take longer than 300 ms");
    assert_eq!(server.health().await["simulations"], 1);
    request.abort(); // the client goes away: its connection closes
    let freed = until_simulations(&server, 0, Duration::from_millis(100)).await;
    eprintln!("slot free {freed:?} after the JSON client left");
    assert_eq!(server.state.active_runs(), 0, "the run stopped with its slot");
}

#[cfg(debug_assertions)]
#[tokio::test]
async fn a_panicking_simulation_fails_its_own_request_only() {
    let server = TestServer::with_config(Config {
        max_simulations: 2,
        panic_on_points: Some(7),
        ..Config::default()
    })
    .await;
    let faulty = json!({"system": "knife_edge", "preset": "paper", "points": 7});
    let fine = json!({"system": "knife_edge", "preset": "paper", "points": 8});
    for _ in 0..3 {
        let (status, _, error) = busy_answer(&server, "application/json", &faulty).await;
        assert_eq!(status, 500, "{error}");
        assert_eq!(error["path"], Value::Null);
        assert!(error["error"].as_str().unwrap().contains("panicked"), "{error}");
        // The answer comes at the first panic; the request's other runs end just after
        // (cancelled, or panicking too), and with them its slot.
        until_simulations(&server, 0, Duration::from_secs(2)).await;
        let (status, _, body) = busy_answer(&server, "application/json", &fine).await;
        assert_eq!(status, 200, "{body}");
    }
    // In a stream each run reports the fault and the stream ends normally.
    let response = server.post_stream("/simulate", &faulty).await;
    let events = SseReader::new(response).collect().await;
    let runs: Vec<_> = events.iter().filter(|e| e.event == "run").collect();
    assert_eq!(runs.len(), 5);
    for run in runs {
        assert_eq!(run.data["status"], "failed");
        assert!(run.data["error"].as_str().unwrap().contains("internal error"), "{:?}", run);
    }
    assert_eq!(events.last().unwrap().data["failed"], 5);
    // Nothing leaked: no slot, no run.
    let h = server.health().await;
    assert_eq!((h["simulations"].as_u64(), h["active_runs"].as_u64()), (Some(0), Some(0)));
}

async fn cors_headers(server: &TestServer, origin: &str) -> (Option<String>, Option<String>) {
    let client = reqwest::Client::new();
    let simple = client.get(server.at("/systems")).header("origin", origin).send().await.unwrap();
    let preflight = client
        .request(reqwest::Method::OPTIONS, server.at("/simulate"))
        .header("origin", origin)
        .header("access-control-request-method", "POST")
        .header("access-control-request-headers", "content-type")
        .send()
        .await
        .unwrap();
    let allow = |r: &reqwest::Response| {
        r.headers().get("access-control-allow-origin").map(|v| v.to_str().unwrap().to_owned())
    };
    (allow(&simple), allow(&preflight))
}

#[tokio::test]
async fn cors_is_off_unless_configured() {
    let server = TestServer::start().await;
    assert_eq!(cors_headers(&server, "https://evil.example").await, (None, None));

    let lab = "https://lab.example.org";
    let config = Config { cors_origins: vec![lab.into()], ..Config::default() };
    let server = TestServer::with_config(config).await;
    assert_eq!(cors_headers(&server, lab).await, (Some(lab.into()), Some(lab.into())));
    assert_eq!(cors_headers(&server, "https://evil.example").await, (None, None));
}

/// Sends `target` verbatim (no client-side normalisation of `..`) and returns the status
/// line and the body.
async fn raw_get(server: &TestServer, target: &str) -> (String, String) {
    let address = server.url.trim_start_matches("http://").to_owned();
    let request = format!("GET {target} HTTP/1.1\r\nHost: {address}\r\nConnection: close\r\n\r\n");
    // A plain blocking socket, off the runtime that serves the app.
    let response = tokio::task::spawn_blocking(move || {
        let mut socket = std::net::TcpStream::connect(address).unwrap();
        socket.write_all(request.as_bytes()).unwrap();
        let mut response = Vec::new();
        socket.read_to_end(&mut response).unwrap();
        String::from_utf8_lossy(&response).into_owned()
    })
    .await
    .unwrap();
    let (head, body) = response.split_once("\r\n\r\n").unwrap_or((&response, ""));
    (head.lines().next().unwrap_or("").to_owned(), body.to_owned())
}

#[tokio::test]
async fn no_file_outside_the_embedded_page_is_served() {
    let server = TestServer::start().await;
    let (status, _) = raw_get(&server, "/index.html").await;
    assert!(status.contains(" 200 "), "{status}");
    for target in [
        "/../Cargo.toml",
        "/../../Cargo.toml",
        "/%2e%2e/Cargo.toml",
        "/..%2fCargo.toml",
        "/%2e%2e%2f%2e%2e%2fCargo.toml",
        "/assets/../../server/Cargo.toml",
        "/index.html/../../Cargo.toml",
        "/..\\Cargo.toml",
        "//etc/passwd",
        "/../../../../../../etc/passwd",
        "/%2e%2e%2f%2e%2e%2f%2e%2e%2f%2e%2e%2f%2e%2e%2fetc%2fpasswd",
        "/src/data/api.js",
        "/build.rs",
        "/web/dist/index.html",
    ] {
        let (status, body) = raw_get(&server, target).await;
        assert!(status.contains(" 404 ") || status.contains(" 400 "), "{target}: {status}");
        assert!(!body.contains("[package]") && !body.contains("root:"), "{target}: {body}");
    }
}
