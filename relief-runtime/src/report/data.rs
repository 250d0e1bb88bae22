//! The sweep's rows as the report reads them: indexed by pipeline, scene and size, with
//! the metrics the report compares.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use relief_dsl::spec::{StageSpec, Value};

use crate::results::{self, Row};

/// The sweep's rows, indexed by (canonical pipeline, scene label, size): rows of one
/// pipeline and scene at two sizes are two rows, never one replacing the other.
pub(crate) struct Data {
    pub dir: PathBuf,
    pub rows: Vec<Row>,
    pub bad_lines: Vec<String>,
    index: HashMap<(String, String, u32), usize>,
}

impl Data {
    /// The rows of one adapter, read from `dir` (or merged into it), indexed.
    pub(crate) fn from_rows(dir: &Path, rows: Vec<Row>, bad_lines: Vec<String>) -> Data {
        // A later row replaces an earlier one, except that an ok row is never replaced by a
        // failed one.
        let mut index: HashMap<(String, String, u32), usize> = HashMap::new();
        for (i, r) in rows.iter().enumerate() {
            let k = (r.metrics.pipeline.to_string(), r.metrics.scene.clone(), r.metrics.size);
            match index.get(&k) {
                Some(&j) if rows[j].status.is_ok() && !r.status.is_ok() => {}
                _ => {
                    index.insert(k, i);
                }
            }
        }
        Data { dir: dir.to_path_buf(), rows, bad_lines, index }
    }

    /// The row of `pipeline` (canonical text) on `scene` (label, `scene:NAME`) at `size`,
    /// any status. On a scene at a named view (`scene:rocks@view=dissertation`) a pipeline
    /// that names no `lod` was measured under the view's, and is found under that name.
    pub(crate) fn get(&self, pipeline: &str, scene: &str, size: u32) -> Option<&Row> {
        let find = |p: &str| self.index.get(&(p.to_string(), scene.to_string(), size)).and_then(|&i| self.rows.get(i));
        find(pipeline).or_else(|| {
            let view = crate::scene::view::of_label(scene)?;
            let p: relief_dsl::Pipeline = pipeline.parse().ok()?;
            (p.lod == relief_dsl::spec::Lod::Zero).then(|| find(&p.with_lod(view.lod()).to_string())).flatten()
        })
    }

    /// The same, only if it succeeded.
    pub(crate) fn ok(&self, pipeline: &str, scene: &str, size: u32) -> Option<&Row> {
        self.get(pipeline, scene, size).filter(|r| r.status.is_ok())
    }

    /// The ok rows of `pipeline` on `scene` at every size, smallest size first.
    pub(crate) fn ok_any_size(&self, pipeline: &str, scene: &str) -> Vec<&Row> {
        let mut v: Vec<&Row> = self.sizes().into_iter().filter_map(|z| self.ok(pipeline, scene, z)).collect();
        v.sort_by_key(|r| r.metrics.size);
        v
    }

    /// Whether `r` is the row the index keeps for its (pipeline, scene, size).
    pub(crate) fn is_indexed(&self, r: &Row) -> bool {
        self.get(&r.metrics.pipeline.to_string(), &r.metrics.scene, r.metrics.size).is_some_and(|x| std::ptr::eq(x, r))
    }

    /// Scene labels in first-seen order.
    pub(crate) fn scenes(&self) -> Vec<String> {
        self.distinct(|r| r.metrics.scene.clone())
    }

    /// Sizes in first-seen order.
    pub(crate) fn sizes(&self) -> Vec<u32> {
        let mut out: Vec<u32> = Vec::new();
        for r in &self.rows {
            if !out.contains(&r.metrics.size) {
                out.push(r.metrics.size);
            }
        }
        out
    }

    /// The sizes with rows on `scene`, first-seen order.
    pub(crate) fn sizes_of(&self, scene: &str) -> Vec<u32> {
        let mut out: Vec<u32> = Vec::new();
        for r in self.rows.iter().filter(|r| r.metrics.scene == scene) {
            if !out.contains(&r.metrics.size) {
                out.push(r.metrics.size);
            }
        }
        out
    }

    pub(crate) fn distinct(&self, f: impl Fn(&Row) -> String) -> Vec<String> {
        let mut out: Vec<String> = Vec::new();
        for r in &self.rows {
            let v = f(r);
            if !out.contains(&v) {
                out.push(v);
            }
        }
        out
    }

    /// The scene the conclusions are checked on: Lion when measured, else the scene with the
    /// most ok rows.
    pub(crate) fn main_scene(&self) -> Option<String> {
        let scenes = self.scenes();
        if scenes.iter().any(|s| s == "scene:lion") {
            return Some("scene:lion".into());
        }
        scenes
            .into_iter()
            .max_by_key(|s| self.rows.iter().filter(|r| &r.metrics.scene == s && r.status.is_ok()).count())
    }
}

/// The rows of the sweeps in `dirs`, in folder order, each row's `cell_dir` made relative to
/// `out` (where the report goes), and the unreadable lines named with their folder.
pub(crate) fn read_merged(dirs: &[PathBuf], out: &Path) -> Result<(Vec<Row>, Vec<String>), crate::io::FileError> {
    let mut rows = Vec::new();
    let mut bad = Vec::new();
    let many = dirs.len() > 1;
    for dir in dirs {
        let read = results::read(dir)?;
        let prefix = relative(out, dir);
        for mut r in read.rows {
            if !r.cell_dir.is_empty() && prefix != Path::new("") {
                r.cell_dir = prefix.join(&r.cell_dir).to_string_lossy().replace('\\', "/");
            }
            rows.push(r);
        }
        bad.extend(read.bad_lines.into_iter().map(|l| if many { format!("{}: {l}", dir.display()) } else { l }));
    }
    Ok((rows, bad))
}

/// `rows` per adapter, the adapter with the most ok rows first (ties: first seen first);
/// each adapter's rows in their order.
pub(crate) fn by_adapter(rows: Vec<Row>) -> Vec<(String, Vec<Row>)> {
    let mut out: Vec<(String, Vec<Row>)> = Vec::new();
    for r in rows {
        match out.iter_mut().find(|(a, _)| *a == r.metrics.adapter) {
            Some((_, v)) => v.push(r),
            None => out.push((r.metrics.adapter.clone(), vec![r])),
        }
    }
    let ok = |v: &Vec<Row>| v.iter().filter(|r| r.status.is_ok()).count();
    out.sort_by_key(|(_, v)| std::cmp::Reverse(ok(v)));
    out
}

/// The path from folder `from` to folder `to` (`""` when they are one), through their
/// canonical forms; `to` as given when either cannot be resolved.
fn relative(from: &Path, to: &Path) -> PathBuf {
    let (Ok(a), Ok(b)) = (from.canonicalize(), to.canonicalize()) else { return to.to_path_buf() };
    let (ac, bc): (Vec<_>, Vec<_>) = (a.components().collect(), b.components().collect());
    let common = ac.iter().zip(&bc).take_while(|(x, y)| x == y).count();
    let mut p = PathBuf::new();
    for _ in common..ac.len() {
        p.push("..");
    }
    for c in &bc[common..] {
        p.push(c);
    }
    p
}

/// A scene and size as a short label: `lion, 64²`.
pub(crate) fn group_label(scene: &str, size: u32) -> String {
    format!("{}, {size}²", short_scene(scene))
}

/// `scene:lion` → `lion`.
pub(crate) fn short_scene(label: &str) -> &str {
    label.strip_prefix("scene:").unwrap_or(label)
}

/// A stage's step count: its `steps` parameter, or the first whole-number parameter, or the
/// steps of a nested stage (`hard(linear(20))`); 0 for `none`.
pub(crate) fn stage_steps(s: &StageSpec) -> u32 {
    if s.is_none() {
        return 0;
    }
    if let Some(Value::Int(n)) = s.get("steps") {
        return *n;
    }
    for (_, v) in &s.params {
        match v {
            Value::Int(n) => return *n,
            Value::Stage(inner) => return stage_steps(inner),
            Value::Word(_) => {}
        }
    }
    0
}

// ---------------------------------------------------------------------------------------
// Error metrics and formatting

/// An error metric of our rows. `Mse` is `mse_dissertation_mean`, the per-ray mean: the
/// dissertation's printed MSE behaves like a per-pixel mean (Burger 2018 Table 4.1: MSE × N²
/// stays near 0.4–0.55 for N = 5…200 linear steps), so the mean is what compares with it
/// and what does not change with the number of probe rays.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Metric {
    Mse,
    RefT,
    Skipped,
}

impl Metric {
    pub(crate) const ALL: [Metric; 3] = [Metric::Mse, Metric::RefT, Metric::Skipped];
    pub(crate) fn name(self) -> &'static str {
        match self {
            Metric::Mse => "mse_dissertation_mean",
            Metric::RefT => "ref_err_t_rms",
            Metric::Skipped => "skipped_rate",
        }
    }
    pub(crate) fn of(self, r: &Row) -> f64 {
        match self {
            Metric::Mse => r.metrics.mse_dissertation_mean,
            Metric::RefT => r.metrics.ref_err_t_rms,
            Metric::Skipped => r.metrics.skipped_rate,
        }
    }
}
