//! The room grid of `relief sweep --grid rooms`: Amaro & Gustafsson 2022's comparison (§3.1.3) of interior
//! mapping alone, + POM, + soft shadows, + light scattering, each against the same room as
//! real geometry, on every room asked for. Each cell's row is a results row
//! ([`crate::results::Row`], its room columns in [`Row::room`]) appended to
//! `DIR/results.jsonl` like any sweep's (so a kill loses at most the cell in flight),
//! pictures go to `DIR/rooms/ROOM/VARIANT/`; a rerun keeps the cells already measured at the
//! same size and wall grid and measures the rest (a failed cell again). `relief report DIR`
//! reads the rows into its room section. An older relief wrote the rows to `DIR/rooms.jsonl`
//! in a shape of their own: [`read_rows`] still reads them, and the next [`run`] moves them
//! into `results.jsonl`.

use std::path::{Path, PathBuf};

use super::accuracy::WallAccuracy;
use super::measure::{measure_room, write_images, RoomSetup};
use super::room_from_arg;
use crate::error::{Error, Result};
use crate::gpu::Gpu;
use crate::results::{Metrics, ResultsError, RoomCells, Row, Status, WallCells};
use relief_dsl::compose::interior::RoomOptions;
use relief_dsl::Pipeline;

mod legacy;

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

/// The grid name a room cell's row carries ([`Row::grid`]).
pub const GRID: &str = "rooms";

impl From<&WallAccuracy> for WallCells {
    fn from(a: &WallAccuracy) -> WallCells {
        WallCells {
            wall: a.wall.clone(),
            rays: a.rays,
            t_err_rms: a.t_err_rms,
            skipped_rate: a.skipped_rate,
            past_rate: a.past_rate,
        }
    }
}

/// The rows file of a sweep folder: `results.jsonl`, where every cell's row goes.
pub fn rows_path(dir: &Path) -> PathBuf {
    dir.join(crate::results::JSONL)
}

/// The rows file of an older relief, which kept the room cells apart (read by
/// [`read_rows`], folded into `results.jsonl` by the next [`run`]).
pub fn legacy_path(dir: &Path) -> PathBuf {
    dir.join("rooms.jsonl")
}

/// The room cells' rows of the sweep folder `dir`, typed once: those of `results.jsonl`
/// ([`crate::results::read`]: unreadable lines are left out there, and named by the
/// report), then those of an older relief's `rooms.jsonl` whose cell `results.jsonl` does not
/// hold (read by `legacy.rs`, beside this file). Empty when the folder holds no room cell.
pub fn read_rows(dir: &Path) -> Result<Vec<Row>, ResultsError> {
    let mut rows: Vec<Row> = crate::results::read(dir)?.rows.into_iter().filter(|r| r.room.is_some()).collect();
    add_legacy(dir, &mut rows)?;
    Ok(rows)
}

/// Adds to `rows` the rows of `dir/rooms.jsonl` (an older relief's) whose cell (room, variant,
/// pipeline, size and wall grid; the older rows have no adapter) `rows` lacks; whether the
/// file was there.
pub(crate) fn add_legacy(dir: &Path, rows: &mut Vec<Row>) -> Result<bool, ResultsError> {
    let Some(old) = legacy::read(&legacy_path(dir))? else { return Ok(false) };
    // The cell without its adapter, which the older rows do not record.
    let cell = |r: &Row| {
        let (pipeline, scene, size, _, room) = crate::results::cell_key(r);
        (pipeline, scene, size, room)
    };
    let keys: Vec<_> = rows.iter().map(cell).collect();
    rows.extend(old.into_iter().filter(|r| !keys.contains(&cell(r))));
    Ok(true)
}

fn folder(s: &str) -> String {
    s.chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '.' { c } else { '_' }).collect()
}

/// What [`run`] did.
pub struct RoomSweep {
    /// Every room cell's row in the folder: those kept from earlier runs, then the new ones.
    pub rows: Vec<Row>,
    /// Cells measured by this run.
    pub measured: usize,
    /// Cells kept from an earlier run.
    pub skipped: usize,
}

/// Measures every variant in every room of `rooms` (`room:NAME` or room files) that the
/// folder's rows do not already hold (ok, same size and wall grid) and appends a row for each
/// to `results.jsonl`, beside any other cells' rows, which it keeps as they are. Failed room
/// cells are measured again: their rows are dropped first (the file rewritten once,
/// atomically), and so is an older relief's `rooms.jsonl`, whose rows move into
/// `results.jsonl`.
pub fn run(rooms: &[String], setup: &RoomSetup, out: &Path) -> Result<RoomSweep> {
    crate::io::create_dir_all(out)?;
    let mut all = crate::results::read_for_append(out)?;
    let before = all.len();
    let legacy = add_legacy(out, &mut all)?;
    let same_cell = |r: &Row, room: &str, variant: &str| {
        r.metrics.scene == room
            && r.metrics.size == setup.size
            && r.room.as_ref().is_some_and(|c| c.variant == variant && c.wall_grid == setup.grid)
    };
    let gpu = Gpu::new()?;
    let adapter = format!("{} ({})", gpu.adapter, gpu.driver);
    // Failed cells are measured again: only ok rows are kept.
    all.retain(|r| r.room.is_none() || r.status.is_ok());
    if legacy || all.len() != before {
        crate::results::write_jsonl(out, &all)?;
        crate::results::write_csv(out, &all)?;
        if legacy {
            let old = legacy_path(out);
            std::fs::remove_file(&old).map_err(|e| crate::io::FileError::write(&old, e))?;
        }
    }
    let (mut measured, mut skipped) = (0, 0);
    for arg in rooms {
        let (room, warnings) = room_from_arg(Some(arg), None).map_err(Error::Room)?;
        for w in &warnings {
            eprintln!("relief: warning: {w}");
        }
        for v in variants() {
            if all.iter().any(|r| same_cell(r, &room.name, v.label)) {
                skipped += 1;
                continue;
            }
            measured += 1;
            let p: Pipeline = v.pipeline.parse().map_err(|e| Error::from(e).in_pipeline(v.pipeline))?;
            let cell_dir = format!("rooms/{}/{}", folder(&room.name), folder(v.label));
            let mut row = Row {
                grid: GRID.into(),
                metrics: Metrics::not_measured(p.clone(), room.name.clone(), setup.size, adapter.clone()),
                status: Status::Ok,
                error: String::new(),
                relief_version: env!("CARGO_PKG_VERSION").into(),
                cell_dir: cell_dir.clone(),
                room: None,
                mesh: None,
            };
            let mut cells = RoomCells {
                variant: v.label.into(),
                scatter: v.scatter.unwrap_or(0),
                wall_grid: setup.grid,
                geometry_ms: f64::NAN,
                mean_abs_diff: f64::NAN,
                per_wall: Vec::new(),
            };
            match measure_room(&gpu, &room, &p, &RoomOptions { scatter: v.scatter }, setup)
                .and_then(|m| Ok((write_images(&out.join(&cell_dir), setup.size, &m)?, m)))
            {
                Ok((diff, m)) => {
                    row.metrics.frame_ms_median = m.frame_ms;
                    row.metrics.ref_err_t_rms = m.t_err_rms();
                    row.metrics.skipped_rate = m.skipped_rate();
                    row.metrics.past_rate = m.past_rate();
                    row.metrics.missed_rate = row.metrics.past_rate;
                    cells.geometry_ms = m.baseline_ms;
                    cells.mean_abs_diff = diff;
                    cells.per_wall = m.per_wall.iter().map(WallCells::from).collect();
                }
                Err(e) => {
                    row.status = Status::Error;
                    row.error = e.to_string();
                }
            }
            row.room = Some(cells);
            crate::results::append(out, &row)?;
            all.push(row);
            crate::results::write_csv(out, &all)?;
        }
    }
    Ok(RoomSweep { rows: all.into_iter().filter(|r| r.room.is_some()).collect(), measured, skipped })
}
