//! Runs a page of `tests/browser/` in headless Chromium through `tests/browser/run.mjs`
//! (SwiftShader's WebGPU and WebGL2) and returns what the page reported
//! (`use crate::common::browser;`).

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// `tests/browser/`, the harness's folder.
pub fn harness_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/browser")
}

/// What to open.
pub struct Page<'a> {
    /// The page's path under `tests/browser/` (`pages/caps.html`).
    pub page: &'a str,
    /// Folders served beside the harness: `(prefix, dir)` is `dir` at `/prefix/`.
    pub mounts: Vec<(&'a str, &'a Path)>,
    /// Query parameters of the page's URL.
    pub query: Vec<(&'a str, String)>,
    /// How long the page may take to set `window.__done`.
    pub timeout: Duration,
    /// The viewport, in CSS pixels (= device pixels).
    pub size: (u32, u32),
}

impl<'a> Page<'a> {
    /// `page` with no mounts or query, a 60 s timeout and a 512×512 viewport.
    pub fn new(page: &'a str) -> Self {
        Page { page, mounts: Vec::new(), query: Vec::new(), timeout: Duration::from_secs(60), size: (512, 512) }
    }
}

/// Fails, naming what to install, when node, Chromium or the harness's npm packages are missing.
fn check_installed() {
    let node = Command::new("node").arg("--version").output().is_ok_and(|o| o.status.success());
    assert!(node, "`node` is not installed: install the Debian package nodejs (and npm); .ci/run does");
    assert!(
        Path::new("/usr/bin/chromium").exists(),
        "/usr/bin/chromium is missing: install the Debian package chromium (.ci/run does)"
    );
    assert!(
        harness_dir().join("node_modules/puppeteer-core").is_dir(),
        "the browser harness's npm packages are missing: run `npm ci --prefix tests/browser` (.ci/run does)"
    );
}

/// Opens the page and returns its `window.__result`; fails with the page's console and
/// errors when it threw, logged an error, timed out, or reported `ok: false`.
pub fn run_page(p: &Page<'_>) -> serde_json::Value {
    check_installed();
    let dir = harness_dir();
    let mut cmd = Command::new("node");
    cmd.arg(dir.join("run.mjs"))
        .arg("--page")
        .arg(p.page)
        .arg("--timeout-ms")
        .arg(p.timeout.as_millis().to_string())
        .arg("--size")
        .arg(format!("{}x{}", p.size.0, p.size.1));
    for (prefix, d) in &p.mounts {
        cmd.arg("--mount").arg(format!("{prefix}={}", d.display()));
    }
    for (k, v) in &p.query {
        cmd.arg("--query").arg(format!("{k}={v}"));
    }
    let mut child = cmd
        .current_dir(&dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("cannot start node for {}: {e}", p.page));
    let mut stdout = child.stdout.take().unwrap();
    let mut stderr = child.stderr.take().unwrap();
    let out = std::thread::spawn(move || {
        let mut s = String::new();
        stdout.read_to_string(&mut s).ok();
        s
    });
    let err = std::thread::spawn(move || {
        let mut s = String::new();
        stderr.read_to_string(&mut s).ok();
        s
    });
    // The driver gives up on the page after `timeout`; Chromium's start and close get a minute more.
    let deadline = Instant::now() + p.timeout + Duration::from_secs(60);
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break Some(s);
        }
        if Instant::now() > deadline {
            child.kill().ok();
            child.wait().ok();
            break None;
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let stdout = out.join().unwrap_or_default();
    let stderr = err.join().unwrap_or_default();
    let Some(status) = status else {
        panic!(
            "{}: the browser harness did not finish within {:?}\n{stdout}\n{stderr}",
            p.page,
            p.timeout + Duration::from_secs(60)
        );
    };
    let report: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap_or_else(|e| {
        panic!("{}: the harness printed no JSON ({e}; exit {status}):\n{stdout}\n{stderr}", p.page)
    });
    if !status.success() || report["ok"] != serde_json::Value::Bool(true) {
        let console: Vec<String> = report["console"]
            .as_array()
            .map(|a| {
                a.iter()
                    .map(|m| format!("  [{}] {}", m["type"].as_str().unwrap_or(""), m["text"].as_str().unwrap_or("")))
                    .collect()
            })
            .unwrap_or_default();
        let errors: Vec<String> = report["errors"]
            .as_array()
            .map(|a| a.iter().map(|e| format!("  {}", e.as_str().unwrap_or(""))).collect())
            .unwrap_or_default();
        let mut result = report["result"].to_string();
        if result.len() > 4000 {
            result.truncate(4000);
            result.push('…');
        }
        panic!(
            "{} failed in Chromium (exit {status}):\nconsole:\n{}\nerrors:\n{}\nresult: {result}\n{stderr}",
            p.page,
            console.join("\n"),
            errors.join("\n")
        );
    }
    report["result"].clone()
}
