//! The conclusions written out: the table of checked conclusions, the per-adapter timing
//! table, the short lists, the `lod` and view tables, the conclusions section of
//! `tables.md`. Checking them is `super`'s; nothing here reads rows.

use std::fmt::Write as _;

use super::{Conclusion, Verdict, ViewChecks};
use crate::report::data::short_scene;
use crate::report::text::{TextTable, DASH};

/// The conclusions as a table.
pub(crate) fn table(cs: &[Conclusion]) -> TextTable {
    let scene = cs.first().map(|c| short_scene(&c.scene).to_string()).unwrap_or_default();
    let cell =
        |v: Verdict, e: &str| if e.is_empty() { v.as_str().to_string() } else { format!("{} ({e})", v.as_str()) };
    TextTable {
        title: "Conclusions".into(),
        notes: vec![format!(
            "Each of the dissertation's conclusions with the criterion used to check it, on our rows (scene {scene}) by \
             `mse_dissertation_mean` and by `ref_err_t_rms`, and on the dissertation's own printed numbers (a check of the \
             criterion). Ratio thresholds are stated for a squared error: `ref_err_t_rms` is squared before they apply. \
             A NaN error counts as the worst error, never as an unmeasured cell. Frame times are means, as the \
             dissertation's. A criterion reads rows of one image size only and refuses otherwise. Unless its criterion \
             says why, a criterion over several cells holds when at least 75% of the measured cells agree (one odd cell \
             in four does not decide it); the same thresholds apply to our rows and the dissertation's numbers. A criterion \
             that reads a cone method is checked twice: on the `form=textbook` rows (the papers' algorithm on texel \
             maps, with the sampling the criterion names) and on the `form=safe` rows (cones of bilinear cells, read \
             unfiltered by every safe method, so a criterion's `sample=nearest` reads the safe default, and a sampling \
             with no safe counterpart, `sample=linear|min4` or `start=hk`, is not measured). Criteria \
             about frame time only have no separate `ref_err_t_rms` verdict. Frame times are read as each row's \
             `frame_ratio_to_baseline` (the row's mean frame time over the baseline pipeline's, timed in alternating \
             blocks in the same run, with its 95 % interval) when every row has one: two cells compare by the quotient \
             of their ratios, and a criterion whose answer the intervals leave open is `not decided`. The `model` \
             column judges every criterion that reads frame time on the SIMD cost model instead (`simd32_fetches`, the \
             largest fetch count of a group of 32 rays, averaged over groups: a GPU whose time goes into fetches); the \
             probe traces only, so criteria about shadows or ambient occlusion are not measured by it. Frame times \
             from a software rasterizer are one adapter's: read timing verdicts with the adapter in mind."
        )],
        header: ["table", "conclusion", "criterion", "ours (mse_dissertation_mean)", "ours (ref_err_t_rms)", "model (simd32_fetches)", "dissertation's numbers"]
            .iter()
            .map(|s| s.to_string())
            .collect(),
        rows: cs
            .iter()
            .map(|c| {
                vec![
                    c.table.clone(),
                    if c.form.is_empty() { c.claim.clone() } else { format!("{} (cone methods in `form={}`)", c.claim, c.form) },
                    if c.why.is_empty() { c.criterion.clone() } else { format!("{} Thresholds: {}", c.criterion, c.why) },
                    cell(c.ours_mse, &c.evidence_mse),
                    match c.ours_ref {
                        Some(v) => cell(v, &c.evidence_ref),
                        None => "(frame time only)".into(),
                    },
                    match c.model {
                        Some(v) => cell(v, &c.evidence_model),
                        None => "(no frame time)".into(),
                    },
                    cell(c.diss, &c.evidence_diss),
                ]
            })
            .collect(),
    }
}

/// The criteria that read frame time, checked on each adapter's rows (`adapters`: the
/// adapter's name and its conclusions, from [`check`]), side by side: one column per
/// adapter, and the model's verdict (the SIMD cost model reads the probe's counters, the
/// same on every adapter: the first adapter's rows). None with fewer than two adapters.
pub(crate) fn by_adapter(adapters: &[(String, Vec<Conclusion>)]) -> Option<TextTable> {
    if adapters.len() < 2 {
        return None;
    }
    let cell =
        |v: Verdict, e: &str| if e.is_empty() { v.as_str().to_string() } else { format!("{} ({e})", v.as_str()) };
    let mut header = vec!["table".to_string(), "conclusion".to_string()];
    header.extend(adapters.iter().map(|(a, _)| a.clone()));
    header.push("model (simd32_fetches)".into());
    let mut rows = Vec::new();
    for (i, c) in adapters[0].1.iter().enumerate() {
        if !c.reads_time {
            continue;
        }
        let claim = if c.form.is_empty() { c.claim.clone() } else { format!("{} (`form={}`)", c.claim, c.form) };
        let mut row = vec![c.table.clone(), claim];
        for (_, cs) in adapters {
            row.push(match cs.get(i).filter(|d| d.claim == c.claim && d.form == c.form) {
                Some(d) => cell(d.ours_mse, &d.evidence_mse),
                None => DASH.into(),
            });
        }
        row.push(c.model.map(|m| cell(m, &c.evidence_model)).unwrap_or_else(|| DASH.into()));
        rows.push(row);
    }
    Some(TextTable {
        title: "Timing conclusions per adapter".into(),
        notes: vec![format!(
            "The criteria that read frame time, on each adapter's rows apart (rows of {} adapters merged from their result folders), \
             errors by `mse_dissertation_mean`; each adapter's frame times as its paired ratios to the baseline where its rows have them. \
             The model column reads the SIMD cost model, which does not depend on the adapter.",
            adapters.len()
        )],
        header,
        rows,
    })
}

/// Short lists: which hold and which do not (by mse_dissertation_mean and by ref_err_t_rms).
pub(crate) fn summary_lines(cs: &[Conclusion]) -> Vec<String> {
    let mut out = Vec::new();
    let by = |v: Verdict, r: bool| -> Vec<String> {
        cs.iter()
            .filter(|c| if r { c.ours_ref.unwrap_or(c.ours_mse) == v } else { c.ours_mse == v })
            .map(|c| {
                let form = if c.form.is_empty() { String::new() } else { format!(" [form={}]", c.form) };
                format!("{} {}{form}", c.table, c.claim.trim_end_matches('.'))
            })
            .collect()
    };
    for (label, r) in [("by mse_dissertation_mean", false), ("by ref_err_t_rms", true)] {
        for v in [Verdict::Holds, Verdict::DoesNotHold, Verdict::NotDecided, Verdict::NotMeasured] {
            let l = by(v, r);
            out.push(format!(
                "**{} {label}** ({}): {}",
                capitalize(v.as_str()),
                l.len(),
                if l.is_empty() { DASH.to_string() } else { l.join("; ") }
            ));
        }
    }
    out
}

fn capitalize(s: &str) -> String {
    let mut c = s.chars();
    match c.next() {
        Some(f) => f.to_uppercase().collect::<String>() + c.as_str(),
        None => String::new(),
    }
}

/// The conclusions section of `tables.md`.
pub(crate) fn to_markdown(cs: &[Conclusion], agreement: &TextTable) -> String {
    let mut md = String::new();
    let t = table(cs);
    md.push_str(&t.to_markdown(2));
    for l in summary_lines(cs) {
        let _ = writeln!(md, "- {l}");
    }
    md.push('\n');
    md.push_str(&agreement.to_markdown(2));
    md
}

/// The conclusions of Tables 4.1, 4.2 and 4.7 (what the `lod` grid repeats) with every
/// sample at level 0 and at the pixel's footprint level, from [`super::lod_checks`]; `None`
/// when no scene has `lod=auto` rows. Verdicts are `mse / ref_err_t_rms` (frame-time
/// criteria have one). Only the criteria of those tables are listed, cone methods in both
/// forms.
pub(crate) fn lod_markdown(checks: &[(String, Vec<Conclusion>, Vec<Conclusion>)]) -> Option<String> {
    if checks.is_empty() {
        return None;
    }
    let mut t = TextTable {
        title: "Conclusions at the footprint level (`lod=auto`)".into(),
        notes: vec!["The criteria of Tables 4.1, 4.2 and 4.7 (grid `lod`) on the same cells sampled at level 0 (`lod=zero`) and at the \
                     pixel's footprint level (`lod=auto`), each scored against the exact hit on the surface it sampled; cone methods \
                     in both forms (the safe form on the cells of the level it samples). Verdicts: `mse_dissertation_mean / ref_err_t_rms`."
            .into()],
        header: vec!["table".into(), "claim".into(), "scene".into(), "lod=zero".into(), "lod=auto".into()],
        ..Default::default()
    };
    let v = |c: &Conclusion| match c.ours_ref {
        Some(r) => format!("{} / {}", c.ours_mse, r),
        None => c.ours_mse.to_string(),
    };
    for (scene, zero, auto) in checks {
        for (z, a) in zero.iter().zip(auto) {
            if !["4.1", "4.2", "4.7"].contains(&z.table.as_str()) {
                continue;
            }
            if z.ours_mse == Verdict::NotMeasured && a.ours_mse == Verdict::NotMeasured {
                continue;
            }
            let claim = if z.form.is_empty() { z.claim.clone() } else { format!("{} (`form={}`)", z.claim, z.form) };
            t.rows.push(vec![z.table.clone(), claim, short_scene(scene).to_string(), v(z), v(a)]);
        }
    }
    Some(t.to_markdown(2))
}

/// The conclusions of the tables grid `dissertation-view` repeats, on each scene at its own
/// view and at the dissertation's, from [`super::view_checks`], side by side, with the
/// verdicts that change marked; `None` when no scene has rows at the dissertation's view.
/// Verdicts are `mse / ref_err_t_rms` (frame-time criteria have one).
pub(crate) fn view_markdown(checks: &[ViewChecks]) -> Option<String> {
    use crate::scene::View;
    let view = View::Dissertation;
    if checks.is_empty() {
        return None;
    }
    let tables: Vec<String> =
        crate::sweep::grids::DISSERTATION_VIEW_TABLES.iter().map(|t| t.trim_start_matches('t').to_string()).collect();
    let mut t = TextTable {
        title: "Conclusions at the dissertation's view".into(),
        notes: vec![format!(
            "The criteria of Tables {} (grid `dissertation-view`) on each scene at its own view and at the dissertation's \
             (depth scale {}, {}° from the normal, {}° field of view, `lod={}`), each scored against the exact hit on the surface \
             it sampled. Verdicts: `mse_dissertation_mean / ref_err_t_rms`; `changes` marks a verdict that differs between the views, \
             `one view only` one measured at a single view. Where linear search's K = 3N²·MSE still rises at a view, a note says so.",
            tables.join(", "),
            view.depth_scale(),
            view.angle_deg(),
            view.fov_deg(),
            view.lod()
        )],
        header: ["table", "claim", "scene", "own view", "dissertation's view", "changes"].iter().map(|s| s.to_string()).collect(),
        ..Default::default()
    };
    let v = |c: &Conclusion| match c.ours_ref {
        Some(r) => format!("{} / {}", c.ours_mse, r),
        None => c.ours_mse.to_string(),
    };
    for c in checks {
        let base = &c.base;
        for (o, d) in c.own.iter().zip(&c.theirs) {
            if !tables.contains(&o.table) || (o.ours_mse == Verdict::NotMeasured && d.ours_mse == Verdict::NotMeasured)
            {
                continue;
            }
            let claim = if o.form.is_empty() { o.claim.clone() } else { format!("{} (`form={}`)", o.claim, o.form) };
            // A verdict measured at one view only has nothing to change from.
            let one_view = o.ours_mse == Verdict::NotMeasured || d.ours_mse == Verdict::NotMeasured;
            let changes = match (one_view, v(o) != v(d)) {
                (true, _) => "one view only",
                (false, true) => "changes",
                (false, false) => "",
            };
            t.rows.push(vec![o.table.clone(), claim, short_scene(base).to_string(), v(o), v(d), changes.into()]);
        }
        for (label, note) in ["its own view", "the dissertation's view"].into_iter().zip(&c.regime) {
            if let Some(note) = note {
                t.notes.push(format!("{} at {label}: {note}", short_scene(base)));
            }
        }
    }
    Some(t.to_markdown(2))
}
