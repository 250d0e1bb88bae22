//! `relief room`: a room behind a window with interior mapping and relief on every wall
//! (seed 003), against the same room as real geometry.

use std::path::PathBuf;

use anyhow::Context;

use relief_runtime::gpu::Gpu;
use relief_runtime::io::write_atomic;
use relief_runtime::metrics::percentile;
use relief_runtime::room::accuracy::{reference_hits, room_accuracy};
use relief_runtime::room::gpu::{probe_room, render_interior, RoomProgram, RoomTextures};
use relief_runtime::room::mesh::{render_geometry, RoomMesh, DEFAULT_GRID};
use relief_runtime::room::{room_from_arg, RoomLight, WALLS};

/// Arguments of `relief room`.
#[derive(clap::Args, Debug)]
pub struct RoomArgs {
    /// The pipeline run on every wall, in the text form, e.g. `linear(32)+binary(5)+shadow=soft(16)`.
    pub pipeline: String,
    /// `room:NAME` (built-in: `room:default`, `room:deep`, `room:window` with mullions) or a room file (`.toml`); default:
    /// the built-in room.
    #[arg(long)]
    pub scene: Option<String>,
    /// Frame size in pixels (square).
    #[arg(long, default_value_t = 512)]
    pub size: u32,
    /// Vertices a side of each wall's grid in the real-geometry baseline (seed 003: 320).
    #[arg(long, default_value_t = DEFAULT_GRID)]
    pub grid: usize,
    /// Texels a side of the procedural wall maps.
    #[arg(long)]
    pub map_size: Option<usize>,
    /// Light scattering through the window (seed 003 §2.3) with this many samples per pixel
    /// (the seed measured 42); off when left out.
    #[arg(long)]
    pub scatter: Option<u32>,
    /// Number of timed frames of each render (after 5 warm-up frames).
    #[arg(long, default_value_t = 50)]
    pub frames: u32,
    /// Output folder.
    #[arg(long)]
    pub out: PathBuf,
}

fn opaque(mut rgba: Vec<u8>) -> Vec<u8> {
    for px in rgba.chunks_mut(4) {
        px[3] = 255;
    }
    rgba
}

/// Runs `relief room`.
pub fn run(a: &RoomArgs) -> anyhow::Result<()> {
    let pipeline: relief_dsl::Pipeline = a.pipeline.parse().map_err(|e| anyhow::anyhow!("pipeline `{}`: {e}", a.pipeline))?;
    if a.size == 0 || a.size > 8192 {
        anyhow::bail!("--size {} is out of range: allowed 1..=8192", a.size);
    }
    if !(2..=2048).contains(&a.grid) {
        anyhow::bail!("--grid {} is out of range: allowed 2..=2048", a.grid);
    }
    let (room, warnings) = room_from_arg(a.scene.as_deref(), a.map_size).map_err(anyhow::Error::msg)?;
    for w in &warnings {
        eprintln!("relief: warning: {w}");
    }
    std::fs::create_dir_all(&a.out).with_context(|| format!("cannot create output folder {}", a.out.display()))?;
    let g = Gpu::new()?;
    let options = relief_dsl::compose::interior::RoomOptions { scatter: a.scatter };
    let prog = RoomProgram::new_with(&pipeline, &options).map_err(|e| anyhow::anyhow!("pipeline `{pipeline}`: {e}"))?;
    let tex = RoomTextures::new(&g, &room, &prog.maps)?;
    let pom = render_interior(&g, &prog, &room, &tex, a.size, 5, a.frames)?;
    let mesh = RoomMesh::new(&room, a.grid);
    let geo = render_geometry(&g, &room, &mesh, a.size, 5, a.frames)?;

    let rays = room.rays(a.size);
    let probe_rays: Vec<_> = rays.iter().map(|r| r.ray).collect();
    let hits = probe_room(&g, &prog, &room, &tex, &probe_rays)?;
    let heights: Vec<Vec<f32>> = tex.walls.iter().map(|t| t.heights_on_device.clone()).collect();
    let refs = reference_hits(&room, &heights, &rays)?;
    let per_wall = room_accuracy(&room, &rays, &hits, &refs);

    let n = a.size as usize;
    let frame = opaque(pom.rgba.clone());
    let base = opaque(geo.rgba.clone());
    let diff: Vec<u8> = frame
        .chunks(4)
        .zip(base.chunks(4))
        .flat_map(|(p, q)| {
            let d = |i: usize| ((p[i] as i32 - q[i] as i32).unsigned_abs() * 4).min(255) as u8;
            [d(0), d(1), d(2), 255]
        })
        .collect();
    let mean_abs_diff = frame.chunks(4).zip(base.chunks(4)).map(|(p, q)| (0..3).map(|i| (p[i] as f64 - q[i] as f64).abs()).sum::<f64>() / 3.0).sum::<f64>() / (n * n) as f64;
    relief_runtime::io::png::write_rgba8(&a.out.join("frame.png"), a.size, a.size, frame)?;
    relief_runtime::io::png::write_rgba8(&a.out.join("baseline.png"), a.size, a.size, base)?;
    relief_runtime::io::png::write_rgba8(&a.out.join("diff.png"), a.size, a.size, diff)?;

    let pom_ms = percentile(&pom.frame_ms, 0.5);
    let geo_ms = percentile(&geo.frame_ms, 0.5);
    let all_rays: usize = per_wall.iter().map(|w| w.rays).sum();
    let all_missed: usize = per_wall.iter().map(|w| w.missed).sum();
    let mismatch: usize = per_wall.iter().map(|w| w.wall_mismatch).sum();
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
        "frame_ms_median": pom_ms,
        "frame_ms_p10": percentile(&pom.frame_ms, 0.1),
        "frame_ms_p90": percentile(&pom.frame_ms, 0.9),
        "baseline_grid": a.grid,
        "baseline_triangles": mesh.wall_triangles,
        "baseline_ms_median": geo_ms,
        "baseline_ms_p10": percentile(&geo.frame_ms, 0.1),
        "baseline_ms_p90": percentile(&geo.frame_ms, 0.9),
        "ratio_pom_to_baseline": pom_ms / geo_ms,
        "rays": all_rays,
        "wall_mismatch": mismatch,
        "missed_rate": if all_rays > 0 { all_missed as f64 / all_rays as f64 } else { f64::NAN },
        "t_err_max": per_wall.iter().map(|w| w.t_err_max).fold(0.0, f64::max),
        "per_wall": per_wall,
        "mean_abs_diff_8bit": mean_abs_diff,
        "warnings": warnings,
    });
    write_atomic(&a.out.join("metrics.json"), serde_json::to_string_pretty(&json)?.as_bytes())?;
    let walls: Vec<String> = per_wall.iter().take(WALLS).map(|w| format!("{} {:.1e}/{:.2}%", w.wall, w.t_err_rms, 100.0 * w.missed_rate)).collect();
    println!(
        "{pipeline} in {} at {}²: interior {pom_ms:.3} ms, geometry ({}² per wall, {} triangles) {geo_ms:.3} ms, ratio {:.2}; t err rms/missed per wall: {} → {}",
        room.name,
        a.size,
        a.grid,
        mesh.wall_triangles,
        pom_ms / geo_ms,
        walls.join(", "),
        a.out.display()
    );
    Ok(())
}
