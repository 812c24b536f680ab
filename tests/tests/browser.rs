//! The page in a real browser, against the real server.
//!
//! The server runs in-process on 127.0.0.1 port 0 ([`TestServer`]); headless Chromium is
//! driven through chromedriver, which this test spawns on a free port, with fantoccini. One
//! browser session checks, in order:
//!
//! 1. the paper's knife-edge experiment (one click) draws five curves, the progress bar
//!    reaches 100 %, every run ends `ok`, and the console has no errors; a screenshot goes to
//!    `<target>/screenshots/knife-edge.png`;
//! 2. runs that fail (a step far too large) are marked failed, with the server's message;
//! 3. a long run shows curves before it ends, and Cancel stops it;
//! 4. editing the form rewrites the URL, and that URL restores the form;
//! 5. a link with a bad parameter and `run=1` fills the form, runs by itself, and shows the
//!    server's error next to the field its `path` names;
//! 6. `?view=paper` draws every panel of the paper's four figures (five curves with data
//!    each) with a verdict per method under it (`paper.png`, `paper-cvt.png`);
//! 7. `?view=scorecard` shows a verdict cell for every method × paper scene × integral and
//!    the property marks (`scorecard.png`); clicking a cell runs that scene in the main view;
//! 8. `?view=work-precision` with a knife-edge scene draws both log–log plots (error against
//!    run time, error against h) with a line per method, and each method's fitted order in
//!    the legend and the table, LF and DLA^{0,1} near 2, DLA^0.4 near 1
//!    (`work-precision.png`); the tab takes the Explore form's scene and methods; a run that
//!    fails is listed as failed with its message, not drawn (`work-precision-failed.png`).
//!
//! Chromium and chromedriver are required, not optional: without them the test fails and
//! says how to install them. `NHLAB_CHROMIUM` / `NHLAB_CHROMEDRIVER` override their paths.

use fantoccini::{Client, ClientBuilder, Locator};
use hyper_util::client::legacy::connect::HttpConnector;
use nhlab_tests::TestServer;
use serde_json::{Value, json};
use std::net::{Ipv4Addr, SocketAddr, TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// How long a run of the knife-edge experiment may take in a debug build on a slow machine.
const RUN_TIMEOUT: Duration = Duration::from_secs(120);

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_page_runs_the_knife_edge_experiment_in_a_real_browser() {
    let chromium = required("NHLAB_CHROMIUM", &["chromium", "chromium-browser", "google-chrome"]);
    let chromedriver = required("NHLAB_CHROMEDRIVER", &["chromedriver"]);
    let server = TestServer::start().await;
    let base = server.at("/");
    let driver = Driver::start(&chromedriver);
    let profile = tempfile::tempdir().expect("temporary Chromium profile");
    let client = driver.session(&chromium, profile.path()).await;

    let outcome = scenarios(&client, &driver, &base).await;
    let _ = client.close().await;
    if let Err(message) = outcome {
        panic!("{message}");
    }
}

async fn scenarios(client: &Client, driver: &Driver, base: &str) -> Result<(), String> {
    knife_edge(client, driver, base).await?;
    failed_runs(client, driver, base).await?;
    cancel(client, driver, base).await?;
    form_in_the_url(client, driver, base).await?;
    bad_parameter_link(client, base).await?;
    paper_view(client, driver, base).await?;
    scorecard_view(client, driver, base).await?;
    work_precision_view(client, driver, base).await
}

/// One click on the paper's knife-edge experiment.
async fn knife_edge(client: &Client, driver: &Driver, base: &str) -> Result<(), String> {
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
        ["DLA^0.5", "DLA^0.4", "DLA^{0,1}", "LF", "DD"],
        "one curve per paper method: {plot}"
    );
    for s in series {
        assert_eq!(s["show"], json!(true), "curve hidden: {s}");
        assert_eq!(s["drawn"], json!(true), "uPlot built no path for a curve: {s}");
        let points = s["points"].as_u64().unwrap_or(0);
        assert!(points >= 100, "a curve has {points} points, expected about a thousand: {s}");
    }
    assert_eq!(plot["legend"], json!(labels), "the legend lists the five methods");
    assert_eq!(plot["runs"], json!(["ok", "ok", "ok", "ok", "ok"]), "every run succeeds: {plot}");
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
async fn failed_runs(client: &Client, driver: &Driver, base: &str) -> Result<(), String> {
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
async fn cancel(client: &Client, driver: &Driver, base: &str) -> Result<(), String> {
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
async fn form_in_the_url(client: &Client, driver: &Driver, base: &str) -> Result<(), String> {
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
async fn console_clean(driver: &Driver, client: &Client, scenario: &str) -> Result<(), String> {
    let log = driver.browser_log(client).await?;
    let errors: Vec<&Value> = log.iter().filter(|e| e["level"] == "SEVERE").collect();
    if errors.is_empty() {
        Ok(())
    } else {
        Err(format!("{scenario}: the browser console has errors: {errors:#?}"))
    }
}

/// A link restores the form, runs by itself, and a 4xx lands next to its field.
async fn bad_parameter_link(client: &Client, base: &str) -> Result<(), String> {
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

/// The Paper view: four figures, fourteen panels, each with its five curves drawn and a
/// verdict per method.
async fn paper_view(client: &Client, driver: &Driver, base: &str) -> Result<(), String> {
    // The previous scenario's expected 422 is still in the log: start from a clean one.
    driver.browser_log(client).await?;
    let link = format!("{base}?view=paper");
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    let (state, text) = wait_for_view(client, "view-paper").await?;
    let shot = screenshot(client, "paper.png").await;
    assert_eq!(state, "done", "the paper view finished with {text:?} ({shot})");
    let report = js(client, PAPER_REPORT).await?;
    let figures = report["figures"].as_array().ok_or("no figures")?;
    assert_eq!(
        figures,
        &[
            json!("knife-energy"),
            json!("cvt-passenger"),
            json!("cvt-driver"),
            json!("cvt-latitude")
        ],
        "{report}"
    );
    let panels = report["panels"].as_array().ok_or("no panels")?;
    assert_eq!(panels.len(), 2 + 3 * 4, "two knife-edge panels, four per CVT figure: {report}");
    for p in panels {
        let series = p["series"].as_array().ok_or_else(|| format!("panel without a chart: {p}"))?;
        let labels: Vec<&str> = series.iter().map(|s| s["label"].as_str().unwrap_or("?")).collect();
        assert_eq!(labels, ["DLA^0.5", "DLA^0.4", "DLA^{0,1}", "LF", "DD"], "{p}");
        for s in series {
            assert_eq!(s["drawn"], json!(true), "a curve is not drawn: {p}");
            assert!(s["points"].as_u64().unwrap_or(0) >= 50, "a curve lacks data: {p}");
        }
        let kinds = p["verdicts"].as_array().ok_or("no verdict row")?;
        assert_eq!(kinds.len(), 5, "one verdict per method: {p}");
        assert!(
            kinds.iter().all(|k| ["exact", "bounded", "drift"].contains(&k.as_str().unwrap_or(""))),
            "every verdict is known: {p}"
        );
        assert!(!p["caption"].as_str().unwrap_or("").is_empty(), "a figure lacks its caption: {p}");
    }
    let knife = &panels[0];
    assert_eq!(knife["scene"], "knife_edge/paper");
    assert_eq!(
        knife["verdicts"],
        json!(["bounded", "drift", "bounded", "bounded", "exact"]),
        "the paper's knife-edge row: {knife}"
    );
    js(client, "document.querySelector('[data-figure=\"cvt-latitude\"]').scrollIntoView();")
        .await?;
    screenshot(client, "paper-cvt.png").await;
    console_clean(driver, client, "paper view").await?;
    println!("paper view: {} panels drawn with verdicts; screenshot {shot}", panels.len());
    Ok(())
}

/// Panels of the paper view: scene, integral, uPlot series, verdict row and caption.
const PAPER_REPORT: &str = r#"
const figures = [...document.querySelectorAll('#view-paper .paper-figure')];
return {
  figures: figures.map((f) => f.dataset.figure),
  panels: figures.flatMap((f) => [...f.querySelectorAll('.paper-panel')].map((p) => {
    const u = p.querySelector('.plot-card')?.uplot;
    return {
      scene: p.dataset.scene,
      integral: p.dataset.integral,
      caption: f.querySelector('figcaption')?.textContent ?? '',
      series: u ? u.series.slice(1).map((s, i) => ({
        label: s.label,
        drawn: !!(s._paths && s._paths.stroke),
        points: u.data[i + 1].filter((v) => v !== null && v !== undefined).length,
      })) : null,
      verdicts: [...p.querySelectorAll('.verdict-chip')].map((c) => c.dataset.kind),
    };
  })),
};
"#;

/// The Scorecard view: a cell per method × scene × integral, property marks, and a cell
/// that opens its scene.
async fn scorecard_view(client: &Client, driver: &Driver, base: &str) -> Result<(), String> {
    let link = format!("{base}?view=scorecard");
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    let (state, text) = wait_for_view(client, "view-scorecard").await?;
    let shot = screenshot(client, "scorecard.png").await;
    assert_eq!(state, "done", "the scorecard finished with {text:?} ({shot})");
    let report = js(client, SCORECARD_REPORT).await?;
    let rows = report["rows"].as_array().ok_or("no rows")?;
    let labels: Vec<&str> = rows.iter().map(|r| r["method"].as_str().unwrap_or("?")).collect();
    assert_eq!(labels, ["DLA^0.5", "DLA^0.4", "DLA^{0,1}", "LF", "DD", "DD-AVF", "RK4"]);
    let paper_scenes = [
        "knife_edge/paper",
        "knife_edge/paper-perturbed",
        "cvt_pendulum/oscillating",
        "cvt_pendulum/rotating",
        "cvt_pendulum/oscillating-perturbed",
        "cvt_pendulum/rotating-perturbed",
    ];
    for row in rows {
        let cells = row["cells"].as_array().ok_or("no cells")?;
        for scene in paper_scenes {
            let n = cells.iter().filter(|c| c["scene"] == scene).count();
            assert!(n >= 3, "{}: {n} cells for {scene}: {row}", row["method"]);
        }
        assert!(
            cells
                .iter()
                .all(|c| ["exact", "bounded", "drift"].contains(&c["kind"].as_str().unwrap_or(""))),
            "every cell has a verdict: {row}"
        );
        let marks = row["marks"].as_object().ok_or("no property marks")?;
        assert_eq!(marks.len(), 4, "reversible and fibration on two systems: {row}");
        assert!(marks.values().all(|m| m == "yes" || m == "no"), "{row}");
    }
    let mark = |method: usize, key: &str| rows[method]["marks"][key].clone();
    assert_eq!(mark(1, "knife_edge.reversible"), "no", "DLA^0.4 is not reversible");
    assert_eq!(mark(4, "cvt_pendulum.reversible"), "yes", "DD is reversible");
    assert_eq!(mark(4, "cvt_pendulum.preserves_fibration"), "no", "DD breaks the fibration");
    assert_eq!(mark(3, "cvt_pendulum.preserves_fibration"), "yes", "LF keeps it");
    assert!(!report["criterion"].as_str().unwrap_or("").is_empty(), "the criterion is shown");
    console_clean(driver, client, "scorecard view").await?;

    // A cell opens its scene, with the scorecard's seven methods, in the main view.
    let cell = r#"#view-scorecard td.verdict-cell[data-scene="cvt_pendulum/rotating"][data-integral="latitude"]"#;
    client
        .find(Locator::Css(cell))
        .await
        .map_err(|e| format!("no cell {cell}: {e}"))?
        .click()
        .await
        .map_err(|e| format!("cannot click {cell}: {e}"))?;
    let (state, text) = wait_for_status(client).await?;
    assert_eq!(state, "done", "the opened scene ran: {text:?}");
    let opened = js(
        client,
        r#"return [location.search, document.getElementById('view-main').hidden,
                   document.querySelectorAll('#runs tr.run').length];"#,
    )
    .await?;
    let url = opened[0].as_str().unwrap_or_default();
    assert!(url.contains("system=cvt_pendulum") && url.contains("preset=rotating"), "{opened}");
    assert_eq!(opened[1], json!(false), "the main view is shown: {opened}");
    assert_eq!(opened[2], json!(7), "the scorecard's seven methods ran: {opened}");
    screenshot(client, "scorecard-opened.png").await;
    console_clean(driver, client, "scorecard cell").await?;
    println!("scorecard view: 7 methods × 6 scenes with property marks; screenshot {shot}");
    Ok(())
}

/// The scorecard grid: per method row its verdict cells and property marks.
const SCORECARD_REPORT: &str = r#"
return {
  criterion: document.querySelector('#view-scorecard .criterion')?.textContent ?? '',
  rows: [...document.querySelectorAll('#view-scorecard table.scorecard tbody tr')].map((tr) => ({
    method: tr.dataset.method,
    cells: [...tr.querySelectorAll('td.verdict-cell')].map((c) => ({ scene: c.dataset.scene, integral: c.dataset.integral, kind: c.dataset.kind })),
    marks: Object.fromEntries([...tr.querySelectorAll('td.prop')].map((c) => [`${c.dataset.system}.${c.dataset.property}`, c.dataset.mark])),
  })),
};
"#;

/// The Work–precision view on the knife edge: two log–log plots, orders in legend and table.
async fn work_precision_view(client: &Client, driver: &Driver, base: &str) -> Result<(), String> {
    driver.browser_log(client).await?;
    let link = format!(
        "{base}?view=work-precision&system=knife_edge&preset=paper&t_end=20\
         &methods=leapfrog,dla01,dla:0.4&levels=4&repeats=2"
    );
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    let (state, text) = wait_for_view(client, "view-work-precision").await?;
    let shot = screenshot(client, "work-precision.png").await;
    assert_eq!(state, "done", "the work-precision view finished with {text:?} ({shot})");
    let report = js(client, WORK_PRECISION_REPORT).await?;
    assert_eq!(report["plots"], json!(["time", "step"]), "two plots: {report}");
    for (plot, series) in report["series"].as_array().ok_or("no series")?.iter().enumerate() {
        let series = series.as_array().ok_or_else(|| format!("plot {plot} has no chart"))?;
        assert_eq!(series.len(), 3, "a line per method: {report}");
        for s in series {
            assert_eq!(s["drawn"], json!(true), "a line is not drawn: {report}");
            assert_eq!(s["points"], json!(4), "four step sizes per line: {report}");
        }
    }
    let legend = report["legend"][1].as_array().ok_or("no legend on the h plot")?;
    assert_eq!(legend.len(), 3, "a legend entry per method: {report}");
    assert!(
        legend.iter().all(|l| l.as_str().unwrap_or("").contains("order ")),
        "the h plot's legend gives each order: {report}"
    );
    let orders = report["orders"].as_array().ok_or("no orders table")?;
    let order = |label: &str| {
        orders
            .iter()
            .find(|o| o[0] == label)
            .and_then(|o| o[1].as_str()?.parse::<f64>().ok())
            .ok_or_else(|| format!("no order for {label}: {report}"))
    };
    for (label, expected) in [("LF", 2.0), ("DLA^{0,1}", 2.0), ("DLA^0.4", 1.0)] {
        let measured = order(label)?;
        assert!((measured - expected).abs() < 0.3, "{label}: order {measured} ({report})");
    }
    assert_eq!(report["failed"], json!(0), "{report}");
    let url = report["url"].as_str().unwrap_or_default();
    assert!(url.contains("view=work-precision") && url.contains("t_end=20"), "{url}");
    console_clean(driver, client, "work-precision view").await?;

    // The tab takes the Explore form's scene and methods, and writes them into the URL.
    let link = format!("{base}?system=knife_edge&preset=paper&t_end=10&methods=leapfrog,dd");
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    client
        .wait()
        .at_most(Duration::from_secs(20))
        .for_element(Locator::Css(r#".tabs .tab[data-view="work-precision"]"#))
        .await
        .map_err(|e| format!("no work-precision tab: {e}"))?
        .click()
        .await
        .map_err(|e| format!("cannot click the work-precision tab: {e}"))?;
    let (state, text) = wait_for_view(client, "view-work-precision").await?;
    assert_eq!(state, "done", "the tab computed the form's scene: {text:?}");
    let report = js(client, WORK_PRECISION_REPORT).await?;
    let methods: Vec<&str> = report["orders"]
        .as_array()
        .map_or(vec![], |o| o.iter().filter_map(|m| m[0].as_str()).collect());
    assert_eq!(methods, ["LF", "DD"], "the form's methods: {report}");
    let url = report["url"].as_str().unwrap_or_default();
    assert!(
        url.starts_with("?view=work-precision") && url.contains("t_end=10"),
        "the view's URL holds the form's scene: {url}"
    );

    // h = 2.5 on the CVT: the leap-frog diverges at the largest step, and says so.
    let link = format!(
        "{base}?view=work-precision&system=cvt&t_end=1000&step=2.5&methods=leapfrog&levels=2&repeats=1"
    );
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    let (state, text) = wait_for_view(client, "view-work-precision").await?;
    let failed_shot = screenshot(client, "work-precision-failed.png").await;
    assert_eq!(state, "done-failed", "a failed run is reported: {text:?} ({failed_shot})");
    let report = js(client, WORK_PRECISION_REPORT).await?;
    assert_eq!(report["failed"], json!(1), "{report}");
    assert!(
        report["legend"][0][0].as_str().unwrap_or("").contains("1 failed"),
        "the legend says a run failed: {report}"
    );
    assert!(
        report["failures"][0].as_str().unwrap_or("").contains("diverged"),
        "the failure is listed with the server's message: {report}"
    );
    let points = report["series"][1][0]["points"].as_u64().unwrap_or(9);
    assert!(points < 2, "the failed run is not a point: {report}");
    println!("work-precision view: two log-log plots, orders {orders:?}; screenshot {shot}");
    Ok(())
}

/// The work-precision view: its plots, their series and legends, the orders table.
const WORK_PRECISION_REPORT: &str = r#"
const root = document.getElementById('view-work-precision');
const cards = [...root.querySelectorAll('.wp-card')];
return {
  plots: cards.map((c) => c.dataset.plot),
  series: cards.map((c) => {
    const u = c.uplot;
    return u ? u.series.slice(1).map((s, i) => ({
      label: s.label,
      drawn: !!(s._paths && s._paths.stroke),
      points: (u.data[i + 1] ?? []).filter((v) => v !== null && v !== undefined).length,
    })) : null;
  }),
  // A static legend (live: false) has no row for the x series.
  legend: cards.map((c) => [...c.querySelectorAll('.u-legend .u-series .u-label')].map((e) => e.textContent)),
  orders: [...root.querySelectorAll('tr.wp-method')].map((tr) => [tr.dataset.method, tr.querySelector('.slope')?.dataset.order ?? '']),
  failed: root.querySelectorAll('td.failed').length,
  failures: [...root.querySelectorAll('.wp-failures li')].map((li) => li.textContent),
  url: location.search,
};
"#;

/// Polls a view's status line until its computation is over; returns its state and text.
async fn wait_for_view(client: &Client, view: &str) -> Result<(String, String), String> {
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
const PLOT_REPORT: &str = r#"
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
async fn wait_for_status(client: &Client) -> Result<(String, String), String> {
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

async fn js(client: &Client, script: &str) -> Result<Value, String> {
    client.execute(script, vec![]).await.map_err(|e| format!("script failed: {e}\n{script}"))
}

/// Saves a PNG under `<target>/screenshots/`; returns its path (or why it could not).
async fn screenshot(client: &Client, name: &str) -> String {
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

/// A program the test cannot run without: from the environment variable, else from PATH.
fn required(var: &str, names: &[&str]) -> PathBuf {
    if let Some(path) = std::env::var_os(var) {
        let path = PathBuf::from(path);
        assert!(path.is_file(), "{var}={} does not exist", path.display());
        return path;
    }
    let dirs: Vec<PathBuf> =
        std::env::var_os("PATH").map(|p| std::env::split_paths(&p).collect()).unwrap_or_default();
    names
        .iter()
        .flat_map(|name| dirs.iter().map(move |d| d.join(name)))
        .find(|p| p.is_file())
        .unwrap_or_else(|| {
            panic!(
                "the browser test needs {} but none is on PATH (or set {var}); on Debian/Ubuntu: \
                 apt-get update && apt-get install -y chromium chromium-driver",
                names.join(" or ")
            )
        })
}

/// chromedriver on a free port, killed when dropped.
struct Driver {
    child: Child,
    url: String,
}

impl Driver {
    fn start(binary: &Path) -> Self {
        let port = TcpListener::bind((Ipv4Addr::LOCALHOST, 0))
            .and_then(|l| l.local_addr())
            .expect("free port")
            .port();
        let child = Command::new(binary)
            .arg(format!("--port={port}"))
            .stdout(Stdio::null())
            .stderr(Stdio::inherit())
            .spawn()
            .unwrap_or_else(|e| panic!("cannot start {}: {e}", binary.display()));
        let driver = Self { child, url: format!("http://127.0.0.1:{port}") };
        let addr = SocketAddr::from((Ipv4Addr::LOCALHOST, port));
        let start = Instant::now();
        while TcpStream::connect_timeout(&addr, Duration::from_millis(200)).is_err() {
            assert!(
                start.elapsed() < Duration::from_secs(20),
                "chromedriver did not listen on {addr} within 20 s"
            );
            std::thread::sleep(Duration::from_millis(50));
        }
        driver
    }

    async fn session(&self, chromium: &Path, profile: &Path) -> Client {
        let caps = json!({
            "goog:chromeOptions": {
                "binary": chromium,
                "args": [
                    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                    "--disable-background-networking", "--disable-component-update", "--disable-sync",
                    "--disable-dev-shm-usage", "--hide-scrollbars", "--window-size=1440,1500",
                    format!("--user-data-dir={}", profile.display()),
                ],
            },
            "goog:loggingPrefs": { "browser": "ALL" },
        });
        let Value::Object(caps) = caps else { unreachable!("a JSON object literal") };
        ClientBuilder::new(HttpConnector::new())
            .capabilities(caps)
            .connect(&self.url)
            .await
            .unwrap_or_else(|e| panic!("cannot start headless Chromium through chromedriver: {e}"))
    }

    /// The browser console since the last call (chromedriver's `se/log` endpoint).
    async fn browser_log(&self, client: &Client) -> Result<Vec<Value>, String> {
        let session = client.session_id().await.map_err(|e| e.to_string())?.ok_or("no session")?;
        let response = reqwest::Client::new()
            .post(format!("{}/session/{session}/se/log", self.url))
            .json(&json!({ "type": "browser" }))
            .send()
            .await
            .map_err(|e| format!("cannot read the browser log: {e}"))?;
        let body: Value =
            response.json().await.map_err(|e| format!("browser log is not JSON: {e}"))?;
        body["value"]
            .as_array()
            .cloned()
            .ok_or_else(|| format!("unexpected browser log answer: {body}"))
    }
}

impl Drop for Driver {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
