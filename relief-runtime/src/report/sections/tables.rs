//! The dissertation's tables beside ours (`tables`), each with its picture strip (`strips`).

use std::fmt::Write as _;

use super::{Report, Section};
use crate::report::data::short_scene;
use crate::report::html::{esc, folded, md_inline, shot, PageSection};
use crate::report::text::anchor;

/// The tables section.
pub(crate) struct Tables;

impl Section for Tables {
    fn markdown(&self, r: &Report) -> Option<String> {
        let mut md = crate::report::tables::intro_md();
        for t in &r.tables {
            md.push_str(&t.table.to_markdown(2));
            if let Some(s) = r.strips.iter().find(|s| s.key == t.key) {
                let _ = writeln!(md, "Image strip (rows in table order, frame | error): [{}]({})\n", s.file, s.file);
                for f in &s.frames {
                    let _ = writeln!(md, "- {}: {}", f.numbered(), f.values);
                }
                md.push('\n');
            }
        }
        Some(md)
    }
    fn html(&self, r: &Report) -> Option<PageSection> {
        Some(page(r))
    }
}

fn page(p: &Report) -> PageSection {
    let mut h = String::from("<h2>Tables</h2>\n");
    let _ = writeln!(
        h,
        "<p>Each table is folded: open it by its title. Click a column's heading to sort by it; type in the box to keep the rows \
         whose pipeline contains the text.</p><details><summary>How to read the columns</summary><p>{}</p></details>",
        md_inline(crate::report::tables::intro_md().trim_start_matches("## Tables").trim())
    );
    h.push_str("<nav class=\"toc\">");
    for t in &p.tables {
        let place = if t.scene == "scene:lion" { String::new() } else { format!(" ({})", short_scene(&t.scene)) };
        let size = t.size.filter(|_| p.data.sizes().len() > 1).map(|z| format!(" {z}²")).unwrap_or_default();
        let _ = write!(h, "<a href=\"#{}\">{}{place}{size}</a>", anchor(&t.table.title), esc(&t.id));
    }
    h.push_str("</nav>\n");
    for t in &p.tables {
        let mut after = String::new();
        if let Some(st) = p.strips.iter().find(|s| s.key == t.key) {
            let _ = writeln!(
                after,
                "<h4>Pictures: frame and error of each row</h4><p><small>{} of {} rows with images; click a picture for full size; \
                 <a href=\"{f}\">all rows on one page</a>. Error images, one scale for all: |t − t_ref| black at 1e-6 or \
                 less, red at 1e-3, yellow at 1 (log scale), magenta = no finite hit.</small></p><div class=\"shots\">",
                st.with_images,
                st.rows.len(),
                f = esc(&st.file)
            );
            for fr in &st.frames {
                after.push_str(&shot(fr));
            }
            after.push_str("</div>\n");
        }
        h.push_str(&folded(&t.table, 3, false, &after));
    }
    PageSection { id: "tables".into(), nav: "Tables".into(), html: h }
}
