//! The live section (`browser`): the pipelines on the reader's GPU, on the page only.

use super::{Report, Section};
use crate::report::browser;
use crate::report::html::PageSection;

/// The live section.
pub(crate) struct Live;

impl Section for Live {
    fn html(&self, r: &Report) -> Option<PageSection> {
        Some(browser::section(&r.shipped))
    }
}
