//! The Paper, Scorecard and Work–precision views.

use crate::driver::Driver;
use crate::explore::console_clean;
use crate::page::{click, js, screenshot, wait_for_status, wait_for_view};
use fantoccini::{Client, Locator};
use serde_json::json;
use std::time::Duration;

/// The Paper view: four figures, fourteen panels, each with its five curves drawn and a
/// verdict per method; then the Poincaré sections beside the reference's.
pub(crate) async fn paper_view(client: &Client, driver: &Driver, base: &str) -> Result<(), String> {
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
            json!("knife_edge-energy"),
            json!("cvt_pendulum-passenger_energy"),
            json!("cvt_pendulum-driver_energy"),
            json!("cvt_pendulum-latitude"),
            json!("section")
        ],
        "{report}"
    );
    let panels = report["panels"].as_array().ok_or("no panels")?;
    assert_eq!(panels.len(), 2 + 3 * 4, "two knife-edge panels, four per CVT figure: {report}");
    for p in panels {
        let series = p["series"].as_array().ok_or_else(|| format!("panel without a chart: {p}"))?;
        let labels: Vec<&str> = series.iter().map(|s| s["label"].as_str().unwrap_or("?")).collect();
        // The paper's labels for people: exponents as superscripts, no TeX braces.
        assert_eq!(labels, ["DLA⁰·⁵", "DLA⁰·⁴", "DLA⁰˒¹", "LF", "DD"], "{p}");
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
    js(
        client,
        "document.querySelector('[data-figure=\"cvt_pendulum-latitude\"]').scrollIntoView();",
    )
    .await?;
    screenshot(client, "paper-cvt.png").await;
    // The figure the paper does not have: LF's and DLA^½'s sections beside the reference's,
    // the reference drawn first (beneath) in grey, and a caption with the methods' verdicts.
    let section = &report["section"];
    let drawn = section["drawn"].as_array().ok_or_else(|| format!("no section drawn: {report}"))?;
    let labels: Vec<&str> = drawn.iter().map(|s| s["label"].as_str().unwrap_or("?")).collect();
    assert_eq!(labels, ["reference", "LF", "DLA⁰·⁵"], "{section}");
    assert_eq!(drawn[0]["colour"], "#94a3b8", "the reference in grey: {section}");
    for s in drawn {
        assert!(s["points"].as_u64().unwrap_or(0) >= 100, "a section lacks crossings: {section}");
    }
    let caption = section["caption"].as_str().unwrap_or("");
    assert!(
        caption.contains("LF: passenger energy") && caption.contains("latitude"),
        "the caption says the verdicts: {caption}"
    );
    js(client, "document.querySelector('[data-figure=\"section\"]').scrollIntoView();").await?;
    screenshot(client, "paper-section.png").await;
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
  section: (() => {
    const f = document.querySelector('#view-paper [data-figure="section"]');
    return f ? { drawn: f.querySelector('.dyn-card').xy.drawn, caption: f.querySelector('figcaption').textContent } : null;
  })(),
};
"#;

/// The Scorecard view: a cell per method × scene × integral on the thirteen default scenes,
/// DD-AVF "n/a" outside the paper's class (not failed), property marks per system (the
/// fibration not defined outside the class), and a cell that opens its scene.
pub(crate) async fn scorecard_view(
    client: &Client,
    driver: &Driver,
    base: &str,
) -> Result<(), String> {
    let link = format!("{base}?view=scorecard");
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    let (state, text) = wait_for_view(client, "view-scorecard").await?;
    let shot = screenshot(client, "scorecard.png").await;
    assert_eq!(state, "done", "the scorecard finished with {text:?} ({shot})");
    assert!(text.contains("on 13 scenes") && text.contains("not applicable"), "{text}");
    assert!(!text.contains("failed"), "an n/a run is not a failure: {text}");
    let report = js(client, SCORECARD_REPORT).await?;
    let rows = report["rows"].as_array().ok_or("no rows")?;
    let labels: Vec<&str> = rows.iter().map(|r| r["method"].as_str().unwrap_or("?")).collect();
    assert_eq!(
        labels,
        ["DLA^0.5", "DLA^0.4", "DLA^{0,1}", "LF", "DD", "DD-AVF", "RK4", "RATTLE", "SPARK3"]
    );
    let systems = js(client, "return fetch('systems').then((r) => r.json());").await?;
    let scenes: Vec<String> = ["paper_scenes", "literature_scenes"]
        .iter()
        .flat_map(|k| systems[*k].as_array().cloned().unwrap_or_default())
        .map(|s| {
            format!("{}/{}", s["system"].as_str().unwrap_or(""), s["preset"].as_str().unwrap_or(""))
        })
        .collect();
    assert_eq!(scenes.len(), 13, "the paper's six and the literature's seven: {scenes:?}");
    let member = |scene: &str| {
        let id = scene.split('/').next().unwrap_or_default();
        systems["systems"]
            .as_array()
            .and_then(|a| a.iter().find(|s| s["id"] == id))
            .is_some_and(|s| s["paper_class"]["member"] == json!(true))
    };
    for row in rows {
        let avf = row["method"] == "DD-AVF";
        let cells = row["cells"].as_array().ok_or("no cells")?;
        for scene in &scenes {
            let here: Vec<_> = cells.iter().filter(|c| c["scene"] == scene.as_str()).collect();
            assert!(here.len() >= 2, "{}: {} cells for {scene}: {row}", row["method"], here.len());
            let na = avf && !member(scene);
            for c in here {
                let kind = c["kind"].as_str().unwrap_or("");
                if na {
                    assert_eq!(kind, "not_applicable", "DD-AVF on {scene}: {c}");
                    let title = c["title"].as_str().unwrap_or("");
                    assert!(title.contains("not applicable: ") && title.contains("paper"), "{c}");
                } else {
                    assert!(
                        ["exact", "bounded", "drift"].contains(&kind),
                        "{}: {c}",
                        row["method"]
                    );
                }
            }
        }
        let marks = row["marks"].as_object().ok_or("no property marks")?;
        assert_eq!(marks.len(), 8 * 3, "rev, sym and fib on eight systems: {row}");
        for paper in ["knife_edge", "cvt_pendulum"] {
            for property in ["reversible", "symmetric", "preserves_fibration"] {
                let mark = &marks[&format!("{paper}.{property}")];
                assert!(mark == "yes" || mark == "no", "{paper}.{property}: {row}");
            }
        }
        let expected = if avf { "not_applicable" } else { "not_defined" };
        assert_eq!(marks["chaplygin_sleigh.preserves_fibration"], expected, "{row}");
        if avf {
            assert_eq!(marks["chaplygin_sleigh.reversible"], "not_applicable", "{row}");
        }
    }
    let mark = |method: usize, key: &str| rows[method]["marks"][key].clone();
    assert_eq!(mark(1, "knife_edge.reversible"), "no", "DLA^0.4 is not reversible");
    assert_eq!(mark(4, "cvt_pendulum.reversible"), "yes", "DD is reversible");
    assert_eq!(mark(4, "cvt_pendulum.preserves_fibration"), "no", "DD breaks the fibration");
    assert_eq!(mark(3, "cvt_pendulum.preserves_fibration"), "yes", "LF keeps it");
    assert_eq!(mark(3, "knife_edge.symmetric"), "yes", "LF is symmetric");
    assert_eq!(mark(1, "knife_edge.symmetric"), "no", "DLA^0.4 is not");
    assert!(!report["criterion"].as_str().unwrap_or("").is_empty(), "the criterion is shown");
    js(client, "document.querySelector('#view-scorecard td.verdict-cell.not_applicable')?.scrollIntoView({block: 'center', inline: 'center'});").await?;
    screenshot(client, "scorecard-not-applicable.png").await;
    console_clean(driver, client, "scorecard view").await?;

    // A cell opens its scene, with the scorecard's seven methods, in the main view.
    click(
        client,
        r#"#view-scorecard td.verdict-cell[data-scene="cvt_pendulum/rotating"][data-integral="latitude"]"#,
    )
    .await?;
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
    assert_eq!(opened[2], json!(9), "the scorecard's nine methods ran: {opened}");
    screenshot(client, "scorecard-opened.png").await;
    console_clean(driver, client, "scorecard cell").await?;

    // A sleigh cell opens its scene without DD-AVF, which does not apply to it.
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    wait_for_view(client, "view-scorecard").await?;
    click(
        client,
        r#"#view-scorecard td.verdict-cell[data-scene="chaplygin_sleigh/free"][data-integral="energy"]:not(.not_applicable)"#,
    )
    .await?;
    let (state, text) = wait_for_status(client).await?;
    assert_eq!(state, "done", "the sleigh's scene ran: {text:?}");
    let opened = js(
        client,
        "return [...document.querySelectorAll('#runs tr.run th')].map((th) => th.textContent);",
    )
    .await?;
    assert_eq!(opened.as_array().map(Vec::len), Some(8), "every method but DD-AVF: {opened}");
    assert!(!opened.to_string().contains("DD-AVF"), "{opened}");
    console_clean(driver, client, "scorecard sleigh cell").await?;
    println!("scorecard view: 9 methods × 13 scenes, n/a outside the class; screenshot {shot}");
    Ok(())
}

/// The scorecard grid: per method row its verdict cells and property marks.
const SCORECARD_REPORT: &str = r#"
return {
  criterion: document.querySelector('#view-scorecard .criterion')?.textContent ?? '',
  rows: [...document.querySelectorAll('#view-scorecard table.scorecard-verdicts tbody tr')].map((tr) => ({
    method: tr.dataset.method,
    cells: [...tr.querySelectorAll('td.verdict-cell')].map((c) => ({ scene: c.dataset.scene, integral: c.dataset.integral, kind: c.dataset.kind, title: c.title })),
    marks: Object.fromEntries([...document.querySelectorAll(`#view-scorecard table.scorecard-properties tr[data-method="${CSS.escape(tr.dataset.method)}"] td.prop`)]
      .map((c) => [`${c.dataset.system}.${c.dataset.property}`, c.dataset.mark])),
  })),
};
"#;

/// The Work–precision view on the knife edge: two log–log plots, orders in legend and table.
pub(crate) async fn work_precision_view(
    client: &Client,
    driver: &Driver,
    base: &str,
) -> Result<(), String> {
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
