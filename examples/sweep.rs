//! A small sweep on the GPU: a grid declared with `relief_grid!`, measured on two scenes
//! (frame time with render-pass timestamps, accuracy against the exact reference), then the
//! report. Into the folder given as the first argument, or `relief-sweep-example` in the
//! system's temporary folder.
//!
//! `LP_NUM_THREADS=1 cargo run --release --example sweep -- out/small-sweep`

use std::path::{Path, PathBuf};

use relief::relief_grid;
use relief::runtime::sweep::{self, NamedGrid};

type Error = Box<dyn std::error::Error + Send + Sync>;

/// Sweeps the grid into `out` and writes the report; returns (cells measured, report files).
pub fn run(out: &Path) -> Result<(usize, usize), Error> {
    let grid = relief_grid! {
        name: "sweep example",
        coarse: [linear(8..=24 step 8), rcs(8)],
        refine: [none, binary(3)],
    };
    let cells = grid.iter().flat_map(|p| ["rock_bump", "shapes"].map(|s| (p.clone(), s.to_string()))).collect();
    let options = sweep::Options {
        grid: NamedGrid { name: "sweep-example".into(), description: "the sweep example".into(), cells },
        size: 64,
        frames: 5,
        warmup: 2,
        out: out.to_path_buf(),
        progress: false,
        overrides: Default::default(),
        shard: None,
        gpu_cost: None,
    };
    let summary = sweep::run(&options).map_err(|e| e.to_string())?;
    let report = relief::runtime::report::write(out).map_err(|e| e.to_string())?;
    Ok((summary.measured + summary.skipped, report.files.len()))
}

#[allow(dead_code)]
fn main() -> Result<(), Error> {
    let out =
        std::env::args().nth(1).map(PathBuf::from).unwrap_or_else(|| std::env::temp_dir().join("relief-sweep-example"));
    let (cells, files) = run(&out)?;
    println!("{cells} cells measured, report of {files} files: {}", out.join("index.html").display());
    Ok(())
}
