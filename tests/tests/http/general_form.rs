//! Systems given in the general form through the API (`docs/model.md` §10): the issue's
//! sleigh runs and says it is outside the paper's class, the contact oscillator is found in
//! it with y as the driver, and every way to get one wrong is a 422 at its field with the
//! number that failed.

use nhlab_tests::{TestServer, with_system};
use serde_json::{Value, json};

/// The example: the Chaplygin sleigh, with its kinetic energy as an invariant (g = 0).
fn sleigh() -> Value {
    json!({"system": {"name": "Chaplygin sleigh",
                      "coordinates": ["x", "y", "theta"],
                      "parameters": {"m": 2, "I": 0.5, "a": 0.5, "g": 0},
                      "mass": [["m", 0, 0], [0, "m", 0], [0, 0, "I"]],
                      "potential": "m*g*y",
                      "constraints": [["-sin(theta)", "cos(theta)", "-a"]],
                      "invariants": {"kinetic": "m*(x_dot^2 + y_dot^2)/2 + I*theta_dot^2/2"}},
           "q": [0, 0, 0], "v": [0, 0.5, 1], "step": 0.1, "t_end": 100,
           "methods": ["dla", "dla01", "leapfrog", "dd", "rk4", "rattle"]})
}

#[tokio::test]
async fn the_sleigh_runs_in_the_general_form_outside_the_class() {
    let s = TestServer::start().await;
    let (status, answer) = s.post_json("/simulate", &sleigh()).await;
    assert_eq!(status, 200, "{answer}");
    let scene = &answer["scene"];
    assert_eq!(scene["system"]["coordinates"], json!(["x", "y", "theta"]));
    assert_eq!(scene["system"]["mass"], json!([["m", 0.0, 0.0], [0.0, "m", 0.0], [0.0, 0.0, "I"]]));
    assert_eq!(scene["integrals"], json!(["energy", "constraint", "kinetic"]));
    assert_eq!(scene["paper_class"]["member"], false);
    let why = scene["paper_class"]["why_not"].as_str().unwrap();
    assert!(why.contains("M ≠ I"), "{why}");
    for run in answer["runs"].as_array().unwrap() {
        assert_eq!(run["status"], "ok", "{run}");
        for integral in ["energy", "kinetic"] {
            assert!(run["series"][integral]["verdict"]["kind"].is_string(), "{run}");
        }
    }
    let dd = &answer["runs"][3];
    assert_eq!(dd["series"]["energy"]["verdict"]["kind"], "exact", "{dd}");
    assert_eq!(dd["series"]["kinetic"]["verdict"]["kind"], "exact", "{dd}");
    // As a stream, the same.
    let mut body = sleigh();
    body["methods"] = json!(["dd"]);
    let (status, json_answer) = s.post_json("/simulate", &body).await;
    assert_eq!(status, 200);
    assert_eq!(json_answer["runs"][0]["series"]["kinetic"]["max"], dd["series"]["kinetic"]["max"]);
}

#[tokio::test]
async fn the_contact_oscillator_is_found_in_the_paper_s_class() {
    let s = TestServer::start().await;
    let body = json!({"system": {"coordinates": ["x", "y", "z"],
                                  "parameters": {"epsilon": 0.3},
                                  "potential": "(x^2 + y^2 + z^2)/2 + epsilon*x^2*z^2/2",
                                  "constraints": [["1", "0", "y"]],
                                  "invariants": {"H_y": "(y^2 + y_dot^2)/2"}},
                      "q": [1.4, 1.0, 0.1], "v": [0.0, 0.0, 0.0], "t_end": 50});
    let (status, answer) = s.post_json("/simulate", &body).await;
    assert_eq!(status, 200, "{answer}");
    let scene = &answer["scene"];
    assert_eq!(scene["paper_class"], json!({"member": true, "driver": "y", "why_not": null}));
    assert_eq!(
        scene["integrals"],
        json!(["energy", "passenger_energy", "driver_energy", "constraint", "H_y"])
    );
    // H_y is the driver's energy: the same series.
    for run in answer["runs"].as_array().unwrap() {
        assert_eq!(run["series"]["H_y"]["max"], run["series"]["driver_energy"]["max"], "{run}");
    }
    // Forced through the general steps: no E, h.
    let mut forced = body.clone();
    forced["system"]["detect_class"] = json!(false);
    let (status, answer) = s.post_json("/simulate", &forced).await;
    assert_eq!(status, 200, "{answer}");
    assert_eq!(answer["scene"]["integrals"], json!(["energy", "constraint", "H_y"]));
    assert_eq!(answer["scene"]["paper_class"]["member"], false);
}

#[tokio::test]
async fn general_form_errors_name_the_field_and_the_number() {
    let s = TestServer::start().await;
    // M not positive definite: its smallest eigenvalue.
    let body = with_system(sleigh(), |s| s["mass"] = json!([1, 1, -0.5]));
    s.rejected(&body, "system.mass", &["positive definite", "smallest eigenvalue is -5.000e-1"])
        .await;
    let body = with_system(sleigh(), |s| s["mass"][0][1] = json!(0.3));
    s.rejected(&body, "system.mass[1][0]", &["symmetric"]).await;
    let body = with_system(sleigh(), |s| s["mass"] = json!(["m", "x"]));
    s.rejected(&body, "system.mass", &["one entry per coordinate (3), got 2"]).await;
    let body = with_system(sleigh(), |s| s["mass"] = json!(["m", "m", "theta"]));
    s.rejected(&body, "system.mass[2]", &["'theta' is a coordinate", "M is constant"]).await;
    // A formula that names a velocity where only invariants may.
    let body = with_system(sleigh(), |s| s["potential"] = json!("x_dot"));
    s.rejected(&body, "system.potential", &["velocities appear in invariants only"]).await;
    let body = with_system(sleigh(), |s| s["invariants"]["kinetic"] = json!("m*x_dot^"));
    s.rejected(&body, "system.invariants.kinetic", &["at 9"]).await;
    let body = with_system(sleigh(), |s| s["invariants"] = json!({"energy": "x"}));
    s.rejected(&body, "system.invariants.energy", &["cannot name an invariant"]).await;
    // Sizes.
    let body = with_system(sleigh(), |s| {
        s["constraints"] = json!([["1", "0", "0"], ["0", "1", "0"], ["0", "0", "1"]])
    });
    s.rejected(&body, "system.constraints", &["1 to N − 1 = 2 constraint rows, got 3"]).await;
    // A loses rank at q₀: its smallest singular value.
    let body = with_system(sleigh(), |s| s["constraints"] = json!([["sin(theta)", "0", "0"]]));
    s.rejected(&body, "system.constraints", &["smallest singular value is 0.000e0"]).await;
    // v₀ off the constraints: the residual and the nearest admissible v₀ in M's metric.
    let mut body = sleigh();
    body["v"] = json!([0, 0.5, 0.5]);
    s.rejected(&body, "v", &["|A(q) v| = 2.500e-1", "the nearest v that does"]).await;
    // A method without a general step.
    let mut body = sleigh();
    body["methods"] = json!(["dla", "dd_avf"]);
    s.rejected(&body, "methods[1]", &["DD-AVF applies only to systems of the paper's class"]).await;
    // Fields of both forms at once.
    let body = with_system(sleigh(), |s| s["driver"] = json!("theta"));
    let (status, error) = s.post_json("/simulate", &body).await;
    assert!(status == 400 || status == 422, "{error}");
    assert!(error["error"].as_str().unwrap().contains("belong to the paper's form"), "{error}");
}

/// The built-ins outside the paper's class are listed with why, and the methods that apply.
#[tokio::test]
async fn systems_say_who_is_in_the_paper_s_class() {
    let s = TestServer::start().await;
    let systems: Value = reqwest::get(s.at("/systems")).await.unwrap().json().await.unwrap();
    let find = |id: &str| {
        systems["systems"].as_array().unwrap().iter().find(|x| x["id"] == id).unwrap().clone()
    };
    let knife = find("knife_edge");
    assert_eq!(knife["paper_class"]["member"], true);
    assert_eq!(knife["paper_class"]["driver"], "zeta");
    assert_eq!(knife["general"]["constraints"][0][2], "0");
    for (id, member, why) in [
        ("chaplygin_sleigh", false, "theta's column"),
        ("heisenberg", false, "A depends on x and y"),
        ("chaotic_oscillator", false, "V couples y and z"),
        ("contact_oscillator", true, ""),
        ("nonholonomic_oscillator", true, ""),
        ("vertical_disk", true, ""),
    ] {
        let system = find(id);
        assert_eq!(system["paper_class"]["member"], member, "{system}");
        let methods = system["methods"].as_array().unwrap();
        assert_eq!(methods.contains(&json!("dd_avf")), member, "{id}: {methods:?}");
        assert!(methods.contains(&json!("rattle")), "{id}");
        if !member {
            let reason = system["paper_class"]["why_not"].as_str().unwrap();
            assert!(reason.contains(why), "{id}: {reason}");
            assert!(system["formulas"].is_null(), "{id}");
        }
    }
    assert_eq!(find("vertical_disk")["exact"], true);
    assert_eq!(systems["literature_scenes"].as_array().unwrap().len(), 7);
    // A preset's parameters may take its system out of the class: each preset says.
    let presets = |id: &str| -> Vec<(String, bool)> {
        let system = find(id);
        let list = system["presets"].as_array().unwrap().clone();
        list.iter()
            .map(|p| (p["id"].as_str().unwrap().to_owned(), p["paper_class"] == true))
            .collect()
    };
    let disk = presets("vertical_disk");
    assert!(disk.contains(&("heavy".to_owned(), false)), "{disk:?}");
    assert!(disk.iter().any(|(_, member)| *member), "{disk:?}");
    assert!(presets("knife_edge").iter().all(|(_, member)| *member));
    assert!(presets("chaplygin_sleigh").iter().all(|(_, member)| !*member));
}

/// Hostile systems through HTTP: twelve coordinates of long formulas run (200); a constraint
/// that loses rank during a run ends that run as failed, with the step and t, not the request.
#[tokio::test]
async fn hostile_general_systems_get_answers_not_5xx() {
    let s = TestServer::start().await;
    let names: Vec<String> = (1..=12).map(|i| format!("q{i}")).collect();
    let potential: String = (1..=12)
        .map(|i| format!("{i}*q{i}^2/2 + cos(q{i})*q{}^2/(10 + q{i}^2)", i % 12 + 1))
        .collect::<Vec<_>>()
        .join(" + ");
    let row = |k: usize| -> Vec<String> {
        (1..=12)
            .map(|i| match i {
                _ if i == k => "1".to_owned(),
                _ if i == k + 1 => format!("sin(q{})", k + 2),
                _ => "0".to_owned(),
            })
            .collect()
    };
    let q: Vec<f64> = (0..12).map(|i| 0.1 * f64::from(i)).collect();
    let mut v = vec![0.0; 12];
    v[11] = 1.0;
    let body = json!({"system": {"coordinates": names, "potential": potential,
                                  "constraints": (1..=5).map(row).collect::<Vec<_>>()},
                      "q": q, "v": v, "step": 0.05, "t_end": 5,
                      "methods": ["dla", "dd", "rk4", "rattle", {"id": "spark", "stages": 3}]});
    let (status, answer) = s.post_json("/simulate", &body).await;
    assert_eq!(status, 200, "{answer}");
    for run in answer["runs"].as_array().unwrap() {
        assert_eq!(run["status"], "ok", "{run}");
    }
    // ẋ cos θ = 0 while θ turns at speed 1: A loses rank at t = π/2.
    let body = json!({"system": {"coordinates": ["x", "theta", "z"], "potential": "0",
                                  "constraints": [["cos(theta)", "0", "0"]], "detect_class": false},
                      "q": [0, 0, 0], "v": [0, 1, 0.5], "step": 0.01, "t_end": 3,
                      "methods": ["dla", "rattle", "rk4"]});
    let (status, answer) = s.post_json("/simulate", &body).await;
    assert_eq!(status, 200, "{answer}");
    for run in answer["runs"].as_array().unwrap() {
        assert_eq!(run["status"], "failed", "{run}");
        let error = run["error"].to_string();
        assert!(error.contains("rank") && error.contains("t = 1.5"), "{error}");
    }
}

/// Work–precision on the vertical disk measures against its exact solution.
#[tokio::test]
async fn work_precision_on_the_vertical_disk_uses_its_exact_solution() {
    let s = TestServer::start().await;
    let body = json!({"system": "vertical_disk", "preset": "heavy", "t_end": 10,
                      "methods": ["dla", "rk4"], "levels": 3});
    let (status, answer) = s.post_json("/work-precision", &body).await;
    assert_eq!(status, 200, "{answer}");
    assert_eq!(answer["reference"]["exact"], true);
    assert_eq!(answer["reference"]["steps"], 0);
    let errors: Vec<f64> = answer["rows"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|r| r["method"]["id"] == "rk4")
        .map(|r| r["final_error"].as_f64().unwrap())
        .collect();
    // Fourth order against the exact solution: each halving divides the error by about 16.
    for w in errors.windows(2) {
        assert!((w[0] / w[1]).log2() > 3.7, "{errors:?}");
    }
}
