//! The binary out of file descriptors: accept fails with `EMFILE`, the server says so once,
//! backs off instead of spinning or stopping, and answers again as soon as descriptors are
//! free; and the connection cap it derives from the descriptor limit.

mod common;

use common::Server;
use std::net::TcpStream;
use std::process::Command;
use std::time::{Duration, Instant};

const BINARY: &str = env!("CARGO_BIN_EXE_nhlab");

/// The binary under `ulimit -n files`.
fn with_open_files(files: u32, extra: &[&str]) -> Server {
    let mut command = Command::new("sh");
    command.args(["-c", &format!("ulimit -n {files} && exec \"$0\" \"$@\""), BINARY]);
    Server::spawn(command, &std::env::temp_dir(), |c| {
        c.args(["--addr", "127.0.0.1:0"]).args(extra);
    })
}

async fn health_status(url: &str) -> Option<u16> {
    let client = reqwest::Client::builder().timeout(Duration::from_secs(2)).build().unwrap();
    client.get(format!("{url}/health")).send().await.ok().map(|r| r.status().as_u16())
}

#[tokio::test]
async fn out_of_descriptors_the_server_backs_off_and_recovers() {
    // A cap above the descriptor limit, so that accept runs out of descriptors first.
    let mut server = with_open_files(48, &["--max-connections", "1000"]);
    let address = server.url.trim_start_matches("http://").to_owned();
    // More connections than descriptors: the kernel completes them (listen backlog), the
    // server cannot take them all.
    let clients: Vec<TcpStream> = (0..80).map(|_| TcpStream::connect(&address).unwrap()).collect();
    server.wait_for("cannot accept connections");
    // Well into the burst, the error is logged once (not once per retry).
    tokio::time::sleep(Duration::from_millis(600)).await;
    let log = server.drain_log();
    let logged = log.iter().filter(|l| l.contains("cannot accept connections")).count();
    assert_eq!(logged, 1, "{log:#?}");

    drop(clients);
    let start = Instant::now();
    loop {
        if health_status(&server.url).await == Some(200) {
            break;
        }
        assert!(start.elapsed() < Duration::from_secs(10), "{:#?}", server.drain_log());
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    eprintln!("answering {:?} after the clients left", start.elapsed());
    server.wait_for("accepting connections again");
    server.terminate();
}

#[test]
fn the_default_cap_follows_the_descriptor_limit() {
    // 100 descriptors, 64 kept free: at most 36 connections. The cap reached is logged.
    let mut server = with_open_files(100, &["--header-timeout", "600"]);
    let address = server.url.trim_start_matches("http://").to_owned();
    let clients: Vec<TcpStream> = (0..40).map(|_| TcpStream::connect(&address).unwrap()).collect();
    let line = server.wait_for("limit max_connections");
    assert!(line.contains("36 connections open"), "{line}");
    assert!(!server.drain_log().iter().any(|l| l.contains("cannot accept")));
    drop(clients);
    server.terminate();
}
