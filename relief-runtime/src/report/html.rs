//! `index.html`: the whole report on one page, readable offline (relative links only, no
//! scripts, no external styles).

use std::fmt::Write as _;

use super::charts::{Chart, FIGURES};
use super::conclusions::{self, Conclusion};
use super::pareto::{self, Front};
use super::strips::Strip;
use super::tables::ReportTable;
use super::{anchor, short_scene, Data, ReportSummary, TextTable};

pub(crate) struct Parts<'a> {
    pub data: &'a Data,
    pub summary: &'a ReportSummary,
    pub tables: &'a [ReportTable],
    pub conclusions: &'a [Conclusion],
    pub agreement: &'a TextTable,
    pub charts: &'a [Chart],
    pub strips: &'a [Strip],
    pub fronts: &'a [Front],
    pub pareto_svgs: &'a [(usize, String)],
}

pub(crate) fn esc(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// Escapes text and turns Markdown's `code` and **bold** into HTML.
pub(crate) fn md_inline(s: &str) -> String {
    let mut out = String::new();
    for (i, part) in s.split('`').enumerate() {
        if i % 2 == 1 {
            let _ = write!(out, "<code>{}</code>", esc(part));
        } else {
            for (j, p) in part.split("**").enumerate() {
                if j % 2 == 1 {
                    let _ = write!(out, "<b>{}</b>", esc(p));
                } else {
                    out.push_str(&esc(p));
                }
            }
        }
    }
    out
}

pub(crate) const STYLE: &str = "body{font-family:sans-serif;margin:1.5em;max-width:110em;color:#222}\
table{border-collapse:collapse;margin:.5em 0 1.5em;font-size:13px}\
th,td{border:1px solid #ccc;padding:2px 6px;text-align:left;vertical-align:top}\
th{background:#f0f0f0}td.holds{background:#dfd}td.fails{background:#fdd}td.err{background:#fdd}\
code{font-size:12px}img{max-width:100%}.frames{display:flex;flex-wrap:wrap;gap:.8em}\
.frames figure{margin:0;font-size:12px;max-width:300px}.noimg{display:inline-block;width:128px;height:128px;background:#ccc;color:#555;text-align:center}nav a{margin-right:1em}.fig{display:inline-block;margin:0 1em 1em 0}\
.strip{display:flex;gap:1em;align-items:flex-start}.strip ol{font-size:12px;margin:0}";

/// Splits a Markdown table line into its cells (`\|` is a literal bar).
fn md_cells(line: &str) -> Vec<String> {
    let inner = line.trim().trim_start_matches('|');
    let inner = inner.strip_suffix('|').filter(|s| !s.ends_with('\\')).unwrap_or(inner);
    let mut cells = vec![String::new()];
    let mut chars = inner.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '\\' if chars.peek() == Some(&'|') => {
                cells.last_mut().expect("one cell").push('|');
                chars.next();
            }
            '|' => cells.push(String::new()),
            _ => cells.last_mut().expect("one cell").push(c),
        }
    }
    cells.into_iter().map(|c| c.trim().to_string()).collect()
}

/// Markdown as written by relief's own writers (headings, paragraphs, pipe tables) as
/// HTML: tables become `<table>`, never preformatted text.
pub(crate) fn md_block(md: &str) -> String {
    let mut h = String::new();
    let lines: Vec<&str> = md.lines().collect();
    let mut i = 0;
    while i < lines.len() {
        let l = lines[i].trim();
        if l.starts_with('|') {
            let mut block = Vec::new();
            while i < lines.len() && lines[i].trim().starts_with('|') {
                block.push(lines[i].trim());
                i += 1;
            }
            let is_sep = |s: &str| md_cells(s).iter().all(|c| !c.is_empty() && c.chars().all(|ch| ch == '-' || ch == ':'));
            h.push_str("<table>\n");
            let (head, body) = if block.len() >= 2 && is_sep(block[1]) { (Some(block[0]), &block[2..]) } else { (None, &block[..]) };
            if let Some(head) = head {
                h.push_str("<thead><tr>");
                for c in md_cells(head) {
                    let _ = write!(h, "<th>{}</th>", md_inline(&c));
                }
                h.push_str("</tr></thead>\n");
            }
            h.push_str("<tbody>\n");
            for r in body {
                h.push_str("<tr>");
                for c in md_cells(r) {
                    let _ = write!(h, "<td>{}</td>", md_inline(&c));
                }
                h.push_str("</tr>\n");
            }
            h.push_str("</tbody></table>\n");
            continue;
        }
        if let Some(t) = l.strip_prefix('#') {
            let _ = writeln!(h, "<h4>{}</h4>", md_inline(t.trim_start_matches('#').trim()));
        } else if !l.is_empty() {
            let _ = writeln!(h, "<p>{}</p>", md_inline(l));
        }
        i += 1;
    }
    h
}

pub(crate) fn page(p: &Parts) -> String {
    let mut h = String::new();
    let _ = writeln!(h, "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>relief report</title><style>{STYLE}</style></head><body>");
    let _ = writeln!(h, "<h1>relief report: Burger 2018, chapter 4, reproduced</h1>");
    let _ = writeln!(
        h,
        "<nav><a href=\"#overview\">Overview</a><a href=\"#conclusions\">Conclusions</a><a href=\"#charts\">Charts</a>\
         <a href=\"#tables\">Tables</a><a href=\"#pareto\">Pareto fronts</a><a href=\"#failed\">Failed cells</a>\
         <a href=\"#stability\">Stability</a><a href=\"tables.md\">tables.md</a><a href=\"pareto.md\">pareto.md</a><a href=\"results.csv\">results.csv</a></nav>"
    );

    // Overview.
    let s = p.summary;
    let _ = writeln!(h, "<h2 id=\"overview\">Overview</h2><ul>");
    let _ = writeln!(h, "<li>Sweep folder: <code>{}</code></li>", esc(&p.data.dir.display().to_string()));
    let _ = writeln!(h, "<li>Rows: {} ({} ok, {} failed{})</li>", s.rows, s.ok, s.failed.len(), if s.bad_lines.is_empty() { String::new() } else { format!(", {} unreadable lines skipped", s.bad_lines.len()) });
    let _ = writeln!(h, "<li>Scenes: {}</li>", esc(&p.data.scenes().iter().map(|x| format!("{} ({})", short_scene(x), crate::scene::scene_kind(x).label())).collect::<Vec<_>>().join(", ")));
    let _ = writeln!(h, "<li>Sizes: {}</li>", esc(&p.data.distinct(|r| r.metrics.size.to_string()).join(", ")));
    let _ = writeln!(h, "<li>Adapters: {}</li>", esc(&p.data.distinct(|r| r.metrics.adapter.clone()).join("; ")));
    let _ = writeln!(h, "</ul>");

    // Stability, when `relief stability --out DIR/stability` has run.
    let stab = p.data.dir.join("stability");
    if let Ok(worst) = std::fs::read_to_string(stab.join("worst.md")) {
        let _ = writeln!(h, "<h2 id=\"stability\">Stability: where each method fails</h2>");
        let _ = writeln!(h, "<p><a href=\"stability/stability.csv\">stability.csv</a>; heat maps (method × scene and angle):</p><ul>");
        for metric in ["nan_count", "outside_count", "missed_rate", "nonconverged_rate", "ref_err_t_max", "ref_err_t_rms"] {
            let f = format!("stability/stability_{metric}.svg");
            if stab.join(format!("stability_{metric}.svg")).exists() {
                let _ = writeln!(h, "<li><a href=\"{f}\">{metric}</a></li>");
            }
        }
        let _ = writeln!(h, "</ul><h3>Worst condition per method</h3>");
        h.push_str(&md_block(&worst));
    }

    // Conclusions.
    let ct = conclusions::table(p.conclusions);
    h.push_str(&ct.to_html(2));
    h.push_str("<ul>");
    for l in conclusions::summary_lines(p.conclusions) {
        let _ = write!(h, "<li>{}</li>", md_inline(&l));
    }
    h.push_str("</ul>\n");
    h.push_str(&p.agreement.to_html(3));

    // Charts.
    let _ = writeln!(h, "<h2 id=\"charts\">Charts</h2>");
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
                "<div class=\"fig\"><a href=\"report/{f}\"><img src=\"report/{f}\" alt=\"{t}\" width=\"640\"></a><br><small>{cap}</small></div>",
                f = esc(&c.file),
                t = esc(&c.title),
                cap = esc(&c.caption)
            );
        }
    }

    // Tables with their strips.
    let _ = writeln!(h, "<h2 id=\"tables\">Tables</h2>");
    h.push_str(&format!("<p>{}</p>", md_inline(super::tables::intro_md().trim_start_matches("## Tables").trim())));
    for t in p.tables {
        h.push_str(&t.table.to_html(3));
        if let Some(st) = p.strips.iter().find(|s| s.key == t.key) {
            let _ = writeln!(
                h,
                "<details><summary>Image strip: frame | error per row ({} of {} rows with images; <a href=\"{f}\">as one image</a>)</summary><div class=\"frames\">",
                st.with_images,
                st.rows.len(),
                f = esc(&st.file)
            );
            for fr in &st.frames {
                h.push_str("<figure>");
                for (img, what) in [(&fr.frame, "frame"), (&fr.error, "error")] {
                    match img {
                        Some(src) => {
                            let _ = write!(h, "<img src=\"{}\" alt=\"{} {}\" height=\"128\">", esc(src), what, esc(&fr.label));
                        }
                        None => {
                            let _ = write!(h, "<span class=\"noimg\">no {what}</span>");
                        }
                    }
                }
                let (num, pipeline) = fr.label.split_once(". ").unwrap_or(("", &fr.label));
                let _ = write!(h, "<figcaption>#{} <code>{}</code><br>{}</figcaption></figure>", esc(num), esc(pipeline), esc(&fr.values));
            }
            h.push_str("</div></details>\n");
        }
    }

    // Pareto.
    let _ = writeln!(h, "<h2 id=\"pareto\">Pareto fronts</h2>");
    if p.fronts.is_empty() {
        h.push_str("<p>No ok rows.</p>");
    }
    for (i, f) in p.fronts.iter().enumerate() {
        let t = pareto::table(f);
        h.push_str(&t.to_html(3));
        if let Some((_, file)) = p.pareto_svgs.iter().find(|(j, _)| *j == i) {
            let _ = writeln!(h, "<p><img src=\"{}\" alt=\"{}\" width=\"640\"></p>", esc(file), esc(&t.title));
        }
    }

    // Failed.
    let _ = writeln!(h, "<h2 id=\"failed\">Failed cells</h2>");
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
    h.push_str("\n</body></html>\n");
    h
}
