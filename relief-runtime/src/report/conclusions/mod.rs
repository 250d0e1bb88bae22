//! The dissertation's conclusions, each checked against our rows with a stated criterion,
//! and the same criterion applied to the dissertation's own numbers (a check that the
//! criterion says what the dissertation says). Error criteria are checked twice: with
//! `mse_dissertation_mean` (the dissertation's metric, as a per-ray mean: see the report's
//! table notes) and with `ref_err_t_rms`, whose thresholds are applied to its square.
//! Frame times are means, as the dissertation's (Burger 2018 §4.1). A criterion reads rows
//! of one size only: one that would mix sizes is refused, "not measured", with the sizes
//! named (a verdict rather than an error, so one mixed criterion does not hide the others).
//!
//! Frame-time criteria read the rows' `frame_ratio_to_baseline` when every ok row of the
//! scene has one against one baseline (paired timing, [`crate::timing`]): a comparison of
//! two cells is the quotient of their ratios with its 95 % interval, and a criterion whose
//! answer the intervals leave open is "not decided". Rows without ratios are compared by
//! their mean frame times, as points. Every criterion that reads frame time is judged a
//! second time on the SIMD cost model (`simd32_fetches`, [`crate::simd`]), labelled
//! "model".
//!
//! This module runs the checks and prints their verdicts; the checks themselves, one per
//! conclusion, are the table in [`checks`].

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::fmt::Write as _;

use relief_dsl::spec::Lod;
use relief_dsl::Pipeline;

mod checks;

use super::diss::{Diss, DissRow};
use super::stats::spearman;
use super::{short_scene, Data, Metric, TextTable, DASH};
use crate::timing::Ratio;

/// Whether a conclusion holds in a set of numbers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// The criterion was checked and is met.
    Holds,
    /// The criterion was checked and is not met.
    DoesNotHold,
    /// The criterion could not be checked: too few of the cells it reads were measured, or
    /// they mix frame sizes. The evidence says which.
    NotMeasured,
    /// The frame-time intervals straddle the criterion's threshold: the rows measured
    /// cannot say whether it holds.
    NotDecided,
}

impl Verdict {
    /// The verdict as the report prints it: `holds`, `does not hold`, `not measured` or
    /// `not decided`.
    pub fn as_str(self) -> &'static str {
        match self {
            Verdict::Holds => "holds",
            Verdict::DoesNotHold => "does not hold",
            Verdict::NotMeasured => "not measured",
            Verdict::NotDecided => "not decided",
        }
    }
}

impl std::fmt::Display for Verdict {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// One conclusion of the dissertation, checked.
#[derive(Clone, Debug)]
pub struct Conclusion {
    /// The table it comes from (`4.1`, `4.11` …); several conclusions may share a table.
    pub table: String,
    /// What the dissertation concludes.
    pub claim: String,
    /// How it is checked.
    pub criterion: String,
    /// Why its thresholds are what they are (where they differ from the common 75% share).
    pub why: String,
    /// Our rows, error measured by `mse_dissertation_mean` (or frame time only).
    pub ours_mse: Verdict,
    /// The numbers behind `ours_mse` in one line, or why it was not measured.
    pub evidence_mse: String,
    /// Our rows, error measured by `ref_err_t_rms`; None when the criterion is about frame
    /// time only.
    pub ours_ref: Option<Verdict>,
    /// The numbers behind `ours_ref`, or why it was not measured; empty when `ours_ref`
    /// is `None`.
    pub evidence_ref: String,
    /// The dissertation's own numbers under the same criterion.
    pub diss: Verdict,
    /// The dissertation's numbers behind `diss`, or why they do not settle it.
    pub evidence_diss: String,
    /// The scene our rows were taken from.
    pub scene: String,
    /// Which form of the cone methods our rows used (`safe` or `textbook`), or empty when the
    /// criterion reads no cone method. The dissertation's numbers are the same for both.
    pub form: String,
    /// Whether the criterion reads frame time.
    pub reads_time: bool,
    /// The criterion on our rows with the SIMD cost model's `simd32_fetches` in place of
    /// frame time (errors by `mse_dissertation_mean`); None when it reads no frame time.
    pub model: Option<Verdict>,
    /// The numbers behind `model`, or why it was not measured.
    pub evidence_model: String,
    /// The criterion with the GPU compiler's modeled instructions per pixel in place of
    /// frame time (`gpu_FAMILY_instr_px`, [`crate::cost`]), per family with columns: (family,
    /// verdict, evidence). Empty when it reads no frame time or no row has the columns.
    pub gpu_model: Vec<(String, Verdict, String)>,
}

/// `p` with its cone method (if any) in the form a reading checks, and whether it has one:
/// `form=textbook` keeps the sampling the text names; `form=safe` reads the cell under the ray
/// point unfiltered, like every safe method, so a textbook sampling choice (`sample=nearest`,
/// chosen to match the others' nearest filtering) becomes the safe default, and one that has
/// no safe counterpart (`sample=linear|min4`, `start=hk`) reads nothing (`None`).
pub(crate) fn for_form(p: &Pipeline, textbook: bool) -> (Option<Pipeline>, bool) {
    use relief_dsl::spec::Value;
    let mut p = p.clone();
    let c = &mut p.coarse;
    if c.get("form").is_none() {
        return (Some(p), false);
    }
    let set = |c: &mut relief_dsl::StageSpec, name: &str, word: &str| {
        if let Some((_, v)) = c.params.iter_mut().find(|(n, _)| n == name) {
            *v = Value::Word(word.into());
        }
    };
    set(c, "form", if textbook { "textbook" } else { "safe" });
    if !textbook {
        match c.get("sample").map(|v| v.to_string()).as_deref() {
            Some("nearest") => set(c, "sample", "auto"),
            Some("linear" | "min4") => return (None, true),
            _ => {}
        }
        match c.get("start").map(|v| v.to_string()).as_deref() {
            Some("bracket") => set(c, "start", "auto"),
            Some("hk") => return (None, true),
            _ => {}
        }
    }
    (Some(p), true)
}

/// Where the numbers come from.
trait Src {
    /// The frame time of pipeline `p` (canonical text) in table `table`: our paired ratio to
    /// the baseline with its 95 % interval, or a point (the mean frame time: the
    /// dissertation reports the mean over 500 frames, Burger 2018 §4.1; the model's cost).
    /// Compare two with [`slower`].
    fn time(&self, table: &str, p: &str) -> Option<Ratio>;
    /// Error of `p` in table `table`, as a *squared* error: an MSE as it is, an RMS squared.
    /// Every ratio threshold below is stated for an MSE, and squaring the RMS makes it mean
    /// the same for `ref_err_t_rms` (a 10% MSE difference is a 4.9% RMS difference). A
    /// non-finite error is infinite: a NaN counts as the worst error, never as unmeasured.
    fn err(&self, table: &str, p: &str) -> Option<f64>;
    /// (frame time, squared error) of `p` from one row, for the criteria about the best
    /// error per frame time: the estimate of [`Src::time`], without its interval. The dissertation's numbers: the latest table that prints `p`
    /// with both (its later tables are the ones comparing methods, as the figures do).
    fn point(&self, p: &str) -> Option<(f64, f64)>;
    /// What `err` is, for evidence.
    fn unit(&self) -> &'static str;
    /// The pipeline this source reads for grid cell `p` (ours: its cone method in the form
    /// being checked), or None when it has none.
    fn select(&self, p: &Pipeline) -> Option<Pipeline>;
}

/// What our rows' frame time is read as.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Clock {
    /// `frame_ratio_to_baseline` with its interval (every ok row of the scene has one, to one
    /// baseline).
    Ratio,
    /// `frame_ms_mean`, a point.
    Mean,
    /// The SIMD cost model's `simd32_fetches`, a point.
    Model,
    /// The GPU compiler's modeled instructions per pixel on a family, a point.
    Gpu(&'static str),
}

/// This run's rows (the results file's ok rows of one scene), read as a [`Src`] by the
/// criteria.
struct MeasuredRows<'a> {
    data: &'a Data,
    /// How frame time is read.
    clock: Clock,
    /// Whether a criterion read frame time.
    read_time: std::cell::Cell<bool>,
    /// Whether the model was asked for a pipeline with shadow or ao work, which the probe
    /// does not trace.
    untraced: std::cell::Cell<bool>,
    scene: String,
    metric: Metric,
    /// Read the cone methods' `form=textbook` rows instead of the (default) safe ones.
    textbook: bool,
    /// Whether a pipeline read had a cone method whose form the reading chose.
    read_cone: std::cell::Cell<bool>,
    /// The sizes of the rows a criterion read, with the pipelines read at each.
    used: RefCell<BTreeMap<u32, Vec<String>>>,
    /// The `lod` of the rows read: every cell a criterion names is read with this option.
    lod: Lod,
}

impl<'a> MeasuredRows<'a> {
    fn new(data: &'a Data, scene: &str, metric: Metric, textbook: bool, lod: Lod, model: Option<Clock>) -> Self {
        let clock = model.unwrap_or_else(|| time_clock(data, scene));
        MeasuredRows {
            data,
            clock,
            read_time: Default::default(),
            untraced: Default::default(),
            scene: scene.to_string(),
            metric,
            textbook,
            read_cone: Default::default(),
            used: RefCell::new(BTreeMap::new()),
            lod,
        }
    }

    /// The row's frame time as this source reads it.
    fn time_of(&self, r: &crate::results::Row) -> Option<Ratio> {
        self.read_time.set(true);
        let m = &r.metrics;
        let v = match self.clock {
            Clock::Ratio => Ratio::to_baseline(m)?,
            Clock::Mean => Ratio::point(m.frame_ms_mean),
            Clock::Model => {
                if !r.metrics.pipeline.shadow.is_none() || !r.metrics.pipeline.ao.is_none() {
                    self.untraced.set(true);
                    return None;
                }
                Ratio::point(m.simd32_fetches)
            }
            Clock::Gpu(family) => {
                if !r.metrics.pipeline.shadow.is_none() || !r.metrics.pipeline.ao.is_none() {
                    self.untraced.set(true);
                    return None;
                }
                Ratio::point(crate::report::gpu_cost::instr_px(m, family))
            }
        };
        v.ratio.is_finite().then_some(v)
    }

    fn note(&self, r: &crate::results::Row) {
        let mut u = self.used.borrow_mut();
        let v = u.entry(r.metrics.size).or_default();
        let text = r.metrics.pipeline.to_string();
        if !v.contains(&text) {
            v.push(text);
        }
    }

    /// The ok rows of `p` on the scene; every size it has is noted.
    fn row(&self, p: &str) -> Option<&'a crate::results::Row> {
        let p = match p.parse::<Pipeline>() {
            Ok(p) => self.select(&p)?.to_string(),
            Err(_) => p.to_string(),
        };
        let rows = self.data.ok_any_size(&p, &self.scene);
        for r in &rows {
            self.note(r);
        }
        rows.first().copied()
    }

    /// Why the rows read so far cannot be compared: they come from more than one size.
    fn mixed_sizes(&self) -> Option<String> {
        let u = self.used.borrow();
        if u.len() < 2 {
            return None;
        }
        let parts: Vec<String> = u
            .iter()
            .map(|(z, ps)| {
                let more = if ps.len() > 3 { format!(" and {} more", ps.len() - 3) } else { String::new() };
                format!("{z}² ({}{more})", ps.iter().take(3).map(|p| format!("`{p}`")).collect::<Vec<_>>().join(", "))
            })
            .collect();
        Some(format!(
            "refused: the rows this criterion needs were measured at {} sizes, {}; errors and frame times of different \
             sizes are not comparable, so sweep the cells at one size (or report each size's sweep separately)",
            u.len(),
            parts.join("; ")
        ))
    }
}

impl Src for MeasuredRows<'_> {
    fn time(&self, _: &str, p: &str) -> Option<Ratio> {
        self.time_of(self.row(p)?)
    }
    fn err(&self, _: &str, p: &str) -> Option<f64> {
        self.row(p).map(|r| self.squared(self.metric.of(r)))
    }
    fn point(&self, p: &str) -> Option<(f64, f64)> {
        let r = self.row(p)?;
        let t = self.time_of(r)?;
        Some((t.ratio, self.squared(self.metric.of(r))))
    }
    fn unit(&self) -> &'static str {
        match self.metric {
            Metric::RefT => "ref_err_t_rms²",
            _ => "mse_dissertation_mean",
        }
    }
    fn select(&self, p: &Pipeline) -> Option<Pipeline> {
        let (q, cone) = for_form(p, self.textbook);
        if cone {
            self.read_cone.set(true);
        }
        q.map(|q| q.with_lod(self.lod))
    }
}

impl MeasuredRows<'_> {
    fn squared(&self, v: f64) -> f64 {
        if !v.is_finite() {
            return f64::INFINITY;
        }
        match self.metric {
            Metric::RefT => v * v,
            _ => v,
        }
    }
}

/// Whether the dissertation's rows can stand for `p`'s cone-map sampling. Its tables print
/// "CSM" without saying how it reads the cone map, so its csm rows stand for linear and
/// nearest sampling alike (matched by name); min-of-4 sampling it names only as a fix it did
/// not tabulate (§4.3.1), and corner sampling is relief's own: no printed row is either.
fn printed_sampling(p: &Pipeline) -> bool {
    !(p.coarse.name == "csm" && matches!(p.coarse.word("sample"), "min4" | "corners"))
}

/// The dissertation's printed rows (Burger 2018's tables), read as a [`Src`] by the criteria.
struct PrintedRows<'a> {
    diss: &'a Diss,
}

impl PrintedRows<'_> {
    /// The row of `p` in `table`; `*` means the first printed row of any table with a value.
    fn find(&self, table: &str, p: &str, f: fn(&DissRow) -> Option<f64>) -> Option<f64> {
        let p: Pipeline = p.parse().ok()?;
        if !printed_sampling(&p) {
            return None;
        }
        if table == "*" {
            return self.diss.rows.iter().filter(|r| r.matches(&p)).find_map(f);
        }
        f(self.diss.find(table, &p)?)
    }
}

impl Src for PrintedRows<'_> {
    fn time(&self, table: &str, p: &str) -> Option<Ratio> {
        self.find(table, p, DissRow::ms_f).map(Ratio::point)
    }
    fn err(&self, table: &str, p: &str) -> Option<f64> {
        self.find(table, p, DissRow::mse_f)
    }
    fn point(&self, p: &str) -> Option<(f64, f64)> {
        let p: Pipeline = p.parse().ok()?;
        if !printed_sampling(&p) {
            return None;
        }
        self.diss.rows.iter().rev().filter(|r| r.matches(&p)).find_map(|r| Some((r.ms_f()?, r.mse_f()?)))
    }
    fn unit(&self) -> &'static str {
        "MSE as printed"
    }
    /// The dissertation's rows stand for both forms: every cell reads as its safe form, so
    /// that the two forms of one cell are one point.
    fn select(&self, p: &Pipeline) -> Option<Pipeline> {
        for_form(p, false).0.or_else(|| Some(p.clone()))
    }
}

/// A comparison's answer: `Some(answer)`, or `None` when the frame-time intervals leave it
/// open (not decided).
type Dec = Option<bool>;

/// A criterion's outcome: Ok((holds, evidence)), `holds` None when not decided, or Err(why
/// it could not be checked).
type Outcome = Result<(Dec, String), String>;

/// How our rows' frame times are read on `scene`: as paired ratios when every ok row there
/// has one, all to one baseline; as mean frame times otherwise (ratios of different
/// baselines, or rows timed alone, do not compare).
fn time_clock(data: &Data, scene: &str) -> Clock {
    let rows: Vec<&crate::results::Row> =
        data.rows.iter().filter(|r| r.metrics.scene == scene && r.status.is_ok()).collect();
    let base = rows.first().map(|r| r.metrics.baseline.clone()).unwrap_or_default();
    let paired = !rows.is_empty()
        && !base.is_empty()
        && rows.iter().all(|r| r.metrics.frame_ratio_to_baseline.is_some() && r.metrics.baseline == base);
    if paired {
        Clock::Ratio
    } else {
        Clock::Mean
    }
}

/// Whether `a` is slower than `factor` × `b` in `table`: decided when the interval of
/// time(a) ÷ time(b) lies on one side of `factor` ([`Ratio::over`], [`Ratio::above`]); None
/// when either is not measured.
fn slower(s: &dyn Src, table: &str, a: &str, b: &str, factor: f64) -> Option<Dec> {
    Some(s.time(table, a)?.over(&s.time(table, b)?).above(factor))
}

/// Both decided true: true; either decided false: false; otherwise not decided.
fn and(a: Dec, b: Dec) -> Dec {
    match (a, b) {
        (Some(false), _) | (_, Some(false)) => Some(false),
        (Some(true), Some(true)) => Some(true),
        _ => None,
    }
}

/// Spearman's ρ between `x` and the frame times `y` is at least `need`: on the estimates
/// when no time has an interval; otherwise decided by a parametric bootstrap over the
/// intervals (2000 draws of every ln time from a normal with its estimate and standard
/// error, [`Ratio::log_se`], a fixed seed): holds when the 2.5 % quantile of the drawn ρ is
/// at least `need`, fails when the 97.5 % quantile is below it, not decided between.
fn spearman_at_least(x: &[f64], y: &[Ratio], need: f64) -> Result<(Dec, String), String> {
    let est: Vec<f64> = y.iter().map(|r| r.ratio).collect();
    let rho = spearman(x, &est).ok_or_else(|| format!("{} step counts measured (need 3)", x.len()))?;
    let se: Vec<f64> = y.iter().map(|r| r.log_se()).collect();
    if se.iter().all(|s| !s.is_finite()) {
        return Ok((Some(rho >= need), format!("ρ = {rho:.2} over {} step counts", x.len())));
    }
    let mut state = 0x5eed_u64;
    let mut uniform = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    };
    let mut rhos: Vec<f64> = (0..2000)
        .map(|_| {
            let draw: Vec<f64> = est
                .iter()
                .zip(&se)
                .map(|(e, s)| {
                    let z = (-2.0 * uniform().ln()).sqrt() * (std::f64::consts::TAU * uniform()).cos();
                    e.ln() + if s.is_finite() { s * z } else { 0.0 }
                })
                .collect();
            spearman(x, &draw).unwrap_or(f64::NAN)
        })
        .collect();
    rhos.sort_by(f64::total_cmp);
    let (lo, hi) = (rhos[50], rhos[1949]);
    let dec = if lo >= need {
        Some(true)
    } else if hi < need {
        Some(false)
    } else {
        None
    };
    Ok((dec, format!("ρ = {rho:.2} [{lo:.2}, {hi:.2}] (95 %) over {} step counts", x.len())))
}

struct Check {
    table: &'static str,
    claim: &'static str,
    criterion: &'static str,
    /// Why the criterion's thresholds are what they are, where they differ from the common
    /// rule (a share of at least 75% of the measured cells).
    why: &'static str,
    /// Whether the criterion looks at errors (else frame time only).
    uses_error: bool,
    run: fn(&dyn Src) -> Outcome,
}

fn verdict(o: &Outcome) -> (Verdict, String) {
    match o {
        Ok((Some(true), e)) => (Verdict::Holds, e.clone()),
        Ok((Some(false), e)) => (Verdict::DoesNotHold, e.clone()),
        Ok((None, e)) => (Verdict::NotDecided, e.clone()),
        Err(e) => (Verdict::NotMeasured, e.clone()),
    }
}

/// A check's outcome on this run's rows.
struct MeasuredCheck {
    verdict: Verdict,
    evidence: String,
    /// Whether the criterion read a cone method (whose form the reading chose).
    read_cone: bool,
    /// Whether the criterion read frame time.
    read_time: bool,
}

/// Runs a check on our rows with `metric`; a criterion that read rows of more than one size
/// is refused (not measured, the evidence naming the sizes) rather than an error, so that
/// the rest of the report stays readable.
/// Also says whether the criterion read a cone method (whose form `textbook` chose) and
/// whether it read frame time. With `model`, frame time is the SIMD cost model's.
fn run_measured(
    c: &Check,
    data: &Data,
    scene: &str,
    metric: Metric,
    textbook: bool,
    lod: Lod,
    model: Option<Clock>,
) -> MeasuredCheck {
    let src = MeasuredRows::new(data, scene, metric, textbook, lod, model);
    let out = (c.run)(&src);
    let (read_cone, read_time) = (src.read_cone.get(), src.read_time.get());
    let refused = |evidence| MeasuredCheck { verdict: Verdict::NotMeasured, evidence, read_cone, read_time };
    if let Some(why) = src.mixed_sizes() {
        return refused(why);
    }
    if src.untraced.get() {
        return refused(
            "the model counts the probe's trace only; shadow and ambient-occlusion work is not in it".into(),
        );
    }
    let (v, mut e) = verdict(&out);
    if read_time && v != Verdict::NotMeasured {
        e.push_str(match src.clock {
            Clock::Ratio => "; frame times as paired ratios to the baseline, 95 % intervals",
            Clock::Mean => "; mean frame times as points (the rows have no paired ratios to one baseline)",
            Clock::Model => "; model: simd32_fetches",
            Clock::Gpu(_) => "; model: the GPU compiler's instructions per pixel",
        });
    }
    MeasuredCheck { verdict: v, evidence: e, read_cone, read_time }
}

/// Checks every conclusion on the main scene's rows; a criterion that reads a cone method
/// is checked twice, on the `form=safe` rows and on the `form=textbook` ones.
pub(crate) fn check(data: &Data, diss: &Diss) -> Vec<Conclusion> {
    let scene = data.main_scene().unwrap_or_else(|| "scene:lion".into());
    check_at(data, diss, &scene, Lod::Zero)
}

/// [`check`] on `scene`'s rows of pipelines with option `lod` (every cell a criterion reads
/// is read as `cell+lod=…`).
pub(crate) fn check_at(data: &Data, diss: &Diss, scene: &str, lod: Lod) -> Vec<Conclusion> {
    let scene = scene.to_string();
    let printed = PrintedRows { diss };
    let mut out = Vec::new();
    for c in &checks::checks() {
        let (dv, de) = verdict(&(c.run)(&printed));
        for textbook in [false, true] {
            let MeasuredCheck { verdict: ours_mse, evidence: evidence_mse, read_cone: cone, read_time: reads_time } =
                run_measured(c, data, &scene, Metric::Mse, textbook, lod, None);
            if textbook && !cone {
                break;
            }
            let (ours_ref, evidence_ref) = if c.uses_error {
                let m = run_measured(c, data, &scene, Metric::RefT, textbook, lod, None);
                (Some(m.verdict), m.evidence)
            } else {
                (None, String::new())
            };
            let (model, evidence_model) = if reads_time {
                let m = run_measured(c, data, &scene, Metric::Mse, textbook, lod, Some(Clock::Model));
                (Some(m.verdict), m.evidence)
            } else {
                (None, String::new())
            };
            let priced = data.rows.iter().any(|r| r.metrics.gpu_driver.is_some());
            let gpu_model = if reads_time && priced {
                crate::report::gpu_cost::FAMILIES
                    .iter()
                    .map(|(f, _)| {
                        let m = run_measured(c, data, &scene, Metric::Mse, textbook, lod, Some(Clock::Gpu(f)));
                        (f.to_string(), m.verdict, m.evidence)
                    })
                    .collect()
            } else {
                vec![]
            };
            let form = match (cone, textbook) {
                (false, _) => "",
                (true, false) => "safe",
                (true, true) => "textbook",
            };
            out.push(Conclusion {
                table: c.table.into(),
                claim: c.claim.into(),
                criterion: c.criterion.into(),
                why: c.why.into(),
                ours_mse,
                evidence_mse,
                ours_ref,
                evidence_ref,
                diss: dv,
                evidence_diss: de.clone(),
                scene: scene.clone(),
                form: form.into(),
                reads_time,
                model,
                evidence_model,
                gpu_model,
            });
        }
    }
    out
}

// ---------------------------------------------------------------------------------------
// Helpers

/// `v` in few characters: three decimals in the middle range, scientific notation outside it.
fn compact(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else if v.abs() >= 0.01 && v.abs() < 1000.0 {
        format!("{v:.3}")
    } else {
        format!("{v:.2e}")
    }
}

/// (pipeline, mean frame ms, squared error) of the measured cells of the figure grids.
fn figure_points(s: &dyn Src, figures: &[&str]) -> Vec<(Pipeline, f64, f64)> {
    let mut out: Vec<(Pipeline, f64, f64)> = Vec::new();
    for g in crate::sweep::grids::builtin(None).iter().filter(|g| figures.contains(&g.name.as_str())) {
        for (p, _) in &g.cells {
            let Some(p) = s.select(p) else { continue };
            if out.iter().any(|(q, _, _)| *q == p) {
                continue;
            }
            if let Some((ms, e)) = s.point(&p.to_string()) {
                out.push((p, ms, e));
            }
        }
    }
    out
}

/// The points no other point beats in both mean frame time and error, fastest first: the
/// report's one front ([`super::pareto::front`]) over (mean frame time, error).
fn pareto_front(pts: Vec<(Pipeline, f64, f64)>) -> Vec<(Pipeline, f64, f64)> {
    let points: Vec<(f64, f64)> = pts.iter().map(|p| (p.1, p.2)).collect();
    super::pareto::front(&points).into_iter().map(|i| pts[i].clone()).collect()
}

/// A coarse stage's choice parameter that changes what it reads (`, sample=min4`), for
/// grouping front points by method.
fn method_variant(p: &Pipeline) -> String {
    match p.coarse.word("sample") {
        "" | "auto" => String::new(),
        w => format!(" sample={w}"),
    }
}

/// `share` of `flags` true among the measured (Some) ones, at least `min` measured.
fn share(flags: &[Option<bool>], need: f64, min: usize, what: &str) -> Outcome {
    let measured: Vec<bool> = flags.iter().flatten().copied().collect();
    if measured.len() < min {
        return Err(format!("{} of the needed cells measured (need {min})", measured.len()));
    }
    let yes = measured.iter().filter(|b| **b).count();
    let holds = yes as f64 >= need * measured.len() as f64 - 1e-9;
    Ok((Some(holds), format!("{yes}/{} {what}", measured.len())))
}

/// [`share`] over comparisons that may be undecided (`Some(None)`): holds when the decided
/// yes alone reach the share, fails when they cannot reach it even with every undecided
/// one counted yes, not decided otherwise.
fn share_dec(flags: &[Option<Dec>], need: f64, min: usize, what: &str) -> Outcome {
    let measured: Vec<Dec> = flags.iter().flatten().copied().collect();
    if measured.len() < min {
        return Err(format!("{} of the needed cells measured (need {min})", measured.len()));
    }
    let n = measured.len() as f64;
    let yes = measured.iter().filter(|d| **d == Some(true)).count();
    let open = measured.iter().filter(|d| d.is_none()).count();
    let reach = |k: usize| k as f64 >= need * n - 1e-9;
    let dec = if reach(yes) {
        Some(true)
    } else if !reach(yes + open) {
        Some(false)
    } else {
        None
    };
    let open_text = if open > 0 { format!(" ({open} not decided)") } else { String::new() };
    Ok((dec, format!("{yes}/{} {what}{open_text}", measured.len())))
}

// ---------------------------------------------------------------------------------------
// Output

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

/// The conclusions of Tables 4.1, 4.2 and 4.7 (what the `lod` grid repeats) with every
/// sample at level 0 and at the pixel's footprint level, on every scene with `lod=auto` rows;
/// `None` when there are none. Verdicts are `mse / ref_err_t_rms` (frame-time criteria have
/// one). Only the criteria of those tables are listed, cone methods in both forms.
pub(crate) fn lod_markdown(data: &Data, diss: &Diss) -> Option<String> {
    let scenes: Vec<String> = data
        .scenes()
        .into_iter()
        .filter(|s| crate::scene::view::of_label(s).is_none())
        .filter(|s| data.rows.iter().any(|r| &r.metrics.scene == s && r.metrics.pipeline.lod == Lod::Auto))
        .collect();
    if scenes.is_empty() {
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
    for scene in &scenes {
        let zero = check_at(data, diss, scene, Lod::Zero);
        let auto = check_at(data, diss, scene, Lod::Auto);
        for (z, a) in zero.iter().zip(&auto) {
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
/// view and at the dissertation's (`scene@view=dissertation`), side by side, with the
/// verdicts that change marked; `None` when no scene has rows at the dissertation's view.
/// Verdicts are `mse / ref_err_t_rms` (frame-time criteria have one).
pub(crate) fn view_markdown(data: &Data, diss: &Diss) -> Option<String> {
    use crate::scene::View;
    let view = View::Dissertation;
    let suffix = format!("@view={}", view.name());
    let pairs: Vec<(String, String)> = data
        .scenes()
        .into_iter()
        .filter_map(|s| s.strip_suffix(&suffix).map(|base| (base.to_string(), s.clone())))
        .collect();
    if pairs.is_empty() {
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
    for (base, at_view) in &pairs {
        let own = check_at(data, diss, base, Lod::Zero);
        let theirs = check_at(data, diss, at_view, Lod::Zero);
        for (o, d) in own.iter().zip(&theirs) {
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
        for (label, scene, lod) in [("its own view", base, Some(Lod::Zero)), ("the dissertation's view", at_view, None)]
        {
            if let Some(note) = regime_line(data, scene, lod) {
                t.notes.push(format!("{} at {label}: {note}", short_scene(base)));
            }
        }
    }
    Some(t.to_markdown(2))
}

/// K = 3N²·MSE of `scene`'s linear-search rows (of `lod` where given) at its largest two
/// step counts, as a note when it still rises ([`super::tables::k_still_rising`]): the pre-asymptotic regime, where the error-slope
/// verdicts (Tables 4.1's and the 1/N² reading) belong to the view, not the method.
/// `None` when it is flat or fewer than three step counts are measured.
pub(crate) fn regime_line(data: &Data, scene: &str, lod: Option<Lod>) -> Option<String> {
    let rows = data.rows.iter().filter(|r| r.status.is_ok() && r.metrics.scene == scene).filter_map(|r| {
        let p = &r.metrics.pipeline;
        let n = super::tables::linear_steps(p).filter(|_| lod.is_none_or(|l| p.lod == l))?;
        Some((n, r.metrics.mse_dissertation_mean))
    });
    let ((n1, k1), (n2, k2)) = super::tables::k_still_rising(rows)?;
    Some(format!(
        "K = 3N²·MSE of linear search still rises ({} at N = {n1}, {} at N = {n2}): pre-asymptotic, the MSE falls slower than 1/N², so \
         a verdict read from the error's slope belongs to this view.",
        super::fmt_num(k1, 3),
        super::fmt_num(k2, 3)
    ))
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
