//! Methods given as tableaux over HTTP (`prk`, docs/api.md): `GET /systems` lists the stored
//! tableaux with the order and symmetry of each constraint; a tableau given in full runs as
//! the stored one it equals; a composition of a symmetric one raises its order; every
//! malformed tableau is a 422 at its field.

use nhlab_tests::TestServer;
use serde_json::{Value, json};

fn body(methods: Value) -> Value {
    json!({"system": "chaplygin_sleigh", "t_end": 2.0, "step": 0.1, "points": 2, "methods": methods})
}

#[tokio::test]
async fn the_stored_tableaux_are_listed_with_their_constraints() {
    let s = TestServer::start().await;
    let systems: Value = reqwest::get(s.at("/systems")).await.unwrap().json().await.unwrap();
    let tableaux = systems["tableaux"].as_array().unwrap();
    let row = |id: &str| tableaux.iter().find(|t| t["id"] == id).unwrap_or_else(|| panic!("{id}"));
    assert_eq!((&row("lobatto5")["order"], &row("gauss3")["order"]), (&json!(8), &json!(6)));
    assert_eq!((&row("radau3")["order"], &row("radau3")["symmetric"]), (&json!(5), &json!(false)));
    let gauss2 = row("gauss2")["constraints"].as_array().unwrap();
    let summary: Vec<(&str, u64, bool)> = gauss2
        .iter()
        .map(|c| {
            (
                c["id"].as_str().unwrap(),
                c["order"].as_u64().unwrap(),
                c["symmetric"].as_bool().unwrap(),
            )
        })
        .collect();
    assert_eq!(summary, [("stage", 4, false), ("end", 2, true), ("midpoint", 2, true)]);
    assert!(systems["methods"].as_array().unwrap().iter().any(|m| m["id"] == "prk"));
}

#[tokio::test]
async fn a_tableau_given_in_full_runs_as_the_stored_one() {
    let s = TestServer::start().await;
    let systems: Value = reqwest::get(s.at("/systems")).await.unwrap().json().await.unwrap();
    let stored =
        systems["tableaux"].as_array().unwrap().iter().find(|t| t["id"] == "gauss2").unwrap();
    let methods = json!([
        {"id": "prk", "tableau": "gauss2"},
        {"id": "prk", "tableau": stored["tableau"].clone()},
        {"id": "prk", "tableau": "lobatto3", "composition": "p4s3"},
    ]);
    let (status, answer) = s.post_json("/simulate", &body(methods)).await;
    assert_eq!(status, 200, "{answer}");
    let runs = answer["runs"].as_array().unwrap();
    assert!(runs.iter().all(|r| r["status"] == "ok"), "{answer}");
    assert_eq!(runs[0]["method"]["label"], "PRK[gauss2]");
    assert_eq!(runs[1]["method"]["tableau"]["b"], json!([0.5, 0.5]), "a given tableau is echoed");
    assert_eq!(runs[0]["final"], runs[1]["final"], "the same method, stored or given");
    assert_eq!(runs[2]["method"]["label"], "PRK[lobatto3]∘p4s3");
}

#[tokio::test]
async fn malformed_tableaux_are_refused_at_their_field() {
    let s = TestServer::start().await;
    let one = |m: Value| body(json!([m]));
    let cases = [
        (
            json!({"id": "prk", "tableau": {"a": [[0.5]], "b": [0.9]}}),
            "methods[0].tableau.b",
            "sum to 0.9",
        ),
        (
            json!({"id": "prk", "tableau": {"a": [[0.5, 0.0]], "b": [1.0]}}),
            "methods[0].tableau.a[0]",
            "2 entries",
        ),
        (
            json!({"id": "prk", "tableau": {"a": [[0.5]], "b": [1.0], "c": [0.4]}}),
            "methods[0].tableau.c[0]",
            "row 0 of a",
        ),
        (
            json!({"id": "prk", "tableau": {"a": [], "b": []}}),
            "methods[0].tableau.b",
            "1 to 5 stages",
        ),
        (json!({"id": "prk", "tableau": "gauss9"}), "methods[0].tableau", "gauss2"),
        (json!({"id": "prk", "constraint": "everywhere"}), "methods[0].constraint", "midpoint"),
        (json!({"id": "rattle", "tableau": "gauss2"}), "methods[0].tableau", "only prk"),
        (
            json!({"id": "prk", "tableau": "radau2", "composition": "p4s3"}),
            "methods[0].composition",
            "not symmetric",
        ),
        (
            json!({"id": "prk", "tableau": {"a": [[0.0, 0.0], [0.5, 0.5]], "b": [0.5, 0.5]}}),
            "methods[0].constraint",
            "'end' or 'midpoint'",
        ),
        // Classical RK4: as many conditions as multipliers, but the first condition sees none.
        (
            json!({"id": "prk", "tableau": {
                "a": [[0, 0, 0, 0], [0.5, 0, 0, 0], [0, 0.5, 0, 0], [0, 0, 1, 0]],
                "b": [1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0]}}),
            "methods[0].constraint",
            "singular",
        ),
        (
            json!({"id": "prk", "tableau": {"a": [[0.0]], "b": [1.0]}, "constraint": "midpoint"}),
            "methods[0].constraint",
            "try 'end'",
        ),
    ];
    for (method, path, mention) in cases {
        s.rejected(&one(method), path, &[mention]).await;
    }
}
