//! The Pareto fronts (`pareto`): on the page, and as their own file, `pareto.md`.

use super::{Report, Section};
use crate::report::html::{esc, folded, PageSection};
use crate::report::pareto;

/// The Pareto fronts section.
pub(crate) struct Pareto;

impl Section for Pareto {
    fn html(&self, r: &Report) -> Option<PageSection> {
        Some(page(r))
    }
    fn file(&self, r: &Report) -> Option<(&'static str, String)> {
        Some(("pareto.md", pareto::to_markdown(&r.fronts, &r.pareto_svgs)))
    }
}

fn page(p: &Report) -> PageSection {
    let mut h = String::from("<h2>Pareto fronts</h2>\n<p>For each scene and error metric: for each budget of mean frame time, the least-error method.</p>\n");
    if p.fronts.is_empty() {
        h.push_str("<p>No ok rows.</p>");
    }
    for (i, f) in p.fronts.iter().enumerate() {
        let t = pareto::table(f);
        let after = match p.pareto_svgs.iter().find(|(j, _)| *j == i) {
            Some((_, file)) => format!(
                "<p><a href=\"{f}\"><img src=\"{f}\" alt=\"{}\" width=\"640\" loading=\"lazy\"></a></p>",
                esc(&t.title),
                f = esc(file)
            ),
            None => String::new(),
        };
        h.push_str(&folded(&t, 3, false, &after));
    }
    PageSection { id: "pareto".into(), nav: "Pareto fronts".into(), html: h }
}
