//! The conclusions at level 0 and at the footprint level (`lod=auto`), in `tables.md` only.

use super::{Report, Section};
use crate::report::conclusions;

/// The `lod` conclusions section.
pub(crate) struct Lod;

impl Section for Lod {
    fn markdown(&self, r: &Report) -> Option<String> {
        conclusions::write::lod_markdown(&conclusions::lod_checks(&r.data, &r.diss))
    }
}
