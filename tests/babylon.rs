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
//! more than 8 in a channel. The clamp-edge case is drawn once more with every texture's
//! address mode forced to repeat in the page, and that picture must miss the bar.
//!
//! The page reads the `.ktx2` files with a documented 30-line reader, not with Babylon's
//! own KTX2 loader; the same run checks why (`docs/libraries.md`): it loads one file of each
//! format the bundles hold (and the 16-bit and four-channel forms `relief maps` writes)
//! with `new BABYLON.Texture(url)`, Babylon's loader, its decoder module served from the test's
//! folder through `KhronosTextureContainer2.URLConfig` (a stand-in that hands every level
//! through as it is, `tests/browser/pages/ktx2-passthrough.js`: Babylon's own decoder is on
//! Babylon's CDN only). Babylon makes the 8-bit files texel for texel, and refuses every
//! float one (a WebGL error as it uploads it).

use crate::common::browser;
use crate::common::exe::{export, relief_exe};
use crate::common::frames::{
    assert_clamp_bundle, engine_picture, from_hex, relief_render, CLAMP_CASE, ENGINE_CASES as CASES,
    ENGINE_SIZE as SIZE,
};

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
        if i == CLAMP_CASE {
            assert_clamp_bundle(&dir.join(&sub));
        }
        let p: Pipeline = pipe.parse().unwrap();
        let scene = scene_from_arg(arg).unwrap();
        let eye = scene.camera.camera_position();
        // The camera only: the page takes everything else from the bundle.
        cases.push(json!({ "dir": sub, "view_proj": scene.camera.view_proj(1.0).to_cols_array(), "eye": [eye.x, eye.y, eye.z] }));
        references.push(relief_render(&g, &p, &scene, SIZE));
    }
    // The clamp-edge case once more, its textures forced to repeat in the page.
    let mut forced = cases[CLAMP_CASE].clone();
    forced["address_override"] = "repeat".into();
    cases.push(forced);
    let probe = probe_files(&dir);
    std::fs::write(dir.join("manifest.json"), json!({ "size": SIZE, "cases": cases, "ktx2_probe": probe }).to_string())
        .unwrap();
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
    let pic = &r["cases"][CASES.len()];
    let rgba = from_hex(pic["rgba"].as_str().unwrap_or_else(|| panic!("the forced-repeat case: no picture: {pic}")));
    let (pipe, arg) = CASES[CLAMP_CASE];
    let what = format!("{pipe} on {arg} with every address mode forced to repeat, Babylon.js (WebGL2)");
    let forced = engine_picture("Babylon.js", &what, &rgba, &references[CLAMP_CASE], &dir, "forced_repeat", keep);
    assert!(forced.is_some(), "{what}: within the bar, so the clamp case does not show the address mode is taken");
    assert!(failures.is_empty(), "Babylon.js's pictures differ from relief render's:\n{}", failures.join("\n"));
    check_ktx2_probe(&r);
    if !keep {
        std::fs::remove_dir_all(&dir).ok();
    }
}

/// One `.ktx2` file of each format under `dir` (the bundles' files, by `relief.json`), and
/// the 16-bit and four-channel forms, which no bundle here holds, written by `relief maps`
/// into `dir/probe/`: the files the page loads with Babylon's own KTX2 loader, relative to
/// `dir`.
fn probe_files(dir: &std::path::Path) -> Vec<String> {
    let mut by_format: Vec<(String, String)> = Vec::new();
    let mut add = |format: &str, file: String| {
        if !by_format.iter().any(|(f, _)| f == format) {
            by_format.push((format.to_string(), file));
        }
    };
    for i in 0..CASES.len() {
        let sub = format!("case{i}");
        let json: serde_json::Value =
            serde_json::from_slice(&std::fs::read(dir.join(&sub).join("relief.json")).unwrap()).unwrap();
        for b in json["bindings"].as_array().unwrap() {
            if let (Some(f), Some(file)) = (b["format"].as_str(), b["file"].as_str()) {
                add(f, format!("{sub}/{file}"));
            }
        }
        for t in json["textures"].as_object().unwrap().values() {
            add(t["format"].as_str().unwrap(), format!("{sub}/{}", t["file"].as_str().unwrap()));
        }
    }
    std::fs::create_dir_all(dir.join("probe")).unwrap();
    for (kind, encoding, format) in PROBE_MAPS {
        let name = format!("probe/{kind}_{encoding}.ktx2");
        let out = std::process::Command::new(relief_exe())
            .args(["maps", "scene:rocks", "--kind", kind, "--encoding", encoding, "--out"])
            .arg(dir.join(&name))
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "relief maps --kind {kind} --encoding {encoding}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        add(format, name);
    }
    for f in
        ["R32Float", "Rg32Float", "Rgba8Unorm", "Rgba8UnormSrgb", "R16Float", "Rg16Float", "Rgba32Float", "Rgba16Float"]
    {
        assert!(by_format.iter().any(|(g, _)| g == f), "no file of format {f} to probe: {by_format:?}");
    }
    by_format.into_iter().map(|(_, file)| file).collect()
}

/// The maps `probe_files` writes with `relief maps scene:rocks` for the formats no bundle
/// here holds: (kind, encoding, the format it is written in).
const PROBE_MAPS: [(&str, &str, &str); 4] = [
    ("max_mip", "f16", "R16Float"),
    ("cell_cone", "f16", "Rg16Float"),
    ("quad_cone", "f32", "Rgba32Float"),
    ("quad_cone", "f16", "Rgba16Float"),
];

/// What Babylon's own KTX2 loader made of each probed file: an 8-bit file texel for texel,
/// with no error; a float file (32- or 16-bit) refused — an error from Babylon or a WebGL
/// error as it made the texture. And the decoder interface of this Babylon names no float
/// source format (its `SourceTextureFormat`: ETC1S, UASTC 4×4 and uncompressed RGBA8).
fn check_ktx2_probe(r: &serde_json::Value) {
    let names: Vec<&str> = r["ktx2_source_formats"].as_array().unwrap().iter().map(|v| v.as_str().unwrap()).collect();
    assert_eq!(names, ["ETC1S", "UASTC4x4", "RGBA32"], "Babylon's KTX2 source formats");
    let probe = r["ktx2_probe"].as_array().unwrap();
    assert_eq!(probe.len(), 8, "one probe per format: {probe:?}");
    for p in probe {
        let (file, vk) = (p["file"].as_str().unwrap(), p["vk"].as_str().unwrap());
        let gl_errors = p["gl_errors"].as_array().map_or(0, |a| a.len());
        println!("Babylon's KTX2 loader, {file} ({vk}): {p}");
        if vk.starts_with("R8G8B8A8") {
            assert!(
                p["error"].is_null() && gl_errors == 0,
                "{file} ({vk}): Babylon's loader failed on an 8-bit file: {p}"
            );
            assert_eq!(p["texels_equal"], true, "{file} ({vk}): Babylon's texture is not the file's level 0: {p}");
        } else {
            assert!(!p["error"].is_null() || gl_errors > 0, "{file} ({vk}): Babylon's loader took a float file: {p}");
        }
    }
}
