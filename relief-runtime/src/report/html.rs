//! `index.html`: the whole report on one page, readable offline (relative links only, the
//! stylesheet and script embedded from `relief-runtime/web/`, no external resource).
//!
//! The page is the report's sections in the order of `super::SECTIONS`, each a
//! [`PageSection`] its own file under `sections/` builds; this module holds the page around
//! them and the HTML helpers the sections share.

use std::fmt::Write as _;

use super::data::Data;
use super::strips::Frame;
use super::summary::ReportSummary;
use super::text::{anchor, TextTable};

/// The page's stylesheet (light and dark schemes).
pub(crate) const STYLE: &str = include_str!("../../web/report.css");
/// The page's script: sortable and filterable tables, links that open folded sections.
pub(crate) const SCRIPT: &str = include_str!("../../web/report.js");

/// One section of the page: its id (the target of its navigation link), its name in the
/// navigation, and its HTML (heading included).
pub(crate) struct PageSection {
    pub id: String,
    pub nav: String,
    pub html: String,
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
/// HTML: tables become sortable `<table>`s (ids from `id_base`), never preformatted text.
pub(crate) fn md_block(md: &str, id_base: &str) -> String {
    let mut h = String::new();
    let lines: Vec<&str> = md.lines().collect();
    let mut i = 0;
    let mut n = 0;
    while i < lines.len() {
        let l = lines[i].trim();
        if l.starts_with('|') {
            let mut block = Vec::new();
            while i < lines.len() && lines[i].trim().starts_with('|') {
                block.push(lines[i].trim());
                i += 1;
            }
            let is_sep =
                |s: &str| md_cells(s).iter().all(|c| !c.is_empty() && c.chars().all(|ch| ch == '-' || ch == ':'));
            n += 1;
            let _ = writeln!(h, "<table class=\"sortable\" id=\"{id_base}-{n}\">");
            let (head, body) =
                if block.len() >= 2 && is_sep(block[1]) { (Some(block[0]), &block[2..]) } else { (None, &block[..]) };
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

/// A table folded under its title (`<details>`, closed unless `open`), with a filter by
/// pipeline text and `after` (a picture strip, say) below it.
pub(crate) fn folded(t: &TextTable, level: usize, open: bool, after: &str) -> String {
    let id = anchor(&t.title);
    let lv = level.clamp(2, 6);
    let mut h = String::new();
    let _ = writeln!(
        h,
        "<details id=\"{id}\"{}><summary><h{lv}>{}</h{lv}></summary>",
        if open { " open" } else { "" },
        md_inline(&t.title)
    );
    for n in &t.notes {
        let _ = writeln!(h, "<p>{}</p>", md_inline(n));
    }
    if !t.header.is_empty() {
        let _ = writeln!(h, "<input class=\"filter\" type=\"search\" placeholder=\"filter rows by pipeline\" aria-label=\"filter rows by pipeline\" data-table=\"{id}-table\" hidden>");
        h.push_str(&t.table_html(&format!("{id}-table")));
    }
    h.push_str(after);
    h.push_str("</details>\n");
    h
}

/// The whole page: a header with the navigation, then `sections` in order.
/// `apart`: what a report without sweep rows holds, as its title and as a noun for its cells
/// (`("rooms", "room")`).
pub(crate) fn page(data: &Data, summary: &ReportSummary, sections: &[PageSection], apart: (&str, &str)) -> String {
    let mut h = String::new();
    let _ = writeln!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\
         <meta name=\"color-scheme\" content=\"light dark\"><title>relief report</title><link rel=\"icon\" href=\"data:,\"><style>{STYLE}</style></head><body>"
    );
    // No sweep rows: the folders hold only room or mesh cells (`relief sweep --grid rooms`, `meshes`).
    let rooms_only = data.rows.is_empty();
    if rooms_only {
        let _ = writeln!(h, "<header><h1>relief report: {}</h1>", apart.0);
        let _ = writeln!(h, "<p class=\"lead\">{} {} cells ({} ok).</p>", summary.rows, apart.1, summary.ok);
    } else {
        let _ = writeln!(
            h,
            "<header><h1>relief report: which relief-mapping search is fastest at the accuracy you need?</h1>"
        );
        let _ = writeln!(
            h,
            "<p class=\"lead\">{} rows ({} ok) on {} · Burger 2018, chapter 4, reproduced below the answer.</p>",
            summary.rows,
            summary.ok,
            esc(&data.distinct(|r| r.metrics.adapter.clone()).join("; "))
        );
    }
    h.push_str("<nav class=\"toc\">");
    for s in sections {
        let _ = write!(h, "<a href=\"#{}\">{}</a>", s.id, esc(&s.nav));
    }
    h.push_str("<a href=\"tables.md\">tables.md</a>");
    if !rooms_only {
        h.push_str("<a href=\"pareto.md\">pareto.md</a>");
    }
    if data.dir.join(crate::results::CSV).is_file() {
        h.push_str("<a href=\"results.csv\">results.csv</a>");
    }
    h.push_str("</nav></header>\n");
    for s in sections {
        let _ = writeln!(h, "<section id=\"{}\">\n{}</section>", s.id, s.html);
    }
    let _ = writeln!(h, "<script>{SCRIPT}</script>\n</body></html>");
    h
}

/// A frame and its error image side by side, each linking to the full-size PNG, with a
/// caption.
pub(crate) fn shot(f: &Frame) -> String {
    let mut h = String::from("<figure class=\"shot\"><div class=\"pair\">");
    for (img, what) in [(&f.frame, "frame"), (&f.error, "error")] {
        match img {
            Some(src) => {
                let _ = write!(
                    h,
                    "<a href=\"{s}\"><img src=\"{s}\" alt=\"{what} of {}\" loading=\"lazy\"></a>",
                    esc(&f.label),
                    s = esc(src)
                );
            }
            None => {
                let _ = write!(h, "<span class=\"noimg\">no {what} image</span>");
            }
        }
    }
    let num = f.number.map(|n| format!("#{n} ")).unwrap_or_default();
    let _ =
        write!(h, "</div><figcaption>{num}<code>{}</code><br>{}</figcaption></figure>", esc(&f.label), esc(&f.values));
    h
}
