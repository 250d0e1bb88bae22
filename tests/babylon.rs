//! Babylon.js as a client of `relief export` (issue 39): for each pipeline the test runs
//! `relief export PIPELINE --scene MAP --target glsl-es --out DIR`, serves the folder, and
//! headless Chromium (SwiftShader's WebGL2) draws the relief quad with Babylon.js
//! (`tests/browser/pages/babylon.html`, npm `babylonjs` pinned by
//! `tests/browser/package-lock.json`): the page reads `relief.json`, the library and the
//! `.ktx2` files it names, as a Babylon user would, and writes the library into a
//! `ShaderMaterial`. The harness hands the page only the camera (relief's `view_proj` and
//! eye); no texture goes to the page but through the bundle's files.
//!
//! Each picture is compared with `relief render`'s frame for the same scene, camera and
//! pipeline, by the bar of `tests/integrate.rs` and `tests/threejs.rs`: a mean absolute
//! difference of at most 1 of 255 per channel and at most 1 % of the pixels differing by
//! more than 8 in a channel.

use crate::common::browser;
use crate::common::exe::export;
use crate::common::frames::{engine_picture, from_hex, relief_render, ENGINE_CASES as CASES, ENGINE_SIZE as SIZE};

use std::time::Duration;

use browser::{run_page, Page};
use relief::runtime::gpu::Gpu;
use relief::runtime::scene_from_arg;
use relief::Pipeline;
use serde_json::json;

#[test]
fn babylon_draws_relief_renders_frame_from_an_export_bundle() {
    let g = Gpu::new().unwrap();
    let dir = std::env::temp_dir().join(format!("relief-babylon-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    let mut cases = Vec::new();
    let mut references = Vec::new();
    for (i, (pipe, arg)) in CASES.iter().enumerate() {
        let sub = format!("case{i}");
        export(pipe, arg, "glsl-es", &dir.join(&sub));
        let p: Pipeline = pipe.parse().unwrap();
        let scene = scene_from_arg(arg).unwrap();
        let eye = scene.camera.camera_position();
        // The camera only: the page takes everything else from the bundle.
        cases.push(json!({ "dir": sub, "view_proj": scene.camera.view_proj(1.0).to_cols_array(), "eye": [eye.x, eye.y, eye.z] }));
        references.push(relief_render(&g, &p, &scene, SIZE));
    }
    std::fs::write(dir.join("manifest.json"), json!({ "size": SIZE, "cases": cases }).to_string()).unwrap();
    let mut page = Page::new("pages/babylon.html");
    page.mounts.push(("data", &dir));
    page.size = (SIZE, SIZE);
    page.timeout = Duration::from_secs(120);
    let r = run_page(&page);
    let keep = std::env::var_os("RELIEF_BABYLON_KEEP").is_some();
    let mut failures = Vec::new();
    for (i, (pipe, arg)) in CASES.iter().enumerate() {
        let pic = &r["cases"][i];
        let rgba = from_hex(pic["rgba"].as_str().unwrap_or_else(|| panic!("{pipe}: no picture: {pic}")));
        let what = format!("{pipe} on {arg}, Babylon.js {} (WebGL2)", r["babylon"]);
        failures.extend(engine_picture("Babylon.js", &what, &rgba, &references[i], &dir, &format!("case{i}"), keep));
    }
    assert!(failures.is_empty(), "Babylon.js's pictures differ from relief render's:\n{}", failures.join("\n"));
    if !keep {
        std::fs::remove_dir_all(&dir).ok();
    }
}
