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

use crate::common::{browser, frames};

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use browser::{run_page, Page};
use relief::runtime::gpu::{self, Gpu, Program, SceneTextures};
use relief::runtime::{scene_from_arg, Scene};
use relief::Pipeline;
use serde_json::json;

/// The frame's side, pixels.
const SIZE: u32 = 128;

/// The pipelines and scenes (as `relief export --scene` takes them): a linear search with
/// binary refinement and a soft shadow on a real height map, a safe cone method (its cell
/// cone map read with nearest filtering) on a rough procedural surface, and the max-mip
/// traversal (its chain read at every level) on one-texel walls and pillars.
const CASES: [(&str, &str); 3] = [
    ("linear(32)+binary(5)+shadow=soft(16)", "scene:lion"),
    ("csm(64)", "scene:rock_bump"),
    ("maxmip(96)", "scene:shapes"),
];

/// The `relief` command line of this build: `target/PROFILE/relief`, beside the test
/// binary's `deps/`. The facade cannot name another package's binary, so it is looked up
/// there; a missing or stale one is a failure that says how to build it.
pub(crate) fn relief_exe() -> PathBuf {
    let me = std::env::current_exe().unwrap();
    let exe = me.parent().and_then(Path::parent).unwrap().join("relief");
    let built = |p: &Path| p.metadata().and_then(|m| m.modified()).ok();
    let Some(exe_time) = built(&exe) else {
        panic!("{} is missing: build it with `cargo build --release -p relief-runtime`", exe.display())
    };
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let newest = ["relief-runtime/src", "relief-dsl/src"]
        .iter()
        .flat_map(|d| walk(&root.join(d)))
        .filter_map(|f| built(&f))
        .max()
        .unwrap();
    assert!(
        exe_time >= newest,
        "{} is older than the sources: rebuild it with `cargo build --release -p relief-runtime`",
        exe.display()
    );
    exe
}

/// The files under `dir`, recursively.
fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let p = e.path();
        if p.is_dir() {
            out.extend(walk(&p));
        } else {
            out.push(p);
        }
    }
    out
}

pub(crate) fn relief_render(g: &Gpu, p: &Pipeline, scene: &Scene) -> Vec<u8> {
    let program = Program::new(p).unwrap();
    let mut tex = SceneTextures::new(g, scene);
    tex.add_maps(g, scene, &p.required_maps()).unwrap();
    gpu::render(g, &program, scene, &tex, SIZE, 0, 1).unwrap().rgba
}

/// The page's pictures come back as hex (RGBA8, top row first).
pub(crate) fn from_hex(s: &str) -> Vec<u8> {
    assert!(s.len().is_multiple_of(2) && s.is_ascii(), "a picture's hex has an odd length or stray characters");
    (0..s.len()).step_by(2).map(|i| u8::from_str_radix(&s[i..i + 2], 16).expect("a picture's hex")).collect()
}

#[test]
fn babylon_draws_relief_renders_frame_from_an_export_bundle() {
    let exe = relief_exe();
    let g = Gpu::new().unwrap();
    let dir = std::env::temp_dir().join(format!("relief-babylon-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    let mut cases = Vec::new();
    let mut references = Vec::new();
    for (i, (pipe, arg)) in CASES.iter().enumerate() {
        let sub = format!("case{i}");
        let out = Command::new(&exe)
            .args(["export", pipe, "--scene", arg, "--target", "glsl-es", "--out"])
            .arg(dir.join(&sub))
            .env("LP_NUM_THREADS", "1")
            .env("NODEVICE_SELECT", "1")
            .output()
            .unwrap();
        assert!(out.status.success(), "relief export {pipe}: {}", String::from_utf8_lossy(&out.stderr));
        let p: Pipeline = pipe.parse().unwrap();
        let scene = scene_from_arg(arg).unwrap();
        let eye = scene.camera.camera_position();
        // The camera only: the page takes everything else from the bundle.
        cases.push(json!({ "dir": sub, "view_proj": scene.camera.view_proj(1.0).to_cols_array(), "eye": [eye.x, eye.y, eye.z] }));
        references.push(relief_render(&g, &p, &scene));
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
        assert_eq!(rgba.len(), (SIZE * SIZE * 4) as usize, "{pipe}: picture size");
        let (mad, share) = frames::frame_difference(&rgba, &references[i]);
        println!(
            "{pipe} on {arg}, Babylon.js {} (WebGL2): mean |difference| {mad:.4} of 255, {:.3} % of pixels off by more than 8",
            r["babylon"],
            share * 100.0
        );
        let lit = rgba.chunks(4).filter(|px| px[0] > 20 || px[1] > 20 || px[2] > 20).count();
        if mad > 1.0 || share > 0.01 || lit <= (SIZE * SIZE / 3) as usize || keep {
            for (what, px) in [("babylon", &rgba), ("relief", &references[i])] {
                relief::runtime::io::png::write_rgba8(&dir.join(format!("case{i}_{what}.png")), SIZE, SIZE, px.clone())
                    .unwrap();
            }
        }
        if mad > 1.0 || share > 0.01 {
            failures.push(format!(
                "{pipe} on {arg}: mean |difference| {mad:.4}, {:.3} % off by > 8 (pictures in {})",
                share * 100.0,
                dir.display()
            ));
        }
        assert!(lit > (SIZE * SIZE / 3) as usize, "{pipe}: only {lit} lit pixels (pictures in {})", dir.display());
    }
    assert!(failures.is_empty(), "Babylon.js's pictures differ from relief render's:\n{}", failures.join("\n"));
    if !keep {
        std::fs::remove_dir_all(&dir).ok();
    }
}
