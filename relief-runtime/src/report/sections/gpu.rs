//! The GPU compiler's model beside the clock (`gpu_cost`), when the rows have its columns.

use super::{Report, Section};
use crate::report::html::PageSection;

/// The GPU model section.
pub(crate) struct Gpu;

impl Section for Gpu {
    fn markdown(&self, r: &Report) -> Option<String> {
        r.gpu.as_ref().map(|g| g.markdown.clone())
    }
    fn html(&self, r: &Report) -> Option<PageSection> {
        r.gpu.as_ref().map(|g| PageSection { id: "gpu-model".into(), nav: "GPU model".into(), html: g.html.clone() })
    }
}
