//! `relief report DIR --add FILE…`: a browser's measurements (the live section's "measure on
//! this GPU" button) added to a sweep's rows under the browser's adapter.
//!
//! The file (format [`FORMAT`], version [`VERSION`]) holds, per cell, the frame times the
//! page measured and the probe entry's raw hits on the shipped rays. The hits are scored here
//! with [`crate::measure::score`], the sweep's own scoring, against the exact hits of the
//! same rays traced again on the CPU ([`super::browser::probe_set`]); no score comes from
//! the page. The rows are appended to `DIR/results.jsonl` with the adapter
//! `GPU (WebGPU, TIMER)`, TIMER `timestamp-query` or `wall-clock`.
//!
//! A row whose pipeline, scene or size has no ok row of another adapter in `DIR` (the
//! sweep), or whose shipped rays differ from this relief's, is set aside and listed. Adding
//! a file whose adapter already has rows in `DIR` is refused, unless `replace`: then that
//! adapter's rows are removed first. Each add is logged in `DIR/`[`LOG`], which the report's
//! adapter section lists (what was added, what was set aside).

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::browser::{self, ProbeSet};
use crate::error::{Error, Result};
use crate::gpu::GpuHit;
use crate::measure::{score, Reference};
use crate::results::{self, Metrics, Row};
use crate::scene::{scene_from_arg, Scene};
use relief_dsl::spec::Lod;
use relief_dsl::Pipeline;

/// The `format` of a browser's results file.
pub(crate) const FORMAT: &str = "relief-browser-results";
/// The version of [`FORMAT`] this relief reads.
pub(crate) const VERSION: u64 = 1;
/// The log of adds, one JSON object per line ([`Added`]), in the sweep folder.
pub(crate) const LOG: &str = "added.jsonl";

/// A browser's results file.
#[derive(Deserialize)]
struct File {
    relief_version: String,
    adapter: String,
    timer: String,
    #[serde(default)]
    user_agent: String,
    rows: Vec<FileRow>,
}

/// One cell the page measured.
#[derive(Deserialize)]
struct FileRow {
    pipeline: String,
    scene: String,
    size: u32,
    /// Per timed block, its time over its frames, in milliseconds.
    frame_ms: Vec<f64>,
    frames_per_block: u32,
    probe_rays: usize,
    probe_stride: usize,
    /// The probe's raw hits (the ABI's records), base64.
    hits_b64: String,
}

/// What one file added.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct Added {
    /// The file, as given.
    pub file: String,
    /// The adapter its rows are under.
    pub adapter: String,
    /// The browser's user agent.
    pub user_agent: String,
    /// Rows added.
    pub rows: usize,
    /// Rows of the same adapter removed first (`replace`).
    pub replaced: usize,
    /// The rows set aside, each with why.
    pub set_aside: Vec<String>,
}

/// Reads a browser's results file: a one-line error when it is not one.
fn read_file(path: &Path) -> Result<File> {
    let name = path.display();
    let bad = |message: String| Error::BrowserFile { path: path.to_path_buf(), message };
    let bytes = crate::io::read_regular(path).map_err(|e| crate::io::FileError::read(path, e))?;
    let v: serde_json::Value = serde_json::from_slice(&bytes)
        .map_err(|e| bad(format!("{name} is not a relief browser results file (not JSON: {e})")))?;
    let format = v.get("format").and_then(|f| f.as_str());
    if format != Some(FORMAT) {
        let got = match format {
            Some(f) => format!("its format is `{}`", relief_dsl::spec::echo(f)),
            None => "it has no `format` field".to_string(),
        };
        return Err(bad(format!("{name} is not a relief browser results file: {got}, expected `{FORMAT}`")));
    }
    match v.get("version").and_then(|x| x.as_u64()) {
        Some(VERSION) => {}
        Some(n) => return Err(bad(format!("{name}: {FORMAT} version {n}, this relief reads version {VERSION}"))),
        None => return Err(bad(format!("{name}: {FORMAT} without a whole-number `version`"))),
    }
    serde_json::from_value(v).map_err(|e| bad(format!("{name}: not {FORMAT} rows: {e}")))
}

/// The adapter a file's rows are recorded under.
fn adapter_of(f: &File) -> String {
    format!("{} (WebGPU, {})", f.adapter.trim(), f.timer.trim())
}

/// A scene of the sweep with its heights as stored and its probe sets per size.
struct SceneCache {
    on_device: Result<Scene, String>,
    probes: HashMap<u32, Result<ProbeSet, String>>,
}

/// Adds the browser results `files` to the sweep in `dir` (see the module docs); with
/// `replace`, a file's adapter's earlier rows are replaced instead of refused.
pub fn add(dir: &Path, files: &[PathBuf], replace: bool) -> Result<Vec<Added>> {
    if !dir.is_dir() {
        return Err(Error::NoSweepFolder(dir.to_path_buf()));
    }
    let mut rows = results::read_for_append(dir)?;
    let mut scenes: HashMap<String, SceneCache> = HashMap::new();
    let mut out = Vec::new();
    let mut rewrite = false;
    for path in files {
        let f = read_file(path)?;
        let adapter = adapter_of(&f);
        let before = rows.len();
        let ours = rows.iter().filter(|r| r.metrics.adapter == adapter).count();
        if ours > 0 && !replace {
            return Err(Error::BrowserFile {
                path: path.clone(),
                message: format!(
                    "{}: {} already holds {ours} rows of adapter `{adapter}` (added before); pass --replace to replace them",
                    path.display(),
                    dir.join(results::JSONL).display()
                ),
            });
        }
        rows.retain(|r| r.metrics.adapter != adapter);
        rewrite |= rows.len() != before;
        // The sweep: the ok cells of the other adapters, with their grid.
        let sweep: HashMap<(Pipeline, String, u32), String> = rows
            .iter()
            .filter(|r| r.status.is_ok() && r.room.is_none())
            .map(|r| ((r.metrics.pipeline.clone(), r.metrics.scene.clone(), r.metrics.size), r.grid.clone()))
            .collect();
        let mut added = Added {
            file: path.display().to_string(),
            adapter: adapter.clone(),
            user_agent: f.user_agent.clone(),
            replaced: before - rows.len(),
            ..Default::default()
        };
        let mut seen = HashSet::new();
        for fr in &f.rows {
            // The file's pipeline, parsed once: the cell's key, and what is scored.
            let pipeline = fr.pipeline.parse::<Pipeline>();
            let what = format!(
                "`{}` on {} at {}²",
                relief_dsl::spec::echo(
                    &pipeline.as_ref().map(|p| p.to_string()).unwrap_or_else(|_| fr.pipeline.clone())
                ),
                relief_dsl::spec::echo(&fr.scene),
                fr.size
            );
            let Some((key, grid)) =
                pipeline.ok().map(|p| (p, fr.scene.clone(), fr.size)).and_then(|k| sweep.get(&k).map(|g| (k, g)))
            else {
                added.set_aside.push(format!("{what}: not in the sweep"));
                continue;
            };
            if !seen.insert(key.clone()) {
                added.set_aside.push(format!("{what}: listed twice in the file, the first kept"));
                continue;
            }
            match scored(&mut scenes, fr, &key, &adapter) {
                Ok(m) => {
                    rows.push(Row {
                        grid: grid.clone(),
                        metrics: m,
                        status: crate::results::Status::Ok,
                        error: String::new(),
                        relief_version: f.relief_version.clone(),
                        cell_dir: String::new(),
                        room: None,
                        mesh: None,
                    });
                    added.rows += 1;
                }
                Err(e) => added.set_aside.push(format!("{what}: {e}")),
            }
        }
        out.push(added);
    }
    // Rows removed: the file is rewritten whole (atomically); else only appended to.
    let kept = rows.len() - out.iter().map(|a| a.rows).sum::<usize>();
    if rewrite {
        results::write_jsonl(dir, &rows)?;
    } else {
        for r in &rows[kept..] {
            results::append(dir, r)?;
        }
    }
    results::write_csv(dir, &rows)?;
    let mut log = crate::io::read_regular_to_string(&dir.join(LOG)).unwrap_or_default();
    for a in &out {
        let line = serde_json::to_string(a)
            .map_err(|e| crate::io::FileError::Encode { path: dir.join(LOG), message: e.to_string() })?;
        log.push_str(&line);
        log.push('\n');
    }
    crate::io::write_atomic(&dir.join(LOG), log.as_bytes())?;
    Ok(out)
}

/// The metrics of one file row: its frame times, and its hits scored against the exact hits
/// of the same rays.
fn scored(
    scenes: &mut HashMap<String, SceneCache>,
    fr: &FileRow,
    key: &(Pipeline, String, u32),
    adapter: &str,
) -> Result<Metrics, String> {
    let pipeline = &key.0;
    if pipeline.lod != Lod::Zero {
        return Err(format!("lod={} is not in the browser data", pipeline.lod));
    }
    let sc = scenes.entry(fr.scene.clone()).or_insert_with(|| SceneCache {
        on_device: scene_from_arg(&fr.scene)
            .map(|s| browser::on_device(&s, &crate::gpu::scene_uploads(&s, true)))
            .map_err(|e| e.to_string()),
        probes: HashMap::new(),
    });
    let scene = sc.on_device.as_ref().map_err(Clone::clone)?;
    let set = sc
        .probes
        .entry(fr.size)
        .or_insert_with(|| browser::probe_set(&fr.scene, scene, fr.size).map_err(|e| e.to_string()))
        .as_ref()
        .map_err(Clone::clone)?;
    if fr.probe_rays != set.rays.len() || fr.probe_stride != set.stride {
        return Err(format!(
            "the file probed {} rays (every {}th), this relief ships {} (every {}th): browser data of another relief version",
            fr.probe_rays,
            fr.probe_stride,
            set.rays.len(),
            set.stride
        ));
    }
    let bytes = crate::io::base64::decode(&fr.hits_b64)?;
    let hit_bytes = std::mem::size_of::<GpuHit>();
    if bytes.len() != set.rays.len() * hit_bytes {
        return Err(format!("{} bytes of hits for {} rays of {hit_bytes} bytes", bytes.len(), set.rays.len()));
    }
    let hits: Vec<GpuHit> = bytemuck::pod_collect_to_vec(&bytes);
    let mut m = Metrics {
        pipeline: pipeline.clone(),
        scene: key.1.clone(),
        size: key.2,
        adapter: adapter.to_string(),
        frames_per_block: fr.frames_per_block,
        // WebGPU gives timestamps in nanoseconds, quantised as the browser chooses.
        timestamp_period_ns: f64::NAN,
        ..Default::default()
    };
    crate::metrics::set_timing(&mut m, &fr.frame_ms);
    let reference = Reference {
        rays: &set.rays,
        refs: &set.refs,
        chain: std::slice::from_ref(&scene.height),
        levels: &[],
        edge: scene.edge,
        tiling: scene.tiling as f64,
        whole_frame: set.stride == 1,
    };
    score(&mut m, pipeline, &reference, &hits).map_err(|e| e.to_string())?;
    Ok(m)
}

/// The adds logged in `dir` ([`LOG`]), oldest first; unreadable lines are skipped.
pub(crate) fn log(dir: &Path) -> Vec<Added> {
    let text = crate::io::read_regular_to_string(&dir.join(LOG)).unwrap_or_default();
    text.lines().filter_map(|l| serde_json::from_str(l).ok()).collect()
}
