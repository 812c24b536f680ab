//! Every limit of the binary is a flag and an environment variable, documented in `--help`,
//! and takes effect (seen in `GET /systems`, `GET /health` and the answers).

mod common;

use common::Server;
use serde_json::{Value, json};
use std::path::Path;
use std::process::Command;

const BINARY: &str = env!("CARGO_BIN_EXE_nhlab");

#[test]
fn help_documents_every_flag_and_its_variable() {
    let out = Command::new(BINARY).arg("--help").output().unwrap();
    assert!(out.status.success());
    let help = String::from_utf8(out.stdout).unwrap();
    for (flag, env) in [
        ("--addr", "NHLAB_ADDR"),
        ("--max-simulations", "NHLAB_MAX_SIMULATIONS"),
        ("--max-steps-json", "NHLAB_MAX_STEPS_JSON"),
        ("--max-steps-stream", "NHLAB_MAX_STEPS_STREAM"),
        ("--max-points", "NHLAB_MAX_POINTS"),
        ("--max-methods", "NHLAB_MAX_METHODS"),
        ("--max-body-bytes", "NHLAB_MAX_BODY_BYTES"),
        ("--cors-origin", "NHLAB_CORS_ORIGIN"),
        ("--shutdown-grace", "NHLAB_SHUTDOWN_GRACE"),
        ("--header-timeout", "NHLAB_HEADER_TIMEOUT"),
        ("--body-timeout", "NHLAB_BODY_TIMEOUT"),
        ("--write-timeout", "NHLAB_WRITE_TIMEOUT"),
        ("--max-connections", "NHLAB_MAX_CONNECTIONS"),
    ] {
        assert!(help.contains(flag) && help.contains(env), "{flag} / {env} missing:\n{help}");
    }
}

#[test]
fn version_names_the_binary() {
    let out = Command::new(BINARY).arg("--version").output().unwrap();
    assert!(out.status.success());
    let version = String::from_utf8(out.stdout).unwrap();
    assert_eq!(version.trim(), format!("nhlab {}", env!("CARGO_PKG_VERSION")));
}

#[test]
fn bad_values_stop_the_binary_with_a_message() {
    for args in [
        &["--max-simulations", "0"][..],
        &["--cors-origin", "lab.example.org"],
        &["--shutdown-grace", "4000"],
        &["--max-points", "many"],
        &["--header-timeout", "0"],
        &["--body-timeout", "0.0"],
        &["--write-timeout", "forever"],
        &["--max-connections", "0"],
    ] {
        let out = Command::new(BINARY).args(args).env_remove("NHLAB_ADDR").output().unwrap();
        assert!(!out.status.success(), "{args:?} accepted");
        let err = String::from_utf8(out.stderr).unwrap();
        assert!(err.contains(args[0]), "{args:?}: {err}");
    }
}

#[tokio::test]
async fn flags_and_environment_set_the_limits() {
    let server = Server::start(Path::new(BINARY), &std::env::temp_dir(), |c| {
        c.args(["--addr", "127.0.0.1:0", "--max-points", "50", "--max-body-bytes", "2000"])
            .args(["--cors-origin", "https://a.example,https://b.example"])
            .env("NHLAB_MAX_SIMULATIONS", "3")
            .env("NHLAB_MAX_METHODS", "2")
            .env("NHLAB_MAX_STEPS_JSON", "1000")
            .env("NHLAB_MAX_STEPS_STREAM", "2000")
            .args(["--max-formula-chars", "30", "--max-formula-depth", "3"])
            .env("NHLAB_MAX_FORMULA_PARAMETERS", "1")
            .args(["--max-sweep-cells", "7"])
            .env("NHLAB_MAX_SWEEP_STEPS", "9000");
    });
    let url = &server.url;
    let systems: Value =
        reqwest::get(format!("{url}/systems")).await.unwrap().json().await.unwrap();
    assert_eq!(
        systems["limits"],
        json!({"max_steps_json": 1000, "max_steps_stream": 2000, "max_points": 50,
               "max_methods": 2, "max_body_bytes": 2000, "max_simulations": 3,
               "formula_chars": 30, "formula_depth": 3, "formula_parameters": 1,
               "max_sweep_cells": 7, "max_sweep_steps": 9000})
    );
    let health: Value = reqwest::get(format!("{url}/health")).await.unwrap().json().await.unwrap();
    assert_eq!(health["max_simulations"], 3);

    let client = reqwest::Client::new();
    let post = |body: Value| client.post(format!("{url}/simulate")).json(&body).send();
    let error: Value = post(json!({"system": "knife_edge", "methods": ["dd", "dd", "dd"]}))
        .await
        .unwrap()
        .json()
        .await
        .unwrap();
    assert!(error["error"].as_str().unwrap().contains("limit of 2"), "{error}");
    let error: Value = post(json!({"system": "knife_edge", "step": 0.01, "t_end": 20}))
        .await
        .unwrap()
        .json()
        .await
        .unwrap();
    assert!(error["error"].as_str().unwrap().contains("limit of 1000"), "{error}");
    let response = post(json!({"system": "knife_edge", "q": vec![0; 1000]})).await.unwrap();
    assert_eq!(response.status(), 413);
    // The formula limits.
    let custom = |u: &str, parameters: Value| {
        json!({"system": {"passenger": ["x", "y"], "driver": "z", "parameters": parameters,
                          "passenger_potential": u, "driver_potential": "0",
                          "constraints": [["1", "z"]]},
               "q": [0, 0, 0], "v": [0, 0, 1], "t_end": 1, "methods": ["leapfrog"], "points": 10})
    };
    for (body, path, mention) in [
        (custom(&"x+".repeat(20), json!({})), "system.passenger_potential", "at most 30"),
        (custom("((((x))))", json!({})), "system.passenger_potential", "deeper than 3"),
        (custom("x", json!({"a": 1, "b": 2})), "system.parameters", "at most 1"),
    ] {
        let error: Value = post(body).await.unwrap().json().await.unwrap();
        assert_eq!(error["path"], path, "{error}");
        assert!(error["error"].as_str().unwrap().contains(mention), "{error}");
    }
    let ok = post(custom("x^2", json!({"a": 1}))).await.unwrap();
    assert_eq!(ok.status(), 200);
    for (origin, allowed) in [("https://b.example", true), ("https://c.example", false)] {
        let response =
            client.get(format!("{url}/systems")).header("origin", origin).send().await.unwrap();
        let header = response.headers().get("access-control-allow-origin");
        assert_eq!(header.is_some(), allowed, "{origin}");
    }
    server.terminate();
}
