//! The conclusions at each scene's own view and at the dissertation's, in `tables.md` only.

use super::{Report, Section};
use crate::report::conclusions;

/// The views section.
pub(crate) struct Views;

impl Section for Views {
    fn markdown(&self, r: &Report) -> Option<String> {
        conclusions::write::view_markdown(&conclusions::view_checks(&r.data, &r.diss))
    }
}
