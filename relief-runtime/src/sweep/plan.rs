//! What `relief sweep --grid NAME` measures, as one entry for every grid: the cells of a
//! built-in grid or a grid file ([`super::run`]), the room comparison `rooms`
//! ([`crate::room::sweep`], its rows with their room columns), or the mesh grid `meshes`
//! ([`super::meshes`], its rows with their mesh columns); all append to
//! `results.jsonl`. The command line asks
//! [`Plan::load`], lists [`listing`] and runs [`Plan::run`]; it knows no grid by name.

use std::fmt;

use super::grids::{self, GridError, NamedGrid};
use super::meshes::{self, MESHES};
use super::{Options, Summary};
use crate::error::{Error, Result};
use crate::room::measure::RoomSetup;
use crate::room::sweep::{self as rooms, RoomSweep};
use crate::scene::Overrides;

/// The name of the room comparison (Amaro & Gustafsson 2022 §3).
pub const ROOMS: &str = "rooms";

/// A grid to measure.
pub enum Plan {
    /// Pipelines on scenes: a built-in grid or a grid file.
    Cells(NamedGrid),
    /// The room comparison's four variants in each of these rooms (`room:NAME` or room files).
    Rooms(Vec<String>),
    /// A pipeline under each `curved=` mode on each of these mesh scenes (scene files, a
    /// view after `@`).
    Meshes(Vec<String>),
}

/// One line of `relief sweep --list`: a grid's name, its cell count and what it measures.
pub struct Listed {
    /// The name `--grid` takes.
    pub name: String,
    /// Cells it measures with the scenes given.
    pub cells: usize,
    /// What it measures.
    pub description: String,
}

/// Every grid `--grid` names, the room comparison last, with the scenes given (`None`: each
/// grid's own).
pub fn listing(scenes: Option<&[String]>) -> Vec<Listed> {
    let mut all: Vec<Listed> = grids::builtin(scenes)
        .into_iter()
        .map(|g| Listed { name: g.name, cells: g.cells.len(), description: g.description })
        .collect();
    all.push(Listed {
        name: ROOMS.to_string(),
        cells: room_names(scenes).len() * rooms::variants().len(),
        description: "Amaro & Gustafsson 2022 §3: interior mapping alone, + POM, + soft shadows, + scattering, each \
                      against real geometry, on rooms"
            .to_string(),
    });
    let mesh_scenes = meshes::scene_names(scenes);
    all.push(Listed {
        name: MESHES.to_string(),
        cells: meshes::cells(&mesh_scenes).len(),
        description: format!(
            "issue 38: {} under curved=none, quadric and prism on mesh scenes against the exact mesh reference \
             (coverage, IoU, t, uv and depth error, time over curved=none), {}² unless --size",
            meshes::PIPELINE,
            meshes::DEFAULT_SIZE
        ),
    });
    all
}

fn room_names(scenes: Option<&[String]>) -> Vec<String> {
    match scenes {
        Some(s) if !s.is_empty() => s.to_vec(),
        _ => rooms::DEFAULT_ROOMS.iter().map(|s| s.to_string()).collect(),
    }
}

/// How [`Plan::run`] measures, whatever the grid: [`Options`] without its grid.
pub struct Settings {
    /// Side of the square frame, in pixels.
    pub size: u32,
    /// Timed blocks per cell ([`Options::frames`]).
    pub frames: u32,
    /// Untimed frames rendered before the timed ones.
    pub warmup: u32,
    /// The output folder (created if missing).
    pub out: std::path::PathBuf,
    /// Show a progress bar.
    pub progress: bool,
    /// Overrides applied to every scene ([`Options::overrides`]).
    pub overrides: Overrides,
    /// Measure only shard K of N ([`Options::shard`]).
    pub shard: Option<(u32, u32)>,
    /// The GPU compiler's modeled cost in every row ([`Options::gpu_cost`]).
    pub gpu_cost: Option<crate::cost::Compiler>,
}

impl Settings {
    /// The options that measure `grid` with these settings.
    pub fn options(self, grid: NamedGrid) -> Options {
        let Settings { size, frames, warmup, out, progress, overrides, shard, gpu_cost } = self;
        Options { grid, size, frames, warmup, out, progress, overrides, shard, gpu_cost }
    }
}

/// What [`Plan::run`] did.
pub enum Done {
    /// A grid of cells.
    Cells(Summary),
    /// The room comparison.
    Rooms(RoomSweep),
}

impl Done {
    /// Why the rows have no GPU compiler columns, when the run asked for them and could not.
    pub fn gpu_note(&self) -> Option<&str> {
        match self {
            Done::Cells(s) => s.gpu_note.as_deref(),
            Done::Rooms(_) => None,
        }
    }
}

/// Why a mesh grid's rows have no GPU compiler columns when the run asked for them.
impl fmt::Display for Done {
    /// The summary line (without the time and the rows' path, which the caller adds).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Done::Cells(s) => {
                write!(f, "{} cells: {} measured, {} failed, {} already done", s.cells, s.measured, s.failed, s.skipped)
            }
            Done::Rooms(s) => {
                let failed = s.rows.iter().filter(|r| !r.status.is_ok()).count();
                write!(
                    f,
                    "{} room cells: {} measured, {failed} failed, {} already done",
                    s.rows.len(),
                    s.measured,
                    s.skipped
                )
            }
        }
    }
}

impl Plan {
    /// The grid `arg` names (`rooms`, a built-in grid, or a grid file) on `scenes` (`None`:
    /// the grid's own scenes; for `rooms`, `room:default` and `room:window`).
    pub fn load(arg: &str, scenes: Option<&[String]>) -> std::result::Result<Plan, GridError> {
        if arg == ROOMS {
            return Ok(Plan::Rooms(room_names(scenes)));
        }
        if arg == MESHES {
            return Ok(Plan::Meshes(meshes::scene_names(scenes)));
        }
        grids::load(arg, scenes).map(Plan::Cells)
    }

    /// The file the rows go to in `out`: `results.csv` (beside `results.jsonl`), for a grid
    /// of cells and for the room comparison alike.
    pub fn rows_path(&self, out: &std::path::Path) -> std::path::PathBuf {
        out.join(crate::results::CSV)
    }

    /// The frame side and timed blocks a run of the plan takes when the command line gives
    /// none: the mesh grid's are smaller ([`meshes::DEFAULT_SIZE`], [`meshes::DEFAULT_FRAMES`]).
    pub fn default_size_frames(&self) -> (u32, u32) {
        match self {
            Plan::Meshes(_) => (meshes::DEFAULT_SIZE, meshes::DEFAULT_FRAMES),
            Plan::Cells(_) | Plan::Rooms(_) => (256, 50),
        }
    }

    /// Measures the plan with `settings`. The room comparison sets its camera and depth scales
    /// in its room files and is not sharded: overrides and a shard are refused for it, naming
    /// them; so does the mesh grid, whose scenes name their views (`FILE.toml@angle=30`).
    pub fn run(self, settings: Settings) -> Result<Done> {
        match self {
            Plan::Cells(grid) => Ok(Done::Cells(super::run(&settings.options(grid))?)),
            Plan::Rooms(names) => {
                if !settings.overrides.is_empty() {
                    return Err(Error::Input(
                        "--view, --angle, --azimuth, --depth-scale and --tiling are not implemented for the room grid \
                         (set the camera and depth scales in a room file)"
                            .to_string(),
                    ));
                }
                if settings.shard.is_some() {
                    return Err(Error::Input("--shard is not implemented for the room grid".to_string()));
                }
                let setup = RoomSetup {
                    size: settings.size,
                    grid: crate::room::mesh::DEFAULT_GRID,
                    warmup: settings.warmup,
                    frames: settings.frames,
                };
                Ok(Done::Rooms(rooms::run(&names, &setup, &settings.out)?))
            }
            Plan::Meshes(scenes) => {
                if !settings.overrides.is_empty() {
                    return Err(Error::Input(
                        "--view, --angle, --azimuth, --depth-scale and --tiling are not implemented for the meshes grid \
                         (name a mesh scene's view as --scene FILE.toml@angle=30)"
                            .to_string(),
                    ));
                }
                if settings.shard.is_some() {
                    return Err(Error::Input("--shard is not implemented for the meshes grid".to_string()));
                }
                let setup = meshes::MeshSetup {
                    size: settings.size,
                    frames: settings.frames,
                    out: settings.out,
                    gpu_cost: settings.gpu_cost,
                };
                Ok(Done::Cells(meshes::run(&scenes, &setup)?))
            }
        }
    }
}
