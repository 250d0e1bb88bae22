//! `relief sweep`: a grid measured cell by cell, resumable.

use std::path::PathBuf;

use relief_runtime::sweep;

/// Arguments of `relief sweep`.
#[derive(clap::Args, Debug)]
pub struct SweepArgs {
    /// A built-in grid (`t4.1` … `t4.15`, `f4.5`, `f4.7` … `f4.11`, `dissertation`, `lod`, `frontier`),
    /// `rooms` (Amaro & Gustafsson 2022's interior-mapping comparison on rooms, `--scene room:NAME` or room
    /// files), `meshes` (curved=none, quadric and prism on mesh scenes, `--scene FILE.toml@angle=30`), or a
    /// grid file.
    #[arg(long, required_unless_present = "list")]
    pub grid: Option<String>,
    /// Scenes to measure on (`scene:NAME`, a bare NAME, a TOML scene file or a height-map
    /// file); repeatable. Default: the scenes the grid names (Lion for most).
    #[arg(long)]
    pub scene: Vec<String>,
    #[command(flatten)]
    pub overrides: crate::OverrideArgs,
    /// Frame size in pixels (square). Default 256 (`meshes`: 96).
    #[arg(long)]
    pub size: Option<u32>,
    /// Timed blocks per cell, the cell's and the baseline's together: frames/2 pairs (at
    /// least 2) alternating with the baseline `linear(32)+binary(5)` (`meshes`: with the same
    /// stages under curved=none), after 3 warm-up frames; a block is as many frames as last
    /// 2 ms (one frame on lavapipe). Default 50 (`meshes`: 12).
    #[arg(long)]
    pub frames: Option<u32>,
    /// Measure only shard K of N (K/N, e.g. 2/4): the grid's cells sorted and dealt round
    /// robin, so that N machines given the same grid measure every cell once between them.
    #[arg(long, value_parser = sweep::parse_shard)]
    pub shard: Option<(u32, u32)>,
    /// Output folder; re-running with the same folder skips finished cells.
    #[arg(long, default_value = "out/sweep")]
    pub out: PathBuf,
    /// List the built-in grids with their cell counts.
    #[arg(long)]
    pub list: bool,
    /// When another relief process holds the output folder's lock (`OUT/.relief.lock`),
    /// wait for it instead of refusing.
    #[arg(long)]
    pub wait: bool,
    /// Leave out the GPU compiler's columns (`relief cost`'s modeled instructions per pixel
    /// on RDNA2 and RDNA3), which the sweep writes when Mesa's RADV is installed.
    #[arg(long, conflicts_with = "gpu_costs")]
    pub no_gpu_cost: bool,
    /// Take the GPU compiler's figures from this file (`relief cost --grid GRID --json
    /// FILE`, written where RADV is installed) instead of compiling: for a machine without
    /// RADV, a GPU machine whose clock the model is set beside.
    #[arg(long, value_name = "FILE")]
    pub gpu_costs: Option<PathBuf>,
}

/// Runs `relief sweep`.
pub fn run(a: &SweepArgs) -> anyhow::Result<()> {
    let scenes = if a.scene.is_empty() { None } else { Some(a.scene.as_slice()) };
    if a.list {
        for g in sweep::plan::listing(scenes) {
            println!("{:<13} {:>4} cells  {}", g.name, g.cells, g.description);
        }
        return Ok(());
    }
    let overrides = a.overrides.checked()?;
    let plan = sweep::Plan::load(a.grid.as_deref().unwrap_or_default(), scenes)?;
    let (default_size, default_frames) = plan.default_size_frames();
    let (size, frames) = (a.size.unwrap_or(default_size), a.frames.unwrap_or(default_frames));
    if size == 0 || size > 4096 {
        anyhow::bail!("--size {size} is out of range: allowed 1..=4096");
    }
    if frames == 0 {
        anyhow::bail!("--frames 0: at least one timed frame is needed");
    }
    let rows = plan.rows_path(&a.out);
    let _lock = crate::lock_folders(&[&a.out], a.wait)?;
    let gpu_cost = if a.no_gpu_cost {
        None
    } else if let Some(file) = &a.gpu_costs {
        Some(relief_runtime::cost::Compiler::from_recorded(file)?)
    } else {
        std::env::current_exe().ok().map(relief_runtime::cost::Compiler::new)
    };
    let start = std::time::Instant::now();
    let done = plan.run(sweep::Settings {
        size,
        frames,
        warmup: 3,
        out: a.out.clone(),
        progress: std::io::IsTerminal::is_terminal(&std::io::stderr()),
        overrides,
        shard: a.shard,
        gpu_cost,
    })?;
    if let Some(note) = done.gpu_note() {
        eprintln!("relief: {note}");
    }
    let shard = a.shard.map(|(k, n)| format!("shard {k}/{n}: ")).unwrap_or_default();
    println!("{shard}{done}, in {:.1} s → {}", start.elapsed().as_secs_f64(), rows.display());
    Ok(())
}
