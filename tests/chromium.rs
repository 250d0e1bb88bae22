//! relief's shaders in a real browser's own compilers: headless Chromium (Debian's
//! `chromium`, SwiftShader for WebGPU and WebGL2) through the harness in `tests/browser/`.
//! Tint (WebGPU) compiles every module `relief gen --all` writes and every WGSL and `tsl`
//! library of `relief gen --all --library`; ANGLE (WebGL2) compiles every GLSL ES library. One Chromium
//! launch per test.

use crate::common::{browser, frames};

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

/// A user's fragment shader around a library, in WGSL or GLSL ES 3.00: trace, then shadow
/// and ao when the pipeline has them, every field of the hit used.
fn user_fragment(lib: &relief::dsl::emit::LibraryForms, es: bool) -> String {
    let hit_ty = if es { "ReliefHit hit" } else { "let hit" };
    let mut s = String::new();
    if es {
        // Uniforms, not varyings: the page links with a vertex shader that writes none.
        s += "uniform vec2 u_uv;\nuniform vec3 u_view;\nout vec4 o_color;\nvoid main() {\n";
        s += "    vec2 uv = u_uv; vec3 view = u_view;\n    float shade = 1.0;\n";
    } else {
        s += "@fragment fn user_main(@location(0) uv: vec2<f32>, @location(1) view: vec3<f32>) -> @location(0) vec4<f32> {\n";
        s += "    var shade = 1.0;\n";
    }
    s += &format!("    {hit_ty} = relief_trace(uv, normalize(view), 0.08);\n");
    if lib.has_shadow {
        s += "    shade *= relief_shadow(hit, normalize(vec3(0.3, 0.2, 0.9)), 0.08);\n";
    }
    if lib.has_ao {
        s += "    shade *= relief_ao(hit);\n";
    }
    if es {
        s += "    o_color = vec4(hit.uv, hit.height + hit.t + hit.depth_offset, shade);\n}\n";
    } else {
        s += "    return vec4(hit.uv, hit.height + hit.t + hit.depth_offset, shade);\n}\n";
    }
    s
}

/// Every library of `relief gen --all --library` (the pipelines a library can express)
/// compiles in Chromium: its WGSL form in Tint, inside a user fragment shader, its `tsl`
/// form (`NAME.tsl.wgsl`, three.js TSL's `wgslFn` include) in Tint, and its GLSL
/// ES form (where GLSL ES 3.00 can express it) in ANGLE, after `#version 300 es` as
/// three.js's `ShaderMaterial` puts it, compiled and linked.
#[test]
fn tint_and_angle_compile_every_library_of_gen_all() {
    use relief::dsl::emit::{library_forms, LibraryForm, LibraryOptions};
    let dir = temp_dir("libraries");
    let mut wgsl = Vec::new();
    let mut es = Vec::new();
    let pipelines = frames::library_pipelines();
    for p in &pipelines {
        // Whatever GLSL ES 3.00 still cannot express is refused in that form (none today).
        let with_es = relief::dsl::emit::inexpressible_in(p, LibraryForm::GlslEs).is_none();
        let wanted: &[LibraryForm] = if with_es {
            &[LibraryForm::Wgsl, LibraryForm::Tsl, LibraryForm::GlslEs]
        } else {
            &[LibraryForm::Wgsl, LibraryForm::Tsl]
        };
        let lib = library_forms(p, &LibraryOptions::default(), wanted).unwrap_or_else(|e| panic!("{p}: {e}"));
        let stem = p.file_stem();
        let w = format!("{stem}.user.wgsl");
        write(&dir, &w, &format!("{}\n{}", lib.files[0].text, user_fragment(&lib, false)));
        wgsl.push(serde_json::json!({ "file": w, "entries": [] }));
        // The tsl form as three.js's `wgslFn` includes it: functions only, every resource an
        // argument; Tint resolves every function of a module, called or not.
        let t = &lib.files[1];
        assert!(t.name.ends_with(".tsl.wgsl"), "{p}: {}", t.name);
        write(&dir, &t.name, &t.text);
        wgsl.push(serde_json::json!({ "file": t.name, "entries": [] }));
        if !with_es {
            continue;
        }
        let g = format!("{stem}.user.es.frag");
        write(
            &dir,
            &g,
            &format!(
                "#version 300 es\nprecision highp float;\nprecision highp int;\n#define RELIEF_EDGE_REPEAT\n{}\n{}",
                lib.files[2].text,
                user_fragment(&lib, true)
            ),
        );
        es.push(g);
    }
    let n = pipelines.len() as u64;
    let es_count = es.len() as u64;
    let r = compile_in_chromium(&dir, serde_json::json!({ "wgsl": wgsl, "glsl_es": es }));
    assert_eq!(r["wgsl"].as_u64(), Some(2 * n), "{r}");
    assert_eq!(r["glsl_es"].as_u64(), Some(es_count), "{r}");
    assert!(es_count > 0, "no GLSL ES library");
    std::fs::remove_dir_all(&dir).ok();
}
