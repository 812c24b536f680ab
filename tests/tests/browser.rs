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
//!    server's error next to the field its `path` names.
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
    bad_parameter_link(client, base).await
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
