//! Shutdown of the real binary: on SIGTERM (or Ctrl-C, SIGINT) it stops accepting
//! connections, ends every open stream with a `shutdown` event, lets a JSON request in flight
//! finish, and exits 0; a JSON request longer than `--shutdown-grace` does not hold it up (the
//! exit is then 1), and neither do idle connections nor a request head sent in part.

mod common;

use common::Server;
use serde_json::{Value, json};
use std::path::Path;
use std::time::{Duration, Instant};

fn start(extra: &[&str]) -> Server {
    let binary = Path::new(env!("CARGO_BIN_EXE_nhlab"));
    let dir = std::env::temp_dir();
    Server::start(binary, &dir, |c| {
        c.args(["--addr", "127.0.0.1:0", "--max-simulations", "4"]).args(extra);
    })
}

async fn health(url: &str) -> Value {
    reqwest::get(format!("{url}/health")).await.unwrap().json().await.unwrap()
}

/// Waits until `active_runs` reaches `n`.
async fn until_runs(url: &str, n: u64) {
    let start = Instant::now();
    while health(url).await["active_runs"].as_u64() < Some(n) {
        assert!(start.elapsed() < Duration::from_secs(10), "runs did not start");
        tokio::time::sleep(Duration::from_millis(5)).await;
    }
}

/// Opens a stream of `request` and reads until its first `progress` event.
async fn open_stream(url: &str, request: &Value) -> (reqwest::Response, String) {
    let mut response = reqwest::Client::new()
        .post(format!("{url}/simulate"))
        .header("accept", "text/event-stream")
        .json(request)
        .send()
        .await
        .unwrap();
    assert_eq!(response.status(), 200);
    let mut text = String::new();
    while !text.contains("event: progress") {
        let chunk = response.chunk().await.unwrap().expect("the stream goes on");
        text.push_str(std::str::from_utf8(&chunk).unwrap());
    }
    (response, text)
}

/// The name and data of the last event in `text`.
fn last_event(text: &str) -> (String, Value) {
    let block = text.trim_end().rsplit("\n\n").next().unwrap();
    let field = |name: &str| {
        block.lines().find_map(|l| l.strip_prefix(name)).map(|v| v.trim().to_owned()).unwrap()
    };
    (field("event:"), serde_json::from_str(&field("data:")).unwrap())
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn sigterm_ends_streams_finishes_json_requests_and_exits() {
    let mut server = start(&["--shutdown-grace", "30"]);
    let url = server.url.clone();
    // A stream of 10⁸ steps: minutes of work.
    let long = json!({"system": "knife_edge", "step": 1e-6, "t_end": 100, "methods": ["leapfrog"]});
    let (mut stream, mut text) = open_stream(&url, &long).await;
    // A JSON request of 10⁷ steps (a second or so) in flight at the signal.
    let json_request =
        json!({"system": "knife_edge", "step": 1e-5, "t_end": 100, "methods": ["leapfrog"]});
    let client = reqwest::Client::new();
    let in_flight = tokio::spawn(client.post(format!("{url}/simulate")).json(&json_request).send());
    until_runs(&url, 2).await;

    let signalled = Instant::now();
    server.signal("TERM");
    // The stream ends with a `shutdown` event, its run reported as stopped.
    while let Some(chunk) = stream.chunk().await.unwrap() {
        text.push_str(std::str::from_utf8(&chunk).unwrap());
    }
    let ended = signalled.elapsed();
    let (name, data) = last_event(&text);
    assert_eq!(name, "shutdown", "{data}");
    assert!(data["error"].as_str().unwrap().contains("shutting down"), "{data}");
    assert!(text.contains("event: run"), "the run's end is reported first");
    assert!(!text.contains("event: done"));
    eprintln!("stream ended {ended:?} after SIGTERM");
    assert!(ended < Duration::from_secs(2), "{ended:?}");

    // No new connections.
    let refused = reqwest::get(format!("{url}/health")).await;
    assert!(refused.is_err(), "a new connection was accepted during shutdown");

    // The JSON request completes in full.
    let response = in_flight.await.unwrap().expect("the JSON request is answered");
    assert_eq!(response.status(), 200);
    let body: Value = response.json().await.unwrap();
    assert_eq!(body["runs"][0]["status"], "ok", "{}", body["runs"][0]["error"]);
    assert_eq!(body["runs"][0]["steps"], 10_000_000);

    let exited = server.wait_exit(Duration::from_secs(10));
    eprintln!("exited {:?} after SIGTERM", signalled.elapsed());
    assert!(exited < Duration::from_secs(10));
    let log = server.drain_log();
    assert!(log.iter().any(|l| l.contains("shutting down")), "{log:#?}");
}

#[tokio::test]
async fn ctrl_c_exits_and_the_grace_period_bounds_the_wait() {
    // Idle: Ctrl-C (SIGINT) exits at once.
    let mut server = start(&[]);
    assert_eq!(health(&server.url).await["status"], "ok");
    server.signal("INT");
    let exited = server.wait_exit(Duration::from_secs(5));
    eprintln!("idle server exited {exited:?} after SIGINT");

    // A JSON request of minutes does not hold the exit beyond the grace period.
    // Admitted whatever its estimated CPU time: what is tested is the exit.
    let mut server = start(&[
        "--shutdown-grace",
        "0.5",
        "--max-steps-json",
        "1000000000",
        "--max-request-seconds",
        "1e7",
    ]);
    let url = server.url.clone();
    let request = json!({"system": "knife_edge", "step": 1e-7, "t_end": 100, "methods": ["dd"]});
    let in_flight =
        tokio::spawn(reqwest::Client::new().post(format!("{url}/simulate")).json(&request).send());
    until_runs(&url, 1).await;
    server.signal("TERM");
    let (status, exited) = server.wait_status(Duration::from_secs(5));
    eprintln!("busy server exited {exited:?} after SIGTERM (grace 0.5 s): {status}");
    assert!(exited >= Duration::from_millis(400), "it waited for the request: {exited:?}");
    assert_eq!(status.code(), Some(1), "a forced exit is a failure");
    assert!(in_flight.await.unwrap().is_err(), "the connection closed unanswered");
    let log = server.drain_log();
    assert!(log.iter().any(|l| l.contains("grace period")), "{log:#?}");
}

#[test]
fn idle_and_half_open_connections_do_not_hold_up_shutdown() {
    use std::io::{Read, Write};
    use std::net::TcpStream;
    // Timeouts far beyond the test: only shutdown itself may close these connections.
    let mut server = start(&["--shutdown-grace", "30", "--header-timeout", "600"]);
    let address = server.url.trim_start_matches("http://").to_owned();
    let connect = || TcpStream::connect(&address).unwrap();
    // Half a request head.
    let mut half = connect();
    half.write_all(b"POST /simulate HTTP/1.1\r\nHost: nhlab\r\nContent-Ty").unwrap();
    // A kept-alive connection, idle after one answered request.
    let mut idle = connect();
    idle.write_all(b"GET /health HTTP/1.1\r\nHost: nhlab\r\n\r\n").unwrap();
    let mut answer = [0; 4096];
    let n = idle.read(&mut answer).unwrap();
    assert!(answer[..n].starts_with(b"HTTP/1.1 200"), "{}", String::from_utf8_lossy(&answer));
    // A connection that says nothing at all.
    let silent = connect();
    std::thread::sleep(Duration::from_millis(200));

    server.signal("TERM");
    let exited = server.wait_exit(Duration::from_secs(10));
    eprintln!("exited {exited:?} after SIGTERM with a half-sent head open (grace 30 s)");
    assert!(exited < Duration::from_secs(2), "{exited:?}");
    // Each was closed by the server, without an answer.
    for mut stream in [half, idle, silent] {
        stream.set_read_timeout(Some(Duration::from_secs(1))).unwrap();
        assert!(matches!(stream.read(&mut answer), Ok(0) | Err(_)));
    }
}
