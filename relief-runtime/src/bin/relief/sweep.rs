//! `relief sweep`: a grid measured cell by cell, resumable.

use std::path::PathBuf;

use relief_runtime::sweep::{self, grids};

/// Arguments of `relief sweep`.
#[derive(clap::Args, Debug)]
pub struct SweepArgs {
    /// A built-in grid (`t4.1` … `t4.15`, `f4.5`, `f4.7` … `f4.11`, `dissertation`, `lod`) or a grid file.
    #[arg(long, required_unless_present = "list")]
    pub grid: Option<String>,
    /// Scenes to measure on (`scene:NAME`, a bare NAME, a TOML scene file or a height-map
    /// file); repeatable. Default: the scenes the grid names (Lion for most).
    #[arg(long)]
    pub scene: Vec<String>,
    #[command(flatten)]
    pub overrides: crate::OverrideArgs,
    /// Frame size in pixels (square).
    #[arg(long, default_value_t = 256)]
    pub size: u32,
    /// Timed frames per cell (after 3 warm-up frames).
    #[arg(long, default_value_t = 50)]
    pub frames: u32,
    /// Output folder; re-running with the same folder skips finished cells.
    #[arg(long, default_value = "out/sweep")]
    pub out: PathBuf,
    /// List the built-in grids with their cell counts.
    #[arg(long)]
    pub list: bool,
}

/// Runs `relief sweep`.
pub fn run(a: &SweepArgs) -> anyhow::Result<()> {
    let scenes = if a.scene.is_empty() { None } else { Some(a.scene.as_slice()) };
    if a.list {
        for g in grids::builtin(scenes) {
            println!("{:<13} {:>4} cells  {}", g.name, g.cells.len(), g.description);
        }
        return Ok(());
    }
    if a.size == 0 || a.size > 4096 {
        anyhow::bail!("--size {} is out of range: allowed 1..=4096", a.size);
    }
    if a.frames == 0 {
        anyhow::bail!("--frames 0: at least one timed frame is needed");
    }
    let overrides = a.overrides.checked()?;
    let grid = grids::load(a.grid.as_deref().unwrap_or_default(), scenes)?;
    let start = std::time::Instant::now();
    let total = grid.cells.len();
    let s = sweep::run(&sweep::Options {
        grid,
        size: a.size,
        frames: a.frames,
        warmup: 3,
        out: a.out.clone(),
        progress: std::io::IsTerminal::is_terminal(&std::io::stderr()),
        overrides,
    })?;
    println!(
        "{total} cells: {} measured, {} failed, {} already done, in {:.1} s → {}",
        s.measured,
        s.failed,
        s.skipped,
        start.elapsed().as_secs_f64(),
        a.out.join("results.csv").display()
    );
    Ok(())
}
