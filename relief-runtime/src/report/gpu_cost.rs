//! The GPU compiler's model beside the clock: for each answer (scene, view, size), the
//! fastest pipeline at each accuracy level and the engine family's fastest, ranked once by
//! lavapipe's frame time and once by the modeled instructions per pixel on RDNA2 and RDNA3
//! (`gpu_navi21_instr_px`, `gpu_gfx1100_instr_px`: [`crate::cost`]), with a chart of error
//! against modeled instructions per scene and view. Where the model and the clock pick
//! differently, or disagree on whether relief beats the engine family by 2×, the section
//! says so. The model is a model: AMD's compiler's static counts times the probe's passes,
//! not a measured time.

use std::fmt::Write as _;
use std::path::Path;

use super::answer::{levels, Answer};
use super::charts::{svg_chart_axes, Line, Pt, Series};
use super::conclusions::{Conclusion, Verdict};
use super::{data::short_scene, data::Data, text::fmt_num, text::TextTable, text::DASH};

/// A ratio as the table prints it, `—` where a side is missing.
fn ratio(x: f64) -> String {
    if x.is_finite() {
        fmt_num(x, 2)
    } else {
        DASH.into()
    }
}
use crate::results::{Metrics, Row};

/// The families with columns, with their generation's name.
pub(crate) const FAMILIES: [(&str, &str); 2] = [("navi21", "RDNA2"), ("gfx1100", "RDNA3")];

/// A row's modeled instructions per pixel on `family`, NaN when it has none.
pub(crate) fn instr_px(m: &Metrics, family: &str) -> f64 {
    match family {
        "navi21" => m.gpu_navi21_instr_px,
        "gfx1100" => m.gpu_gfx1100_instr_px,
        _ => None,
    }
    .unwrap_or(f64::NAN)
}

/// What the rows' clock is called in this section: `lavapipe` for Mesa's CPU rasterizer
/// (its adapter reports itself as llvmpipe), else the adapter's name before its driver.
pub(crate) fn clock_label(adapters: &[String]) -> String {
    let names: Vec<String> = adapters
        .iter()
        .map(|a| {
            if a.contains("llvmpipe") {
                "lavapipe".to_string()
            } else {
                a.split(" (").next().unwrap_or(a).trim().to_string()
            }
        })
        .collect::<std::collections::BTreeSet<_>>()
        .into_iter()
        .collect();
    if names.is_empty() {
        "the clock".into()
    } else {
        names.join(" + ")
    }
}

/// How well the model orders one answer's pipelines against its clock: Spearman's ρ
/// between each family's modeled instructions per pixel and the rows' frame time (their
/// paired ratio to the baseline where they have one), over the rows with both, and how many.
fn model_order(a: &Answer, data: &Data) -> Vec<(Option<f64>, usize)> {
    FAMILIES
        .iter()
        .map(|(f, _)| {
            let (xs, ys): (Vec<f64>, Vec<f64>) = a
                .cands
                .iter()
                .filter_map(|c| {
                    let r = data.ok(&c.pipeline, &a.scene, a.size)?;
                    let x = instr_px(&r.metrics, f);
                    let y = c.speed.rank();
                    (x.is_finite() && y.is_finite()).then_some((x, y))
                })
                .unzip();
            (super::stats::spearman(&xs, &ys), xs.len())
        })
        .collect()
}

/// Whether the model's fastest `model` is the clock's pick: its fastest, or one of the rows
/// the clock cannot tell apart from it (`Pick::ties`: their intervals reach 1).
fn same_as_clock(model: Option<usize>, clock: &super::answer::Pick) -> bool {
    model == clock.best || model.is_some_and(|m| clock.ties.contains(&m))
}

/// The section: markdown, HTML and the charts it wrote (relative to the sweep folder).
pub(crate) struct GpuSection {
    pub markdown: String,
    pub html: String,
    pub files: Vec<String>,
}

/// A pick on the model: the fastest candidate reaching a level by modeled instructions.
fn model_pick(a: &Answer, data: &Data, level: usize, family: &str, engine_only: bool) -> Option<(usize, f64)> {
    let l = &levels()[level];
    a.cands
        .iter()
        .enumerate()
        .filter(|(_, c)| !engine_only || c.engine)
        .filter_map(|(i, c)| {
            let r = data.ok(&c.pipeline, &a.scene, a.size)?;
            let x = instr_px(&r.metrics, family);
            ((l.reached)(r) && x.is_finite()).then_some((i, x))
        })
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

/// Builds the section from the answers; `None` when no row has the GPU columns.
pub(crate) fn build(
    data: &Data,
    answers: &[Answer],
    conclusions: &[Conclusion],
    sub: &Path,
    warnings: &mut Vec<String>,
) -> Option<GpuSection> {
    let priced: Vec<&Row> = data.rows.iter().filter(|r| r.metrics.gpu_driver.is_some()).collect();
    if priced.is_empty() {
        return None;
    }
    let drivers = data.distinct(|r| r.metrics.gpu_driver.clone().unwrap_or_default());
    let clock = clock_label(&data.distinct(|r| r.metrics.adapter.clone()));
    let mut md = String::from("## The GPU compiler's model beside the clock\n\n");
    let _ = writeln!(
        md,
        "A **model**, not a clock: AMD's shader compiler ({}, on RADV's null device, no GPU) counts each pipeline's \
         fragment shader; a SIMD group issues the instructions outside its loops plus each coarse and refine loop's body \
         times its slowest lane's passes (the probe's counters), averaged over groups (`gpu_FAMILY_instr_px`, at the \
         compiler's wave size). Latency, caches and occupancy are not in it. Rows priced: {} of {}.\n",
        drivers.join(", "),
        priced.len(),
        data.rows.len()
    );
    let mut html = String::new();
    let mut files = vec![];
    let mut disagreements = vec![];
    let mut order = TextTable {
        title: "How the model orders the pipelines".into(),
        notes: vec![format!(
            "Spearman's ρ between the modeled instructions per pixel and {clock}'s frame time (paired ratio to the \
             baseline), over an answer's competing rows: 1 = the model ranks them as the clock does."
        )],
        header: vec!["scene, view, size".into(), "clock".into(), "rows".into()],
        rows: vec![],
    };
    for (f, gen) in FAMILIES {
        order.header.push(format!("ρ, {gen} model ({f})"));
    }
    for a in answers {
        if a.cands.iter().all(|c| data.ok(&c.pipeline, &a.scene, a.size).is_none_or(|r| r.metrics.gpu_driver.is_none()))
        {
            continue;
        }
        let here = clock_label(&a.adapters);
        let each = model_order(a, data);
        let mut orow = vec![a.title.clone(), here.clone(), each.iter().map(|e| e.1).max().unwrap_or(0).to_string()];
        orow.extend(each.iter().map(|(r, _)| r.map_or_else(|| DASH.to_string(), |r| fmt_num(r, 2))));
        order.rows.push(orow);
        let mut t = TextTable {
            title: format!("Model against clock: {}", a.title),
            notes: vec![format!(
                "Per level: the fastest pipeline and the engine family's fastest ÷ it, by {here} ({}) and by the \
                 modeled instructions per pixel on each family. The model's fastest agrees with the clock when it is \
                 the clock's fastest or one the clock cannot tell apart from it (their paired interval reaches 1).",
                a.clock.name()
            )],
            header: vec!["level".into(), format!("{here}: fastest"), format!("{here}: family ÷ fastest")],
            rows: vec![],
        };
        for (f, gen) in FAMILIES {
            t.header.push(format!("{gen} model ({f}): fastest"));
            t.header.push(format!("{gen}: family ÷ fastest"));
        }
        t.header.push("model and clock".into());
        for (k, (l, pick)) in levels().iter().zip(&a.picks).enumerate() {
            let name = |i: Option<usize>| i.map(|i| format!("`{}`", a.cands[i].pipeline)).unwrap_or_else(|| "—".into());
            let clock_ratio = match (pick.best, pick.engine) {
                (Some(b), Some(e)) => a.cands[e].speed.over(&a.cands[b].speed).ratio,
                _ => f64::NAN,
            };
            let mut row = vec![l.name.to_string(), name(pick.best), ratio(clock_ratio)];
            let mut verdicts = vec![];
            let mut same_pick = true;
            for (f, gen) in FAMILIES {
                let best = model_pick(a, data, k, f, false);
                let engine = model_pick(a, data, k, f, true);
                let ratio = match (best, engine) {
                    (Some((_, b)), Some((_, e))) => e / b,
                    _ => f64::NAN,
                };
                row.push(name(best.map(|b| b.0)));
                row.push(self::ratio(ratio));
                if !same_as_clock(best.map(|b| b.0), pick) {
                    same_pick = false;
                }
                if clock_ratio.is_finite() && ratio.is_finite() && (clock_ratio >= 2.0) != (ratio >= 2.0) {
                    verdicts.push(format!("{gen}: ≥ 2× {}", if ratio >= 2.0 { "holds" } else { "does not hold" }));
                }
            }
            let agree = if verdicts.is_empty() && same_pick {
                "agree".to_string()
            } else {
                let mut v = verdicts.clone();
                if !same_pick {
                    v.insert(0, "different fastest".into());
                }
                v.join("; ")
            };
            if agree != "agree" {
                disagreements.push(format!("{}, {}: {agree}", a.title, l.name));
            }
            row.push(agree);
            t.rows.push(row);
        }
        md.push_str(&t.to_markdown(3));
        html.push_str(&t.to_html(3));
        if let Some(file) = chart(a, data, sub, warnings) {
            let _ = writeln!(md, "![error against modeled instructions: {}]({file})\n", a.title);
            let _ = writeln!(html, "<p><img src=\"{file}\" alt=\"error against modeled instructions\"></p>");
            files.push(file);
        }
    }
    let summary = if disagreements.is_empty() {
        format!("The model and {clock} agree on every level's fastest pipeline and on every ≥ 2× verdict.\n\n")
    } else {
        format!(
            "**Where the model and {clock} disagree** ({}):\n\n{}\n\n",
            disagreements.len(),
            disagreements.iter().map(|d| format!("- {d}")).collect::<Vec<_>>().join("\n")
        )
    };
    md.push_str(&summary);
    let order = (!order.rows.is_empty()).then_some(order);
    if let Some(t) = &order {
        md.push_str(&t.to_markdown(3));
    }
    let verdicts = conclusions_table(conclusions, &clock);
    if let Some(t) = &verdicts {
        md.push_str(&t.to_markdown(3));
    }
    let head = super::html::md_block(&md[..md.find("###").unwrap_or(md.len())], "gpu-model");
    let html = format!(
        "{head}{html}{}{}{}",
        super::html::md_block(&summary, "gpu-model-summary"),
        order.map(|t| t.to_html(3)).unwrap_or_default(),
        verdicts.map(|t| t.to_html(3)).unwrap_or_default()
    );
    Some(GpuSection { markdown: md, html, files })
}

/// The chart of one answer: RMS t error against modeled instructions per pixel, one series
/// per family, the engine family apart.
fn chart(a: &Answer, data: &Data, sub: &Path, warnings: &mut Vec<String>) -> Option<String> {
    let mut series = vec![];
    for (f, gen) in FAMILIES {
        for engine in [false, true] {
            let points: Vec<Pt> = a
                .cands
                .iter()
                .filter(|c| c.engine == engine)
                .filter_map(|c| {
                    let r = data.ok(&c.pipeline, &a.scene, a.size)?;
                    Some(Pt { x: instr_px(&r.metrics, f), y: c.err, label: String::new() })
                })
                .filter(|p| p.x.is_finite())
                .collect();
            if !points.is_empty() {
                let who = if engine { "engine family" } else { "others" };
                series.push(Series { name: format!("{gen} ({f}), {who}"), points, line: Line::None, faint: false });
            }
        }
    }
    if series.is_empty() {
        return None;
    }
    let svg = svg_chart_axes(
        &format!("Modeled instructions per pixel against t error: {}", a.title),
        "modeled instructions per pixel (model)",
        "ref_err_t_rms",
        &series,
        true,
    );
    let name = format!("gpu_{}.svg", super::text::file_safe(&format!("{}_s{}", short_scene(&a.scene), a.size)));
    match std::fs::write(sub.join(&name), &svg.svg) {
        Ok(()) => Some(format!("report/{name}")),
        Err(e) => {
            warnings.push(format!("cannot write {}: {e}", sub.join(&name).display()));
            None
        }
    }
}

/// The dissertation's conclusions that read frame time, judged on the rows' clock (`clock`
/// names it) and on the GPU compiler's model per family; `None` when none was judged on the
/// model.
fn conclusions_table(conclusions: &[Conclusion], clock: &str) -> Option<TextTable> {
    let judged: Vec<&Conclusion> = conclusions.iter().filter(|c| !c.gpu_model.is_empty()).collect();
    if judged.is_empty() {
        return None;
    }
    let mut t = TextTable {
        title: "The timing conclusions on the model".into(),
        notes: vec![format!(
            "Each conclusion of Burger 2018 that reads frame time, checked on this run's rows with {clock}'s frame \
             time and again with the GPU compiler's modeled instructions per pixel in its place (a model, not a clock); \
             errors by `mse_dissertation_mean`. \"differs\" marks a conclusion where a decided model verdict is not \
             {clock}'s."
        )],
        header: vec!["table".into(), "conclusion".into(), "form".into(), clock.to_string()],
        rows: vec![],
    };
    for (f, gen) in FAMILIES {
        t.header.push(format!("{gen} model ({f})"));
    }
    t.header.push("model and clock".into());
    for c in judged {
        let mut row = vec![c.table.clone(), c.claim.clone(), c.form.clone(), c.ours_mse.as_str().to_string()];
        let mut differs = false;
        for (f, _) in FAMILIES {
            match c.gpu_model.iter().find(|(g, _, _)| g == f) {
                Some((_, v, e)) => {
                    let decided = matches!(v, Verdict::Holds | Verdict::DoesNotHold);
                    differs |= decided && *v != c.ours_mse;
                    row.push(format!("{} ({})", v.as_str(), e));
                }
                None => row.push(DASH.into()),
            }
        }
        row.push(if differs { "differs".into() } else { "same".into() });
        t.rows.push(row);
    }
    Some(t)
}

#[cfg(test)]
mod tests {
    use super::{clock_label, same_as_clock};
    use crate::report::answer::Pick;

    #[test]
    fn the_models_pick_agrees_when_the_clock_cannot_tell_it_from_its_own() {
        let pick = Pick { best: Some(0), engine: Some(3), ties: vec![2] };
        assert!(same_as_clock(Some(0), &pick));
        assert!(same_as_clock(Some(2), &pick));
        assert!(!same_as_clock(Some(1), &pick));
        assert!(!same_as_clock(Some(3), &pick));
        assert!(!same_as_clock(None, &pick));
        assert!(same_as_clock(None, &Pick { best: None, engine: None, ties: vec![] }));
    }

    #[test]
    fn the_clock_is_named_by_its_adapter() {
        let lp = "llvmpipe (LLVM 15.0.6, 256 bits) (llvmpipe Mesa 22.3.6 (LLVM 15.0.6))".to_string();
        assert_eq!(clock_label(std::slice::from_ref(&lp)), "lavapipe");
        let nv = "NVIDIA H100 80GB HBM3 (NVIDIA 550.54.15)".to_string();
        assert_eq!(clock_label(std::slice::from_ref(&nv)), "NVIDIA H100 80GB HBM3");
        assert_eq!(clock_label(&[nv, lp]), "NVIDIA H100 80GB HBM3 + lavapipe");
        assert_eq!(clock_label(&[]), "the clock");
    }
}
