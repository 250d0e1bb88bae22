//! The dissertation's conclusions, checked (`conclusions`), and how the two error metrics agree (`agreement`).

use std::fmt::Write as _;

use super::{Report, Section};
use crate::report::conclusions;
use crate::report::html::{esc, folded, md_inline, PageSection};

/// The conclusions section.
pub(crate) struct Conclusions;

impl Section for Conclusions {
    fn markdown(&self, r: &Report) -> Option<String> {
        Some(conclusions::write::to_markdown(&r.conclusions, &r.agreement))
    }
    fn html(&self, r: &Report) -> Option<PageSection> {
        Some(page(r))
    }
}

fn page(p: &Report) -> PageSection {
    let ct = conclusions::write::table(&p.conclusions);
    let mut h = format!("<h2>{}</h2>\n", esc(&ct.title));
    for n in &ct.notes {
        let _ = writeln!(h, "<p>{}</p>", md_inline(n));
    }
    h.push_str(&ct.table_html("conclusions-table"));
    h.push_str("<ul>");
    for l in conclusions::write::summary_lines(&p.conclusions) {
        let _ = write!(h, "<li>{}</li>", md_inline(&l));
    }
    h.push_str("</ul>\n");
    h.push_str(&folded(&p.agreement, 3, false, ""));
    PageSection { id: "conclusions".into(), nav: "Conclusions".into(), html: h }
}
