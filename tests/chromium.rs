//! relief's shaders in a real browser's own compilers: headless Chromium (Debian's
//! `chromium`, SwiftShader for WebGPU and WebGL2) through the harness in `tests/browser/`.
//! Tint (WebGPU) compiles every module `relief gen --all` writes and every WGSL library of
//! `relief gen --all --library`; ANGLE (WebGL2) compiles every GLSL ES library. One Chromium
//! launch per test.

#[path = "common/browser.rs"]
mod browser;

use std::path::Path;
use std::time::Duration;

use browser::{run_page, Page};
use relief::Pipeline;

/// The browser offers what the other tests rely on: a WebGPU adapter (SwiftShader) and a
/// WebGL2 context (ANGLE on SwiftShader).
#[test]
fn chromium_has_webgpu_and_webgl2() {
    let r = run_page(&Page::new("pages/caps.html"));
    assert!(r["webgpu"].is_object(), "no WebGPU adapter in Chromium: {r}");
    assert_eq!(r["webgpu"]["device"], true, "{r}");
    let version = r["webgl2"]["version"].as_str().unwrap_or_default();
    assert!(version.starts_with("WebGL 2.0"), "no WebGL2 in Chromium: {r}");
}

fn write(dir: &Path, name: &str, text: &str) {
    std::fs::write(dir.join(name), text).unwrap_or_else(|e| panic!("{name}: {e}"));
}

/// Compiles what `manifest` lists in the folder with Chromium's compilers (pages/compile.html)
/// and fails with every error message.
fn compile_in_chromium(dir: &Path, manifest: serde_json::Value) -> serde_json::Value {
    write(dir, "manifest.json", &manifest.to_string());
    let mut page = Page::new("pages/compile.html");
    page.mounts.push(("shaders", dir));
    page.timeout = Duration::from_secs(300);
    run_page(&page)
}

fn temp_dir(what: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("relief-chromium-{what}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Every module of `relief gen --all` compiles in Tint (`createShaderModule` with no error
/// in `getCompilationInfo`); every tenth also builds its render and probe pipelines.
#[test]
fn tint_compiles_every_module_of_gen_all() {
    let dir = temp_dir("modules");
    let mut items = Vec::new();
    for (i, p) in Pipeline::all_defaults().iter().enumerate() {
        let out = relief::dsl::emit::emit(p).unwrap_or_else(|e| panic!("{p}: {e}"));
        let file = format!("{}.wgsl", p.file_stem());
        write(&dir, &file, &out.wgsl);
        let entries = if i % 10 == 0 {
            serde_json::json!([["render", "vs_main", "fs_main"], ["compute", "probe"]])
        } else {
            serde_json::json!([])
        };
        items.push(serde_json::json!({ "file": file, "entries": entries }));
    }
    let n = items.len();
    let r = compile_in_chromium(&dir, serde_json::json!({ "wgsl": items }));
    assert_eq!(r["wgsl"].as_u64(), Some(n as u64), "{r}");
    assert_eq!(r["pipelines"].as_u64(), Some(2 * n.div_ceil(10) as u64), "{r}");
    std::fs::remove_dir_all(&dir).ok();
}
