//! Hostile bodies for `POST /simulate`, each with the status it must get: never a 5xx,
//! every error a JSON `{"error", "path"}`, and the server still serving afterwards.
//! (The fuzzer, `tests/fuzz/run.sh`, explores further from the OpenAPI document.)

use nhlab_tests::TestServer;
use serde_json::Value;

/// A JSON array of `n` copies of `item`.
fn many(item: &str, n: usize) -> String {
    format!("[{}]", vec![item; n].join(","))
}

fn hostile() -> Vec<(&'static str, Vec<u8>, u16)> {
    let ke = |rest: &str| format!(r#"{{"system": "knife_edge", {rest}}}"#).into_bytes();
    vec![
        // Huge, tiny and non-finite numbers.
        ("t_end 1e300", ke(r#""t_end": 1e300"#), 422),
        ("step 1e-300", ke(r#""step": 1e-300"#), 422),
        ("step subnormal", ke(r#""step": 5e-324"#), 422),
        ("step 1e308", ke(r#""step": 1e308"#), 422),
        ("step beyond f64", ke(r#""step": 1e999"#), 400),
        ("t_end -1e300", ke(r#""t_end": -1e300"#), 422),
        ("step negative", ke(r#""step": -0.1"#), 422),
        ("step -0", ke(r#""step": -0.0"#), 422),
        ("points 1e20", ke(r#""points": 1e20"#), 400),
        ("points 2^64", ke(r#""points": 18446744073709551616"#), 400),
        ("points i64::MAX", ke(r#""points": 9223372036854775807"#), 422),
        ("points negative", ke(r#""points": -5"#), 422),
        ("points i64::MIN", ke(r#""points": -9223372036854775808"#), 422),
        ("points zero", ke(r#""points": 0"#), 422),
        ("points fractional", ke(r#""points": 10.5"#), 400),
        ("epsilon 1e300", ke(r#""params": {"epsilon": 1e300}"#), 422),
        ("alpha 1e300", ke(r#""methods": [{"id": "dla", "alpha": 1e300}]"#), 422),
        ("v 1e308", ke(r#""v": [1e308, 0, 1e308]"#), 422),
        // NaN and infinities, bare (not JSON) and as strings (not numbers).
        ("NaN bare", ke(r#""step": NaN"#), 400),
        ("Infinity bare", ke(r#""t_end": Infinity"#), 400),
        ("NaN string", ke(r#""step": "NaN""#), 400),
        ("inf string param", ke(r#""params": {"epsilon": "inf"}"#), 400),
        ("NaN string alpha", ke(r#""methods": [{"id": "dla", "alpha": "NaN"}]"#), 400),
        ("NaN in q", ke(r#""q": [0, "NaN", 0]"#), 400),
        // Deep nesting (serde_json stops at 128 levels).
        ("deep arrays", ke(&format!(r#""q": {}{}"#, "[".repeat(20_000), "]".repeat(20_000))), 400),
        (
            "deep objects",
            ke(&format!(r#""params": {}1{}"#, r#"{"a":"#.repeat(5_000), "}".repeat(5_000))),
            400,
        ),
        ("deep unclosed", "[".repeat(60_000).into_bytes(), 400),
        // Big bodies and long lists.
        ("10 MB body", ke(&format!(r#""q": {}"#, many("0", 5_000_000))), 413),
        (
            "65 KiB of spaces",
            format!("{}{}", " ".repeat(66_000), r#"{"system":"knife_edge"}"#).into_bytes(),
            413,
        ),
        (
            "thousands of methods",
            ke(&format!(r#""methods": {}"#, many(r#""leapfrog""#, 5_000))),
            422,
        ),
        (
            "thousands of method params",
            ke(&format!(
                r#""methods": [{{"id": "dla", {}}}]"#,
                (0..2_000).map(|i| format!(r#""p{i}": 1"#)).collect::<Vec<_>>().join(",")
            )),
            422,
        ),
        (
            "thousands of integrals",
            ke(&format!(r#""integrals": {}"#, many(r#""energy""#, 5_000))),
            422,
        ),
        (
            "thousands of params",
            ke(&format!(
                r#""params": {{{}}}"#,
                (0..2_000).map(|i| format!(r#""e{i}": 1"#)).collect::<Vec<_>>().join(",")
            )),
            422,
        ),
        ("q of 5000", ke(&format!(r#""q": {}"#, many("0", 5_000))), 422),
        ("empty methods", ke(r#""methods": []"#), 422),
        ("empty integrals", ke(r#""integrals": []"#), 422),
        // Not the right shape at all.
        ("empty body", Vec::new(), 400),
        ("null", b"null".to_vec(), 400),
        ("array", b"[]".to_vec(), 400),
        ("string", br#""knife_edge""#.to_vec(), 400),
        ("number", b"1e300".to_vec(), 400),
        ("system missing", b"{}".to_vec(), 400),
        ("system null", br#"{"system": null}"#.to_vec(), 400),
        ("system number", br#"{"system": 1}"#.to_vec(), 400),
        ("duplicate field", br#"{"system": "knife_edge", "system": "cvt"}"#.to_vec(), 400),
        ("unknown field", ke(r#""__proto__": {}"#), 400),
        ("method object without id", ke(r#""methods": [{"alpha": 0.5}]"#), 400),
        ("method id number", ke(r#""methods": [7]"#), 400),
        ("invalid UTF-8", b"{\"system\": \"\xff\xfe\"}".to_vec(), 400),
        ("lone surrogate", br#"{"system": "\ud800"}"#.to_vec(), 400),
        ("NUL in system", br#"{"system": "knife_edge\u0000"}"#.to_vec(), 422),
        ("long system id", format!(r#"{{"system": "{}"}}"#, "x".repeat(60_000)).into_bytes(), 422),
        ("trailing garbage", br#"{"system": "knife_edge"} {"#.to_vec(), 400),
        ("preset of another system", ke(r#""preset": "rotating""#), 422),
        ("integral the system lacks", ke(r#""integrals": ["latitude"]"#), 422),
        // A state the run would count as diverged from its first step (over 1e100): refused.
        ("q far away", ke(r#""preset": "paper", "q": [1e300, -1e300, 1.5]"#), 422),
        ("q 1e308", ke(r#""q": [1e308, 1e308, 1e308]"#), 422),
        ("v 1e150", ke(r#""preset": "paper", "v": [0, 0, 1e150], "t_end": 1"#), 422),
        // Within every limit: it runs (and a run may fail, saying why), never a 5xx.
        ("q far", ke(r#""preset": "paper", "q": [1e89, -1e89, 1.5]"#), 200),
        ("fast and short", ke(r#""preset": "paper", "v": [0, 0, 1e89], "t_end": 1"#), 200),
    ]
}

#[tokio::test]
async fn hostile_bodies_get_their_status_and_json_errors() {
    let server = TestServer::start().await;
    let client = reqwest::Client::new();
    let mut wrong = Vec::new();
    for (name, body, expected) in hostile() {
        let response = client
            .post(server.at("/simulate"))
            .header("content-type", "application/json")
            .body(body)
            .send()
            .await
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let status = response.status().as_u16();
        let content_type = response.headers()["content-type"].to_str().unwrap().to_owned();
        let text = response.text().await.unwrap();
        let json: Option<Value> = serde_json::from_str(&text).ok();
        let is_error_json = json.as_ref().is_some_and(|j| j["error"].is_string());
        let ok = status == expected
            && content_type == "application/json"
            && (status == 200 || is_error_json);
        if !ok {
            let shown: String = text.chars().take(300).collect();
            wrong.push(format!("{name}: {status} (expected {expected}) {content_type} {shown}"));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
    // Still serving.
    assert_eq!(reqwest::get(server.at("/health")).await.unwrap().status(), 200);
}
