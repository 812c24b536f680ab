//! Numbers and keys as sent: a double in a request comes back bit for bit in the resolved
//! scene (so a scene sent back reproduces the runs), a parameter named twice is refused like
//! any other duplicate field, and an error never echoes a number in 309 digits.

use nhlab_server::json_object::read_object;
use nhlab_server::{Caches, Config, Delivery, Plan, SimulateRequest};
use nhlab_tests::TestServer;
use serde_json::{Value, json};

/// xorshift64*: a fixed sequence of pseudo-random 64-bit words, no dependency needed.
struct Words(u64);

impl Iterator for Words {
    type Item = u64;
    fn next(&mut self) -> Option<u64> {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        Some(self.0.wrapping_mul(0x2545_f491_4f6c_dd1d))
    }
}

/// Doubles a scene accepts in `q` (|x| ≤ 1e90): half from random bit patterns, half of
/// ordinary size (where one ulp off was seen), with 0.9999999999999999 and friends.
fn doubles(n: usize) -> Vec<f64> {
    let mut words = Words(0x9e37_79b9_7f4a_7c15);
    let mut out =
        vec![0.9999999999999999, 1.0000000000000002, 0.1, 5e-324, -2.2250738585072014e-308];
    while out.len() < n {
        let w = words.next().unwrap_or_default();
        let x = if out.len() % 2 == 0 {
            f64::from_bits(w)
        } else {
            let unit = (w >> 11) as f64 / (1u64 << 53) as f64;
            (unit - 0.5) * 10f64.powi((w % 41) as i32 - 20)
        };
        if x.is_finite() && x.abs() <= 1e90 {
            out.push(x);
        }
    }
    out
}

#[test]
fn ten_thousand_doubles_round_trip_through_the_scene() {
    let (config, caches) = (Config::default(), Caches::default());
    let xs = doubles(10_000);
    let mut off = Vec::new();
    for pair in xs.chunks(2) {
        let (x, y) = (pair[0], *pair.get(1).unwrap_or(&0.0));
        // Rust prints the shortest text that reads back as the same double, as serde_json does.
        let body = format!(
            r#"{{"system": "knife_edge", "q": [{x:?}, {y:?}, 1.5707963267948966],
                "integrals": ["energy"], "methods": ["leapfrog"], "t_end": 1}}"#
        );
        let req: SimulateRequest = read_object(body.as_bytes()).expect("a valid body");
        let plan = Plan::resolve(&req, &config, &caches, Delivery::Json).expect("a valid scene");
        let echoed: Value = serde_json::to_value(&plan.scene).expect("the scene serializes");
        let text = serde_json::to_string(&echoed["q"]).expect("q serializes");
        let back: Vec<f64> = serde_json::from_str(&text).expect("q reads back");
        for (given, got) in [x, y].into_iter().zip(back) {
            if given.to_bits() != got.to_bits() {
                off.push((given, got));
            }
        }
    }
    assert!(
        off.is_empty(),
        "{} of {} doubles came back changed: {:?}",
        off.len(),
        xs.len(),
        &off[..off.len().min(5)]
    );
}

#[tokio::test]
async fn the_scene_as_printed_is_read_back_exactly_over_http() {
    let s = TestServer::start().await;
    // 0.9999999999999999 is how the server prints the double just below 1; read as 1 it
    // would move the start.
    let request = json!({"system": "knife_edge", "q": [0.9999999999999999, 0.30000000000000004,
        std::f64::consts::FRAC_PI_2], "t_end": 1, "methods": ["leapfrog"], "integrals": ["energy"]});
    let (status, first) = s.post_json("/simulate", &request).await;
    assert_eq!(status, 200, "{first}");
    assert_eq!(first["scene"]["q"], request["q"]);
    // The resolved scene, sent back, is the same scene.
    let scene = &first["scene"];
    let again = json!({"system": scene["system"], "params": scene["params"], "q": scene["q"],
        "v": scene["v"], "step": scene["step"], "t_end": scene["t_end"],
        "methods": ["leapfrog"], "integrals": ["energy"]});
    let (status, second) = s.post_json("/simulate", &again).await;
    assert_eq!(status, 200, "{second}");
    assert_eq!(second["scene"]["q"], first["scene"]["q"]);
    assert_eq!(second["runs"][0]["series"], first["runs"][0]["series"]);
}

#[tokio::test]
async fn a_parameter_given_twice_is_refused_in_params_too() {
    let s = TestServer::start().await;
    let body = r#"{"system": "cvt_pendulum", "params": {"epsilon": 0.1, "epsilon": 0.5}}"#;
    let response = s.post_text("/simulate", body).await;
    assert_eq!(response.status(), 400);
    let error: Value = response.json().await.expect("a JSON error");
    assert_eq!(error["path"], "params", "{error}");
    assert!(error["error"].as_str().unwrap_or_default().contains("`epsilon` is given twice"));
}

#[tokio::test]
async fn errors_write_huge_numbers_short() {
    let s = TestServer::start().await;
    for body in [
        json!({"system": "knife_edge", "points": 1e308}),
        json!({"system": "knife_edge", "methods": [{"id": "dla", "alpha": 1e300}]}),
        json!({"system": "knife_edge", "step": 1e-300, "t_end": 1e300}),
    ] {
        let (status, error) = s.post_json("/simulate", &body).await;
        assert!(status == 400 || status == 422, "{status} {error}");
        let message = error["error"].as_str().unwrap_or_default();
        let longest =
            message.split(|c: char| !c.is_ascii_digit()).map(str::len).max().unwrap_or_default();
        assert!(longest <= 17, "{longest} digits in a row: {message}");
    }
}
