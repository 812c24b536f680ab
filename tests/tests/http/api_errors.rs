//! Bad input to `POST /simulate`: each gets a 4xx with a JSON body `{"error", "path"}` whose
//! path names the offending field and whose message says what is allowed.

use nhlab_tests::TestServer;
use serde_json::{Value, json};

/// Posts `body` (raw text) and checks the status, the path and that the message contains
/// each of `mentions`.
async fn rejects(
    server: &TestServer,
    body: &str,
    status: u16,
    path: Option<&str>,
    mentions: &[&str],
) {
    for accept in ["application/json", "text/event-stream"] {
        let response = reqwest::Client::new()
            .post(server.at("/simulate"))
            .header("content-type", "application/json")
            .header("accept", accept)
            .body(body.to_owned())
            .send()
            .await
            .expect("request succeeds");
        assert_eq!(response.status().as_u16(), status, "{body} ({accept})");
        let content_type = response.headers()["content-type"].to_str().unwrap().to_owned();
        assert_eq!(content_type, "application/json", "{body}");
        let error: Value = response.json().await.expect("a JSON error");
        assert_eq!(error["path"].as_str(), path, "{body}: {error}");
        let message = error["error"].as_str().expect("an error message");
        for m in mentions {
            assert!(message.contains(m), "{body}: '{message}' does not mention '{m}'");
        }
    }
}

#[tokio::test]
async fn malformed_json_and_wrong_types_are_400() {
    let s = TestServer::start().await;
    rejects(&s, r#"{"system": "knife_edge","#, 400, None, &["EOF"]).await;
    rejects(&s, "not json", 400, None, &["malformed JSON", "JSON object"]).await;
    // JSON that is not an object; serde alone would read `["knife_edge"]` as a scene.
    for (body, kind) in [
        ("[]", "an array"),
        (r#" ["knife_edge"]"#, "an array"),
        ("\"knife_edge\"", "a string"),
        ("null", "null"),
        ("5", "a number"),
    ] {
        rejects(&s, body, 400, None, &["must be a JSON object", kind]).await;
    }
    // `[]` would otherwise be a scorecard with every default: all methods on the paper's scenes.
    for route in ["/scorecard", "/work-precision"] {
        let response = s.post_text(route, "[]").await;
        assert_eq!(response.status(), 400, "{route}");
        let error: Value = response.json().await.unwrap();
        assert!(error["error"].as_str().unwrap().contains("must be a JSON object"), "{error}");
    }
    rejects(&s, "", 400, None, &["EOF"]).await;
    rejects(&s, r#"{"system": 5}"#, 400, Some("system"), &["string"]).await;
    rejects(&s, r#"{"step": 0.1}"#, 400, Some("system"), &["missing field `system`"]).await;
    rejects(&s, r#"{"system": "knife_edge", "q": "0,0,0"}"#, 400, Some("q"), &["sequence"]).await;
    rejects(
        &s,
        r#"{"system": "knife_edge", "params": {"epsilon": "0.1"}}"#,
        400,
        Some("params.epsilon"),
        &["f64"],
    )
    .await;
    rejects(
        &s,
        r#"{"system": "knife_edge", "methods": [{"alpha": 0.4}]}"#,
        400,
        Some("methods[0].id"),
        &["missing field `id`"],
    )
    .await;
    rejects(
        &s,
        r#"{"system": "knife_edge", "methods": [{"id": "dla", "alpha": "x"}]}"#,
        400,
        Some("methods[0].alpha"),
        &[],
    )
    .await;
    rejects(&s, r#"{"system": "knife_edge", "points": 1.5}"#, 400, Some("points"), &[]).await;
    // A method's `params` object: its errors point into it.
    let dla = |method: &str| format!(r#"{{"system": "knife_edge", "methods": [{method}]}}"#);
    let cases: [(&str, u16, &str, &[&str]); 6] = [
        (r#"{"id": "dla", "params": {"alpha": "x"}}"#, 400, "methods[0].params.alpha", &["f64"]),
        (r#"{"id": "dla", "params": [0.4]}"#, 400, "methods[0].params", &["object"]),
        (r#"{"id": "dla", "params": {"alfa": 1}}"#, 422, "methods[0].params.alfa", &["alpha"]),
        (r#"{"id": "dla", "params": {"alpha": 7}}"#, 422, "methods[0].params.alpha", &["(0, 1]"]),
        (r#"{"id": "dla", "alpha": 0.4, "params": {}}"#, 400, "methods[0]", &["not both"]),
        (r#"{"id": "dla", "alpha": 0.4, "alpha": 0.3}"#, 400, "methods[0]", &["twice"]),
    ];
    for (method, status, path, words) in cases {
        rejects(&s, &dla(method), status, Some(path), words).await;
    }
}

#[tokio::test]
async fn unknown_fields_are_400_naming_the_field() {
    let s = TestServer::start().await;
    let body = r#"{"system": "knife_edge", "tend": 10}"#;
    rejects(&s, body, 400, Some("tend"), &["unknown field `tend`", "t_end"]).await;
}

#[tokio::test]
async fn unknown_names_are_422_listing_the_valid_ones() {
    let s = TestServer::start().await;
    rejects(
        &s,
        r#"{"system": "skate"}"#,
        422,
        Some("system"),
        &["skate", "knife_edge", "cvt_pendulum"],
    )
    .await;
    rejects(
        &s,
        r#"{"system": "knife_edge", "preset": "rotating"}"#,
        422,
        Some("preset"),
        &["rotating", "paper", "paper-perturbed"],
    )
    .await;
    rejects(
        &s,
        r#"{"system": "knife_edge", "params": {"eps": 0.1}}"#,
        422,
        Some("params.eps"),
        &["eps", "epsilon"],
    )
    .await;
    let body = r#"{"system": "knife_edge", "methods": [{"id": "dla"}, {"id": "nosuch"}]}"#;
    rejects(&s, body, 422, Some("methods[1].id"), &["nosuch", "dla, dla01, leapfrog, dd"]).await;
    let body = r#"{"system": "knife_edge", "methods": ["leapfrog", "euler"]}"#;
    rejects(&s, body, 422, Some("methods[1].id"), &["euler", "leapfrog"]).await;
    let body = r#"{"system": "knife_edge", "methods": [{"id": "dla", "beta": 1}]}"#;
    rejects(&s, body, 422, Some("methods[0].beta"), &["beta", "alpha"]).await;
    let body = r#"{"system": "knife_edge", "methods": [{"id": "leapfrog", "alpha": 0.5}]}"#;
    rejects(&s, body, 422, Some("methods[0].alpha"), &["none"]).await;
    let body = r#"{"system": "knife_edge", "integrals": ["energy", "momentum"]}"#;
    rejects(&s, body, 422, Some("integrals[1]"), &["momentum", "passenger_energy", "latitude"])
        .await;
}

#[tokio::test]
async fn an_integral_the_system_lacks_is_422() {
    let s = TestServer::start().await;
    let body = r#"{"system": "knife_edge", "integrals": ["energy", "latitude"]}"#;
    rejects(
        &s,
        body,
        422,
        Some("integrals[1]"),
        &["knife_edge has no integral 'latitude'", "passenger_energy"],
    )
    .await;
}

#[tokio::test]
async fn out_of_range_parameters_are_422_with_the_range() {
    let s = TestServer::start().await;
    rejects(
        &s,
        r#"{"system": "knife_edge", "params": {"epsilon": 1}}"#,
        422,
        Some("params.epsilon"),
        &["(-1, 1)"],
    )
    .await;
    rejects(
        &s,
        r#"{"system": "knife_edge", "methods": [{"id": "dla", "alpha": 7}]}"#,
        422,
        Some("methods[0].alpha"),
        &["alpha = 7"],
    )
    .await;
}

/// A huge or tiny number comes back as written, not as its 300 decimal digits.
#[tokio::test]
async fn extreme_values_are_echoed_in_exponent_form() {
    let s = TestServer::start().await;
    let cases = [
        (
            r#"{"system": "cvt_pendulum", "params": {"epsilon": 1e308}}"#,
            "params.epsilon",
            "= 1e308 is",
        ),
        (
            r#"{"system": "knife_edge", "methods": [{"id": "dla", "alpha": -1e300}]}"#,
            "methods[0].alpha",
            "= -1e300 is",
        ),
        (r#"{"system": "knife_edge", "step": -1e-300}"#, "step", "got -1e-300"),
        (r#"{"system": "knife_edge", "t_end": -1e300}"#, "t_end", "t_end = -1e300 must"),
    ];
    for (body, path, words) in cases {
        rejects(&s, body, 422, Some(path), &[words]).await;
    }
    let response = s.post_text("/simulate", r#"{"system": "knife_edge", "t_end": -1e300}"#).await;
    let error: Value = response.json().await.expect("a JSON error");
    assert!(error["error"].as_str().unwrap().len() < 100, "{error}");
}

#[tokio::test]
async fn wrong_lengths_and_inconsistent_velocities_are_422() {
    let s = TestServer::start().await;
    rejects(
        &s,
        r#"{"system": "knife_edge", "q": [0, 0]}"#,
        422,
        Some("q"),
        &["3 components", "got 2"],
    )
    .await;
    rejects(
        &s,
        r#"{"system": "knife_edge", "v": [0, 0, 1, 0]}"#,
        422,
        Some("v"),
        &["3 components", "got 4"],
    )
    .await;
    // At ζ = π/2 the knife edge may not move along x₁.
    let body = r#"{"system": "knife_edge", "q": [0, 0, 1.5707963267948966], "v": [1, 0, 1]}"#;
    rejects(&s, body, 422, Some("v"), &["inconsistent initial velocity", "|A(q) v| = 1.000e0"])
        .await;
}

#[tokio::test]
async fn steps_and_points_out_of_bounds_are_422() {
    let s = TestServer::start().await;
    rejects(&s, r#"{"system": "knife_edge", "step": 0}"#, 422, Some("step"), &["positive"]).await;
    rejects(&s, r#"{"system": "knife_edge", "step": -0.1}"#, 422, Some("step"), &["positive"])
        .await;
    rejects(
        &s,
        r#"{"system": "knife_edge", "t_end": 0.1}"#,
        422,
        Some("t_end"),
        &["at least one step"],
    )
    .await;
    rejects(
        &s,
        r#"{"system": "knife_edge", "points": 0}"#,
        422,
        Some("points"),
        &["between 1 and 100000"],
    )
    .await;
    rejects(&s, r#"{"system": "knife_edge", "points": -5}"#, 422, Some("points"), &["between 1"])
        .await;
    rejects(&s, r#"{"system": "knife_edge", "points": 1000000}"#, 422, Some("points"), &["100000"])
        .await;
    rejects(&s, r#"{"system": "knife_edge", "methods": []}"#, 422, Some("methods"), &["empty"])
        .await;
    rejects(&s, r#"{"system": "knife_edge", "integrals": []}"#, 422, Some("integrals"), &["empty"])
        .await;
    let many =
        format!(r#"{{"system": "knife_edge", "methods": [{}]}}"#, vec![r#""dd""#; 17].join(","));
    rejects(&s, &many, 422, Some("methods"), &["17 methods", "16"]).await;
    // 10¹⁴ steps: over both the JSON and the stream limit, named in the error.
    rejects(
        &s,
        r#"{"system": "knife_edge", "step": 1e-12}"#,
        422,
        Some("t_end"),
        &["steps", "limit"],
    )
    .await;
}

#[tokio::test]
async fn the_json_step_limit_points_to_the_stream_where_there_is_one() {
    let s = TestServer::start().await;
    // 10⁸ steps: over the JSON limit (2·10⁷), within the stream's (2·10⁸).
    let body = json!({"system": "knife_edge", "step": 1e-6, "t_end": 100}).to_string();
    let response = s.post_text("/simulate", body).await;
    assert_eq!(response.status(), 422);
    let error: Value = response.json().await.unwrap();
    assert_eq!(error["path"], "t_end");
    let message = error["error"].as_str().unwrap();
    assert!(message.contains("20000000") && message.contains("text/event-stream"), "{message}");
    // The endpoints that answer only in JSON do not point to a stream they cannot give.
    let scene = json!({"system": "knife_edge", "step": 1e-6, "t_end": 100});
    for (route, body) in [
        ("/work-precision", scene.clone()),
        ("/scorecard", json!({"scenes": [scene], "methods": ["leapfrog"]})),
    ] {
        let response = reqwest::Client::new().post(s.at(route)).json(&body).send().await.unwrap();
        assert_eq!(response.status(), 422, "{route}");
        let error: Value = response.json().await.unwrap();
        let message = error["error"].as_str().unwrap();
        assert!(message.contains("20000000") && !message.contains("stream"), "{route}: {message}");
    }
}

#[tokio::test]
async fn non_finite_numbers_are_rejected_with_their_path() {
    let s = TestServer::start().await;
    // JSON has no NaN or infinity; 1e999 overflows f64.
    rejects(&s, r#"{"system": "knife_edge", "q": [0, 1e999, 0]}"#, 400, Some("q[1]"), &["finite"])
        .await;
    rejects(&s, r#"{"system": "knife_edge", "step": -1e999}"#, 400, Some("step"), &["finite"])
        .await;
    rejects(
        &s,
        r#"{"system": "knife_edge", "params": {"epsilon": 1e999}}"#,
        400,
        Some("params.epsilon"),
        &["finite"],
    )
    .await;
    rejects(
        &s,
        r#"{"system": "knife_edge", "methods": [{"id": "dla", "alpha": 1e400}]}"#,
        400,
        Some("methods[0].alpha"),
        &["finite"],
    )
    .await;
    rejects(
        &s,
        r#"{"system": "knife_edge", "t_end": NaN}"#,
        400,
        Some("t_end"),
        &["malformed JSON"],
    )
    .await;
    rejects(&s, r#"{"system": "knife_edge", "t_end": "NaN"}"#, 400, Some("t_end"), &["f64"]).await;
}

#[tokio::test]
async fn oversized_bodies_are_413_json() {
    let s = TestServer::start().await;
    let body = format!(r#"{{"system": "knife_edge", "q": [{}]}}"#, vec!["0"; 100_000].join(","));
    let response = s.post_text("/simulate", body).await;
    assert_eq!(response.status(), 413);
    let error: Value = response.json().await.unwrap();
    assert!(
        error["error"].as_str().unwrap().contains("exceeds the limit of 65536 bytes"),
        "{error}"
    );
}

#[tokio::test]
async fn wrong_methods_are_405_json() {
    let s = TestServer::start().await;
    let response = reqwest::get(s.at("/simulate")).await.unwrap();
    assert_eq!(response.status(), 405);
    let error: Value = response.json().await.unwrap();
    assert!(error["error"].as_str().unwrap().contains("POST /simulate"), "{error}");
}
