//! Writes the shader files (WGSL, SPIR-V, GLSL per entry point) of every pipeline of a grid
//! into a folder: the one given as the first argument, or `relief-generate` in the system's
//! temporary folder.
//!
//! `cargo run --release --example generate -- out/shaders`

use std::path::{Path, PathBuf};

use relief::relief_grid;

type Error = Box<dyn std::error::Error + Send + Sync>;

/// Writes the grid's shaders into `out`; returns the file stems, one per pipeline.
pub fn run(out: &Path) -> Result<Vec<String>, Error> {
    let grid = relief_grid! {
        name: "generate example",
        coarse: [linear(8..=16 step 8), linear_dynamic(8, 32)],
        refine: [none, binary(4), interval(4)],
        shadow: [none, soft(16)],
    };
    std::fs::create_dir_all(out)?;
    let mut stems = Vec::new();
    for p in &grid {
        stems.push(relief::runtime::io::write_pipeline(p, out)?);
    }
    Ok(stems)
}

#[allow(dead_code)]
fn main() -> Result<(), Error> {
    let out =
        std::env::args_os().nth(1).map(PathBuf::from).unwrap_or_else(|| std::env::temp_dir().join("relief-generate"));
    let stems = run(&out)?;
    for s in &stems {
        println!("{s}");
    }
    println!("{} pipelines, 5 files each, in {}", stems.len(), out.display());
    Ok(())
}
