//! The `nhlab` binary alone, copied into an empty directory, serves the page and the API
//! (the page is embedded), logs one line per request, takes its address from `--addr` or
//! `NHLAB_ADDR`, and exits cleanly on SIGTERM.
//!
//! Its page's assets are named by their content, cached for good and sent compressed; the
//! page itself is revalidated by its ETag; a release binary serves no source map.
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
    let html = page.text().await.unwrap();
    assert!(html.to_lowercase().contains("<html"));
    assets_are_compressed_and_cached(&server.url, &html).await;

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

/// The page's script and style sheet: named by their content (`app-<hash>.js`), cached for a
/// year, gzip-compressed when asked; `index.html` revalidated by its ETag; in a release build
/// no source map.
async fn assets_are_compressed_and_cached(url: &str, html: &str) {
    let client = reqwest::Client::new();
    let get = |path: String, headers: &[(&str, &str)]| {
        let mut request = client.get(format!("{url}/{path}"));
        for (k, v) in headers {
            request = request.header(*k, *v);
        }
        request.send()
    };
    let index = get(String::new(), &[]).await.unwrap();
    assert_eq!(index.headers()["cache-control"], "no-cache");
    let etag = index.headers()["etag"].to_str().unwrap().to_owned();
    let again = get(String::new(), &[("if-none-match", &etag)]).await.unwrap();
    assert_eq!(again.status(), 304, "an unchanged page is not sent again");
    for ext in ["js", "css"] {
        let name = html
            .match_indices("app-")
            .map(|(i, _)| html[i..].split('"').next().unwrap_or_default().to_owned())
            .find(|n| n.ends_with(&format!(".{ext}")))
            .unwrap_or_else(|| panic!("index.html names no app-<hash>.{ext}"));
        let plain = get(name.clone(), &[]).await.unwrap();
        assert_eq!(plain.status(), 200, "{name}");
        assert_eq!(plain.headers()["cache-control"], "public, max-age=31536000, immutable");
        let plain = plain.bytes().await.unwrap();
        let gzip = get(name.clone(), &[("accept-encoding", "gzip")]).await.unwrap();
        assert_eq!(gzip.headers()["content-encoding"], "gzip", "{name}");
        let gzip = gzip.bytes().await.unwrap();
        assert!(
            gzip.len() * 2 < plain.len(),
            "{name}: {} bytes gzipped of {}",
            gzip.len(),
            plain.len()
        );
        if cfg!(not(debug_assertions)) {
            let map = get(format!("{name}.map"), &[]).await.unwrap();
            assert_eq!(map.status(), 404, "a release binary serves no source map");
            assert!(!String::from_utf8_lossy(&plain).contains("sourceMappingURL"), "{name}");
        }
    }
}
