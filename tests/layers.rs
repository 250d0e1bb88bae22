//! The layers of ARCHITECTURE.md, checked on the source: no module names one above it.
//!
//! relief-dsl: abi → spec → ir → stage → compose → emit. relief-runtime: the leaves (io,
//! lock, results, picture, timing), then heightmap, scene, maps, reference and mesh → gpu → metrics, simd → measure, mesh_measure →
//! sweep, stability, room → report; the command line (src/bin) is above everything, and nothing in
//! the library names it. A module may name its own layer and any below it (`crate::X` paths
//! and `use crate::{X, ...}` groups are both read). A file's unit tests (from its
//! `#[cfg(test)]` line on) are not part of the library and may drive the whole pipeline.

use std::path::{Path, PathBuf};

/// Files under `dir`, recursively.
fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            out.extend(rust_files(&p));
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
    out
}

/// The top-level modules a source text names through `crate::`, outside `//` comments.
fn named_modules(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    // The code of all lines joined, so that a `crate::{…}` group that rustfmt splits over
    // several lines is read whole.
    let code: String = text
        .lines()
        .take_while(|l| l.trim() != "#[cfg(test)]")
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join(" ");
    let ident = |s: &str| -> String { s.trim().chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect() };
    let mut rest = code.as_str();
    while let Some(i) = rest.find("crate::") {
        rest = &rest[i + "crate::".len()..];
        let Some(group) = rest.strip_prefix('{') else {
            out.push(ident(rest));
            continue;
        };
        // The group's top-level items: the first name of each, nested groups skipped.
        let (mut depth, mut start) = (0, true);
        for (k, c) in group.char_indices() {
            match c {
                '{' => depth += 1,
                '}' if depth == 0 => break,
                '}' => depth -= 1,
                ',' if depth == 0 => start = true,
                _ if start && !c.is_whitespace() => {
                    out.push(ident(&group[k..]));
                    start = false;
                }
                _ => {}
            }
        }
    }
    out
}

/// Checks every file of `src`: the layer of a file is that of its top-level module; a file
/// may name modules of its layer or lower. `layers[i]` lists the modules of layer i. A
/// module in no layer is reported too, so that a new module cannot escape the check (the
/// crate root `lib.rs` and the command line under `bin/` are above every layer).
fn check(src: &Path, layers: &[&[&str]]) -> Vec<String> {
    let layer_of = |m: &str| layers.iter().position(|l| l.contains(&m));
    let mut bad = Vec::new();
    for file in rust_files(src) {
        let rel = file.strip_prefix(src).unwrap();
        let top = rel.iter().next().unwrap().to_string_lossy().trim_end_matches(".rs").to_string();
        if top == "lib" || top == "bin" {
            continue;
        }
        let Some(own) = layer_of(&top) else {
            bad.push(format!("{} ({top}) is in no layer", rel.display()));
            continue;
        };
        let text = std::fs::read_to_string(&file).unwrap();
        for m in named_modules(&text) {
            if let Some(l) = layer_of(&m) {
                if l > own {
                    bad.push(format!("{} ({top}, layer {own}) names crate::{m} (layer {l})", rel.display()));
                }
            }
        }
    }
    bad
}

#[test]
fn relief_dsl_imports_point_down() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let layers: &[&[&str]] = &[&["abi"], &["spec"], &["ir"], &["stage"], &["compose"], &["emit"]];
    let bad = check(&root.join("relief-dsl/src"), layers);
    assert!(bad.is_empty(), "back edges:\n{}", bad.join("\n"));
}

#[test]
fn relief_runtime_imports_point_down() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let layers: &[&[&str]] = &[
        &["io", "lock", "results", "picture", "timing"],
        &["heightmap"],
        &["scene"],
        &["maps"],
        &["reference", "mesh"],
        &["gpu"],
        &["metrics", "simd", "cost", "error"],
        &["measure", "mesh_measure"],
        &["sweep", "stability", "room", "tune"],
        &["report"],
    ];
    let bad = check(&root.join("relief-runtime/src"), layers);
    assert!(bad.is_empty(), "back edges:\n{}", bad.join("\n"));
    // The library never names the command line.
    for file in rust_files(&root.join("relief-runtime/src")) {
        if file.components().any(|c| c.as_os_str() == "bin") {
            continue;
        }
        let text = std::fs::read_to_string(&file).unwrap();
        assert!(!text.contains("bin::relief") && !text.contains("cli_"), "{} names the CLI", file.display());
    }
}

#[test]
fn the_checker_sees_a_back_edge() {
    assert_eq!(named_modules("use crate::stage::{self, StageFn};"), ["stage"]);
    assert_eq!(named_modules("use crate::{ir::FnBuilder, spec};  // crate::emit"), ["ir", "spec"]);
    // A group split over lines, with a nested group, as rustfmt writes it.
    assert_eq!(named_modules("use crate::{\n    ir::{FnBuilder, Val},\n    spec,\n};"), ["ir", "spec"]);
    assert_eq!(named_modules("let a = crate::abi::X;\n#[cfg(test)]\nmod tests { use crate::emit; }"), ["abi"]);
    // On a tree: a back edge and a module in no layer.
    let dir = std::env::temp_dir().join(format!("relief-layers-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("low")).unwrap();
    std::fs::write(dir.join("low/mod.rs"), "use crate::high::X;\n").unwrap();
    std::fs::write(dir.join("high.rs"), "use crate::low::Y;\n").unwrap();
    std::fs::write(dir.join("stray.rs"), "").unwrap();
    std::fs::write(dir.join("lib.rs"), "use crate::high;\n").unwrap();
    let mut bad = check(&dir, &[&["low"], &["high"]]);
    bad.sort();
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(bad.len(), 2, "{bad:?}");
    assert!(bad[0].contains("low/mod.rs (low, layer 0) names crate::high (layer 1)"), "{bad:?}");
    assert!(bad[1].contains("stray.rs (stray) is in no layer"), "{bad:?}");
}
