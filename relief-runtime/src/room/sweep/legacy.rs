//! The room rows of an older relief: `DIR/rooms.jsonl`, one object per line in a shape of
//! their own, read once into results rows ([`Row`] with its [`RoomCells`]). Nothing writes
//! this shape any more.

use std::path::Path;

use serde::Deserialize;

use crate::io::FileError;
use crate::results::{null_as_nan, Metrics, ResultsError, RoomCells, Row, Status, WallCells};

/// A line of `rooms.jsonl`.
#[derive(Deserialize)]
struct OldRow {
    room: String,
    variant: String,
    pipeline: String,
    scatter: u32,
    size: u32,
    grid: usize,
    frame_ms: f64,
    baseline_ms: f64,
    t_err_rms: f64,
    #[serde(flatten)]
    rates: OldRates,
    mean_abs_diff: f64,
    status: Status,
    error: String,
    #[serde(default)]
    per_wall: Vec<OldWall>,
}

#[derive(Deserialize)]
struct OldWall {
    wall: String,
    rays: usize,
    t_err_rms: f64,
    #[serde(flatten)]
    rates: OldRates,
}

/// The rates a row and each of its walls carry, each absent or null in some older rows.
#[derive(Deserialize)]
struct OldRates {
    #[serde(default = "not_recorded", deserialize_with = "null_as_nan")]
    skipped_rate: f64,
    #[serde(default = "not_recorded", deserialize_with = "null_as_nan")]
    past_rate: f64,
    #[serde(default = "not_recorded", deserialize_with = "null_as_nan")]
    missed_rate: f64,
}

impl OldRates {
    /// The past rate: a row written before `past_rate` had the name holds it as `missed_rate`.
    fn past(&self) -> f64 {
        if self.past_rate.is_nan() {
            self.missed_rate
        } else {
            self.past_rate
        }
    }
}

/// A measure the row does not hold: NaN, shown as such, never a silent 0.
fn not_recorded() -> f64 {
    f64::NAN
}

/// The rows of `path`, or `None` when there is none. A line that is not such a row, or
/// whose pipeline does not parse, is an error naming the file and the line.
pub(super) fn read(path: &Path) -> Result<Option<Vec<Row>>, ResultsError> {
    if !path.exists() {
        return Ok(None);
    }
    let text = crate::io::read_regular_to_string(path).map_err(|e| FileError::read(path, e))?;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty()) {
        let at = |source| ResultsError::Line { path: path.to_path_buf(), line: i + 1, source };
        let old: OldRow = serde_json::from_str(line).map_err(at)?;
        let pipeline = old.pipeline.parse().map_err(|e| {
            at(serde::de::Error::custom(format_args!("pipeline `{}`: {e}", relief_dsl::spec::echo(&old.pipeline))))
        })?;
        let mut metrics = Metrics::not_measured(pipeline, old.room, old.size, String::new());
        metrics.frame_ms_median = old.frame_ms;
        metrics.ref_err_t_rms = old.t_err_rms;
        metrics.skipped_rate = old.rates.skipped_rate;
        metrics.past_rate = old.rates.past();
        metrics.missed_rate = metrics.past_rate;
        let per_wall = old
            .per_wall
            .into_iter()
            .map(|w| WallCells {
                wall: w.wall,
                rays: w.rays,
                t_err_rms: w.t_err_rms,
                skipped_rate: w.rates.skipped_rate,
                past_rate: w.rates.past(),
            })
            .collect();
        let cell_dir = format!("rooms/{}/{}", super::folder(&metrics.scene), super::folder(&old.variant));
        out.push(Row {
            grid: super::GRID.into(),
            metrics,
            status: old.status,
            error: old.error,
            relief_version: String::new(),
            cell_dir,
            room: Some(RoomCells {
                variant: old.variant,
                scatter: old.scatter,
                wall_grid: old.grid,
                geometry_ms: old.baseline_ms,
                mean_abs_diff: old.mean_abs_diff,
                per_wall,
            }),
            mesh: None,
        });
    }
    Ok(Some(out))
}
