//! `relief room`: a room behind a window with interior mapping and relief on every wall
//! (Amaro & Gustafsson 2022), against the same room as real geometry.

use std::path::PathBuf;

use anyhow::Context;

use relief_runtime::gpu::Gpu;
use relief_runtime::io::write_atomic;
use relief_runtime::metrics::percentile;
use relief_runtime::room::measure::{measure_room, write_images, RoomSetup};
use relief_runtime::room::mesh::DEFAULT_GRID;
use relief_runtime::room::{room_from_arg, RoomLight};

/// Arguments of `relief room`.
#[derive(clap::Args, Debug)]
pub struct RoomArgs {
    /// The pipeline run on every wall, in the text form, e.g. `linear(32)+binary(5)+shadow=soft(16)`.
    pub pipeline: String,
    /// `room:NAME` (built-in: `room:default`, `room:deep`, `room:window` with mullions) or a
    /// room file (`.toml`); default: the built-in room.
    #[arg(long)]
    pub scene: Option<String>,
    /// Frame size in pixels (square).
    #[arg(long, default_value_t = 512)]
    pub size: u32,
    /// Vertices a side of each wall's grid in the real-geometry baseline (Amaro & Gustafsson 2022: 320).
    #[arg(long, default_value_t = DEFAULT_GRID)]
    pub grid: usize,
    /// Texels a side of the procedural wall maps.
    #[arg(long)]
    pub map_size: Option<usize>,
    /// Light scattering through the window (Amaro & Gustafsson 2022, §2.3) with this many
    /// samples per pixel (the paper measured 42); off when left out.
    #[arg(long)]
    pub scatter: Option<u32>,
    /// Number of timed frames of each render (after 5 warm-up frames).
    #[arg(long, default_value_t = 50)]
    pub frames: u32,
    /// Output folder.
    #[arg(long)]
    pub out: PathBuf,
}

/// Runs `relief room`.
pub fn run(a: &RoomArgs) -> anyhow::Result<()> {
    let pipeline: relief_dsl::Pipeline =
        a.pipeline.parse().map_err(|e| anyhow::anyhow!("pipeline `{}`: {e}", relief_dsl::spec::echo(&a.pipeline)))?;
    if a.size == 0 || a.size > 8192 {
        anyhow::bail!("--size {} is out of range: allowed 1..=8192", a.size);
    }
    if !(2..=2048).contains(&a.grid) {
        anyhow::bail!("--grid {} is out of range: allowed 2..=2048", a.grid);
    }
    if a.frames == 0 {
        anyhow::bail!("--frames 0: at least one timed frame is needed");
    }
    let (room, warnings) = room_from_arg(a.scene.as_deref(), a.map_size).map_err(anyhow::Error::msg)?;
    for w in &warnings {
        eprintln!("relief: warning: {w}");
    }
    std::fs::create_dir_all(&a.out).with_context(|| format!("cannot create output folder {}", a.out.display()))?;
    let g = Gpu::new()?;
    let options = relief_dsl::compose::interior::RoomOptions { scatter: a.scatter };
    let setup = RoomSetup { size: a.size, grid: a.grid, warmup: 5, frames: a.frames };
    let m = measure_room(&g, &room, &pipeline, &options, &setup)?;
    let mean_abs_diff = write_images(&a.out, a.size, &m)?;
    let light = match room.light {
        RoomLight::Point(p) => serde_json::json!({ "point": p.to_array() }),
        RoomLight::Directional(d) => serde_json::json!({ "direction": d.to_array() }),
    };
    let json = serde_json::json!({
        "pipeline": pipeline.to_string(),
        "scatter": a.scatter,
        "room": room.name,
        "size": a.size,
        "room_size": room.size,
        "depth_scales": room.walls.iter().map(|w| w.depth_scale).collect::<Vec<_>>(),
        "map_size": room.walls.iter().map(|w| w.height.width).collect::<Vec<_>>(),
        "light": light,
        "adapter": g.adapter,
        "driver": g.driver,
        "frames": a.frames,
        "frame_ms_median": m.frame_ms,
        "frame_ms_p10": percentile(&m.interior.frame_ms, 0.1),
        "frame_ms_p90": percentile(&m.interior.frame_ms, 0.9),
        "baseline_grid": a.grid,
        "baseline_triangles": m.baseline_triangles,
        "baseline_ms_median": m.baseline_ms,
        "baseline_ms_p10": percentile(&m.baseline.frame_ms, 0.1),
        "baseline_ms_p90": percentile(&m.baseline.frame_ms, 0.9),
        "ratio_interior_to_baseline": m.frame_ms / m.baseline_ms,
        "rays": m.rays(),
        "wall_mismatch": m.per_wall.iter().map(|w| w.wall_mismatch).sum::<usize>(),
        "skipped_rate": m.skipped_rate(),
        "past_rate": m.past_rate(),
        "missed_rate": m.past_rate(),
        "t_err_rms": m.t_err_rms(),
        "t_err_max": m.per_wall.iter().map(|w| w.t_err_max).fold(0.0, f64::max),
        "per_wall": m.per_wall,
        "mean_abs_diff_8bit": mean_abs_diff,
        "warnings": warnings,
    });
    write_atomic(&a.out.join("metrics.json"), serde_json::to_string_pretty(&json)?.as_bytes())?;
    let walls: Vec<String> = m
        .per_wall
        .iter()
        .map(|w| format!("{} {:.1e}/{:.2}%/{:.2}%", w.wall, w.t_err_rms, 100.0 * w.skipped_rate, 100.0 * w.past_rate))
        .collect();
    println!(
        "{pipeline}{} in {} at {}²: interior {:.3} ms, geometry ({}² per wall, {} triangles) {:.3} ms, ratio {:.2}; t err rms/skipped/past per wall: {} → {}",
        a.scatter.map(|n| format!(" + scatter({n})")).unwrap_or_default(),
        room.name,
        a.size,
        m.frame_ms,
        a.grid,
        m.baseline_triangles,
        m.baseline_ms,
        m.frame_ms / m.baseline_ms,
        walls.join(", "),
        a.out.display()
    );
    Ok(())
}
