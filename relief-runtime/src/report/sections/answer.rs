//! The answer: the fastest pipeline at each accuracy, per scene (`answer`), in `tables.md` and on the page.

use std::fmt::Write as _;

use super::{Report, Section};
use crate::report::answer::{self, Answer};
use crate::report::data::short_scene;
use crate::report::html::{esc, md_inline, shot, PageSection};
use crate::report::strips::Frame;
use crate::report::text::{fmt_ms, fmt_num, fmt_sci};

/// The answer section.
pub(crate) struct Answers;

impl Section for Answers {
    fn markdown(&self, r: &Report) -> Option<String> {
        Some(answer::to_markdown(&r.answers))
    }
    fn html(&self, r: &Report) -> Option<PageSection> {
        Some(page(r))
    }
}

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
        Some(r) => format!("{} ms · {}× baseline", fmt_ms(c.speed.ms), fmt_num(r.ratio, 2)),
        None => format!("{} ms", fmt_ms(c.speed.ms)),
    }
}

fn page(p: &Report) -> PageSection {
    let mut h = String::from("<h2>The answer: the fastest pipeline at each accuracy</h2>\n");
    if p.answers.is_empty() {
        h.push_str("<p>No ok row of a search pipeline (without shadow or AO stages, at level 0) was measured.</p>\n");
        return PageSection { id: "answer".into(), nav: "Answer".into(), html: h };
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
    for a in &p.answers {
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
                    fmt_num(c.skipped, 4)
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
    PageSection { id: "answer".into(), nav: "Answer".into(), html: h }
}
