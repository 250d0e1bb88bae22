//! Helpers the tests share: finding the Khronos tools and running them (here), driving the
//! browser harness (`browser`), comparing frames (`frames`) and running this build's `relief`
//! (`exe`).

pub mod browser;
pub mod exe;
pub mod frames;

use std::process::Command;

/// `name` if it runs, else a failure that says which packages to install.
pub fn tool(name: &str) -> &str {
    let found = Command::new(name).arg("--version").output().is_ok();
    assert!(
        found,
        "`{name}` is not installed: install the Debian packages spirv-tools and glslang-tools (.ci/run does)"
    );
    name
}

/// Runs `cmd`; a failure shows its output under `what`.
pub fn run(cmd: &mut Command, what: &str) {
    let out = cmd.output().unwrap_or_else(|e| panic!("{what}: {e}"));
    assert!(
        out.status.success(),
        "{what} failed:\n{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}
