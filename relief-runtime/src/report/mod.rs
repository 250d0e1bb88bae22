//! `relief report DIR`: tables, conclusions, charts, image strips and Pareto fronts from a
//! sweep's `results.jsonl`, written next to it.
//!
//! Everything is written into `DIR` (charts, strips and per-table HTML under `DIR/report/`):
//! - `tables.md`: one table per dissertation table (Burger 2018, Tables 4.1–4.15), our
//!   measurements and the dissertation's numbers side by side, with trend columns (frame time
//!   and error relative to each row's base row), then the conclusions, checked.
//! - `pareto.md`: the least-error method for each frame-time budget, per scene.
//! - `report/*.svg`: charts like Figures 4.5 and 4.7–4.11, one per error metric.
//! - `report/strip_*.png`: frame and error images of each table's cells, stacked.
//! - `index.html`: all of it, readable offline.
//!
//! The dissertation's numbers are embedded (`data/dissertation_tables.csv`), so a report
//! works on a fresh clone. The report never fails on a failed cell: failed rows are listed.

mod charts;
mod conclusions;
mod diss;
mod html;
mod pareto;
mod strips;
mod tables;

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::Context;
use relief_dsl::spec::{StageSpec, Value};
use relief_dsl::Pipeline;

use crate::results::{self, Row};

pub use conclusions::{Conclusion, Verdict};

/// What `write` produced.
#[derive(Clone, Debug, Default)]
pub struct ReportSummary {
    /// The sweep folder.
    pub dir: PathBuf,
    /// Rows read from `results.jsonl` (after dropping unreadable lines).
    pub rows: usize,
    /// Rows with status `ok`.
    pub ok: usize,
    /// Failed rows: (pipeline, scene, error).
    pub failed: Vec<(String, String, String)>,
    /// Lines of `results.jsonl` that could not be read, with the reason.
    pub bad_lines: Vec<String>,
    /// Every file written, `tables.md` and `index.html` first.
    pub files: Vec<PathBuf>,
    /// The dissertation's conclusions, checked.
    pub conclusions: Vec<Conclusion>,
    /// Problems that did not stop the report (an unreadable image, ...).
    pub warnings: Vec<String>,
}

impl ReportSummary {
    /// How many conclusions hold / do not hold / were not measured, by `mse_dissertation_mean`.
    pub fn verdict_counts(&self) -> (usize, usize, usize) {
        let mut c = (0, 0, 0);
        for k in &self.conclusions {
            match k.ours_mse {
                Verdict::Holds => c.0 += 1,
                Verdict::DoesNotHold => c.1 += 1,
                Verdict::NotMeasured => c.2 += 1,
            }
        }
        c
    }
}

/// Writes the report for the sweep in `dir` (see the module docs).
pub fn write(dir: &Path) -> anyhow::Result<ReportSummary> {
    if !dir.is_dir() {
        anyhow::bail!("no sweep folder {}: it does not exist or is not a folder", dir.display());
    }
    let data = Data::load(dir)?;
    if data.rows.is_empty() {
        let mut msg = format!(
            "{} holds no results: {} is missing or has no rows (run `relief sweep --out {}` first)",
            dir.display(),
            dir.join("results.jsonl").display(),
            dir.display()
        );
        if !data.bad_lines.is_empty() {
            let _ = write!(msg, "; unreadable lines: {}", data.bad_lines.join("; "));
        }
        anyhow::bail!(msg);
    }
    let sub = dir.join("report");
    std::fs::create_dir_all(&sub).with_context(|| format!("cannot create {}", sub.display()))?;
    remove_stale(&sub);

    let mut summary = ReportSummary {
        dir: dir.to_path_buf(),
        rows: data.rows.len(),
        ok: data.rows.iter().filter(|r| r.status == "ok").count(),
        failed: data
            .rows
            .iter()
            .filter(|r| r.status != "ok")
            .map(|r| (r.metrics.pipeline.clone(), r.metrics.scene.clone(), r.error.clone()))
            .collect(),
        bad_lines: data.bad_lines.clone(),
        ..Default::default()
    };

    let diss = diss::Diss::load();
    let tables = tables::build(&data, &diss);
    let conclusions = conclusions::check(&data, &diss);
    let agreement = conclusions::metric_agreement(&data, &tables);
    let charts = charts::write_all(&data, &sub, &mut summary.warnings);
    let strips = strips::write_all(&data, &tables, &sub, &mut summary.warnings);
    let fronts = pareto::build(&data);
    let pareto_svgs = pareto::write_svgs(&fronts, &sub, &mut summary.warnings);

    // tables.md
    let mut md = String::new();
    let _ = writeln!(md, "# relief report: Burger 2018, chapter 4, reproduced\n");
    md.push_str(&overview_md(&data, &summary));
    md.push_str(&tables::intro_md());
    for t in &tables {
        md.push_str(&t.table.to_markdown(2));
        if let Some(s) = strips.iter().find(|s| s.key == t.key) {
            let _ = writeln!(md, "Image strip (rows in table order, frame | error): [{}]({})\n", s.file, s.file);
            for f in &s.frames {
                let _ = writeln!(md, "- {}: {}", f.label, f.values);
            }
            md.push('\n');
        }
    }
    md.push_str("## Charts\n\n");
    if charts.is_empty() {
        md.push_str("No figure grid (f4.5, f4.7–f4.11) has ok rows.\n\n");
    }
    for c in &charts {
        let _ = writeln!(md, "![{}](report/{})  \n{}\n", c.title, c.file, c.caption);
    }
    md.push_str(&conclusions::to_markdown(&conclusions, &agreement));
    md.push_str(&failed_md(&summary));
    write_file(&dir.join("tables.md"), md.as_bytes(), &mut summary.files)?;

    // pareto.md
    let pmd = pareto::to_markdown(&fronts, &pareto_svgs);
    write_file(&dir.join("pareto.md"), pmd.as_bytes(), &mut summary.files)?;

    // index.html
    let page = html::page(&html::Parts {
        data: &data,
        summary: &summary,
        tables: &tables,
        conclusions: &conclusions,
        agreement: &agreement,
        charts: &charts,
        strips: &strips,
        fronts: &fronts,
        pareto_svgs: &pareto_svgs,
    });
    write_file(&dir.join("index.html"), page.as_bytes(), &mut summary.files)?;
    // index first, then tables.md, then the rest.
    summary.files.rotate_right(1);
    summary.files.extend(charts.iter().map(|c| sub.join(&c.file)));
    summary.files.extend(strips.iter().map(|s| dir.join(&s.file)));
    summary.files.extend(pareto_svgs.iter().map(|p| dir.join(&p.1)));
    summary.conclusions = conclusions;
    Ok(summary)
}

/// Removes charts and strips an earlier report wrote (only names this module writes).
fn remove_stale(sub: &Path) {
    let Ok(rd) = std::fs::read_dir(sub) else { return };
    for e in rd.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let ours = (name.starts_with("strip_") && name.ends_with(".png"))
            || ((name.starts_with('f') || name.starts_with("pareto_")) && name.ends_with(".svg"));
        if ours {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

fn write_file(path: &Path, bytes: &[u8], files: &mut Vec<PathBuf>) -> anyhow::Result<()> {
    std::fs::write(path, bytes).with_context(|| format!("cannot write {}", path.display()))?;
    files.push(path.to_path_buf());
    Ok(())
}

fn overview_md(data: &Data, s: &ReportSummary) -> String {
    let mut md = String::new();
    let _ = writeln!(md, "Sweep folder: `{}`  ", data.dir.display());
    let _ = writeln!(md, "Rows: {} ({} ok, {} failed{})  ", s.rows, s.ok, s.failed.len(), if s.bad_lines.is_empty() { String::new() } else { format!(", {} unreadable lines skipped", s.bad_lines.len()) });
    let _ = writeln!(md, "Scenes: {}  ", data.scenes().iter().map(|x| short_scene(x)).collect::<Vec<_>>().join(", "));
    let _ = writeln!(md, "Sizes: {}  ", data.distinct(|r| r.metrics.size.to_string()).join(", "));
    let _ = writeln!(md, "Adapters: {}  ", data.distinct(|r| r.metrics.adapter.clone()).join("; "));
    let _ = writeln!(md, "relief versions: {}\n", data.distinct(|r| r.relief_version.clone()).join(", "));
    md
}

fn failed_md(s: &ReportSummary) -> String {
    let mut md = String::from("\n## Failed cells\n\n");
    if s.failed.is_empty() && s.bad_lines.is_empty() {
        md.push_str("None.\n");
        return md;
    }
    for (p, sc, e) in &s.failed {
        let _ = writeln!(md, "- `{p}` on {}: {}", short_scene(sc), e.replace('\n', " "));
    }
    for l in &s.bad_lines {
        let _ = writeln!(md, "- unreadable results line: {l}");
    }
    md
}

// ---------------------------------------------------------------------------------------
// Data

/// The sweep's rows, indexed by (canonical pipeline, scene label, size): rows of one
/// pipeline and scene at two sizes are two rows, never one replacing the other (issue #11).
pub(crate) struct Data {
    pub dir: PathBuf,
    pub rows: Vec<Row>,
    pub bad_lines: Vec<String>,
    index: HashMap<(String, String, u32), usize>,
}

impl Data {
    /// Reads `dir/results.jsonl` without changing it ([`results::read`]): unreadable lines
    /// are skipped and kept in `bad_lines`. A missing file gives no rows.
    pub fn load(dir: &Path) -> anyhow::Result<Data> {
        let read = results::read(dir)?;
        Ok(Data::from_rows(dir, read.rows, read.bad_lines))
    }

    pub fn from_rows(dir: &Path, mut rows: Vec<Row>, bad_lines: Vec<String>) -> Data {
        for r in rows.iter_mut() {
            r.metrics.pipeline = canonical(&r.metrics.pipeline);
        }
        // A later row replaces an earlier one, except that an ok row is never replaced by a
        // failed one.
        let mut index: HashMap<(String, String, u32), usize> = HashMap::new();
        for (i, r) in rows.iter().enumerate() {
            let k = (r.metrics.pipeline.clone(), r.metrics.scene.clone(), r.metrics.size);
            match index.get(&k) {
                Some(&j) if rows[j].status == "ok" && r.status != "ok" => {}
                _ => {
                    index.insert(k, i);
                }
            }
        }
        Data { dir: dir.to_path_buf(), rows, bad_lines, index }
    }

    /// The row of `pipeline` (canonical text) on `scene` (label, `scene:NAME`) at `size`,
    /// any status.
    pub fn get(&self, pipeline: &str, scene: &str, size: u32) -> Option<&Row> {
        self.index.get(&(pipeline.to_string(), scene.to_string(), size)).and_then(|&i| self.rows.get(i))
    }

    /// The same, only if it succeeded.
    pub fn ok(&self, pipeline: &str, scene: &str, size: u32) -> Option<&Row> {
        self.get(pipeline, scene, size).filter(|r| r.status == "ok")
    }

    /// The ok rows of `pipeline` on `scene` at every size, smallest size first.
    pub fn ok_any_size(&self, pipeline: &str, scene: &str) -> Vec<&Row> {
        let mut v: Vec<&Row> = self.sizes().into_iter().filter_map(|z| self.ok(pipeline, scene, z)).collect();
        v.sort_by_key(|r| r.metrics.size);
        v
    }

    /// Whether `r` is the row the index keeps for its (pipeline, scene, size).
    pub fn is_indexed(&self, r: &Row) -> bool {
        self.get(&r.metrics.pipeline, &r.metrics.scene, r.metrics.size).is_some_and(|x| std::ptr::eq(x, r))
    }

    /// Scene labels in first-seen order.
    pub fn scenes(&self) -> Vec<String> {
        self.distinct(|r| r.metrics.scene.clone())
    }

    /// Sizes in first-seen order.
    pub fn sizes(&self) -> Vec<u32> {
        let mut out: Vec<u32> = Vec::new();
        for r in &self.rows {
            if !out.contains(&r.metrics.size) {
                out.push(r.metrics.size);
            }
        }
        out
    }

    /// The sizes with rows on `scene`, first-seen order.
    pub fn sizes_of(&self, scene: &str) -> Vec<u32> {
        let mut out: Vec<u32> = Vec::new();
        for r in self.rows.iter().filter(|r| r.metrics.scene == scene) {
            if !out.contains(&r.metrics.size) {
                out.push(r.metrics.size);
            }
        }
        out
    }

    pub fn distinct(&self, f: impl Fn(&Row) -> String) -> Vec<String> {
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
    pub fn main_scene(&self) -> Option<String> {
        let scenes = self.scenes();
        if scenes.iter().any(|s| s == "scene:lion") {
            return Some("scene:lion".into());
        }
        scenes.into_iter().max_by_key(|s| self.rows.iter().filter(|r| &r.metrics.scene == s && r.status == "ok").count())
    }
}

/// A scene and size as a short label: `lion, 64²`.
pub(crate) fn group_label(scene: &str, size: u32) -> String {
    format!("{}, {size}²", short_scene(scene))
}

/// The canonical text of a pipeline (the text itself when it does not parse).
pub(crate) fn canonical(text: &str) -> String {
    text.parse::<Pipeline>().map(|p| p.to_string()).unwrap_or_else(|_| text.to_string())
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
    Missed,
}

impl Metric {
    pub const ALL: [Metric; 3] = [Metric::Mse, Metric::RefT, Metric::Missed];
    pub fn name(self) -> &'static str {
        match self {
            Metric::Mse => "mse_dissertation_mean",
            Metric::RefT => "ref_err_t_rms",
            Metric::Missed => "missed_rate",
        }
    }
    pub fn of(self, r: &Row) -> f64 {
        match self {
            Metric::Mse => r.metrics.mse_dissertation_mean,
            Metric::RefT => r.metrics.ref_err_t_rms,
            Metric::Missed => r.metrics.missed_rate,
        }
    }
}

/// A cell of our columns: the value, "error" for a failed cell, "—" for a missing one.
pub(crate) fn ours(row: Option<&Row>, f: impl Fn(&Row) -> String) -> String {
    match row {
        None => DASH.into(),
        Some(r) if r.status != "ok" => "error".into(),
        Some(r) => f(r),
    }
}

pub(crate) const DASH: &str = "—";

pub(crate) fn fmt_ms(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.3}")
    } else {
        "NaN".into()
    }
}

pub(crate) fn fmt_sci(v: f64) -> String {
    if !v.is_finite() {
        "NaN".into()
    } else if v == 0.0 {
        "0".into()
    } else {
        format!("{v:.3e}")
    }
}

pub(crate) fn fmt_num(v: f64, decimals: usize) -> String {
    if v.is_finite() {
        format!("{v:.decimals$}")
    } else {
        "NaN".into()
    }
}

pub(crate) fn fmt_pct(v: Option<f64>) -> String {
    match v {
        Some(x) if x.is_finite() => format!("{x:.1}%"),
        _ => DASH.into(),
    }
}

/// A table of text cells, printable as Markdown or HTML.
#[derive(Clone, Debug, Default)]
pub(crate) struct TextTable {
    pub title: String,
    /// Paragraphs under the title.
    pub notes: Vec<String>,
    pub header: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

impl TextTable {
    pub fn to_markdown(&self, level: usize) -> String {
        let mut md = String::new();
        if !self.title.is_empty() {
            let _ = writeln!(md, "{} {}\n", "#".repeat(level.max(1)), self.title);
        }
        for n in &self.notes {
            let _ = writeln!(md, "{n}\n");
        }
        if self.header.is_empty() {
            return md;
        }
        let esc = |s: &str| s.replace('|', "\\|").replace('\n', " ");
        let _ = writeln!(md, "| {} |", self.header.iter().map(|h| esc(h)).collect::<Vec<_>>().join(" | "));
        let _ = writeln!(md, "|{}", self.header.iter().map(|_| "---|").collect::<String>());
        for r in &self.rows {
            let mut cells: Vec<String> = r.iter().map(|c| esc(c)).collect();
            cells.resize(self.header.len(), String::new());
            let _ = writeln!(md, "| {} |", cells.join(" | "));
        }
        md.push('\n');
        md
    }

    pub fn to_html(&self, level: usize) -> String {
        let mut h = String::new();
        let lv = level.clamp(1, 6);
        if !self.title.is_empty() {
            let _ = writeln!(h, "<h{lv} id=\"{}\">{}</h{lv}>", anchor(&self.title), html::esc(&self.title));
        }
        for n in &self.notes {
            let _ = writeln!(h, "<p>{}</p>", html::md_inline(n));
        }
        if self.header.is_empty() {
            return h;
        }
        h.push_str("<table>\n<thead><tr>");
        for c in &self.header {
            let _ = write!(h, "<th>{}</th>", html::esc(c));
        }
        h.push_str("</tr></thead>\n<tbody>\n");
        for r in &self.rows {
            h.push_str("<tr>");
            for c in r {
                let class = if c.starts_with("holds") {
                    " class=\"holds\""
                } else if c.starts_with("does not hold") {
                    " class=\"fails\""
                } else if c == "error" {
                    " class=\"err\""
                } else {
                    ""
                };
                let _ = write!(h, "<td{class}>{}</td>", html::md_inline(c));
            }
            h.push_str("</tr>\n");
        }
        h.push_str("</tbody></table>\n");
        h
    }
}

/// An HTML id from a title.
pub(crate) fn anchor(title: &str) -> String {
    let mut s: String = title.chars().map(|c| if c.is_ascii_alphanumeric() { c.to_ascii_lowercase() } else { '-' }).collect();
    while s.contains("--") {
        s = s.replace("--", "-");
    }
    s.trim_matches('-').to_string()
}

/// A file-safe name.
pub(crate) fn file_safe(s: &str) -> String {
    s.chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' || c == '.' { c } else { '_' }).collect()
}
