//! `relief tune`: the fastest pipeline of the `frontier` grid whose RMS t error
//! (`ref_err_t_rms`) is at most E and which skips no geometry (`skipped_rate` = 0) at every
//! view asked, on one map, found by measuring a quarter of the grid's cells or fewer.
//!
//! ```text
//! relief tune rocks --error 1e-2 --view 45 --view 70 --size 256
//! ```
//!
//! # The search
//!
//! The `frontier` grid's pipelines fall into families that differ only in their step count
//! ([`families`]: `linear_dynamic(1, N)+binary(5)` for N in 8…256, `csm(N)` for N in 8…64,
//! …). Within a family two things are assumed monotone in the step count: reaching the goal
//! at a view (more steps land closer and jump over less), and the frame time (more steps cost
//! more). Reaching the goal at *every* view is then monotone too, and each family has a
//! smallest step count that does it: that one, and no other of its family, can be the answer.
//!
//! Every cell is first measured at the hardest view (the most grazing angle asked), with
//! paired timing against Bevy's default [`BEVY_DEFAULT`] (its frame time over Bevy's, with a
//! 95 % interval); the other views are probed for accuracy only, and only for a pipeline
//! that reached the goal at the hardest view and is faster than the best found so far. The
//! families are searched best first, by branch and bound:
//!
//! * a family's bound is the frame time of its largest step count known to fail (every
//!   larger one costs at least as much); a family never measured has bound 0;
//! * the family with the lowest bound is measured next, at its smallest step count first
//!   (which gives the bound), then by bisection of the step counts still open (the upper
//!   middle, so that a family that never reaches the goal is closed in few measurements);
//! * a step count that reaches the goal at the hardest view but is slower than the best
//!   found so far closes its family above it; one that reaches it at every view becomes the
//!   best found so far when it is faster;
//! * a family whose bound is at least the best's frame time is dropped: none of its step
//!   counts can be faster.
//!
//! The search stops when every family is closed or dropped, or when the budget of
//! measurements is spent: a quarter of the `frontier` grid's cells for the views asked (its
//! pipelines × the views; [`Tuned::budget`]). A family left open then is named in
//! [`Tuned::open`]. Frame times are compared by their point estimates; the answer shows
//! the intervals.

use std::collections::HashMap;

use crate::error::{Error, Result};
use crate::gpu::{Gpu, GpuHit};
use crate::measure::{measure_accuracy, measure_paired_against, Prepared};
use crate::scene::{Overrides, Scene};
use crate::sweep::progress::Progress;
use crate::timing::Ratio;
use relief_dsl::spec::Value;
use relief_dsl::Pipeline;

/// The pipeline `relief tune` times every candidate against: Bevy's default parallax
/// mapping (`ParallaxMappingMethod::Relief { max_steps: 5 }` with 16 layers).
pub const BEVY_DEFAULT: &str = "linear_dynamic(1, 16)+binary(5)";

/// The views asked when none is given: 30°, 60° and 80° from the surface normal.
pub const DEFAULT_ANGLES: [f32; 3] = [30.0, 60.0, 80.0];

/// The grid whose pipelines are searched.
pub const GRID: &str = "frontier";

/// What `relief tune` is asked.
pub struct Options {
    /// The goal: RMS t error at most this (finite, > 0).
    pub error: f64,
    /// The views, degrees from the surface normal, each in [0, 90); at the map's own depth
    /// scale and azimuth.
    pub angles: Vec<f32>,
    /// Side of the square frame, in pixels.
    pub size: u32,
    /// Timed blocks per timed cell, the cell's and Bevy's together (as `relief sweep
    /// --frames`: `frames / 2` pairs, at least 2).
    pub frames: u32,
    /// Untimed frames before the timed ones.
    pub warmup: u32,
    /// Show a progress bar.
    pub progress: bool,
    /// The GPU compiler, for the modeled cost of the pick and its runners-up (`crate::cost`);
    /// none, or none installed: no model.
    pub gpu_cost: Option<crate::cost::Compiler>,
}

impl Options {
    /// Refuses a goal that is not a finite number above 0, no view, or a view outside
    /// [0, 90): one line each.
    pub fn check(&self) -> Result<()> {
        if !(self.error.is_finite() && self.error > 0.0) {
            return Err(Error::Input(format!(
                "--error {}: expected a finite RMS t error above 0 (e.g. 1e-2)",
                self.error
            )));
        }
        if self.angles.is_empty() {
            return Err(Error::Input("no view: give --view ANGLE at least once".into()));
        }
        for a in &self.angles {
            Overrides { angle: Some(*a), ..Default::default() }
                .check()
                .map_err(|e| Error::Input(e.replace("--angle", "--view")))?;
        }
        if self.size == 0 || self.size > 8192 {
            return Err(Error::Input(format!("--size {} is out of range: allowed 1..=8192", self.size)));
        }
        Ok(())
    }
}

/// A family of the grid: pipelines that differ only in their step count, fewest first.
#[derive(Clone, Debug)]
pub struct Family {
    /// The coarse method and the refinement, `csm` or `linear_dynamic+binary(5)`.
    pub name: String,
    /// Its pipelines, by step count (the coarse stage's largest integer parameter).
    pub pipelines: Vec<Pipeline>,
}

/// The step count a family orders by: the coarse stage's largest integer parameter.
fn steps(p: &Pipeline) -> u32 {
    p.coarse.params.iter().filter_map(|(_, v)| if let Value::Int(i) = v { Some(*i) } else { None }).max().unwrap_or(0)
}

/// The grid's pipelines in families, in the grid's order of first appearance.
pub fn families() -> Vec<Family> {
    let grid = crate::sweep::grids::load(GRID, Some(&["lion".to_string()])).expect("the frontier grid is built in");
    let mut out: Vec<Family> = Vec::new();
    for (p, _) in grid.cells {
        let mut key = p.clone();
        key.coarse.params.retain(|(_, v)| !matches!(v, Value::Int(_)));
        let name = key.to_string();
        match out.iter_mut().find(|f| f.name == name) {
            Some(f) => {
                if !f.pipelines.contains(&p) {
                    f.pipelines.push(p)
                }
            }
            None => out.push(Family { name, pipelines: vec![p] }),
        }
    }
    for f in &mut out {
        f.pipelines.sort_by_key(steps);
    }
    out
}

/// One measured (pipeline, view) cell.
#[derive(Clone, Debug)]
pub struct Cell {
    /// The pipeline as measured.
    pub pipeline: Pipeline,
    /// The view, degrees from the normal.
    pub angle: f32,
    /// `ref_err_t_rms`.
    pub err: f64,
    /// `skipped_rate`.
    pub skipped: f64,
    /// Its frame time over [`BEVY_DEFAULT`]'s, timed in alternating blocks: at the hardest
    /// view only (elsewhere the cell is probed for accuracy alone).
    pub speed: Option<Ratio>,
}

impl Cell {
    /// Whether the cell reaches the goal `error`: RMS t error ≤ `error` and no ray that
    /// skipped geometry (a NaN error or share never does).
    pub fn reaches(&self, error: f64) -> bool {
        self.err <= error && self.skipped == 0.0
    }
}

/// Where a pipeline that reached the goal at the hardest view stands at the others.
#[derive(Clone, Debug, PartialEq)]
pub enum Checked {
    /// It reaches the goal at every view.
    Every,
    /// It misses the goal at this view (degrees).
    Misses(f32),
    /// Not probed at the other views: slower than a pipeline already found.
    Slower,
}

/// A pipeline that reached the goal at the hardest view.
#[derive(Clone, Debug)]
pub struct Candidate {
    /// The pipeline as measured.
    pub pipeline: Pipeline,
    /// Its frame time over [`BEVY_DEFAULT`]'s at the hardest view, with its 95 % interval.
    pub speed: Ratio,
    /// Its largest RMS t error over the views it was measured at.
    pub err: f64,
    /// Its standing at the other views.
    pub checked: Checked,
    /// The GPU compiler's modeled instructions per pixel on RDNA2 (`gpu_navi21_instr_px`,
    /// a model, not a clock), for the pick and the runners-up shown, where RADV is installed.
    pub model_navi21: Option<f64>,
}

/// What `relief tune` found.
#[derive(Debug)]
pub struct Tuned {
    /// The map's name.
    pub scene: String,
    /// The goal.
    pub error: f64,
    /// Side of the square frame, in pixels.
    pub size: u32,
    /// The views, hardest (largest angle) first.
    pub angles: Vec<f32>,
    /// Every measurement, in the order made.
    pub cells: Vec<Cell>,
    /// The grid's cells for these views: its pipelines × the views.
    pub grid_cells: usize,
    /// The most measurements allowed: a quarter of [`Tuned::grid_cells`].
    pub budget: usize,
    /// The pick: the fastest pipeline found reaching the goal at every view.
    pub pick: Option<Pipeline>,
    /// Every pipeline that reached the goal at the hardest view, fastest first (the pick
    /// among them).
    pub candidates: Vec<Candidate>,
    /// Families left neither closed nor dropped when the budget ran out.
    pub open: Vec<String>,
    /// The adapter the cells were timed on.
    pub adapter: String,
}

impl Tuned {
    /// The pick's entry in [`Tuned::candidates`].
    pub fn pick(&self) -> Option<&Candidate> {
        let p = self.pick.as_ref()?;
        self.candidates.iter().find(|c| &c.pipeline == p)
    }

    /// The measured pipeline closest to the goal: at the hardest view, the smallest RMS t
    /// error among those that skipped nothing, else the smallest of all.
    pub fn closest(&self) -> Option<&Cell> {
        let hardest = *self.angles.first()?;
        self.cells
            .iter()
            .filter(|c| c.angle == hardest && c.err.is_finite())
            .min_by(|a, b| (a.skipped != 0.0).cmp(&(b.skipped != 0.0)).then(a.err.total_cmp(&b.err)))
    }

    /// The fastest pipeline timed that missed the goal though faster than the pick (what
    /// accuracy ruled out), with how many such there were.
    pub fn faster_missing(&self) -> (usize, Option<&Cell>) {
        let Some(pick) = self.pick() else { return (0, None) };
        let hardest = self.angles[0];
        let missed = |c: &Cell| {
            !c.reaches(self.error) || self.cells.iter().any(|d| d.pipeline == c.pipeline && !d.reaches(self.error))
        };
        let faster: Vec<&Cell> = self
            .cells
            .iter()
            .filter(|c| c.angle == hardest && c.speed.is_some_and(|s| s.ratio < pick.speed.ratio) && missed(c))
            .collect();
        let fastest = faster
            .iter()
            .copied()
            .min_by(|a, b| a.speed.map_or(f64::NAN, |s| s.ratio).total_cmp(&b.speed.map_or(f64::NAN, |s| s.ratio)));
        (faster.len(), fastest)
    }
}

/// What the search needs of one measurement.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Outcome {
    /// It reaches the goal.
    pub reaches: bool,
    /// Its frame time's rank (the ratio to Bevy's default), at the hardest view.
    pub speed: f64,
}

/// What the search found, as indices: the best (family, step index), the families left open.
#[derive(Debug, Default)]
pub(crate) struct Found {
    pub best: Option<(usize, usize)>,
    pub open: Vec<usize>,
    pub measured: usize,
}

/// The branch-and-bound of the module docs over families of `sizes[f]` step counts and
/// `views` views (0 the hardest), at most `budget` calls of `measure(family, index, view)`.
pub(crate) fn search(
    sizes: &[usize],
    views: usize,
    budget: usize,
    measure: &mut dyn FnMut(usize, usize, usize) -> Result<Outcome>,
) -> Result<Found> {
    struct State {
        lo: isize,
        hi: usize,
        bound: f64,
    }
    let mut st: Vec<State> = sizes.iter().map(|&n| State { lo: -1, hi: n, bound: 0.0 }).collect();
    let mut best: Option<(usize, usize, f64)> = None;
    let mut measured = 0;
    loop {
        let u = best.map_or(f64::INFINITY, |b| b.2);
        let open = |s: &State| ((s.lo + 1) as usize) < s.hi && s.bound < u;
        let Some(f) = (0..st.len()).filter(|&f| open(&st[f])).min_by(|&a, &b| st[a].bound.total_cmp(&st[b].bound))
        else {
            break;
        };
        if measured >= budget {
            return Ok(Found {
                best: best.map(|b| (b.0, b.1)),
                open: (0..st.len()).filter(|&f| open(&st[f])).collect(),
                measured,
            });
        }
        let s = &st[f];
        let i = if s.lo < 0 { 0 } else { (s.lo as usize + s.hi).div_ceil(2) };
        let i = i.clamp((s.lo + 1) as usize, s.hi - 1);
        let first = measure(f, i, 0)?;
        measured += 1;
        let speed = if first.speed.is_nan() { f64::INFINITY } else { first.speed };
        if !first.reaches {
            st[f].lo = i as isize;
            st[f].bound = st[f].bound.max(speed);
            continue;
        }
        if speed >= u {
            st[f].hi = i;
            continue;
        }
        let mut every = true;
        for v in 1..views {
            if measured >= budget {
                // Unchecked: the family stays open, the budget is spent.
                return Ok(Found {
                    best: best.map(|b| (b.0, b.1)),
                    open: (0..st.len()).filter(|&g| g == f || open(&st[g])).collect(),
                    measured,
                });
            }
            let o = measure(f, i, v)?;
            measured += 1;
            if !o.reaches {
                every = false;
                break;
            }
        }
        if every {
            st[f].hi = i;
            best = Some((f, i, speed));
        } else {
            st[f].lo = i as isize;
            st[f].bound = st[f].bound.max(speed);
        }
    }
    Ok(Found { best: best.map(|b| (b.0, b.1)), open: Vec::new(), measured })
}

/// Runs the search on `scene` (as `relief render --scene` takes it, loaded).
pub fn run(scene: &Scene, opts: &Options) -> Result<Tuned> {
    opts.check()?;
    let fams = families();
    let mut angles = opts.angles.clone();
    angles.sort_by(|a, b| b.total_cmp(a));
    angles.dedup();
    let pipelines: usize = fams.iter().map(|f| f.pipelines.len()).sum();
    let grid_cells = pipelines * angles.len();
    let budget = grid_cells / 4;
    let gpu = Gpu::new()?;
    let adapter = format!("{} ({})", gpu.adapter, gpu.driver);
    let mut bar = Progress::new(budget as u64, opts.progress);
    bar.preparing(format!("tracing the reference of {} at {}°", scene.name, angles[0]));
    let mut preps: Vec<Option<Prepared>> = angles.iter().map(|_| None).collect();
    let mut cells: Vec<Cell> = Vec::new();
    let mut hits: HashMap<Pipeline, Vec<GpuHit>> = HashMap::new();
    let pairs = crate::sweep::pairs(opts.frames);
    let found =
        search(&fams.iter().map(|f| f.pipelines.len()).collect::<Vec<_>>(), angles.len(), budget, &mut |f, i, v| {
            let p = &fams[f].pipelines[i];
            let angle = angles[v];
            bar.set_message(format!("{p} at {angle}°"));
            if preps[v].is_none() {
                let s = Overrides { angle: Some(angle), ..Default::default() }.apply(scene.clone());
                preps[v] = Some(Prepared::new(&gpu, s, opts.size)?);
            }
            let prep = preps[v].as_mut().expect("prepared above");
            let cell = if v == 0 {
                let m = measure_paired_against(&gpu, prep, p, BEVY_DEFAULT, opts.warmup, pairs)?;
                let speed = Ratio::to_baseline(&m.metrics);
                let c = Cell {
                    pipeline: m.metrics.pipeline.clone(),
                    angle,
                    err: m.metrics.ref_err_t_rms,
                    skipped: m.metrics.skipped_rate,
                    speed,
                };
                if c.reaches(opts.error) {
                    hits.insert(c.pipeline.clone(), m.hits);
                }
                c
            } else {
                let m = measure_accuracy(&gpu, prep, p)?;
                Cell { pipeline: m.pipeline.clone(), angle, err: m.ref_err_t_rms, skipped: m.skipped_rate, speed: None }
            };
            bar.inc();
            let o = Outcome { reaches: cell.reaches(opts.error), speed: cell.speed.map_or(f64::NAN, |s| s.ratio) };
            cells.push(cell);
            Ok(o)
        })?;
    bar.finish();
    debug_assert_eq!(found.measured, cells.len());
    let pick = found.best.map(|(f, i)| preps[0].as_ref().expect("measured").scene.pipeline_for(&fams[f].pipelines[i]));
    let mut candidates: Vec<Candidate> = Vec::new();
    for c in cells.iter().filter(|c| c.angle == angles[0] && c.reaches(opts.error)) {
        let Some(speed) = c.speed else { continue };
        let others: Vec<&Cell> = cells.iter().filter(|d| d.pipeline == c.pipeline && d.angle != angles[0]).collect();
        let checked = match others.iter().find(|d| !d.reaches(opts.error)) {
            Some(d) => Checked::Misses(d.angle),
            None if others.len() + 1 == angles.len() => Checked::Every,
            None => Checked::Slower,
        };
        let err = others.iter().map(|d| d.err).fold(c.err, f64::max);
        candidates.push(Candidate { pipeline: c.pipeline.clone(), speed, err, checked, model_navi21: None });
    }
    candidates.sort_by(|a, b| a.speed.ratio.total_cmp(&b.speed.ratio));
    if let (Some(compiler), Some(prep)) = (&opts.gpu_cost, &preps[0]) {
        model(compiler, prep, &hits, &mut candidates);
    }
    Ok(Tuned {
        scene: scene.name.clone(),
        error: opts.error,
        size: opts.size,
        angles,
        cells,
        grid_cells,
        budget,
        pick,
        candidates,
        open: found.open.iter().map(|&f| fams[f].name.clone()).collect(),
        adapter,
    })
}

/// The runners-up the answer shows besides the pick.
pub const RUNNERS_UP: usize = 4;

/// The GPU compiler's modeled instructions per pixel on RDNA2 for the pick and the
/// runners-up shown (the first candidates), from the hardest view's probe; left empty where
/// the compiler cannot price them (no RADV).
fn model(
    compiler: &crate::cost::Compiler,
    prep: &Prepared,
    hits: &HashMap<Pipeline, Vec<GpuHit>>,
    cands: &mut [Candidate],
) {
    let shown = cands.len().min(RUNNERS_UP + 1);
    let pipelines: Vec<Pipeline> = cands[..shown].iter().map(|c| c.pipeline.clone()).collect();
    let Ok(each) = compiler.cost_each(&pipelines, &["navi21".to_string()], false) else { return };
    for (c, costs) in cands[..shown].iter_mut().zip(each) {
        if let (Ok(costs), Some(h)) = (costs, hits.get(&c.pipeline)) {
            let navi21 = costs.iter().find(|cost| cost.family == "navi21");
            c.model_navi21 = navi21.map(|cost| crate::cost::modeled(cost, &prep.rays, h).instr_px);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_frontier_falls_into_twelve_families_ordered_by_steps() {
        let f = families();
        assert_eq!(f.len(), 12, "{:?}", f.iter().map(|f| &f.name).collect::<Vec<_>>());
        assert_eq!(f.iter().map(|f| f.pipelines.len()).sum::<usize>(), 54);
        for fam in &f {
            let s: Vec<u32> = fam.pipelines.iter().map(steps).collect();
            assert!(s.windows(2).all(|w| w[0] < w[1]), "{}: {s:?}", fam.name);
        }
        assert!(f.iter().any(|fam| fam.pipelines.iter().any(|p| p.to_string() == BEVY_DEFAULT)));
    }

    /// A synthetic grid: family f's step i reaches the goal at view v from `need[f][v]` on and
    /// costs `cost[f] * 2^i`. The search must find the true optimum (by exhaustion) within
    /// its budget, for every goal the table makes.
    #[test]
    fn the_search_finds_the_exhaustive_optimum_within_a_quarter_of_the_cells() {
        let sizes = [6usize, 6, 6, 4, 4, 4, 4, 4, 4, 4, 4, 4];
        let mut rng = 7u64;
        let mut next = |n: u64| {
            rng = rng.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (rng >> 33) % n
        };
        for trial in 0..300 {
            let views = 2 + (trial % 2);
            let need: Vec<Vec<usize>> = sizes
                .iter()
                .map(|&n| {
                    // The hardest view needs the most steps; n + 1 means never.
                    let h = next(n as u64 + 2) as usize;
                    (0..views).map(|v| if v == 0 { h } else { h.saturating_sub(next(2) as usize) }).collect()
                })
                .collect();
            let cost: Vec<f64> = sizes.iter().map(|_| 0.5 + next(100) as f64 / 50.0).collect();
            let speed = |f: usize, i: usize| cost[f] * 2f64.powi(i as i32);
            let truth = (0..sizes.len())
                .flat_map(|f| (0..sizes[f]).map(move |i| (f, i)))
                .filter(|&(f, i)| need[f].iter().all(|&k| i >= k))
                .min_by(|a, b| speed(a.0, a.1).total_cmp(&speed(b.0, b.1)));
            let budget = 54 * views / 4;
            let mut calls = 0;
            let found = search(&sizes, views, budget, &mut |f, i, v| {
                calls += 1;
                Ok(Outcome { reaches: i >= need[f][v], speed: if v == 0 { speed(f, i) } else { f64::NAN } })
            })
            .unwrap();
            assert_eq!(found.measured, calls);
            assert!(calls <= budget);
            if found.open.is_empty() {
                assert_eq!(found.best, truth, "trial {trial}: need {need:?}, cost {cost:?}");
            } else {
                // A budget that ran out: the best found is still a true solution.
                if let Some((f, i)) = found.best {
                    assert!(need[f].iter().all(|&k| i >= k));
                }
            }
        }
    }
}
