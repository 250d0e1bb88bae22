//! The room grid (`rooms`), when the folders hold its cells; the one section of a report
//! whose folders hold nothing else.

use super::{Report, Section};
use crate::report::html::PageSection;
use crate::report::rooms;

/// The rooms section.
pub(crate) struct Rooms;

impl Section for Rooms {
    fn markdown(&self, r: &Report) -> Option<String> {
        (!r.room_rows.is_empty()).then(|| rooms::to_markdown(&r.room_rows))
    }
    fn html(&self, r: &Report) -> Option<PageSection> {
        (!r.room_rows.is_empty()).then(|| PageSection {
            id: "rooms".into(),
            nav: "Rooms".into(),
            html: rooms::to_html(&r.room_rows),
        })
    }
    fn of_sweep(&self) -> bool {
        false
    }
}
