//! One table per dissertation table: the dissertation's rows in its order, our measurements
//! and its numbers side by side, and trend columns relative to each row's base row.

use relief_dsl::spec::StageSpec;
use relief_dsl::Pipeline;

use super::diss::{Diss, DissRow};
use super::{
    data::short_scene, data::Data, text::fmt_ms, text::fmt_num, text::fmt_pct, text::fmt_sci, text::ours,
    text::TextTable, text::DASH,
};
use crate::results::Row;
use crate::sweep::grids;
use crate::sweep::scene_label;

/// One table of the report: a dissertation table on one scene.
pub(crate) struct ReportTable {
    /// `t4.1`, or `t4.1-rock_bump` when not on Lion.
    pub key: String,
    /// `4.1`.
    pub id: String,
    /// The scene label (`scene:lion`).
    pub scene: String,
    /// The image size our rows were measured at (None: no row of this table anywhere).
    pub size: Option<u32>,
    pub entries: Vec<Entry>,
    pub table: TextTable,
}

/// One row of a table.
pub(crate) struct Entry {
    /// Our pipeline (None for a printed row no cell of the grid matches).
    pub pipeline: Option<Pipeline>,
    /// The pipeline's canonical text, or a description of the printed row.
    pub label: String,
    pub diss: Option<DissRow>,
    /// The entry the trend columns are relative to.
    pub base: usize,
}

impl ReportTable {
    /// Our row of entry `i` (any status).
    pub(crate) fn row<'a>(&self, data: &'a Data, i: usize) -> Option<&'a Row> {
        let e = self.entries.get(i)?;
        data.get(&e.pipeline.as_ref()?.to_string(), &self.scene, self.size?)
    }
}

/// The table ids `4.1` … `4.15`, in order.
pub(crate) fn table_ids() -> Vec<String> {
    (1..=15).map(|i| format!("4.{i}")).collect()
}

/// Every table, for every scene that has rows of it (Lion when none has).
pub(crate) fn build(data: &Data, diss: &Diss) -> Vec<ReportTable> {
    let all = grids::builtin(None);
    let mut out = Vec::new();
    for id in table_ids() {
        let name = format!("t{id}");
        let Some(grid) = all.iter().find(|g| g.name == name) else { continue };
        let mut pipelines: Vec<Pipeline> = Vec::new();
        for (p, _) in &grid.cells {
            if !pipelines.contains(p) {
                pipelines.push(p.clone());
            }
        }
        let entries_template = entries(&id, &pipelines, diss);
        // (scene, size) groups: those with at least one row of this table, else the grid's
        // own scenes, unmeasured. A table never mixes sizes.
        let multi_size = data.sizes().len() > 1;
        let mut groups: Vec<(String, Option<u32>)> = Vec::new();
        for s in data.scenes() {
            for size in data.sizes_of(&s) {
                let have = pipelines.iter().filter(|p| data.get(&p.to_string(), &s, size).is_some()).count();
                // The grid's own scenes with any row; other scenes only when they cover at
                // least half the table (not just cells another grid shares with it).
                let own = grid.cells.iter().any(|(_, g)| scene_label(g) == s);
                if have > 0 && (own || 2 * have >= pipelines.len()) {
                    groups.push((s.clone(), Some(size)));
                }
            }
        }
        if groups.is_empty() {
            for (_, s) in &grid.cells {
                let l = scene_label(s);
                if !groups.iter().any(|(g, _)| *g == l) {
                    groups.push((l, None));
                }
            }
        }
        for (scene, size) in groups {
            let mut key = if scene == "scene:lion" {
                name.clone()
            } else {
                format!("{name}-{}", super::text::file_safe(short_scene(&scene)))
            };
            if let (true, Some(z)) = (multi_size, size) {
                key.push_str(&format!("-s{z}"));
            }
            let mut t = ReportTable {
                key,
                id: id.clone(),
                scene: scene.clone(),
                size,
                entries: entries_template
                    .iter()
                    .map(|e| Entry {
                        pipeline: e.pipeline.clone(),
                        label: e.label.clone(),
                        diss: e.diss.clone(),
                        base: e.base,
                    })
                    .collect(),
                table: TextTable::default(),
            };
            t.table = render(&t, data, &grid.description, multi_size);
            out.push(t);
        }
    }
    out
}

/// The rows of table `id`: the printed rows in the dissertation's order, each with the grid
/// cell that is it, then the grid's cells nothing printed matches.
fn entries(id: &str, pipelines: &[Pipeline], diss: &Diss) -> Vec<Entry> {
    let mut out: Vec<Entry> = Vec::new();
    let mut used = vec![false; pipelines.len()];
    for d in diss.table(id) {
        let found = pipelines.iter().position(|p| d.matches(p));
        match found {
            Some(i) => {
                used[i] = true;
                out.push(Entry {
                    pipeline: Some(pipelines[i].clone()),
                    label: pipelines[i].to_string(),
                    diss: Some(d.clone()),
                    base: 0,
                });
            }
            None => out.push(Entry { pipeline: None, label: describe(d), diss: Some(d.clone()), base: 0 }),
        }
    }
    for (i, p) in pipelines.iter().enumerate() {
        if !used[i] {
            out.push(Entry { pipeline: Some(p.clone()), label: p.to_string(), diss: None, base: 0 });
        }
    }
    for i in 0..out.len() {
        out[i].base = base_of(id, &out, i);
    }
    out
}

fn describe(d: &DissRow) -> String {
    let mut s = String::from("(dissertation) ");
    let part = |name: &str, steps: &str| if steps.is_empty() { name.to_string() } else { format!("{name}({steps})") };
    s.push_str(&part(if d.coarse.is_empty() { "?" } else { &d.coarse }, &d.coarse_steps));
    if !d.refine.is_empty() && d.refine != "none" {
        s.push_str(&format!("+{}", part(&d.refine, &d.refine_steps)));
    }
    if !d.shadow.is_empty() && d.shadow != "none" {
        s.push_str(&format!("+shadow={}", part(&d.shadow, &d.shadow_steps)));
    }
    if !d.ao.is_empty() && d.ao != "none" {
        s.push_str(&format!("+ao={}", d.ao));
    }
    s
}

/// The reference method of a comparison table: (slot, method name). Rows of another method
/// in that slot are compared with the same pipeline using the reference method.
fn reference(id: &str) -> Option<(&'static str, &'static str)> {
    Some(match id {
        "4.5" | "4.10" => ("refine", "binary"),
        "4.7" => ("coarse", "linear"),
        "4.8" | "4.9" | "4.11" => ("coarse", "csm"),
        "4.12" => ("coarse", "rcs"),
        "4.13" => ("coarse", "cns"),
        _ => return None,
    })
}

/// Describes how the base row is chosen (for the table's notes).
fn base_rule(id: &str) -> String {
    match (id, reference(id)) {
        ("4.3", _) => "Base: the paired linear-only row just above (the dissertation's \"% of linear-only frame time\").".into(),
        (_, Some((slot, name))) => format!(
            "Base: the same pipeline with {slot} `{name}` (e.g. relative MSE); rows of `{name}` itself: the same search without refinement if the table has it, else the table's first row."
        ),
        _ => "Base: the same search without AO / shadow / refinement where the table has that row, else the table's first row.".into(),
    }
}

fn base_of(id: &str, entries: &[Entry], i: usize) -> usize {
    let Some(p) = entries[i].pipeline.as_ref() else { return 0 };
    let find = |q: &Pipeline| entries.iter().position(|e| e.pipeline.as_ref() == Some(q));
    if id == "4.3" && !p.refine.is_none() && i > 0 {
        if let Some(prev) = entries[i - 1].pipeline.as_ref() {
            if prev.refine.is_none() {
                return i - 1;
            }
        }
    }
    if let Some((slot, name)) = reference(id) {
        let mut q = p.clone();
        let stage = if slot == "coarse" { &mut q.coarse } else { &mut q.refine };
        if stage.name != name {
            stage.name = name.to_string();
            // Keep only the steps: the reference method's other parameters are its defaults.
            let steps = super::data::stage_steps(stage);
            if let Ok(s) = StageSpec::new(
                if slot == "coarse" { relief_dsl::Slot::Coarse } else { relief_dsl::Slot::Refine },
                name,
                &[relief_dsl::spec::Value::Int(steps)],
            ) {
                *stage = s;
            }
            if let Some(j) = find(&q) {
                return j;
            }
        }
    }
    for which in ["ao", "shadow", "refine"] {
        let mut q = p.clone();
        let stage = match which {
            "ao" => &mut q.ao,
            "shadow" => &mut q.shadow,
            _ => &mut q.refine,
        };
        if !stage.is_none() {
            *stage = StageSpec::none();
            if let Some(j) = find(&q) {
                return j;
            }
            // Only the outermost extra is dropped (AO before shadow before refinement).
            break;
        }
    }
    0
}

fn ratio_pct(v: f64, base: f64) -> Option<f64> {
    (v.is_finite() && base.is_finite() && base != 0.0).then(|| 100.0 * v / base)
}

/// The columns of every table. Each frame-time column says whether it is the median or
/// the mean; the dissertation's frame times are means over 500 frames (Burger 2018 §4.1),
/// so they sit next to our mean and the trend columns use the mean. The dissertation's
/// "avg steps" counts the coarse search only (Table 4.11's csm(5)+binary(5) shows 2.016 as
/// Table 4.8's csm(5) does), so it sits next to our coarse steps.
pub(crate) const HEADER: [&str; 32] = [
    "#",
    "pipeline",
    "base",
    "frame ms (median)",
    "frame ms (mean)",
    "diss ms (mean of 500)",
    "mean ms % base",
    "diss ms (mean) % base",
    "frame ÷ baseline (95 %)",
    "avg coarse steps",
    "diss avg steps (coarse)",
    "avg refine steps",
    "avg iter (total)",
    "avg fetches (total)",
    "simd32 fetches (model)",
    "mse_dissertation (sum)",
    "mse_dissertation_mean",
    "diss MSE",
    "MSE mean % base",
    "diss MSE % base",
    "ref_err_t_rms",
    "ref_t % base",
    "|t err| median",
    "|t err| p90",
    "|t err| p99",
    "MSE share of worst 1 %",
    "K = 3N²·MSE",
    "skipped_rate",
    "past_rate",
    "nan_count",
    "outside_count",
    "nonconverged_rate",
];

/// N of a pipeline that is linear search alone (`linear(N)`, no refinement): the searches
/// whose error K = 3N²·MSE describes.
pub(crate) fn linear_steps(p: &Pipeline) -> Option<u32> {
    (p.coarse.name == "linear" && p.refine.is_none()).then(|| p.coarse.int("steps"))
}

/// K = 3N²·MSE: a linear search of N steps ends within one step (1/N in t) past the first
/// hit, uniformly if the surface is smooth on the step's scale, so its mean squared height
/// error is E[(1 + s)²]/(3N²) with s the surface's slope along the ray per unit of the ray's
/// descent; K is then the constant E[(1 + s)²]. While steps still cross features K rises
/// with N (the pre-asymptotic regime); once they are small against every feature it is flat.
pub(crate) fn k_linear(n: u32, mse_mean: f64) -> f64 {
    3.0 * (n as f64).powi(2) * mse_mean
}

/// K grows by more than this from one N to the next (in the largest two N of a table)
/// before the report calls the table pre-asymptotic: the goal's margin, not a fit.
pub(crate) const K_RISING: f64 = 1.2;

/// The note for Table 4.1 on Lion (any view): the stand-in's avg coarse steps per step
/// count N against the dissertation's Lion's, and why they differ. A linear search stops
/// after about N·(1 − z) steps where it meets the surface at height z, so avg steps / N is
/// one minus the mean height at the hit: the dissertation's Lion's 0.6 means hits near
/// height 0.4, and a stand-in whose visible surface sits higher takes fewer steps.
fn steps_note(t: &ReportTable, data: &Data) -> Option<String> {
    if t.id != "4.1" || !(t.scene == "scene:lion" || t.scene.starts_with("scene:lion@")) {
        return None;
    }
    let (mut ours, mut theirs) = (Vec::new(), Vec::new());
    for (i, e) in t.entries.iter().enumerate() {
        let Some(n) = e.pipeline.as_ref().and_then(linear_steps) else { continue };
        if let Some(r) = t.row(data, i).filter(|r| r.status.is_ok() && r.metrics.avg_coarse_steps.is_finite()) {
            ours.push(r.metrics.avg_coarse_steps / n as f64);
        }
        if let Some(d) = e.diss.as_ref().and_then(|d| d.avg_steps.trim().parse::<f64>().ok()) {
            theirs.push(d / n as f64);
        }
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    if ours.is_empty() || theirs.is_empty() {
        return None;
    }
    Some(format!(
        "Avg coarse steps: the stand-in takes {}·N on average over these rows, the dissertation's Lion {}·N. Linear search stops after \
         about N·(1 − z) steps where it meets the surface at height z, so the dissertation's Lion's hits lie near height {}, the \
         stand-in's near {}: its medallion, rim and mane (heights 0.62–0.96) cover about 60 % of the map, and more of a view as \
         narrow as the dissertation's. The stand-in's heights are kept, since every \
         Lion result rests on them; compare the step counts' trend, not their level.",
        fmt_num(mean(&ours), 2),
        fmt_num(mean(&theirs), 2),
        fmt_num(1.0 - mean(&theirs), 2),
        fmt_num(1.0 - mean(&ours), 2)
    ))
}

/// The note for a table whose linear-search rows' K = 3N²·MSE ([`k_linear`]) is still
/// rising at its largest two N (by more than [`K_RISING`]×): its MSE falls slower than
/// 1/N², and a slope read from it belongs to the view, not the method.
fn regime_note(t: &ReportTable, data: &Data) -> Option<String> {
    let ks = (0..t.entries.len()).filter_map(|i| {
        let n = linear_steps(t.entries[i].pipeline.as_ref()?)?;
        let r = t.row(data, i).filter(|r| r.status.is_ok())?;
        Some((n, r.metrics.mse_dissertation_mean))
    });
    let ((n1, k1), (n2, k2)) = k_still_rising(ks)?;
    Some(format!(
        "Pre-asymptotic: K = 3N²·MSE of linear search still rises from {} at N = {n1} to {} at N = {n2}, so the MSE falls slower than 1/N² here \
         (steps still cross features); a 1/N² slope is reached only once K is flat.",
        fmt_num(k1, 3),
        fmt_num(k2, 3)
    ))
}

/// K = 3N²·MSE ([`k_linear`]) of linear-search rows given as (N, per-ray MSE), at their
/// largest two step counts (the first row of each N), when it still rises there by more
/// than [`K_RISING`]×; `None` when it is flat or fewer than three step counts have a finite K.
pub(crate) fn k_still_rising(rows: impl Iterator<Item = (u32, f64)>) -> Option<((u32, f64), (u32, f64))> {
    let mut ks: Vec<(u32, f64)> = rows.map(|(n, mse)| (n, k_linear(n, mse))).filter(|(_, k)| k.is_finite()).collect();
    ks.sort_by_key(|&(n, _)| n);
    ks.dedup_by_key(|&mut (n, _)| n);
    // Two step counts (Tables 4.2 and 4.4's linear-only rows) are no trend to read.
    let [_, .., a, b] = ks[..] else { return None };
    (b.1 > K_RISING * a.1).then_some((a, b))
}

fn render(t: &ReportTable, data: &Data, description: &str, multi_size: bool) -> TextTable {
    let mut title = description.to_string();
    if title.is_empty() {
        title = format!("Table {}", t.id);
    }
    if t.scene != "scene:lion" {
        title = title.replace(" (Lion)", "");
        title.push_str(&format!(" — scene {}", short_scene(&t.scene)));
    }
    if let (true, Some(z)) = (multi_size, t.size) {
        title.push_str(&format!(" — size {z}²"));
    }
    let measured = (0..t.entries.len()).filter(|&i| t.row(data, i).is_some()).count();
    let size_text = match t.size {
        Some(z) => format!("Our rows: size {z}²."),
        None => "No row measured.".into(),
    };
    let mut notes = vec![format!(
        "{} rows ({} printed in the dissertation), {} measured here. {size_text} {}",
        t.entries.len(),
        t.entries.iter().filter(|e| e.diss.is_some()).count(),
        measured,
        base_rule(&t.id)
    )];
    if t.scene != "scene:lion" {
        notes.push("The dissertation's numbers are from Lion; compare trends only.".into());
    }
    let mut source_notes: Vec<&str> = Vec::new();
    for e in &t.entries {
        if let Some(n) = e.diss.as_ref().map(|d| d.note.as_str()).filter(|n| !n.is_empty()) {
            if !source_notes.contains(&n) {
                source_notes.push(n);
            }
        }
    }
    if !source_notes.is_empty() {
        notes.push(format!("Notes on the dissertation's rows: {}.", source_notes.join(" / ")));
    }
    if let Some(note) = regime_note(t, data) {
        notes.push(note);
    }
    if let Some(note) = steps_note(t, data) {
        notes.push(note);
    }
    let mut rows = Vec::new();
    for (i, e) in t.entries.iter().enumerate() {
        let r = t.row(data, i);
        let b = t.row(data, e.base).filter(|b| b.status.is_ok());
        let d = e.diss.as_ref();
        let bd = t.entries.get(e.base).and_then(|x| x.diss.as_ref());
        let rel = |f: fn(&Row) -> f64| -> String {
            ours(r, |r| match b {
                Some(b) => fmt_pct(ratio_pct(f(r), f(b))),
                None => DASH.into(),
            })
        };
        let diss_rel = |f: fn(&DissRow) -> Option<f64>| -> String {
            match (d.and_then(f), bd.and_then(f)) {
                (Some(v), Some(bv)) => fmt_pct(ratio_pct(v, bv)),
                _ => DASH.into(),
            }
        };
        let text = |s: Option<&String>| s.filter(|s| !s.is_empty()).cloned().unwrap_or_else(|| DASH.into());
        rows.push(vec![
            (i + 1).to_string(),
            format!("`{}`", e.label),
            if e.base == i { DASH.into() } else { format!("#{}", e.base + 1) },
            ours(r, |r| fmt_ms(r.metrics.frame_ms_median)),
            ours(r, |r| fmt_ms(r.metrics.frame_ms_mean)),
            text(d.map(|d| &d.frame_ms)),
            rel(|r| r.metrics.frame_ms_mean),
            diss_rel(DissRow::ms_f),
            ours(r, fmt_ratio),
            ours(r, |r| fmt_num(r.metrics.avg_coarse_steps, 3)),
            text(d.map(|d| &d.avg_steps)),
            ours(r, |r| fmt_num(r.metrics.avg_refine_steps, 3)),
            ours(r, |r| fmt_num(r.metrics.avg_iterations, 2)),
            ours(r, |r| fmt_num(r.metrics.avg_fetches, 2)),
            ours(r, |r| fmt_num(r.metrics.simd32_fetches, 2)),
            ours(r, |r| fmt_sci(r.metrics.mse_dissertation)),
            ours(r, |r| fmt_sci(r.metrics.mse_dissertation_mean)),
            text(d.map(|d| &d.mse)),
            rel(|r| r.metrics.mse_dissertation_mean),
            diss_rel(DissRow::mse_f),
            ours(r, |r| fmt_sci(r.metrics.ref_err_t_rms)),
            rel(|r| r.metrics.ref_err_t_rms),
            ours(r, |r| fmt_sci(r.metrics.ref_err_t_median)),
            ours(r, |r| fmt_sci(r.metrics.ref_err_t_p90)),
            ours(r, |r| fmt_sci(r.metrics.ref_err_t_p99)),
            ours(r, |r| fmt_num(r.metrics.mse_worst1_share, 3)),
            match e.pipeline.as_ref().and_then(linear_steps) {
                Some(n) => ours(r, |r| fmt_num(k_linear(n, r.metrics.mse_dissertation_mean), 3)),
                None => DASH.into(),
            },
            ours(r, |r| fmt_num(r.metrics.skipped_rate, 4)),
            ours(r, |r| fmt_num(r.metrics.past_rate, 4)),
            ours(r, |r| r.metrics.nan_count.to_string()),
            ours(r, |r| r.metrics.outside_count.to_string()),
            ours(r, |r| fmt_num(r.metrics.nonconverged_rate, 4)),
        ]);
    }
    TextTable { title, notes, header: HEADER.iter().map(|s| s.to_string()).collect(), rows }
}

/// `1.234 [1.201, 1.268]`: the row's frame time over the baseline's with its 95 % interval
/// (paired timing), `—` for a row timed alone.
fn fmt_ratio(r: &Row) -> String {
    let m = &r.metrics;
    match (m.frame_ratio_to_baseline, m.frame_ratio_to_baseline_lo, m.frame_ratio_to_baseline_hi) {
        (Some(x), Some(lo), Some(hi)) => format!("{x:.3} [{lo:.3}, {hi:.3}]"),
        (Some(x), _, _) => format!("{x:.3}"),
        _ => DASH.into(),
    }
}

/// The explanation printed before the tables.
pub(crate) fn intro_md() -> String {
    "## Tables\n\n\
Each table has the dissertation's rows in its order (rows the grid adds come last), on one scene \
and one image size: rows of different sizes are never mixed. Frame time: `frame ms (median)` and \
`frame ms (mean)` over the timed frames; the dissertation's `diss ms (mean of 500)` is a mean over \
500 frames, so compare it with our mean, and `mean ms % base` is the mean's trend. \
`frame ÷ baseline (95 %)` is the row's mean frame time over the baseline pipeline's, timed in \
alternating blocks in the same run, with its 95 % interval (docs/timing.md): the timing that \
survives a busy machine, and what the timing conclusions read. `simd32 fetches (model)` is the \
GPU cost model: the largest fetch count of a group of 32 rays (8 × 4 pixels), averaged over \
groups. Steps: \
`avg coarse steps` and `avg refine steps` are loop passes per ray of each search; the \
dissertation's \"avg steps\" counts the coarse search only (Table 4.11's csm(5)+binary(5) shows \
2.016, like Table 4.8's csm(5)), so it sits next to `avg coarse steps`; `avg iter (total)` and \
`avg fetches (total)` are over all stages. Error: `mse_dissertation (sum)` sums the squared height \
errors (h(hit.uv) − hit.z)² over the probe rays, as the dissertation describes its MSE; \
`mse_dissertation_mean` is that sum divided by the rays. Both are in squared height units (heights \
in [0, 1]). The dissertation's printed MSE behaves like the mean, not the sum (Table 4.1: MSE × N² \
stays near 0.4–0.55 for N = 5…200, so it does not grow with the pixel count), so `diss MSE` is \
compared with `mse_dissertation_mean`, and the conclusions use the mean. A hit that is NaN or \
infinite counts as an error in the metrics, never as a skipped ray, and `nan_count` shows how many \
there were. `ref_err_t_rms` is the RMS error of the hit's ray parameter t against the exact \
reference, and `|t err|` its median, 90th and 99th percentile over the rays; `MSE share of worst 1 %` \
how much of the MSE the worst 1 % of the rays carry (near 1: a few rays carry the error, and an RMS or \
mean alone misleads); `K = 3N²·MSE` for linear search alone (flat once the MSE falls as 1/N²); \
`skipped_rate` the share of rays that jumped over geometry (after the exact first hit the ray comes \
back above the surface before the reported hit); `past_rate` the share whose hit lies more than one \
texel of travel beyond the true first hit, or that miss (on a large map a linear step spans several \
texels, so this counts rays that skipped nothing); `outside_count` hits outside the volume before any clamp; \
`nonconverged_rate` the share of rays whose coarse search found no crossing. Absolute times and MSE \
sums depend on the hardware and the pixel count, so compare the `% base` trend columns: each row \
relative to its base row (`base` names it by `#`). `—` = not measured / not printed, `NaN` = not \
recorded (a results file older than the column) or not a finite number, `error` = the cell failed \
(see Failed cells).\n\n"
        .to_string()
}
