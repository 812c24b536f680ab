//! Window widths, verdicts on Explore and stable method colours: at 400, 800 and 1400 px a
//! one-click experiment brings its status line and first plot into view, and no view scrolls
//! sideways (360 px too); each run's verdict is beside it in the runs table and in every
//! legend; a method keeps its colour and marker when the run's method list changes.

use crate::driver::Driver;
use crate::explore::console_clean;
use crate::page::{js, poll, screenshot, wait_for_status, wait_for_view};
use fantoccini::{Client, Locator};
use serde_json::{Value, json};
use std::collections::BTreeMap;
use std::time::{Duration, Instant};

/// The experiment clicked at each width: the rotating, perturbed pendulum CVT.
const EXPERIMENT: &str =
    r#"#experiments button[data-system="cvt_pendulum"][data-preset="rotating-perturbed"]"#;

/// Where the results are after Run, and whether the page scrolls sideways.
const IN_VIEW: &str = r#"
const status = document.getElementById('status').getBoundingClientRect();
const plot = document.querySelector('#plots .plot-card')?.getBoundingClientRect();
return { scrollY, innerHeight, innerWidth, scrollWidth: document.documentElement.scrollWidth,
  status: status.top, plot: plot ? plot.top : null,
  header: document.querySelector('header.top').getBoundingClientRect().height };
"#;

/// Per chart: each legend entry's label, swatch colour and marker, uPlot's stroke and the
/// verdict badge; per runs-table row: the label and its verdict chips.
const LOOKS: &str = r#"
return {
  charts: [...document.querySelectorAll('#plots .plot-card')].map((card) => {
    const u = card.uplot;
    const rows = [...card.querySelectorAll('.u-legend .u-series')].slice(1);
    return rows.map((row, i) => ({
      label: row.querySelector('.u-label')?.textContent ?? '',
      colour: row.querySelector('svg.method-swatch')?.dataset.colour ?? null,
      marker: row.querySelector('svg.method-swatch')?.dataset.marker ?? null,
      stroke: u.series[i + 1]._stroke ?? null,
      badge: row.querySelector('.legend-verdict')?.textContent ?? null,
      kind: row.querySelector('.legend-verdict')?.dataset.kind ?? null,
      title: row.querySelector('.legend-verdict')?.title ?? '',
    }));
  }),
  runs: [...document.querySelectorAll('#runs tr.run')].map((tr) => ({
    label: tr.querySelector('th')?.textContent ?? '',
    colour: tr.querySelector('svg.method-swatch')?.dataset.colour ?? null,
    chips: [...tr.querySelectorAll('.verdict-chip')].map((c) => c.dataset.kind),
  })),
};
"#;

pub(crate) async fn window_widths(
    client: &Client,
    driver: &Driver,
    base: &str,
) -> Result<(), String> {
    driver.browser_log(client).await?;
    let start = Instant::now();
    let mut looks = Value::Null;
    for (width, height) in [(400, 800), (800, 900), (1400, 900)] {
        looks = results_in_view(client, base, width, height).await?;
    }
    verdicts_beside_runs(&looks)?;
    views_fit(client, &[360, 400, 800, 1400]).await?;
    stable_colours(client, base, &looks).await?;
    client.set_window_size(1440, 1500).await.map_err(|e| e.to_string())?;
    println!("window widths: checked in {:.1} s", start.elapsed().as_secs_f64());
    console_clean(driver, client, "window widths").await
}

/// One click at `width`: the results end up on screen (scrolled there when they were below
/// the fold, not moved when they were visible), and the page is no wider than the window.
async fn results_in_view(
    client: &Client,
    base: &str,
    width: u32,
    height: u32,
) -> Result<Value, String> {
    client.set_window_size(width, height).await.map_err(|e| format!("{width} px: {e}"))?;
    client.goto(base).await.map_err(|e| format!("cannot load {base}: {e}"))?;
    let button = client
        .wait()
        .at_most(Duration::from_secs(20))
        .for_element(Locator::Css(EXPERIMENT))
        .await
        .map_err(|e| format!("no rotating, perturbed experiment button: {e}"))?;
    let before = js(client, IN_VIEW).await?;
    button.click().await.map_err(|e| format!("cannot click the experiment: {e}"))?;
    let (state, text) = wait_for_status(client).await?;
    let after = settled(client).await?;
    let shot = screenshot(client, &format!("width-{width}.png")).await;
    assert_eq!(state, "done", "{width} px: the run ended with {text:?} ({shot})");
    let num = |v: &Value, k: &str| v[k].as_f64().unwrap_or(f64::NAN);
    let inner = num(&after, "innerHeight");
    assert!(
        (0.0..inner - 40.0).contains(&num(&after, "status")),
        "{width} px: the status line is not on screen after Run: {after} ({shot})"
    );
    assert!(
        num(&after, "plot") < inner - 40.0,
        "{width} px: the first plot is below the fold after Run: {after} ({shot})"
    );
    assert!(
        num(&after, "scrollWidth") <= num(&after, "innerWidth"),
        "{width} px: the page scrolls sideways: {after} ({shot})"
    );
    let below = num(&before, "status") > num(&before, "innerHeight") - 100.0;
    assert_eq!(
        num(&after, "scrollY") > 0.0,
        below,
        "{width} px: scroll only when the results were off screen: before {before}, after {after}"
    );
    assert!(
        num(&after, "header") < 130.0 || width < 700,
        "{width} px: the header takes {} px ({shot})",
        num(&after, "header")
    );
    println!(
        "{width} px: status at {} → {}, first plot at {}, scrolled to {}, header {} px",
        num(&before, "status"),
        num(&after, "status"),
        num(&after, "plot"),
        num(&after, "scrollY"),
        num(&after, "header")
    );
    js(client, LOOKS).await
}

/// Waits until the page stops scrolling (a smooth scroll takes a moment); returns `IN_VIEW`.
async fn settled(client: &Client) -> Result<Value, String> {
    let start = Instant::now();
    let mut last = js(client, IN_VIEW).await?;
    loop {
        tokio::time::sleep(Duration::from_millis(250)).await;
        let now = js(client, IN_VIEW).await?;
        if now["scrollY"] == last["scrollY"] || start.elapsed() > Duration::from_secs(5) {
            return Ok(now);
        }
        last = now;
    }
}

/// After the run: every legend entry and runs-table row carries a verdict, with its numbers
/// on hover, and the legend's agrees with the table's.
fn verdicts_beside_runs(looks: &Value) -> Result<(), String> {
    let charts = looks["charts"].as_array().ok_or_else(|| format!("no charts: {looks}"))?;
    let runs = looks["runs"].as_array().ok_or_else(|| format!("no runs table: {looks}"))?;
    assert_eq!(runs.len(), 5, "the paper's five methods: {looks}");
    assert!(!charts.is_empty(), "{looks}");
    let kinds = ["exact", "bounded", "drift"];
    for (c, chart) in charts.iter().enumerate() {
        let entries = chart.as_array().ok_or("no legend")?;
        assert_eq!(entries.len(), runs.len(), "a legend entry per run: {chart}");
        for (r, e) in entries.iter().enumerate() {
            let kind = e["kind"].as_str().unwrap_or_default();
            assert!(kinds.contains(&kind), "legend verdict badge missing: {e}");
            assert_eq!(e["badge"], json!(kind), "the badge says its verdict in words: {e}");
            assert!(
                e["title"].as_str().unwrap_or_default().contains("max"),
                "numbers on hover: {e}"
            );
            assert_eq!(
                runs[r]["chips"][c],
                json!(kind),
                "legend and runs table agree: {e} {looks}"
            );
        }
    }
    Ok(())
}

/// Every view at every width: the document is no wider than the window.
async fn views_fit(client: &Client, widths: &[u32]) -> Result<(), String> {
    for view in ["scorecard", "paper", "work-precision", "map", "main"] {
        let tab = format!(r#".tabs .tab[data-view="{view}"]"#);
        client
            .find(Locator::Css(&tab))
            .await
            .map_err(|e| e.to_string())?
            .click()
            .await
            .map_err(|e| e.to_string())?;
        if view != "map" && view != "main" {
            let (state, text) = wait_for_view(client, &format!("view-{view}")).await?;
            assert_eq!(state, "done", "{view}: {text}");
        }
        for &width in widths {
            let before = js(client, "return innerWidth;").await?;
            client.set_window_size(width, 800).await.map_err(|e| e.to_string())?;
            // Once the window has its new width (unless it had it already), two frames for
            // the layout and the plots' resize. A width the browser will not take is measured
            // as it is: the check below still holds there.
            let resized = format!(
                "return innerWidth !== {before} || outerWidth === {width} ? new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(() => r(innerWidth)))) : null;"
            );
            let _ = poll(client, &resized, Duration::from_secs(3)).await;
            let v = js(client, OVERFLOW).await?;
            if v["scrollWidth"].as_f64() > v["innerWidth"].as_f64() {
                let shot = screenshot(client, &format!("overflow-{view}-{width}.png")).await;
                return Err(format!("{view} at {width} px scrolls sideways: {v} ({shot})"));
            }
        }
        println!("{view}: no sideways scrolling at {widths:?} px");
    }
    Ok(())
}

/// The document's width against the window's, and the widest elements when it is wider.
pub(crate) const OVERFLOW: &str = r#"
const wide = [...document.querySelectorAll('body *')]
  .filter((e) => e.offsetParent && e.getBoundingClientRect().right > innerWidth + 1)
  .slice(0, 5).map((e) => `${e.tagName}.${e.className}`);
return { scrollWidth: document.documentElement.scrollWidth, innerWidth, wide };
"#;

/// A second run with another method list: each method shared with the first keeps its
/// colour and marker though its place in the list changed; a composed method keeps its
/// base's colour with a dash; distinct methods look distinct.
async fn stable_colours(client: &Client, base: &str, first: &Value) -> Result<(), String> {
    let link = format!(
        "{base}?system=knife_edge&preset=paper&t_end=20&integrals=energy\
         &methods=dd_avf,leapfrog@p4s3,dd,leapfrog&run=1"
    );
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    let (state, text) = wait_for_status(client).await?;
    assert_eq!(state, "done", "the second run ended with {text:?}");
    let second = js(client, LOOKS).await?;
    let by_label = |looks: &Value| -> BTreeMap<String, (Value, Value, Value)> {
        looks["charts"][0]
            .as_array()
            .map(|entries| {
                entries
                    .iter()
                    .map(|e| {
                        let label = e["label"].as_str().unwrap_or_default().to_owned();
                        (label, (e["colour"].clone(), e["marker"].clone(), e["stroke"].clone()))
                    })
                    .collect()
            })
            .unwrap_or_default()
    };
    let (a, b) = (by_label(first), by_label(&second));
    let look = |m: &BTreeMap<String, (Value, Value, Value)>, label: &str| {
        m.get(label).cloned().ok_or_else(|| format!("no legend entry {label}: {first} / {second}"))
    };
    for label in ["LF", "DD"] {
        let (x, y) = (look(&a, label)?, look(&b, label)?);
        assert_eq!(x, y, "{label} changed its look between runs: {first} / {second}");
        assert_eq!(x.0, x.2, "{label}: the legend swatch is the curve's colour: {first}");
    }
    let (lf, composed) = (look(&b, "LF")?, look(&b, "LF∘p4s3")?);
    assert_eq!(composed.0, lf.0, "a composition keeps its base colour: {second}");
    let dashed = js(
        client,
        "const u = document.querySelector('#plots .plot-card').uplot; return u.series.slice(1).map((s) => s.dash ?? null);",
    )
    .await?;
    assert!(dashed[1].is_array() && dashed[3].is_null(), "the composition is dashed: {dashed}");
    let looks: Vec<_> = a.values().map(|(c, m, _)| (c.to_string(), m.to_string())).collect();
    let distinct: std::collections::BTreeSet<_> = looks.iter().collect();
    assert_eq!(distinct.len(), looks.len(), "five methods, five looks: {first}");
    let table = second["runs"].as_array().ok_or("no runs table")?;
    for row in table {
        let label = row["label"].as_str().unwrap_or_default();
        let legend = look(&b, label)?.0;
        assert_eq!(row["colour"], legend, "the runs table's swatch matches the legend: {row}");
    }
    println!("stable colours: LF {} and DD {} in both runs", lf.0, look(&b, "DD")?.0);
    Ok(())
}
