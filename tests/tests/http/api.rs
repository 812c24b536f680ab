//! The API against the real server (in-process, real TCP): every endpoint, the JSON answer,
//! the stream (equal to the JSON), a failed run, parallel runs and cancellation when the
//! client goes away. Bad input has its own file, `api_errors.rs`.

use nhlab_server::{Config, Page};
use nhlab_tests::{SseEvent, SseReader, TestServer};
use serde_json::{Value, json};
use std::collections::BTreeMap;
use std::time::Duration;

async fn post_stream(server: &TestServer, body: &Value) -> reqwest::Response {
    let response = server.post_stream("/simulate", body).await;
    assert_eq!(response.status(), 200);
    let content_type = response.headers()["content-type"].to_str().unwrap().to_owned();
    assert!(content_type.starts_with("text/event-stream"), "{content_type}");
    response
}

async fn get(server: &TestServer, path: &str) -> reqwest::Response {
    reqwest::get(server.at(path)).await.expect("request succeeds")
}

#[tokio::test]
async fn health() {
    let server = TestServer::start().await;
    let response = get(&server, "/health").await;
    assert_eq!(response.status(), 200);
    let body: Value = response.json().await.unwrap();
    assert_eq!(body["status"], "ok");
    assert_eq!(body["active_runs"], 0);
    // Formulas run as machine code exactly when the server is built with the JIT and the
    // environment does not turn it off (`NHLAB_JIT=off`); otherwise the answer says why.
    let formulas = &body["formulas"];
    let turned_off = std::env::var_os("NHLAB_JIT").is_some_and(|v| v == "off");
    let native = cfg!(feature = "jit") && !turned_off;
    assert_eq!(formulas["native"], native, "{formulas}");
    assert_eq!(formulas["why"].is_null(), native, "{formulas}");
    if !cfg!(feature = "jit") {
        assert!(formulas["why"].as_str().unwrap().contains("`jit` feature"), "{formulas}");
    } else if turned_off {
        assert!(formulas["why"].as_str().unwrap().contains("NHLAB_JIT=off"), "{formulas}");
    }
}

#[tokio::test]
async fn systems_lists_systems_presets_and_methods() {
    let server = TestServer::start().await;
    let response = get(&server, "/systems").await;
    assert_eq!(response.status(), 200);
    let body: Value = response.json().await.unwrap();
    let systems = body["systems"].as_array().unwrap();
    let ids: Vec<&str> = systems.iter().map(|s| s["id"].as_str().unwrap()).collect();
    for id in ["knife_edge", "cvt_pendulum"] {
        assert!(ids.contains(&id), "{ids:?}");
    }
    let presets = |id: &str| -> Vec<String> {
        let system = systems.iter().find(|s| s["id"] == id).unwrap();
        system["presets"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| p["id"].as_str().unwrap().into())
            .collect()
    };
    assert_eq!(presets("knife_edge"), ["paper", "paper-perturbed"]);
    for p in ["oscillating", "rotating", "oscillating-perturbed", "rotating-perturbed"] {
        assert!(presets("cvt_pendulum").contains(&p.to_owned()), "{p}");
    }
    // The paper's six experiments, each a system's preset.
    let paper: Vec<(String, String)> = body["paper_scenes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| (s["system"].as_str().unwrap().into(), s["preset"].as_str().unwrap().into()))
        .collect();
    assert_eq!(paper.len(), 6, "{paper:?}");
    assert_eq!(paper[0], ("knife_edge".to_owned(), "paper".to_owned()));
    for (system, preset) in &paper {
        assert!(presets(system).contains(preset), "{system}/{preset}");
    }
    for system in systems {
        for key in ["name", "description", "dof", "constraints", "params", "integrals", "presets"] {
            assert!(!system[key].is_null(), "{} lacks {key}", system["id"]);
        }
        let dof = system["dof"].as_u64().unwrap() as usize;
        for preset in system["presets"].as_array().unwrap() {
            for key in ["id", "label", "params", "step", "t_end"] {
                assert!(!preset[key].is_null(), "{} lacks {key}", preset["id"]);
            }
            // `dof` is at the default parameters; a preset that sets one that shapes the system
            // (the chaotic oscillator's n) has its own.
            let n = preset["q"].as_array().unwrap().len();
            assert_eq!(preset["v"].as_array().unwrap().len(), n);
            let defaults = system["params"].as_array().unwrap().iter().all(|p| {
                preset["params"].get(p["name"].as_str().unwrap()).is_none_or(|v| *v == p["default"])
            });
            if defaults {
                assert_eq!(n, dof, "{}/{}", system["id"], preset["id"]);
            }
        }
        for param in system["params"].as_array().unwrap() {
            for key in ["name", "default", "min", "max", "description"] {
                assert!(param.get(key).is_some(), "{param} lacks {key}");
            }
        }
    }
    let knife = systems.iter().find(|s| s["id"] == "knife_edge").unwrap();
    assert_eq!(knife["params"][0]["name"], "epsilon");
    let methods: Vec<&str> =
        body["methods"].as_array().unwrap().iter().map(|m| m["id"].as_str().unwrap()).collect();
    for id in ["dla", "dla01", "leapfrog", "dd"] {
        assert!(methods.contains(&id), "{methods:?}");
    }
    for m in body["methods"].as_array().unwrap() {
        for key in ["name", "params", "order", "reference"] {
            assert!(!m[key].is_null(), "{} lacks {key}", m["id"]);
        }
    }
    let dla = &body["methods"][0];
    assert_eq!(dla["params"][0]["name"], "alpha");
    let labels: Vec<&str> = body["default_methods"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["label"].as_str().unwrap())
        .collect();
    assert_eq!(labels.len(), 5);
    assert_eq!(body["limits"]["max_points"], 100_000);
}

/// The page's node tests read `GET /systems` from a saved copy: it must be what the server
/// answers (but the number of simulation slots, which is the machine's number of cores).
/// Refresh it with `curl -s localhost:8080/systems | python3 -m json.tool --indent 1
/// --no-ensure-ascii > web/test/fixtures/systems.json`.
#[tokio::test]
async fn the_page_tests_catalog_is_the_servers() {
    let server = TestServer::start().await;
    let mut served: Value = get(&server, "/systems").await.json().await.unwrap();
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../web/test/fixtures/systems.json");
    let mut saved: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    for catalog in [&mut served, &mut saved] {
        catalog["limits"]["max_simulations"] = Value::Null;
    }
    assert!(
        served == saved,
        "web/test/fixtures/systems.json differs from GET /systems: refresh it"
    );
}

#[tokio::test]
async fn openapi_describes_the_api() {
    let server = TestServer::start().await;
    let response = get(&server, "/openapi.json").await;
    assert_eq!(response.status(), 200);
    let doc: Value = response.json().await.unwrap();
    assert!(doc["openapi"].as_str().unwrap().starts_with("3."));
    for path in ["/simulate", "/systems", "/health", "/openapi.json"] {
        assert!(doc["paths"][path].is_object(), "{path} missing");
    }
    let request = &doc["components"]["schemas"]["SimulateRequest"];
    assert_eq!(request["required"], json!(["system"]));
    // `system`: an id of the registry, or a system given as formulas.
    let system = &request["properties"]["system"]["oneOf"];
    let systems = system[0]["enum"].as_array().unwrap();
    assert!(systems.contains(&json!("knife_edge")));
    let formulas = &system[1];
    let formulas = if formulas["$ref"].is_string() {
        &doc["components"]["schemas"]["FormulaSystem"]
    } else {
        formulas
    };
    assert!(formulas["properties"]["constraints"].is_object(), "{formulas}");
    let methods = &request["properties"]["methods"]["items"]["oneOf"];
    assert!(methods.as_array().unwrap().len() >= 5, "{methods}");
    let simulate = &doc["paths"]["/simulate"]["post"];
    for status in ["200", "400", "422"] {
        assert!(simulate["responses"][status].is_object(), "{status}");
    }
    for schema in ["SimulateResponse", "ErrorBody", "PointsEvent", "RunEvent", "SystemsResponse"] {
        assert!(doc["components"]["schemas"][schema].is_object(), "{schema} missing");
    }
}

#[tokio::test]
async fn page_and_its_assets_are_served_with_content_types() {
    let server = TestServer::start().await;
    let response = get(&server, "/").await;
    assert_eq!(response.status(), 200);
    assert!(response.headers()["content-type"].to_str().unwrap().starts_with("text/html"));
    assert!(response.text().await.unwrap().to_lowercase().contains("<html"));
    let mut served = 0;
    for file in Page::iter() {
        let response = get(&server, &format!("/{file}")).await;
        assert_eq!(response.status(), 200, "{file}");
        let content_type = response.headers()["content-type"].to_str().unwrap().to_owned();
        let expected = match file.rsplit('.').next() {
            Some("html") => "text/html",
            Some("js") => "javascript",
            Some("css") => "text/css",
            Some("json" | "map") => "json",
            _ => "",
        };
        assert!(content_type.contains(expected), "{file}: {content_type}");
        served += 1;
    }
    assert!(served >= 1);
    let missing = get(&server, "/no/such/file.js").await;
    assert_eq!(missing.status(), 404);
    let body: Value = missing.json().await.unwrap();
    assert!(body["error"].as_str().unwrap().contains("/systems"));
    let traversal = get(&server, "/../Cargo.toml").await;
    assert_eq!(traversal.status(), 404);
}

#[tokio::test]
async fn simulate_defaults_come_from_the_first_preset_and_the_paper() {
    let server = TestServer::start().await;
    let (status, body) = server.post_json("/simulate", &json!({"system": "knife_edge"})).await;
    assert_eq!(status, 200, "{body}");
    let scene = &body["scene"];
    assert_eq!(scene["system"], "knife_edge");
    assert_eq!(scene["preset"], "paper");
    assert_eq!(scene["params"], json!({"epsilon": 0.0}));
    assert_eq!(scene["q"].as_array().unwrap().len(), 3);
    assert_eq!(scene["v"].as_array().unwrap().len(), 3);
    assert_eq!(scene["points"], 1000);
    let steps = scene["steps"].as_u64().unwrap();
    let expected =
        (scene["t_end"].as_f64().unwrap() / scene["step"].as_f64().unwrap() + 1e-9).floor() as u64;
    assert_eq!(steps, expected);
    let labels: Vec<&str> =
        scene["methods"].as_array().unwrap().iter().map(|m| m["label"].as_str().unwrap()).collect();
    assert_eq!(labels, ["DLA^0.5", "DLA^0.4", "DLA^{0,1}", "LF", "DD"]);
    assert_eq!(scene["methods"][1], json!({"id": "dla", "alpha": 0.4, "label": "DLA^0.4"}));
    assert!(scene["methods"][3].get("alpha").is_none());
    let integrals = scene["integrals"].as_array().unwrap();
    assert!(integrals.contains(&json!("energy")));
    let runs = body["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 5);
    for (run, method) in runs.iter().zip(scene["methods"].as_array().unwrap()) {
        assert_eq!(&run["method"], method);
        assert_eq!(run["status"], "ok", "{}", run["error"]);
        assert!(run["error"].is_null());
        assert_eq!(run["steps"].as_u64().unwrap(), steps);
        // The run's thread cannot have used more CPU than the wall time it ran (the clock
        // rounds both to the microsecond); a process-wide clock over five runs would.
        let (wall, cpu) = (run["elapsed_ms"].as_f64().unwrap(), run["cpu_ms"].as_f64().unwrap());
        assert!(wall >= 0.0 && cpu > 0.0 && cpu <= wall + 0.002, "cpu {cpu} ms, wall {wall} ms");
        let series = run["series"].as_object().unwrap();
        assert_eq!(series.len(), integrals.len());
        for integral in integrals {
            let s = &series[integral.as_str().unwrap()];
            let n = s["t"].as_array().unwrap().len();
            assert_eq!(n as u64, steps.min(1000), "{integral}");
            assert_eq!(s["mean"].as_array().unwrap().len(), n);
            assert_eq!(s["max"].as_array().unwrap().len(), n);
            let last_t = s["t"][n - 1].as_f64().unwrap();
            assert!((last_t - steps as f64 * scene["step"].as_f64().unwrap()).abs() < 1e-9);
        }
    }
}

#[tokio::test]
async fn simulate_explicit_fields_override_the_preset() {
    let server = TestServer::start().await;
    let request = json!({
        "system": "cvt_pendulum", "params": {"epsilon": 0.5}, "preset": "rotating",
        "step": 0.1, "t_end": 300,
        "methods": [{"id": "dla", "alpha": 0.4}, {"id": "leapfrog"}, "dd"],
        "integrals": ["passenger_energy", "latitude"], "points": 100,
    });
    let (status, body) = server.post_json("/simulate", &request).await;
    assert_eq!(status, 200, "{body}");
    let scene = &body["scene"];
    assert_eq!(scene["preset"], "rotating");
    assert_eq!(scene["params"]["epsilon"], 0.5);
    assert_eq!(scene["step"], 0.1);
    assert_eq!(scene["t_end"], 300.0);
    assert_eq!(scene["steps"], 3000);
    assert_eq!(scene["points"], 100);
    assert_eq!(scene["integrals"], json!(["passenger_energy", "latitude"]));
    let runs = body["runs"].as_array().unwrap();
    assert_eq!(runs[0]["method"], json!({"id": "dla", "alpha": 0.4, "label": "DLA^0.4"}));
    assert_eq!(runs[1]["method"]["id"], "leapfrog");
    assert_eq!(runs[2]["method"]["id"], "dd");
    // The parameters in a `params` object (as a scene's and `GET /systems` give them): the
    // same runs.
    let mut nested = request.clone();
    nested["methods"] =
        json!([{"id": "dla", "params": {"alpha": 0.4}}, {"id": "leapfrog", "params": {}}, "dd"]);
    let (status, nested) = server.post_json("/simulate", &nested).await;
    assert_eq!(status, 200, "{nested}");
    let strip = |mut b: serde_json::Value| {
        for run in b["runs"].as_array_mut().unwrap() {
            run.as_object_mut().unwrap().remove("elapsed_ms");
            run.as_object_mut().unwrap().remove("cpu_ms");
        }
        b
    };
    assert_eq!(strip(nested), strip(body.clone()));
    for run in runs {
        let series = run["series"].as_object().unwrap();
        let keys: Vec<&String> = series.keys().collect();
        assert_eq!(keys, ["latitude", "passenger_energy"]);
        assert_eq!(series["passenger_energy"]["t"].as_array().unwrap().len(), 100);
        assert!(!series["latitude"]["t"].as_array().unwrap().is_empty());
    }
}

/// Reassembles a stream: the scene, each run's series (concatenated `points`) and `run`
/// events, checking the order of events on the way.
struct Streamed {
    scene: Value,
    series: BTreeMap<usize, BTreeMap<String, BTreeMap<&'static str, Vec<Value>>>>,
    runs: BTreeMap<usize, Value>,
    points_events: usize,
    progress_events: usize,
    done: Value,
}

fn reassemble(events: &[SseEvent]) -> Streamed {
    assert_eq!(events[0].event, "scene");
    assert_eq!(events.last().unwrap().event, "done");
    let mut out = Streamed {
        scene: events[0].data.clone(),
        series: BTreeMap::new(),
        runs: BTreeMap::new(),
        points_events: 0,
        progress_events: 0,
        done: events.last().unwrap().data.clone(),
    };
    for e in &events[1..events.len() - 1] {
        let run = e.data["run"].as_u64().unwrap() as usize;
        assert!(!out.runs.contains_key(&run), "{} after run {run} ended", e.event);
        match e.event.as_str() {
            "points" => {
                out.points_events += 1;
                let integral = e.data["integral"].as_str().unwrap().to_owned();
                let series = out.series.entry(run).or_default().entry(integral).or_default();
                for column in ["t", "mean", "max"] {
                    let values = e.data[column].as_array().unwrap();
                    assert!(!values.is_empty());
                    series.entry(column).or_default().extend(values.iter().cloned());
                }
            }
            "progress" => {
                out.progress_events += 1;
                let fraction = e.data["fraction"].as_f64().unwrap();
                assert!((0.0..=1.0).contains(&fraction));
                assert!(e.data["t"].is_number());
            }
            "run" => {
                out.runs.insert(run, e.data.clone());
            }
            other => panic!("unexpected event {other}"),
        }
    }
    out
}

async fn stream_equals_json(config: Config, request: Value) -> Streamed {
    let server = TestServer::with_config(config).await;
    let (status, json) = server.post_json("/simulate", &request).await;
    assert_eq!(status, 200, "{json}");
    let events = SseReader::new(post_stream(&server, &request).await).collect().await;
    let streamed = reassemble(&events);
    assert_eq!(streamed.scene, json["scene"]);
    let runs = json["runs"].as_array().unwrap();
    assert_eq!(streamed.runs.len(), runs.len());
    assert_eq!(streamed.done["runs"], runs.len());
    for (i, run) in runs.iter().enumerate() {
        let event = &streamed.runs[&i];
        for key in ["method", "status", "error", "steps"] {
            assert_eq!(event[key], run[key], "run {i} {key}");
        }
        let (wall, cpu) =
            (event["elapsed_ms"].as_f64().unwrap(), event["cpu_ms"].as_f64().unwrap());
        assert!(cpu <= wall + 0.002, "run {i}: cpu {cpu} ms, wall {wall} ms");
        let series = run["series"].as_object().unwrap();
        for (integral, s) in series {
            let gap = event["gaps"].get(integral).cloned().unwrap_or(Value::Null);
            assert_eq!(gap, s["gap"], "run {i} {integral} gap");
            let got = streamed.series.get(&i).and_then(|r| r.get(integral));
            for column in ["t", "mean", "max"] {
                let expected = s[column].as_array().unwrap();
                let got = got.and_then(|g| g.get(column)).cloned().unwrap_or_default();
                assert_eq!(&got, expected, "run {i} {integral} {column}");
            }
        }
        let streamed_integrals = streamed.series.get(&i).map(|s| s.len()).unwrap_or(0);
        let nonempty = series.values().filter(|s| !s["t"].as_array().unwrap().is_empty());
        assert_eq!(streamed_integrals, nonempty.count(), "run {i}");
    }
    streamed
}

#[tokio::test]
async fn stream_equals_json_in_many_batches() {
    // Report at every look (every 1024 steps), so the series arrive in many batches.
    let config = Config { report_every: Duration::ZERO, ..Config::default() };
    let request = json!({
        "system": "cvt_pendulum", "preset": "rotating-perturbed", "t_end": 3000, "step": 0.05,
        "methods": [{"id": "dla", "alpha": 0.4}, "leapfrog"], "points": 700,
    });
    let streamed = stream_equals_json(config, request).await;
    assert!(streamed.progress_events >= 2 * 50, "{}", streamed.progress_events);
    assert!(streamed.points_events > 2 * 4 * 10, "{}", streamed.points_events);
}

#[tokio::test]
async fn stream_equals_json_with_the_default_methods() {
    stream_equals_json(Config::default(), json!({"system": "knife_edge"})).await;
}

/// DLA^0.4 brings the pendulum CVT's passenger to rest within t ≈ 7·10⁴: from there its
/// latitude `a·u/|u|` is undefined. The series stops at its last value and says why (in JSON
/// and in the stream alike), and its verdict's numbers are of the values it has.
#[tokio::test]
async fn a_series_without_values_to_the_end_says_why() {
    let request = json!({
        "system": "cvt_pendulum", "preset": "rotating", "t_end": 300000,
        "methods": [{"id": "dla", "alpha": 0.4}, "leapfrog"], "integrals": ["latitude"],
        "points": 200,
    });
    let server = TestServer::start().await;
    let (status, body) = server.post_json("/simulate", &request).await;
    assert_eq!(status, 200, "{body}");
    let (dla, lf) = (&body["runs"][0], &body["runs"][1]);
    assert_eq!(dla["status"], "ok");
    let latitude = &dla["series"]["latitude"];
    let gap = &latitude["gap"];
    assert_eq!(gap["reason"], "passenger_at_rest", "{gap}");
    let since = gap["since"].as_f64().unwrap();
    assert!((1e4..2e5).contains(&since), "gap since {since}");
    assert!(gap["message"].as_str().unwrap().starts_with("no value since t = "), "{gap}");
    let t = latitude["t"].as_array().unwrap();
    assert!(!t.is_empty() && t.len() < 200, "{} buckets", t.len());
    assert_eq!(t.last().unwrap().as_f64(), Some(since));
    for column in ["t", "mean", "max"] {
        assert!(latitude[column].as_array().unwrap().iter().all(Value::is_f64), "{column}");
    }
    for number in ["max", "early", "late", "ratio"] {
        assert!(latitude["verdict"][number].is_f64(), "verdict {number}: {}", latitude["verdict"]);
    }
    // LF keeps the passenger moving: its latitude has values to the end, and no gap.
    assert_eq!(lf["series"]["latitude"]["gap"], Value::Null);
    assert_eq!(lf["series"]["latitude"]["t"].as_array().unwrap().len(), 200);
    stream_equals_json(Config::default(), request).await;
}

/// A scene on which some of the paper's methods diverge: their runs fail and keep their
/// series up to the failure, in JSON and in the stream alike.
#[tokio::test]
async fn failed_runs_say_so_and_keep_their_series() {
    let request = json!({"system": "cvt", "step": 3, "t_end": 1000, "points": 1000});
    let server = TestServer::start().await;
    let (status, body) = server.post_json("/simulate", &request).await;
    assert_eq!(status, 200, "{body}");
    let steps = body["scene"]["steps"].as_u64().unwrap();
    let failed: Vec<&Value> =
        body["runs"].as_array().unwrap().iter().filter(|r| r["status"] == "failed").collect();
    assert!(!failed.is_empty(), "no run failed: the scene needs updating");
    for run in failed {
        let error = run["error"].as_str().unwrap();
        let done = run["steps"].as_u64().unwrap();
        assert!(done < steps);
        assert!(error.contains(&format!("step {}", done + 1)), "{error}");
        let energy = &run["series"]["energy"];
        let n = energy["t"].as_array().unwrap().len();
        assert!(n > 0 && n as u64 <= done, "{n} buckets for {done} steps");
    }
    stream_equals_json(Config::default(), request).await;
}

#[tokio::test]
async fn methods_run_in_parallel_and_stop_when_the_client_leaves() {
    let server = TestServer::start().await;
    // 10⁸ steps per run: minutes of work, unless it is stopped.
    let request = json!({
        "system": "knife_edge", "step": 1e-6, "t_end": 100,
        "methods": ["leapfrog", {"id": "dla", "alpha": 0.5}],
    });
    let mut events = SseReader::new(post_stream(&server, &request).await);
    assert_eq!(events.next().await.unwrap().event, "scene");
    loop {
        let e = events.next().await.expect("the stream goes on");
        assert_ne!(e.event, "run", "{e:?}");
        if e.event == "progress" {
            break;
        }
    }
    assert_eq!(server.state.active_runs(), 2, "both methods run at once");
    // The runtime stays free while they run.
    let health: Value = get(&server, "/health").await.json().await.unwrap();
    assert_eq!(health["active_runs"], 2);

    drop(events); // the client goes away: the connection closes
    let took = server.wait_idle(Duration::from_millis(500)).await;
    eprintln!("runs stopped {took:?} after the client left");
}

#[tokio::test]
async fn a_json_request_stops_when_the_client_leaves() {
    let server = TestServer::start().await;
    // 1.5·10⁷ steps per run: seconds of work, within the JSON limit.
    let request = json!({
        "system": "knife_edge", "step": 1e-5, "t_end": 150,
        "methods": ["dd", {"id": "dla", "alpha": 0.5}],
    });
    let client = reqwest::Client::new();
    let send = client.post(server.at("/simulate")).json(&request).send();
    let waited = tokio::time::timeout(Duration::from_millis(300), send).await;
    assert!(waited.is_err(), "the runs should take longer than 300 ms");
    assert_eq!(server.state.active_runs(), 2, "both methods run at once");
    drop(client); // the request future was dropped with the timeout: the connection closes
    let took = server.wait_idle(Duration::from_millis(500)).await;
    eprintln!("runs stopped {took:?} after the client left");
}
