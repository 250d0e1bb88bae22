//! The report's sections, one file each. A section builds its part of `tables.md`, its
//! section of `index.html` and any file of its own (`pareto.md`) from the typed data of
//! one report run ([`Report`], built once by `super::build`); `super::SECTIONS` lists them
//! in order, and both documents follow that list.

pub(crate) mod about;
pub(crate) mod adapters;
pub(crate) mod answer;
pub(crate) mod charts;
pub(crate) mod conclusions;
pub(crate) mod failed;
pub(crate) mod gpu;
pub(crate) mod live;
pub(crate) mod lod;
pub(crate) mod meshes;
pub(crate) mod pareto;
pub(crate) mod rooms;
pub(crate) mod stability;
pub(crate) mod tables;
pub(crate) mod views;

use std::path::PathBuf;

use super::answer::{Answer, AnswerChart};
use super::browser::Written;
use super::charts::Chart;
use super::conclusions::Conclusion;
use super::data::Data;
use super::diss::Diss;
use super::gpu_cost::GpuSection;
use super::html::PageSection;
use super::pareto::Front;
use super::strips::Strip;
use super::summary::ReportSummary;
use super::tables::ReportTable;
use super::text::TextTable;
use crate::results::Row;

/// One part of the report: what it adds to `tables.md`, to `index.html` and as a file of
/// its own. Each method gives nothing unless the section has that part.
pub(crate) trait Section: Sync {
    /// Its part of `tables.md`, heading included.
    fn markdown(&self, _r: &Report) -> Option<String> {
        None
    }
    /// Its section of `index.html` (heading included) and its entry in the navigation.
    fn html(&self, _r: &Report) -> Option<PageSection> {
        None
    }
    /// A file of its own in the report's folder: its name and its text.
    fn file(&self, _r: &Report) -> Option<(&'static str, String)> {
        None
    }
    /// Whether the section shows the sweep's rows (every section but the rooms'): a report
    /// of folders holding only room cells has none, and leaves such sections out.
    fn of_sweep(&self) -> bool {
        true
    }
}

/// The typed data of one report run, which every section reads: the rows, and what was
/// built and written from them (the pictures and charts already on disk).
pub(crate) struct Report {
    /// The rows of the adapter the tables show.
    pub data: Data,
    pub diss: Diss,
    /// The summary so far (warnings included); its `files` are completed by `finish`.
    pub summary: ReportSummary,
    /// `DIR/report`, where the charts, strips and pictures are.
    pub sub: PathBuf,
    pub tables: Vec<ReportTable>,
    pub conclusions: Vec<Conclusion>,
    /// The timing conclusions per adapter (several adapters only).
    pub per_adapter: Option<TextTable>,
    /// Every cell with a column set per adapter (several adapters or an added one).
    pub per_adapter_cells: Option<TextTable>,
    pub agreement: TextTable,
    pub charts: Vec<Chart>,
    pub strips: Vec<Strip>,
    pub fronts: Vec<Front>,
    /// The Pareto charts written: (index in `fronts`, file).
    pub pareto_svgs: Vec<(usize, String)>,
    pub answers: Vec<Answer>,
    /// One per answer, in order (None: no chart).
    pub answer_charts: Vec<Option<AnswerChart>>,
    /// The height map picture of each answer's scene, in order.
    pub scene_maps: Vec<Option<String>>,
    pub gpu: Option<GpuSection>,
    /// The room cells' rows (`relief sweep --grid rooms`), apart from `data`'s; empty when
    /// the folders hold none.
    pub room_rows: Vec<Row>,
    /// The mesh grid's rows (`relief sweep --grid meshes`), apart from `data`'s; empty when
    /// the folders hold none.
    pub mesh_rows: Vec<crate::results::Row>,
    /// The browser data the live section reads, or why there is none.
    pub shipped: crate::error::Result<Written>,
}
