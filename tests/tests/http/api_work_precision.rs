//! `POST /work-precision` against the real server: the levels and steps forms, the order of
//! the knife edge's second-order methods measured from the final errors, the errors of bad
//! fields with their paths, 503 when busy, a client leaving stops the runs and the reference
//! solve (which is then not cached), and the caches (reference and latitude axis) hit on a
//! second request, as `/health` counts them.

use nhlab_server::Config;
use nhlab_tests::TestServer;
use serde_json::{Value, json};
use std::time::Duration;

/// The least-squares slope of log(error) against log(h).
fn slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (xs, ys): (Vec<f64>, Vec<f64>) = points.iter().map(|(h, e)| (h.ln(), e.ln())).unzip();
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

/// `(step, final_error)` of the rows of one method label.
fn curve(rows: &[Value], label: &str) -> Vec<(f64, f64)> {
    rows.iter()
        .filter(|r| r["method"]["label"] == label)
        .map(|r| (r["step"].as_f64().unwrap(), r["final_error"].as_f64().unwrap()))
        .collect()
}

#[tokio::test]
async fn second_order_methods_show_order_two_on_the_knife_edge() {
    let server = TestServer::start().await;
    let body = json!({
        "system": "knife_edge", "preset": "paper", "t_end": 10,
        "methods": ["leapfrog", "dla01", {"id": "dla", "alpha": 0.4}],
        "steps": [0.1, 0.05, 0.025, 0.0125], "repeats": 1,
    });
    let (status, wp) = server.post_json("/work-precision", &body).await;
    assert_eq!(status, 200, "{wp}");
    let rows = wp["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 3 * 4, "one row per method × step");
    for r in rows {
        assert_eq!(r["status"], "ok", "{r}");
        assert!(r["error"].is_null() && r["elapsed_ms"].as_f64().unwrap() >= 0.0, "{r}");
        let h = r["step"].as_f64().unwrap();
        assert_eq!(r["steps"].as_f64().unwrap(), (10.0 / h).round(), "{r}");
        let integrals: Vec<&String> = r["max_error"].as_object().unwrap().keys().collect();
        assert_eq!(integrals, ["constraint", "driver_energy", "energy", "passenger_energy"]);
    }
    for label in ["LF", "DLA^{0,1}"] {
        let c = curve(rows, label);
        let order = slope(&c);
        assert!((order - 2.0).abs() < 0.2, "{label}: fitted order {order} from {c:?}");
        // Each halving divides the error by about four.
        for pair in c.windows(2) {
            let ratio = pair[0].1 / pair[1].1;
            assert!((3.0..5.3).contains(&ratio), "{label}: ratio {ratio} in {c:?}");
        }
    }
    // DLA^0.4 is first order: a test that a wrong order is told apart.
    let first = slope(&curve(rows, "DLA^0.4"));
    assert!((first - 1.0).abs() < 0.2, "DLA^0.4: fitted order {first}");
    let reference = &wp["reference"];
    assert_eq!(reference["cached"], false, "{reference}");
    assert!(reference["evaluations"].as_u64().unwrap() > 0, "{reference}");
    assert!(reference["constraint_residual"].as_f64().unwrap() < 1e-9, "{reference}");
}

#[tokio::test]
async fn levels_halve_the_scenes_step_and_default_to_four() {
    let server = TestServer::start().await;
    let body = json!({"system": "knife_edge", "preset": "paper", "t_end": 20, "levels": 3,
                      "methods": ["dd"], "integrals": ["energy"]});
    let (status, wp) = server.post_json("/work-precision", &body).await;
    assert_eq!(status, 200, "{wp}");
    let h = std::f64::consts::PI / 10.0;
    assert_eq!(wp["scene"]["step"].as_f64(), Some(h));
    let rows = wp["rows"].as_array().unwrap();
    let steps: Vec<u64> = rows.iter().map(|r| r["steps"].as_u64().unwrap()).collect();
    let expected: Vec<u64> = (0..3).map(|k| (20.0 / (h / 2f64.powi(k))).round() as u64).collect();
    assert_eq!(steps, expected);
    for r in rows {
        // The step is rounded so that the run ends at t_end exactly.
        let (step, n) = (r["step"].as_f64().unwrap(), r["steps"].as_f64().unwrap());
        assert!((step * n - 20.0).abs() < 1e-12, "{r}");
        // DD conserves the energy: its largest error is round-off.
        assert!(r["max_error"]["energy"].as_f64().unwrap() < 1e-12, "{r}");
    }
    // No steps, no levels: four levels; the paper's five methods by default.
    let body = json!({"system": "knife_edge", "preset": "paper", "t_end": 5, "repeats": 1});
    let (status, wp) = server.post_json("/work-precision", &body).await;
    assert_eq!(status, 200, "{wp}");
    assert_eq!(wp["rows"].as_array().unwrap().len(), 5 * 4);
    assert_eq!(wp["scene"]["methods"].as_array().unwrap().len(), 5);
    // Given steps and no step: the largest stands for the scene's step, even where the
    // preset's step (π/10) would not fit t_end.
    let body = json!({"system": "knife_edge", "preset": "paper", "t_end": 0.2,
                      "steps": [0.05, 0.1], "methods": ["leapfrog"], "repeats": 1});
    let (status, wp) = server.post_json("/work-precision", &body).await;
    assert_eq!(status, 200, "{wp}");
    assert_eq!(wp["scene"]["step"], 0.1);
    let steps: Vec<u64> =
        wp["rows"].as_array().unwrap().iter().map(|r| r["steps"].as_u64().unwrap()).collect();
    assert_eq!(steps, [4, 2], "rows in the order of the steps given");
}

#[tokio::test]
async fn a_failed_row_has_no_final_error() {
    let server = TestServer::start().await;
    // h = 2.5 on the CVT: the leap-frog diverges (core/tests/it/work_precision.rs).
    let body = json!({"system": "cvt", "t_end": 1000, "steps": [2.5], "methods": ["leapfrog"],
                      "repeats": 1});
    let (status, wp) = server.post_json("/work-precision", &body).await;
    assert_eq!(status, 200, "{wp}");
    let row = &wp["rows"][0];
    assert_eq!(row["status"], "failed", "{row}");
    assert!(row["final_error"].is_null(), "{row}");
    assert!(row["error"].as_str().unwrap().contains("diverged"), "{row}");
}

#[tokio::test]
async fn bad_fields_are_named() {
    let server = TestServer::start().await;
    let base = json!({"system": "knife_edge", "preset": "paper", "t_end": 10});
    let with = |extra: Value| {
        let mut b = base.clone();
        b.as_object_mut().unwrap().extend(extra.as_object().unwrap().clone());
        b
    };
    let cases = [
        (with(json!({"steps": [0.1], "levels": 2})), 422, "levels"),
        (with(json!({"steps": [0.1, -0.1]})), 422, "steps[1]"),
        (with(json!({"steps": [0.1, 0.2, 11]})), 422, "steps[2]"),
        (with(json!({"steps": [0.1, 0]})), 422, "steps[1]"),
        // t_end shorter than the preset's step (π/10): the steps are what is checked.
        (with(json!({"t_end": 0.2, "steps": [0.1, 0.3]})), 422, "steps[1]"),
        (with(json!({"steps": []})), 422, "steps"),
        (with(json!({"steps": vec![0.1; 13]})), 422, "steps"),
        (with(json!({"steps": [0.1, "x"]})), 400, "steps[1]"),
        (with(json!({"levels": 0})), 422, "levels"),
        (with(json!({"levels": 13})), 422, "levels"),
        (with(json!({"levels": 1.5})), 400, "levels"),
        (with(json!({"repeats": 0})), 422, "repeats"),
        (with(json!({"repeats": 11})), 422, "repeats"),
        // 10⁷ steps × 5 methods × 3 repeats: over the 2·10⁷ steps of a JSON request.
        (with(json!({"steps": [1e-6]})), 422, "steps"),
        (with(json!({"levels": 12, "step": 0.01})), 422, "levels"),
        (with(json!({"methods": [{"id": "dla", "alfa": 1}]})), 422, "methods[0].alfa"),
        (with(json!({"integrals": ["latitude"]})), 422, "integrals[0]"),
        (with(json!({"preset": "nope"})), 422, "preset"),
        (with(json!({"points": 10})), 400, "points"),
        (json!({"preset": "paper"}), 400, "system"),
    ];
    for (body, code, path) in cases {
        let (status, err) = server.post_json("/work-precision", &body).await;
        assert_eq!(status, code, "{body}: {err}");
        assert_eq!(err["path"], path, "{body}: {err}");
        assert!(!err["error"].as_str().unwrap().is_empty(), "{err}");
    }
}

#[tokio::test]
async fn a_busy_server_says_503_and_a_leaving_client_stops_the_runs() {
    let server = TestServer::with_config(Config { max_simulations: 1, ..Config::default() }).await;
    let body = json!({"system": "knife_edge", "preset": "paper", "t_end": 10, "steps": [0.1]});
    let (slot, _budget) = server.state.admit(0).expect("a free slot");
    let response =
        reqwest::Client::new().post(server.at("/work-precision")).json(&body).send().await.unwrap();
    assert_eq!(response.status(), 503);
    assert_eq!(response.headers()["retry-after"], "1");
    drop(slot);
    let (status, _) = server.post_json("/work-precision", &body).await;
    assert_eq!(status, 200);

    // 1.5·10⁷ steps of DD: seconds of work; the client gives up after 300 ms.
    let long = json!({"system": "knife_edge", "preset": "paper", "t_end": 150, "steps": [1e-5],
                      "methods": ["dd"], "repeats": 1});
    let client = reqwest::Client::new();
    let send = client.post(server.at("/work-precision")).json(&long).send();
    let waited = tokio::time::timeout(Duration::from_millis(300), send).await;
    assert!(waited.is_err(), "the run should take longer than 300 ms");
    assert_eq!(server.state.active_runs(), 1, "the rows run");
    drop(client);
    let took = server.wait_idle(Duration::from_millis(500)).await;
    eprintln!("work-precision stopped {took:?} after the client left");
}

/// The rotating CVT to t = 10⁴: a reference of about 5·10⁵ Dop853 steps, seconds of work
/// before any row runs.
#[tokio::test]
async fn a_leaving_client_stops_a_long_reference_and_frees_its_slot() {
    let server = TestServer::with_config(Config { max_simulations: 1, ..Config::default() }).await;
    let body = json!({"system": "cvt_pendulum", "preset": "rotating", "t_end": 10000,
                      "steps": [100], "methods": ["leapfrog"], "repeats": 1});
    let send = reqwest::Client::new()
        .post(server.at("/work-precision"))
        .header("content-type", "application/json")
        .body(body.to_string())
        .send();
    let request = tokio::spawn(send);
    // Wait until it is admitted and computing (its check may take a while on a busy machine).
    let start = std::time::Instant::now();
    loop {
        let h = server.health().await;
        if (h["simulations"].as_u64(), h["active_runs"].as_u64()) == (Some(1), Some(1)) {
            break;
        }
        assert!(!request.is_finished(), "the request ended before it was seen computing: {h}");
        assert!(start.elapsed() < Duration::from_secs(20), "never admitted: {h}");
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    tokio::time::sleep(Duration::from_millis(100)).await;
    assert!(!request.is_finished(), "the reference should take longer than that");
    request.abort(); // the client goes away: its connection closes
    let took = server.wait_idle(Duration::from_secs(1)).await;
    eprintln!("the reference stopped and its slot was free {took:?} after the client left");
    let h = server.health().await;
    assert_eq!(h["simulations"], 0, "{h}");
    // A cancelled reference is not the scene's: nothing is cached.
    assert_eq!(h["cache"]["reference"], json!({"hits": 0, "misses": 1, "entries": 0}), "{h}");
}

#[tokio::test]
async fn a_second_request_reuses_the_reference_and_gives_the_same_numbers() {
    let server = TestServer::start().await;
    let body = json!({"system": "knife_edge", "preset": "paper-perturbed", "t_end": 30,
                      "levels": 2, "methods": ["leapfrog", "dd"], "repeats": 1});
    let (status, first) = server.post_json("/work-precision", &body).await;
    assert_eq!(status, 200, "{first}");
    assert_eq!(first["reference"]["cached"], false);
    let (status, second) = server.post_json("/work-precision", &body).await;
    assert_eq!(status, 200, "{second}");
    assert_eq!(second["reference"]["cached"], true);
    let strip = |v: &Value| {
        let mut v = v.clone();
        v["reference"]["cached"] = Value::Null;
        for r in v["rows"].as_array_mut().unwrap() {
            r["elapsed_ms"] = Value::Null; // wall time: the one number that may differ
        }
        v
    };
    assert_eq!(strip(&first), strip(&second), "the same numbers from the cached reference");
    let h = server.health().await;
    assert_eq!(h["cache"]["reference"], json!({"hits": 1, "misses": 1, "entries": 1}), "{h}");
    // Another t_end is another reference.
    let mut other = body.clone();
    other["t_end"] = json!(31);
    let (_, third) = server.post_json("/work-precision", &other).await;
    assert_eq!(third["reference"]["cached"], false);
}

#[tokio::test]
async fn the_latitude_axis_is_computed_once_per_scene_across_endpoints() {
    let server = TestServer::start().await;
    let scene = json!({"system": "cvt_pendulum", "preset": "oscillating", "t_end": 30,
                       "integrals": ["latitude"], "methods": ["leapfrog"]});
    let latitude = |h: &Value| h["cache"]["latitude"].clone();
    assert_eq!(latitude(&server.health().await), json!({"hits": 0, "misses": 0, "entries": 0}));
    let (status, a) = server.post_json("/simulate", &scene).await;
    assert_eq!(status, 200, "{a}");
    assert_eq!(latitude(&server.health().await), json!({"hits": 0, "misses": 1, "entries": 1}));
    let (_, b) = server.post_json("/simulate", &scene).await;
    assert_eq!(latitude(&server.health().await), json!({"hits": 1, "misses": 1, "entries": 1}));
    assert_eq!(a["runs"][0]["series"], b["runs"][0]["series"], "the same latitude series");
    // Another t_end or step: the same axis. Another start: another axis.
    let mut wp = scene.clone();
    wp["steps"] = json!([0.1, 0.05]);
    wp["repeats"] = json!(1);
    let (status, w) = server.post_json("/work-precision", &wp).await;
    assert_eq!(status, 200, "{w}");
    assert!(w["rows"][0]["max_error"]["latitude"].as_f64().unwrap() > 0.0, "{w}");
    let card = json!({"methods": ["leapfrog"], "scenes": [
        {"system": "cvt_pendulum", "preset": "oscillating", "t_end": 60, "integrals": ["latitude"]},
        {"system": "cvt_pendulum", "preset": "rotating", "t_end": 60, "integrals": ["latitude"]},
    ]});
    let (status, c) = server.post_json("/scorecard", &card).await;
    assert_eq!(status, 200, "{c}");
    assert_eq!(latitude(&server.health().await), json!({"hits": 3, "misses": 2, "entries": 2}));
}

#[tokio::test]
async fn openapi_documents_work_precision() {
    let server = TestServer::start().await;
    let doc: Value = reqwest::get(server.at("/openapi.json")).await.unwrap().json().await.unwrap();
    let op = &doc["paths"]["/work-precision"]["post"];
    assert!(op.is_object(), "{}", doc["paths"]);
    for code in ["200", "400", "422", "503"] {
        assert!(op["responses"][code].is_object(), "{code} undocumented");
    }
    let schemas = &doc["components"]["schemas"];
    for name in ["WorkPrecisionRequest", "WorkPrecisionResponse", "WorkPrecisionRow"] {
        assert!(schemas[name].is_object(), "{name} missing");
    }
    assert_eq!(schemas["WorkPrecisionRequest"]["properties"]["steps"]["maxItems"], 12);
    assert!(schemas["Health"]["properties"]["cache"].is_object(), "{}", schemas["Health"]);
    assert!(schemas["Health"]["properties"]["formulas"].is_object(), "{}", schemas["Health"]);
}
