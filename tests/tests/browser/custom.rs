//! The custom-system editor: opened from a built-in, a formula changed and run; a bad
//! formula's error at its input; a link that brings the custom system back and reruns it.

use crate::driver::Driver;
use crate::explore::console_clean;
use crate::page::{PLOT_REPORT, js, screenshot, wait_for_status, wait_for_view};
use fantoccini::{Client, Locator};
use serde_json::json;
use std::time::Duration;

/// The knife edge's U with a small well across the slope: a system nhlab does not have.
const NEW_U: &str = "-x1 + x2^2/50";

/// Opens the editor from the knife edge, changes U, runs, breaks a constraint entry, then
/// reloads the successful run's link.
pub(crate) async fn custom_system(
    client: &Client,
    driver: &Driver,
    base: &str,
) -> Result<(), String> {
    // The previous scenario's expected 422 is still in the log: start from a clean one.
    driver.browser_log(client).await?;
    let link = format!("{base}?system=knife_edge&preset=paper");
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    client
        .wait()
        .at_most(Duration::from_secs(20))
        .for_element(Locator::Css("#system option[value='(custom)']"))
        .await
        .map_err(|e| format!("the system picker offers no custom system: {e}"))?;
    let err = |e: fantoccini::error::CmdError| e.to_string();
    let find = |css: &'static str| async move {
        client.find(Locator::Css(css)).await.map_err(|e| format!("{css}: {e}"))
    };
    find("#system").await?.select_by_value("(custom)").await.map_err(err)?;

    // The editor shows the knife edge as the server writes it, at the preset's values.
    let editor = js(client, EDITOR_REPORT).await?;
    let catalog = js(client, "return fetch('systems').then((r) => r.json()).then((c) => c.systems.find((s) => s.id === 'knife_edge').formulas);").await?;
    assert_eq!(editor["hidden"], json!(false), "the editor opens: {editor}");
    assert_eq!(editor["U"], catalog["passenger_potential"], "U from /systems: {editor}");
    assert_eq!(editor["constraints"], catalog["constraints"], "A from /systems: {editor}");
    assert_eq!(editor["q"], json!("0, 0, 1.5707963267948966"), "the preset's q(0): {editor}");
    assert_eq!(editor["parameters"], json!([["epsilon", "0"]]), "{editor}");

    let u = find("#custom-U").await?;
    u.clear().await.map_err(err)?;
    u.send_keys(NEW_U).await.map_err(err)?;
    find("#run").await?.click().await.map_err(err)?;
    let (state, text) = wait_for_status(client).await?;
    let shot = screenshot(client, "custom-system.png").await;
    assert_eq!(state, "done", "the custom run ended with {text:?} ({shot})");
    let plot = js(client, PLOT_REPORT).await?;
    let series = plot["series"].as_array().ok_or_else(|| format!("no energy chart: {plot}"))?;
    assert_eq!(series.len(), 5, "the five default methods: {plot}");
    for s in series {
        assert_eq!(s["drawn"], json!(true), "a curve is not drawn: {plot}");
        assert!(s["points"].as_u64().unwrap_or(0) >= 100, "a curve lacks data: {plot}");
    }
    assert_eq!(plot["runs"], json!(["ok", "ok", "ok", "ok", "ok"]), "{plot}");
    let caption =
        js(client, "return document.querySelector('.plot-card .plot-scene')?.textContent ?? '';")
            .await?;
    assert!(
        caption.as_str().unwrap_or_default().contains("(custom)"),
        "the plot card names the custom system: {caption}"
    );
    let url = js(client, "return location.href;").await?;
    let url = url.as_str().unwrap_or_default().to_owned();
    assert!(
        url.contains("custom=") && url.contains("run=1") && !url.contains("system="),
        "the custom system is in the URL: {url}"
    );
    console_clean(driver, client, "custom system").await?;

    bad_formula(client).await?;
    driver.browser_log(client).await?;

    // The link of the successful run brings the system back and runs it again.
    client.goto(&url).await.map_err(|e| format!("cannot load {url}: {e}"))?;
    let (state, text) = wait_for_status(client).await?;
    assert_eq!(state, "done", "the custom link ran with {text:?}");
    let editor = js(client, EDITOR_REPORT).await?;
    assert_eq!(editor["system"], "(custom)", "{editor}");
    assert_eq!(editor["U"], NEW_U, "the link keeps the edited U: {editor}");
    assert_eq!(editor["constraints"], catalog["constraints"], "{editor}");
    assert_eq!(editor["q"], json!("0, 0, 1.5707963267948966"), "{editor}");
    let plot = js(client, PLOT_REPORT).await?;
    assert_eq!(plot["runs"], json!(["ok", "ok", "ok", "ok", "ok"]), "{plot}");
    console_clean(driver, client, "custom system from its link").await?;
    work_precision(client).await?;
    start_from(client).await?;
    println!("custom system: edited, run, error at its input, link reproduces it ({shot})");
    Ok(())
}

/// A stray parenthesis in a constraint entry: the server's message under that entry's row,
/// the entry marked.
async fn bad_formula(client: &Client) -> Result<(), String> {
    let entry = client
        .find(Locator::Css("[data-path='system.constraints[0][1]'] input"))
        .await
        .map_err(|e| format!("no input for system.constraints[0][1]: {e}"))?;
    entry.clear().await.map_err(|e| e.to_string())?;
    entry.send_keys("cos(zeta) - epsilon)").await.map_err(|e| e.to_string())?;
    client
        .find(Locator::Id("run"))
        .await
        .map_err(|e| e.to_string())?
        .click()
        .await
        .map_err(|e| e.to_string())?;
    let (state, text) = wait_for_status(client).await?;
    let shot = screenshot(client, "custom-bad-formula.png").await;
    assert_eq!(state, "error", "a bad formula is rejected; the page said {text:?} ({shot})");
    let field = js(
        client,
        r#"const f = document.querySelector('[data-path="system.constraints[0][1]"]');
           return [f.classList.contains('invalid'),
                   f.closest('.custom-row')?.querySelector('.field-error')?.textContent ?? null];"#,
    )
    .await?;
    assert_eq!(field[0], json!(true), "the entry is marked invalid: {field} ({shot})");
    let message = field[1].as_str().unwrap_or_default();
    assert!(message.contains(')'), "the server's message sits under the entry: {field}");
    Ok(())
}

/// The Work–precision tab measures the custom system too, and names it; then back to Explore.
async fn work_precision(client: &Client) -> Result<(), String> {
    let tab = |view: &'static str| async move {
        client
            .find(Locator::Css(&format!(".tabs .tab[data-view=\"{view}\"]")))
            .await
            .map_err(|e| format!("no {view} tab: {e}"))?
            .click()
            .await
            .map_err(|e| format!("cannot click the {view} tab: {e}"))
    };
    tab("work-precision").await?;
    let (state, text) = wait_for_view(client, "view-work-precision").await?;
    assert_eq!(state, "done", "work–precision on the custom system: {text:?}");
    assert!(text.contains("(custom)"), "the status names the custom system: {text:?}");
    tab("main").await
}

/// "Start from" refills the editor and the initial state from another built-in: the rolling
/// disk's three passengers and two constraints (no latitude offered), the pendulum CVT's
/// latitude (offered, and checked as the built-in has it).
async fn start_from(client: &Client) -> Result<(), String> {
    let select = client.find(Locator::Id("custom-start")).await.map_err(|e| e.to_string())?;
    select.select_by_value("paper:rolling_disk").await.map_err(|e| e.to_string())?;
    let editor = js(client, EDITOR_REPORT).await?;
    let rows = editor["constraints"].as_array().cloned().unwrap_or_default();
    assert_eq!(rows.len(), 2, "two constraints: {editor}");
    assert!(rows.iter().all(|r| r.as_array().map(Vec::len) == Some(3)), "{editor}");
    assert_eq!(editor["q"].as_str().unwrap_or_default().split(',').count(), 4, "{editor}");
    assert!(!editor["integrals"].to_string().contains("latitude"), "{editor}");
    let url = js(client, "return location.search;").await?;
    assert!(url.as_str().unwrap_or_default().contains("passenger=x1,x2,phi"), "{url}");

    let select = client.find(Locator::Id("custom-start")).await.map_err(|e| e.to_string())?;
    select.select_by_value("paper:cvt_pendulum").await.map_err(|e| e.to_string())?;
    let editor = js(client, EDITOR_REPORT).await?;
    assert_eq!(editor["checked"], json!(true), "the latitude offered and checked: {editor}");
    Ok(())
}

/// What the editor shows.
const EDITOR_REPORT: &str = r#"
return {
  system: document.getElementById('system').value,
  hidden: document.getElementById('custom-editor').hidden,
  U: document.getElementById('custom-U').value,
  parameters: [...document.querySelectorAll('#custom-params .custom-param')]
    .map((r) => [r.querySelector('.param-name').value, r.querySelector('.param-value').value]),
  constraints: [...document.querySelectorAll('#custom-constraints .custom-row')]
    .map((r) => [...r.querySelectorAll('.custom-cell input')].map((i) => i.value)),
  q: document.getElementById('q').value,
  integrals: [...document.querySelectorAll('#integrals input')].map((b) => b.value),
  checked: document.querySelector('#integrals input[value="latitude"]')?.checked ?? null,
};
"#;
