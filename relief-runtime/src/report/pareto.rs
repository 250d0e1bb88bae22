//! The Pareto front per scene: for each frame-time budget, the least-error method among the
//! ok rows (search pipelines only: rows with a shadow or AO stage add shading cost, not
//! search accuracy, and are left out).

use std::fmt::Write as _;
use std::path::Path;

use relief_dsl::Pipeline;

use super::charts::{svg_chart, Line, Pt, Series};
use super::{fmt_ms, fmt_sci, short_scene, Data, Metric, TextTable};

pub(crate) struct Front {
    pub scene: String,
    pub metric: Metric,
    /// (pipeline, frame ms, error) on the front, fastest first.
    pub front: Vec<(String, f64, f64)>,
    /// Every candidate row.
    pub all: Vec<(String, f64, f64)>,
}

pub(crate) fn build(data: &Data) -> Vec<Front> {
    let mut out = Vec::new();
    for scene in data.scenes() {
        for metric in [Metric::RefT, Metric::Mse] {
            let mut all: Vec<(String, f64, f64)> = Vec::new();
            for r in &data.rows {
                if r.status != "ok" || r.metrics.scene != scene {
                    continue;
                }
                // Only the row the index picked for this pipeline.
                if !data.get(&r.metrics.pipeline, &scene).is_some_and(|x| std::ptr::eq(x, r)) {
                    continue;
                }
                if let Ok(p) = r.metrics.pipeline.parse::<Pipeline>() {
                    if !p.shadow.is_none() || !p.ao.is_none() {
                        continue;
                    }
                }
                let (ms, e) = (r.metrics.frame_ms_median, metric.of(r));
                if ms.is_finite() && e.is_finite() {
                    all.push((r.metrics.pipeline.clone(), ms, e));
                }
            }
            all.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.2.total_cmp(&b.2)));
            let mut front: Vec<(String, f64, f64)> = Vec::new();
            for c in &all {
                if front.last().is_none_or(|l| c.2 < l.2) {
                    front.push(c.clone());
                }
            }
            if !all.is_empty() {
                out.push(Front { scene: scene.clone(), metric, front, all });
            }
        }
    }
    out
}

/// The front as a budget table.
pub(crate) fn table(f: &Front) -> TextTable {
    let mut rows = Vec::new();
    for (i, (p, ms, e)) in f.front.iter().enumerate() {
        let until = f.front.get(i + 1).map(|n| format!("< {}", fmt_ms(n.1))).unwrap_or_else(|| "and more".into());
        rows.push(vec![format!("≥ {} {until}", fmt_ms(*ms)), format!("`{p}`"), fmt_sci(*e), fmt_ms(*ms)]);
    }
    TextTable {
        title: format!("Pareto front, scene {}, by {}", short_scene(&f.scene), f.metric.name()),
        notes: vec![format!(
            "{} candidate rows (no shadow / AO stages), {} on the front. For a frame-time budget in the first column, the second column is the least-error method.",
            f.all.len(),
            f.front.len()
        )],
        header: ["budget (ms)", "least-error method", f.metric.name(), "its frame ms"].iter().map(|s| s.to_string()).collect(),
        rows,
    }
}

/// One SVG per front: every candidate faint, the front as a staircase. Returns
/// (index into `fronts`, file relative to the sweep folder).
pub(crate) fn write_svgs(fronts: &[Front], sub: &Path, warnings: &mut Vec<String>) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    for (i, f) in fronts.iter().enumerate() {
        let series = vec![
            Series {
                name: "all rows".into(),
                points: f.all.iter().map(|(p, x, y)| Pt { x: *x, y: *y, label: p.clone() }).collect(),
                line: Line::None,
                faint: true,
            },
            Series {
                name: "Pareto front".into(),
                points: f.front.iter().map(|(p, x, y)| Pt { x: *x, y: *y, label: p.clone() }).collect(),
                line: Line::Step,
                faint: false,
            },
        ];
        let title = format!("Pareto front, scene {} — {}", short_scene(&f.scene), f.metric.name());
        let (svg, _) = svg_chart(&title, "frame time, median (ms)", f.metric.name(), &series);
        let name = format!("pareto_{}_{}.svg", super::file_safe(short_scene(&f.scene)), f.metric.name());
        match std::fs::write(sub.join(&name), svg) {
            Ok(()) => out.push((i, format!("report/{name}"))),
            Err(e) => warnings.push(format!("cannot write {}: {e}", sub.join(&name).display())),
        }
    }
    out
}

pub(crate) fn to_markdown(fronts: &[Front], svgs: &[(usize, String)]) -> String {
    let mut md = String::from("# Pareto fronts\n\nFor each scene and error metric: for each frame-time budget, the least-error method among the ok rows.\n\n");
    if fronts.is_empty() {
        md.push_str("No ok rows.\n");
    }
    for (i, f) in fronts.iter().enumerate() {
        md.push_str(&table(f).to_markdown(2));
        if let Some((_, file)) = svgs.iter().find(|(j, _)| *j == i) {
            let _ = writeln!(md, "![{}]({file})\n", table(f).title);
        }
    }
    md
}
