//! One report run's typed data ([`Report`]): the rows read and merged once, and everything
//! built and written from them before any section is rendered (tables, conclusions, charts,
//! strips, fronts, answers, the GPU model, the browser data).

use std::path::{Path, PathBuf};

use super::add::{self, Added};
use super::sections::Report;
use super::summary::ReportSummary;
use super::{adapters, agreement, answer, browser, charts, conclusions, data, diss, gpu_cost, pareto, strips, tables};
use crate::error::{Error, Result};
use crate::results::Row;

/// Reads the rows of `dirs` (merged, each adapter's apart; the room cells' and the mesh grid's apart
/// from the others) and builds and writes everything the sections show, into `out` (see
/// `super::write_many`). Folders that hold only room cells or mesh cells (`relief sweep --grid rooms`, `meshes`)
/// give a report with no sweep rows: nothing is built from those, and only the sections that
/// show no sweep rows render (`super::sections::Section::of_sweep`).
pub(crate) fn build(dirs: &[PathBuf], out: &Path) -> Result<Box<Report>> {
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
    let (merged, bad_lines) = data::read_merged(dirs, dir)?;
    let (mut room_rows, all_rows): (Vec<Row>, Vec<Row>) = merged.iter().cloned().partition(|r| r.room.is_some());
    // An older relief's room rows, in `rooms.jsonl` beside `results.jsonl`.
    for d in dirs {
        crate::room::sweep::add_legacy(d, &mut room_rows)?;
    }
    let (mesh_rows, all_rows): (Vec<Row>, Vec<Row>) =
        all_rows.into_iter().partition(super::sections::meshes::is_mesh_row);
    let mut adapters = data::by_adapter(all_rows.clone());
    let primary = if adapters.is_empty() { Vec::new() } else { adapters.remove(0).1 };
    let data = data::Data::from_rows(dir, primary, bad_lines);
    let others: Vec<(String, data::Data)> =
        adapters.into_iter().map(|(a, rows)| (a, data::Data::from_rows(dir, rows, Vec::new()))).collect();
    if data.rows.is_empty() {
        if room_rows.is_empty() && mesh_rows.is_empty() {
            return Err(Error::NoResults { dir: dir.to_path_buf(), bad_lines: data.bad_lines });
        }
        return Ok(rooms_only(dirs, data, room_rows, mesh_rows));
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
        write_file(&dir.join(crate::results::CSV), &crate::results::csv_bytes(&merged)?, &mut summary.files)?;
    }

    let diss = diss::Diss::load();
    let tables = tables::build(&data, &diss);
    let conclusions = conclusions::check(&data, &diss);
    let per_adapter = {
        let mut v = vec![(summary.adapters.first().cloned().unwrap_or_default(), conclusions.clone())];
        v.extend(others.iter().map(|(a, d)| (a.clone(), conclusions::check(d, &diss))));
        conclusions::write::by_adapter(&v)
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
    // browser/: what the live section and the measure button need.
    let shipped = {
        let datas: Vec<&data::Data> = std::iter::once(&data).chain(others.iter().map(|(_, d)| d)).collect();
        browser::write(&datas, dir)
    };
    if let Err(e) = &shipped {
        summary.warnings.push(format!("no browser data: {e}"));
    }
    Ok(Box::new(Report {
        data,
        diss,
        summary,
        sub,
        tables,
        conclusions,
        per_adapter,
        per_adapter_cells,
        agreement,
        charts,
        strips,
        fronts,
        pareto_svgs,
        answers,
        answer_charts,
        scene_maps,
        gpu,
        room_rows,
        mesh_rows,
        shipped,
    }))
}

/// The report of folders whose rows are all room cells' or mesh cells': their summary, and
/// nothing built from the (absent) sweep rows; no file is written here.
fn rooms_only(dirs: &[PathBuf], data: data::Data, room_rows: Vec<Row>, mesh_rows: Vec<Row>) -> Box<Report> {
    let apart = || room_rows.iter().chain(&mesh_rows);
    let summary = ReportSummary {
        dir: data.dir.clone(),
        rows: apart().count(),
        ok: apart().filter(|r| r.status.is_ok()).count(),
        failed: apart()
            .filter(|r| !r.status.is_ok())
            .map(|r| (r.metrics.pipeline.to_string(), r.metrics.scene.clone(), r.error.clone()))
            .collect(),
        bad_lines: data.bad_lines.clone(),
        sources: dirs.to_vec(),
        ..Default::default()
    };
    Box::new(Report {
        sub: data.dir.join("report"),
        data,
        diss: diss::Diss::load(),
        summary,
        tables: Vec::new(),
        conclusions: Vec::new(),
        per_adapter: None,
        per_adapter_cells: None,
        agreement: Default::default(),
        charts: Vec::new(),
        strips: Vec::new(),
        fronts: Vec::new(),
        pareto_svgs: Vec::new(),
        answers: Vec::new(),
        answer_charts: Vec::new(),
        scene_maps: Vec::new(),
        gpu: None,
        room_rows,
        mesh_rows,
        shipped: Err(Error::Input("no sweep rows: only room or mesh cells".into())),
    })
}

impl Report {
    /// The summary, once the documents are written (`index.html` last): its files with
    /// `index.html` first, then the documents, then every picture, chart and data file.
    pub(crate) fn finish(self) -> ReportSummary {
        let Report { mut summary, sub, .. } = self;
        let dir = summary.dir.clone();
        summary.files.rotate_right(1);
        summary.files.extend(self.charts.iter().map(|c| sub.join(&c.file)));
        summary.files.extend(self.gpu.iter().flat_map(|g| g.files.iter().map(|f| dir.join(f))));
        summary.files.extend(self.strips.iter().map(|s| dir.join(&s.file)));
        summary.files.extend(self.pareto_svgs.iter().map(|p| dir.join(&p.1)));
        summary.files.extend(self.answer_charts.iter().flatten().map(|c| dir.join(&c.file)));
        let mut maps: Vec<&String> = self.scene_maps.iter().flatten().collect();
        maps.dedup();
        summary.files.extend(maps.into_iter().map(|m| dir.join(m)));
        if let Ok(w) = self.shipped {
            summary.files.extend(w.files);
        }
        summary.conclusions = self.conclusions;
        summary
    }
}

/// Removes charts, strips and pictures an earlier report wrote (only names the report writes).
fn remove_stale(sub: &Path) {
    let Ok(rd) = std::fs::read_dir(sub) else { return };
    for e in rd.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let ours = ((name.starts_with("strip_") || name.starts_with("scene_")) && name.ends_with(".png"))
            || (name.starts_with("strip_") && name.ends_with(".html"))
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

/// Writes `bytes` to `path` atomically and records it in `files`.
pub(crate) fn write_file(path: &Path, bytes: &[u8], files: &mut Vec<PathBuf>) -> Result<()> {
    crate::io::write_atomic(path, bytes)?;
    files.push(path.to_path_buf());
    Ok(())
}

/// Whether `a` and `b` name the same folder.
pub(crate) fn same_dir(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => a == b,
    }
}
