//! The charts like the dissertation's figures (`charts`).

use std::fmt::Write as _;

use super::{Report, Section};
use crate::report::charts::{Chart, FIGURES};
use crate::report::html::{esc, PageSection};
use crate::report::text::anchor;

/// The charts section.
pub(crate) struct Charts;

impl Section for Charts {
    fn markdown(&self, r: &Report) -> Option<String> {
        let mut md = String::from("## Charts\n\n");
        if r.charts.is_empty() {
            md.push_str("No figure grid (f4.5, f4.7–f4.11) has ok rows.\n\n");
        }
        for c in &r.charts {
            let _ = writeln!(md, "![{}](report/{})  \n{}\n", c.title, c.file, c.caption);
        }
        Some(md)
    }
    fn html(&self, r: &Report) -> Option<PageSection> {
        Some(page(r))
    }
}

fn page(p: &Report) -> PageSection {
    let mut h = String::from("<h2>Charts</h2>\n");
    for (fig, title) in FIGURES {
        let _ = writeln!(h, "<h3 id=\"{}\">{}</h3>", anchor(fig), esc(title));
        let charts: Vec<&Chart> = p.charts.iter().filter(|c| c.figure == fig).collect();
        if charts.is_empty() {
            let _ = writeln!(h, "<p>Not measured: no ok rows of grid <code>{fig}</code>.</p>");
            continue;
        }
        for c in charts {
            let _ = writeln!(
                h,
                "<div class=\"fig\"><a href=\"report/{f}\"><img src=\"report/{f}\" alt=\"{t}\" width=\"640\" loading=\"lazy\"></a><br><small>{cap}</small></div>",
                f = esc(&c.file),
                t = esc(&c.title),
                cap = esc(&c.caption)
            );
        }
    }
    PageSection { id: "charts".into(), nav: "Charts".into(), html: h }
}
