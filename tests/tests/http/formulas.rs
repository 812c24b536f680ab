//! Systems given as formulas through the API: the built-ins' formula forms give the
//! built-ins' numbers, a new system runs, and every way to get one wrong is a 4xx that
//! names the field (`system.constraints[0][1]`), the position in the formula and why.

use nhlab_tests::{TestServer, with_system};
use serde_json::{Value, json};

/// The issue's example: a skate in a bowl.
fn bowl() -> Value {
    json!({"system": {"name": "skate in a bowl",
                      "passenger": ["x", "y"], "driver": "theta",
                      "parameters": {"k": 1.0, "eps": 0.1},
                      "passenger_potential": "k*(x^2 + y^2)/2",
                      "driver_potential": "0",
                      "constraints": [["-sin(theta)", "cos(theta) - eps"]]},
           "q": [0, 0, std::f64::consts::FRAC_PI_2], "v": [0, 0, 1], "step": 0.1, "t_end": 100})
}

#[tokio::test]
async fn the_issues_example_runs_and_echoes_its_system() {
    let s = TestServer::start().await;
    let (status, answer) = s.post_json("/simulate", &bowl()).await;
    assert_eq!(status, 200, "{answer}");
    let scene = &answer["scene"];
    assert_eq!(scene["system"]["name"], "skate in a bowl");
    assert_eq!(scene["system"]["parameters"], json!({"k": 1.0, "eps": 0.1}));
    assert_eq!(scene["preset"], Value::Null);
    assert_eq!(scene["steps"], 1000);
    // The latitude is defined for this U, but not for a passenger at rest at the origin:
    // among "all the system has" it is left out.
    assert_eq!(
        scene["integrals"],
        json!(["energy", "passenger_energy", "driver_energy", "constraint"])
    );
    for run in answer["runs"].as_array().unwrap() {
        assert_eq!(run["status"], "ok", "{run}");
    }
    // `params` overrides the object's defaults, and the echo says so.
    let body = json!({"params": {"eps": 0.2}});
    let mut req = bowl();
    req["params"] = body["params"].clone();
    let (status, answer) = s.post_json("/simulate", &req).await;
    assert_eq!(status, 200, "{answer}");
    assert_eq!(answer["scene"]["system"]["parameters"]["eps"], 0.2);
    assert_eq!(answer["scene"]["params"]["eps"], 0.2);
}

/// Every built-in's formula forms from `GET /systems` (the paper's form where it has one, the
/// general form always), sent with its first preset's state, give the built-in's series (the
/// core's tests compare the steps to 1e-12).
#[tokio::test]
async fn every_built_ins_formula_form_gives_its_numbers() {
    let s = TestServer::start().await;
    let systems: Value = reqwest::get(s.at("/systems")).await.unwrap().json().await.unwrap();
    for system in systems["systems"].as_array().unwrap() {
        let id = system["id"].as_str().unwrap();
        let preset = &system["presets"][0];
        let common = json!({"q": preset["q"], "v": preset["v"], "step": preset["step"],
                            "t_end": 20.0, "params": preset["params"], "points": 50});
        let mut built_in = common.clone();
        built_in["system"] = json!(id);
        let (a, built) = s.post_json("/simulate", &built_in).await;
        assert_eq!(a, 200, "{id}: {built}");
        for form in ["formulas", "general"].into_iter().filter(|f| !system[*f].is_null()) {
            let mut formulas = common.clone();
            formulas["system"] = system[form].clone();
            let (b, custom) = s.post_json("/simulate", &formulas).await;
            assert_eq!(b, 200, "{id} {form}: {custom}");
            assert_eq!(built["scene"]["integrals"], custom["scene"]["integrals"], "{id} {form}");
            for (x, y) in
                built["runs"].as_array().unwrap().iter().zip(custom["runs"].as_array().unwrap())
            {
                assert_eq!(x["status"], y["status"], "{id} {form}");
                for (integral, sx) in x["series"].as_object().unwrap() {
                    let sy = &y["series"][integral];
                    for (bx, by) in
                        sx["max"].as_array().unwrap().iter().zip(sy["max"].as_array().unwrap())
                    {
                        let (bx, by) = (bx.as_f64().unwrap_or(0.0), by.as_f64().unwrap_or(0.0));
                        // Errors at round-off differ by round-off.
                        assert!(
                            (bx - by).abs() <= 1e-9 * bx.abs() + 1e-12,
                            "{id} {form} {} {integral}: {bx} vs {by}",
                            x["method"]
                        );
                    }
                }
            }
        }
    }
}

#[tokio::test]
async fn formula_errors_name_the_field_the_position_and_the_reason() {
    let s = TestServer::start().await;
    let cases: Vec<(Value, &str, Vec<&str>)> = vec![
        (
            with_system(bowl(), |s| s["passenger_potential"] = json!("k*(x^2 + y^2))")),
            "system.passenger_potential",
            vec!["unexpected ')' at 14"],
        ),
        (
            with_system(bowl(), |s| s["passenger_potential"] = json!("k*(x^2 + y^2")),
            "system.passenger_potential",
            vec!["end of formula"],
        ),
        (
            with_system(bowl(), |s| s["driver_potential"] = json!("sinn(theta)")),
            "system.driver_potential",
            vec!["unknown function 'sinn'", "sin"],
        ),
        (
            with_system(bowl(), |s| s["passenger_potential"] = json!("z^2")),
            "system.passenger_potential",
            vec!["unknown variable 'z'", "x, y, eps, k"],
        ),
        (
            with_system(bowl(), |s| s["constraints"][0][1] = json!("cos(theta) - x")),
            "system.constraints[0][1]",
            vec!["'x' is a passenger coordinate", "driver"],
        ),
        (
            with_system(bowl(), |s| s["passenger_potential"] = json!("x^2 + theta")),
            "system.passenger_potential",
            vec!["'theta' is the driver"],
        ),
        (
            with_system(bowl(), |s| s["driver_potential"] = json!("x*theta")),
            "system.driver_potential",
            vec!["'x' is a passenger coordinate"],
        ),
        (
            with_system(bowl(), |s| s["driver_potential"] = json!("nan")),
            "system.driver_potential",
            vec!["unknown variable 'nan'"],
        ),
        (
            with_system(bowl(), |s| s["driver_potential"] = json!("1e999")),
            "system.driver_potential",
            vec!["'1e999' at 1 is not a finite number"],
        ),
        (
            with_system(bowl(), |s| s["driver_potential"] = json!("")),
            "system.driver_potential",
            vec!["empty"],
        ),
        (
            with_system(bowl(), |s| {
                s["driver_potential"] = json!(format!("{}theta{}", "(".repeat(65), ")".repeat(65)))
            }),
            "system.driver_potential",
            vec!["deeper than 64"],
        ),
        (
            with_system(bowl(), |s| {
                s["driver_potential"] = json!(format!("theta{}", "+1".repeat(1000)))
            }),
            "system.driver_potential",
            vec!["2005 characters", "2000"],
        ),
        (
            with_system(bowl(), |s| s["constraints"] = json!([["1", "0"], ["0", "1"]])),
            "system.constraints",
            vec!["1 to n − 1 = 1"],
        ),
        (
            with_system(bowl(), |s| s["constraints"] = json!([["1"]])),
            "system.constraints[0]",
            vec!["one entry per passenger coordinate (2)"],
        ),
        (
            with_system(bowl(), |s| s["passenger"] = json!(["x", "sin"])),
            "system.passenger[1]",
            vec!["not a usable name"],
        ),
        (with_system(bowl(), |s| s["driver"] = json!("x")), "system.driver", vec!["named twice"]),
        (
            with_system(bowl(), |s| s["passenger"] = json!(["a", "b", "c", "d", "e", "f", "g"])),
            "system.passenger",
            vec!["1 to 6"],
        ),
        (
            with_system(bowl(), |s| {
                let params: serde_json::Map<String, Value> =
                    (0..17).map(|i| (format!("p{i}"), json!(1.0))).collect();
                s["parameters"] = Value::Object(params);
            }),
            "system.parameters",
            vec!["at most 16"],
        ),
    ];
    for (body, path, mentions) in cases {
        s.rejected(&body, path, &mentions).await;
    }
    // Rank: A = [−sin θ, cos θ − 1] vanishes at θ = 0.
    let mut body =
        with_system(bowl(), |s| s["constraints"] = json!([["-sin(theta)", "cos(theta) - 1"]]));
    body["q"] = json!([0, 0, 0]);
    s.rejected(&body, "system.constraints", &["loses rank", "smallest singular value"]).await;
    // Division by zero at the start.
    let mut body = with_system(bowl(), |s| s["driver_potential"] = json!("1/(theta - pi/2)"));
    body["q"] = json!([0, 0, std::f64::consts::FRAC_PI_2]);
    s.rejected(&body, "system.driver_potential", &["V_d is inf"]).await;
    // No presets, and q and v are required.
    let mut body = bowl();
    body["preset"] = json!("paper");
    s.rejected(&body, "preset", &["no presets"]).await;
    let mut body = bowl();
    body.as_object_mut().unwrap().remove("q");
    s.rejected(&body, "q", &["required", "3 numbers"]).await;
    let mut body = bowl();
    body["params"] = json!({"kk": 1});
    s.rejected(&body, "params.kk", &["unknown parameter 'kk'", "eps, k"]).await;
    // The latitude where it is undefined: U not |x|²/2.
    let mut body = with_system(bowl(), |s| s["parameters"]["k"] = json!(2.0));
    body["integrals"] = json!(["latitude"]);
    s.rejected(&body, "integrals[0]", &["no integral 'latitude'", "U = |x|²/2"]).await;
    // Unknown fields in the object are a 400 at their path.
    let body = with_system(bowl(), |s| s["potentials"] = json!("x"));
    let (status, error) = s.post_json("/simulate", &body).await;
    assert_eq!((status, error["path"].as_str()), (400, Some("system.potentials")), "{error}");
    let body = with_system(bowl(), |s| s["constraints"][0][1] = json!(5));
    let (status, error) = s.post_json("/simulate", &body).await;
    assert_eq!(
        (status, error["path"].as_str()),
        (400, Some("system.constraints[0][1]")),
        "{error}"
    );
}

/// A formula that stops being finite during a run (the driver, pushed on, leaves the domain
/// of `sqrt(2 − θ)`) ends that run as failed, with the step and t, like any divergence.
#[tokio::test]
async fn a_formula_that_blows_up_mid_run_fails_that_run() {
    let s = TestServer::start().await;
    let mut body =
        with_system(bowl(), |s| s["driver_potential"] = json!("sqrt(2 - theta) - theta"));
    body["methods"] = json!(["leapfrog", "dd"]);
    let (status, answer) = s.post_json("/simulate", &body).await;
    assert_eq!(status, 200, "{}", answer["error"]);
    for run in answer["runs"].as_array().unwrap() {
        assert_eq!(run["status"], "failed", "{} {}", run["method"], run["steps"]);
        let error = run["error"].as_str().unwrap();
        assert!(error.contains("step") && error.contains("t = "), "{error}");
    }
}

/// Systems given as formulas in the other endpoints: a stream, a scorecard scene and a
/// work–precision request.
#[tokio::test]
async fn formulas_work_in_every_endpoint() {
    let s = TestServer::start().await;
    let events =
        nhlab_tests::SseReader::new(s.post_stream("/simulate", &bowl()).await).collect().await;
    let scene = events.iter().find(|e| e.event == "scene").expect("a scene event");
    assert_eq!(scene.data["system"]["name"], "skate in a bowl", "{:?}", scene.data);
    assert!(events.iter().any(|e| e.event == "done"));

    let mut scene = bowl();
    scene["t_end"] = json!(10);
    let (status, card) =
        s.post_json("/scorecard", &json!({"scenes": [scene], "methods": ["leapfrog"]})).await;
    assert_eq!(status, 200, "{card}");
    assert_eq!(card["scenes"][0]["id"], "skate in a bowl (formulas)");

    let mut wp = bowl();
    wp["t_end"] = json!(10);
    wp["methods"] = json!(["leapfrog", "dd"]);
    wp["levels"] = json!(3);
    let (status, answer) = s.post_json("/work-precision", &wp).await;
    assert_eq!(status, 200, "{answer}");
    // A scorecard scene's error is placed under its scene.
    let mut bad = bowl();
    bad["system"]["driver_potential"] = json!("sin(");
    let (status, error) = s.post_json("/scorecard", &json!({"scenes": [bad]})).await;
    assert_eq!(status, 422, "{error}");
    assert_eq!(error["path"], "scenes[0].system.driver_potential", "{error}");
}
