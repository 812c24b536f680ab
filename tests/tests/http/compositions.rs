//! Compositions through the API: a method's `composition` runs everywhere a method does
//! (`/simulate` as JSON and SSE, `/work-precision`, `/scorecard`), labelled `LF∘p4s3`;
//! `GET /systems` lists the schemes; a method that is not symmetric, or an unknown scheme, is a
//! 422 that names the field and says why.

use nhlab_tests::{SseReader, TestServer};
use serde_json::{Value, json};

fn lf(composition: &str) -> Value {
    json!({"id": "leapfrog", "composition": composition})
}

#[tokio::test]
async fn systems_lists_the_compositions_and_who_may_take_them() {
    let s = TestServer::start().await;
    let systems: Value = reqwest::get(s.at("/systems")).await.unwrap().json().await.unwrap();
    let listed: Vec<(String, u64, u64)> = systems["compositions"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            let sum: f64 =
                c["coefficients"].as_array().unwrap().iter().filter_map(Value::as_f64).sum();
            assert!((sum - 1.0).abs() < 1e-15, "{c}");
            (
                c["id"].as_str().unwrap().into(),
                c["order"].as_u64().unwrap(),
                c["stages"].as_u64().unwrap(),
            )
        })
        .collect();
    let expected = [("p4s3", 4, 3), ("p4s5", 4, 5), ("p6s9", 6, 9), ("p8s15", 8, 15)]
        .map(|(id, order, stages)| (id.to_owned(), order, stages));
    assert_eq!(listed, expected);
    let composable: Vec<&str> = systems["methods"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|m| m["composable"] == true)
        .map(|m| m["id"].as_str().unwrap())
        .collect();
    assert_eq!(composable, ["dla", "dla01", "leapfrog", "dd", "dd_avf", "rattle", "spark"]);
    // Where compositions stop below the scheme's order (measured, docs/high-order.md).
    let limits: Vec<(&str, u64)> = systems["methods"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|m| Some((m["id"].as_str()?, m["composed_order_limit"].as_u64()?)))
        .collect();
    assert_eq!(limits, [("leapfrog", 4), ("dd", 4), ("dd_avf", 4)]);
}

#[tokio::test]
async fn a_composed_method_runs_with_its_label_and_full_steps() {
    let s = TestServer::start().await;
    let body = json!({"system": "knife_edge", "preset": "paper", "step": 0.1, "t_end": 20, "points": 50,
                      "methods": ["leapfrog", lf("p4s3"), {"id": "dd", "composition": "p8s15"},
                                  {"id": "dla", "params": {"alpha": 0.5}, "composition": "p6s9"}]});
    let (status, answer) = s.post_json("/simulate", &body).await;
    assert_eq!(status, 200, "{answer}");
    let runs = answer["runs"].as_array().unwrap();
    let labels: Vec<&str> = runs.iter().map(|r| r["method"]["label"].as_str().unwrap()).collect();
    assert_eq!(labels, ["LF", "LF∘p4s3", "DD∘p8s15", "DLA^0.5∘p6s9"]);
    assert_eq!(runs[1]["method"]["composition"], "p4s3");
    assert!(runs[0]["method"].get("composition").is_none(), "{}", runs[0]);
    for run in runs {
        // `steps` counts full steps, and the series sample once per full step.
        assert_eq!(
            (run["status"].as_str(), run["steps"].as_u64()),
            (Some("ok"), Some(200)),
            "{run}"
        );
        assert_eq!(run["series"]["energy"]["t"].as_array().unwrap().len(), 50);
    }
    // Order 4 against order 2 at the same step: the composed LF's energy error is smaller.
    let max = |run: &Value| run["series"]["energy"]["verdict"]["max"].as_f64().unwrap();
    assert!(max(&runs[1]) < 0.01 * max(&runs[0]), "{} vs {}", runs[1], runs[0]);
}

#[tokio::test]
async fn a_composed_method_streams() {
    let s = TestServer::start().await;
    let body = json!({"system": "cvt_pendulum", "preset": "rotating", "t_end": 50, "points": 20,
                      "methods": [lf("p6s9")]});
    let events = SseReader::new(s.post_stream("/simulate", &body).await).collect().await;
    let run = events.iter().find(|e| e.event == "run").expect("a run event");
    assert_eq!(run.data["method"]["label"], "LF∘p6s9", "{}", run.data);
    assert_eq!(run.data["status"], "ok");
    assert!(events.iter().any(|e| e.event == "done"));
}

#[tokio::test]
async fn only_symmetric_methods_compose_and_the_error_says_why() {
    let s = TestServer::start().await;
    let cases = [
        // A type error is a 400, as for any field; the others are 422.
        (json!({"id": "rk4", "composition": "p4s3"}), "methods[1].composition", "not symmetric"),
        (
            json!({"id": "dla", "alpha": 0.4, "composition": "p4s3"}),
            "methods[1].composition",
            "α = 0.5",
        ),
        (
            json!({"id": "dla", "params": {"alpha": 0.4}, "composition": "p4s3"}),
            "methods[1].composition",
            "α = 0.5",
        ),
        (lf("p5s3"), "methods[1].composition", "valid compositions: p4s3, p4s5, p6s9, p8s15"),
        (
            json!({"id": "leapfrog", "composition": 4}),
            "methods[1].composition",
            "expected a string",
        ),
    ];
    for (method, path, mentions) in cases {
        let body = json!({"system": "knife_edge", "methods": ["leapfrog", method]});
        let (status, error) = s.post_json("/simulate", &body).await;
        assert_eq!(status, if mentions == "expected a string" { 400 } else { 422 }, "{error}");
        assert_eq!(error["path"], path, "{error}");
        assert!(error["error"].as_str().unwrap().contains(mentions), "{error}");
    }
}

#[tokio::test]
async fn work_precision_shows_the_composed_order() {
    let s = TestServer::start().await;
    let body = json!({"system": "knife_edge", "preset": "paper", "t_end": 10, "repeats": 1,
                      "methods": [lf("p4s3"), {"id": "dla01", "composition": "p6s9"}],
                      "steps": [0.2, 0.1, 0.05]});
    let (status, wp) = s.post_json("/work-precision", &body).await;
    assert_eq!(status, 200, "{wp}");
    let rows = wp["rows"].as_array().unwrap();
    for (label, order) in [("LF∘p4s3", 4.0), ("DLA^{0,1}∘p6s9", 6.0)] {
        let errors: Vec<f64> = rows
            .iter()
            .filter(|r| r["method"]["label"] == label)
            .map(|r| r["final_error"].as_f64().unwrap())
            .collect();
        assert_eq!(errors.len(), 3, "{label}: {rows:?}");
        let p = (errors[0] / errors[2]).log2() / 2.0;
        assert!((p - order).abs() < 0.3, "{label}: order {p} from {errors:?}");
    }
}

#[tokio::test]
async fn the_scorecard_measures_composed_methods() {
    let s = TestServer::start().await;
    let body = json!({"methods": [lf("p4s3"), {"id": "dd", "composition": "p4s5"}],
                      "scenes": [{"system": "cvt_pendulum", "preset": "rotating-perturbed", "t_end": 100}]});
    let (status, card) = s.post_json("/scorecard", &body).await;
    assert_eq!(status, 200, "{card}");
    let properties = card["properties"].as_array().unwrap();
    let of =
        |label: &str| properties.iter().find(|p| p["method"]["label"] == label).unwrap().clone();
    // As their base methods: LF both, DD reversible but coupling the driver to the passenger.
    let (lf, dd) = (of("LF∘p4s3"), of("DD∘p4s5"));
    assert_eq!(
        (lf["reversible"].as_bool(), lf["preserves_fibration"].as_bool()),
        (Some(true), Some(true)),
        "{lf}"
    );
    assert_eq!(
        (dd["reversible"].as_bool(), dd["preserves_fibration"].as_bool()),
        (Some(true), Some(false)),
        "{dd}"
    );
}

#[tokio::test]
async fn the_step_limits_count_sub_steps() {
    let s = TestServer::start().await;
    // 2·10⁶ steps are within the JSON limit of 2·10⁷ alone, not as 15 sub-steps each.
    let body = json!({"system": "knife_edge", "step": 0.001, "t_end": 2000,
                      "methods": ["leapfrog", lf("p8s15")]});
    let (status, error) = s.post_json("/simulate", &body).await;
    assert_eq!(status, 422, "{error}");
    assert_eq!(error["path"], "t_end", "{error}");
    let message = error["error"].as_str().unwrap();
    assert!(message.contains("15 sub-steps of LF∘p8s15 × t_end / step"), "{message}");
    let body = json!({"system": "knife_edge", "t_end": 1000, "methods": [lf("p8s15"), lf("p8s15")],
                      "steps": [0.001, 0.0005], "repeats": 1});
    let (status, error) = s.post_json("/work-precision", &body).await;
    assert_eq!(status, 422, "{error}");
    assert!(error["error"].as_str().unwrap().contains("30 sub-steps per step in all"), "{error}");
}
