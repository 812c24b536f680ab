//! The `nhlab` binary alone, copied into an empty directory, serves the page and the API
//! (the page is embedded), logs one line per request, takes its address from `--addr` or
//! `NHLAB_ADDR`, and exits cleanly on SIGTERM.
//!
//! `cargo test -p nhlab-server --test binary_alone` checks the test-profile binary;
//! `cargo test --release -p nhlab-server --test binary_alone` the release binary.

mod common;

use common::Server;
use serde_json::{Value, json};

#[tokio::test]
async fn binary_alone_serves_page_and_api() {
    let dir = tempfile::tempdir().unwrap();
    let binary = dir.path().join("nhlab");
    std::fs::copy(env!("CARGO_BIN_EXE_nhlab"), &binary).expect("copy the binary");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1, "the binary is alone");

    let mut server = Server::start(&binary, dir.path(), |c| {
        c.args(["--addr", "127.0.0.1:0"]);
    });
    let page = reqwest::get(format!("{}/", server.url)).await.unwrap();
    assert_eq!(page.status(), 200);
    assert!(page.headers()["content-type"].to_str().unwrap().starts_with("text/html"));
    assert!(page.text().await.unwrap().to_lowercase().contains("<html"));

    let systems = reqwest::get(format!("{}/systems", server.url)).await.unwrap();
    assert_eq!(systems.status(), 200);
    let systems: Value = systems.json().await.unwrap();
    assert!(!systems["systems"].as_array().unwrap().is_empty());

    let response = reqwest::Client::new()
        .post(format!("{}/simulate", server.url))
        .json(&json!({"system": "knife_edge", "preset": "paper", "points": 50}))
        .send()
        .await
        .unwrap();
    assert_eq!(response.status(), 200);
    let body: Value = response.json().await.unwrap();
    let runs = body["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 5);
    assert!(runs.iter().all(|r| r["status"] == "ok"), "{body}");

    // One log line per request, with the scene of a simulation.
    let line = server.wait_for("uri=/simulate");
    assert!(line.contains("knife_edge/paper") && line.contains("status=200"), "{line}");
    assert!(line.contains("latency="), "the time is in the line: {line}");
    server.terminate();

    // The address may also come from the environment.
    let server = Server::start(&binary, dir.path(), |c| {
        c.env("NHLAB_ADDR", "127.0.0.1:0");
    });
    let health = reqwest::get(format!("{}/health", server.url)).await.unwrap();
    assert_eq!(health.status(), 200);
    server.terminate();
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1, "nothing written to disk");
}
