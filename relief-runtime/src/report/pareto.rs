//! The Pareto front per scene: for each frame-time budget, the least-error method among the
//! ok rows (search pipelines only: rows with a shadow or AO stage add shading cost, not
//! search accuracy, and are left out).

use std::fmt::Write as _;
use std::path::Path;

use super::charts::{svg_chart, Line, Pt, Series};
use super::{data::short_scene, data::Data, data::Metric, text::fmt_ms, text::fmt_sci, text::TextTable};

pub(crate) struct Front {
    pub scene: String,
    pub size: u32,
    /// Whether the sweep has several sizes (then titles and file names name the size).
    pub multi_size: bool,
    /// Rows left out because their error or frame time is not a finite number.
    pub not_finite: Vec<String>,
    pub metric: Metric,
    /// (pipeline, frame ms, error) on the front, fastest first.
    pub front: Vec<(String, f64, f64)>,
    /// Every candidate row.
    pub all: Vec<(String, f64, f64)>,
}

/// The one Pareto front of the report (this section's, the answer's charts and the
/// conclusions' checks): the indices of the `(time, error)` points no other point beats in
/// both (strictly faster and strictly more accurate), fastest first; of points at equal time,
/// the more accurate one. Ties in both keep their order in `points`.
pub(crate) fn front(points: &[(f64, f64)]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&a, &b| points[a].0.total_cmp(&points[b].0).then(points[a].1.total_cmp(&points[b].1)));
    let mut out: Vec<usize> = Vec::new();
    for i in order {
        if out.last().is_none_or(|&j| points[i].1 < points[j].1) {
            out.push(i);
        }
    }
    out
}

pub(crate) fn build(data: &Data) -> Vec<Front> {
    let mut out = Vec::new();
    let multi_size = data.sizes().len() > 1;
    for scene in data.scenes() {
        for size in data.sizes_of(&scene) {
            for metric in [Metric::RefT, Metric::Mse] {
                let mut all: Vec<(String, f64, f64)> = Vec::new();
                let mut not_finite = Vec::new();
                for r in &data.rows {
                    if !r.status.is_ok() || r.metrics.scene != scene || r.metrics.size != size {
                        continue;
                    }
                    // Only the row the index picked for this pipeline.
                    if !data.is_indexed(r) {
                        continue;
                    }
                    let p = &r.metrics.pipeline;
                    if !p.shadow.is_none() || !p.ao.is_none() {
                        continue;
                    }
                    let (ms, e) = (r.metrics.frame_ms_mean, metric.of(r));
                    if ms.is_finite() && e.is_finite() {
                        all.push((r.metrics.pipeline.to_string(), ms, e));
                    } else {
                        not_finite.push(r.metrics.pipeline.to_string());
                    }
                }
                all.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.2.total_cmp(&b.2)));
                let points: Vec<(f64, f64)> = all.iter().map(|c| (c.1, c.2)).collect();
                let front = self::front(&points).into_iter().map(|i| all[i].clone()).collect();
                if !all.is_empty() || !not_finite.is_empty() {
                    out.push(Front { scene: scene.clone(), size, multi_size, not_finite, metric, front, all });
                }
            }
        }
    }
    out
}

/// `lion`, or `lion, 64²` when the sweep has several sizes.
fn front_place(f: &Front) -> String {
    if f.multi_size {
        super::data::group_label(&f.scene, f.size)
    } else {
        short_scene(&f.scene).to_string()
    }
}

/// The front as a budget table.
pub(crate) fn table(f: &Front) -> TextTable {
    let mut rows = Vec::new();
    for (i, (p, ms, e)) in f.front.iter().enumerate() {
        let until = f.front.get(i + 1).map(|n| format!("< {}", fmt_ms(n.1))).unwrap_or_else(|| "and more".into());
        rows.push(vec![format!("≥ {} {until}", fmt_ms(*ms)), format!("`{p}`"), fmt_sci(*e), fmt_ms(*ms)]);
    }
    let mut notes = vec![format!(
        "{} candidate rows (no shadow / AO stages), {} on the front. Frame time is the mean over the timed frames \
         (the dissertation's measure). For a frame-time budget in the first column, the second column is the least-error method.",
        f.all.len(),
        f.front.len()
    )];
    if !f.not_finite.is_empty() {
        notes.push(format!(
            "Left out, their error or frame time is not a finite number (failures, not skipped rays): {}.",
            f.not_finite.iter().map(|p| format!("`{p}`")).collect::<Vec<_>>().join(", ")
        ));
    }
    TextTable {
        title: format!("Pareto front, scene {}, by {}", front_place(f), f.metric.name()),
        notes,
        header: ["budget, mean frame ms", "least-error method", f.metric.name(), "its mean frame ms"]
            .iter()
            .map(|s| s.to_string())
            .collect(),
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
        let title = format!("Pareto front, scene {} — {}", front_place(f), f.metric.name());
        let svg = svg_chart(&title, "frame time, mean (ms)", f.metric.name(), &series).svg;
        let place = if f.multi_size {
            format!("{}_s{}", short_scene(&f.scene), f.size)
        } else {
            short_scene(&f.scene).to_string()
        };
        let name = format!("pareto_{}_{}.svg", super::text::file_safe(&place), f.metric.name());
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

#[cfg(test)]
mod tests {
    use super::front;

    /// Fastest first; a slower point joins only when strictly more accurate; of two at equal
    /// time the more accurate; ties in both keep their order.
    #[test]
    fn the_front_keeps_what_no_faster_point_beats_in_error() {
        let pts = [(3.0, 0.5), (1.0, 0.9), (2.0, 0.9), (2.0, 0.4), (4.0, 0.4), (5.0, 0.1), (5.0, 0.1)];
        assert_eq!(front(&pts), vec![1, 3, 5]);
        assert!(front(&[]).is_empty());
    }
}
