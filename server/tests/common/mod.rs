//! The `nhlab` binary as a child process, for the tests of this directory: started with
//! `--addr 127.0.0.1:0` or the like, its address read from its log, its log lines kept.
#![allow(dead_code, reason = "each test file uses a part of the helper")]

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// The binary running in `dir`, with its log lines arriving on `log`.
pub struct Server {
    /// The process.
    pub child: Child,
    log: mpsc::Receiver<String>,
    /// `http://127.0.0.1:<port>`.
    pub url: String,
    lines: Vec<String>,
}

impl Server {
    /// Starts `binary` in `dir`, configured by `configure`, and waits for its address.
    pub fn start(binary: &Path, dir: &Path, configure: impl FnOnce(&mut Command)) -> Self {
        Self::spawn(Command::new(binary), dir, configure)
    }

    /// Like [`start`](Self::start), with a command of the caller's (e.g. the binary run by a
    /// shell that lowers a limit first).
    pub fn spawn(mut command: Command, dir: &Path, configure: impl FnOnce(&mut Command)) -> Self {
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
    pub fn wait_for(&mut self, text: &str) -> String {
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

    /// Sends SIGTERM and waits (up to 15 s) for a clean exit.
    pub fn terminate(mut self) {
        self.signal("TERM");
        self.wait_exit(Duration::from_secs(15));
    }

    /// Sends signal `name` (TERM, INT, …).
    pub fn signal(&self, name: &str) {
        let status = Command::new("kill")
            .args([&format!("-{name}"), &self.child.id().to_string()])
            .status()
            .expect("kill runs");
        assert!(status.success());
    }

    /// Waits up to `limit` for a successful exit; how long it took.
    pub fn wait_exit(&mut self, limit: Duration) -> Duration {
        let (status, took) = self.wait_status(limit);
        assert!(status.success(), "exit status {status}; log: {:#?}", self.drain_log());
        took
    }

    /// Waits up to `limit` for the process to exit; its status and how long it took.
    pub fn wait_status(&mut self, limit: Duration) -> (ExitStatus, Duration) {
        let start = Instant::now();
        loop {
            if let Some(status) = self.child.try_wait().unwrap() {
                return (status, start.elapsed());
            }
            assert!(start.elapsed() < limit, "still running {limit:?} after the signal");
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    /// Every log line so far.
    pub fn drain_log(&mut self) -> Vec<String> {
        while let Ok(line) = self.log.try_recv() {
            self.lines.push(line);
        }
        self.lines.clone()
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
