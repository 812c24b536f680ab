//! `POST /sweep` against the real server: the rows' order and values, each row's verdicts
//! equal to those of the `/simulate` body it echoes, the same rows as JSON, CSV and a stream
//! and on a second request, cells made invalid by an axis reported in their rows, the
//! request's errors at their fields, the limits refused up front, and a sweep stopped when
//! its client leaves.

use nhlab_server::Config;
use nhlab_tests::{SseReader, TestServer};
use serde_json::{Value, json};
use std::time::Duration;

/// DLA^α and LF on the rotating perturbed CVT, α × ε: 3 × 2 cells.
fn alpha_epsilon() -> Value {
    json!({
        "system": "cvt_pendulum", "preset": "rotating-perturbed", "t_end": 60, "points": 200,
        "methods": [{"id": "dla", "alpha": 0.5}, "leapfrog"],
        "axes": [{"path": "methods.alpha", "linspace": [0.3, 0.7, 3]},
                 {"path": "params.epsilon", "values": [0, 0.5]}]
    })
}

/// The rows without their timing, the only columns that differ from run to run.
fn untimed(rows: &Value) -> Vec<Value> {
    rows.as_array()
        .unwrap()
        .iter()
        .map(|r| {
            let mut r = r.clone();
            r.as_object_mut().unwrap().remove("cpu_ms");
            r
        })
        .collect()
}

#[tokio::test]
async fn rows_come_by_cell_then_method_and_each_is_one_simulate_away() {
    let server = TestServer::start().await;
    let (status, answer) = server.post_json("/sweep", &alpha_epsilon()).await;
    assert_eq!(status, 200, "{answer}");
    assert_eq!(answer["cells"], 6);
    assert_eq!(answer["axes"][0]["values"], json!([0.3, 0.5, 0.7]));
    assert_eq!(answer["methods"][0]["label"], "DLA^0.5");
    let integrals = answer["integrals"].as_array().unwrap();
    assert_eq!(integrals.len(), 5, "{integrals:?}");
    let rows = answer["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 12);
    for (k, row) in rows.iter().enumerate() {
        let (cell, m) = (k / 2, k % 2);
        assert_eq!(row["cell"], cell);
        assert_eq!(row["method_index"], m);
        // The last axis varies fastest.
        let (alpha, epsilon) = ([0.3, 0.5, 0.7][cell / 2], [0.0, 0.5][cell % 2]);
        let values = json!([alpha, epsilon]);
        assert_eq!(row["values"], values);
        assert_eq!(row["status"], "ok", "{row}");
        assert_eq!(row["steps"], 600);
        assert!(row["cpu_ms"].as_f64().unwrap() > 0.0);
        if m == 0 {
            // The method axis sets α: label and echoed method follow it.
            let alpha = values[0].as_f64().unwrap();
            assert_eq!(row["method"]["alpha"], alpha);
            assert_eq!(row["simulate"]["methods"][0], json!({"id": "dla", "alpha": alpha}));
            // DLA^α is implicit: Newton's iterations, one or more per step.
            let iterations = row["newton_iterations"].as_u64().unwrap();
            assert!((600..=20 * 600).contains(&iterations), "{iterations}");
        } else {
            assert_eq!(row["method"]["label"], "LF");
            assert!(row["newton_iterations"].is_null(), "an explicit method: {row}");
        }
        assert_eq!(row["simulate"]["params"]["epsilon"], values[1]);
        assert_eq!(row["verdicts"].as_object().unwrap().len(), 5, "{row}");
    }
    // A row's verdicts are those of the /simulate body it echoes, exactly.
    for k in [0, 5, 11] {
        let row = &rows[k];
        let (status, run) = server.post_json("/simulate", &row["simulate"]).await;
        assert_eq!(status, 200, "{run}");
        for (integral, verdict) in row["verdicts"].as_object().unwrap() {
            assert_eq!(
                &run["runs"][0]["series"][integral]["verdict"], verdict,
                "row {k}, {integral}"
            );
        }
        assert_eq!(run["runs"][0]["steps"], row["steps"]);
    }
}

#[tokio::test]
async fn the_same_rows_as_json_csv_and_stream_and_on_every_request() {
    let server = TestServer::start().await;
    let body = alpha_epsilon();
    let (_, first) = server.post_json("/sweep", &body).await;
    let (_, second) = server.post_json("/sweep", &body).await;
    assert_eq!(untimed(&first["rows"]), untimed(&second["rows"]), "same request, same rows");

    // The stream: `start` (the head), a `cell` per cell in any order, `done` last.
    let events = SseReader::new(server.post_stream("/sweep", &body).await).collect().await;
    assert_eq!(events[0].event, "start");
    let mut head = first.clone();
    head.as_object_mut().unwrap().remove("rows");
    assert_eq!(events[0].data, head);
    let mut streamed: Vec<Value> = events
        .iter()
        .filter(|e| e.event == "cell")
        .flat_map(|e| e.data["rows"].as_array().unwrap().clone())
        .collect();
    streamed.sort_by_key(|r| (r["cell"].as_u64(), r["method_index"].as_u64()));
    assert_eq!(untimed(&Value::from(streamed)), untimed(&first["rows"]));
    let done = events.last().unwrap();
    assert_eq!(done.event, "done");
    assert_eq!((done.data["cells"].clone(), done.data["rows"].clone()), (json!(6), json!(12)));

    // CSV: a header and a line per row, the same numbers.
    let csv = reqwest::Client::new()
        .post(server.at("/sweep"))
        .header("accept", "text/csv")
        .json(&body)
        .send()
        .await
        .unwrap();
    assert!(csv.headers()["content-type"].to_str().unwrap().starts_with("text/csv"));
    let text = csv.text().await.unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 13);
    assert!(lines[0].starts_with(
        "cell,methods.alpha,params.epsilon,method_index,method,status,error,steps,cpu_ms,\
         newton_iterations,energy.kind,energy.max,"
    ));
    let row = &first["rows"][3];
    let cut = |s: &str| s.split(',').take(8).collect::<Vec<_>>().join(",");
    assert_eq!(cut(lines[4]), "1,0.3,0.5,1,LF,ok,,600");
    assert!(lines[4].contains(&format!(",{},", row["verdicts"]["energy"]["max"])), "{}", lines[4]);
}

#[tokio::test]
async fn a_cell_made_invalid_by_an_axis_says_so_in_its_rows() {
    let server = TestServer::start().await;
    // The CVT's constraint at ζ = 0 is v[0] = 0: v[0] = 3 is off it, a cell's error; so is a
    // t_end shorter than one step.
    let body = json!({
        "system": "cvt_pendulum", "preset": "rotating", "t_end": 5, "methods": ["leapfrog", "rk4"],
        "axes": [{"path": "v[0]", "values": [0, 3]}, {"path": "t_end", "values": [0.05, 5]}]
    });
    let (status, answer) = server.post_json("/sweep", &body).await;
    assert_eq!(status, 200, "{answer}");
    let rows = answer["rows"].as_array().unwrap();
    let summary: Vec<(u64, &str)> =
        rows.iter().map(|r| (r["cell"].as_u64().unwrap(), r["status"].as_str().unwrap())).collect();
    assert_eq!(
        summary,
        [
            (0, "invalid"),
            (0, "invalid"),
            (1, "ok"),
            (1, "ok"),
            (2, "invalid"),
            (2, "invalid"),
            (3, "invalid"),
            (3, "invalid")
        ]
    );
    assert!(rows[0]["error"].as_str().unwrap().starts_with("t_end: "), "{}", rows[0]["error"]);
    assert!(rows[6]["error"].as_str().unwrap().starts_with("v: "), "{}", rows[6]["error"]);
    assert_eq!(rows[6]["verdicts"], json!({}));
    assert!(rows[6]["cpu_ms"].is_null() && rows[6]["newton_iterations"].is_null());
    // Its echo is the body as the cell gave it, to correct and send.
    assert_eq!(rows[6]["simulate"]["v"][0], 3.0);

    // A method parameter out of range for one value: that row alone.
    let body = json!({
        "system": "knife_edge", "t_end": 3, "methods": ["dla", "leapfrog"],
        "axes": [{"path": "methods[0].alpha", "values": [0.5, 1.5]}]
    });
    let (status, answer) = server.post_json("/sweep", &body).await;
    assert_eq!(status, 200, "{answer}");
    let statuses: Vec<&str> =
        answer["rows"].as_array().unwrap().iter().map(|r| r["status"].as_str().unwrap()).collect();
    assert_eq!(statuses, ["ok", "ok", "invalid", "ok"]);
    let error = answer["rows"][2]["error"].as_str().unwrap();
    assert!(error.starts_with("methods[0].alpha: "), "{error}");
}

#[tokio::test]
async fn a_system_given_as_formulas_sweeps_its_parameters() {
    let server = TestServer::start().await;
    let system = json!({"name": "bowl", "passenger": ["x", "y"], "driver": "theta",
        "parameters": {"k": 1.0}, "passenger_potential": "k*(x^2 + y^2)/2",
        "driver_potential": "1 - cos(theta)", "constraints": [["1", "sin(theta)"]]});
    let body = json!({"system": system, "q": [1, 1, 0], "v": [0, 0, 2], "t_end": 30,
        "methods": ["leapfrog", "dd"], "axes": [{"path": "params.k", "values": [0.5, 1, 2]}]});
    let (status, answer) = server.post_json("/sweep", &body).await;
    assert_eq!(status, 200, "{}", answer["error"]);
    let rows = answer["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 6);
    for row in rows {
        assert_eq!(row["status"], "ok", "{}", row["error"]);
        // The echo holds the system with this cell's k, and reproduces the row.
        let k = row["values"][0].clone();
        assert_eq!(row["simulate"]["system"]["parameters"]["k"], k);
        let (status, run) = server.post_json("/simulate", &row["simulate"]).await;
        assert_eq!(status, 200, "{}", run["error"]);
        assert_eq!(run["runs"][0]["series"]["energy"]["verdict"], row["verdicts"]["energy"]);
    }
}

#[tokio::test]
async fn the_requests_errors_name_their_field() {
    let server = TestServer::start().await;
    let cases = [
        (json!({"system": "knife_edge"}), 422, "axes"),
        (json!({"system": "knife_edge", "axes": []}), 422, "axes"),
        (
            json!({"system": "knife_edge", "axes": [{"path": "step", "values": [0.1]}, {"path": "t_end", "values": [1]}, {"path": "q[0]", "values": [0]}, {"path": "v[0]", "values": [0]}]}),
            422,
            "axes",
        ),
        (
            json!({"system": "knife_edge", "axes": [{"path": "speed", "values": [1]}]}),
            422,
            "axes[0].path",
        ),
        (
            json!({"system": "knife_edge", "axes": [{"path": "params.nope", "values": [1]}]}),
            422,
            "axes[0].path",
        ),
        (
            json!({"system": "knife_edge", "axes": [{"path": "q[9]", "values": [1]}]}),
            422,
            "axes[0].path",
        ),
        (
            json!({"system": "knife_edge", "methods": ["leapfrog"], "axes": [{"path": "methods.alpha", "values": [0.4]}]}),
            422,
            "axes[0].path",
        ),
        (
            json!({"system": "knife_edge", "axes": [{"path": "methods[7].alpha", "values": [0.4]}]}),
            422,
            "axes[0].path",
        ),
        (
            json!({"system": "knife_edge", "axes": [{"path": "step", "values": [0.1]}, {"path": "step", "values": [0.2]}]}),
            422,
            "axes[1].path",
        ),
        (json!({"system": "knife_edge", "axes": [{"path": "step"}]}), 422, "axes[0]"),
        (
            json!({"system": "knife_edge", "axes": [{"path": "step", "values": []}]}),
            422,
            "axes[0].values",
        ),
        (
            json!({"system": "knife_edge", "axes": [{"path": "step", "logspace": [0, 1, 4]}]}),
            422,
            "axes[0].logspace",
        ),
        (
            json!({"system": "knife_edge", "axes": [{"path": "step", "linspace": [0.1, 1, 2.5]}]}),
            422,
            "axes[0].linspace",
        ),
        (
            json!({"system": "knife_edge", "axes": [{"path": "step", "linspace": [0.1, 1]}]}),
            422,
            "axes[0].linspace",
        ),
        (
            json!({"system": "knife_edge", "axes": [{"path": "step", "values": ["a"]}]}),
            400,
            "axes[0].values[0]",
        ),
        (
            json!({"system": "knife_edge", "axes": [{"path": "step", "values": [1], "size": 3}]}),
            400,
            "axes[0].size",
        ),
        (json!({"system": "knife_edge", "axes": [[1, 2]]}), 400, "axes[0]"),
        (json!({"system": "nope", "axes": [{"path": "step", "values": [0.1]}]}), 422, "system"),
        (
            json!({"system": "knife_edge", "step": -1, "axes": [{"path": "params.epsilon", "values": [0.1]}]}),
            422,
            "step",
        ),
        (
            json!({"system": "knife_edge", "integrals": ["latitude"], "axes": [{"path": "step", "values": [0.1]}]}),
            422,
            "integrals[0]",
        ),
        (
            json!({"system": "knife_edge", "methods": ["nope"], "axes": [{"path": "step", "values": [0.1]}]}),
            422,
            "methods[0].id",
        ),
    ];
    for (body, status, path) in cases {
        let (got, answer) = server.post_json("/sweep", &body).await;
        assert_eq!((got, answer["path"].as_str()), (status, Some(path)), "{body}: {answer}");
        assert!(!answer["error"].as_str().unwrap().is_empty());
    }
}

#[tokio::test]
async fn limits_are_refused_up_front_with_the_estimate() {
    let config = Config { max_sweep_cells: 100, max_sweep_steps: 1_000_000, ..Config::default() };
    let server = TestServer::with_config(config).await;
    let grid = |n: u32| json!({"path": "params.epsilon", "linspace": [0, 0.5, n]});
    let (status, answer) = server
        .post_json("/sweep", &json!({"system": "knife_edge", "axes": [grid(11), grid(11)]}))
        .await;
    assert_eq!(status, 422, "{answer}");
    // (A path twice is refused before its cells are counted.)
    assert_eq!(answer["path"], "axes[1].path");
    let body = json!({"system": "knife_edge", "axes": [grid(11), {"path": "step", "logspace": [0.01, 0.1, 10]}]});
    let (status, answer) = server.post_json("/sweep", &body).await;
    assert_eq!((status, answer["path"].as_str()), (422, Some("axes")), "{answer}");
    assert!(answer["error"].as_str().unwrap().contains("110 cells"), "{answer}");
    // 20 cells × 5 methods × 10⁴ to 10⁵ steps: over the total.
    let body = json!({"system": "knife_edge", "t_end": 1000, "axes": [grid(2), {"path": "step", "logspace": [0.01, 0.1, 10]}]});
    let (status, answer) = server.post_json("/sweep", &body).await;
    assert_eq!((status, answer["path"].as_str()), (422, Some("axes")), "{}", answer["error"]);
    let error = answer["error"].as_str().unwrap();
    assert!(error.contains("max_sweep_steps") && error.contains("steps in all"), "{error}");
    // One run over the per-run limit of a JSON answer names its cell.
    let body = json!({"system": "knife_edge", "t_end": 1e6, "methods": ["leapfrog"], "axes": [{"path": "step", "values": [0.1, 1e-4]}]});
    let (status, answer) = server.post_json("/sweep", &body).await;
    assert_eq!(status, 422, "{answer}");
    assert!(answer["error"].as_str().unwrap().contains("step = 0.0001"), "{answer}");
}

#[tokio::test]
async fn a_sweep_stops_when_its_client_leaves() {
    let server = TestServer::start().await;
    let body = json!({
        "system": "cvt_pendulum", "preset": "rotating-perturbed", "t_end": 20000,
        "axes": [{"path": "params.epsilon", "linspace": [0, 0.5, 40]}]
    });
    let mut events = SseReader::new(server.post_stream("/sweep", &body).await);
    assert_eq!(events.next().await.unwrap().event, "start");
    tokio::time::sleep(Duration::from_millis(300)).await;
    assert!(server.state.active_runs() > 0, "the sweep computes");
    drop(events);
    let took = server.wait_idle(Duration::from_secs(10)).await;
    assert!(took < Duration::from_secs(5), "stopped after {took:?}");
}

/// A system of about 1,900 characters of smooth formulas whose U reads the parameter `k`.
fn large_formula_system() -> Value {
    let mut terms = Vec::new();
    let mut i = 0;
    while terms.iter().map(|t: &String| t.len() + 1).sum::<usize>() < 1900 {
        terms.push(format!("0.{}*cos(x*{}+y/{})", i % 9 + 1, i % 7 + 1, i % 5 + 2));
        i += 1;
    }
    json!({"name": "large", "passenger": ["x", "y"], "driver": "z", "parameters": {"k": 1},
        "passenger_potential": format!("k*x^2 + {}", terms.join("+")),
        "driver_potential": "z^2/2", "constraints": [["cos(z)", "sin(z)"]]})
}

/// A sweep over a parameter of a large system given as formulas compiles it once, the
/// parameter an input of the code: 1,000 cells are answered in seconds, where compiling
/// each cell's system (a tenth of a second each in a release build, more here) would take
/// minutes.
#[tokio::test]
async fn a_sweep_over_a_formula_system_s_parameter_compiles_it_once() {
    let server = TestServer::start().await;
    let values: Vec<f64> = (0..1000).map(|j| 1.0 + j as f64 * 1e-3).collect();
    let body = json!({"system": large_formula_system(), "q": [0.1, 0.2, 0.3], "v": [0, 0, 1],
        "step": 0.01, "t_end": 0.01, "methods": ["leapfrog"],
        "axes": [{"path": "params.k", "values": values}]});
    let started = std::time::Instant::now();
    let (status, answer) = server.post_json("/sweep", &body).await;
    let took = started.elapsed();
    assert_eq!(status, 200, "{}", answer["error"]);
    let rows = answer["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 1000);
    assert!(rows.iter().all(|r| r["status"] == "ok"));
    assert_eq!(rows[999]["simulate"]["system"]["parameters"]["k"], json!(values[999]));
    assert!(took < Duration::from_secs(60), "1,000 cells took {took:?}");
}

/// The step limits are checked before anything is compiled: a sweep over the limit is refused
/// for its steps even when its formulas would not compile.
#[tokio::test]
async fn a_sweep_s_steps_are_checked_before_its_formulas_are_compiled() {
    let server = TestServer::start().await;
    let mut system = large_formula_system();
    system["passenger_potential"] = json!("k*x^2 + (");
    let body = json!({"system": system, "q": [0.1, 0.2, 0.3], "v": [0, 0, 1],
        "step": 1e-300, "t_end": 1, "methods": ["leapfrog"],
        "axes": [{"path": "params.k", "values": [1, 2]}]});
    let (status, answer) = server.post_json("/sweep", &body).await;
    assert_eq!(status, 422);
    assert_eq!(answer["path"], "axes", "{answer}");
    let error = answer["error"].as_str().unwrap();
    assert!(error.contains("about 1.0e300 steps"), "{error}");
}

#[tokio::test]
async fn observables_at_t_end_come_in_each_row_as_simulate_gives_them() {
    let server = TestServer::start().await;
    let mut spec = alpha_epsilon();
    // A formula with a parameter the axis sets: compiled in each cell with its value.
    spec["observables"] = json!({"x": "x1", "e": "epsilon*x1 + zeta_dot"});
    let (status, answer) = server.post_json("/sweep", &spec).await;
    assert_eq!(status, 200, "{answer}");
    // In the order sent (a `Value` sends its keys sorted).
    assert_eq!(answer["observables"], json!(["e", "x"]));
    for row in answer["rows"].as_array().unwrap() {
        assert_eq!(row["status"], "ok", "{row}");
        let at_end = &row["observables"];
        // The echoed /simulate body, asked for the same observables once: its last sample.
        let mut body = row["simulate"].clone();
        body["observables"] = spec["observables"].clone();
        body["points"] = json!(1);
        let (status, run) = server.post_json("/simulate", &body).await;
        assert_eq!(status, 200, "{run}");
        let sampled = &run["runs"][0]["observables"];
        assert_eq!(sampled["t"], json!([60.0]), "{sampled}");
        for name in ["x", "e"] {
            assert_eq!(at_end[name], sampled[name][0], "{name}: {row}");
        }
        let epsilon = row["values"][1].as_f64().unwrap();
        let (x, e) = (at_end["x"].as_f64().unwrap(), at_end["e"].as_f64().unwrap());
        if epsilon == 0.0 {
            assert!((e - x).abs() > 1e-3, "ε = 0 leaves ζ̇ alone: {row}");
        }
    }
    // CSV: a column per observable.
    let csv = reqwest::Client::new()
        .post(server.at("/sweep"))
        .header("accept", "text/csv")
        .json(&spec)
        .send()
        .await
        .unwrap()
        .text()
        .await
        .unwrap();
    let header = csv.lines().next().unwrap();
    assert!(header.ends_with(",observables.e,observables.x,simulate"), "{header}");
    // A formula's error at its field; a run that fails has nulls.
    let mut bad = spec.clone();
    bad["observables"] = json!({"x": "x1^"});
    let (status, error) = server.post_json("/sweep", &bad).await;
    assert_eq!((status, &error["path"]), (422, &json!("observables.x")), "{error}");
    let failing = json!({"system": "knife_edge", "preset": "paper", "t_end": 50, "methods": ["leapfrog"],
                         "observables": {"x": "x1"},
                         "axes": [{"path": "step", "values": [0.1, 1e9]}]});
    let (status, answer) = server.post_json("/sweep", &failing).await;
    assert_eq!(status, 200, "{answer}");
    assert!(answer["rows"][0]["observables"]["x"].is_f64(), "{answer}");
    assert_ne!(answer["rows"][1]["status"], "ok", "{answer}");
    assert!(answer["rows"][1]["observables"]["x"].is_null(), "{answer}");
}
