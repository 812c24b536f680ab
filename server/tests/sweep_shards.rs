//! `nhlab sweep` as a user runs it on a cluster: three shards computed by separate
//! processes at once, merged into exactly the bytes of `POST /sweep`'s answer (timing aside,
//! and the same CSV); a shard stopped midway resumed without recomputing its whole cells;
//! and the errors a user meets (a bad spec, a missing shard, a shard given twice, a shard
//! number out of range), each on standard error with exit code 1 or 2.

mod common;

use common::Server;
use std::path::Path;
use std::process::{Command, Output};

const SPEC: &str = r#"{
  "system": "cvt_pendulum", "preset": "rotating-perturbed", "t_end": 30, "points": 100,
  "methods": [{"id": "dla", "alpha": 0.5}, "leapfrog", "dd"],
  "axes": [{"path": "methods.alpha", "linspace": [0.3, 0.7, 4]},
           {"path": "params.epsilon", "values": [0, 0.25, 0.5]}]
}"#;

fn nhlab(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_nhlab"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("nhlab runs")
}

/// A JSON text without its `cpu_ms` values, the only numbers that differ between runs.
fn untimed(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(at) = rest.find("\"cpu_ms\":") {
        out += &rest[..at + 9];
        rest = &rest[at + 9..];
        let end = rest.find([',', '}']).unwrap_or(rest.len());
        rest = &rest[end..];
    }
    out + rest
}

fn ok(output: &Output) -> String {
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    String::from_utf8(output.stdout.clone()).unwrap()
}

#[tokio::test]
async fn shards_merge_into_the_answer_of_post_sweep_and_resume_where_they_stopped() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("spec.json"), SPEC).unwrap();

    // Three shards at once, as an array job runs them.
    let shards: Vec<_> = (0..3)
        .map(|i| {
            Command::new(env!("CARGO_BIN_EXE_nhlab"))
                .current_dir(d)
                .args(["sweep", "spec.json", "--shard", &format!("{i}/3"), "--out"])
                .arg(format!("shard{i}.jsonl"))
                .args(["--threads", "1"])
                .spawn()
                .unwrap()
        })
        .collect();
    for mut s in shards {
        assert!(s.wait().unwrap().success());
    }
    // Shard i holds the cells c with c mod 3 = i: a header line, then three rows a cell.
    let shard1 = std::fs::read_to_string(d.join("shard1.jsonl")).unwrap();
    assert_eq!(shard1.lines().count(), 1 + 4 * 3);
    assert!(shard1.lines().skip(1).all(|l| l.starts_with("{\"cell\":1,")
        || l.starts_with("{\"cell\":4,")
        || l.starts_with("{\"cell\":7,")
        || l.starts_with("{\"cell\":10,")));
    let merged =
        ok(&nhlab(d, &["sweep", "--merge", "shard0.jsonl", "shard1.jsonl", "shard2.jsonl"]));

    // POST /sweep of the same spec: the same bytes but for the timing.
    let server = Server::start(Path::new(env!("CARGO_BIN_EXE_nhlab")), d, |c| {
        c.args(["--addr", "127.0.0.1:0"]);
    });
    let post = |accept: &'static str| {
        let url = format!("{}/sweep", server.url);
        async move {
            let response = reqwest::Client::new()
                .post(url)
                .header("content-type", "application/json")
                .header("accept", accept)
                .body(SPEC)
                .send()
                .await
                .unwrap();
            assert_eq!(response.status(), 200);
            response.text().await.unwrap()
        }
    };
    let answer = post("application/json").await;
    assert_eq!(untimed(&merged), untimed(&answer));
    let csv = post("text/csv").await;
    let merged_csv = ok(&nhlab(
        d,
        &["sweep", "--merge", "shard0.jsonl", "shard1.jsonl", "shard2.jsonl", "--format", "csv"],
    ));
    let no_cpu = |t: &str| -> Vec<String> {
        // cpu_ms is the ninth column.
        t.lines()
            .map(|l| {
                l.split(',')
                    .enumerate()
                    .filter(|(k, _)| *k != 8)
                    .map(|(_, f)| f)
                    .collect::<Vec<_>>()
                    .join(",")
            })
            .collect()
    };
    assert_eq!(no_cpu(&merged_csv), no_cpu(&csv));
    server.terminate();

    // A shard stopped midway, its last line half written: --resume keeps its two whole cells.
    let cut: String = shard1.lines().take(1 + 2 * 3).map(|l| format!("{l}\n")).collect::<String>()
        + &shard1.lines().nth(7).unwrap()[..40];
    std::fs::write(d.join("stopped.jsonl"), cut).unwrap();
    let resumed =
        nhlab(d, &["sweep", "spec.json", "--shard", "1/3", "--out", "stopped.jsonl", "--resume"]);
    let log = String::from_utf8_lossy(&resumed.stderr);
    assert!(resumed.status.success(), "{log}");
    assert!(log.contains("4 cells (2 kept from before)"), "{log}");
    let merged_again =
        ok(&nhlab(d, &["sweep", "--merge", "shard0.jsonl", "stopped.jsonl", "shard2.jsonl"]));
    assert_eq!(untimed(&merged_again), untimed(&merged));
}

#[test]
fn errors_say_what_is_wrong() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("spec.json"), SPEC).unwrap();
    std::fs::write(d.join("bad.json"), SPEC.replace("params.epsilon", "params.nope")).unwrap();
    let fails = |args: &[&str], code: i32, message: &str| {
        let out = nhlab(d, args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(code), "{args:?}: {stderr}");
        assert!(stderr.contains(message), "{args:?}: {stderr}");
    };
    fails(&["sweep", "bad.json"], 1, "bad.json: axes[1].path: the system has no parameter `nope`");
    fails(&["sweep", "missing.json"], 1, "missing.json: No such file");
    fails(&["sweep", "spec.json", "--shard", "3/3"], 2, "0 ≤ I < N");
    ok(&nhlab(d, &["sweep", "spec.json", "--shard", "0/2", "--out", "a.jsonl"]));
    fails(
        &["sweep", "--merge", "a.jsonl"],
        1,
        "6 of 12 cells are missing (cells 1, 3, 5, 7, 9, …), from shard 1/2",
    );
    fails(&["sweep", "--merge", "a.jsonl", "a.jsonl"], 1, "cell 0 is in both a.jsonl and a.jsonl");
    fails(&["sweep", "--merge", "spec.json"], 1, "spec.json: line 1 is not a shard header");
    std::fs::write(d.join("other.json"), SPEC.replace("\"t_end\": 30", "\"t_end\": 20")).unwrap();
    ok(&nhlab(d, &["sweep", "other.json", "--shard", "1/2", "--out", "b.jsonl"]));
    fails(&["sweep", "--merge", "a.jsonl", "b.jsonl"], 1, "shards of different sweeps");
    fails(
        &["sweep", "spec.json", "--shard", "1/2", "--out", "b.jsonl", "--resume"],
        1,
        "of another sweep",
    );
}
