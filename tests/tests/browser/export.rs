//! A plot as a file and as text: the PNG and SVG export of an Explore plot (the download's
//! name and bytes), the card naming its scene, the canvas's text alternative; a diverged run
//! clipped off the y-range, with a note; a 3·10⁶ time axis with short tick labels, the
//! elapsed time while it runs, and the steps and time a cancelled run keeps; an empty Step
//! field shows and reports the preset's step, and the sticky Run bar does not cover it when
//! it is brought into view.
use crate::driver::Driver;
use crate::explore::console_clean;
use crate::page::{click, js, poll, wait_for_status};
use fantoccini::{Client, Locator};
use serde_json::{Value, json};
use std::path::Path;
use std::time::Duration;

pub(crate) async fn plot_export(
    client: &Client,
    driver: &Driver,
    base: &str,
) -> Result<(), String> {
    driver.browser_log(client).await?;
    let link = format!("{base}?system=knife_edge&preset=paper&t_end=20&run=1");
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    let (state, text) = wait_for_status(client).await?;
    assert_eq!(state, "done", "{text}");
    js(client, CATCH_DOWNLOADS).await?;
    let card = r#".plot-card[data-integral="energy"]"#;
    click(client, &format!("{card} .export-png")).await?;
    click(client, &format!("{card} .export-svg")).await?;
    let downloads = match poll(client, DOWNLOADS, Duration::from_secs(20)).await {
        Ok(d) => d,
        Err(e) => {
            let log = driver.browser_log(client).await?;
            let seen = js(client, "return window.__downloads.map(({ bytes, ...x }) => x);").await?;
            return Err(format!("{e}; downloads {seen}; console {log:#?}"));
        }
    };
    let png = &downloads[0];
    assert_eq!(png["name"], "nhlab-knife_edge-paper-energy.png", "{downloads}");
    assert_eq!(png["head"], json!([137, 80, 78, 71]), "a PNG file: {downloads}");
    assert!(png["size"].as_u64().unwrap_or(0) > 5000, "a whole chart: {downloads}");
    let svg = &downloads[1];
    assert_eq!(svg["name"], "nhlab-knife_edge-paper-energy.svg", "{downloads}");
    assert!(svg["text"].as_str().unwrap_or("").starts_with("<svg"), "{downloads}");
    assert!(svg["paths"].as_u64().unwrap_or(0) >= 5, "a path per curve: {downloads}");
    // The error axis's labels, as uPlot chose them (recorded through its axis options).
    assert!(svg["decades"].as_u64().unwrap_or(0) >= 2, "the y ticks' labels: {downloads}");
    let files = js(client, "return window.__downloads.map((d) => [d.name, d.bytes]);").await?;
    for file in files.as_array().into_iter().flatten() {
        save(file[0].as_str().unwrap_or("export"), &file[1]);
    }
    let card = js(client, CARD).await?;
    assert!(card["scene"].as_str().unwrap_or("").contains("t_end = 20"), "{card}");
    let alt = card["alt"].as_str().unwrap_or_default();
    assert!(
        alt.contains("last error") && ["exact", "bounded", "drift"].iter().any(|v| alt.contains(v)),
        "the canvas's text alternative gives errors and verdicts: {card}"
    );
    console_clean(driver, client, "plot export").await?;

    // A run that blows up is left out of the y-range, and the plot says so.
    let link =
        format!("{base}?system=cvt&t_end=1000&step=2.5&methods=leapfrog,dd&integrals=energy&run=1");
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    let (state, text) = wait_for_status(client).await?;
    assert_eq!(state, "done-failed", "the leap-frog diverges at h = 2.5: {text}");
    let clip = js(client, CLIP).await?;
    let note = clip["note"].as_str().unwrap_or_default();
    assert!(note.contains("LF") && note.contains("diverges"), "the plot says so: {clip}");
    assert!(clip["max"].as_f64().unwrap_or(f64::MAX) <= 1e8, "the y-axis is clipped: {clip}");

    // A long run: compact time ticks, progress with elapsed time; Cancel keeps steps and time.
    let link = format!(
        "{base}?system=knife_edge&preset=paper&t_end=3000000&methods=leapfrog&integrals=energy&run=1"
    );
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    let live = poll(client, LIVE, Duration::from_secs(20)).await?;
    let ticks: Vec<&str> =
        live["ticks"].as_array().map_or(vec![], |t| t.iter().filter_map(Value::as_str).collect());
    assert!(ticks.contains(&"1e6") && ticks.iter().all(|t| t.len() <= 6), "ticks {live}");
    assert!(live["status"].as_str().unwrap_or("").contains("elapsed"), "{live}");
    click(client, "#cancel").await?;
    let (state, text) = wait_for_status(client).await?;
    assert_eq!(state, "cancelled", "{text}");
    let row = js(client, "const c = [...document.querySelectorAll('#runs tr.run td.num')]; return c.map((x) => x.textContent);").await?;
    assert_ne!(row[0], "–", "a cancelled run keeps its steps: {row}");
    assert!(row[1].as_str().unwrap_or("").contains("partial"), "and its time: {row}");

    // An empty Step field: the preset's step as the placeholder and in the status.
    let link = format!("{base}?system=knife_edge&preset=paper&t_end=10&methods=leapfrog");
    client.goto(&link).await.map_err(|e| format!("cannot load {link}: {e}"))?;
    let step = client
        .wait()
        .at_most(Duration::from_secs(20))
        .for_element(Locator::Css("#step"))
        .await
        .map_err(|e| format!("no Step field: {e}"))?;
    // Brought into view at the bottom of a short window, the field stays clear of the Run bar.
    client.set_window_size(1200, 640).await.map_err(|e| e.to_string())?;
    let focus = js(client, STICKY).await;
    client.set_window_size(1440, 1500).await.map_err(|e| e.to_string())?;
    let focus = focus?;
    assert_eq!(focus["covered"], json!(false), "the Run bar covers the Step field: {focus}");
    step.clear().await.map_err(|e| e.to_string())?;
    click(client, "#run").await?;
    let (state, text) = wait_for_status(client).await?;
    assert_eq!(state, "done", "{text}");
    assert!(text.contains("the Step field is empty") && text.contains("0.314"), "{text}");
    let placeholder = js(client, "return document.getElementById('step').placeholder;").await?;
    assert_eq!(placeholder, "0.314159 (preset)");
    console_clean(driver, client, "long axis, cancel, empty step").await?;
    println!("plot export: PNG and SVG, ticks {ticks:?}, partial run {row}, focus {focus}");
    Ok(())
}

/// Keeps an exported file beside the screenshots, under `<target>/screenshots/`.
pub(crate) fn save(name: &str, bytes: &Value) {
    let bytes: Vec<u8> = bytes
        .as_array()
        .map_or(vec![], |b| b.iter().filter_map(|x| u8::try_from(x.as_u64()?).ok()).collect());
    let dir =
        Path::new(env!("CARGO_TARGET_TMPDIR")).parent().expect("target dir").join("screenshots");
    let _ = std::fs::create_dir_all(&dir).and_then(|()| std::fs::write(dir.join(name), bytes));
}

/// Downloads go through a blob URL and an anchor with `download`: record the anchor's name
/// and the blob's first bytes instead of saving it (the page's CSP forbids fetching blob URLs).
pub(crate) const CATCH_DOWNLOADS: &str = r#"
window.__downloads = [];
const blobs = new Map();
const createObjectURL = URL.createObjectURL;
URL.createObjectURL = (blob) => {
  const url = createObjectURL(blob);
  blobs.set(url, blob);
  return url;
};
HTMLAnchorElement.prototype.click = function () {
  const d = { name: this.download, size: null, head: null, text: null, paths: 0, rects: 0, bytes: null };
  window.__downloads.push(d);
  blobs.get(this.href).arrayBuffer().then((b) => {
    d.head = [...new Uint8Array(b.slice(0, 4))];
    d.bytes = [...new Uint8Array(b)];
    if (d.name.endsWith('.svg')) {
      const text = new TextDecoder().decode(b);
      d.text = text.slice(0, 200);
      d.paths = (text.match(/<path/g) ?? []).length;
      d.rects = (text.match(/<rect/g) ?? []).length;
      d.letters = (text.match(/>[EBD]<\/text>/g) ?? []).length;
      d.decades = (text.match(/>10[⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+<\/text>/g) ?? []).length;
    }
    d.size = b.byteLength;
  });
};
"#;

/// Both downloads, once their bytes are read, PNG first.
pub(crate) const DOWNLOADS: &str = "const d = window.__downloads; return d.length === 2 && d.every((x) => x.size !== null) ? d.map(({ bytes, ...x }) => x).sort((a, b) => a.name.localeCompare(b.name)) : null;";

/// The energy card's scene line and its canvas's text alternative.
const CARD: &str = r#"
const card = document.querySelector('.plot-card[data-integral="energy"]');
return { scene: card.querySelector('.plot-scene')?.textContent ?? '', alt: card.querySelector('canvas')?.getAttribute('aria-label') ?? '' };
"#;

/// The energy plot's y-range and its note on runs left out of it.
const CLIP: &str = r#"
const card = document.querySelector('.plot-card[data-integral="energy"]');
const note = card.querySelector('.clip-note');
return { max: card.uplot.scales.y.max, note: note.hidden ? null : note.textContent, full: card.uplot.data.slice(1, 3).map((d) => Math.max(...d.filter((v) => v != null))) };
"#;

/// Puts the Step field just below the window's bottom edge, brings it into view as a field
/// error does (the nearest edge) with the focus, and says whether the sticky Run/Cancel bar
/// then covers it.
const STICKY: &str = r#"
const step = document.getElementById('step');
window.scrollTo(0, Math.max(0, step.getBoundingClientRect().top + scrollY - innerHeight + 5));
step.closest('.field').scrollIntoView({ block: 'nearest' });
step.focus({ preventScroll: true });
const s = step.getBoundingClientRect();
const a = document.querySelector('#form .actions').getBoundingClientRect();
return { step: [s.top, s.bottom], bar: [a.top, a.bottom], covered: s.bottom > a.top && s.top < a.bottom };
"#;

/// Once some progress arrived: the time axis's tick labels and the status line.
const LIVE: &str = r#"
const u = document.querySelector('.plot-card')?.uplot;
if (!u || !(document.getElementById('progress').value > 0)) return null;
return { ticks: u.axes[0]._values ?? [], status: document.getElementById('status').textContent };
"#;
