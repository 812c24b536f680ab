//! What a request may cost before any work: its answer's memory (per request, 422 with the
//! estimate; server-wide with the answers in flight, 503), its turn to be checked, and what it
//! must say about itself (a JSON `Content-Type`; `Accept` read with its qualities).

use nhlab_server::{AppState, Config};
use nhlab_tests::{SseReader, TestServer};
use serde_json::{Value, json};
use std::time::{Duration, Instant};
use tokio::io::{AsyncReadExt, AsyncWriteExt};

#[tokio::test]
async fn amplified_answers_are_refused_with_their_estimate() {
    let s = TestServer::start().await;
    // 289 bytes asking for 16 runs × 5 series × 10⁵ points: hundreds of MB.
    let simulate = json!({"system": "cvt_pendulum", "preset": "rotating", "t_end": 1e4,
        "points": 100000, "methods": vec!["leapfrog"; 16]});
    let scene = json!({"system": "cvt_pendulum", "preset": "rotating", "t_end": 1e4});
    let scorecard = json!({"scenes": vec![scene; 16], "methods": vec!["leapfrog"; 16],
        "points": 100000});
    for (route, body) in [("/simulate", &simulate), ("/scorecard", &scorecard)] {
        let (status, error) = s.post_json(route, body).await;
        assert_eq!(status, 422, "{route}: {error}");
        assert_eq!(error["path"], "points", "{route}");
        let message = error["error"].as_str().unwrap_or_default();
        assert!(message.contains("MiB") && message.contains("max_answer_bytes"), "{message}");
    }
    // The same as a stream keeps only the buckets: over the limit too, said the same way.
    let response = s.post_stream("/simulate", &simulate).await;
    assert_eq!(response.status(), 422);
    // A short run holds no more buckets than it has steps: 10 steps × 16 × 10⁵ points is fine.
    let short = json!({"system": "cvt_pendulum", "preset": "rotating", "t_end": 1, "step": 0.1,
        "points": 100000, "methods": vec!["leapfrog"; 16]});
    let (status, answer) = s.post_json("/simulate", &short).await;
    assert_eq!(status, 200, "{answer}");
}

#[tokio::test]
async fn answers_in_flight_share_one_budget_until_written() {
    // Room for one answer of 5 series × 20000 points at 128 bytes (12.8 MB), not two.
    let config = Config { max_inflight_bytes: 20 << 20, ..Config::default() };
    let s = TestServer::with_config(config).await;
    let body = json!({"system": "cvt_pendulum", "preset": "oscillating", "step": 0.01,
        "t_end": 400, "points": 20000, "methods": ["leapfrog"]})
    .to_string();
    // A client that sends its request and does not read the answer (async: the server runs
    // on this test's runtime).
    let mut stalled =
        tokio::net::TcpStream::connect(s.url.trim_start_matches("http://")).await.unwrap();
    let request = format!(
        "POST /simulate HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n\
         Connection: close\r\nContent-Length: {}\r\n\r\n{body}",
        body.len()
    );
    stalled.write_all(request.as_bytes()).await.unwrap();
    // Its runs end and its slot is free, but its answer is still held for it.
    let start = Instant::now();
    loop {
        let h = s.health().await;
        if h["active_runs"] == 0 && h["simulations"] == 0 && h["answer_bytes"].as_u64() > Some(0) {
            break;
        }
        assert!(start.elapsed() < Duration::from_secs(20), "{h}");
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    let parsed: Value = serde_json::from_str(&body).unwrap();
    let (status, error) = s.post_json("/simulate", &parsed).await;
    assert_eq!(status, 503, "{error}");
    assert!(error["error"].as_str().unwrap_or_default().contains("max_inflight_bytes"));
    // Once read, the answer gives its bytes back.
    let mut answer = Vec::new();
    stalled.read_to_end(&mut answer).await.unwrap();
    assert!(answer.len() > 1_000_000, "the whole answer arrives");
    let start = Instant::now();
    while s.health().await["answer_bytes"] != 0 {
        assert!(start.elapsed() < Duration::from_secs(5), "the budget is given back");
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    let (status, _) = s.post_json("/simulate", &parsed).await;
    assert_eq!(status, 200);
}

#[tokio::test]
async fn a_check_waits_its_turn_then_is_told_the_server_is_busy() {
    let state = AppState::new(Config { max_simulations: 1, ..Config::default() });
    let (hold, release) = std::sync::mpsc::channel::<()>();
    let (started_tx, started) = tokio::sync::oneshot::channel();
    let busy = tokio::spawn({
        let state = state.clone();
        async move {
            state
                .check(move |_| {
                    let _ = started_tx.send(());
                    let _ = release.recv();
                    Ok(())
                })
                .await
        }
    });
    started.await.unwrap();
    let start = Instant::now();
    let refused = state.check(|_| Ok(())).await.unwrap_err();
    assert_eq!(refused.status, 503);
    assert!(start.elapsed() >= nhlab_server::state::CHECK_WAIT, "it waited for a turn first");
    hold.send(()).unwrap();
    busy.await.unwrap().unwrap();
    state.check(|_| Ok(())).await.expect("a free turn");
}

#[tokio::test]
async fn bodies_must_be_sent_as_json() {
    let s = TestServer::start().await;
    let body = r#"{"system": "knife_edge", "t_end": 1}"#;
    for (content_type, status) in [
        (None, 415),
        (Some("text/plain"), 415),
        (Some("application/x-www-form-urlencoded"), 415),
        (Some("application/json"), 200),
        (Some("Application/JSON; charset=utf-8"), 200),
        (Some("application/vnd.nhlab+json"), 200),
    ] {
        for route in ["/simulate", "/scorecard", "/work-precision"] {
            let mut request = reqwest::Client::new().post(s.at(route)).body(body);
            if let Some(t) = content_type {
                request = request.header("content-type", t);
            }
            let response = request.send().await.unwrap();
            if status == 415 {
                assert_eq!(response.status(), 415, "{route} {content_type:?}");
                let error: Value = response.json().await.unwrap();
                assert!(error["error"].as_str().unwrap().contains("application/json"), "{error}");
            } else if route == "/simulate" {
                assert_eq!(response.status(), 200, "{content_type:?}");
            }
        }
    }
}

#[tokio::test]
async fn accept_is_read_with_its_qualities() {
    let s = TestServer::start().await;
    let body = json!({"system": "knife_edge", "t_end": 1, "methods": ["leapfrog"]});
    for (accept, streams) in [
        ("text/event-stream", true),
        ("text/event-stream;q=0", false),
        ("text/event-stream; q=0.0, application/json", false),
        ("application/json;q=0.9, text/event-stream", true),
        ("text/event-stream;q=0.5, application/json", false),
        ("*/*", false),
    ] {
        let response = reqwest::Client::new()
            .post(s.at("/simulate"))
            .header("accept", accept)
            .json(&body)
            .send()
            .await
            .unwrap();
        assert_eq!(response.status(), 200, "{accept}");
        let content_type = response.headers()["content-type"].to_str().unwrap().to_owned();
        assert_eq!(content_type.starts_with("text/event-stream"), streams, "{accept}");
    }
}

#[tokio::test]
async fn a_run_shorter_than_a_progress_interval_still_reports_progress() {
    let s = TestServer::start().await;
    let body = json!({"system": "knife_edge", "t_end": 1, "methods": ["leapfrog", "dd"]});
    let events = SseReader::new(s.post_stream("/simulate", &body).await).collect().await;
    for run in 0..2 {
        let progress: Vec<_> =
            events.iter().filter(|e| e.event == "progress" && e.data["run"] == run).collect();
        let last = progress.last().unwrap_or_else(|| panic!("no progress for run {run}"));
        assert_eq!(last.data["fraction"], 1.0, "{last:?}");
    }
}

#[tokio::test]
async fn every_response_says_nosniff_and_the_page_has_a_policy() {
    let s = TestServer::start().await;
    for path in ["/", "/health", "/systems", "/nowhere"] {
        let response = reqwest::get(s.at(path)).await.unwrap();
        assert_eq!(response.headers()["x-content-type-options"], "nosniff", "{path}");
    }
    let page = reqwest::get(s.at("/")).await.unwrap();
    let csp = page.headers()["content-security-policy"].to_str().unwrap();
    assert!(csp.contains("script-src 'self'") && csp.contains("frame-ancestors 'none'"));
}
