//! The async runtime never runs a simulation: with every simulation slot taken by long
//! streams (the paper's five methods each, more computing threads than cores), `GET /health`
//! still answers with p99 under 50 ms.
//!
//! This file holds one test so that no other test of the binary competes for the cores. The
//! server runs on a two-worker runtime like the binary's; the streams are read to the end
//! (unread, their bounded channels would fill and pause the runs, and the cores would idle).
//! The bound is a correctness bound, not a benchmark: a simulation on the runtime would
//! block a worker for seconds, so the p99 would be in seconds, not milliseconds.

use nhlab_server::Config;
use nhlab_tests::{SseReader, TestServer};
use serde_json::{Value, json};
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

const SLOTS: usize = 2;
const REQUESTS: usize = 200;

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn health_answers_fast_while_every_slot_computes() {
    let server =
        TestServer::with_config(Config { max_simulations: SLOTS, ..Config::default() }).await;
    // 10⁸ steps per run, the five default methods: minutes of work on every core.
    let long = json!({"system": "knife_edge", "step": 1e-6, "t_end": 100});
    let mut readers = Vec::new();
    let mut progress = Vec::new();
    for _ in 0..SLOTS {
        let response = server.post_stream("/simulate", &long).await;
        assert_eq!(response.status(), 200);
        let mut events = SseReader::new(response);
        assert_eq!(events.next().await.unwrap().event, "scene");
        // Read on, counting progress events.
        let count = Arc::new(AtomicUsize::new(0));
        progress.push(count.clone());
        readers.push(tokio::spawn(async move {
            while let Some(e) = events.next().await {
                if e.event == "progress" {
                    count.fetch_add(1, Ordering::SeqCst);
                }
            }
        }));
    }
    let client = reqwest::Client::new();
    let get = || async {
        let start = Instant::now();
        let response = client.get(server.at("/health")).send().await.unwrap();
        assert_eq!(response.status(), 200);
        let body: Value = response.json().await.unwrap();
        (start.elapsed(), body)
    };
    // Every slot taken, every run computing. A stream's answer starts before its coordinating
    // task has started all five runs (on the runtime's other worker), so wait for them.
    let started = Instant::now();
    while server.state.active_runs() < 5 * SLOTS && started.elapsed() < Duration::from_secs(5) {
        tokio::time::sleep(Duration::from_millis(1)).await;
    }
    let (_, h) = get().await;
    assert_eq!(h["simulations"], SLOTS);
    assert_eq!(h["active_runs"], 5 * SLOTS);

    let mut latencies = Vec::with_capacity(REQUESTS);
    for _ in 0..REQUESTS {
        let (latency, body) = get().await;
        assert_eq!(body["active_runs"], 5 * SLOTS, "the runs go on");
        latencies.push(latency);
        // Spread the requests over a few seconds of computation.
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    latencies.sort();
    let p50 = latencies[REQUESTS / 2];
    let p99 = latencies[REQUESTS * 99 / 100 - 1];
    let max = latencies[REQUESTS - 1];
    eprintln!("GET /health with {SLOTS} busy slots: p50 {p50:?}, p99 {p99:?}, max {max:?}");
    assert!(p99 < Duration::from_millis(50), "p99 {p99:?} (p50 {p50:?}, max {max:?})");

    // The streams were computing all along: they reported progress meanwhile.
    let progress: Vec<usize> = progress.iter().map(|c| c.load(Ordering::SeqCst)).collect();
    eprintln!("progress events per stream: {progress:?}");
    assert!(progress.iter().all(|&p| p >= 5), "{progress:?}");
    // Closing the streams stops their runs.
    readers.iter().for_each(tokio::task::JoinHandle::abort);
    let closed = Instant::now();
    while server.state.active_runs() > 0 {
        assert!(closed.elapsed() < Duration::from_secs(1), "runs still going");
        tokio::time::sleep(Duration::from_millis(5)).await;
    }
}
