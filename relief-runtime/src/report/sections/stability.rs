//! Stability (`relief stability --out DIR/stability`), on the page only, when it has run.

use std::fmt::Write as _;

use super::{Report, Section};
use crate::report::html::{esc, md_block, PageSection};

/// The stability section.
pub(crate) struct Stability;

impl Section for Stability {
    fn html(&self, r: &Report) -> Option<PageSection> {
        page(r)
    }
}

/// Stability, when `relief stability --out DIR/stability` has run: the heat maps first, the
/// per-method table folded.
fn page(p: &Report) -> Option<PageSection> {
    let stab = p.data.dir.join("stability");
    let worst = crate::io::read_regular_to_string(&stab.join("worst.md")).ok()?;
    let mut h = String::from("<h2>Stability: where each method fails</h2>\n");
    let csv = if stab.join("stability.csv").is_file() {
        "; the numbers are in <a href=\"stability/stability.csv\">stability.csv</a>"
    } else {
        ""
    };
    let mut maps: Vec<String> = std::fs::read_dir(&stab)
        .map(|rd| {
            rd.flatten()
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .filter(|n| n.starts_with("stability_") && n.ends_with(".svg"))
                .collect()
        })
        .unwrap_or_default();
    maps.sort();
    let _ = writeln!(h, "<p>Heat maps of method × scene and angle{csv}.</p>");
    if maps.iter().any(|m| m.starts_with("stability_meshes_")) {
        let _ = writeln!(
            h,
            "<p>The maps named <code>meshes_…</code> are the mesh conditions: the built-in sphere and torus, each with {}, at 75°, 85° and 89° from the normal at the frame's centre, each method under <code>curved=none</code>, <code>quadric</code> and <code>prism</code>, against the exact mesh reference (coverage error, RMS t in depths along the ray, hits past the first hit); their worst conditions are the second table below.</p>",
            crate::stability::mesh_maps_named("<code>", "</code>")
        );
    }
    h.push_str("<div class=\"heat\">");
    for m in &maps {
        let metric = m.trim_start_matches("stability_").trim_end_matches(".svg");
        let _ = write!(
            h,
            "<div class=\"fig\"><a href=\"stability/{f}\"><img src=\"stability/{f}\" alt=\"heat map of {metric}\" width=\"640\" loading=\"lazy\"></a><br><small>{metric}</small></div>",
            f = esc(m),
            metric = esc(metric)
        );
    }
    h.push_str("</div>\n<details id=\"stability-worst\"><summary><h3>Worst condition per method</h3></summary>\n");
    h.push_str(&md_block(&worst, "stability-worst"));
    h.push_str("</details>\n");
    Some(PageSection { id: "stability".into(), nav: "Stability".into(), html: h })
}
