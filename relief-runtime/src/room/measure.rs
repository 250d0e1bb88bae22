//! One room measured: the interior frames of a pipeline, the real-geometry baseline, both
//! timed, and the probe's per-wall accuracy against the exact reference.

use relief_dsl::compose::interior::RoomOptions;
use relief_dsl::Pipeline;

use super::accuracy::{reference_hits, room_accuracy, WallAccuracy};
use super::gpu::{probe_room, render_interior, RoomProgram, RoomTextures};
use super::mesh::{render_geometry, RoomMesh};
use super::{Frames, Room};
use crate::error::{Error, Result};
use crate::gpu::Gpu;
use crate::metrics::percentile;

/// What [`measure_room`] measures.
#[derive(Clone, Copy, Debug)]
pub struct RoomSetup {
    /// Frame size (square), pixels.
    pub size: u32,
    /// Vertices a side of each wall's grid in the baseline.
    pub grid: usize,
    /// Untimed frames before the timed ones.
    pub warmup: u32,
    /// Timed frames of each render.
    pub frames: u32,
}

/// A room measured.
pub struct RoomMeasure {
    /// The interior frames.
    pub interior: Frames,
    /// The baseline's frames.
    pub baseline: Frames,
    /// Triangles of the baseline's walls.
    pub baseline_triangles: usize,
    /// Per-wall accuracy of the probe.
    pub per_wall: Vec<WallAccuracy>,
    /// Median interior frame time, ms.
    pub frame_ms: f64,
    /// Median baseline frame time, ms.
    pub baseline_ms: f64,
}

impl RoomMeasure {
    /// Rays over all walls.
    pub fn rays(&self) -> usize {
        self.per_wall.iter().map(|w| w.rays).sum()
    }
    fn share(&self, count: impl Fn(&WallAccuracy) -> usize) -> f64 {
        let n = self.rays();
        if n == 0 {
            f64::NAN
        } else {
            self.per_wall.iter().map(count).sum::<usize>() as f64 / n as f64
        }
    }
    /// Share of rays that jumped over geometry ([`WallAccuracy::skipped`]), over all walls.
    pub fn skipped_rate(&self) -> f64 {
        self.share(|w| w.skipped)
    }
    /// Share of rays past the first hit by more than a texel of travel, or on the wrong
    /// wall ([`WallAccuracy::past`]), over all walls.
    pub fn past_rate(&self) -> f64 {
        self.share(|w| w.past)
    }
    /// RMS t error over all walls (weighted by rays).
    pub fn t_err_rms(&self) -> f64 {
        let n = self.rays();
        let sq: f64 = self
            .per_wall
            .iter()
            .filter(|w| w.rays > 0 && w.t_err_rms.is_finite())
            .map(|w| w.t_err_rms * w.t_err_rms * w.rays as f64)
            .sum();
        if n == 0 {
            f64::NAN
        } else {
            (sq / n as f64).sqrt()
        }
    }
}

/// Renders and probes `room` with pipeline `p` (and `options`), renders the baseline, and
/// compares the probe's hits with the exact reference.
pub fn measure_room(
    gpu: &Gpu,
    room: &Room,
    p: &Pipeline,
    options: &RoomOptions,
    setup: &RoomSetup,
) -> Result<RoomMeasure> {
    let prog = RoomProgram::new_with(p, options)
        .map_err(|e| Error::from(e).in_pipeline(format!("`{}`", relief_dsl::spec::echo(&p.to_string()))))?;
    let tex = RoomTextures::new(gpu, room, &prog.maps)?;
    let interior = render_interior(gpu, &prog, room, &tex, setup.size, setup.warmup, setup.frames)?;
    let mesh = RoomMesh::new(room, setup.grid);
    let baseline = render_geometry(gpu, room, &mesh, setup.size, setup.warmup, setup.frames)?;
    let rays = room.rays(setup.size);
    let probe_rays: Vec<_> = rays.iter().map(|r| r.ray).collect();
    let hits = probe_room(gpu, &prog, room, &tex, &probe_rays)?;
    let heights: Vec<Vec<f32>> = tex.walls.iter().map(|t| t.heights_on_device.clone()).collect();
    let refs = reference_hits(room, &heights, &rays)?;
    let per_wall = room_accuracy(room, &heights, &rays, &hits, &refs);
    let frame_ms = percentile(&interior.frame_ms, 0.5);
    let baseline_ms = percentile(&baseline.frame_ms, 0.5);
    Ok(RoomMeasure { interior, baseline, baseline_triangles: mesh.wall_triangles, per_wall, frame_ms, baseline_ms })
}

/// The frame with alpha made opaque (the baseline's alpha holds wall indices).
pub(crate) fn opaque(rgba: &[u8]) -> Vec<u8> {
    let mut out = rgba.to_vec();
    for px in out.chunks_mut(4) {
        px[3] = 255;
    }
    out
}

/// Writes `frame.png`, `baseline.png` and `diff.png` (|frame − baseline| × 4 per channel)
/// into `dir`; returns the mean absolute difference per 8-bit channel.
pub fn write_images(dir: &std::path::Path, size: u32, m: &RoomMeasure) -> Result<f64> {
    crate::io::create_dir_all(dir)?;
    let frame = opaque(&m.interior.rgba);
    let base = opaque(&m.baseline.rgba);
    let diff: Vec<u8> = frame
        .chunks(4)
        .zip(base.chunks(4))
        .flat_map(|(p, q)| {
            let d = |i: usize| ((p[i] as i32 - q[i] as i32).unsigned_abs() * 4).min(255) as u8;
            [d(0), d(1), d(2), 255]
        })
        .collect();
    let px = (size as f64) * (size as f64);
    let mean = frame
        .chunks(4)
        .zip(base.chunks(4))
        .map(|(p, q)| (0..3).map(|i| (p[i] as f64 - q[i] as f64).abs()).sum::<f64>() / 3.0)
        .sum::<f64>()
        / px;
    crate::io::png::write_rgba8(&dir.join("frame.png"), size, size, frame)?;
    crate::io::png::write_rgba8(&dir.join("baseline.png"), size, size, base)?;
    crate::io::png::write_rgba8(&dir.join("diff.png"), size, size, diff)?;
    Ok(mean)
}
