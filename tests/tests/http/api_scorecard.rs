//! Verdicts and the scorecard against the real server: every `/simulate` series carries the
//! verdict of the core's criterion (the stream's `run` events the same ones), and the default
//! `POST /scorecard` reproduces the paper's tables: the verdicts of the knife edge and the
//! measured "preserves fibration / reversibility" table on the CVT.

use nhlab_tests::{SseReader, TestServer};
use serde_json::{Value, json};
use std::collections::BTreeMap;

/// `label → kind` of the verdicts `verdict(run)` of a list of runs.
fn kinds<'a>(
    runs: &'a [Value],
    verdict: impl Fn(&'a Value) -> &'a Value,
) -> BTreeMap<String, String> {
    runs.iter()
        .map(|r| {
            let label = r["method"]["label"].as_str().unwrap().to_owned();
            let kind = verdict(r)["kind"].as_str().unwrap_or("missing").to_owned();
            (label, kind)
        })
        .collect()
}

fn table(pairs: &[(&str, &str)]) -> BTreeMap<String, String> {
    pairs.iter().map(|(a, b)| ((*a).to_owned(), (*b).to_owned())).collect()
}

#[tokio::test]
async fn simulate_series_carry_verdicts_and_the_stream_agrees() {
    let server = TestServer::start().await;
    let body = json!({"system": "knife_edge", "preset": "paper"});
    let (status, json) = server.post_json("/simulate", &body).await;
    assert_eq!(status, 200, "{json}");
    let runs = json["runs"].as_array().unwrap();
    let energy = kinds(runs, |r| &r["series"]["energy"]["verdict"]);
    let expected = table(&[
        ("DLA^0.5", "bounded"),
        ("DLA^0.4", "drift"),
        ("DLA^{0,1}", "bounded"),
        ("LF", "bounded"),
        ("DD", "exact"),
    ]);
    assert_eq!(energy, expected);
    // Every series has a verdict with its numbers; drift means late/early > 1.
    for run in runs {
        for (integral, series) in run["series"].as_object().unwrap() {
            let v = &series["verdict"];
            for key in ["kind", "max", "early", "late"] {
                assert!(!v[key].is_null(), "{integral}: {v}");
            }
            if v["kind"] == "drift" {
                assert!(v["ratio"].is_null() || v["ratio"].as_f64().unwrap() > 1.0, "{v}");
            }
        }
    }
    let dla04 = &runs[1]["series"]["energy"]["verdict"];
    assert!(dla04["late"].as_f64().unwrap() > dla04["early"].as_f64().unwrap(), "{dla04}");

    // The stream: no verdict in `points`, the same verdicts in `run`.
    let response = server.post_stream("/simulate", &body).await;
    let events = SseReader::new(response).collect().await;
    let mut streamed = vec![Value::Null; runs.len()];
    for e in &events {
        match e.event.as_str() {
            "points" => assert!(e.data.get("verdict").is_none(), "{}", e.data),
            "run" => streamed[e.data["run"].as_u64().unwrap() as usize] = e.data.clone(),
            _ => {}
        }
    }
    for (run, ev) in runs.iter().zip(&streamed) {
        let json_verdicts: BTreeMap<&String, &Value> =
            run["series"].as_object().unwrap().iter().map(|(k, s)| (k, &s["verdict"])).collect();
        let stream_verdicts: BTreeMap<&String, &Value> =
            ev["verdicts"].as_object().unwrap().iter().collect();
        assert_eq!(json_verdicts, stream_verdicts, "{}", run["method"]);
    }
}

#[tokio::test]
async fn default_scorecard_reproduces_the_papers_tables() {
    let server = TestServer::start().await;
    let (status, card) = server.post_json("/scorecard", &json!({})).await;
    assert_eq!(status, 200, "{card}");
    assert!(card["criterion"].as_str().unwrap().contains("1e-10"));
    let methods: Vec<&str> =
        card["methods"].as_array().unwrap().iter().map(|m| m["label"].as_str().unwrap()).collect();
    assert_eq!(
        methods,
        ["DLA^0.5", "DLA^0.4", "DLA^{0,1}", "LF", "DD", "DD-AVF", "RK4", "RATTLE", "SPARK3"]
    );
    let scenes = card["scenes"].as_array().unwrap();
    let ids: Vec<&str> = scenes.iter().map(|s| s["id"].as_str().unwrap()).collect();
    assert_eq!(
        ids,
        [
            "knife_edge/paper",
            "knife_edge/paper-perturbed",
            "cvt_pendulum/oscillating",
            "cvt_pendulum/rotating",
            "cvt_pendulum/oscillating-perturbed",
            "cvt_pendulum/rotating-perturbed",
            "chaplygin_sleigh/free",
            "chaplygin_sleigh/inclined",
            "chaotic_oscillator/n1",
            "contact_oscillator/mp",
            "nonholonomic_oscillator/default",
            "heisenberg/default",
            "vertical_disk/long",
        ]
    );
    // Outside the paper's class DD-AVF has no step: its run says so, with why.
    let general = ["chaplygin_sleigh", "chaotic_oscillator", "heisenberg"];
    for scene in scenes {
        assert_eq!(scene["runs"].as_array().unwrap().len(), 9, "{}", scene["id"]);
        let system = scene["scene"]["system"].as_str().unwrap();
        for run in scene["runs"].as_array().unwrap() {
            let expected = if general.contains(&system) && run["method"]["id"] == "dd_avf" {
                "not_applicable"
            } else {
                "ok"
            };
            assert_eq!(run["status"], expected, "{} {}", scene["id"], run["method"]);
        }
    }
    // DD keeps the energy wherever it runs; the fibration is measured on the class only.
    for scene in &scenes[6..] {
        let dd = &scene["runs"][4];
        assert_eq!(dd["verdicts"]["energy"]["kind"], "exact", "{}: {dd}", scene["id"]);
    }

    // The paper's knife-edge table: ε = 0, then ε = 0.1.
    let energy = |i: usize| {
        let mut k = kinds(scenes[i]["runs"].as_array().unwrap(), |r| &r["verdicts"]["energy"]);
        k.retain(|label, _| methods[..5].contains(&label.as_str()));
        k
    };
    assert_eq!(
        energy(0),
        table(&[
            ("DLA^0.5", "bounded"),
            ("DLA^0.4", "drift"),
            ("DLA^{0,1}", "bounded"),
            ("LF", "bounded"),
            ("DD", "exact"),
        ])
    );
    assert_eq!(
        energy(1),
        table(&[
            ("DLA^0.5", "drift"),
            ("DLA^0.4", "drift"),
            ("DLA^{0,1}", "drift"),
            ("LF", "drift"),
            ("DD", "exact"),
        ])
    );

    // The paper's property table, measured on every CVT scene.
    let properties = card["properties"].as_array().unwrap();
    assert_eq!(properties.len(), 13 * 9);
    for p in properties.iter().filter(|p| general.contains(&p["system"].as_str().unwrap())) {
        assert!(p["preserves_fibration"].is_null(), "{p}");
        if ["rattle", "spark"].contains(&p["method"]["id"].as_str().unwrap()) {
            assert_eq!((&p["reversible"], &p["symmetric"]), (&json!(true), &json!(true)), "{p}");
        }
    }
    let expected = [
        ("DLA^0.5", true, true),
        ("DLA^0.4", false, true),
        ("DLA^{0,1}", true, true),
        ("LF", true, true),
        ("DD", true, false),
        ("RK4", false, false),
    ];
    for p in properties.iter().filter(|p| p["system"] == "cvt_pendulum") {
        let label = p["method"]["label"].as_str().unwrap();
        assert!(p["error"].is_null(), "{p}");
        if let Some((_, reversible, fibration)) = expected.iter().find(|e| e.0 == label) {
            assert_eq!(p["reversible"], *reversible, "{label} on {}: {p}", p["scene"]);
            assert_eq!(p["preserves_fibration"], *fibration, "{label} on {}: {p}", p["scene"]);
        }
    }
    // The numbers behind the marks: DD fails the fibration through the driver.
    let dd = properties
        .iter()
        .find(|p| p["scene"] == "cvt_pendulum/oscillating" && p["method"]["id"] == "dd")
        .unwrap();
    assert!(dd["driver_coupling"].as_f64().unwrap() > 1e-9, "{dd}");
    assert!(dd["reversibility_defect"].as_f64().unwrap() < 1e-11, "{dd}");
}

#[tokio::test]
async fn scorecard_takes_given_scenes_and_methods() {
    let server = TestServer::start().await;
    let body = json!({
        "methods": ["leapfrog", {"id": "dla", "alpha": 0.4}],
        "scenes": [
            {"system": "knife_edge", "preset": "paper", "t_end": 50, "integrals": ["energy"]},
            {"system": "knife_edge", "preset": "paper", "params": {"epsilon": 0.1}},
        ],
        "points": 200,
    });
    let (status, card) = server.post_json("/scorecard", &body).await;
    assert_eq!(status, 200, "{card}");
    let scenes = card["scenes"].as_array().unwrap();
    assert_eq!(scenes[0]["id"], "knife_edge/paper");
    assert_eq!(scenes[1]["id"], "knife_edge/paper#1", "a repeated id is made unique");
    assert_eq!(scenes[0]["scene"]["t_end"], 50.0);
    assert_eq!(scenes[0]["scene"]["points"], 200);
    assert_eq!(scenes[1]["scene"]["params"]["epsilon"], 0.1);
    let verdicts = scenes[0]["runs"][0]["verdicts"].as_object().unwrap();
    assert_eq!(verdicts.keys().collect::<Vec<_>>(), ["energy"]);
    assert_eq!(card["properties"].as_array().unwrap().len(), 4);
}

#[tokio::test]
async fn scorecard_errors_name_the_field() {
    let server = TestServer::start().await;
    let cases = [
        (
            json!({"scenes": [{"system": "knife_edge"}, {"system": "knife_edge", "preset": "nope"}]}),
            422,
            "scenes[1].preset",
        ),
        (
            json!({"scenes": [{"system": "cvt_pendulum", "integrals": ["energy", "nope"]}]}),
            422,
            "scenes[0].integrals[1]",
        ),
        (
            json!({"scenes": [{"system": "knife_edge", "methods": ["dd"]}]}),
            400,
            "scenes[0].methods",
        ),
        (json!({"scenes": [{"system": "knife_edge", "step": "big"}]}), 400, "scenes[0].step"),
        (json!({"scenes": []}), 422, "scenes"),
        (json!({"methods": [{"id": "dla", "alfa": 1}]}), 422, "methods[0].alfa"),
        (json!({"points": 0}), 422, "points"),
        (json!({"scene": []}), 400, "scene"),
        // A scene written as an array of its fields (serde alone would read it as one).
        (json!({"scenes": [["knife_edge"]]}), 400, "scenes[0]"),
        (
            json!({"scenes": [{"system": "knife_edge"}, {"system": "cvt", "t_end": "x"}]}),
            400,
            "scenes[1].t_end",
        ),
    ];
    for (body, code, path) in cases {
        let (status, err) = server.post_json("/scorecard", &body).await;
        assert_eq!(status, code, "{body}: {err}");
        assert_eq!(err["path"], path, "{body}: {err}");
        assert!(!err["error"].as_str().unwrap().is_empty());
    }
    let many: Vec<Value> = (0..17).map(|_| json!({"system": "knife_edge"})).collect();
    let (status, err) = server.post_json("/scorecard", &json!({ "scenes": many })).await;
    assert_eq!((status, err["path"].as_str()), (422, Some("scenes")), "{err}");
}

#[tokio::test]
async fn openapi_documents_the_scorecard_and_verdicts() {
    let server = TestServer::start().await;
    let doc: Value = reqwest::get(server.at("/openapi.json")).await.unwrap().json().await.unwrap();
    assert!(doc["paths"]["/scorecard"]["post"].is_object());
    let schemas = &doc["components"]["schemas"];
    for name in ["ScorecardRequest", "ScorecardResponse", "VerdictView", "PropertiesView"] {
        assert!(schemas[name].is_object(), "{name} missing");
    }
    let description =
        doc["paths"]["/scorecard"]["post"]["responses"]["200"]["description"].as_str().unwrap();
    assert!(description.contains("1/32"), "{description}");
}
