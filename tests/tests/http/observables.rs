//! Observables through `/simulate`: sampled at the steps nearest evenly spread times, equal
//! to the exact solution where there is one (the vertical disk), read from a system given as
//! formulas in its user's order, the same as a stream and as JSON, formula errors at
//! `observables.NAME`, and counted in the answer's size.

use nhlab_tests::{SseReader, TestServer};
use serde_json::{Value, json};

fn column(run: &Value, name: &str) -> Vec<f64> {
    run["observables"][name]
        .as_array()
        .unwrap_or_else(|| panic!("no column {name} in {}", run["observables"]))
        .iter()
        .map(|x| x.as_f64().expect("a number"))
        .collect()
}

/// The vertical disk's exact solution (docs/model.md): φ and θ turn uniformly, and the
/// contact point runs on a circle of radius ρ = R ω_θ / ω_φ.
fn disk_exact(t: f64) -> [f64; 5] {
    let (r, w_phi, w_theta) = (1.0, 2.0, 1.0);
    let phi = w_phi * t;
    let rho = r * w_theta / w_phi;
    let (x, y) = (rho * phi.sin(), -rho * (phi.cos() - 1.0));
    [x, y, phi, w_theta * t, r * phi.cos() * w_theta]
}

#[tokio::test]
async fn the_vertical_disks_observables_follow_its_exact_solution() {
    let s = TestServer::start().await;
    let body = json!({"system": "vertical_disk", "preset": "odelab", "step": 0.001, "t_end": 3.0,
                      "methods": ["rattle", "leapfrog"], "points": 7,
                      "observables": {"x": "x", "y": "y", "phi": "phi", "theta": "theta",
                                      "x_dot": "x_dot", "r2": "x^2 + (y - R/2)^2"}});
    let (status, answer) = s.post_json("/simulate", &body).await;
    assert_eq!(status, 200, "{answer}");
    // The columns come in the order given, the times first.
    // (As text: a `Value` sorts its keys.)
    let raw = r#"{"system": "vertical_disk", "t_end": 1, "methods": ["rattle"], "points": 3,
                  "observables": {"x": "x", "y": "y", "phi": "phi", "theta": "theta",
                                  "x_dot": "x_dot", "r2": "x^2 + (y - R/2)^2"}}"#;
    let text = s.post_text("/simulate", raw).await.text().await.unwrap();
    let observed = &text[text.find("\"observables\":{").expect("observables")..];
    let at = |key: &str| observed.find(&format!("\"{key}\":[")).unwrap_or(usize::MAX);
    let order = ["t", "x", "y", "phi", "theta", "x_dot", "r2"].map(at);
    assert!(order.windows(2).all(|w| w[0] < w[1]), "{order:?}");
    for run in answer["runs"].as_array().unwrap() {
        assert_eq!(run["status"], "ok", "{run}");
        let keys: Vec<&String> = run["observables"].as_object().unwrap().keys().collect();
        assert_eq!(keys.len(), 7, "{keys:?}");
        let t = column(run, "t");
        // 3000 steps, 7 samples: every 500th step, t = 0 first and t_end last.
        assert_eq!(t.len(), 7);
        for (j, &tj) in t.iter().enumerate() {
            assert!((tj - 0.5 * j as f64).abs() < 1e-12, "{t:?}");
        }
        let names = ["x", "y", "phi", "theta", "x_dot"];
        for (j, &tj) in t.iter().enumerate() {
            let exact = disk_exact(tj);
            for (k, name) in names.iter().enumerate() {
                let got = column(run, name)[j];
                // Second-order methods at h = 1e-3 over t ≤ 3: errors of order 1e-6.
                assert!((got - exact[k]).abs() < 1e-5, "{name} at t = {tj}: {got} vs {}", exact[k]);
            }
            // The contact point stays on its circle of radius 1/2 about (0, 1/2).
            let r2 = column(run, "r2")[j];
            assert!((r2 - 0.25).abs() < 1e-5, "r² = {r2} at t = {tj}");
        }
    }
}

#[tokio::test]
async fn a_system_given_as_formulas_is_observed_in_its_users_order() {
    let s = TestServer::start().await;
    // The driver first: the code holds it last.
    let body = json!({"system": {"name": "skate", "coordinates": ["theta", "x", "y"],
                                 "potential": "(x^2 + y^2)/2",
                                 "constraints": [["0", "-sin(theta)", "cos(theta)"]]},
                      "q": [0.5, 0.1, 0.0], "v": [1.0, 0.0, 0.0], "step": 0.01, "t_end": 1.0,
                      "methods": ["leapfrog"], "points": 3,
                      "observables": {"theta": "theta", "w": "theta_dot", "clock": "2*t"}});
    let (status, answer) = s.post_json("/simulate", &body).await;
    assert_eq!(status, 200, "{answer}");
    let run = &answer["runs"][0];
    assert_eq!(column(run, "t"), [0.0, 0.5, 1.0]);
    assert_eq!(column(run, "clock"), [0.0, 1.0, 2.0]);
    // θ turns uniformly (no torque on it): θ = 0.5 + t.
    for (theta, t) in column(run, "theta").iter().zip([0.0, 0.5, 1.0]) {
        assert!((theta - (0.5 + t)).abs() < 1e-12, "{theta} at {t}");
    }
    assert!(column(run, "w").iter().all(|w| (w - 1.0).abs() < 1e-12));
}

#[tokio::test]
async fn a_stream_sends_the_same_observables_as_json() {
    let s = TestServer::start().await;
    let body = json!({"system": "knife_edge", "preset": "paper-perturbed", "t_end": 300,
                      "methods": ["leapfrog", "dla"], "points": 50,
                      "observables": {"x": "x1", "speed": "x1_dot*cos(zeta) + x2_dot*sin(zeta)"}});
    let (status, answer) = s.post_json("/simulate", &body).await;
    assert_eq!(status, 200, "{answer}");
    let events = SseReader::new(s.post_stream("/simulate", &body).await).collect().await;
    for (i, run) in answer["runs"].as_array().unwrap().iter().enumerate() {
        let mut streamed: Vec<(String, Vec<Value>)> =
            ["t", "x", "speed"].iter().map(|n| ((*n).to_owned(), Vec::new())).collect();
        for e in events.iter().filter(|e| e.event == "observables" && e.data["run"] == i) {
            for (name, values) in &mut streamed {
                values.extend(e.data[name.as_str()].as_array().unwrap().iter().cloned());
            }
        }
        for (name, values) in streamed {
            assert_eq!(Value::Array(values), run["observables"][&name], "run {i}, {name}");
        }
        assert_eq!(column(run, "t").len(), 50);
    }
}

#[tokio::test]
async fn observables_that_are_wrong_are_refused_at_their_field() {
    let s = TestServer::start().await;
    let base = json!({"system": "knife_edge", "t_end": 10, "methods": ["leapfrog"]});
    let with = |observables: Value| {
        let mut body = base.clone();
        body["observables"] = observables;
        body
    };
    s.rejected(&with(json!({"e": "x1^"})), "observables.e", &["unexpected end of formula at 4"])
        .await;
    s.rejected(&with(json!({"e": "z + 1"})), "observables.e", &["x1_dot", "zeta"]).await;
    s.rejected(&with(json!({"t": "x1"})), "observables.t", &["'t'"]).await;
    s.rejected(&with(json!({})), "observables", &["must not be empty"]).await;
    let many: serde_json::Map<String, Value> =
        (0..17).map(|i| (format!("o{i}"), json!("x1"))).collect();
    s.rejected(&with(Value::Object(many)), "observables", &["limit of 16"]).await;
    // A name given twice is refused, as in every object of the API.
    let text = r#"{"system": "knife_edge", "observables": {"a": "x1", "a": "x2"}}"#;
    let response = s.post_text("/simulate", text).await;
    assert_eq!(response.status(), 400);
    let error: Value = response.json().await.unwrap();
    assert!(error["error"].as_str().unwrap().contains("given twice"), "{error}");
}

#[tokio::test]
async fn observables_count_in_the_answers_size() {
    let s = TestServer::start().await;
    // 5 methods × (16 + 1) columns × 10⁵ points × 32 bytes: 272 MB, over the 64 MiB default.
    let observables: serde_json::Map<String, Value> =
        (0..16).map(|i| (format!("o{i}"), json!("x1 + x2"))).collect();
    let body = json!({"system": "knife_edge", "t_end": 10000, "step": 0.01, "points": 100000,
                      "integrals": ["energy"], "observables": observables});
    let (status, error) = s.post_json("/simulate", &body).await;
    assert_eq!(status, 422, "{error}");
    assert_eq!(error["path"], "points", "{error}");
    // Without them the same request fits.
    let mut fits = body.clone();
    fits.as_object_mut().unwrap().remove("observables");
    fits["t_end"] = json!(10);
    let (status, answer) = s.post_json("/simulate", &fits).await;
    assert_eq!(status, 200, "{answer}");
    assert!(answer["runs"][0].get("observables").is_none(), "absent unless asked for");
}

#[tokio::test]
async fn a_sections_crossings_are_the_latitudes_on_the_same_surface() {
    let s = TestServer::start().await;
    // The rotating CVT's driver ζ crosses the latitude's section ζ = 2πm once a turn: the
    // same crossings as sin(ζ/2) = 0 either way (ζ counted with its whole turns).
    let body = json!({"system": "cvt_pendulum", "preset": "rotating", "step": 0.01,
                      "t_end": 60, "methods": ["leapfrog", "dla"], "points": 1000,
                      "integrals": ["latitude"],
                      "section": {"surface": "sin(zeta/2)", "direction": "both",
                                  "plot": ["zeta", "zeta_dot"]}});
    let (status, answer) = s.post_json("/simulate", &body).await;
    assert_eq!(status, 200, "{answer}");
    for run in answer["runs"].as_array().unwrap() {
        let latitude: Vec<f64> = run["series"]["latitude"]["t"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        let crossings: Vec<f64> =
            run["section"]["t"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
        assert!(latitude.len() > 10, "{latitude:?}");
        assert_eq!(crossings.len(), latitude.len(), "{crossings:?} {latitude:?}");
        // The latitude interpolates linearly in ζ (O(h²)), the section along a cubic: they
        // agree to about h².
        for (a, b) in crossings.iter().zip(&latitude) {
            assert!((a - b).abs() < 1e-4, "{a} vs {b}");
        }
        let zeta = &run["section"]["zeta"];
        for (m, z) in zeta.as_array().unwrap().iter().enumerate() {
            let turn = 2.0 * std::f64::consts::PI * (m + 1) as f64;
            assert!((z.as_f64().unwrap() - turn).abs() < 1e-9, "{z} at crossing {m}");
        }
    }
}

#[tokio::test]
async fn a_section_of_the_vertical_disk_is_at_its_exact_crossings() {
    let s = TestServer::start().await;
    // φ = 2t: sin φ falls through 0 at φ = π + 2πk, t = π/2 + πk, where the contact point
    // is at (0, 1) exactly.
    let body = json!({"system": "vertical_disk", "preset": "long", "t_end": 20, "step": 0.005,
                      "methods": ["rattle", "dd"], "points": 10,
                      "section": {"surface": "sin(phi)", "direction": "down",
                                  "plot": ["x", "y", "phi_dot"]}});
    let (status, answer) = s.post_json("/simulate", &body).await;
    assert_eq!(status, 200, "{answer}");
    for run in answer["runs"].as_array().unwrap() {
        let section = &run["section"];
        let t: Vec<f64> =
            section["t"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
        assert_eq!(t.len(), 6, "{section}");
        for (k, &tk) in t.iter().enumerate() {
            let exact = std::f64::consts::FRAC_PI_2 + std::f64::consts::PI * k as f64;
            assert!((tk - exact).abs() < 1e-6, "crossing {k} at {tk}, exact {exact}");
            let at = |name: &str| section[name][k].as_f64().unwrap();
            assert!(at("x").abs() < 1e-4 && (at("y") - 1.0).abs() < 1e-4, "{section}");
            assert!((at("phi_dot") - 2.0).abs() < 1e-10, "{section}");
        }
    }
    // The most crossings kept, and a stream's `section` events the same as the JSON.
    let mut fewer = body.clone();
    fewer["section"]["max_crossings"] = json!(2);
    let (status, answer) = s.post_json("/simulate", &fewer).await;
    assert_eq!(status, 200, "{answer}");
    assert_eq!(answer["runs"][0]["section"]["t"].as_array().unwrap().len(), 2);
    let events = SseReader::new(s.post_stream("/simulate", &fewer).await).collect().await;
    let streamed: Vec<Value> = events
        .iter()
        .filter(|e| e.event == "section" && e.data["run"] == 0)
        .flat_map(|e| e.data["t"].as_array().unwrap().clone())
        .collect();
    assert_eq!(Value::Array(streamed), answer["runs"][0]["section"]["t"]);
}

#[tokio::test]
async fn a_section_that_is_wrong_is_refused_at_its_field() {
    let s = TestServer::start().await;
    let base = json!({"system": "knife_edge", "t_end": 10, "methods": ["leapfrog"]});
    let with = |section: Value| {
        let mut body = base.clone();
        body["section"] = section;
        body
    };
    let at = |surface: &str, plot: Value| json!({"surface": surface, "plot": plot});
    s.rejected(&with(at("zeta^", json!(["x1"]))), "section.surface", &["unexpected end"]).await;
    s.rejected(&with(at("zeta", json!(["x1", "q"]))), "section.plot[1]", &["x1_dot"]).await;
    s.rejected(&with(at("zeta", json!([]))), "section.plot", &["at least one"]).await;
    s.rejected(&with(at("zeta", json!(["x1", "x1"]))), "section.plot[1]", &["twice"]).await;
    let mut sideways = at("zeta", json!(["x1"]));
    sideways["direction"] = json!("sideways");
    s.rejected(&with(sideways), "section.direction", &["up, down or both"]).await;
    let mut many = at("zeta", json!(["x1"]));
    many["max_crossings"] = json!(100_001);
    s.rejected(&with(many), "section.max_crossings", &["between 1 and 10000"]).await;
    // A plotted name that is an observable takes its formula.
    let mut body = with(at("sin(zeta)", json!(["speed"])));
    body["observables"] = json!({"speed": "x1_dot*cos(zeta) + x2_dot*sin(zeta)"});
    body["t_end"] = json!(100);
    let (status, answer) = s.post_json("/simulate", &body).await;
    assert_eq!(status, 200, "{answer}");
    assert!(answer["runs"][0]["section"]["speed"].is_array(), "{answer}");
}

#[tokio::test]
async fn work_precision_takes_the_observables_at_t_end_for_each_row_and_the_reference() {
    let s = TestServer::start().await;
    // The vertical disk's reference is its exact solution.
    let body = json!({"system": "vertical_disk", "preset": "odelab", "t_end": 3.0,
                      "methods": ["rattle"], "steps": [0.01, 0.001], "repeats": 1,
                      "observables": {"x": "x", "r2": "x^2 + (y - R/2)^2"}});
    let (status, answer) = s.post_json("/work-precision", &body).await;
    assert_eq!(status, 200, "{answer}");
    let exact = disk_exact(3.0);
    let reference = &answer["reference"]["observables"];
    assert!((reference["x"].as_f64().unwrap() - exact[0]).abs() < 1e-14, "{reference}");
    assert!((reference["r2"].as_f64().unwrap() - 0.25).abs() < 1e-14, "{reference}");
    let errors: Vec<f64> = answer["rows"]
        .as_array()
        .unwrap()
        .iter()
        .map(|row| {
            let x = row["observables"]["x"].as_f64().unwrap();
            // Within the row's final error of the reference.
            let final_error = row["final_error"].as_f64().unwrap();
            assert!((x - exact[0]).abs() <= final_error * (1.0 + 1e-9), "{row}");
            (x - exact[0]).abs()
        })
        .collect();
    // Second order: ten times the steps, a hundred times less error.
    assert!(errors[1] < errors[0] / 50.0, "{errors:?}");
    // An error names its field.
    let mut bad = body.clone();
    bad["observables"] = json!({"x": "x^"});
    let (status, error) = s.post_json("/work-precision", &bad).await;
    assert_eq!((status, &error["path"]), (422, &json!("observables.x")), "{error}");
}

#[tokio::test]
async fn the_knife_edges_observables_follow_its_exact_solution_and_the_reference_run_is_it() {
    let s = TestServer::start().await;
    // The skate (x1, x2) at angle ζ = θ. ε = 0 from θ = π/2, θ̇ = 1: θ = π/2 + t, and it slides
    // x = 1 − cos t − sin²t / 2, y = t/2 + sin 2t / 4 − sin t.
    let body = json!({"system": "knife_edge", "preset": "paper", "q": [0, 0, std::f64::consts::FRAC_PI_2],
                      "v": [0, 0, 1], "step": 0.01, "t_end": 20, "points": 11,
                      "methods": ["leapfrog", "reference"],
                      "observables": {"x": "x1", "y": "x2", "theta": "zeta",
                                      "speed": "x1_dot*cos(zeta) + x2_dot*sin(zeta)"}});
    let (status, answer) = s.post_json("/simulate", &body).await;
    assert_eq!(status, 200, "{answer}");
    let mut worst = Vec::new();
    for run in answer["runs"].as_array().unwrap() {
        assert_eq!(run["status"], "ok", "{run}");
        let t = column(run, "t");
        assert_eq!(t.len(), 11);
        let mut err: f64 = 0.0;
        for (j, &tj) in t.iter().enumerate() {
            let (sn, cs) = tj.sin_cos();
            let exact = [
                ("x", 1.0 - cs - sn * sn / 2.0),
                ("y", tj / 2.0 + (2.0 * tj).sin() / 4.0 - sn),
                ("theta", std::f64::consts::FRAC_PI_2 + tj),
                // The speed along the blade, ẋ cos θ + ẏ sin θ, from the formulas above.
                ("speed", (sn - sn * cs) * (-sn) + (0.5 + 0.5 * (2.0 * tj).cos() - cs) * cs),
            ];
            for (name, value) in exact {
                err = err.max((column(run, name)[j] - value).abs());
            }
        }
        worst.push(err);
    }
    // Leap-frog is second order (h = 0.01: ~1e-4), the reference exact to its tolerance.
    assert!(worst[0] < 1e-2 && worst[0] > 1e-7, "leap-frog's error {:e}", worst[0]);
    assert!(worst[1] < 1e-11, "the reference run's error {:e}", worst[1]);
}

#[tokio::test]
async fn the_reference_runs_beside_the_methods_and_its_section_is_the_exact_one() {
    let s = TestServer::start().await;
    let body = json!({"system": "vertical_disk", "preset": "long", "t_end": 20, "step": 0.05,
                      "methods": ["rattle", "reference"], "points": 10,
                      "section": {"surface": "sin(phi)", "direction": "down", "plot": ["x", "y"]}});
    let (status, answer) = s.post_json("/simulate", &body).await;
    assert_eq!(status, 200, "{answer}");
    let runs = answer["runs"].as_array().unwrap();
    assert_eq!(runs[1]["method"], json!({"id": "reference", "label": "reference"}));
    // Its series like any run's: the energy kept to the tolerance.
    let energy = runs[1]["series"]["energy"]["verdict"]["max"].as_f64().unwrap();
    assert!(energy < 1e-12, "the reference's energy error {energy:e}");
    // Crossings at t = π/2 + πk, at (0, 1): interpolated inside a step of 0.05 (O(h⁴)), far
    // closer than the method's own.
    let off = |run: &Value| {
        let t = run["section"]["t"].as_array().unwrap();
        assert_eq!(t.len(), 6, "{}", run["section"]);
        (0..6)
            .map(|k| {
                let exact = std::f64::consts::FRAC_PI_2 + std::f64::consts::PI * k as f64;
                let tk = t[k].as_f64().unwrap();
                let y = run["section"]["y"][k].as_f64().unwrap();
                (tk - exact).abs().max((y - 1.0).abs())
            })
            .fold(0.0, f64::max)
    };
    let (method, reference) = (off(&runs[0]), off(&runs[1]));
    assert!(reference < 1e-6, "the reference's crossings are {reference:e} off");
    assert!(reference < method / 10.0, "reference {reference:e}, RATTLE {method:e}");
    // It is listed as an instrument, never a default, and work–precision refuses it.
    let systems: Value =
        reqwest::get(s.at("/systems")).await.unwrap().json().await.expect("GET /systems");
    let listed = systems["methods"].as_array().unwrap().iter().find(|m| m["id"] == "reference");
    assert_eq!(listed.map(|m| m["instrument"].clone()), Some(json!(true)));
    assert!(!systems["default_methods"].to_string().contains("reference"));
    let wp = json!({"system": "knife_edge", "methods": ["leapfrog", "reference"], "levels": 2});
    let (status, error) = s.post_json("/work-precision", &wp).await;
    assert_eq!((status, &error["path"]), (422, &json!("methods[1]")), "{error}");
}
