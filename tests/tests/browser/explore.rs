//! The Explore view: the knife-edge experiment, failed runs, Cancel, the form in the URL,
//! a bad parameter's error next to its field.

use crate::RUN_TIMEOUT;
use crate::driver::Driver;
use crate::page::{PLOT_REPORT, js, screenshot, wait_for_status};
use fantoccini::{Client, Locator};
use serde_json::{Value, json};
use std::time::{Duration, Instant};

/// One click on the paper's knife-edge experiment.
pub(crate) async fn knife_edge(client: &Client, driver: &Driver, base: &str) -> Result<(), String> {
    client.goto(base).await.map_err(|e| format!("cannot load {base}: {e}"))?;
    let button = r#"#experiments button[data-system="knife_edge"][data-preset="paper"]"#;
    client
        .wait()
        .at_most(Duration::from_secs(20))
        .for_element(Locator::Css(button))
        .await
        .map_err(|e| format!("the page shows no knife-edge experiment button ({button}): {e}"))?
        .click()
        .await
        .map_err(|e| format!("cannot click the experiment button: {e}"))?;
    let status = wait_for_status(client).await;
    let shot = screenshot(client, "knife-edge.png").await;
    let (state, text) = status?;
    if state != "done" {
        return Err(format!("the run ended in state {state:?}: {text:?} (screenshot: {shot})"));
    }

    let progress = js(client, "const p = document.getElementById('progress'); return [p.value / p.max, document.getElementById('progress-text').textContent];").await?;
    assert_eq!(
        progress[0].as_f64(),
        Some(1.0),
        "the progress bar must finish: {progress} (screenshot: {shot})"
    );
    assert_eq!(progress[1], "100%", "the progress text must say 100 %: {progress}");

    let plot = js(client, PLOT_REPORT).await?;
    let integrals = &plot["integrals"];
    assert_eq!(integrals, &json!(["energy"]), "the knife-edge experiment plots the energy only");
    let series = plot["series"].as_array().ok_or("no uPlot chart on the energy card")?;
    let labels: Vec<&str> = series.iter().map(|s| s["label"].as_str().unwrap_or("?")).collect();
    assert_eq!(
        labels,
        ["DLA⁰·⁵", "DLA⁰·⁴", "DLA⁰˒¹", "LF", "DD"],
        "one curve per paper method, labelled for people: {plot}"
    );
    for s in series {
        assert_eq!(s["show"], json!(true), "curve hidden: {s}");
        assert_eq!(s["drawn"], json!(true), "uPlot built no path for a curve: {s}");
        let points = s["points"].as_u64().unwrap_or(0);
        assert!(points >= 100, "a curve has {points} points, expected about a thousand: {s}");
    }
    assert_eq!(plot["legend"], json!(labels), "the legend lists the five methods");
    assert_eq!(plot["runs"], json!(["ok", "ok", "ok", "ok", "ok"]), "every run succeeds: {plot}");
    // The runs table says each run's verdict beside it: on the knife edge, DD keeps the energy
    // to round-off and DLA^0.4, the one method that is not reversible, lets it drift.
    let verdicts = js(
        client,
        "return [...document.querySelectorAll('#runs tbody tr.run')].map((tr) => \
         [...tr.querySelectorAll('.verdict-chip')].map((c) => [c.dataset.integral, c.dataset.kind, c.title]));",
    )
    .await?;
    let rows = verdicts.as_array().ok_or("no runs table rows")?;
    assert_eq!(rows.len(), 5, "one row per run: {verdicts}");
    for (label, row) in labels.iter().zip(rows) {
        let chips = row.as_array().map(Vec::as_slice).unwrap_or_default();
        assert_eq!(chips.len(), 1, "{label}: one verdict, the energy's: {row}");
        assert_eq!(chips[0][0], "energy", "{label}: {row}");
        let kind = chips[0][1].as_str().unwrap_or_default();
        assert!(matches!(kind, "exact" | "bounded" | "drift"), "{label}: {kind}: {row}");
        assert!(
            chips[0][2].as_str().unwrap_or_default().contains("max"),
            "{label}: numbers on hover"
        );
    }
    assert_eq!(rows[1][0][1], "drift", "DLA^0.4 drifts: {verdicts}");
    assert_eq!(rows[4][0][1], "exact", "DD keeps the knife edge's energy to round-off: {verdicts}");
    let url = js(client, "return location.search;").await?;
    let url = url.as_str().unwrap_or_default();
    assert!(
        url.contains("system=knife_edge") && url.contains("preset=paper") && url.contains("run=1"),
        "the URL must reproduce the run: {url}"
    );

    console_clean(driver, client, "knife edge").await?;
    println!("knife edge: five curves drawn, progress 100 %, console clean; screenshot {shot}");
    Ok(())
}

/// A link whose step is far too large for the implicit methods: the runs that fail say so in
/// the runs table (with the server's message) and in the legend, the others still plot.
pub(crate) async fn failed_runs(
    client: &Client,
    driver: &Driver,
    base: &str,
) -> Result<(), String> {
    let link = format!(
        "{base}?system=cvt_pendulum&preset=oscillating&step=2.5&t_end=300&integrals=energy&run=1"
    );
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    let (state, text) = wait_for_status(client).await?;
    let shot = screenshot(client, "failed-runs.png").await;
    assert_eq!(
        state, "done-failed",
        "some runs must fail with h = 2.5 on the CVT; the page said {text:?} ({shot})"
    );
    let report = js(client, FAILED_REPORT).await?;
    let runs: Vec<&str> = report["runs"]
        .as_array()
        .map(|a| a.iter().filter_map(Value::as_str).collect())
        .unwrap_or_default();
    let failed = runs.iter().filter(|s| **s == "failed").count();
    assert!(failed >= 1 && failed < runs.len(), "expected some runs failed, some ok: {report}");
    let messages = report["messages"].as_array().map(Vec::len).unwrap_or(0);
    assert_eq!(messages, failed, "each failed run shows its message: {report}");
    let legend = report["legend"].as_array().map(Vec::len).unwrap_or(0);
    assert_eq!(legend, failed, "each failed run is marked in the legend: {report}");
    console_clean(driver, client, "failed runs").await
}

/// DLA^0.4 brings the rotating pendulum CVT's passenger to rest by t ≈ 7·10⁴: its latitude
/// curve stops there, and the page says why under the plot and in the runs table (the API's
/// gap), where LF's goes on without a word.
pub(crate) async fn gap_message(
    client: &Client,
    driver: &Driver,
    base: &str,
) -> Result<(), String> {
    let link = format!(
        "{base}?system=cvt_pendulum&preset=rotating&t_end=300000&integrals=latitude\
         &methods=dla:0.4,leapfrog&run=1"
    );
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    let (state, text) = wait_for_status(client).await?;
    let shot = screenshot(client, "gap.png").await;
    assert_eq!(state, "done", "both runs end ok; the page said {text:?} ({shot})");
    let report = js(client, GAP_REPORT).await?;
    let rows: Vec<&str> = report["rows"]
        .as_array()
        .map(|a| a.iter().filter_map(Value::as_str).collect())
        .unwrap_or_default();
    assert_eq!(rows.len(), 1, "one run has a gap, in the runs table: {report} ({shot})");
    assert!(rows[0].contains("no value since t = ") && rows[0].contains("at rest"), "{report}");
    let note = report["note"].as_str().unwrap_or_default();
    assert!(note.contains("no value since t = ") && note.contains("at rest"), "{report} ({shot})");
    console_clean(driver, client, "gap").await
}

/// The gap rows of the runs table and the note under the latitude plot.
const GAP_REPORT: &str = r#"
const note = document.querySelector('.plot-card[data-integral="latitude"] .gap-note');
return {
  rows: [...document.querySelectorAll('#runs tr.run-gap td')].map((t) => t.textContent),
  note: note && !note.hidden ? note.textContent : null,
};
"#;

/// The runs table's badges and messages, and the legend entries marked failed.
const FAILED_REPORT: &str = r#"
return {
  runs: [...document.querySelectorAll('#runs tr.run .badge')].map((b) => b.textContent),
  messages: [...document.querySelectorAll('#runs tr.run-error td')].map((t) => t.textContent),
  legend: [...document.querySelectorAll('.plot-card .u-legend .u-series.failed .u-label')]
    .map((e) => e.textContent),
};
"#;

/// A long run: curves appear before it ends (the stream is live), and Cancel stops it.
pub(crate) async fn cancel(client: &Client, driver: &Driver, base: &str) -> Result<(), String> {
    let link = format!(
        "{base}?system=cvt_pendulum&preset=oscillating&t_end=10000000&integrals=energy&run=1"
    );
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    let start = Instant::now();
    loop {
        let v = js(client, LIVE_REPORT).await?;
        if v[0].as_f64().unwrap_or(0.0) > 0.0 && v[1].as_u64().unwrap_or(0) > 0 {
            break;
        }
        if start.elapsed() > RUN_TIMEOUT {
            return Err(format!("no progress and no points within {RUN_TIMEOUT:?}: {v}"));
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    let button = client.find(Locator::Id("cancel")).await.map_err(|e| e.to_string())?;
    button.click().await.map_err(|e| format!("cannot click Cancel: {e}"))?;
    let (state, text) = wait_for_status(client).await?;
    assert_eq!(state, "cancelled", "Cancel stops the run; the page said {text:?}");
    let v = js(client, AFTER_CANCEL).await?;
    assert!(v[0].as_f64().unwrap_or(1.0) < 1.0, "a cancelled run is not complete: {v}");
    let badges = v[1].as_array().cloned().unwrap_or_default();
    assert!(badges.iter().any(|s| s == "cancelled"), "runs show as cancelled: {v}");
    assert_eq!(v[2], json!(false), "Run is enabled again after Cancel: {v}");
    console_clean(driver, client, "cancel").await
}

/// Progress so far and the number of points drawn on the first chart.
const LIVE_REPORT: &str = "const u = document.querySelector('.plot-card')?.uplot;
return [document.getElementById('progress').value,
        u ? u.data.slice(1).reduce((n, d) => n + d.filter((x) => x != null).length, 0) : 0];";

const AFTER_CANCEL: &str = "return [document.getElementById('progress').value,
  [...document.querySelectorAll('#runs tr.run .badge')].map((b) => b.textContent),
  document.getElementById('run').disabled];";

/// Editing the form rewrites the URL, and loading that URL restores the form.
pub(crate) async fn form_in_the_url(
    client: &Client,
    driver: &Driver,
    base: &str,
) -> Result<(), String> {
    client.goto(base).await.map_err(|e| format!("cannot load {base}: {e}"))?;
    let system = client
        .wait()
        .at_most(Duration::from_secs(20))
        .for_element(Locator::Css("#system option[value='cvt_pendulum']"))
        .await
        .map_err(|e| format!("no cvt_pendulum in the system list: {e}"))?;
    drop(system);
    let select = |css: &'static str| async move {
        client.find(Locator::Css(css)).await.map_err(|e| format!("{css}: {e}"))
    };
    let err = |e: fantoccini::error::CmdError| e.to_string();
    select("#system").await?.select_by_value("cvt_pendulum").await.map_err(err)?;
    select("#preset").await?.select_by_value("rotating-perturbed").await.map_err(err)?;
    select("#add-method-id").await?.select_by_value("dla").await.map_err(err)?;
    select("#add-method").await?.click().await.map_err(err)?;
    let url = js(client, "return location.href;").await?;
    let url = url.as_str().unwrap_or_default().to_owned();
    for part in ["system=cvt_pendulum", "preset=rotating-perturbed", ",dd,dla:0.5"] {
        assert!(url.contains(part), "the URL follows the form ({part}): {url}");
    }
    assert!(!url.contains("run=1"), "editing the form does not make the link auto-run: {url}");
    client.goto(&url).await.map_err(|e| format!("cannot load {url}: {e}"))?;
    // The form is built once the catalog has arrived, after the page's load event.
    client
        .wait()
        .at_most(Duration::from_secs(20))
        .for_element(Locator::Css("#param-epsilon"))
        .await
        .map_err(|e| format!("the link did not restore the form: {e}"))?;
    let form = js(
        client,
        r#"return [document.getElementById('system').value, document.getElementById('preset').value,
                   document.getElementById('param-epsilon').value,
                   document.querySelectorAll('#methods .method-row').length,
                   document.getElementById('status').dataset.state];"#,
    )
    .await?;
    assert_eq!(form, json!(["cvt_pendulum", "rotating-perturbed", "0.5", 6, "idle"]), "{url}");
    console_clean(driver, client, "form in the URL").await
}

/// Fails on any console error since the last look.
pub(crate) async fn console_clean(
    driver: &Driver,
    client: &Client,
    scenario: &str,
) -> Result<(), String> {
    let log = driver.browser_log(client).await?;
    let errors: Vec<&Value> = log.iter().filter(|e| e["level"] == "SEVERE").collect();
    if errors.is_empty() {
        Ok(())
    } else {
        Err(format!("{scenario}: the browser console has errors: {errors:#?}"))
    }
}

/// A link restores the form, runs by itself, and a 4xx lands next to its field.
pub(crate) async fn bad_parameter_link(client: &Client, base: &str) -> Result<(), String> {
    let link = format!("{base}?system=knife_edge&preset=paper-perturbed&param.epsilon=2&run=1");
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    let (state, text) = wait_for_status(client).await?;
    assert_eq!(state, "error", "epsilon = 2 is outside (-1, 1); the page said {text:?}");
    let field = js(
        client,
        r#"const f = document.querySelector('[data-path="params.epsilon"]');
           return [document.getElementById('param-epsilon').value,
                   f.classList.contains('invalid'),
                   f.querySelector('.field-error')?.textContent ?? null];"#,
    )
    .await?;
    assert_eq!(field[0], json!("2"), "the link's epsilon fills the form: {field}");
    assert_eq!(field[1], json!(true), "the epsilon field is marked invalid: {field}");
    let message = field[2].as_str().unwrap_or_default();
    assert!(message.contains("epsilon"), "the server's message sits next to the field: {field}");
    screenshot(client, "bad-parameter.png").await;
    Ok(())
}

/// A composition picked beside a method: it travels in the URL, runs, and labels its curve.
pub(crate) async fn composition(
    client: &Client,
    driver: &Driver,
    base: &str,
) -> Result<(), String> {
    let link = format!(
        "{base}?system=knife_edge&preset=paper&methods=leapfrog,leapfrog@p4s3,rk4&integrals=energy"
    );
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    let pickers = "#methods .method-row select[data-composition]";
    client
        .wait()
        .at_most(Duration::from_secs(20))
        .for_element(Locator::Css(pickers))
        .await
        .map_err(|e| format!("no composition picker beside a method ({pickers}): {e}"))?;
    // The scenario before ended on a 422, which the console logged: read it away.
    driver.browser_log(client).await?;
    let chosen = js(
        client,
        "return [...document.querySelectorAll('#methods .method-row')].map((r) => \
         r.querySelector('select[data-composition]')?.value ?? null);",
    )
    .await?;
    assert_eq!(chosen, json!(["", "p4s3", null]), "the link's compositions, none for RK4");
    let first = client.find(Locator::Css(pickers)).await.map_err(|e| e.to_string())?;
    first.select_by_value("p6s9").await.map_err(|e| format!("cannot pick p6s9: {e}"))?;
    let url = js(client, "return location.search;").await?;
    let url = url.as_str().unwrap_or_default();
    assert!(url.contains("methods=leapfrog@p6s9,leapfrog@p4s3,rk4"), "the URL follows: {url}");
    let run = client.find(Locator::Id("run")).await.map_err(|e| e.to_string())?;
    run.click().await.map_err(|e| format!("cannot click Run: {e}"))?;
    let (state, text) = wait_for_status(client).await?;
    assert_eq!(state, "done", "the composed runs end; the page said {text:?}");
    let plot = js(client, PLOT_REPORT).await?;
    assert_eq!(plot["legend"], json!(["LF∘p6s9", "LF∘p4s3", "RK4"]), "{plot}");
    console_clean(driver, client, "composition").await
}
