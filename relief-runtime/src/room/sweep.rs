//! The room grid of `relief sweep --grid rooms`: Amaro & Gustafsson 2022's comparison (§3.1.3) of interior
//! mapping alone, + POM, + soft shadows, + light scattering, each against the same room as
//! real geometry, on every room asked for. Rows go to `DIR/rooms.jsonl` (rewritten whole,
//! atomically, after every cell, so a kill loses at most the cell in flight), pictures to
//! `DIR/rooms/ROOM/VARIANT/`; a rerun keeps the cells already measured at the same size and
//! grid and measures the rest (a failed cell again). `relief report DIR` reads the rows into
//! its room section.

use std::path::{Path, PathBuf};

use relief_dsl::compose::interior::RoomOptions;
use relief_dsl::Pipeline;
use serde::{Deserialize, Serialize};

use super::accuracy::WallAccuracy;
use super::measure::{measure_room, write_images, RoomSetup};
use super::room_from_arg;
use crate::error::{Error, Result};
use crate::gpu::Gpu;
use crate::io::FileError;
use crate::results::ResultsError;

/// One variant of the paper's comparison: a label, the pipeline on every wall, scattering.
#[derive(Clone, Debug, PartialEq)]
pub struct Variant {
    /// The paper's name for it.
    pub label: &'static str,
    /// The pipeline on every wall.
    pub pipeline: &'static str,
    /// Light-scattering samples, if on.
    pub scatter: Option<u32>,
}

/// The paper's four variants (§3.1.3, Figures 11–14). POM uses the paper's dynamic layer
/// count (§2.1.3, `linear_distance` with its defaults 16, 180, 4) refined by 5 binary
/// steps; soft shadows 16 steps; scattering the paper's 42 samples (§3.1.2).
pub fn variants() -> Vec<Variant> {
    vec![
        Variant { label: "interior mapping alone", pipeline: "none", scatter: None },
        Variant { label: "+ POM", pipeline: "linear_distance+binary(5)", scatter: None },
        Variant { label: "+ soft shadows", pipeline: "linear_distance+binary(5)+shadow=soft(16)", scatter: None },
        Variant { label: "+ scattering", pipeline: "linear_distance+binary(5)+shadow=soft(16)", scatter: Some(42) },
    ]
}

/// The rooms measured when none are named.
pub const DEFAULT_ROOMS: [&str; 2] = ["room:default", "room:window"];

/// One cell: a variant in a room, against that room's geometry.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RoomRow {
    /// The room.
    pub room: String,
    /// The variant's label ([`Variant::label`]).
    pub variant: String,
    /// The pipeline on every wall.
    pub pipeline: String,
    /// Scattering samples (0: off).
    pub scatter: u32,
    /// Frame size.
    pub size: u32,
    /// Vertices a side of each wall's baseline grid.
    pub grid: usize,
    /// Median interior frame time, ms.
    pub frame_ms: f64,
    /// Median baseline frame time, ms.
    pub baseline_ms: f64,
    /// `frame_ms / baseline_ms`.
    pub ratio: f64,
    /// RMS t error over all walls.
    pub t_err_rms: f64,
    /// Share of rays that jumped over geometry, over all walls
    /// ([`WallAccuracy::skipped_rate`]); NaN in a row written before it was measured.
    #[serde(default = "not_recorded", deserialize_with = "null_as_nan")]
    pub skipped_rate: f64,
    /// Share of rays more than a texel of travel past the exact hit, over all walls
    /// ([`WallAccuracy::past_rate`]); a row written before it had the name reads
    /// `missed_rate`.
    #[serde(default = "not_recorded", deserialize_with = "null_as_nan")]
    pub past_rate: f64,
    /// The old name of `past_rate`, written beside it (the same value) for one release.
    #[serde(default = "not_recorded", deserialize_with = "null_as_nan")]
    pub missed_rate: f64,
    /// Mean |interior − baseline| per 8-bit channel.
    pub mean_abs_diff: f64,
    /// Measured or failed (`ok` or `error` in the file).
    pub status: crate::results::Status,
    /// The error, when the cell failed.
    pub error: String,
    /// Per wall (names and the same measures).
    #[serde(default)]
    pub per_wall: Vec<WallRow>,
}

/// A wall's accuracy in a [`RoomRow`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WallRow {
    /// The wall.
    pub wall: String,
    /// Rays on it.
    pub rays: usize,
    /// RMS t error.
    pub t_err_rms: f64,
    /// Share that jumped over geometry ([`WallAccuracy::skipped_rate`]).
    #[serde(default = "not_recorded", deserialize_with = "null_as_nan")]
    pub skipped_rate: f64,
    /// Share past the exact hit by more than a texel of travel ([`WallAccuracy::past_rate`]).
    #[serde(default = "not_recorded", deserialize_with = "null_as_nan")]
    pub past_rate: f64,
    /// The old name of `past_rate` (the same value), for one release.
    #[serde(default = "not_recorded", deserialize_with = "null_as_nan")]
    pub missed_rate: f64,
}

impl From<&WallAccuracy> for WallRow {
    fn from(a: &WallAccuracy) -> WallRow {
        WallRow {
            wall: a.wall.clone(),
            rays: a.rays,
            t_err_rms: a.t_err_rms,
            skipped_rate: a.skipped_rate,
            past_rate: a.past_rate,
            missed_rate: a.past_rate,
        }
    }
}

/// A measure a row does not hold: NaN, shown as such, never a silent 0.
fn not_recorded() -> f64 {
    f64::NAN
}

/// A number written as `null` (NaN when measured) reads back as NaN.
fn null_as_nan<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// A row written before `past_rate` had the name holds it as `missed_rate`.
fn past_from_missed(past: &mut f64, missed: f64) {
    if past.is_nan() {
        *past = missed;
    }
}

/// The rows file of a sweep folder.
pub fn rows_path(dir: &Path) -> PathBuf {
    dir.join("rooms.jsonl")
}

/// Reads `DIR/rooms.jsonl`; `None` when there is none. Unreadable lines are errors.
pub fn read_rows(dir: &Path) -> Result<Option<Vec<RoomRow>>, ResultsError> {
    let p = rows_path(dir);
    if !p.exists() {
        return Ok(None);
    }
    let text = crate::io::read_regular_to_string(&p).map_err(|e| FileError::read(&p, e))?;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty()) {
        let mut row: RoomRow =
            serde_json::from_str(line).map_err(|source| ResultsError::Line { path: p.clone(), line: i + 1, source })?;
        past_from_missed(&mut row.past_rate, row.missed_rate);
        for w in &mut row.per_wall {
            past_from_missed(&mut w.past_rate, w.missed_rate);
        }
        out.push(row);
    }
    Ok(Some(out))
}

fn folder(s: &str) -> String {
    s.chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '.' { c } else { '_' }).collect()
}

/// What [`run`] did.
pub struct RoomSweep {
    /// Every row of the folder: those kept from earlier runs, then the new ones.
    pub rows: Vec<RoomRow>,
    /// Cells measured by this run.
    pub measured: usize,
    /// Cells kept from an earlier run.
    pub skipped: usize,
}

/// Measures every variant in every room of `rooms` (`room:NAME` or room files) that the
/// folder's rows do not already hold (ok, same size and grid) and writes the rows.
pub fn run(rooms: &[String], setup: &RoomSetup, out: &Path) -> Result<RoomSweep> {
    crate::io::create_dir_all(out)?;
    let earlier = read_rows(out)?.unwrap_or_default();
    let same_cell = |r: &RoomRow, room: &str, variant: &str| {
        r.room == room && r.variant == variant && r.size == setup.size && r.grid == setup.grid
    };
    let gpu = Gpu::new()?;
    // Failed cells are measured again: only ok rows are kept.
    let mut rows: Vec<RoomRow> = earlier.into_iter().filter(|r| r.status.is_ok()).collect();
    let (mut measured, mut skipped) = (0, 0);
    for arg in rooms {
        let (room, warnings) = room_from_arg(Some(arg), None).map_err(Error::Room)?;
        for w in &warnings {
            eprintln!("relief: warning: {w}");
        }
        for v in variants() {
            if rows.iter().any(|r| same_cell(r, &room.name, v.label)) {
                skipped += 1;
                continue;
            }
            measured += 1;
            let p: Pipeline = v.pipeline.parse().map_err(|e| Error::from(e).in_pipeline(v.pipeline))?;
            let mut row = RoomRow {
                room: room.name.clone(),
                variant: v.label.into(),
                pipeline: p.to_string(),
                scatter: v.scatter.unwrap_or(0),
                size: setup.size,
                grid: setup.grid,
                status: crate::results::Status::Ok,
                ..Default::default()
            };
            let dir = out.join("rooms").join(folder(&room.name)).join(folder(v.label));
            match measure_room(&gpu, &room, &p, &RoomOptions { scatter: v.scatter }, setup)
                .and_then(|m| Ok((write_images(&dir, setup.size, &m)?, m)))
            {
                Ok((diff, m)) => {
                    row.frame_ms = m.frame_ms;
                    row.baseline_ms = m.baseline_ms;
                    row.ratio = m.frame_ms / m.baseline_ms;
                    row.t_err_rms = m.t_err_rms();
                    row.skipped_rate = m.skipped_rate();
                    row.past_rate = m.past_rate();
                    row.missed_rate = row.past_rate;
                    row.mean_abs_diff = diff;
                    row.per_wall = m.per_wall.iter().map(WallRow::from).collect();
                }
                Err(e) => {
                    row.status = crate::results::Status::Error;
                    row.error = e.to_string();
                }
            }
            rows.push(row);
            let text: String = rows
                .iter()
                .map(|r| serde_json::to_string(r).map(|s| s + "\n"))
                .collect::<Result<_, _>>()
                .map_err(|e| ResultsError::Encode(e.to_string()))?;
            crate::io::write_atomic(&rows_path(out), text.as_bytes())?;
        }
    }
    Ok(RoomSweep { rows, measured, skipped })
}
