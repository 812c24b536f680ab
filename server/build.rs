//! Builds the page (`web/`) so the binary can embed `web/dist/`.
//!
//! When `web/package.json` exists: `npm ci` (only when `web/node_modules` is missing or older
//! than `package-lock.json`), then `npm run build`, which writes `web/dist/`. A failing npm
//! fails the build with its output. Several cargo invocations (different target dirs) may
//! build at once, so the npm steps run under a lock on `web/package.json`.
//!
//! `NHLAB_SKIP_WEB_BUILD=1` skips npm and embeds whatever `web/dist/` holds (a Docker stage
//! that built the page with node already). Without `web/package.json` (the page not written
//! yet) a placeholder `web/dist/index.html` is written so the server still compiles.

use std::fs;
use std::path::Path;
use std::process::Command;

fn main() {
    let manifest = std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR");
    let web = Path::new(&manifest).join("../web");
    let dist = web.join("dist");
    println!("cargo:rerun-if-env-changed=NHLAB_SKIP_WEB_BUILD");
    println!("cargo:rerun-if-changed={}", web.join("package.json").display());

    let package = web.join("package.json");
    if !package.exists() {
        placeholder(&dist);
        return;
    }
    // Everything the page is built from: every top-level entry of web/ (src/, package.json,
    // package-lock.json, the build script, …) except installed packages and the output.
    for entry in fs::read_dir(&web).expect("web/ is readable").flatten() {
        let name = entry.file_name();
        if !matches!(name.to_str(), Some("node_modules" | "dist" | "test")) {
            println!("cargo:rerun-if-changed={}", entry.path().display());
        }
    }
    if std::env::var_os("NHLAB_SKIP_WEB_BUILD").is_some_and(|v| v != "0" && !v.is_empty()) {
        if !dist.join("index.html").exists() {
            fail("NHLAB_SKIP_WEB_BUILD is set but web/dist/index.html does not exist");
        }
        return;
    }

    let lock = fs::File::open(&package).expect("web/package.json is readable");
    lock.lock().expect("lock web/package.json");
    if needs_install(&web) {
        npm(&web, &["ci", "--no-audit", "--no-fund"]);
    }
    // Source maps for a debug build only: a release binary does not carry them.
    let debug = std::env::var("PROFILE").is_ok_and(|p| p == "debug");
    npm_with(&web, &["run", "build"], &[("NHLAB_WEB_SOURCEMAP", if debug { "1" } else { "0" })]);
    drop(lock);
    if !dist.join("index.html").exists() {
        fail("`npm run build` in web/ did not produce web/dist/index.html");
    }
}

fn needs_install(web: &Path) -> bool {
    let modified = |p: &Path| fs::metadata(p).and_then(|m| m.modified()).ok();
    match (modified(&web.join("node_modules")), modified(&web.join("package-lock.json"))) {
        (None, _) => true,
        (Some(modules), Some(lock)) => lock > modules,
        (Some(_), None) => false,
    }
}

fn npm(web: &Path, args: &[&str]) {
    npm_with(web, args, &[]);
}

fn npm_with(web: &Path, args: &[&str], vars: &[(&str, &str)]) {
    let shown = format!("npm {}", args.join(" "));
    let output =
        Command::new("npm").args(args).envs(vars.iter().copied()).current_dir(web).output();
    match output {
        Err(e) => fail(&format!(
            "could not run `{shown}` in web/ ({e}); nhlab embeds the page, so building it \
             needs Node.js and npm (e.g. `apt-get install nodejs npm`)"
        )),
        Ok(out) if !out.status.success() => fail(&format!(
            "`{shown}` in web/ failed ({}):\n{}\n{}",
            out.status,
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        )),
        Ok(_) => {}
    }
}

fn placeholder(dist: &Path) {
    let index = dist.join("index.html");
    if index.exists() {
        return;
    }
    fs::create_dir_all(dist).expect("create web/dist");
    fs::write(
        index,
        "<!doctype html><meta charset=utf-8><title>nhlab</title>\
         <p>nhlab: the page is not built (web/package.json is missing). The API works: \
         <a href=/systems>/systems</a>, <a href=/openapi.json>/openapi.json</a>.</p>\n",
    )
    .expect("write web/dist/index.html");
}

fn fail(message: &str) -> ! {
    eprintln!("error: {message}");
    panic!("building the page failed: {message}");
}
