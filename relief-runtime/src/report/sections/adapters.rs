//! Every cell with one column set per adapter (`adapters`), and the timing conclusions of each adapter side by side.

use super::{Report, Section};
use crate::report::html::PageSection;

/// The per-adapter section (only with several adapters or an added one).
pub(crate) struct Adapters;

impl Section for Adapters {
    fn markdown(&self, r: &Report) -> Option<String> {
        let md: String = r.per_adapter_cells.iter().chain(&r.per_adapter).map(|t| t.to_markdown(2)).collect();
        Some(md)
    }
    fn html(&self, r: &Report) -> Option<PageSection> {
        (r.per_adapter_cells.is_some() || r.per_adapter.is_some()).then(|| PageSection {
            id: "adapters".into(),
            nav: "Per adapter".into(),
            html: r.per_adapter_cells.iter().chain(&r.per_adapter).map(|t| t.to_html(2)).collect(),
        })
    }
}
