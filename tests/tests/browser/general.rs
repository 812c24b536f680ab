//! Systems beyond the paper's class: the Chaplygin sleigh picked in Explore (only the methods
//! and integrals it has, why it is outside the class) and run; the chaotic oscillator's n = 2
//! preset with its five coordinates; a custom system in the general form started from the
//! sleigh, run, then a bad mass entry and a bad invariant shown at their inputs.

use crate::driver::Driver;
use crate::explore::console_clean;
use crate::page::{PLOT_REPORT, click, js, poll, screenshot, wait_for_status};
use crate::widths::OVERFLOW;
use fantoccini::{Client, Locator};
use serde_json::json;
use std::time::Duration;

/// What the form offers and says for the system shown.
const FORM_REPORT: &str = r#"
return {
  system: document.getElementById('system').value,
  class: document.getElementById('system-class').textContent,
  add: [...document.querySelectorAll('#add-method-id option')].map((o) => o.value),
  methods: [...document.querySelectorAll('#methods .method-on')].map((b) => b.dataset.id),
  integrals: [...document.querySelectorAll('#integrals input')].map((b) => [b.value, b.checked]),
  q: document.getElementById('q').value,
  v: document.getElementById('v').value,
  qHint: document.getElementById('q').placeholder,
  sceneClass: document.getElementById('scene-class').hidden ? null : document.getElementById('scene-class').textContent,
  form: document.getElementById('custom-editor').dataset.form ?? null,
  url: location.search,
};
"#;

pub(crate) async fn sleigh_in_explore(
    client: &Client,
    driver: &Driver,
    base: &str,
) -> Result<(), String> {
    driver.browser_log(client).await?;
    // DD-AVF among the methods: it does not apply to the sleigh, and is left out on the switch.
    let link = format!("{base}?system=knife_edge&preset=paper&methods=dd_avf,leapfrog,dd,rattle");
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    let err = |e: fantoccini::error::CmdError| e.to_string();
    client
        .wait()
        .at_most(Duration::from_secs(20))
        .for_element(Locator::Css("#system option[value='chaplygin_sleigh']"))
        .await
        .map_err(|e| format!("the system picker does not offer the sleigh: {e}"))?;
    let offered =
        js(client, "return [...document.querySelectorAll('#system option')].map((o) => o.value);")
            .await?;
    let catalog = js(
        client,
        "return fetch('systems').then((r) => r.json()).then((c) => c.systems.map((s) => s.id));",
    )
    .await?;
    let mut every = catalog.as_array().cloned().unwrap_or_default();
    every.push(json!("(custom)"));
    assert_eq!(offered, json!(every), "the picker offers every system and a custom one");
    let before = js(client, FORM_REPORT).await?;
    let class = before["class"].as_str().unwrap_or("");
    assert!(class.starts_with("In the paper’s class") && class.contains("driver zeta"), "{before}");
    assert!(before["add"].as_array().is_some_and(|a| a.contains(&json!("dd_avf"))), "{before}");

    let select = client.find(Locator::Id("system")).await.map_err(err)?;
    select.select_by_value("chaplygin_sleigh").await.map_err(err)?;
    let form = js(client, FORM_REPORT).await?;
    let class = form["class"].as_str().unwrap_or_default();
    assert!(
        class.starts_with("Outside the paper’s class") && class.contains("theta's column"),
        "the sleigh says why it is outside the class: {form}"
    );
    assert!(!form["add"].as_array().is_some_and(|a| a.contains(&json!("dd_avf"))), "{form}");
    assert!(form["add"].as_array().is_some_and(|a| a.contains(&json!("rattle"))), "{form}");
    assert_eq!(form["methods"], json!(["leapfrog", "dd", "rattle"]), "DD-AVF left out: {form}");
    assert_eq!(
        form["integrals"],
        json!([["energy", true], ["constraint", true]]),
        "only the integrals the sleigh has: {form}"
    );
    assert_eq!(form["qHint"], "3 numbers: x, y, theta", "{form}");

    client.find(Locator::Id("run")).await.map_err(err)?.click().await.map_err(err)?;
    let (state, text) = wait_for_status(client).await?;
    let shot = screenshot(client, "sleigh.png").await;
    assert_eq!(state, "done", "the sleigh ran with {text:?} ({shot})");
    let plot = js(client, PLOT_REPORT).await?;
    assert_eq!(plot["integrals"], json!(["energy", "constraint"]), "{plot}");
    assert_eq!(plot["runs"], json!(["ok", "ok", "ok"]), "{plot}");
    for s in plot["series"].as_array().ok_or_else(|| format!("no energy chart: {plot}"))? {
        assert_eq!(s["drawn"], json!(true), "a curve is not drawn: {plot}");
    }
    let form = js(client, FORM_REPORT).await?;
    let said = form["sceneClass"].as_str().unwrap_or_default();
    assert!(said.starts_with("Outside the paper’s class"), "the results say so too: {form}");
    assert!(form["url"].as_str().unwrap_or("").contains("system=chaplygin_sleigh"), "{form}");
    console_clean(driver, client, "the sleigh in Explore").await?;

    // The chaotic oscillator at n = 2: five coordinates from its preset, and it runs.
    let select = client.find(Locator::Id("system")).await.map_err(err)?;
    select.select_by_value("chaotic_oscillator").await.map_err(err)?;
    let preset = client.find(Locator::Id("preset")).await.map_err(err)?;
    preset.select_by_value("n2").await.map_err(err)?;
    let form = js(client, FORM_REPORT).await?;
    assert_eq!(form["q"].as_str().unwrap_or("").split(',').count(), 5, "{form}");
    assert_eq!(form["v"].as_str().unwrap_or("").split(',').count(), 5, "{form}");
    assert_eq!(form["qHint"], "5 numbers", "{form}");
    let t_end = client.find(Locator::Id("t_end")).await.map_err(err)?;
    t_end.clear().await.map_err(err)?;
    t_end.send_keys("50").await.map_err(err)?;
    client.find(Locator::Id("run")).await.map_err(err)?.click().await.map_err(err)?;
    let (state, text) = wait_for_status(client).await?;
    let shot = screenshot(client, "chaotic-n2.png").await;
    assert_eq!(state, "done", "n = 2 ran with {text:?} ({shot})");
    let plot = js(client, PLOT_REPORT).await?;
    assert_eq!(plot["runs"], json!(["ok", "ok", "ok"]), "{plot}");
    console_clean(driver, client, "the chaotic oscillator at n = 2").await?;
    println!(
        "sleigh in Explore: DD-AVF left out, energy and constraint only, ran; n = 2 ran ({shot})"
    );
    Ok(())
}

/// The editor in the general form, from the sleigh: it runs; then an entry of M that names a
/// coordinate and an invariant that does not parse are each shown at their input.
pub(crate) async fn general_custom(
    client: &Client,
    driver: &Driver,
    base: &str,
) -> Result<(), String> {
    driver.browser_log(client).await?;
    let link = format!("{base}?system=knife_edge&preset=paper&methods=leapfrog,dd&t_end=20");
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    let err = |e: fantoccini::error::CmdError| e.to_string();
    let find = |css: &'static str| async move {
        client.find(Locator::Css(css)).await.map_err(|e| format!("{css}: {e}"))
    };
    client
        .wait()
        .at_most(Duration::from_secs(20))
        .for_element(Locator::Css("#system option[value='(custom)']"))
        .await
        .map_err(|e| format!("no custom system: {e}"))?;
    find("#system").await?.select_by_value("(custom)").await.map_err(err)?;
    find("#custom-start").await?.select_by_value("general:chaplygin_sleigh").await.map_err(err)?;
    let editor = js(client, GENERAL_REPORT).await?;
    let general = js(
        client,
        "return fetch('systems').then((r) => r.json()).then((c) => c.systems.find((s) => s.id === 'chaplygin_sleigh').general);",
    )
    .await?;
    assert_eq!(editor["form"], "general", "{editor}");
    assert_eq!(editor["coordinates"], "x, y, theta", "{editor}");
    assert_eq!(editor["mode"], "diagonal", "{editor}");
    assert_eq!(editor["mass"], json!([general["mass"]]), "M from /systems: {editor}");
    assert_eq!(editor["V"], general["potential"], "{editor}");
    assert_eq!(editor["constraints"], general["constraints"], "{editor}");
    assert_eq!(editor["q"], "0, 0, 0", "the sleigh's first preset: {editor}");

    // Its kinetic energy as an invariant (g = 0): measured, and checked by default.
    click(client, "#custom-add-invariant").await?;
    let name = find("#custom-invariants .custom-param:last-child .param-name").await?;
    name.send_keys("kinetic").await.map_err(err)?;
    let formula = find("#custom-invariants .custom-param:last-child .param-value").await?;
    formula.send_keys("m*(x_dot^2 + y_dot^2)/2 + I*theta_dot^2/2").await.map_err(err)?;
    click(client, "#custom-name").await?;
    let editor = js(client, GENERAL_REPORT).await?;
    assert!(
        editor["integrals"].as_array().is_some_and(|a| a.contains(&json!(["kinetic", true]))),
        "the new invariant is offered and checked: {editor}"
    );
    find("#run").await?.click().await.map_err(err)?;
    let (state, text) = wait_for_status(client).await?;
    let shot = screenshot(client, "custom-general.png").await;
    assert_eq!(state, "done", "the general-form sleigh ran with {text:?} ({shot})");
    let report = js(client, GENERAL_REPORT).await?;
    assert!(
        report["sceneClass"].as_str().unwrap_or("").starts_with("Outside the paper’s class"),
        "{report}"
    );
    assert_eq!(report["plots"], json!(["energy", "constraint", "kinetic"]), "{report}");
    let url = report["url"].as_str().unwrap_or_default().to_owned();
    assert!(url.contains("coordinates=x,y,theta") && url.contains("inv.kinetic="), "{url}");
    console_clean(driver, client, "general-form custom system").await?;

    // M's last entry names a coordinate: the server's message under the mass row.
    let entry = find("[data-path='system.mass[2]'] input").await?;
    entry.clear().await.map_err(err)?;
    entry.send_keys("theta").await.map_err(err)?;
    find("#run").await?.click().await.map_err(err)?;
    let (state, text) = wait_for_status(client).await?;
    let shot = screenshot(client, "custom-general-bad-mass.png").await;
    assert_eq!(state, "error", "M with a coordinate is rejected; the page said {text:?} ({shot})");
    let field = js(client, &at_field("system.mass[2]")).await?;
    assert_eq!(field[0], json!(true), "the entry is marked: {field} ({shot})");
    assert!(field[1].as_str().unwrap_or("").contains("'theta' is a coordinate"), "{field}");
    entry.clear().await.map_err(err)?;
    entry.send_keys("I").await.map_err(err)?;

    // An invariant that does not parse: at its row.
    let formula = find("#custom-invariants .custom-param:last-child .param-value").await?;
    formula.clear().await.map_err(err)?;
    formula.send_keys("m*x_dot^").await.map_err(err)?;
    find("#run").await?.click().await.map_err(err)?;
    let (state, text) = wait_for_status(client).await?;
    let shot = screenshot(client, "custom-general-bad-invariant.png").await;
    assert_eq!(state, "error", "a bad invariant is rejected; the page said {text:?} ({shot})");
    let field = js(client, &at_field("system.invariants.kinetic")).await?;
    assert_eq!(field[0], json!(true), "the invariant is marked: {field} ({shot})");
    assert!(field[1].as_str().unwrap_or("").contains("at 9"), "the server's message: {field}");

    // The form switch writes the system in the paper's form, and back.
    find("#custom-form").await?.select_by_value("paper").await.map_err(err)?;
    let editor = js(client, GENERAL_REPORT).await?;
    assert_eq!(editor["form"], "paper", "{editor}");
    assert_eq!(editor["passenger"], "x, y", "{editor}");
    // A link of the run brings the general form back.
    client.goto(&url).await.map_err(|e| format!("cannot load {url}: {e}"))?;
    let (state, text) = wait_for_status(client).await?;
    assert_eq!(state, "done", "the general-form link ran with {text:?}");
    let editor = js(client, GENERAL_REPORT).await?;
    assert_eq!(editor["form"], "general", "{editor}");
    assert_eq!(
        editor["invariants"],
        json!([["kinetic", "m*(x_dot^2 + y_dot^2)/2 + I*theta_dot^2/2"]]),
        "{editor}"
    );
    // A full M: a row per coordinate, the diagonal kept; the editor fits 400 px.
    find("#custom-mass-mode").await?.select_by_value("full").await.map_err(err)?;
    let editor = js(client, GENERAL_REPORT).await?;
    assert_eq!(
        editor["mass"],
        json!([["m", "0", "0"], ["0", "m", "0"], ["0", "0", "I"]]),
        "{editor}"
    );
    client.set_window_size(400, 800).await.map_err(err)?;
    let fit = poll(
        client,
        &format!("return innerWidth <= 400 ? (() => {{ {OVERFLOW} }})() : null;"),
        Duration::from_secs(3),
    )
    .await?;
    js(client, "document.getElementById('custom-editor').scrollIntoView();").await?;
    let narrow = screenshot(client, "custom-general-400.png").await;
    client.set_window_size(1440, 1500).await.map_err(err)?;
    assert!(
        fit["scrollWidth"].as_f64() <= fit["innerWidth"].as_f64(),
        "the general-form editor scrolls sideways at 400 px: {fit} ({narrow})"
    );
    driver.browser_log(client).await?;
    println!("general-form custom system: ran, bad M entry and invariant at their inputs ({shot})");
    Ok(())
}

/// Whether the field at `path` is marked, and the message under its row.
fn at_field(path: &str) -> String {
    format!(
        r#"const f = document.querySelector('[data-path="{path}"]');
           const row = f?.closest('.custom-row') ?? f;
           return [f?.classList.contains('invalid') ?? false,
                   row?.querySelector('.field-error')?.textContent ?? null];"#
    )
}

/// What the general-form editor shows.
const GENERAL_REPORT: &str = r#"
const rows = (id) => [...document.querySelectorAll(`#${id} .custom-row`)]
  .map((r) => [...r.querySelectorAll('.custom-cell input')].map((i) => i.value));
return {
  form: document.getElementById('custom-editor').dataset.form ?? null,
  coordinates: document.getElementById('custom-coordinates').value,
  passenger: document.getElementById('custom-passenger').value,
  mode: document.getElementById('custom-mass-mode').value,
  mass: rows('custom-mass'),
  V: document.getElementById('custom-V').value,
  constraints: rows('custom-constraints'),
  invariants: [...document.querySelectorAll('#custom-invariants .custom-param')]
    .map((r) => [r.querySelector('.param-name').value, r.querySelector('.param-value').value]),
  integrals: [...document.querySelectorAll('#integrals input')].map((b) => [b.value, b.checked]),
  q: document.getElementById('q').value,
  plots: [...document.querySelectorAll('.plot-card')].map((c) => c.dataset.integral),
  sceneClass: document.getElementById('scene-class').hidden ? null : document.getElementById('scene-class').textContent,
  url: location.search,
};
"#;
