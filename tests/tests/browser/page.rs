//! Reading the page: scripts run in it, its status lines, screenshots.

use crate::RUN_TIMEOUT;
use fantoccini::{Client, Locator};
use serde_json::Value;
use std::path::Path;
use std::time::{Duration, Instant};

/// Polls a view's status line until its computation is over; returns its state and text.
pub(crate) async fn wait_for_view(client: &Client, view: &str) -> Result<(String, String), String> {
    let start = Instant::now();
    let script = format!(
        "const s = document.querySelector('#{view} .view-status'); return s ? [s.dataset.state, s.textContent] : ['', ''];"
    );
    loop {
        let v = js(client, &script).await?;
        let state = v[0].as_str().unwrap_or_default().to_owned();
        if !matches!(state.as_str(), "idle" | "running" | "") {
            return Ok((state, v[1].as_str().unwrap_or_default().to_owned()));
        }
        if start.elapsed() > RUN_TIMEOUT {
            return Err(format!("#{view} did not finish within {RUN_TIMEOUT:?}: {v}"));
        }
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
}

/// What the energy chart drew: uPlot's series (after the x series), legend labels and run statuses.
pub(crate) const PLOT_REPORT: &str = r#"
const cards = [...document.querySelectorAll('.plot-card')];
const card = document.querySelector('.plot-card[data-integral="energy"]');
const u = card?.uplot;
return {
  integrals: cards.map((c) => c.dataset.integral),
  series: u ? u.series.slice(1).map((s, i) => ({
    label: s.label,
    show: s.show,
    drawn: !!(s._paths && s._paths.stroke),
    points: u.data[i + 1].filter((v) => v !== null && v !== undefined).length,
  })) : null,
  legend: card ? [...card.querySelectorAll('.u-legend .u-series .u-label')].slice(1).map((e) => e.textContent) : null,
  runs: [...document.querySelectorAll('#runs tr.run .badge')].map((b) => b.textContent),
};
"#;

/// Polls the status line until the run is over; returns its state and text.
pub(crate) async fn wait_for_status(client: &Client) -> Result<(String, String), String> {
    let start = Instant::now();
    loop {
        let v = js(client, "const s = document.getElementById('status'); return [s.dataset.state, s.textContent, document.getElementById('run-error').textContent];").await?;
        let state = v[0].as_str().unwrap_or_default().to_owned();
        if !matches!(state.as_str(), "idle" | "running" | "") {
            let text = format!(
                "{} {}",
                v[1].as_str().unwrap_or_default(),
                v[2].as_str().unwrap_or_default()
            );
            return Ok((state, text.trim().to_owned()));
        }
        if start.elapsed() > RUN_TIMEOUT {
            return Err(format!("the run did not finish within {RUN_TIMEOUT:?}; status {v}"));
        }
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
}

/// Runs `script` every 25 ms until it returns something other than null (`within` at most).
pub(crate) async fn poll(client: &Client, script: &str, within: Duration) -> Result<Value, String> {
    let start = Instant::now();
    loop {
        let v = js(client, script).await?;
        if !v.is_null() {
            return Ok(v);
        }
        if start.elapsed() > within {
            return Err(format!("nothing within {within:?} from {script}"));
        }
        tokio::time::sleep(Duration::from_millis(25)).await;
    }
}

/// Clicks the element `css` finds, scrolled to the middle of the window first (the form's
/// sticky Run bar covers its bottom).
pub(crate) async fn click(client: &Client, css: &str) -> Result<(), String> {
    let element = client.find(Locator::Css(css)).await.map_err(|e| format!("no {css}: {e}"))?;
    client
        .execute(
            "arguments[0].scrollIntoView({block: 'center'});",
            vec![serde_json::to_value(&element).map_err(|e| e.to_string())?],
        )
        .await
        .map_err(|e| format!("cannot scroll to {css}: {e}"))?;
    element.click().await.map_err(|e| format!("cannot click {css}: {e}"))
}

pub(crate) async fn js(client: &Client, script: &str) -> Result<Value, String> {
    client.execute(script, vec![]).await.map_err(|e| format!("script failed: {e}\n{script}"))
}

/// Saves a PNG under `<target>/screenshots/`; returns its path (or why it could not).
pub(crate) async fn screenshot(client: &Client, name: &str) -> String {
    let dir =
        Path::new(env!("CARGO_TARGET_TMPDIR")).parent().expect("target dir").join("screenshots");
    let path = dir.join(name);
    let png = match client.screenshot().await {
        Ok(png) => png,
        Err(e) => return format!("(no screenshot: {e})"),
    };
    match std::fs::create_dir_all(&dir).and_then(|()| std::fs::write(&path, png)) {
        Ok(()) => path.display().to_string(),
        Err(e) => format!("(cannot write {}: {e})", path.display()),
    }
}
