//! `relief report DIR`: tables, conclusions, charts, image strips and Pareto fronts from a
//! sweep's `results.jsonl`, written next to it.
//!
//! Everything is written into `DIR` (charts, strips and per-table HTML under `DIR/report/`):
//! - `tables.md`: one table per dissertation table (Burger 2018, Tables 4.1–4.15), our
//!   measurements and the dissertation's numbers side by side, with trend columns (frame time
//!   and error relative to each row's base row), then the conclusions, checked.
//! - `pareto.md`: the least-error method for each frame-time budget, per scene.
//! - `report/*.svg`: charts like Figures 4.5 and 4.7–4.11, one per error metric.
//! - `report/strip_*.html`: frame and error images of each table's cells, stacked (the
//!   cells' own files, linked).
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
mod build;
mod charts;
mod conclusions;
mod data;
mod diss;
mod gpu_cost;
mod html;
mod labels;
mod pareto;
mod rooms;
mod sections;
mod stats;
mod strips;
mod summary;
mod tables;
mod text;

use std::path::{Path, PathBuf};

use crate::error::Result;
use build::write_file;
use sections::Section;

pub use add::{add, Added};
pub use conclusions::{Conclusion, Verdict};
pub use summary::ReportSummary;

/// The report's sections, in the order of the page (`index.html`); each with its place in
/// `tables.md`, which orders them otherwise (the particulars first, the Pareto fronts in
/// `pareto.md` of their own), or none where it has no part there. Adding a section is its
/// file under `sections/` and one line here.
const SECTIONS: &[(Option<u8>, &dyn Section)] = &[
    (Some(1), &sections::answer::Answers),
    (Some(5), &sections::conclusions::Conclusions),
    (Some(4), &sections::charts::Charts),
    (Some(3), &sections::tables::Tables),
    (None, &sections::pareto::Pareto),
    (None, &sections::stability::Stability),
    (None, &sections::live::Live),
    (Some(6), &sections::adapters::Adapters),
    (Some(7), &sections::lod::Lod),
    (Some(8), &sections::views::Views),
    (Some(2), &sections::gpu::Gpu),
    (Some(9), &sections::rooms::Rooms),
    (Some(9), &sections::meshes::Meshes),
    (Some(10), &sections::failed::Failed),
    (Some(0), &sections::about::About),
];

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
    let mut r = build::build(dirs, out)?;
    let dir = r.summary.dir.clone();
    // Folders holding only room or mesh cells: no sweep rows, so only the sections of other rows.
    let rooms_only = r.data.rows.is_empty();
    let sections: Vec<(Option<u8>, &dyn Section)> =
        SECTIONS.iter().copied().filter(|(_, s)| !rooms_only || !s.of_sweep()).collect();
    let mut in_md: Vec<(u8, &dyn Section)> = sections.iter().filter_map(|&(place, s)| Some((place?, s))).collect();
    in_md.sort_by_key(|(place, _)| *place);
    // What the folders hold apart from sweep rows, for the title of a report without them.
    let apart = match (r.room_rows.is_empty(), r.mesh_rows.is_empty()) {
        (false, true) => ("rooms", "room"),
        (true, false) => ("meshes", "mesh"),
        _ => ("rooms and meshes", "room and mesh"),
    };
    let mut md = if rooms_only {
        format!("# relief report: {}\n\n", apart.0)
    } else {
        "# relief report: Burger 2018, chapter 4, reproduced\n\n".to_string()
    };
    for (_, s) in in_md {
        md.extend(s.markdown(&r));
    }
    write_file(&dir.join("tables.md"), md.as_bytes(), &mut r.summary.files)?;
    for (_, s) in &sections {
        if let Some((name, text)) = s.file(&r) {
            write_file(&dir.join(name), text.as_bytes(), &mut r.summary.files)?;
        }
    }
    let page: Vec<_> = sections.iter().filter_map(|(_, s)| s.html(&r)).collect();
    let page = html::page(&r.data, &r.summary, &page, apart);
    write_file(&dir.join("index.html"), page.as_bytes(), &mut r.summary.files)?;
    Ok(r.finish())
}
