//! The page's second pass, at 400 and 1400 px: a field the server refuses gets the focus and
//! the eye (in view, `aria-invalid`, described by its message) while the earlier results
//! are marked stale (dimmed, a line, downloads off) until a run starts; a skip link lands on
//! Run; after a run the focus is on the results, not lost; the Scorecard's verdicts are one
//! Tab stop with arrow keys inside, its method column stays while the scenes scroll, and a
//! line says more scenes follow where they do. A method offers compositions only where it is
//! symmetric as configured (DLA^α at α = 0.5), with the order it reaches. While two runs go at
//! different paces, the status's time left is the slowest run's, as the runs table gives it.

use crate::driver::Driver;
use crate::explore::console_clean;
use crate::page::{click, js, poll, screenshot, wait_for_status, wait_for_view};
use fantoccini::Client;
use fantoccini::key::Key;
use serde_json::Value;
use std::time::Duration;

/// The invalid field, the focus and the stale results after a refused request.
const AFTER_ERROR: &str = r#"
const active = document.activeElement;
const box = active.getBoundingClientRect();
const described = active.getAttribute('aria-describedby');
return {
  active: active.closest('[data-path]')?.dataset.path ?? active.id ?? active.tagName,
  invalid: active.getAttribute('aria-invalid'),
  message: described ? document.getElementById(described)?.textContent ?? null : null,
  inView: box.top >= 0 && box.bottom <= innerHeight,
  stale: document.querySelector('main.results').classList.contains('stale'),
  note: !document.getElementById('stale-note').hidden,
  downloads: document.getElementById('download-json').disabled && document.getElementById('download-csv').disabled,
};
"#;

/// The scorecard's verdict table: Tab stops, the method column after scrolling, the cue.
const SCORECARD_KEYS: &str = r#"
const table = document.querySelector('table.scorecard-verdicts');
const box = table.closest('.scorecard-scroll');
box.scrollLeft = box.scrollWidth;
const method = table.querySelector('tbody th.method').getBoundingClientRect();
return {
  stops: [...table.querySelectorAll('[tabindex]')].filter((c) => c.tabIndex === 0).length,
  cells: table.querySelectorAll('td.verdict-cell[tabindex]').length,
  methodLeft: method.left - box.getBoundingClientRect().left,
  overflow: box.scrollWidth > box.clientWidth,
  hint: !document.querySelector('#view-scorecard .scroll-hint').hidden,
};
"#;

pub(crate) async fn second_pass(
    client: &Client,
    driver: &Driver,
    base: &str,
) -> Result<(), String> {
    driver.browser_log(client).await?;
    for (width, height) in [(400, 800), (1400, 900)] {
        client.set_window_size(width, height).await.map_err(|e| format!("{width} px: {e}"))?;
        refused_field(client, base, width).await?;
        keyboard(client, base, width).await?;
        scorecard(client, base, width).await?;
        time_left(client, base, width).await?;
    }
    client.set_window_size(1440, 1500).await.map_err(|e| e.to_string())?;
    // The refused requests' 422s are in the log by design.
    driver.browser_log(client).await?;
    console_clean(driver, client, "second pass").await
}

/// A run, then a t_end the server refuses (too many steps): the field has the focus, in view
/// and marked; the earlier results are stale until the next run starts.
async fn refused_field(client: &Client, base: &str, width: u32) -> Result<(), String> {
    let link = format!("{base}?system=knife_edge&preset=paper&t_end=20&run=1");
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    let (state, text) = wait_for_status(client).await?;
    assert_eq!(state, "done", "{width} px: {text}");
    js(client, "const t = document.querySelector('[data-path=\"t_end\"] input') ?? document.getElementById('t_end'); t.value = '1e12'; t.dispatchEvent(new Event('input', {bubbles: true}));").await?;
    click(client, "#run").await?;
    let (state, _) = wait_for_status(client).await?;
    let shot = screenshot(client, &format!("refused-{width}.png")).await;
    assert_eq!(state, "error", "{width} px: the server refuses t_end ({shot})");
    let after = poll(
        client,
        &format!("const r = (() => {{{AFTER_ERROR}}})(); return r.inView ? r : null;"),
        Duration::from_secs(5),
    )
    .await
    .map_err(|e| format!("{width} px: the refused field is not in view ({shot}): {e}"))?;
    assert_eq!(after["active"], "t_end", "{width} px: the focus is on the refused field: {after}");
    assert_eq!(after["invalid"], "true", "{width} px: {after}");
    assert!(after["message"].as_str().is_some_and(|m| m.contains("steps")), "{width} px: {after}");
    assert_eq!(after["stale"], true, "{width} px: the earlier results are dimmed: {after}");
    assert_eq!(after["note"], true, "{width} px: a line says they are stale: {after}");
    assert_eq!(after["downloads"], true, "{width} px: their downloads are off: {after}");
    // A run that starts clears it.
    js(client, "const t = document.querySelector('[data-path=\"t_end\"] input') ?? document.getElementById('t_end'); t.value = '20'; t.dispatchEvent(new Event('input', {bubbles: true}));").await?;
    click(client, "#run").await?;
    let (state, text) = wait_for_status(client).await?;
    assert_eq!(state, "done", "{width} px: {text}");
    let fresh = js(client, AFTER_ERROR).await?;
    assert_eq!((&fresh["stale"], &fresh["note"]), (&Value::Bool(false), &Value::Bool(false)));
    println!("{width} px: a refused t_end has the focus, in view; the old results stale, then not");
    Ok(())
}

/// Both runs' times left, as the runs table and the status line give them in one frame.
const TIME_LEFT: &str = r#"
const ms = (t) => [...t.matchAll(/(\d+) (ms|s|min|h)\b/g)].reduce((sum, [, n, unit]) => sum + Number(n) * { ms: 1, s: 1e3, min: 6e4, h: 3.6e6 }[unit], 0);
const status = document.getElementById('status').textContent;
const overall = /about (.+?) left/.exec(status);
const cells = [...document.querySelectorAll('#runs tr.run')].map((tr) => tr.querySelectorAll('td.num')[1]?.textContent ?? '');
const runs = cells.map((c) => /~(.+?) left/.exec(c)).filter(Boolean);
if (!overall || runs.length < 2) return null;
return { status, cells, overall: ms(overall[1]), runs: runs.map((r) => ms(r[1])) };
"#;

/// Two runs at different paces: the status's estimate is the slower run's, not an average.
async fn time_left(client: &Client, base: &str, width: u32) -> Result<(), String> {
    let link = format!(
        "{base}?system=knife_edge&preset=paper&t_end=10000000&methods=dla01,dd&integrals=energy&run=1"
    );
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    let seen = poll(client, TIME_LEFT, Duration::from_secs(30)).await.map_err(|e| {
        format!("{width} px: no estimate of the time left for two running runs: {e}")
    })?;
    let runs: Vec<f64> =
        seen["runs"].as_array().into_iter().flatten().filter_map(Value::as_f64).collect();
    let slowest = runs.iter().copied().fold(0.0, f64::max);
    assert_eq!(
        seen["overall"].as_f64(),
        Some(slowest),
        "the status gives the slowest run's: {seen}"
    );
    click(client, "#cancel").await?;
    let (state, text) = wait_for_status(client).await?;
    assert_eq!(state, "cancelled", "{width} px: {text}");
    println!(
        "{width} px: the status's time left, {} ms, is the slowest of {runs:?}",
        seen["overall"]
    );
    Ok(())
}

/// The skip link is the first Tab stop and lands on Run; after a run the focus is on the
/// results heading.
async fn keyboard(client: &Client, base: &str, width: u32) -> Result<(), String> {
    let link = format!("{base}?system=knife_edge&preset=paper&t_end=20");
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    let ready = "return document.querySelectorAll('#system option').length > 0 ? true : null;";
    poll(client, ready, Duration::from_secs(20)).await?;
    offers_compositions_as_configured(client, width).await?;
    let body = client.find(fantoccini::Locator::Css("body")).await.map_err(|e| e.to_string())?;
    body.send_keys(&String::from(char::from(Key::Tab))).await.map_err(|e| e.to_string())?;
    let first = js(client, "return document.activeElement.className;").await?;
    assert_eq!(first, "skip-link", "{width} px: the first Tab stop is the skip link");
    let active = client.active_element().await.map_err(|e| e.to_string())?;
    active.send_keys(&String::from(char::from(Key::Enter))).await.map_err(|e| e.to_string())?;
    let focused = js(client, "return document.activeElement.id;").await?;
    assert_eq!(focused, "run", "{width} px: the skip link lands on Run");
    let run = client.active_element().await.map_err(|e| e.to_string())?;
    run.send_keys(&String::from(char::from(Key::Enter))).await.map_err(|e| e.to_string())?;
    let (state, text) = wait_for_status(client).await?;
    assert_eq!(state, "done", "{width} px: {text}");
    let focused = poll(
        client,
        "return document.activeElement.id === 'results-title' ? true : null;",
        Duration::from_secs(5),
    )
    .await
    .map_err(|e| format!("{width} px: after a run the focus is not on the results: {e}"))?;
    assert_eq!(focused, true);
    println!("{width} px: skip link to Run; after the run, focus on the results");
    Ok(())
}

/// The paper's five: DLA^0.5 offers compositions (its own order 2 first), DLA^0.4 none; set
/// to α = 0.4, DLA^0.5's offer goes and its order reads 1.
async fn offers_compositions_as_configured(client: &Client, width: u32) -> Result<(), String> {
    let offers = r#"
const rows = [...document.querySelectorAll('#methods .method-row')];
const offer = (row) => {
  const picker = row.querySelector('.method-composition');
  return picker && !picker.hidden ? picker.querySelector('select').options[0].textContent : null;
};
const before = rows.map(offer);
const alpha = rows[0].querySelector('input[data-param="alpha"]');
alpha.value = '0.4';
alpha.dispatchEvent(new Event('input', {bubbles: true}));
const after = offer(rows[0]);
const title = rows[0].querySelector('.method-name').title;
alpha.value = '0.5';
alpha.dispatchEvent(new Event('input', {bubbles: true}));
return { before, after, title, again: offer(rows[0]) };
"#;
    let report = js(client, offers).await?;
    assert_eq!(report["before"][0], "order 2", "{width} px: DLA^0.5 offers compositions: {report}");
    assert_eq!(report["before"][1], Value::Null, "{width} px: DLA^0.4 offers none: {report}");
    assert_eq!(report["after"], Value::Null, "{width} px: none at α = 0.4: {report}");
    assert!(report["title"].as_str().unwrap_or("").contains("order 1"), "{report}");
    assert_eq!(report["again"], "order 2", "{width} px: {report}");
    Ok(())
}

/// The scorecard's verdicts: one Tab stop, arrows inside; the method column stays; the cue.
async fn scorecard(client: &Client, base: &str, width: u32) -> Result<(), String> {
    let link = format!("{base}?view=scorecard");
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    let (state, text) = wait_for_view(client, "view-scorecard").await?;
    assert_eq!(state, "done", "{width} px: {text}");
    let report = js(client, SCORECARD_KEYS).await?;
    let shot = screenshot(client, &format!("scorecard-{width}.png")).await;
    assert_eq!(report["stops"], 1, "{width} px: one Tab stop for the verdicts: {report}");
    assert!(report["cells"].as_u64().unwrap_or(0) > 100, "{report}");
    let left = report["methodLeft"].as_f64().unwrap_or(f64::NAN);
    assert!(
        left.abs() < 2.0,
        "{width} px: the method column stays in view when scrolled: {report} ({shot})"
    );
    assert_eq!(
        report["hint"], report["overflow"],
        "{width} px: the cue where the scenes overflow: {report}"
    );
    if width <= 400 {
        assert_eq!(report["overflow"], true, "{width} px: {report}");
    }
    // Arrow keys move along the row and down the column; Enter opens the scene.
    let moved = js(
        client,
        r#"
const first = document.querySelector('table.scorecard-verdicts td.verdict-cell[tabindex="0"]');
first.focus();
const key = (k) => document.activeElement.dispatchEvent(new KeyboardEvent('keydown', {key: k, bubbles: true}));
key('ArrowRight');
const right = document.activeElement;
key('ArrowDown');
const down = document.activeElement;
return {
  right: right !== first && right.matches('td.verdict-cell'),
  down: down.parentElement !== right.parentElement && down.matches('td.verdict-cell'),
  stops: [...document.querySelectorAll('table.scorecard-verdicts [tabindex="0"]')].length,
};
"#,
    )
    .await?;
    assert_eq!(moved["right"], true, "{width} px: {moved}");
    assert_eq!(moved["down"], true, "{width} px: {moved}");
    assert_eq!(moved["stops"], 1, "{width} px: still one Tab stop: {moved}");
    println!("{width} px: scorecard verdicts one Tab stop, arrows inside, method column sticky");
    Ok(())
}
