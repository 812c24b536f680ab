//! The `nhlab` binary alone, copied into an empty directory, serves the page and the API
//! (the page is embedded), logs one line per request, takes its address from `--addr` or
//! `NHLAB_ADDR`, and exits cleanly on SIGTERM.
//!
//! `cargo test -p nhlab-server --test binary_alone` checks the test-profile binary;
//! `cargo test --release -p nhlab-server --test binary_alone` the release binary.

use serde_json::{Value, json};
use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// The binary running in `dir`, with its log lines arriving on `log`.
struct Server {
    child: Child,
    log: mpsc::Receiver<String>,
    url: String,
    lines: Vec<String>,
}

impl Server {
    fn start(binary: &Path, dir: &Path, configure: impl FnOnce(&mut Command)) -> Self {
        let mut command = Command::new(binary);
        command
            .current_dir(dir)
            .env_remove("NHLAB_ADDR")
            .env("RUST_LOG", "info")
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::piped());
        configure(&mut command);
        let mut child = command.spawn().expect("the binary starts");
        let stderr = child.stderr.take().unwrap();
        let (tx, log) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stderr).lines().map_while(Result::ok) {
                if tx.send(line).is_err() {
                    break;
                }
            }
        });
        let mut server = Self { child, log, url: String::new(), lines: Vec::new() };
        let line = server.wait_for("listening on http://");
        server.url = line[line.find("http://").unwrap()..].trim().to_owned();
        server
    }

    /// Waits (up to 20 s) for a log line containing `text`.
    fn wait_for(&mut self, text: &str) -> String {
        let deadline = Instant::now() + Duration::from_secs(20);
        if let Some(line) = self.lines.iter().find(|l| l.contains(text)) {
            return line.clone();
        }
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.log.recv_timeout(left) {
                Ok(line) => {
                    self.lines.push(line.clone());
                    if line.contains(text) {
                        return line;
                    }
                }
                Err(_) => panic!("no log line with '{text}'; log so far: {:#?}", self.lines),
            }
        }
    }

    fn terminate(mut self) {
        let status = Command::new("kill")
            .args(["-TERM", &self.child.id().to_string()])
            .status()
            .expect("kill runs");
        assert!(status.success());
        let deadline = Instant::now() + Duration::from_secs(15);
        loop {
            if let Some(status) = self.child.try_wait().unwrap() {
                assert!(status.success(), "exit status {status}");
                return;
            }
            assert!(Instant::now() < deadline, "still running 15 s after SIGTERM");
            std::thread::sleep(Duration::from_millis(20));
        }
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

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
