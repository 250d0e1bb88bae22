//! Image strips: for each table, each row's frame and error images side by side, rows
//! stacked in table order (a grey tile where a row has no image), at least 256 pixels high.

use std::path::Path;

use image::{imageops, Rgba, RgbaImage};

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

pub(crate) fn write_all(data: &Data, tables: &[ReportTable], sub: &Path, warnings: &mut Vec<String>) -> Vec<Strip> {
    let mut out = Vec::new();
    for t in tables {
        let mut tiles: Vec<(Option<RgbaImage>, Option<RgbaImage>)> = Vec::new();
        let mut labels = Vec::new();
        let mut frames = Vec::new();
        for (i, e) in t.entries.iter().enumerate() {
            let row = t.row(data, i).filter(|r| r.status.is_ok() && !r.cell_dir.is_empty());
            let load = |name: &str, warnings: &mut Vec<String>| -> Option<RgbaImage> {
                let r = row?;
                let path = data.dir.join(&r.cell_dir).join(name);
                if !path.exists() {
                    return None;
                }
                match crate::io::open_image(&path) {
                    Ok(img) => Some(scale(&img.to_rgba8())),
                    Err(err) => {
                        warnings.push(format!("cannot read picture {err}"));
                        None
                    }
                }
            };
            let f = load("frame.png", warnings);
            let er = load("error.png", warnings);
            let rel = |name: &str, present: bool| {
                present.then(|| format!("{}/{name}", row.map(|r| r.cell_dir.as_str()).unwrap_or("")))
            };
            frames.push(Frame {
                number: Some(i + 1),
                label: e.label.clone(),
                frame: rel("frame.png", f.is_some()),
                error: rel("error.png", er.is_some()),
                values: caption_values(t.row(data, i)),
            });
            tiles.push((f, er));
            labels.push(format!("{}. {}", i + 1, e.label));
        }
        let with_images = tiles.iter().filter(|(a, b)| a.is_some() || b.is_some()).count();
        if with_images == 0 {
            continue;
        }
        let width_of = |x: &Option<RgbaImage>| x.as_ref().map(|i| i.width()).unwrap_or(TILE);
        let left = tiles.iter().map(|(a, _)| width_of(a)).max().unwrap_or(TILE);
        let right = tiles.iter().map(|(_, b)| width_of(b)).max().unwrap_or(TILE);
        let n = tiles.len() as u32;
        let (w, h) = (left + GAP + right, n * TILE + n.saturating_sub(1) * GAP);
        let mut canvas = RgbaImage::from_pixel(w, h, Rgba([255, 255, 255, 255]));
        for (k, (a, b)) in tiles.iter().enumerate() {
            let y = k as u32 * (TILE + GAP);
            for (img, x) in [(a, 0u32), (b, left + GAP)] {
                match img {
                    Some(img) => imageops::overlay(&mut canvas, img, x as i64, y as i64),
                    None => {
                        let grey = RgbaImage::from_pixel(TILE, TILE, Rgba([200, 200, 200, 255]));
                        imageops::overlay(&mut canvas, &grey, x as i64, y as i64);
                    }
                }
            }
        }
        let name = format!("strip_{}.png", super::text::file_safe(&t.key));
        let path = sub.join(&name);
        let (w, h) = canvas.dimensions();
        match crate::io::png::write_rgba8(&path, w, h, canvas.into_raw()) {
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

/// Scales an image to TILE pixels high, keeping its aspect (at most 2 TILE wide).
fn scale(img: &RgbaImage) -> RgbaImage {
    let (w, h) = img.dimensions();
    if w == 0 || h == 0 {
        return RgbaImage::from_pixel(TILE, TILE, Rgba([200, 200, 200, 255]));
    }
    let nw = ((w as u64 * TILE as u64) / h as u64).clamp(1, 2 * TILE as u64) as u32;
    imageops::resize(img, nw, TILE, imageops::FilterType::Triangle)
}
