//! The Map view: a preset's sweep fills the heat map, a hovered cell names itself and its
//! numbers, a clicked cell opens its run in Explore; a one-axis link draws the line plot, on
//! the knife edge and on the Chaplygin sleigh (outside the paper's class); an axis the server
//! rejects is marked at its field.

use crate::driver::Driver;
use crate::explore::console_clean;
use crate::export::{CATCH_DOWNLOADS, DOWNLOADS, save};
use crate::page::{PLOT_REPORT, js, poll, screenshot, wait_for_status, wait_for_view};
use fantoccini::actions::{InputSource, MOUSE_BUTTON_LEFT, MouseActions, PointerAction};
use fantoccini::{Client, Locator};
use nhlab_server::sweep::csv;
use serde_json::{Value, json};
use std::time::Duration;

/// The "where DLA^α stops being reversible enough" preset: 21 values of α × 11 of ε on the
/// rotating CVT, one method.
pub(crate) async fn map_view(client: &Client, driver: &Driver, base: &str) -> Result<(), String> {
    driver.browser_log(client).await?;
    let link = format!("{base}?view=map");
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    let button = r#"#view-map .map-presets button[data-preset="alpha-reversibility"]"#;
    client
        .wait()
        .at_most(Duration::from_secs(20))
        .for_element(Locator::Css(button))
        .await
        .map_err(|e| format!("the map shows no α preset ({button}): {e}"))?
        .click()
        .await
        .map_err(|e| format!("cannot click the α preset: {e}"))?;
    let (state, text) = wait_for_view(client, "view-map").await?;
    let shot = screenshot(client, "map.png").await;
    assert_eq!(state, "done", "the sweep finished with {text:?} ({shot})");
    let report = js(client, MAP_REPORT).await?;
    assert_eq!(report["cells"], json!(231), "21 × 11 cells: {report}");
    assert_eq!(report["drawn"], report["cells"], "every cell is drawn: {report}");
    assert_eq!(report["progress"].as_f64(), Some(1.0), "the progress bar is full: {report}");
    let kinds = report["kinds"].as_array().ok_or("no cell kinds")?;
    assert!(
        kinds.iter().all(|k| ["exact", "bounded", "drift", "failed", "invalid"]
            .contains(&k.as_str().unwrap_or(""))),
        "every cell has a verdict or a status: {report}"
    );
    // The axes by the labels the form uses, not the API's paths.
    assert_eq!(report["axes"], json!(["α (every method)", "ε (epsilon)"]), "{report}");
    // Reversible only at α = 0.5, and only while ε is small: bounded there (row 10, ε = 0),
    // drifting at α = 0.3 (cell 0) and at ε = 0.5 (the last column).
    assert_eq!(kinds[10 * 11], "bounded", "DLA^0.5 at ε = 0: {report}");
    assert_eq!(kinds[0], "drift", "DLA^0.3 at ε = 0: {report}");
    assert_eq!(kinds[10 * 11 + 10], "drift", "DLA^0.5 at ε = 0.5: {report}");
    let url = report["url"].as_str().unwrap_or_default();
    for part in [
        "view=map",
        "system=cvt_pendulum",
        "preset=rotating-perturbed",
        "t_end=300",
        "methods=dla:0.5",
        "map.axis=methods.alpha:linspace:0.3,0.7,21",
        "map.axis=params.epsilon:linspace:0,0.5,11",
        "run=1",
    ] {
        assert!(url.contains(part), "the URL holds the map ({part}): {url}");
    }
    // The legend says what each letter means, and the server's criterion is shown.
    assert!(report["legend"].as_str().unwrap_or("").contains("bounded"), "{report}");
    assert!(report["criterion"].as_str().unwrap_or("").starts_with("Criterion: "), "{report}");
    console_clean(driver, client, "map view").await?;

    // The heat map as PNG and SVG: every cell in the drawing, with its verdict letter.
    js(client, CATCH_DOWNLOADS).await?;
    for format in ["png", "svg"] {
        let css = format!("#view-map .map-card .plot-head .export-{format}");
        let button = client.find(Locator::Css(&css)).await.map_err(|e| format!("no {css}: {e}"))?;
        button.click().await.map_err(|e| format!("cannot click {css}: {e}"))?;
    }
    let files = poll(client, DOWNLOADS, Duration::from_secs(20)).await?;
    let stem = "nhlab-map-cvt_pendulum-methods-alpha-x-params-epsilon";
    assert_eq!(files[0]["name"], format!("{stem}.png"), "{files}");
    assert_eq!(files[0]["head"], json!([137, 80, 78, 71]), "a PNG file: {files}");
    assert_eq!(files[1]["name"], format!("{stem}.svg"), "{files}");
    assert!(files[1]["rects"].as_u64().unwrap_or(0) >= 231, "a rectangle per cell: {files}");
    assert!(files[1]["letters"].as_u64().unwrap_or(0) >= 200, "verdict letters: {files}");
    let bytes = js(client, "return window.__downloads.map((d) => [d.name, d.bytes]);").await?;
    for file in bytes.as_array().into_iter().flatten() {
        save(file[0].as_str().unwrap_or("map-export"), &file[1]);
    }

    // Hovering cell 5 (α = 0.3, the first row; ε = 0.25, the sixth column) names it.
    let (x, y) = cell_center(client, 5).await?;
    let mouse = MouseActions::new("mouse".to_owned()).then(PointerAction::MoveTo {
        duration: Some(Duration::from_millis(50)),
        x,
        y,
    });
    client.perform_actions(mouse).await.map_err(|e| format!("cannot hover the map: {e}"))?;
    let tip = js(
        client,
        "const t = document.querySelector('#view-map .map-tooltip'); return [t.hidden, t.dataset.cell, t.innerText];",
    )
    .await?;
    assert_eq!(tip[0], json!(false), "a tooltip appears on hover: {tip}");
    assert_eq!(tip[1], json!("5"), "the hovered cell's tooltip: {tip}");
    let text = tip[2].as_str().unwrap_or_default();
    for part in
        ["α (every method) = 0.3", "ε (epsilon) = 0.25", "DLA⁰·³: ", "energy: ", "max ", "steps"]
    {
        assert!(text.contains(part), "the tooltip names the cell and its numbers ({part}): {text}");
    }
    screenshot(client, "map-tooltip.png").await;

    // Clicking it opens that run in Explore, with its curves.
    let click = MouseActions::new("mouse".to_owned())
        .then(PointerAction::MoveTo { duration: None, x, y })
        .then(PointerAction::Down { button: MOUSE_BUTTON_LEFT })
        .then(PointerAction::Up { button: MOUSE_BUTTON_LEFT });
    client.perform_actions(click).await.map_err(|e| format!("cannot click the map: {e}"))?;
    client.release_actions().await.map_err(|e| format!("cannot release the mouse: {e}"))?;
    let (state, text) = wait_for_status(client).await?;
    assert_eq!(state, "done", "the opened cell ran in Explore: {text:?}");
    let opened = js(
        client,
        r#"return [location.search, document.getElementById('view-main').hidden,
                   document.getElementById('param-epsilon').value];"#,
    )
    .await?;
    let url = opened[0].as_str().unwrap_or_default();
    for part in ["system=cvt_pendulum", "preset=rotating-perturbed", "methods=dla:0.3", "t_end=300"]
    {
        assert!(url.contains(part), "Explore runs the cell's scene ({part}): {opened}");
    }
    assert_eq!(opened[1], json!(false), "Explore is shown: {opened}");
    assert_eq!(opened[2], json!("0.25"), "with the cell's ε: {opened}");
    let plot = js(client, PLOT_REPORT).await?;
    let series = plot["series"].as_array().ok_or("no energy chart in Explore")?;
    assert_eq!(series.len(), 1, "one curve, the cell's method: {plot}");
    assert_eq!(series[0]["label"], json!("DLA⁰·³"), "{plot}");
    assert_eq!(series[0]["drawn"], json!(true), "{plot}");
    screenshot(client, "map-opened.png").await;
    console_clean(driver, client, "map cell opened").await?;
    one_axis(client, driver, base).await?;
    sleigh(client, driver, base).await?;
    bad_axis(client, base).await?;
    println!("map view: 231 cells drawn, tooltip and click checked; screenshot {shot}");
    Ok(())
}

/// A link with one axis and `run=1`: a strip of cells and a line per method.
async fn one_axis(client: &Client, driver: &Driver, base: &str) -> Result<(), String> {
    let link = format!(
        "{base}?view=map&system=knife_edge&preset=paper&t_end=20&integrals=energy\
         &map.axis=step:logspace:0.05,0.8,5&map.color=log&run=1"
    );
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    let (state, text) = wait_for_view(client, "view-map").await?;
    let shot = screenshot(client, "map-one-axis.png").await;
    assert_eq!(state, "done", "the one-axis sweep finished with {text:?} ({shot})");
    let report = js(client, MAP_REPORT).await?;
    assert_eq!([&report["cells"], &report["drawn"]], [&json!(5), &json!(5)], "{report}");
    let lines = report["lines"].as_array().ok_or_else(|| format!("no line plot: {report}"))?;
    let labels: Vec<&str> = lines.iter().map(|l| l["label"].as_str().unwrap_or("?")).collect();
    assert_eq!(labels, ["DLA⁰·⁵", "DLA⁰·⁴", "DLA⁰˒¹", "LF", "DD"], "a line per method");
    for l in lines {
        assert_eq!(l["drawn"], json!(true), "{report}");
        assert!(l["points"].as_u64().unwrap_or(0) >= 3, "a line lacks points: {report}");
    }
    assert!(report["legend"].as_str().unwrap_or("").contains("log₁₀"), "{report}");
    console_clean(driver, client, "map with one axis").await
}

/// A system outside the paper's class: the sleigh's preset button is offered, and a short
/// one-axis link sweeps it, with a line per method and an integral it has (no DD-AVF offered).
async fn sleigh(client: &Client, driver: &Driver, base: &str) -> Result<(), String> {
    let link = format!(
        "{base}?view=map&system=chaplygin_sleigh&preset=inclined&t_end=20\
         &methods=leapfrog,dd,rattle&map.axis=step:logspace:0.05,0.5,4&run=1"
    );
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    let (state, text) = wait_for_view(client, "view-map").await?;
    let shot = screenshot(client, "map-sleigh.png").await;
    assert_eq!(state, "done", "the sleigh's sweep finished with {text:?} ({shot})");
    let report = js(client, MAP_REPORT).await?;
    assert_eq!([&report["cells"], &report["drawn"]], [&json!(4), &json!(4)], "{report}");
    let kinds = report["kinds"].as_array().ok_or("no cell kinds")?;
    assert!(
        kinds.iter().all(|k| ["exact", "bounded", "drift"].contains(&k.as_str().unwrap_or(""))),
        "every cell has a verdict: {report}"
    );
    let lines = report["lines"].as_array().ok_or_else(|| format!("no line plot: {report}"))?;
    assert_eq!(lines.len(), 3, "a line per method: {report}");
    let offered = js(
        client,
        r#"return {
             presets: [...document.querySelectorAll('#view-map .map-presets button')].map((b) => b.dataset.preset),
             integrals: [...document.querySelectorAll('#map-integral option')].map((o) => o.value),
             scene: document.querySelector('#view-map .map-scene-text').textContent,
           };"#,
    )
    .await?;
    assert!(offered["presets"].to_string().contains("sleigh-step"), "{offered}");
    assert_eq!(offered["integrals"], json!(["energy", "constraint"]), "{offered}");
    assert!(offered["scene"].as_str().unwrap_or("").starts_with("Chaplygin sleigh"), "{offered}");
    console_clean(driver, client, "map of the sleigh").await
}

/// An axis path the server does not know: its 422 is shown at that axis's field.
async fn bad_axis(client: &Client, base: &str) -> Result<(), String> {
    let link = format!(
        "{base}?view=map&system=knife_edge&preset=paper&t_end=10&map.axis=params.nope:values:1,2&run=1"
    );
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    let (state, text) = wait_for_view(client, "view-map").await?;
    assert_eq!(state, "error", "an unknown path is rejected: {text:?}");
    let field = js(
        client,
        r#"const f = document.querySelector('#view-map [data-path="axes[0].path"]');
           return [f.classList.contains('invalid'), f.querySelector('.field-error')?.textContent ?? null];"#,
    )
    .await?;
    assert_eq!(field[0], json!(true), "the axis path is marked: {field} ({text})");
    assert!(
        field[1].as_str().unwrap_or_default().contains("nope"),
        "the server's message sits at the path: {field}"
    );
    screenshot(client, "map-bad-axis.png").await;
    Ok(())
}

/// A cell's centre in viewport pixels, after scrolling the map into view.
async fn cell_center(client: &Client, cell: u64) -> Result<(f64, f64), String> {
    let v: Value = js(
        client,
        &format!(
            "const c = document.querySelector('#view-map .heatmap-canvas'); c.scrollIntoView({{block: 'center'}});
             const r = c.getBoundingClientRect(); const p = c.heatmap.centerOf({cell});
             return [Math.round(r.left + p.x), Math.round(r.top + p.y)];"
        ),
    )
    .await?;
    match (v[0].as_f64(), v[1].as_f64()) {
        (Some(x), Some(y)) => Ok((x, y)),
        _ => Err(format!("no position for cell {cell}: {v}")),
    }
}

/// The map: its cells (drawn, received), the kind of each, axes, legend, line plot, URL.
const MAP_REPORT: &str = r#"
const root = document.getElementById('view-map');
const h = root.querySelector('.heatmap-canvas')?.heatmap;
const m = h?.model;
const u = root.querySelector('.map-line-plot')?.uplot;
return {
  cells: m ? m.cells : null,
  drawn: h ? h.drawn : null,
  progress: Number(root.querySelector('.map-progress').value),
  kinds: m ? Array.from({ length: m.cells }, (_, c) => m.stateOf(c).kind) : [],
  axes: m ? (m.ys ? [m.yTitle, m.xTitle] : [m.xTitle]) : [],
  legend: root.querySelector('.map-legend').textContent,
  criterion: root.querySelector('.map-criterion').textContent,
  lines: u ? u.series.slice(1).map((s, i) => ({
    label: s.label,
    drawn: !!(s._paths && s._paths.stroke),
    points: u.data[i + 1].filter((v) => v !== null && v !== undefined).length,
  })) : null,
  url: location.search,
};
"#;

/// A sweep saved as JSON with a method written in Python among its methods, as the Python
/// package publishes one (`SweepRows.to_json`), opens in the Map view from a file: its own
/// axes and methods, every cell drawn with its verdict, and a cell of the Python method is
/// named but not opened in Explore (it runs only in the Python package). The same rows as
/// the server's CSV writer gives them open alike.
pub(crate) async fn map_opens_a_file(client: &Client, base: &str) -> Result<(), String> {
    let sweep = saved_sweep();
    let columns = csv::Columns {
        axes: vec!["methods[0].damping".into(), "params.epsilon".into()],
        integrals: vec!["energy".into(), "constraint".into()],
        observables: vec![],
    };
    let rows = sweep["rows"].as_array().cloned().unwrap_or_default();
    let files = [
        ("projected-verlet.json", sweep.to_string()),
        ("projected-verlet.csv", csv::write(&columns, rows.into_iter())),
    ];
    for (name, text) in files {
        map_opens(client, base, name, &text).await?;
    }
    Ok(())
}

async fn map_opens(client: &Client, base: &str, name: &str, contents: &str) -> Result<(), String> {
    let link = format!("{base}?view=map");
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    let dir = tempfile::tempdir().map_err(|e| format!("no temporary folder: {e}"))?;
    let path = dir.path().join(name);
    std::fs::write(&path, contents).map_err(|e| format!("cannot write: {e}"))?;
    let input = client
        .wait()
        .at_most(Duration::from_secs(20))
        .for_element(Locator::Css("#map-open"))
        .await
        .map_err(|e| format!("the map offers no file to open: {e}"))?;
    input.send_keys(&path.to_string_lossy()).await.map_err(|e| format!("cannot pick it: {e}"))?;
    let opened = "const t = document.querySelector('#view-map .view-status').textContent; \
                  return t.startsWith('Opened') || t.startsWith('Cannot') ? t : null";
    let text = poll(client, opened, Duration::from_secs(20)).await?;
    assert!(text.as_str().unwrap_or_default().contains("6 cells, 12 runs"), "{text}");
    let report = js(client, MAP_REPORT).await?;
    assert_eq!(report["cells"], json!(6), "{report}");
    assert_eq!(report["drawn"], json!(6), "every cell is drawn: {report}");
    assert_eq!(report["axes"], json!(["method 1, damping", "ε (epsilon)"]), "{report}");
    let kinds = json!(["bounded", "bounded", "bounded", "drift", "drift", "drift"]);
    assert_eq!(report["kinds"], kinds, "the Python method's verdicts: {report}");
    let options = js(
        client,
        "return [...document.querySelectorAll('#map-method option')].map((o) => o.textContent)",
    )
    .await?;
    assert_eq!(options, json!(["projected Verlet", "LF"]), "the file's methods");
    // Opening the Python method's cell names why it cannot run here.
    let refused = js(
        client,
        "document.querySelector('.heatmap-canvas').heatmap.onOpen(4); \
         return document.querySelector('#view-map .view-status').textContent",
    )
    .await?;
    let refused = refused.as_str().unwrap_or_default();
    assert!(refused.contains("written in Python"), "{refused}");
    Ok(())
}

/// Six cells (damping 0 and 1 × ε 0, 0.1, 0.2) of a method written in Python beside LF.
fn saved_sweep() -> Value {
    let python = json!({"id": "python", "name": "projected Verlet", "label": "projected Verlet"});
    let lf = json!({"id": "leapfrog", "label": "LF"});
    let verdict =
        |kind: &str| json!({"kind": kind, "max": 0.1, "early": 0.01, "late": 0.05, "ratio": 5.0});
    let mut rows = Vec::new();
    for cell in 0..6 {
        let (damping, epsilon) = ([0.0, 1.0][cell / 3], [0.0, 0.1, 0.2][cell % 3]);
        let values = json!([damping, epsilon]);
        for (index, method) in [&python, &lf].into_iter().enumerate() {
            let kind = if index == 0 && cell >= 3 { "drift" } else { "bounded" };
            rows.push(json!({
                "cell": cell, "values": values, "method_index": index, "method": method,
                "status": "ok", "error": null, "steps": 955, "cpu_ms": 1.0,
                "newton_iterations": null, "gaps": {},
                "verdicts": {"energy": verdict(kind), "constraint": verdict("exact")},
                "simulate": {"system": "knife_edge", "preset": "paper-perturbed",
                             "methods": [method], "points": 50},
            }));
        }
    }
    json!({
        "axes": [{"path": "methods[0].damping", "values": [0.0, 1.0]},
                 {"path": "params.epsilon", "values": [0.0, 0.1, 0.2]}],
        "methods": [python, lf], "integrals": ["energy", "constraint"], "cells": 6,
        "criterion": "drift when late/early > 2", "rows": rows,
    })
}
