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
//!
//! [`write_many`] merges the result folders of several sweeps (the shards of one grid, the
//! same grid on several machines) into one report. Rows are kept apart per adapter: the
//! tables, charts and conclusions show the adapter with the most ok rows; one table gives
//! every cell with one column set per adapter (frame time, its ratio to the fastest on that
//! adapter, RMS t error; `adapters`), another the timing conclusions of every adapter side
//! by side. `relief report DIR --add FILE` adds a browser's measurements as an adapter
//! (`add`).

mod adapters;
mod add;
mod agreement;
mod answer;
mod browser;
mod charts;
mod conclusions;
mod data;
mod diss;
mod gpu_cost;
mod html;
mod labels;
mod pareto;
mod rooms;
mod stats;
mod strips;
mod tables;
mod text;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

pub use add::{add, Added};
pub use conclusions::{Conclusion, Verdict};
pub(crate) use data::{group_label, short_scene, stage_steps, Data, Metric};
pub(crate) use text::{anchor, file_safe, fmt_ms, fmt_num, fmt_pct, fmt_sci, ours, TextTable, DASH};

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
    /// The result folders read (one, or several merged).
    pub sources: Vec<PathBuf>,
    /// The adapters of the rows, the one the tables show first.
    pub adapters: Vec<String>,
}

impl ReportSummary {
    /// The rows read, as the page and `tables.md` both state them: `N (K ok, F failed, U
    /// unreadable lines skipped)`, the last part only when there are such lines.
    pub(crate) fn rows_counted(&self) -> String {
        let skipped = if self.bad_lines.is_empty() {
            String::new()
        } else {
            format!(", {} unreadable lines skipped", self.bad_lines.len())
        };
        format!("{} ({} ok, {} failed{skipped})", self.rows, self.ok, self.failed.len())
    }

    /// How many conclusions hold / do not hold / were not measured / are not decided, by
    /// `mse_dissertation_mean`.
    pub fn verdict_counts(&self) -> (usize, usize, usize, usize) {
        let mut c = (0, 0, 0, 0);
        for k in &self.conclusions {
            match k.ours_mse {
                Verdict::Holds => c.0 += 1,
                Verdict::DoesNotHold => c.1 += 1,
                Verdict::NotMeasured => c.2 += 1,
                Verdict::NotDecided => c.3 += 1,
            }
        }
        c
    }
}

/// Writes the report for the sweep in `dir` (see the module docs).
pub fn write(dir: &Path) -> Result<ReportSummary> {
    write_many(&[dir.to_path_buf()], dir)
}

/// Writes the report of the sweeps in `dirs`, merged, into `out` (created if missing; one of
/// `dirs` or another folder). Rows of one pipeline, scene and size from two folders are one
/// cell (the later folder's row wins, an ok row over a failed one), unless their adapters
/// differ: each adapter's rows are kept apart (see the module docs). With `out` outside
/// `dirs`, the merged rows are written to `out/results.csv` too.
pub fn write_many(dirs: &[PathBuf], out: &Path) -> Result<ReportSummary> {
    if dirs.is_empty() {
        return Err(Error::NoSweepFolders);
    }
    for dir in dirs {
        if !dir.is_dir() {
            return Err(Error::NoSweepFolder(dir.clone()));
        }
    }
    let dir = out;
    crate::io::create_dir_all(dir)?;
    let (all_rows, bad_lines) = data::read_merged(dirs, dir)?;
    let mut adapters = data::by_adapter(all_rows.clone());
    let primary = if adapters.is_empty() { Vec::new() } else { adapters.remove(0).1 };
    let data = Data::from_rows(dir, primary, bad_lines);
    let others: Vec<(String, Data)> =
        adapters.into_iter().map(|(a, rows)| (a, Data::from_rows(dir, rows, Vec::new()))).collect();
    let mut room_rows = None;
    for d in dirs {
        if let Some(rr) = crate::room::sweep::read_rows(d)? {
            room_rows = Some(rr);
            break;
        }
    }
    if data.rows.is_empty() {
        if let Some(rr) = &room_rows {
            return write_rooms_only(dir, rr);
        }
        return Err(Error::NoResults { dir: dir.to_path_buf(), bad_lines: data.bad_lines });
    }
    let sub = dir.join("report");
    crate::io::create_dir_all(&sub)?;
    remove_stale(&sub);

    let mut summary = ReportSummary {
        dir: dir.to_path_buf(),
        rows: all_rows.len(),
        ok: all_rows.iter().filter(|r| r.status.is_ok()).count(),
        failed: all_rows
            .iter()
            .filter(|r| !r.status.is_ok())
            .map(|r| (r.metrics.pipeline.to_string(), r.metrics.scene.clone(), r.error.clone()))
            .collect(),
        bad_lines: data.bad_lines.clone(),
        sources: dirs.to_vec(),
        adapters: std::iter::once(&data)
            .chain(others.iter().map(|(_, d)| d))
            .filter_map(|d| d.rows.first().map(|r| r.metrics.adapter.clone()))
            .collect(),
        ..Default::default()
    };
    if !dirs.iter().any(|d| same_dir(d, dir)) {
        write_file(&dir.join("results.csv"), &crate::results::csv_bytes(&all_rows)?, &mut summary.files)?;
    }

    let diss = diss::Diss::load();
    let tables = tables::build(&data, &diss);
    let conclusions = conclusions::check(&data, &diss);
    let per_adapter = {
        let mut v = vec![(summary.adapters.first().cloned().unwrap_or_default(), conclusions.clone())];
        v.extend(others.iter().map(|(a, d)| (a.clone(), conclusions::check(d, &diss))));
        conclusions::by_adapter(&v)
    };
    let added: Vec<Added> = dirs.iter().flat_map(|d| add::log(d)).collect();
    let per_adapter_cells = {
        let mut v = vec![(summary.adapters.first().cloned().unwrap_or_default(), &data)];
        v.extend(others.iter().map(|(a, d)| (a.clone(), d)));
        adapters::table(&v, &added)
    };
    let agreement = agreement::metric_agreement(&data, &tables);
    let charts = charts::write_all(&data, &sub, &mut summary.warnings);
    let strips = strips::write_all(&data, &tables, &sub, &mut summary.warnings);
    let fronts = pareto::build(&data);
    let pareto_svgs = pareto::write_svgs(&fronts, &sub, &mut summary.warnings);
    let answers = answer::build(&data);
    let answer_charts: Vec<_> = answers.iter().map(|a| answer::write_chart(a, &sub, &mut summary.warnings)).collect();
    let scene_maps: Vec<_> =
        answers.iter().map(|a| answer::write_height_map(&a.scene, &sub, &mut summary.warnings)).collect();
    let gpu = gpu_cost::build(&data, &answers, &conclusions, &sub, &mut summary.warnings);

    // tables.md
    let mut md = String::new();
    let _ = writeln!(md, "# relief report: Burger 2018, chapter 4, reproduced\n");
    md.push_str(&overview_md(&data, &summary));
    md.push_str(&answer::to_markdown(&answers));
    if let Some(g) = &gpu {
        md.push_str(&g.markdown);
    }
    md.push_str(&tables::intro_md());
    for t in &tables {
        md.push_str(&t.table.to_markdown(2));
        if let Some(s) = strips.iter().find(|s| s.key == t.key) {
            let _ = writeln!(md, "Image strip (rows in table order, frame | error): [{}]({})\n", s.file, s.file);
            for f in &s.frames {
                let _ = writeln!(md, "- {}: {}", f.numbered(), f.values);
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
    if let Some(t) = &per_adapter_cells {
        md.push_str(&t.to_markdown(2));
    }
    if let Some(t) = &per_adapter {
        md.push_str(&t.to_markdown(2));
    }
    if let Some(lod) = conclusions::lod_markdown(&data, &diss) {
        md.push_str(&lod);
    }
    if let Some(views) = conclusions::view_markdown(&data, &diss) {
        md.push_str(&views);
    }
    if let Some(rr) = &room_rows {
        md.push_str(&rooms::to_markdown(rr));
    }
    md.push_str(&failed_md(&summary));
    write_file(&dir.join("tables.md"), md.as_bytes(), &mut summary.files)?;

    // pareto.md
    let pmd = pareto::to_markdown(&fronts, &pareto_svgs);
    write_file(&dir.join("pareto.md"), pmd.as_bytes(), &mut summary.files)?;

    // browser/: what the live section and the measure button need.
    let shipped = {
        let datas: Vec<&Data> = std::iter::once(&data).chain(others.iter().map(|(_, d)| d)).collect();
        browser::write(&datas, dir)
    };
    if let Err(e) = &shipped {
        summary.warnings.push(format!("no browser data: {e}"));
    }
    let live = browser::section(&shipped);

    // index.html
    let page = html::page(html::Parts {
        data: &data,
        summary: &summary,
        answers: &answers,
        answer_charts: &answer_charts,
        scene_maps: &scene_maps,
        tables: &tables,
        conclusions: &conclusions,
        agreement: &agreement,
        charts: &charts,
        strips: &strips,
        fronts: &fronts,
        pareto_svgs: &pareto_svgs,
        extra: std::iter::once(live)
            .chain((per_adapter_cells.is_some() || per_adapter.is_some()).then(|| html::Section {
                id: "adapters".into(),
                nav: "Per adapter".into(),
                html: per_adapter_cells.iter().chain(&per_adapter).map(|t| t.to_html(2)).collect(),
            }))
            .chain(gpu.iter().map(|g| html::Section {
                id: "gpu-model".into(),
                nav: "GPU model".into(),
                html: g.html.clone(),
            }))
            .chain(room_rows.iter().map(|rr| html::Section {
                id: "rooms".into(),
                nav: "Rooms".into(),
                html: rooms::to_html(rr),
            }))
            .collect(),
    });
    write_file(&dir.join("index.html"), page.as_bytes(), &mut summary.files)?;
    // index first, then tables.md, then the rest.
    summary.files.rotate_right(1);
    summary.files.extend(charts.iter().map(|c| sub.join(&c.file)));
    summary.files.extend(gpu.iter().flat_map(|g| g.files.iter().map(|f| dir.join(f))));
    summary.files.extend(strips.iter().map(|s| dir.join(&s.file)));
    summary.files.extend(pareto_svgs.iter().map(|p| dir.join(&p.1)));
    summary.files.extend(answer_charts.iter().flatten().map(|c| dir.join(&c.file)));
    let mut maps: Vec<&String> = scene_maps.iter().flatten().collect();
    maps.dedup();
    summary.files.extend(maps.into_iter().map(|m| dir.join(m)));
    if let Ok(w) = shipped {
        summary.files.extend(w.files);
    }
    summary.conclusions = conclusions;
    Ok(summary)
}

/// The report of a folder holding only a room grid (`relief sweep --grid rooms`): the room
/// section as `tables.md` and `index.html`.
fn write_rooms_only(dir: &Path, rows: &[crate::room::sweep::RoomRow]) -> Result<ReportSummary> {
    let mut summary = ReportSummary {
        dir: dir.to_path_buf(),
        rows: rows.len(),
        ok: rows.iter().filter(|r| r.status.is_ok()).count(),
        failed: rows
            .iter()
            .filter(|r| !r.status.is_ok())
            .map(|r| (r.pipeline.clone(), r.room.clone(), r.error.clone()))
            .collect(),
        ..Default::default()
    };
    let md = format!("# relief report: rooms\n\n{}", rooms::to_markdown(rows));
    write_file(&dir.join("tables.md"), md.as_bytes(), &mut summary.files)?;
    let page = format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>relief report: rooms</title><style>{}</style></head><body>\n<h1>relief report: rooms</h1>\n{}</body></html>\n",
        html::STYLE,
        rooms::to_html(rows)
    );
    write_file(&dir.join("index.html"), page.as_bytes(), &mut summary.files)?;
    Ok(summary)
}

/// Removes charts, strips and pictures an earlier report wrote (only names this module writes).
fn remove_stale(sub: &Path) {
    let Ok(rd) = std::fs::read_dir(sub) else { return };
    for e in rd.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let ours = ((name.starts_with("strip_") || name.starts_with("scene_")) && name.ends_with(".png"))
            || ((name.starts_with('f')
                || name.starts_with("pareto_")
                || name.starts_with("answer_")
                || name.starts_with("gpu_"))
                && name.ends_with(".svg"));
        if ours {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

fn write_file(path: &Path, bytes: &[u8], files: &mut Vec<PathBuf>) -> Result<()> {
    crate::io::write_atomic(path, bytes)?;
    files.push(path.to_path_buf());
    Ok(())
}

/// Whether `a` and `b` name the same folder.
fn same_dir(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => a == b,
    }
}

fn overview_md(data: &Data, s: &ReportSummary) -> String {
    let mut md = String::new();
    let _ = writeln!(md, "Sweep folder: `{}`  ", data.dir.display());
    if s.sources.len() > 1 || s.sources.first().is_some_and(|d| !same_dir(d, &data.dir)) {
        let _ = writeln!(
            md,
            "Merged from: {}  ",
            s.sources.iter().map(|d| format!("`{}`", d.display())).collect::<Vec<_>>().join(", ")
        );
    }
    if s.adapters.len() > 1 {
        let _ = writeln!(md, "Adapters kept apart: {} (tables, charts and conclusions: the first; timing conclusions of each side by side)  ", s.adapters.join("; "));
    }
    let _ = writeln!(md, "Rows: {}  ", s.rows_counted());
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
