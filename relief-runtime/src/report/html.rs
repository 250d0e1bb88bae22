//! `index.html`: the whole report on one page, readable offline (relative links only, the
//! stylesheet and script embedded from `relief-runtime/web/`, no external resource).
//!
//! The page is a list of [`Section`]s, each built by its own function from [`Parts`]: the
//! answer first, then the conclusions, charts, tables, Pareto fronts, stability, failed
//! cells and the sweep's particulars. A new section (or its own script) is one more entry
//! of [`sections`]; the navigation follows the list.

use std::fmt::Write as _;

use super::answer::{self, Answer, AnswerChart};
use super::charts::{Chart, FIGURES};
use super::conclusions::{self, Conclusion};
use super::pareto::{self, Front};
use super::strips::{Frame, Strip};
use super::tables::ReportTable;
use super::{anchor, fmt_ms, fmt_sci, short_scene, Data, ReportSummary, TextTable};

/// The page's stylesheet (light and dark schemes).
pub(crate) const STYLE: &str = include_str!("../../web/report.css");
/// The page's script: sortable and filterable tables, links that open folded sections.
pub(crate) const SCRIPT: &str = include_str!("../../web/report.js");

pub(crate) struct Parts<'a> {
    pub data: &'a Data,
    pub summary: &'a ReportSummary,
    pub answers: &'a [Answer],
    /// One per answer, in order (None: no chart).
    pub answer_charts: &'a [Option<AnswerChart>],
    /// The height map picture of each answer's scene, in order.
    pub scene_maps: &'a [Option<String>],
    pub tables: &'a [ReportTable],
    pub conclusions: &'a [Conclusion],
    pub agreement: &'a TextTable,
    pub charts: &'a [Chart],
    pub strips: &'a [Strip],
    pub fronts: &'a [Front],
    pub pareto_svgs: &'a [(usize, String)],
    /// Sections other parts of the report add (rooms), placed before the sweep's particulars.
    pub extra: Vec<Section>,
}

/// One section of the page: its id (the target of its navigation link), its name in the
/// navigation, and its HTML (heading included).
pub(crate) struct Section {
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

/// The sections of the page, in order.
pub(crate) fn sections(p: &mut Parts) -> Vec<Section> {
    let mut v =
        vec![answer_section(p), conclusions_section(p), charts_section(p), tables_section(p), pareto_section(p)];
    v.extend(stability_section(p));
    v.append(&mut p.extra);
    v.push(failed_section(p));
    v.push(about_section(p));
    v
}

pub(crate) fn page(mut p: Parts) -> String {
    let sections = sections(&mut p);
    let mut h = String::new();
    let _ = writeln!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\
         <meta name=\"color-scheme\" content=\"light dark\"><title>relief report</title><link rel=\"icon\" href=\"data:,\"><style>{STYLE}</style></head><body>"
    );
    let _ =
        writeln!(h, "<header><h1>relief report: which relief-mapping search is fastest at the accuracy you need?</h1>");
    let _ = writeln!(
        h,
        "<p class=\"lead\">{} rows ({} ok) on {} · Burger 2018, chapter 4, reproduced below the answer.</p>",
        p.summary.rows,
        p.summary.ok,
        esc(&p.data.distinct(|r| r.metrics.adapter.clone()).join("; "))
    );
    h.push_str("<nav class=\"toc\">");
    for s in &sections {
        let _ = write!(h, "<a href=\"#{}\">{}</a>", s.id, esc(&s.nav));
    }
    h.push_str("<a href=\"tables.md\">tables.md</a><a href=\"pareto.md\">pareto.md</a>");
    if p.data.dir.join("results.csv").is_file() {
        h.push_str("<a href=\"results.csv\">results.csv</a>");
    }
    h.push_str("</nav></header>\n");
    for s in &sections {
        let _ = writeln!(h, "<section id=\"{}\">\n{}</section>", s.id, s.html);
    }
    let _ = writeln!(h, "<script>{SCRIPT}</script>\n</body></html>");
    h
}

// ---------------------------------------------------------------------------------------
// The answer

/// One cell of the overview, kept to about two lines so that the whole table sits above the
/// fold: the fastest pipeline and its speed (and its t error where the level does not bound
/// it); under it the engine family's multiple (its pipeline in the tooltip; nothing where the
/// family was not measured: the row is greyed) and how many rows are not told apart from
/// the pick (their names in the tooltip; the scene's table lists them).
fn overview_cell(a: &Answer, k: usize, level: &answer::Level) -> String {
    let pick = &a.picks[k];
    let Some(b) = pick.best else {
        return "<td>unreachable</td>".into();
    };
    let c = &a.cands[b];
    let mut under = Vec::new();
    match pick.engine {
        Some(e) if e == b => under.push("in the engine family".to_string()),
        Some(e) => under.push(format!(
            "<span title=\"the engine family's fastest here: {}\">family: {}</span>",
            esc(&a.cands[e].pipeline),
            esc(&answer::ratio_cell(a, pick))
        )),
        None if a.engine_measured => under.push(esc(&answer::ratio_cell(a, pick))),
        None => {}
    }
    if !pick.ties.is_empty() {
        let n = pick.ties.len();
        under.push(format!(
            "<span title=\"not told apart from the fastest in this run (95 %): {}\">≈ {n} other{}</span>",
            esc(&answer::ties_cell(a, pick, 8).replace('`', "")),
            if n == 1 { "" } else { "s" }
        ));
    }
    let err = if level.bounds_error { String::new() } else { format!(" · t error {}", fmt_sci(c.err)) };
    let under =
        if under.is_empty() { String::new() } else { format!("<span class=\"fam\">{}</span>", under.join(" · ")) };
    format!("<td><code>{}</code> {}{err}{under}</td>", esc(&c.pipeline), esc(&speed_words(c)))
}

/// `1.234 ms`, or `1.234 ms · 0.81× baseline` under paired timing.
fn speed_words(c: &answer::Cand) -> String {
    match c.speed.paired {
        Some(r) => format!("{} ms · {}× baseline", fmt_ms(c.speed.ms), super::fmt_num(r.ratio, 2)),
        None => format!("{} ms", fmt_ms(c.speed.ms)),
    }
}

fn answer_section(p: &Parts) -> Section {
    let mut h = String::from("<h2>The answer: the fastest pipeline at each accuracy</h2>\n");
    if p.answers.is_empty() {
        h.push_str("<p>No ok row of a search pipeline (without shadow or AO stages, at level 0) was measured.</p>\n");
        return Section { id: "answer".into(), nav: "Answer".into(), html: h };
    }
    let levels = answer::levels();
    let _ = writeln!(
        h,
        "<p class=\"answer-lead\">Per scene and view: the fastest measured pipeline at each accuracy, and the \
         engine family's fastest there.</p>"
    );
    h.push_str("<table class=\"answer sortable\" id=\"answer-table\"><thead><tr><th>scene, view, size</th>");
    for l in &levels {
        let _ = write!(h, "<th>{}</th>", esc(l.name));
    }
    h.push_str("</tr></thead><tbody>\n");
    for a in p.answers {
        let _ = write!(
            h,
            "<tr{}><td><a href=\"#{}\">{}</a></td>",
            if a.engine_measured { "" } else { " class=\"unmeasured\"" },
            a.id,
            esc(&a.title)
        );
        for (k, level) in levels.iter().enumerate() {
            h.push_str(&overview_cell(a, k, level));
        }
        h.push_str("</tr>\n");
    }
    h.push_str("</tbody></table>\n");
    let _ = writeln!(
        h,
        "<p class=\"legend\">Each cell: the fastest pipeline whose RMS t error (<code>ref_err_t_rms</code>) is at most \
         the level, and its speed. <i>family</i>: the engine family's ({}) fastest there as a multiple of its time \
         (hover for its pipeline), <i>unreachable</i> where none of its rows gets there; greyed rows: the family was not \
         measured on that scene. <i>≈ N others</i>: rows that reach the level and cannot be told apart from the pick in \
         this run (hover for their names). The last column asks no bound on the t error: no ray of the row steps over \
         a surface it should have hit (<code>skipped_rate</code> exactly 0); its t error is given. Each scene's name \
         leads to its table, picture and chart.</p>\
         <details class=\"how\"><summary>How speed is compared</summary><p>Where the sweep timed every row against one \
         baseline in alternating blocks, “fastest” ranks by that paired ratio (<code>× baseline</code>); the family's multiple \
         carries its 95 % interval and is <i>not decided</i> where the interval reaches 1, and the rows that cannot be told \
         apart from the fastest are counted under it. Otherwise frame times are medians of one run and a multiple near 1 is \
         within the noise.</p></details>",
        md_inline(answer::ENGINE_FAMILY)
    );
    for (i, a) in p.answers.iter().enumerate() {
        let _ = writeln!(h, "<h3 id=\"{}\">{}</h3>", a.id, esc(&a.title));
        // The scene itself: its height map and the shaded frame of an exact pipeline.
        h.push_str("<div class=\"scene-head\">");
        if let Some(Some(map)) = p.scene_maps.get(i) {
            let _ = write!(
                h,
                "<figure class=\"shot\"><a href=\"{m}\"><img src=\"{m}\" alt=\"height map of {s}\" loading=\"lazy\"></a><figcaption>height map of {s} (white = top)</figcaption></figure>",
                m = esc(map),
                s = esc(short_scene(a.scene.split('@').next().unwrap_or(&a.scene)))
            );
        }
        if let Some(c) = a.exact_or_best() {
            let what = if c.err <= 1e-6 && c.skipped == 0.0 { "exact" } else { "most accurate measured" };
            let fr = Frame {
                number: None,
                label: c.pipeline.clone(),
                frame: Some(format!("{}/frame.png", c.cell_dir)).filter(|f| p.data.dir.join(f).is_file()),
                error: Some(format!("{}/error.png", c.cell_dir)).filter(|f| p.data.dir.join(f).is_file()),
                values: format!(
                    "{what}: {} · t error {} · skipped {}",
                    speed_words(c),
                    fmt_sci(c.err),
                    super::fmt_num(c.skipped, 4)
                ),
            };
            h.push_str(&shot(&fr));
        }
        h.push_str("</div>\n");
        let t = answer::table(a);
        for n in &t.notes {
            let _ = writeln!(h, "<p>{}</p>", md_inline(n));
        }
        h.push_str(&t.table_html(&format!("{}-table", a.id)));
        if let Some(Some(ch)) = p.answer_charts.get(i) {
            let _ = write!(
                h,
                "<div class=\"chart-key\"><a href=\"{f}\"><img src=\"{f}\" alt=\"frame time against t error, {t}\" width=\"860\" loading=\"lazy\"></a><div><b>Numbered points</b> (fronts: ● overall, ◆ engine family)<ol class=\"key\">",
                f = esc(&ch.file),
                t = esc(&a.title)
            );
            for k in &ch.key {
                let c = &a.cands[k.cand];
                let _ = write!(
                    h,
                    "<li value=\"{}\">{}{} <code>{}</code> {} · {}{}</li>",
                    k.number,
                    if k.on_all { "●" } else { "" },
                    if k.on_family { "◆" } else { "" },
                    esc(&c.pipeline),
                    esc(&speed_words(c)),
                    fmt_sci(c.err),
                    if k.drawn { "" } else { " <small>(no room for its number in the chart)</small>" }
                );
            }
            h.push_str("</ol>");
            if let Some(n) = &ch.note {
                let _ = write!(h, "<p><small>{}</small></p>", esc(n));
            }
            h.push_str("</div></div>\n");
        }
    }
    Section { id: "answer".into(), nav: "Answer".into(), html: h }
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

// ---------------------------------------------------------------------------------------
// The rest

fn conclusions_section(p: &Parts) -> Section {
    let ct = conclusions::table(p.conclusions);
    let mut h = format!("<h2>{}</h2>\n", esc(&ct.title));
    for n in &ct.notes {
        let _ = writeln!(h, "<p>{}</p>", md_inline(n));
    }
    h.push_str(&ct.table_html("conclusions-table"));
    h.push_str("<ul>");
    for l in conclusions::summary_lines(p.conclusions) {
        let _ = write!(h, "<li>{}</li>", md_inline(&l));
    }
    h.push_str("</ul>\n");
    h.push_str(&folded(p.agreement, 3, false, ""));
    Section { id: "conclusions".into(), nav: "Conclusions".into(), html: h }
}

fn charts_section(p: &Parts) -> Section {
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
    Section { id: "charts".into(), nav: "Charts".into(), html: h }
}

fn tables_section(p: &Parts) -> Section {
    let mut h = String::from("<h2>Tables</h2>\n");
    let _ = writeln!(
        h,
        "<p>Each table is folded: open it by its title. Click a column's heading to sort by it; type in the box to keep the rows \
         whose pipeline contains the text.</p><details><summary>How to read the columns</summary><p>{}</p></details>",
        md_inline(super::tables::intro_md().trim_start_matches("## Tables").trim())
    );
    h.push_str("<nav class=\"toc\">");
    for t in p.tables {
        let place = if t.scene == "scene:lion" { String::new() } else { format!(" ({})", short_scene(&t.scene)) };
        let size = t.size.filter(|_| p.data.sizes().len() > 1).map(|z| format!(" {z}²")).unwrap_or_default();
        let _ = write!(h, "<a href=\"#{}\">{}{place}{size}</a>", anchor(&t.table.title), esc(&t.id));
    }
    h.push_str("</nav>\n");
    for t in p.tables {
        let mut after = String::new();
        if let Some(st) = p.strips.iter().find(|s| s.key == t.key) {
            let _ = writeln!(
                after,
                "<h4>Pictures: frame and error of each row</h4><p><small>{} of {} rows with images; click a picture for full size; \
                 <a href=\"{f}\">all rows as one image</a>. Error images, one scale for all: |t − t_ref| black at 1e-6 or \
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
    Section { id: "tables".into(), nav: "Tables".into(), html: h }
}

fn pareto_section(p: &Parts) -> Section {
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
    Section { id: "pareto".into(), nav: "Pareto fronts".into(), html: h }
}

/// Stability, when `relief stability --out DIR/stability` has run: the heat maps first, the
/// per-method table folded.
fn stability_section(p: &Parts) -> Option<Section> {
    let stab = p.data.dir.join("stability");
    let worst = crate::io::read_regular_to_string(&stab.join("worst.md")).ok()?;
    let mut h = String::from("<h2>Stability: where each method fails</h2>\n");
    let csv = if stab.join("stability.csv").is_file() {
        "; the numbers are in <a href=\"stability/stability.csv\">stability.csv</a>"
    } else {
        ""
    };
    let _ = writeln!(h, "<p>Heat maps of method × scene and angle{csv}.</p>");
    let mut maps: Vec<String> = std::fs::read_dir(&stab)
        .map(|rd| {
            rd.flatten()
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .filter(|n| n.starts_with("stability_") && n.ends_with(".svg"))
                .collect()
        })
        .unwrap_or_default();
    maps.sort();
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
    Some(Section { id: "stability".into(), nav: "Stability".into(), html: h })
}

fn failed_section(p: &Parts) -> Section {
    let s = p.summary;
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
    Section { id: "failed".into(), nav: "Failed cells".into(), html: h }
}

fn about_section(p: &Parts) -> Section {
    let s = p.summary;
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
    Section { id: "about".into(), nav: "This sweep".into(), html: h }
}
