//! The `relief` command line of this build, for the tests that run it as a user would
//! (`use crate::common::exe;`).

use std::path::{Path, PathBuf};
use std::process::Command;

/// The `relief` command line of this build: `target/PROFILE/relief`, beside the test
/// binary's `deps/`. The facade cannot name another package's binary, so it is looked up
/// there; a missing or stale one is a failure that says how to build it.
pub fn relief_exe() -> PathBuf {
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

/// `relief export PIPE --scene ARG --target TARGET --out DIR` on lavapipe, which must succeed.
pub fn export(pipe: &str, arg: &str, target: &str, dir: &Path) {
    let out = Command::new(relief_exe())
        .args(["export", pipe, "--scene", arg, "--target", target, "--out"])
        .arg(dir)
        .env("LP_NUM_THREADS", "1")
        .env("NODEVICE_SELECT", "1")
        .output()
        .unwrap();
    assert!(out.status.success(), "relief export {pipe} --target {target}: {}", String::from_utf8_lossy(&out.stderr));
}
