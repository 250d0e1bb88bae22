//! How differently the error metrics rank the methods (Kendall's τ per table).

use super::data::{group_label, short_scene, Data, Metric};
use super::stats::kendall;
use super::tables::ReportTable;
use super::text::{fmt_num, TextTable, DASH};

/// How differently the metrics rank the rows of each table: Kendall's τ between
/// `mse_dissertation_mean` and `ref_err_t_rms` / `skipped_rate`, and the pairs the first two
/// order most differently.
pub(crate) fn metric_agreement(data: &Data, tables: &[ReportTable]) -> TextTable {
    let mut rows = Vec::new();
    let mut groups: Vec<(String, Vec<&crate::results::Row>)> = Vec::new();
    for t in tables {
        let mut v = Vec::new();
        for i in 0..t.entries.len() {
            if let Some(r) = t.row(data, i).filter(|r| r.status.is_ok()) {
                if !v.iter().any(|x: &&crate::results::Row| std::ptr::eq(*x, r)) {
                    v.push(r);
                }
            }
        }
        let name = if t.scene == "scene:lion" {
            format!("Table {}", t.id)
        } else {
            format!("Table {} ({})", t.id, short_scene(&t.scene))
        };
        groups.push((name, v));
    }
    let multi_size = data.sizes().len() > 1;
    for scene in data.scenes() {
        for size in data.sizes_of(&scene) {
            // One row per pipeline: the one the index picked.
            let v: Vec<_> = data
                .rows
                .iter()
                .filter(|r| {
                    r.status.is_ok() && r.metrics.scene == scene && r.metrics.size == size && data.is_indexed(r)
                })
                .collect();
            let place = if multi_size { group_label(&scene, size) } else { short_scene(&scene).to_string() };
            groups.push((format!("all rows, {place}"), v));
        }
    }
    for (name, v) in groups {
        let finite: Vec<_> = v.into_iter().filter(|r| Metric::ALL.iter().all(|m| m.of(r).is_finite())).collect();
        if finite.len() < 2 {
            continue;
        }
        let col = |m: Metric| finite.iter().map(|r| m.of(r)).collect::<Vec<f64>>();
        let (mse, rft, skip) = (col(Metric::Mse), col(Metric::RefT), col(Metric::Skipped));
        let k1 = kendall(&mse, &rft);
        let k2 = kendall(&mse, &skip);
        // The pair the two metrics disagree on most (product of the log ratios).
        let mut worst: Option<(f64, usize, usize)> = None;
        for i in 0..finite.len() {
            for j in i + 1..finite.len() {
                if mse[i] > 0.0 && mse[j] > 0.0 && rft[i] > 0.0 && rft[j] > 0.0 {
                    let a = (mse[i] / mse[j]).ln();
                    let b = (rft[i] / rft[j]).ln();
                    if a * b < 0.0 {
                        let score = -(a * b);
                        if worst.is_none_or(|w| score > w.0) {
                            worst = Some((score, i, j));
                        }
                    }
                }
            }
        }
        let example = match worst {
            None => DASH.to_string(),
            Some((_, i, j)) => {
                let (lo, hi) = if mse[i] < mse[j] { (i, j) } else { (j, i) };
                format!(
                    "`{}` has {}× lower mse_dissertation_mean than `{}` but {}× higher ref_err_t_rms",
                    finite[lo].metrics.pipeline,
                    fmt_num(mse[hi] / mse[lo], 2),
                    finite[hi].metrics.pipeline,
                    fmt_num(rft[lo] / rft[hi], 2)
                )
            }
        };
        let tau = |k: Option<(f64, usize)>| k.map(|(t, _)| format!("{t:.2}")).unwrap_or_else(|| DASH.into());
        rows.push(vec![
            name,
            finite.len().to_string(),
            tau(k1),
            k1.map(|(_, d)| d.to_string()).unwrap_or_else(|| DASH.into()),
            tau(k2),
            example,
        ]);
    }
    TextTable {
        title: "How the metrics rank the methods".into(),
        notes: vec!["Kendall's τ between `mse_dissertation_mean` and the other metrics over each table's ok rows (1 = same order, \
            −1 = reversed, — = no spread), the number of pairs `mse_dissertation_mean` and `ref_err_t_rms` order oppositely, \
            and the most striking such pair. `mse_dissertation_mean` does not penalise rays that skip a feature and land on \
            a wrong but consistent surface point; `ref_err_t_rms` and `skipped_rate` do."
            .into()],
        header: ["rows of", "n", "τ(mse, ref_err_t_rms)", "opposite pairs", "τ(mse, skipped_rate)", "largest disagreement"]
            .iter()
            .map(|s| s.to_string())
            .collect(),
        rows,
    }
}
