//! The Work–precision view's settings and requests: the scene named on every plot card, the
//! DiffEqDevTools orientation from the URL, a 0 in "Step sizes" reported at that field with
//! the previous plots marked stale, a list of steps (a 0 in it refused at its field), and
//! Cancel stopping a long request.

use crate::driver::Driver;
use crate::explore::console_clean;
use crate::page::{self, js, poll, screenshot, wait_for_view};
use fantoccini::{Client, Locator};
use serde_json::json;
use std::time::Duration;

pub(crate) async fn work_precision_controls(
    client: &Client,
    driver: &Driver,
    base: &str,
) -> Result<(), String> {
    driver.browser_log(client).await?;
    let link = format!(
        "{base}?view=work-precision&system=knife_edge&preset=paper&t_end=10\
         &methods=leapfrog,dd&levels=2&repeats=1&orient=error-x"
    );
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    let (state, text) = wait_for_view(client, "view-work-precision").await?;
    assert_eq!(state, "done", "the work-precision view finished with {text:?}");
    let report = js(client, REPORT).await?;
    for scene in report["scenes"].as_array().ok_or("no plot cards")? {
        let scene = scene.as_str().unwrap_or_default();
        for part in ["Knife edge", "ε = 0", "t_end = 10"] {
            assert!(scene.contains(part), "the card names its scene ({part}): {report}");
        }
    }
    assert_eq!(report["orients"], json!(["error-x", "h"]), "{report}");
    assert!(
        report["xLabel"].as_str().unwrap_or("").starts_with("final error"),
        "error on x, as DiffEqDevTools draws it: {report}"
    );
    assert!(
        report["alt"].as_str().unwrap_or("").contains("order"),
        "the h plot's canvas has a text alternative with the orders: {report}"
    );

    // 0 step sizes: an error at that field, named by its label; nothing is sent.
    set_value(client, ".wp-levels", "0").await?;
    click(client, ".wp-run").await?;
    let report = js(client, REPORT).await?;
    assert_eq!(report["state"], "error", "{report}");
    let error = report["fieldError"].as_str().unwrap_or_default();
    assert!(
        error.starts_with("Step sizes") && error.contains("0 would measure nothing"),
        "the error is at the Step sizes field, in its words: {report}"
    );
    assert!(report["status"].as_str().unwrap_or("").contains("Step sizes"), "{report}");
    assert_eq!(report["stale"], json!(true), "the previous plots are marked stale: {report}");
    let shot = screenshot(client, "work-precision-zero-steps.png").await;

    // A list of steps replaces the number of step sizes; a 0 in it is refused at its field.
    set_value(client, ".wp-steps", "0.2, 0").await?;
    click(client, ".wp-run").await?;
    let report = js(client, REPORT).await?;
    let error = report["fieldError"].as_str().unwrap_or_default();
    assert!(error.starts_with("Steps h") && error.contains("positive"), "{report}");
    set_value(client, ".wp-steps", "0.2, 0.1").await?;
    click(client, ".wp-run").await?;
    let (state, text) = wait_for_view(client, "view-work-precision").await?;
    assert_eq!(state, "done", "the listed steps ran: {text:?}");
    let heads = js(client, "return [...document.querySelectorAll('#view-work-precision table.wp-orders thead th')].slice(2).map((t) => t.textContent);").await?;
    assert_eq!(heads, json!(["h = 0.2", "h = 0.1"]), "one column per listed step");

    // A long request (5 methods, 9 step sizes to t = 1000, twice): Cancel stops it.
    let link = format!(
        "{base}?view=work-precision&system=knife_edge&preset=paper&t_end=1000&levels=9&repeats=2"
    );
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    client
        .wait()
        .at_most(Duration::from_secs(20))
        .for_element(Locator::Css("#view-work-precision .wp-cancel:not([disabled])"))
        .await
        .map_err(|e| format!("no enabled Cancel while the request runs: {e}"))?;
    let running = js(client, REPORT).await?;
    assert_eq!(running["state"], "running", "{running}");
    assert_eq!(running["progress"], json!(true), "a progress bar while it runs: {running}");
    // The elapsed time counts up while it runs: the status changes, still running.
    let first = running["status"].as_str().unwrap_or_default().to_owned();
    assert!(first.contains("elapsed"), "progress: {running}");
    let later = poll(
        client,
        &format!(
            "const s = document.querySelector('#view-work-precision .view-status'); \
             return s.dataset.state === 'running' && s.textContent !== {first:?} ? s.textContent : null;"
        ),
        Duration::from_secs(5),
    )
    .await
    .map_err(|e| format!("the elapsed time does not count up while it runs: {e}"))?;
    assert!(later.as_str().unwrap_or_default().contains("elapsed"), "progress: {later}");
    click(client, ".wp-cancel").await?;
    let (state, text) = wait_for_view(client, "view-work-precision").await?;
    assert_eq!(state, "cancelled", "Cancel stops the request: {text:?}");
    let report = js(client, REPORT).await?;
    assert_eq!(report["cancelDisabled"], json!(true), "{report}");
    assert_eq!(report["progress"], json!(false), "{report}");
    console_clean(driver, client, "work-precision controls").await?;
    println!("work-precision controls: scene named, 0 step sizes refused, Cancel; {shot}");
    Ok(())
}

async fn click(client: &Client, css: &str) -> Result<(), String> {
    page::click(client, &format!("#view-work-precision {css}")).await
}

async fn set_value(client: &Client, css: &str, value: &str) -> Result<(), String> {
    let css = format!("#view-work-precision {css}");
    let input = client.find(Locator::Css(&css)).await.map_err(|e| format!("no {css}: {e}"))?;
    input.clear().await.map_err(|e| format!("cannot clear {css}: {e}"))?;
    input.send_keys(value).await.map_err(|e| format!("cannot type in {css}: {e}"))
}

/// The view's cards (scene captions, orientations, the time plot's x label, the h plot's
/// text alternative), status, field error, stale mark and controls.
const REPORT: &str = r#"
const root = document.getElementById('view-work-precision');
const cards = [...root.querySelectorAll('.wp-card')];
const status = root.querySelector('.view-status');
return {
  scenes: cards.map((c) => c.querySelector('.wp-scene')?.textContent ?? ''),
  orients: cards.map((c) => c.dataset.orient),
  xLabel: cards[0]?.uplot?.axes[0].label ?? '',
  alt: cards[1]?.querySelector('canvas')?.getAttribute('aria-label') ?? '',
  state: status.dataset.state,
  status: status.textContent,
  fieldError: root.querySelector('.wp-field.invalid .field-error')?.textContent ?? '',
  stale: root.querySelector('.wp-plots').classList.contains('stale') && !root.querySelector('.wp-stale').hidden,
  progress: !root.querySelector('.wp-progress-line').hidden,
  cancelDisabled: root.querySelector('.wp-cancel').disabled,
};
"#;
