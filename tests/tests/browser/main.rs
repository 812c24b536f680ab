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
//!    DLA^0.4's latitude on the rotating pendulum CVT stops at t ≈ 7·10⁴ (the passenger at
//!    rest) and the page says so under the plot and in the runs table (`gap.png`);
//! 3. a long run shows curves before it ends, and Cancel stops it;
//! 4. editing the form rewrites the URL, and that URL restores the form;
//! 5. a link with a bad parameter and `run=1` fills the form, runs by itself, and shows the
//!    server's error next to the field its `path` names;
//! 6. "Custom system" opens the editor filled with the knife edge's formulas; an edited U runs
//!    (`custom-system.png`), a stray parenthesis in a constraint entry is shown under that
//!    entry (`custom-bad-formula.png`), the successful run's link brings it all back, the
//!    Work–precision tab measures it and names it, and "Start from" refills the editor (the
//!    rolling disk's two constraints, the pendulum CVT's latitude); the Chaplygin sleigh,
//!    picked in Explore, offers only the methods and integrals it has (DD-AVF left out), says
//!    why it is outside the paper's class, and runs (`sleigh.png`); the chaotic oscillator's
//!    n = 2 preset fills five coordinates and runs; the editor in the general form, started
//!    from the sleigh with an invariant added, runs (`custom-general.png`), an entry of M
//!    naming a coordinate and an invariant that does not parse are shown at their inputs, its
//!    link brings the general form back, and it fits 400 px (`custom-general-400.png`);
//! 7. `?view=paper` draws every panel of the paper's four figures (five curves with data
//!    each) with a verdict per method under it (`paper.png`, `paper-cvt.png`);
//! 8. `?view=scorecard` shows a verdict cell for every method × default scene (the paper's six,
//!    the literature's seven) × integral, DD-AVF "n/a" outside the paper's class with its
//!    reason, and the property marks, the fibration "not defined" outside the class
//!    (`scorecard.png`); clicking a cell runs that scene in the main view, without the methods
//!    that do not apply;
//! 9. `?view=work-precision` with a knife-edge scene draws both log–log plots (error against
//!    run time, error against h) with a line per method, and each method's fitted order in
//!    the legend and the table, LF and DLA^{0,1} near 2, DLA^0.4 near 1
//!    (`work-precision.png`); the tab takes the Explore form's scene and methods; a run that
//!    fails is listed as failed with its message, not drawn (`work-precision-failed.png`);
//! 10. `?view=map`: the "where DLA^α stops being reversible enough" preset (21 × 11 cells on
//!     the rotating CVT) fills the heat map, every cell drawn with a verdict or a status, the
//!     URL holding the map (`map.png`); hovering a cell shows its tooltip with its axis values,
//!     method and numbers (`map-tooltip.png`); clicking it runs that cell in Explore, its one
//!     curve drawn (`map-opened.png`); a one-axis link with `run=1` draws a cell strip and a
//!     line per method (`map-one-axis.png`), and so does one on the Chaplygin sleigh, whose
//!     preset the map offers (`map-sleigh.png`); an axis path the server rejects is marked at
//!     its field (`map-bad-axis.png`).
//! 11. at 400, 800 and 1400 px the rotating, perturbed experiment (one click) brings its status
//!     line and first plot into view, scrolling only when they were off screen
//!     (`width-400.png`, …); no view scrolls sideways at 360, 400, 800 or 1400 px; every
//!     legend entry and runs-table row shows its run's verdict, with the numbers on hover; a
//!     second run with another method list draws LF and DD in the same colours and markers,
//!     a composition in its base's colour, dashed;
//! 12. a plot's PNG and SVG export downloads `nhlab-knife_edge-paper-energy.png` / `.svg`
//!     (a PNG's bytes, an SVG path per curve); the card names its scene and its canvas has a
//!     text alternative; a diverged run is clipped off the y-range with a note saying so; a
//!     3·10⁶ time axis has short tick labels, a long run shows its elapsed time, and Cancel
//!     keeps the steps and time of the run; an empty Step field runs and reports the preset's
//!     step, and the sticky Run bar does not cover it;
//! 13. Work–precision names its scene on every plot card and takes the DiffEqDevTools
//!     orientation from the URL; 0 step sizes is refused at the "Step sizes" field, the
//!     previous plots marked stale (`work-precision-zero-steps.png`); a list of steps runs
//!     those steps, a 0 in it refused at its field; Cancel stops a long request.
//! 14. the Trajectory and Section panels draw the rotating, perturbed CVT's phase portrait
//!     and Poincaré section (x1, x2) with a series per method, a legend in the error plot's
//!     colours and markers, and the section exports as PNG and SVG (`dynamics.png`);
//! 15. the page's second pass at 400 and 1400 px (second_pass.rs): a refused field in view
//!     and focused, stale results, the skip link, the Scorecard's keyboard grid, compositions
//!     offered as configured, and the status's time left being the slowest run's.
//!
//! Chromium and chromedriver are required, not optional: without them the test fails and
//! says how to install them. `NHLAB_CHROMIUM` / `NHLAB_CHROMEDRIVER` override their paths.

mod custom;
mod driver;
mod dynamics;
mod explore;
mod export;
mod general;
mod maps;
mod page;
mod precision;
mod second_pass;
mod views;
mod widths;

use custom::custom_system;
use driver::{Driver, required};
use dynamics::dynamics_panels;
use explore::{
    bad_parameter_link, cancel, composition, failed_runs, form_in_the_url, gap_message, knife_edge,
};
use export::plot_export;
use fantoccini::Client;
use general::{general_custom, sleigh_in_explore};
use maps::{map_opens_a_file, map_view};
use nhlab_tests::TestServer;
use precision::work_precision_controls;
use second_pass::second_pass;
use std::time::Duration;
use views::{paper_view, scorecard_view, work_precision_view};
use widths::window_widths;

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
    gap_message(client, driver, base).await?;
    cancel(client, driver, base).await?;
    form_in_the_url(client, driver, base).await?;
    bad_parameter_link(client, base).await?;
    composition(client, driver, base).await?;
    custom_system(client, driver, base).await?;
    sleigh_in_explore(client, driver, base).await?;
    general_custom(client, driver, base).await?;
    paper_view(client, driver, base).await?;
    scorecard_view(client, driver, base).await?;
    work_precision_view(client, driver, base).await?;
    map_view(client, driver, base).await?;
    map_opens_a_file(client, base).await?;
    window_widths(client, driver, base).await?;
    plot_export(client, driver, base).await?;
    work_precision_controls(client, driver, base).await?;
    second_pass(client, driver, base).await?;
    dynamics_panels(client, driver, base).await
}
