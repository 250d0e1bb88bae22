//! The sweep's particulars: folders, rows, scenes, sizes, adapters, versions (first in `tables.md`, last on the page).

use std::fmt::Write as _;

use super::{Report, Section};
use crate::report::build::same_dir;
use crate::report::data::short_scene;
use crate::report::html::{esc, PageSection};

/// The sweep's particulars.
pub(crate) struct About;

impl Section for About {
    fn markdown(&self, r: &Report) -> Option<String> {
        let (data, s) = (&r.data, &r.summary);
        let mut md = String::new();
        let _ = writeln!(md, "Sweep folder: `{}`  ", data.dir.display());
        if s.sources.len() > 1 || s.sources.first().is_some_and(|d| !same_dir(d, &data.dir)) {
            let _ = writeln!(
                md,
                "Merged from: {}  ",
                s.sources.iter().map(|d| format!("`{}`", d.display())).collect::<Vec<_>>().join(", ")
            );
        }
        if s.adapters.len() > 1 {
            let _ = writeln!(md, "Adapters kept apart: {} (tables, charts and conclusions: the first; timing conclusions of each side by side)  ", s.adapters.join("; "));
        }
        let _ = writeln!(md, "Rows: {}  ", s.rows_counted());
        let _ =
            writeln!(md, "Scenes: {}  ", data.scenes().iter().map(|x| short_scene(x)).collect::<Vec<_>>().join(", "));
        let _ = writeln!(md, "Sizes: {}  ", data.distinct(|r| r.metrics.size.to_string()).join(", "));
        let _ = writeln!(md, "Adapters: {}  ", data.distinct(|r| r.metrics.adapter.clone()).join("; "));
        let _ = writeln!(md, "relief versions: {}\n", data.distinct(|r| r.relief_version.clone()).join(", "));
        Some(md)
    }
    fn html(&self, r: &Report) -> Option<PageSection> {
        Some(page(r))
    }
}

fn page(p: &Report) -> PageSection {
    let s = &p.summary;
    let mut h = String::from("<h2>This sweep</h2><ul>\n");
    let _ = writeln!(h, "<li>Sweep folder: <code>{}</code></li>", esc(&p.data.dir.display().to_string()));
    let _ = writeln!(h, "<li>Rows: {}</li>", s.rows_counted());
    let _ = writeln!(
        h,
        "<li>Scenes: {}</li>",
        esc(&p
            .data
            .scenes()
            .iter()
            .map(|x| format!("{} ({})", short_scene(x), crate::scene::scene_kind(x).label()))
            .collect::<Vec<_>>()
            .join(", "))
    );
    let _ = writeln!(h, "<li>Sizes: {}</li>", esc(&p.data.distinct(|r| r.metrics.size.to_string()).join(", ")));
    let _ = writeln!(h, "<li>Adapters: {}</li>", esc(&p.data.distinct(|r| r.metrics.adapter.clone()).join("; ")));
    let _ = writeln!(h, "<li>relief versions: {}</li>", esc(&p.data.distinct(|r| r.relief_version.clone()).join(", ")));
    h.push_str("</ul>\n");
    PageSection { id: "about".into(), nav: "This sweep".into(), html: h }
}
