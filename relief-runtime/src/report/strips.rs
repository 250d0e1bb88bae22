//! Image strips: for each table, a page with each row's frame and error images side by side,
//! rows stacked in table order (a grey tile where a row has no image), 256 pixels high; the
//! page links the cells' pictures, it does not copy them.

use std::path::Path;

use super::tables::ReportTable;
use super::{data::Data, text::fmt_ms, text::fmt_num, text::fmt_sci};

/// Height of each tile in pixels: frames are readable at this size.
pub(crate) const TILE: u32 = 256;
const GAP: u32 = 4;

/// A strip written under `report/`.
pub(crate) struct Strip {
    /// The table's key (`t4.1`).
    pub key: String,
    /// Path relative to the sweep folder (`report/strip_t4.1.png`).
    pub file: String,
    /// The label of each stacked row, in order.
    pub rows: Vec<String>,
    /// Rows that had at least one image.
    pub with_images: usize,
    /// Each row as a captioned frame, for the HTML figure.
    pub frames: Vec<Frame>,
}

/// One row of a strip as the HTML report shows it: its images and a caption naming the
/// pipeline and its metric values, so the strip reads without the table beside it.
pub(crate) struct Frame {
    /// Its row's number in the table (`3`), when it has one.
    pub number: Option<usize>,
    /// The pipeline (`linear(15)`).
    pub label: String,
    /// The frame and error images, relative to the sweep folder, when they exist.
    pub frame: Option<String>,
    pub error: Option<String>,
    /// `0.512 ms (median) · t error 1.2e-3 · skipped 0.0100 · …`, or why there are no values.
    pub values: String,
}

impl Frame {
    /// `3. linear(15)`, or the pipeline alone.
    pub(crate) fn numbered(&self) -> String {
        match self.number {
            Some(n) => format!("{n}. {}", self.label),
            None => self.label.clone(),
        }
    }
}

/// The caption values of a row.
pub(crate) fn caption_values(r: Option<&crate::results::Row>) -> String {
    match r {
        None => "not measured".into(),
        Some(r) if !r.status.is_ok() => format!("failed: {}", r.error.replace('\n', " ")),
        Some(r) => {
            let m = &r.metrics;
            let nan = if m.nan_count > 0 { format!(" · {} non-finite hits", m.nan_count) } else { String::new() };
            format!(
                "{} ms (median; mean {}) · t error {} (RMS) · skipped {} · MSE mean {} · {}²{nan}",
                fmt_ms(m.frame_ms_median),
                fmt_ms(m.frame_ms_mean),
                fmt_sci(m.ref_err_t_rms),
                fmt_num(m.skipped_rate, 4),
                fmt_sci(m.mse_dissertation_mean),
                m.size,
            )
        }
    }
}

/// Writes one strip page per table with at least one picture: `report/strip_KEY.html`, each
/// row's frame and error side by side in table order, at [`TILE`] pixels high (a grey tile
/// where a row has none). The page links the cells' own `frame.png` and `error.png`: the
/// pictures are not copied (a 256² frame is shown pixel for pixel, as the stacked PNG that
/// used to be written held it).
pub(crate) fn write_all(data: &Data, tables: &[ReportTable], sub: &Path, warnings: &mut Vec<String>) -> Vec<Strip> {
    let mut out = Vec::new();
    for t in tables {
        let mut labels = Vec::new();
        let mut frames = Vec::new();
        for (i, e) in t.entries.iter().enumerate() {
            let row = t.row(data, i).filter(|r| r.status.is_ok() && !r.cell_dir.is_empty());
            let rel = |name: &str| {
                let r = row?;
                let file = format!("{}/{name}", r.cell_dir);
                data.dir.join(&file).is_file().then_some(file)
            };
            frames.push(Frame {
                number: Some(i + 1),
                label: e.label.clone(),
                frame: rel("frame.png"),
                error: rel("error.png"),
                values: caption_values(t.row(data, i)),
            });
            labels.push(format!("{}. {}", i + 1, e.label));
        }
        let with_images = frames.iter().filter(|f| f.frame.is_some() || f.error.is_some()).count();
        if with_images == 0 {
            continue;
        }
        let name = format!("strip_{}.html", super::text::file_safe(&t.key));
        let path = sub.join(&name);
        match crate::io::write_atomic(&path, page(&t.key, &frames).as_bytes()) {
            Ok(()) => out.push(Strip {
                key: t.key.clone(),
                file: format!("report/{name}"),
                rows: labels,
                with_images,
                frames,
            }),
            Err(e) => warnings.push(format!("cannot write {}: {e}", path.display())),
        }
    }
    out
}

/// A strip page: the rows stacked, each its frame and error image ([`TILE`] pixels high,
/// `GAP` pixels apart) and its caption; image paths are relative to the sweep folder, the
/// page sits one folder below it.
fn page(key: &str, frames: &[Frame]) -> String {
    use super::html::esc;
    use std::fmt::Write as _;
    let mut h = format!(
        "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>Table {k}: frame and error of each row</title>\n\
         <style>body{{font-family:sans-serif;margin:8px}}.row{{display:flex;gap:{GAP}px;margin-bottom:{GAP}px;align-items:flex-start}}\
         .row img{{height:{TILE}px;display:block}}.none{{width:{TILE}px;height:{TILE}px;background:#c8c8c8}}\
         .cap{{font-size:12px;max-width:30em}}</style></head><body>\n<h1>Table {k}: frame and error of each row</h1>\n",
        k = esc(key)
    );
    for f in frames {
        h.push_str("<div class=\"row\">");
        for (img, what) in [(&f.frame, "frame"), (&f.error, "error")] {
            match img {
                Some(src) => {
                    let _ = write!(
                        h,
                        "<a href=\"../{s}\"><img src=\"../{s}\" alt=\"{what} of {}\"></a>",
                        esc(&f.label),
                        s = esc(src)
                    );
                }
                None => h.push_str("<div class=\"none\"></div>"),
            }
        }
        let _ = writeln!(h, "<div class=\"cap\"><code>{}</code><br>{}</div></div>", esc(&f.numbered()), esc(&f.values));
    }
    h.push_str("</body></html>\n");
    h
}
