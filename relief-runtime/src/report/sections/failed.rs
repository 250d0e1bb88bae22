//! The failed cells and unreadable lines, and (on the page) the warnings.

use std::fmt::Write as _;

use super::{Report, Section};
use crate::report::data::short_scene;
use crate::report::html::{esc, PageSection};

/// The failed cells section.
pub(crate) struct Failed;

impl Section for Failed {
    fn markdown(&self, r: &Report) -> Option<String> {
        let s = &r.summary;
        let mut md = String::from("\n## Failed cells\n\n");
        if s.failed.is_empty() && s.bad_lines.is_empty() {
            md.push_str("None.\n");
            return Some(md);
        }
        for (p, sc, e) in &s.failed {
            let _ = writeln!(md, "- `{p}` on {}: {}", short_scene(sc), e.replace('\n', " "));
        }
        for l in &s.bad_lines {
            let _ = writeln!(md, "- unreadable results line: {l}");
        }
        Some(md)
    }
    fn html(&self, r: &Report) -> Option<PageSection> {
        Some(page(r))
    }
}

fn page(p: &Report) -> PageSection {
    let s = &p.summary;
    let mut h = String::from("<h2>Failed cells</h2>\n");
    if s.failed.is_empty() && s.bad_lines.is_empty() {
        h.push_str("<p>None.</p>");
    } else {
        h.push_str("<ul>");
        for (pl, sc, e) in &s.failed {
            let _ = write!(h, "<li><code>{}</code> on {}: {}</li>", esc(pl), esc(short_scene(sc)), esc(e));
        }
        for l in &s.bad_lines {
            let _ = write!(h, "<li>unreadable results line: {}</li>", esc(l));
        }
        h.push_str("</ul>");
    }
    if !s.warnings.is_empty() {
        h.push_str("<h3>Warnings</h3><ul>");
        for w in &s.warnings {
            let _ = write!(h, "<li>{}</li>", esc(w));
        }
        h.push_str("</ul>");
    }
    PageSection { id: "failed".into(), nav: "Failed cells".into(), html: h }
}
