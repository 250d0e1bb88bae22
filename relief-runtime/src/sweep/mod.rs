//! `relief sweep`: measure every cell of a grid (pipeline × scene) and keep the results.
//!
//! Results go to `DIR/results.jsonl` (one JSON object per line, the source of truth) and
//! `DIR/results.csv` (the same rows, rewritten whole through a temporary file after every
//! cell), with each cell's `frame.png` and `error.png` under `DIR/cells/SCENE/SIZE/ADAPTER/PIPELINE/` ([`cell_dir`]).
//! A row is appended with one write as soon as its cell finishes, so a run killed at any
//! moment loses at most the cell in flight; a line cut short by the kill is dropped when the
//! next run starts, and cells already recorded (same pipeline, scene, size and adapter) are
//! skipped. A results file with two rows for one cell is refused ([`results::read`]).
//! A cell that fails is recorded with its error, and the sweep goes on. Rows are read,
//! appended and written by [`crate::results`].
//!
//! Each cell is timed in blocks alternating with the scene's baseline pipeline
//! ([`crate::measure::BASELINE`], [`crate::measure::measure_paired`]), and its row records
//! `frame_ratio_to_baseline` with its 95 % interval. `--shard K/N` measures a deterministic
//! share of the cells (`shard_of`); the report merges the shards' folders.

pub mod grids;
pub mod meshes;
pub mod plan;
pub(crate) mod progress;

use std::collections::{HashMap, HashSet};
use std::path::PathBuf;

use crate::error::{Error, Result};
use crate::gpu::Gpu;
use crate::measure::{measure_paired, write_images, Prepared};
use crate::results::{self, Metrics, Row};
use crate::scene::{scene_from_arg, Overrides, Scene};
pub use grids::NamedGrid;
pub use plan::{Done, Plan, Settings};
use progress::Progress;

/// What `relief sweep` measures.
pub struct Options {
    /// The cells to measure; its name goes into every row's `grid`.
    pub grid: NamedGrid,
    /// Side of the square frame, in pixels.
    pub size: u32,
    /// Timed blocks per cell, the cell's and the baseline's together: `frames / 2` pairs
    /// (at least 2) of blocks alternating with the scene's baseline ([`pairs`]). On a device
    /// where a frame lasts at least 2 ms a block is one frame, so a cell renders about as
    /// many timed frames as `frames`, half of them the baseline's.
    pub frames: u32,
    /// Untimed frames rendered before the timed ones.
    pub warmup: u32,
    /// The output folder (created if missing): `results.jsonl`, `results.csv`, `cells/`.
    pub out: PathBuf,
    /// Show a progress bar.
    pub progress: bool,
    /// Overrides applied to every scene (`--depth-scale`, `--tiling`, `--angle`,
    /// `--azimuth`); an overridden scene's results carry [`Overrides::suffix`] in their name.
    pub overrides: Overrides,
    /// Measure only shard K of N (`Some((K, N))`, K in 1..=N): see `shard_of`.
    pub shard: Option<(u32, u32)>,
    /// The GPU compiler's modeled cost (`crate::cost`) in every row, for the default
    /// families, when set and RADV is installed; without RADV the rows have no GPU columns
    /// and [`Summary::gpu_note`] says why.
    pub gpu_cost: Option<crate::cost::Compiler>,
}

/// The pairs of blocks a cell is timed in for `frames` timed blocks: `frames / 2`, at least 2
/// (an interval needs two pairs).
pub fn pairs(frames: u32) -> u32 {
    (frames / 2).max(2)
}

/// The shard (1..=`n`) of each of `cells` (keys: the pipeline's canonical text as measured,
/// and the scene's label), same order: the distinct keys sorted, then dealt round robin, the
/// first to shard 1. Shards differ in size by at most one cell and do not depend on the
/// order the grid lists its cells in, nor on duplicates; they do depend on the whole grid (a
/// cell added to it can move others to another shard), so every shard must be given the same
/// grid, scenes and overrides.
pub(crate) fn shard_of(cells: &[(String, String)], n: u32) -> Vec<u32> {
    let mut keys: Vec<&(String, String)> = cells.iter().collect();
    keys.sort_by(|a, b| (&a.1, &a.0).cmp(&(&b.1, &b.0)));
    keys.dedup();
    cells
        .iter()
        .map(|c| {
            (keys.binary_search_by(|k| (&k.1, &k.0).cmp(&(&c.1, &c.0))).expect("every key is listed") as u32 % n.max(1))
                + 1
        })
        .collect()
}

/// Parses `K/N` (1 ≤ K ≤ N): the shard a sweep measures.
pub fn parse_shard(text: &str) -> Result<(u32, u32), String> {
    let bad = || format!("--shard `{text}`: expected K/N with 1 ≤ K ≤ N, e.g. 2/4");
    let (k, n) = text.split_once('/').ok_or_else(bad)?;
    let (k, n): (u32, u32) = (k.trim().parse().map_err(|_| bad())?, n.trim().parse().map_err(|_| bad())?);
    if k == 0 || n == 0 || k > n {
        return Err(bad());
    }
    Ok((k, n))
}

/// What a sweep did.
#[derive(Debug, Default)]
pub struct Summary {
    /// Cells measured and recorded as `ok` in this run.
    pub measured: usize,
    /// Cells not run because the results already hold them (same pipeline as measured,
    /// scene, size and adapter).
    pub skipped: usize,
    /// Cells recorded with status `error` in this run.
    pub failed: usize,
    /// The cells this run was given: the grid's, or its shard's with `shard`.
    pub cells: usize,
    /// Why the rows have no GPU compiler columns though [`Options::gpu_cost`] asked for
    /// them (RADV missing, the compiling child failed), once for the run.
    pub gpu_note: Option<String>,
}

/// The key that says a cell is done: its row's [`results::cell_key`].
fn key(pipeline: &str, scene: &str, size: u32, adapter: &str) -> results::CellKey {
    (pipeline.to_string(), scene.to_string(), size, adapter.to_string(), None)
}

/// Runs the sweep.
pub fn run(opts: &Options) -> Result<Summary> {
    crate::io::create_dir_all(&opts.out)?;
    // Shown from the start: a large grid takes a while to check before its first cell.
    let mut bar = Progress::new(opts.grid.cells.len() as u64, opts.progress);
    bar.preparing(format!("preparing {} cells: reading results and scenes, building pipelines", opts.grid.cells.len()));
    let mut rows = results::read_for_append(&opts.out)?;
    let label = |arg: &str| scene_label(arg) + &opts.overrides.suffix();
    // Rows of other adapters (another device, a browser's rows added to the folder) are
    // other cells.
    let done: HashSet<_> = rows.iter().map(results::cell_key).collect();
    // Each scene once: a cell is recorded under the pipeline as measured on its scene (the
    // scene's lod policy applied), so that is what resuming compares.
    let mut scenes: HashMap<String, Result<Scene, String>> = HashMap::new();
    for (_, s) in &opts.grid.cells {
        scenes.entry(s.clone()).or_insert_with(|| {
            scene_from_arg(&scene_spec(s)).map(|sc| opts.overrides.apply(sc)).map_err(|e| format!("{e:#}"))
        });
    }
    let measured_as = |p: &relief_dsl::Pipeline, s: &str| match &scenes[s] {
        Ok(sc) => sc.pipeline_for(p),
        Err(_) => p.clone(),
    };
    let mine: Vec<_> = match opts.shard {
        None => opts.grid.cells.clone(),
        Some((k, n)) => {
            let keys: Vec<(String, String)> =
                opts.grid.cells.iter().map(|(p, s)| (measured_as(p, s).to_string(), label(s))).collect();
            let shards = shard_of(&keys, n);
            opts.grid.cells.iter().zip(shards).filter(|(_, s)| *s == k).map(|(c, _)| c.clone()).collect()
        }
    };
    opts.overrides.check().map_err(Error::Input)?;
    check_views(&opts.grid, &opts.overrides)?;
    check_pipelines(&opts.grid.name, mine.iter().map(|(p, s)| measured_as(p, s)))?;
    let gpu = Gpu::new()?;
    let adapter = format!("{} ({})", gpu.adapter, gpu.driver);
    let todo: Vec<_> = mine
        .iter()
        .filter(|(p, s)| !done.contains(&key(&measured_as(p, s).to_string(), &label(s), opts.size, &adapter)))
        .cloned()
        .collect();
    let mut summary = Summary { skipped: mine.len() - todo.len(), cells: mine.len(), ..Default::default() };
    if todo.is_empty() {
        bar.finish();
        results::write_csv(&opts.out, &rows)?;
        return Ok(summary);
    }
    bar.set_len(todo.len() as u64);
    let gpu_costs = gpu_costs(opts, &todo, &measured_as, &mut bar, &mut summary);
    let mut prepared: HashMap<String, Result<Prepared, String>> = HashMap::new();
    for (pipeline, scene_arg) in todo {
        let pipeline = measured_as(&pipeline, &scene_arg);
        let text = pipeline.to_string();
        bar.set_message(format!("{text} on {scene_arg}"));
        let prep = prepared.entry(scene_arg.clone()).or_insert_with(|| {
            let scene = scenes[&scene_arg].clone()?;
            Prepared::new(&gpu, scene, opts.size).map_err(|e| format!("{e:#}"))
        });
        let cell_dir = cell_dir(&label(&scene_arg), opts.size, &adapter, &pipeline);
        let mut row = Row {
            grid: opts.grid.name.clone(),
            status: crate::results::Status::Ok,
            relief_version: env!("CARGO_PKG_VERSION").into(),
            cell_dir: cell_dir.clone(),
            ..Default::default()
        };
        // A failed cell's row records its error's one line.
        let result = match prep {
            Err(e) => Err(format!("scene {scene_arg}: {e}")),
            Ok(prep) => {
                let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    let mut m = measure_paired(&gpu, prep, &pipeline, opts.warmup, pairs(opts.frames))?;
                    write_images(&opts.out.join(&cell_dir), prep, &m)?;
                    if let Some(Ok(costs)) = gpu_costs.get(&text) {
                        crate::cost::set_columns(&mut m.metrics, costs, &prep.rays, &m.hits);
                    }
                    Ok::<_, Error>(m.metrics)
                }));
                match outcome {
                    Ok(r) => r.map_err(|e| e.to_string()),
                    Err(panic) => Err(format!("panicked: {}", panic_text(&*panic))),
                }
            }
        };
        match result {
            Ok(mut m) => {
                // Rows are named (and resumed) by the scene argument, not the file's stem.
                m.scene = label(&scene_arg);
                row.metrics = m;
                summary.measured += 1;
            }
            Err(e) => {
                row.metrics = Metrics {
                    pipeline: pipeline.clone(),
                    scene: label(&scene_arg),
                    size: opts.size,
                    adapter: adapter.clone(),
                    ..Default::default()
                };
                row.status = crate::results::Status::Error;
                row.error = e;
                summary.failed += 1;
            }
        }
        results::append(&opts.out, &row)?;
        rows.push(row);
        results::write_csv(&opts.out, &rows)?;
        bar.inc();
    }
    bar.finish();
    Ok(summary)
}

/// The GPU compiler's costs of every pipeline to measure, by text form (`Options::gpu_cost`):
/// one compiling child per default family for the whole run. A pipeline that fails to
/// compile there keeps its error (its row then has no GPU columns); a missing driver or a
/// failed child is said once in `summary.gpu_note`.
fn gpu_costs(
    opts: &Options,
    todo: &[(relief_dsl::Pipeline, String)],
    measured_as: &dyn Fn(&relief_dsl::Pipeline, &str) -> relief_dsl::Pipeline,
    bar: &mut Progress,
    summary: &mut Summary,
) -> HashMap<String, std::result::Result<Vec<crate::cost::PipelineCost>, String>> {
    let mut out = HashMap::new();
    let Some(compiler) = &opts.gpu_cost else {
        return out;
    };
    let mut distinct: Vec<relief_dsl::Pipeline> = vec![];
    let mut seen = HashSet::new();
    for (p, s) in todo {
        let q = measured_as(p, s);
        if seen.insert(q.to_string()) {
            distinct.push(q);
        }
    }
    bar.preparing(match &compiler.recorded {
        Some(r) => format!("pricing {} pipelines from {}", distinct.len(), r.file.display()),
        None => format!("pricing {} pipelines with the GPU compiler (RADV)", distinct.len()),
    });
    let families: Vec<String> = crate::cost::DEFAULT_FAMILIES.iter().map(|f| f.to_string()).collect();
    match compiler.cost_each(&distinct, &families, false) {
        Ok(each) => {
            let mut failed = vec![];
            for (p, c) in distinct.iter().zip(each) {
                let c = c.map_err(|e| e.to_string());
                if let Err(e) = &c {
                    failed.push(e.clone());
                }
                out.insert(p.to_string(), c);
            }
            if let Some(first) = failed.first() {
                summary.gpu_note = Some(format!(
                    "{} of {} pipelines have no GPU compiler columns; the first: {first}",
                    failed.len(),
                    distinct.len()
                ));
            }
        }
        Err(e) => summary.gpu_note = Some(format!("no GPU compiler columns: {e}")),
    }
    out
}

/// The distinct pipelines a sweep of `grid` measures, each as measured on its scene (the
/// scene's lod policy applied after `overrides`), in the grid's order: what `relief cost
/// --grid` prices ahead of a run on a machine without the compiler. A scene that cannot be
/// read keeps its cells' pipelines as written (the sweep would record those cells failed).
pub fn measured_pipelines(grid: &NamedGrid, overrides: &Overrides) -> Vec<relief_dsl::Pipeline> {
    let mut scenes: HashMap<String, Option<Scene>> = HashMap::new();
    let mut seen = HashSet::new();
    let mut out = vec![];
    for (p, s) in &grid.cells {
        let sc = scenes
            .entry(s.clone())
            .or_insert_with(|| scene_from_arg(&scene_spec(s)).ok().map(|sc| overrides.apply(sc)));
        let q = match sc {
            Some(sc) => sc.pipeline_for(p),
            None => p.clone(),
        };
        if seen.insert(q.to_string()) {
            out.push(q);
        }
    }
    out
}

/// Refuses a grid holding a pipeline that cannot be built (`csm(4, form=safe, sample=min4)`:
/// a stage refuses the combination), before any cell runs: each distinct pipeline is built
/// once (the naga module, as `relief gen` builds it), in parallel.
fn check_pipelines(grid: &str, pipelines: impl Iterator<Item = relief_dsl::Pipeline>) -> Result<()> {
    use rayon::prelude::*;
    let mut distinct: Vec<relief_dsl::Pipeline> = Vec::new();
    let mut seen = HashSet::new();
    for p in pipelines {
        if seen.insert(p.to_string()) {
            distinct.push(p);
        }
    }
    let bad = distinct.par_iter().find_map_first(|p| relief_dsl::compose::compose_module(p).err().map(|e| (p, e)));
    if let Some((p, e)) = bad {
        return Err(Error::Input(format!(
            "grid `{grid}`: pipeline {} cannot be built: {e} (no cell was run)",
            relief_dsl::spec::echo(&p.to_string())
        )));
    }
    Ok(())
}

/// Refuses overrides that would replace a view a cell's scene names itself (`--angle 30` on
/// `rocks@angle=70`): the cell would be measured at another view than its name says.
fn check_views(grid: &NamedGrid, overrides: &crate::scene::Overrides) -> Result<()> {
    for (_, s) in &grid.cells {
        if let Some((_, Ok(view))) = crate::scene::file::split_view(s) {
            if let Some(k) = view.shared_keys(overrides).first() {
                return Err(Error::Input(format!(
                    "--{} conflicts with grid `{}`'s own view of scene `{s}`: leave the flag out or name scenes without a view",
                    k.replace('_', "-"),
                    grid.name
                )));
            }
        }
    }
    Ok(())
}

/// How a scene argument is named in results: `scene:NAME` for procedural scenes (a bare
/// name is one), the path otherwise.
pub(crate) fn scene_label(arg: &str) -> String {
    scene_spec(arg)
}

fn scene_spec(arg: &str) -> String {
    crate::scene::scene_spec(arg)
}

/// A cell's folder, relative to the sweep's folder: `cells/SCENE/SIZE/ADAPTER/PIPELINE`, the
/// scene's label and the adapter each made one file-name component injectively
/// (`crate::io::path_component`), the size in pixels, the pipeline's file stem. Every part
/// of the cell's key (`results::cell_key`) is in it, so no two cells of one folder share
/// pictures. Readers take the folder from the row's `cell_dir`, never rebuild it.
pub fn cell_dir(label: &str, size: u32, adapter: &str, pipeline: &relief_dsl::Pipeline) -> String {
    let (scene, adapter) = (crate::io::path_component(label), crate::io::path_component(adapter));
    format!("cells/{scene}/{size}/{adapter}/{}", pipeline.file_stem())
}

/// The message a caught panic carries (`panic!` with a format string gives a `String`, with
/// a literal a `&str`), or nothing.
pub(crate) fn panic_text(panic: &(dyn std::any::Any + Send)) -> String {
    panic
        .downcast_ref::<String>()
        .cloned()
        .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cells(n: usize) -> Vec<(String, String)> {
        (0..n).map(|i| (format!("linear({})", i % 7 + 1), format!("scene:s{}", i / 7))).collect()
    }

    #[test]
    fn shards_are_balanced_cover_every_cell_once_and_ignore_the_listing_order() {
        let c = cells(23);
        for n in 1..=5u32 {
            let s = shard_of(&c, n);
            let sizes: Vec<usize> = (1..=n).map(|k| s.iter().filter(|x| **x == k).count()).collect();
            assert_eq!(sizes.iter().sum::<usize>(), 23);
            assert!(sizes.iter().max().unwrap() - sizes.iter().min().unwrap() <= 1, "{n}: {sizes:?}");
            // The same cells listed in another order (reversed, rotated) land in the same shards.
            let mut shuffled: Vec<(usize, (String, String))> = c.iter().cloned().enumerate().collect();
            shuffled.reverse();
            shuffled.rotate_left(5);
            let (idx, cs): (Vec<usize>, Vec<(String, String)>) = shuffled.into_iter().unzip();
            let t = shard_of(&cs, n);
            for (i, shard) in idx.iter().zip(t) {
                assert_eq!(s[*i], shard, "cell {:?} with {n} shards", c[*i]);
            }
        }
        // A cell listed twice is one cell, in one shard.
        let mut d = cells(6);
        d.push(d[2].clone());
        let s = shard_of(&d, 3);
        assert_eq!(s[2], s[6]);
    }

    #[test]
    fn shard_arguments_are_checked() {
        assert_eq!(parse_shard("2/4"), Ok((2, 4)));
        for bad in ["0/4", "5/4", "2", "a/b", "1/0", ""] {
            let e = parse_shard(bad).unwrap_err();
            assert!(e.contains("expected K/N"), "{bad}: {e}");
        }
        assert_eq!(pairs(50), 25);
        assert_eq!(pairs(1), 2);
    }
}
