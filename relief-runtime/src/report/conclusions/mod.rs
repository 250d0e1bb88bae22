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

use relief_dsl::spec::Lod;
use relief_dsl::Pipeline;

mod checks;
pub(crate) mod write;

use super::data::{Data, Metric};
use super::diss::{Diss, DissRow};
use super::stats::spearman;
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

/// The scenes with `lod=auto` rows (at their own view), each with its conclusions at level 0
/// and at the footprint level ([`check_at`]): what the `lod` grid repeats.
pub(crate) fn lod_checks(data: &Data, diss: &Diss) -> Vec<(String, Vec<Conclusion>, Vec<Conclusion>)> {
    data.scenes()
        .into_iter()
        .filter(|s| crate::scene::view::of_label(s).is_none())
        .filter(|s| data.rows.iter().any(|r| &r.metrics.scene == s && r.metrics.pipeline.lod == Lod::Auto))
        .map(|s| {
            let zero = check_at(data, diss, &s, Lod::Zero);
            let auto = check_at(data, diss, &s, Lod::Auto);
            (s, zero, auto)
        })
        .collect()
}

/// One scene checked at its own view and at the dissertation's ([`view_checks`]).
pub(crate) struct ViewChecks {
    /// The scene's label at its own view.
    pub base: String,
    /// Its conclusions at its own view, at level 0.
    pub own: Vec<Conclusion>,
    /// Its conclusions at the dissertation's view (`scene@view=dissertation`).
    pub theirs: Vec<Conclusion>,
    /// Where linear search is still pre-asymptotic ([`regime_line`]): at its own view, at
    /// the dissertation's.
    pub regime: [Option<String>; 2],
}

/// Every scene with rows at the dissertation's view, checked there and at its own view.
pub(crate) fn view_checks(data: &Data, diss: &Diss) -> Vec<ViewChecks> {
    let suffix = format!("@view={}", crate::scene::View::Dissertation.name());
    data.scenes()
        .into_iter()
        .filter_map(|s| s.strip_suffix(&suffix).map(|base| (base.to_string(), s.clone())))
        .map(|(base, at_view)| ViewChecks {
            own: check_at(data, diss, &base, Lod::Zero),
            theirs: check_at(data, diss, &at_view, Lod::Zero),
            regime: [regime_line(data, &base, Some(Lod::Zero)), regime_line(data, &at_view, None)],
            base,
        })
        .collect()
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
        super::text::fmt_num(k1, 3),
        super::text::fmt_num(k2, 3)
    ))
}
