//! The Trajectory and Section panels: after the rotating, perturbed CVT, a phase portrait
//! (x2 against x1) and a Poincaré section drawn with one series per method, a legend in the
//! methods' colours and markers (the same as the error plot's), and the section's PNG and SVG
//! export.

use crate::driver::Driver;
use crate::explore::console_clean;
use crate::export::{CATCH_DOWNLOADS, DOWNLOADS, save};
use crate::page::{click, js, poll, screenshot, wait_for_status};
use fantoccini::Client;
use serde_json::json;
use std::time::Duration;

pub(crate) async fn dynamics_panels(
    client: &Client,
    driver: &Driver,
    base: &str,
) -> Result<(), String> {
    driver.browser_log(client).await?;
    let link = format!(
        "{base}?system=cvt_pendulum&preset=rotating-perturbed&t_end=300&integrals=energy&run=1"
    );
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    let (state, text) = wait_for_status(client).await?;
    assert_eq!(state, "done", "{text}");
    // The section is computed only when asked for (it checks every step): ticked, and run
    // again; the section's first crossings say the new run is in.
    let asked = js(client, "return document.querySelector('.dyn-card[data-panel=\"section\"]').xy.drawn.reduce((n, s) => n + s.points, 0);").await?;
    assert_eq!(asked, json!(0), "no section before it is ticked");
    click(client, ".section-on").await?;
    click(client, "#run").await?;
    let drawn = "const d = document.querySelector('.dyn-card[data-panel=\"section\"]').xy.drawn; \
                 return d.length === 5 && d.every((s) => s.points >= 10) && \
                 document.getElementById('status').dataset.state === 'done' ? true : null;";
    poll(client, drawn, Duration::from_secs(60)).await?;
    js(client, "document.getElementById('dynamics').scrollIntoView();").await?;
    let shot = screenshot(client, "dynamics.png").await;
    let report = js(client, REPORT).await?;
    let expected = &report["plot"];
    for panel in ["trajectory", "section"] {
        let card = &report["cards"][panel];
        assert_eq!(
            card["axes"],
            json!(["x1", "x2"]),
            "{panel}: the passenger plane: {card} ({shot})"
        );
        let drawn = card["drawn"].as_array().ok_or_else(|| format!("no {panel} card: {report}"))?;
        assert_eq!(drawn.len(), 5, "{panel}: one series per method: {card}");
        let least = if panel == "trajectory" { 100 } else { 10 };
        for s in drawn {
            let points = s["points"].as_u64().unwrap_or(0);
            assert!(points >= least, "{panel}: {points} points for {s} ({shot})");
        }
        assert_eq!(&card["legend"], expected, "{panel}: the error plot's colours and markers");
        assert_eq!(card["labels"], report["runs"], "{panel}: the legend names the runs");
    }

    js(client, CATCH_DOWNLOADS).await?;
    click(client, r#".dyn-card[data-panel="section"] .export-png"#).await?;
    click(client, r#".dyn-card[data-panel="section"] .export-svg"#).await?;
    let downloads = poll(client, DOWNLOADS, Duration::from_secs(20)).await?;
    let stem = "nhlab-cvt_pendulum-rotating-perturbed-section-x1-x2";
    assert_eq!(downloads[0]["name"], format!("{stem}.png"), "{downloads}");
    assert_eq!(downloads[0]["head"], json!([137, 80, 78, 71]), "a PNG file: {downloads}");
    assert_eq!(downloads[1]["name"], format!("{stem}.svg"), "{downloads}");
    assert!(downloads[1]["paths"].as_u64().unwrap_or(0) >= 5, "a path per method: {downloads}");
    let files = js(client, "return window.__downloads.map((d) => [d.name, d.bytes]);").await?;
    for file in files.as_array().into_iter().flatten() {
        save(file[0].as_str().unwrap_or("export"), &file[1]);
    }
    console_clean(driver, client, "dynamics panels").await?;
    println!("dynamics: phase portrait and section drawn, legend, export; screenshot {shot}");
    Ok(())
}

/// Per panel: its axes, what it drew, its legend's [colour, marker] and labels; the runs
/// table's labels and the energy plot's legend's [colour, marker].
const REPORT: &str = r#"
const looks = (root, row) => [...root.querySelectorAll(row)].map((r) => {
  const s = r.querySelector('svg.method-swatch');
  return [s?.dataset.colour ?? null, s?.dataset.marker ?? null];
});
const cards = {};
for (const c of document.querySelectorAll('.dyn-card')) {
  cards[c.dataset.panel] = { axes: [c.dataset.x, c.dataset.y], drawn: c.xy.drawn, legend: looks(c, '.dyn-legend .legend-item'), labels: [...c.querySelectorAll('.legend-label')].map((l) => l.textContent) };
}
const energy = document.querySelector('.plot-card[data-integral="energy"]');
const runs = [...document.querySelectorAll('#runs tr.run th')].map((th) => th.textContent);
return { cards, runs, plot: looks(energy, '.u-legend .u-series').slice(-5) };
"#;
