//! Results rows (a leaf): the row type, its columns, and how rows are read, appended and
//! written as CSV. `relief sweep` appends rows; `relief report` reads them with the same
//! rules.
//!
//! `DIR/results.jsonl` holds one JSON object per line and is the source of truth; a row is
//! appended with one write, so a run killed at any moment leaves at most a last line cut
//! short, which every reader drops ([`read`]; [`read_for_append`] also truncates it away).
//! A metric written as `null` (NaN or infinite when measured) reads back as NaN, and so
//! does a metric that older rows lack, never a silent 0.
//! `DIR/results.csv` holds the same rows in the [`COLUMNS`] order.
//!
//! A row of the room comparison (`relief sweep --grid rooms`) is a results row too: its
//! [`Row::room`] holds what a room cell has beyond [`Metrics`] ([`RoomCells`]: the variant,
//! the real-geometry baseline's time, the per-wall accuracy); a plain cell has none, and its
//! line is written without the column.
//!
//! A row of the mesh grid (`relief sweep --grid meshes`) is a results row too: its
//! [`Row::mesh`] holds what a mesh cell measures beyond [`Metrics`] ([`MeshCells`]: coverage,
//! IoU, t, uv and depth error against the exact mesh reference); every other row has none,
//! and its line is written without the column, as before.

use std::io::Write;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::io::FileError;

/// Why a results file could not be read, appended to or written.
#[derive(Debug, thiserror::Error)]
pub enum ResultsError {
    /// A complete line of `results.jsonl` is not a results row; appending after it would
    /// hide the cells it recorded.
    #[error("{}: {text} (not a results row)", path.display())]
    BadLine {
        /// The results file.
        path: PathBuf,
        /// The line's number (from 1); for rows that repeat one cell, the first of them.
        line: usize,
        /// The entry of [`ReadRows::bad_lines`]: `line N: WHY` (a [`RowError`]), or
        /// `lines N, M: …` for rows that repeat one cell.
        text: String,
    },
    /// A line of a rows file that must be whole (an older relief's `rooms.jsonl`) is not a row.
    #[error("{}: line {line}: {source}", path.display())]
    Line {
        /// The rows file.
        path: PathBuf,
        /// The line's number (from 1).
        line: usize,
        /// The JSON reader's error.
        #[source]
        source: serde_json::Error,
    },
    /// Rows that could not be encoded as JSON or CSV (the writers refused a value).
    #[error("cannot encode results rows: {0}")]
    Encode(String),
    /// The file could not be read or written.
    #[error(transparent)]
    File(#[from] FileError),
}

/// Why one line of a results file is not a results row.
#[derive(Debug, thiserror::Error)]
pub enum RowError {
    /// The line does not parse as JSON.
    #[error("not JSON: {0}")]
    NotJson(serde_json::Error),
    /// The line is JSON but not an object.
    #[error("not a JSON object")]
    NotObject,
    /// A column every row has (`pipeline`, `scene`, `size`, `status`) is missing or null.
    #[error("not a results row: no `{0}`")]
    Missing(&'static str),
    /// A column holds a value of the wrong type.
    #[error("not a results row: {0}")]
    Field(serde_json::Error),
    /// The status is neither `ok` nor `error` (quoted, escaped).
    #[error("not a results row: status `{0}` (expected ok or error)")]
    Status(String),
    /// The pipeline column does not parse (the text quoted, escaped).
    #[error("not a results row: pipeline `{pipeline}`: {source}")]
    Pipeline {
        /// The pipeline column, escaped for one line.
        pipeline: String,
        /// The parser's error.
        #[source]
        source: Box<relief_dsl::spec::ParseError>,
    },
}

/// One run's metrics (the names are the column names of results files).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Metrics {
    /// The pipeline as measured, with the scene's `lod` policy applied
    /// ([`crate::scene::Scene::pipeline_for`]); the files hold its canonical text form,
    /// parsed once when a row is read.
    #[serde(with = "pipeline_text")]
    pub pipeline: relief_dsl::Pipeline,
    /// The scene's name; in a sweep the scene argument (`crate::sweep::scene_label`) with
    /// the overrides' suffix.
    pub scene: String,
    /// Side of the square frame, in pixels (one probe ray per pixel that sees the quad).
    pub size: u32,
    /// The GPU adapter and its driver: `NAME (DRIVER VERSION)`.
    pub adapter: String,
    /// Median GPU time of the timed frames' render pass, in milliseconds.
    pub frame_ms_median: f64,
    /// Mean frame time over the timed frames (the dissertation reports the mean of 500).
    #[serde(default)]
    pub frame_ms_mean: f64,
    /// 10th percentile of the frame times (nearest rank), in milliseconds.
    pub frame_ms_p10: f64,
    /// 90th percentile of the frame times (nearest rank), in milliseconds.
    pub frame_ms_p90: f64,
    /// Burger 2018 §4.1: Σ over pixels of (h(hit.uv) − hit.z)², the sum (a NaN hit adds 1,
    /// the largest error a hit in the volume can have).
    pub mse_dissertation: f64,
    /// The same, divided by the number of rays: the per-pixel mean, which is how the
    /// dissertation's numbers behave (Table 4.1's MSE × N² stays near 0.4–0.55 for N = 5…200).
    pub mse_dissertation_mean: f64,
    /// RMS of (t − t_ref) over rays both hit.
    pub ref_err_t_rms: f64,
    /// RMS distance between hit and reference hit in texels.
    pub ref_err_uv_texels_rms: f64,
    /// Median of |t − t_ref| over the rays the reference hits (nearest rank).
    #[serde(default)]
    pub ref_err_t_median: f64,
    /// 90th percentile of |t − t_ref| over the same rays.
    #[serde(default)]
    pub ref_err_t_p90: f64,
    /// 99th percentile of |t − t_ref| over the same rays.
    #[serde(default)]
    pub ref_err_t_p99: f64,
    /// The share of `mse_dissertation` that the worst 1 % of the rays carry
    /// (`crate::metrics::worst_share`); NaN when the MSE is 0.
    #[serde(default)]
    pub mse_worst1_share: f64,
    /// Share of rays that jumped over geometry: the reported hit lies beyond a point where
    /// the ray, after the exact first hit, is back above the surface it sampled
    /// ([`crate::metrics::Accuracy::skipped`]); resolution-independent.
    #[serde(default)]
    pub skipped_rate: f64,
    /// Share of rays whose hit lies beyond the true first hit by more than one texel of
    /// travel ([`crate::metrics::one_texel_t`]), or that report no (finite) hit. Says
    /// nothing of skipped geometry at high resolution (see `skipped_rate`).
    #[serde(default)]
    pub past_rate: f64,
    /// The old name of `past_rate`, written beside it for one release (the same value).
    pub missed_rate: f64,
    /// Share of rays the pipeline reports a hit for where the reference has none (with
    /// `silhouette=clip`: a hit kept inside the square where the true first hit lies
    /// outside it, or the ray leaves the square first).
    #[serde(default)]
    pub false_hit_rate: f64,
    /// Hits with NaN or Inf anywhere.
    pub nan_count: u64,
    /// Hits whose raw t lies outside the volume (`t < 0` or `t > t_max`), counted before any
    /// clamp.
    #[serde(default)]
    pub outside_count: u64,
    /// Share of rays whose coarse search ran out of steps without finding the surface.
    #[serde(default)]
    pub nonconverged_rate: f64,
    /// Loop passes of the coarse search per ray (the dissertation's "avg steps").
    #[serde(default)]
    pub avg_coarse_steps: f64,
    /// Loop passes of the refine search per ray.
    #[serde(default)]
    pub avg_refine_steps: f64,
    /// Loop passes over all stages per ray (coarse + refine).
    pub avg_iterations: f64,
    /// Texture fetches per ray over all stages.
    pub avg_fetches: f64,
    /// The SIMD cost model (`crate::simd`): the largest coarse + refine step count of a
    /// group of 32 rays (8 × 4 pixels), averaged over groups.
    #[serde(default)]
    pub simd32_steps: f64,
    /// The same for groups of 64 rays (8 × 8 pixels).
    #[serde(default)]
    pub simd64_steps: f64,
    /// The largest fetch count of a group of 32 rays, averaged over groups.
    #[serde(default)]
    pub simd32_fetches: f64,
    /// A group of 32's largest step count over its mean, averaged over groups.
    #[serde(default)]
    pub simd32_divergence: f64,
    /// The pipeline the cell was timed against in alternating blocks (paired timing,
    /// `crate::timing`); empty when it was timed alone.
    #[serde(default)]
    pub baseline: String,
    /// The cell's mean frame time over the baseline's, from the paired blocks.
    #[serde(default)]
    pub frame_ratio_to_baseline: Option<f64>,
    /// Lower end of the ratio's 95 % interval.
    #[serde(default)]
    pub frame_ratio_to_baseline_lo: Option<f64>,
    /// Upper end of the ratio's 95 % interval.
    #[serde(default)]
    pub frame_ratio_to_baseline_hi: Option<f64>,
    /// Pairs of blocks behind the ratio (0 when timed alone).
    #[serde(default)]
    pub timing_pairs: u32,
    /// Frames per timed block (each block lasts at least 2 ms of device time); 0 when not
    /// recorded.
    #[serde(default)]
    pub frames_per_block: u32,
    /// The device timer's tick, in nanoseconds (`wgpu::Queue::get_timestamp_period`).
    #[serde(default)]
    pub timestamp_period_ns: f64,
    /// With `relief render --write-depth`: the largest |NDC depth − the reference hit's NDC
    /// depth| over the covered pixels.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub depth_err_max: Option<f64>,
    /// The GPU compiler's driver that priced the pipeline (`cost`), e.g. `radv Mesa 22.3.6`;
    /// absent (with every `gpu_*` column) when the sweep ran without RADV.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gpu_driver: Option<String>,
    /// A model, not a clock (`crate::cost`): instructions a lane of the render entry's
    /// fragment shader issues on RDNA2 (navi21), its SIMD group at the compiler's wave size
    /// running each loop as many passes as its slowest lane, averaged over groups.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gpu_navi21_instr_px: Option<f64>,
    /// The same model in groups of 32 lanes (8 × 4 pixels) on RDNA2 (navi21).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gpu_navi21_instr_w32: Option<f64>,
    /// Vector registers of the fragment shader on RDNA2 (navi21).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gpu_navi21_vgprs: Option<u32>,
    /// Instructions of the fragment shader on RDNA2 (navi21) (the compiler's static count).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gpu_navi21_instructions: Option<u32>,
    /// The fragment shader's coarse and refine loop bodies on RDNA2 (navi21), summed (0: no loop,
    /// or the compiler unrolled it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gpu_navi21_loop_body: Option<u32>,
    /// A model, not a clock (`crate::cost`): instructions a lane of the render entry's
    /// fragment shader issues on RDNA3 (gfx1100), its SIMD group at the compiler's wave size
    /// running each loop as many passes as its slowest lane, averaged over groups.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gpu_gfx1100_instr_px: Option<f64>,
    /// The same model in groups of 32 lanes (8 × 4 pixels) on RDNA3 (gfx1100).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gpu_gfx1100_instr_w32: Option<f64>,
    /// Vector registers of the fragment shader on RDNA3 (gfx1100).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gpu_gfx1100_vgprs: Option<u32>,
    /// Instructions of the fragment shader on RDNA3 (gfx1100) (the compiler's static count).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gpu_gfx1100_instructions: Option<u32>,
    /// The fragment shader's coarse and refine loop bodies on RDNA3 (gfx1100), summed (0: no loop,
    /// or the compiler unrolled it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gpu_gfx1100_loop_body: Option<u32>,
}

/// Every metric zero or absent, the naming fields empty, and a placeholder pipeline (`none`
/// in every slot, which no results file can hold): a row to fill in.
impl Default for Metrics {
    fn default() -> Self {
        use relief_dsl::spec::StageSpec;
        Metrics {
            pipeline: relief_dsl::Pipeline::new(
                StageSpec::none(),
                StageSpec::none(),
                StageSpec::none(),
                StageSpec::none(),
            ),
            scene: String::new(),
            size: 0,
            adapter: String::new(),
            frame_ms_median: 0.0,
            frame_ms_mean: 0.0,
            frame_ms_p10: 0.0,
            frame_ms_p90: 0.0,
            mse_dissertation: 0.0,
            mse_dissertation_mean: 0.0,
            ref_err_t_rms: 0.0,
            ref_err_uv_texels_rms: 0.0,
            ref_err_t_median: 0.0,
            ref_err_t_p90: 0.0,
            ref_err_t_p99: 0.0,
            mse_worst1_share: 0.0,
            skipped_rate: 0.0,
            past_rate: 0.0,
            missed_rate: 0.0,
            false_hit_rate: 0.0,
            nan_count: 0,
            outside_count: 0,
            nonconverged_rate: 0.0,
            avg_coarse_steps: 0.0,
            avg_refine_steps: 0.0,
            avg_iterations: 0.0,
            avg_fetches: 0.0,
            simd32_steps: 0.0,
            simd64_steps: 0.0,
            simd32_fetches: 0.0,
            simd32_divergence: 0.0,
            baseline: String::new(),
            frame_ratio_to_baseline: None,
            frame_ratio_to_baseline_lo: None,
            frame_ratio_to_baseline_hi: None,
            timing_pairs: 0,
            frames_per_block: 0,
            timestamp_period_ns: 0.0,
            depth_err_max: None,
            gpu_driver: None,
            gpu_navi21_instr_px: None,
            gpu_navi21_instr_w32: None,
            gpu_navi21_vgprs: None,
            gpu_navi21_instructions: None,
            gpu_navi21_loop_body: None,
            gpu_gfx1100_instr_px: None,
            gpu_gfx1100_instr_w32: None,
            gpu_gfx1100_vgprs: None,
            gpu_gfx1100_instructions: None,
            gpu_gfx1100_loop_body: None,
        }
    }
}

/// A pipeline in a results file: its canonical text form ([`relief_dsl::Pipeline`]'s
/// `Display`), parsed back with its `FromStr`.
mod pipeline_text {
    use serde::{Deserialize, Deserializer, Serializer};

    pub(super) fn serialize<S: Serializer>(p: &relief_dsl::Pipeline, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(p)
    }

    pub(super) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<relief_dsl::Pipeline, D::Error> {
        let text = String::deserialize(d)?;
        text.parse()
            .map_err(|e| serde::de::Error::custom(format_args!("pipeline `{}`: {e}", relief_dsl::spec::echo(&text))))
    }
}

/// Whether a cell was measured or failed; the files hold `ok` or `error`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// Measured: every metric is the cell's (`ok`).
    #[default]
    Ok,
    /// Failed: the row's error says why; only the key columns are set (`error`).
    Error,
}

impl Status {
    /// Whether the cell was measured.
    pub fn is_ok(self) -> bool {
        self == Status::Ok
    }

    /// The word the files hold: `ok` or `error`.
    pub fn as_str(self) -> &'static str {
        match self {
            Status::Ok => "ok",
            Status::Error => "error",
        }
    }
}

impl std::fmt::Display for Status {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// One results row: the metrics and where they came from.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct Row {
    /// The name of the grid the cell belongs to (`t4.1`, `dissertation`, …).
    pub grid: String,
    /// The cell's metrics; in the files their fields are columns of the row itself. Only
    /// the pipeline, scene, size and adapter are set for a failed cell.
    #[serde(flatten)]
    pub metrics: Metrics,
    /// Measured or failed (`ok` or `error` in the files).
    pub status: Status,
    /// The error of a failed cell (empty otherwise).
    pub error: String,
    /// The version of relief-runtime that measured the row.
    pub relief_version: String,
    /// The cell's folder, relative to the sweep's folder (holds frame.png and error.png; a
    /// room cell's frame.png, baseline.png and diff.png; a mesh cell's frame.png and coverage.png).
    pub cell_dir: String,
    /// A room cell's own columns (`relief sweep --grid rooms`); `None` for every other cell,
    /// whose line has no `room` column.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub room: Option<RoomCells>,
    /// A mesh cell's own columns (`relief sweep --grid meshes`); `None` for every other cell,
    /// whose line has no `mesh` column.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mesh: Option<MeshCells>,
}

/// What a mesh cell (`crate::sweep::meshes`) records beyond [`Metrics`]: one `curved=` mode's
/// figures against the exact mesh reference (`crate::mesh_measure::MeshScore`, whose doc
/// defines each). In its row the metrics hold the pipeline with its `curved=` option, the
/// scene argument with its view, and the frame time over `curved=none`'s with the same stages
/// (`baseline`, `frame_ratio_to_baseline` and its interval, paired blocks; none for
/// `curved=none` itself); the metrics a mesh cell does not measure are NaN.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct MeshCells {
    /// The mesh drawn (`sphere`, `torus`, a file's mesh).
    pub name: String,
    /// Pixels in the frame.
    pub pixels: usize,
    /// Pixels both the pipeline and the reference hit.
    pub both: usize,
    /// Pixels the pipeline draws and the reference does not hit.
    pub extra: usize,
    /// Pixels the reference hits and the pipeline does not draw.
    pub missing: usize,
    /// `(extra + missing) / pixels` (a share, not a percentage).
    #[serde(deserialize_with = "null_as_nan")]
    pub coverage_error: f64,
    /// `both / (both + extra + missing)`.
    #[serde(deserialize_with = "null_as_nan")]
    pub iou: f64,
    /// RMS of `(t − t_ref) / depth` on pixels both hit (NaN when none).
    #[serde(deserialize_with = "null_as_nan")]
    pub rms_t: f64,
    /// The largest `(t_ref − t) / depth` on pixels both hit: how far a hit came before the
    /// exact first hit (NaN when none).
    #[serde(deserialize_with = "null_as_nan")]
    pub earliest: f64,
    /// RMS uv distance in texels on pixels both hit.
    #[serde(deserialize_with = "null_as_nan")]
    pub uv_texels: f64,
    /// RMS NDC depth difference on pixels both hit.
    #[serde(deserialize_with = "null_as_nan")]
    pub depth: f64,
}

/// What a room cell (`crate::room::sweep`) records beyond [`Metrics`]. In its row the
/// metrics hold the pipeline on every wall, the room's name as the scene, the median interior
/// frame time (`frame_ms_median`), the RMS t error over all walls (`ref_err_t_rms`) and the
/// skipped and past rates over all walls; the metrics a room cell does not measure are NaN.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct RoomCells {
    /// The variant of the comparison (`crate::room::sweep::Variant::label`): with the room,
    /// the size and `wall_grid`, the cell's key (two variants share a pipeline).
    pub variant: String,
    /// Light-scattering samples (0: off).
    pub scatter: u32,
    /// Vertices a side of each wall's grid in the real-geometry baseline.
    pub wall_grid: usize,
    /// Median frame time of the real-geometry baseline, ms.
    #[serde(deserialize_with = "null_as_nan")]
    pub geometry_ms: f64,
    /// Mean |interior − baseline| per 8-bit channel.
    #[serde(deserialize_with = "null_as_nan")]
    pub mean_abs_diff: f64,
    /// Each wall's accuracy.
    #[serde(default)]
    pub per_wall: Vec<WallCells>,
}

impl RoomCells {
    /// The interior's median frame time over the baseline's.
    pub fn ratio(&self, m: &Metrics) -> f64 {
        m.frame_ms_median / self.geometry_ms
    }
}

/// One wall's accuracy in a room cell ([`RoomCells::per_wall`]).
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct WallCells {
    /// The wall.
    pub wall: String,
    /// Rays the host sends to it.
    pub rays: usize,
    /// RMS t error.
    #[serde(deserialize_with = "null_as_nan")]
    pub t_err_rms: f64,
    /// Share that jumped over geometry (`crate::room::accuracy::WallAccuracy::skipped_rate`).
    #[serde(deserialize_with = "null_as_nan")]
    pub skipped_rate: f64,
    /// Share past the exact hit by more than a texel of travel
    /// (`crate::room::accuracy::WallAccuracy::past_rate`).
    #[serde(deserialize_with = "null_as_nan")]
    pub past_rate: f64,
}

/// A number written as `null` (NaN or infinite when measured) reads back as NaN.
pub(crate) fn null_as_nan<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// The columns of `results.csv`, in order.
pub const COLUMNS: &[&str] = &[
    "grid",
    "pipeline",
    "scene",
    "size",
    "adapter",
    "status",
    "error",
    "relief_version",
    "frame_ms_median",
    "frame_ms_mean",
    "frame_ms_p10",
    "frame_ms_p90",
    "mse_dissertation",
    "mse_dissertation_mean",
    "ref_err_t_rms",
    "ref_err_uv_texels_rms",
    "ref_err_t_median",
    "ref_err_t_p90",
    "ref_err_t_p99",
    "mse_worst1_share",
    "skipped_rate",
    "past_rate",
    "missed_rate",
    "false_hit_rate",
    "nan_count",
    "outside_count",
    "nonconverged_rate",
    "avg_coarse_steps",
    "avg_refine_steps",
    "avg_iterations",
    "avg_fetches",
    "simd32_steps",
    "simd64_steps",
    "simd32_fetches",
    "simd32_divergence",
    "baseline",
    "frame_ratio_to_baseline",
    "frame_ratio_to_baseline_lo",
    "frame_ratio_to_baseline_hi",
    "timing_pairs",
    "frames_per_block",
    "timestamp_period_ns",
    "cell_dir",
];

/// The GPU compiler's columns (`crate::cost`), after [`COLUMNS`] in `results.csv` when any
/// row has them: a sweep without RADV writes none.
pub const GPU_COLUMNS: &[&str] = &[
    "gpu_driver",
    "gpu_navi21_instr_px",
    "gpu_navi21_instr_w32",
    "gpu_navi21_vgprs",
    "gpu_navi21_instructions",
    "gpu_navi21_loop_body",
    "gpu_gfx1100_instr_px",
    "gpu_gfx1100_instr_w32",
    "gpu_gfx1100_vgprs",
    "gpu_gfx1100_instructions",
    "gpu_gfx1100_loop_body",
];

/// A room cell's columns ([`RoomCells`], less its per-wall list), after the others in
/// `results.csv` when any row is a room cell's.
pub const ROOM_COLUMNS: &[&str] = &["variant", "scatter", "wall_grid", "geometry_ms", "mean_abs_diff"];
/// A mesh cell's columns ([`MeshCells`], each field `F` as `mesh_F`), after the others in
/// `results.csv` when any row is a mesh cell's.
pub const MESH_COLUMNS: &[&str] = &[
    "mesh_name",
    "mesh_pixels",
    "mesh_both",
    "mesh_extra",
    "mesh_missing",
    "mesh_coverage_error",
    "mesh_iou",
    "mesh_rms_t",
    "mesh_earliest",
    "mesh_uv_texels",
    "mesh_depth",
];

/// The file rows are appended to, in a sweep folder.
pub(crate) const JSONL: &str = "results.jsonl";

/// The name of the rows' CSV copy in a sweep's folder.
pub(crate) const CSV: &str = "results.csv";

/// What [`read`] found.
#[derive(Clone, Debug, Default)]
pub struct ReadRows {
    /// The readable rows, in file order.
    pub rows: Vec<Row>,
    /// The lines that could not be read (`line N: reason`), a cut last line included.
    pub bad_lines: Vec<String>,
    /// The length in bytes of the file up to its last complete line.
    complete_len: usize,
    /// Whether the last line was cut short (no newline after it).
    cut: bool,
    /// The (first) line number of each entry of `bad_lines`.
    bad_at: Vec<usize>,
}

/// Reads `dir/results.jsonl` without changing it. A last line without its newline (a kill
/// cut it short) is dropped and named in `bad_lines`; so is every complete line that is not
/// a results row (`parse_row`). A missing file gives no rows.
pub fn read(dir: &Path) -> Result<ReadRows, FileError> {
    let path = dir.join(JSONL);
    let text = match crate::io::read_regular(&path) {
        Ok(b) => String::from_utf8_lossy(&b).into_owned(),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => String::new(),
        Err(e) => return Err(FileError::read(&path, e)),
    };
    let complete = match text.rfind('\n') {
        Some(i) => &text[..=i],
        None => "",
    };
    let mut out = ReadRows { complete_len: complete.len(), cut: complete.len() != text.len(), ..Default::default() };
    let lines = complete.lines().count();
    let mut numbered = Vec::new();
    for (i, line) in complete.lines().enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        match parse_row(line) {
            Ok(r) => numbered.push((i + 1, r)),
            Err(e) => {
                out.bad_lines.push(format!("line {}: {e}", i + 1));
                out.bad_at.push(i + 1);
            }
        }
    }
    let (rows, duplicates) = without_duplicates(numbered);
    out.rows = rows;
    for (line, message) in duplicates {
        out.bad_lines.push(message);
        out.bad_at.push(line);
    }
    if out.cut {
        out.bad_lines.push(format!("line {}: cut short (no newline at the end), ignored", lines + 1));
        out.bad_at.push(lines + 1);
    }
    Ok(out)
}

/// A cell's key ([`cell_key`]).
pub(crate) type CellKey = (String, String, u32, String, Option<(String, usize)>);

/// A cell's key: the pipeline's canonical text, the scene, the size and the adapter, and a
/// room cell's variant and wall grid. A results file holds one row per key.
pub(crate) fn cell_key(r: &Row) -> CellKey {
    let m = &r.metrics;
    let room = r.room.as_ref().map(|c| (c.variant.clone(), c.wall_grid));
    (m.pipeline.to_string(), m.scene.clone(), m.size, m.adapter.clone(), room)
}

/// `rows` (with their line numbers) less every row whose cell key ([`cell_key`]) is on
/// more than one line, and one message per such key naming it and its lines (with the
/// first of them): which of two
/// rows for one cell is right cannot be told (two sweeps wrote into one folder at once,
/// or a file was edited), so neither is chosen.
fn without_duplicates(rows: Vec<(usize, Row)>) -> (Vec<Row>, Vec<(usize, String)>) {
    let mut lines_of: std::collections::HashMap<_, Vec<usize>> = std::collections::HashMap::new();
    let keys: Vec<_> = rows.iter().map(|(_, r)| cell_key(r)).collect();
    for ((line, _), k) in rows.iter().zip(&keys) {
        lines_of.entry(k.clone()).or_default().push(*line);
    }
    let mut messages = Vec::new();
    let mut kept = Vec::new();
    for ((line, r), k) in rows.into_iter().zip(keys) {
        let lines = &lines_of[&k];
        if lines.len() == 1 {
            kept.push(r);
        } else if lines[0] == line {
            let list: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
            messages.push((
                line,
                format!(
                "lines {}: {} rows for one cell (pipeline {}, scene {}, size {}, adapter {}{}), all left out: keep one",
                list.join(", "),
                lines.len(),
                relief_dsl::spec::echo(&k.0),
                relief_dsl::spec::echo(&k.1),
                k.2,
                relief_dsl::spec::echo(&k.3),
                k.4.as_ref()
                    .map(|(v, g)| format!(", variant {}, wall grid {g}", relief_dsl::spec::echo(v)))
                    .unwrap_or_default()
            ),
            ));
        }
    }
    (kept, messages)
}

/// Reads `dir/results.jsonl` to append to it: the rows of [`read`], the file truncated to
/// its last complete line first. An unreadable complete line is an error (appending after
/// it would hide the cells it recorded).
pub fn read_for_append(dir: &Path) -> Result<Vec<Row>, ResultsError> {
    let path = dir.join(JSONL);
    let read = read(dir)?;
    if read.cut {
        let f = std::fs::OpenOptions::new().write(true).open(&path).map_err(|e| FileError::write(&path, e))?;
        f.set_len(read.complete_len as u64).map_err(|e| FileError::write(&path, e))?;
    }
    let bad = if read.cut { read.bad_lines.len() - 1 } else { read.bad_lines.len() };
    if bad > 0 {
        return Err(ResultsError::BadLine { path, line: read.bad_at[0], text: read.bad_lines[0].clone() });
    }
    Ok(read.rows)
}

/// Appends `row` to `dir/results.jsonl` with one write of the whole line, synced: a kill
/// leaves either the whole row or a cut line, which the next read drops.
pub fn append(dir: &Path, row: &Row) -> Result<(), ResultsError> {
    let path = dir.join(JSONL);
    let mut line = serde_json::to_string(row).map_err(|e| ResultsError::Encode(e.to_string()))?;
    line.push('\n');
    let write = || -> std::io::Result<()> {
        let mut f = std::fs::OpenOptions::new().create(true).append(true).open(&path)?;
        f.write_all(line.as_bytes())?;
        f.sync_data()
    };
    write().map_err(|e| FileError::write(&path, e))?;
    Ok(())
}

/// Rewrites `dir/results.jsonl` with `rows`, one line each, atomically
/// ([`crate::io::write_atomic`]): for a change that removes rows, where [`append`] cannot.
pub(crate) fn write_jsonl(dir: &Path, rows: &[Row]) -> Result<(), ResultsError> {
    let mut text = String::new();
    for r in rows {
        text.push_str(&serde_json::to_string(r).map_err(|e| ResultsError::Encode(e.to_string()))?);
        text.push('\n');
    }
    Ok(crate::io::write_atomic(&dir.join(JSONL), text.as_bytes())?)
}

/// `rows` as `results.csv` text, [`COLUMNS`] in order (NaN and infinite metrics empty).
pub(crate) fn csv_bytes(rows: &[Row]) -> Result<Vec<u8>, ResultsError> {
    let encode = |e: &dyn std::fmt::Display| ResultsError::Encode(e.to_string());
    let mut w = csv::Writer::from_writer(Vec::new());
    let mut columns = COLUMNS.to_vec();
    if rows.iter().any(|r| r.metrics.gpu_driver.is_some()) {
        columns.extend(GPU_COLUMNS);
    }
    let plain = columns.len();
    if rows.iter().any(|r| r.room.is_some()) {
        columns.extend(ROOM_COLUMNS);
    }
    if rows.iter().any(|r| r.mesh.is_some()) {
        columns.extend(MESH_COLUMNS);
    }
    w.write_record(&columns).map_err(|e| encode(&e))?;
    for r in rows {
        let v = serde_json::to_value(r).map_err(|e| encode(&e))?;
        let record: Vec<String> = columns
            .iter()
            .enumerate()
            .map(|(i, c)| {
                match if i < plain {
                    &v[*c]
                } else if let Some(field) = c.strip_prefix("mesh_") {
                    &v["mesh"][field]
                } else {
                    &v["room"][*c]
                } {
                    serde_json::Value::String(s) => s.clone(),
                    serde_json::Value::Null => String::new(),
                    other => other.to_string(),
                }
            })
            .collect();
        w.write_record(&record).map_err(|e| encode(&e))?;
    }
    w.into_inner().map_err(|e| encode(&e))
}

/// Rewrites `dir/results.csv` from `rows`, atomically ([`crate::io::write_atomic`]).
pub fn write_csv(dir: &Path, rows: &[Row]) -> Result<(), ResultsError> {
    Ok(crate::io::write_atomic(&dir.join(CSV), &csv_bytes(rows)?)?)
}

/// Parses one results line; numbers written as `null` (NaN or infinite when measured) come
/// back as NaN. A row must have a `pipeline` that parses, a `scene`, a `size` and a
/// `status` of `ok` or `error`; other columns an older row lacks take their defaults.
pub(crate) fn parse_row(line: &str) -> Result<Row, RowError> {
    let v: serde_json::Value = serde_json::from_str(line).map_err(RowError::NotJson)?;
    let serde_json::Value::Object(obj) = v else {
        return Err(RowError::NotObject);
    };
    for k in ["pipeline", "scene", "size", "status"] {
        if obj.get(k).is_none_or(|v| v.is_null()) {
            return Err(RowError::Missing(k));
        }
    }
    let mut obj = obj;
    // A row written before `past_rate` had the name: `missed_rate` is the same measure.
    if !obj.contains_key("past_rate") {
        if let Some(v) = obj.get("missed_rate").cloned() {
            obj.insert("past_rate".into(), v);
        }
    }
    match obj.get("status") {
        Some(serde_json::Value::String(w)) if w == Status::Ok.as_str() || w == Status::Error.as_str() => {}
        Some(serde_json::Value::String(w)) => return Err(RowError::Status(relief_dsl::spec::echo(w))),
        Some(other) => return Err(RowError::Status(relief_dsl::spec::echo(&other.to_string()))),
        None => return Err(RowError::Missing("status")),
    }
    let pipeline_text = obj.get("pipeline").and_then(|v| v.as_str()).map(str::to_string);
    let mut base = serde_json::to_value(Row::default()).map_err(RowError::Field)?;
    let mut nulls = Vec::new();
    // Fields that older rows lack: not recorded, so NaN (shown as such),
    // never a silent 0.
    for k in LATER_FIELDS {
        if !obj.contains_key(*k) {
            nulls.push(k.to_string());
        }
    }
    if let serde_json::Value::Object(b) = &mut base {
        for (k, val) in obj {
            if val.is_null() {
                nulls.push(k);
            } else {
                b.insert(k, val);
            }
        }
    }
    // The pipeline is parsed here, once (`pipeline_text`); a row whose pipeline does not
    // parse is named as such.
    let mut row: Row = serde_json::from_value(base).map_err(|e| {
        match pipeline_text.as_deref().map(|t| (t, t.parse::<relief_dsl::Pipeline>())) {
            Some((t, Err(source))) => {
                RowError::Pipeline { pipeline: relief_dsl::spec::echo(t), source: Box::new(source) }
            }
            _ => RowError::Field(e),
        }
    })?;
    for k in nulls {
        set_nan(&mut row.metrics, &k);
    }
    Ok(row)
}

/// Metrics fields added after the first results files (absent from older ones).
const LATER_FIELDS: &[&str] = &[
    "frame_ms_mean",
    "avg_coarse_steps",
    "avg_refine_steps",
    "nonconverged_rate",
    "false_hit_rate",
    "simd32_steps",
    "simd64_steps",
    "simd32_fetches",
    "simd32_divergence",
    "timestamp_period_ns",
    "ref_err_t_median",
    "ref_err_t_p90",
    "ref_err_t_p99",
    "mse_worst1_share",
    "skipped_rate",
    "past_rate",
];

impl Metrics {
    /// The metrics of a cell that measures none but the ones its caller sets: the naming
    /// columns given, every number NaN (never a silent 0), the counts 0.
    pub(crate) fn not_measured(pipeline: relief_dsl::Pipeline, scene: String, size: u32, adapter: String) -> Metrics {
        let mut m = Metrics { pipeline, scene, size, adapter, ..Default::default() };
        for f in NUMBERS {
            set_nan(&mut m, f);
        }
        m
    }
}

/// The `f64` metrics a row may leave unmeasured, named once: [`NUMBERS`] lists them and
/// [`set_nan`] sets one by its column name.
macro_rules! numbers {
    ($($field:ident),* $(,)?) => {
        /// Every `f64` metric [`set_nan`] knows.
        const NUMBERS: &[&str] = &[$(stringify!($field)),*];

        /// Sets the `f64` metric named `field` to NaN (a name not in [`NUMBERS`] is left alone).
        fn set_nan(m: &mut Metrics, field: &str) {
            match field {
                $(stringify!($field) => m.$field = f64::NAN,)*
                _ => {}
            }
        }
    };
}

numbers!(
    frame_ms_median,
    frame_ms_mean,
    avg_coarse_steps,
    avg_refine_steps,
    nonconverged_rate,
    frame_ms_p10,
    frame_ms_p90,
    mse_dissertation,
    mse_dissertation_mean,
    ref_err_t_rms,
    ref_err_uv_texels_rms,
    missed_rate,
    past_rate,
    skipped_rate,
    ref_err_t_median,
    ref_err_t_p90,
    ref_err_t_p99,
    mse_worst1_share,
    false_hit_rate,
    avg_iterations,
    avg_fetches,
    simd32_steps,
    simd64_steps,
    simd32_fetches,
    simd32_divergence,
    timestamp_period_ns,
);
