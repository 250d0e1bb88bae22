//! Text output: number formats and tables printable as Markdown or HTML.

use std::fmt::Write as _;

use super::html;
use crate::results::Row;

/// A cell of our columns: the value, "error" for a failed cell, "—" for a missing one.
pub(crate) fn ours(row: Option<&Row>, f: impl Fn(&Row) -> String) -> String {
    match row {
        None => DASH.into(),
        Some(r) if !r.status.is_ok() => "error".into(),
        Some(r) => f(r),
    }
}

pub(crate) const DASH: &str = "—";

pub(crate) fn fmt_ms(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.3}")
    } else {
        "NaN".into()
    }
}

pub(crate) fn fmt_sci(v: f64) -> String {
    if !v.is_finite() {
        "NaN".into()
    } else if v == 0.0 {
        "0".into()
    } else {
        format!("{v:.3e}")
    }
}

pub(crate) fn fmt_num(v: f64, decimals: usize) -> String {
    if v.is_finite() {
        format!("{v:.decimals$}")
    } else {
        "NaN".into()
    }
}

pub(crate) fn fmt_pct(v: Option<f64>) -> String {
    match v {
        Some(x) if x.is_finite() => format!("{x:.1}%"),
        _ => DASH.into(),
    }
}

/// A table of text cells, printable as Markdown or HTML.
#[derive(Clone, Debug, Default)]
pub(crate) struct TextTable {
    pub title: String,
    /// Paragraphs under the title.
    pub notes: Vec<String>,
    pub header: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

impl TextTable {
    pub(crate) fn to_markdown(&self, level: usize) -> String {
        let mut md = String::new();
        if !self.title.is_empty() {
            let _ = writeln!(md, "{} {}\n", "#".repeat(level.max(1)), self.title);
        }
        for n in &self.notes {
            let _ = writeln!(md, "{n}\n");
        }
        if self.header.is_empty() {
            return md;
        }
        let esc = |s: &str| s.replace('|', "\\|").replace('\n', " ");
        let _ = writeln!(md, "| {} |", self.header.iter().map(|h| esc(h)).collect::<Vec<_>>().join(" | "));
        let _ = writeln!(md, "|{}", self.header.iter().map(|_| "---|").collect::<String>());
        for r in &self.rows {
            let mut cells: Vec<String> = r.iter().map(|c| esc(c)).collect();
            cells.resize(self.header.len(), String::new());
            let _ = writeln!(md, "| {} |", cells.join(" | "));
        }
        md.push('\n');
        md
    }

    /// The table with its heading (`<hN id=…>` from the title) and notes.
    pub(crate) fn to_html(&self, level: usize) -> String {
        let mut h = String::new();
        let lv = level.clamp(1, 6);
        if !self.title.is_empty() {
            let _ = writeln!(h, "<h{lv} id=\"{}\">{}</h{lv}>", anchor(&self.title), html::md_inline(&self.title));
        }
        for n in &self.notes {
            let _ = writeln!(h, "<p>{}</p>", html::md_inline(n));
        }
        if self.header.is_empty() {
            return h;
        }
        h.push_str(&self.table_html(&format!("{}-table", anchor(&self.title))));
        h
    }

    /// The `<table>` alone, sortable by the page's script, with id `id`. A cell that starts
    /// with a verdict (`holds`, `does not hold`, `not measured`) shows it as a badge.
    pub(crate) fn table_html(&self, id: &str) -> String {
        let mut h = String::new();
        let _ = write!(h, "<table class=\"sortable\" id=\"{id}\">\n<thead><tr>");
        for c in &self.header {
            let _ = write!(h, "<th>{}</th>", html::esc(c));
        }
        h.push_str("</tr></thead>\n<tbody>\n");
        for r in &self.rows {
            h.push_str("<tr>");
            for c in r {
                let badge = [("holds", "holds"), ("does not hold", "fails"), ("not measured", "nm")].into_iter().find(
                    |(v, _)| c.starts_with(v) && c[v.len()..].chars().next().is_none_or(|ch| !ch.is_alphanumeric()),
                );
                match badge {
                    Some((v, class)) => {
                        let rest = c[v.len()..].trim_start();
                        let td = if class == "nm" { String::new() } else { format!(" class=\"{class}\"") };
                        let _ =
                            write!(h, "<td{td}><span class=\"badge {class}\">{v}</span>{}</td>", html::md_inline(rest));
                    }
                    None if c == "error" => {
                        let _ = write!(h, "<td class=\"err\">error</td>");
                    }
                    None => {
                        let _ = write!(h, "<td>{}</td>", html::md_inline(c));
                    }
                }
            }
            h.push_str("</tr>\n");
        }
        h.push_str("</tbody></table>\n");
        h
    }
}

/// An HTML id from a title.
pub(crate) fn anchor(title: &str) -> String {
    let mut s: String =
        title.chars().map(|c| if c.is_ascii_alphanumeric() { c.to_ascii_lowercase() } else { '-' }).collect();
    while s.contains("--") {
        s = s.replace("--", "-");
    }
    s.trim_matches('-').to_string()
}

/// A file-safe name.
pub(crate) fn file_safe(s: &str) -> String {
    s.chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' || c == '.' { c } else { '_' }).collect()
}
