//! The facade's integration tests, one module per file beside this one, linked into one test
//! binary (linking wgpu and naga once instead of once per file). Run one file's tests with
//! `cargo test --release --test facade compose::`.

mod common;

mod babylon;
mod chromium;
mod compose;
mod examples;
mod integrate;
mod khronos;
mod layers;
mod library;
mod meshes_shaders;
mod report_browser;
mod room_modules;
mod text_form;
mod threejs;
mod threejs_mesh;

/// Every `tests/*.rs` file of the facade and of relief-runtime is a module of its crate's one
/// test binary: a file added without its `mod` line would otherwise never be compiled or run.
#[test]
fn every_test_file_is_a_module() {
    let workspace = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    for (dir, root) in [("tests", "facade"), ("relief-runtime/tests", "runtime")] {
        let text = std::fs::read_to_string(workspace.join(dir).join(format!("{root}.rs"))).unwrap();
        let mut missing = Vec::new();
        for e in std::fs::read_dir(workspace.join(dir)).unwrap() {
            let path = e.unwrap().path();
            let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or_default();
            let is_rs = path.extension().is_some_and(|x| x == "rs");
            if is_rs && stem != root && !text.lines().any(|l| l == format!("mod {stem};")) {
                missing.push(stem.to_string());
            }
        }
        assert!(missing.is_empty(), "{dir}: {missing:?} are not modules: add `mod NAME;` to {dir}/{root}.rs");
    }
}
