//! The room grid (`rooms`), when the folder holds one.

use super::{Report, Section};
use crate::report::build::write_file;
use crate::report::html::PageSection;
use crate::report::rooms;
use crate::report::summary::ReportSummary;

/// The rooms section.
pub(crate) struct Rooms;

impl Section for Rooms {
    fn markdown(&self, r: &Report) -> Option<String> {
        r.room_rows.as_deref().map(rooms::to_markdown)
    }
    fn html(&self, r: &Report) -> Option<PageSection> {
        r.room_rows.as_deref().map(|rr| PageSection {
            id: "rooms".into(),
            nav: "Rooms".into(),
            html: rooms::to_html(rr),
        })
    }
}

/// The report of a folder holding only a room grid (`relief sweep --grid rooms`): the room
/// section as `tables.md` and `index.html`.
pub(crate) fn write_only(
    dir: &std::path::Path,
    rows: &[crate::room::sweep::RoomRow],
) -> crate::error::Result<ReportSummary> {
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
        crate::report::html::STYLE,
        rooms::to_html(rows)
    );
    write_file(&dir.join("index.html"), page.as_bytes(), &mut summary.files)?;
    Ok(summary)
}
