//! The answer first: for each scene, view and frame size in the results, the fastest
//! pipeline at each accuracy level, and the fastest of the engine family at the same level
//! with the ratio of their frame times ("unreachable" where a family never gets there).
//!
//! What competes is what the sweep measured: every ok row of a search pipeline (no shadow
//! or AO stage, which add shading cost, not search accuracy) sampling level 0 without a
//! silhouette option (rows under another `lod` are scored against another surface, and
//! `silhouette=clip` changes what counts as a hit). Accuracy is `ref_err_t_rms`, the RMS of
//! t − t_ref over the rays the exact reference hits (a non-finite hit counts as the whole
//! ray length, never as a skipped ray).

use relief_dsl::spec::{Lod, Silhouette, Value};
use relief_dsl::Pipeline;

use super::{
    data::short_scene, data::stage_steps, data::Data, text::fmt_ms, text::fmt_num, text::fmt_sci, text::TextTable,
};
use crate::results::Row;
use crate::timing::Ratio;

/// The engine family in words, as every part of the report names it.
pub(crate) const ENGINE_FAMILY: &str = "`linear_dynamic(1, N)` + `interval(1)` or `binary(k)`";

/// Whether `p` is in the engine family ([`ENGINE_FAMILY`]): the search game engines ship
/// (Bevy's default is `linear_dynamic(1, 16)+binary(5)`): linear search whose layer count
/// grows from one layer face-on to N at grazing angles (Tatarchuk 2006), refined by one
/// interval step or by k binary steps; no other stage or option.
pub(crate) fn is_engine_family(p: &Pipeline) -> bool {
    p.coarse.name == "linear_dynamic"
        && p.coarse.get("min") == Some(&Value::Int(1))
        && (p.refine.name == "binary" || (p.refine.name == "interval" && stage_steps(&p.refine) == 1))
        && competes(p)
}

/// Whether a row of `p` competes in the answer (see the module docs).
fn competes(p: &Pipeline) -> bool {
    p.shadow.is_none() && p.ao.is_none() && p.lod == Lod::Zero && p.silhouette == Silhouette::None
}

/// An accuracy level of the answer table.
pub(crate) struct Level {
    /// How the table names it.
    pub name: &'static str,
    /// Whether a row reaches it.
    pub reached: fn(&Row) -> bool,
    /// Whether it is an RMS level, named by its bound; where it is not ([`SKIPS_NONE`], whose
    /// bound is looser than the level before it), the overview shows the pick's t error beside it.
    pub bounds_error: bool,
}

/// What the last level, [`SKIPS_NONE`], is called.
pub(crate) const SKIPS_NONE: &str = "skips no geometry and t error ≤ 1e-2 (skipped_rate = 0)";

/// The t error the last level, [`SKIPS_NONE`], asks for besides skipping nothing: RMS t error
/// at most 1e-2. A search that stops early skips nothing (it halts above the surface or in the
/// first bump it meets) yet lands short by a large t: in the main job the rows that won a level
/// of skipping alone had RMS t errors of 0.04 to 0.22 (a few coarse steps of a safe or relaxed
/// search). 1e-2 keeps them out by a factor of four, where 3e-2 would sit next to the smallest
/// of them, and it is the answer's own second level: a row at this level lands as close as that
/// level asks and steps over nothing.
pub(crate) const SKIPS_NONE_MAX_ERR: f64 = 1e-2;

/// The accuracy levels: the RMS t error at most 3e-2, 1e-2, 1e-3 and 1e-6, coarsest first,
/// then [`SKIPS_NONE`]: no ray of the row jumped over geometry (`skipped_rate` exactly 0;
/// a NaN share never reaches it) and the RMS t error at most [`SKIPS_NONE_MAX_ERR`], so that a
/// search that stops early (skipping nothing, landing far short) does not win it. A row with a
/// small RMS can still step over a ridge on a few rays, which this level alone shows.
pub(crate) fn levels() -> Vec<Level> {
    vec![
        Level { name: "t error ≤ 3e-2", reached: |r| r.metrics.ref_err_t_rms <= 3e-2, bounds_error: true },
        Level { name: "t error ≤ 1e-2", reached: |r| r.metrics.ref_err_t_rms <= 1e-2, bounds_error: true },
        Level { name: "t error ≤ 1e-3", reached: |r| r.metrics.ref_err_t_rms <= 1e-3, bounds_error: true },
        Level { name: "t error ≤ 1e-6", reached: |r| r.metrics.ref_err_t_rms <= 1e-6, bounds_error: true },
        Level {
            name: SKIPS_NONE,
            reached: |r| r.metrics.skipped_rate == 0.0 && r.metrics.ref_err_t_rms <= SKIPS_NONE_MAX_ERR,
            bounds_error: false,
        },
    ]
}

/// How fast a row is, as the answer ranks it: its frame time over the baseline's, timed in
/// alternating blocks in the row's own run, with its 95 % interval ([`Ratio::to_baseline`]),
/// when every competing row of the answer has one to one baseline; else the median frame
/// time of the row's one run, a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Speed {
    /// The median frame time in ms (shown; it ranks only without paired timing).
    pub ms: f64,
    /// The paired ratio to the baseline, when the answer ranks by it.
    pub paired: Option<Ratio>,
}

impl Speed {
    /// What ranks: smaller is faster.
    pub(crate) fn rank(&self) -> f64 {
        self.paired.map_or(self.ms, |r| r.ratio)
    }

    /// `self`'s frame time over `other`'s: the quotient of the two paired ratios with its
    /// interval ([`Ratio::over`]; the baseline cancels), or the quotient of the medians as a
    /// point when either was timed alone.
    pub(crate) fn over(&self, other: &Speed) -> Ratio {
        match (self.paired, other.paired) {
            (Some(a), Some(b)) => a.over(&b),
            _ => Ratio::point(self.ms / other.ms),
        }
    }
}

/// Whether a ratio of two frame times leaves open which is faster: its 95 % interval reaches
/// 1. A point (no interval) never does.
pub(crate) fn undecided(r: &Ratio) -> bool {
    r.lo.is_finite() && r.hi.is_finite() && r.lo <= 1.0 && 1.0 <= r.hi
}

/// `1.33×`, `1.33× [1.20, 1.47]`, or `not decided: 1.05× [0.97, 1.14]` where the interval
/// reaches 1 (the two cannot be told apart in this run).
pub(crate) fn fmt_times(r: &Ratio) -> String {
    if !(r.lo.is_finite() && r.hi.is_finite()) {
        return format!("{}×", fmt_num(r.ratio, 2));
    }
    let body = format!("{}× [{}, {}]", fmt_num(r.ratio, 2), fmt_num(r.lo, 2), fmt_num(r.hi, 2));
    if undecided(r) {
        format!("not decided: {body}")
    } else {
        body
    }
}

/// How an answer's rows are timed.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Clock {
    /// Every competing row has a paired ratio to this baseline.
    Paired(String),
    /// Median frame times of one run each.
    Median,
}

impl Clock {
    /// What the answer ranks by, in the table's words.
    pub(crate) fn name(&self) -> &'static str {
        match self {
            Clock::Paired(_) => RATIO_NAME,
            Clock::Median => SPEED_NAME,
        }
    }
}

/// A median frame time, in the table's words.
pub(crate) const SPEED_NAME: &str = "frame ms (median)";
/// A paired ratio to the baseline, in the table's words.
pub(crate) const RATIO_NAME: &str = "frame ÷ baseline (95 %)";

/// One competing row.
pub(crate) struct Cand {
    pub pipeline: String,
    pub speed: Speed,
    pub err: f64,
    /// `skipped_rate`: rays that jumped over geometry.
    pub skipped: f64,
    pub engine: bool,
    pub cell_dir: String,
}

/// The picks at one level: indices into [`Answer::cands`].
pub(crate) struct Pick {
    pub best: Option<usize>,
    pub engine: Option<usize>,
    /// The other rows that reach the level and cannot be told apart from `best` in this run
    /// (their frame time over its has an interval that reaches 1), fastest first: under
    /// paired timing "the fastest" is one of these as much as `best`.
    pub ties: Vec<usize>,
}

/// The answer for one scene (with its view) and size.
pub(crate) struct Answer {
    /// The scene label (`scene:rocks@angle=70`).
    pub scene: String,
    pub size: u32,
    /// `rocks, 70°, 256²`.
    pub title: String,
    /// An HTML id for its section.
    pub id: String,
    /// The competing rows, fastest first.
    pub cands: Vec<Cand>,
    /// Whether any engine-family row was measured here.
    pub engine_measured: bool,
    /// How the rows are timed (what "fastest" ranks by).
    pub clock: Clock,
    /// One per [`levels`].
    pub picks: Vec<Pick>,
    /// Competing rows left out because their error or frame time is not a finite number.
    pub not_finite: Vec<String>,
    /// The adapters of the rows.
    pub adapters: Vec<String>,
}

impl Answer {
    /// The fastest exact row (t error ≤ 1e-6 and no ray that skipped geometry), else the most accurate.
    pub(crate) fn exact_or_best(&self) -> Option<&Cand> {
        self.cands.iter().find(|c| c.err <= 1e-6 && c.skipped == 0.0).or_else(|| {
            self.cands.iter().min_by(|a, b| a.err.total_cmp(&b.err).then(a.speed.rank().total_cmp(&b.speed.rank())))
        })
    }
}

/// The view of a scene label in words: `70°` from the label's own angle, else the angle of
/// the scene's camera (loaded), plus any other override it names.
fn view_words(label: &str) -> (String, String) {
    let (base, view) = match crate::scene::file::split_view(label) {
        Some((base, Ok(v))) => (base.to_string(), Some(v)),
        _ => (label.to_string(), None),
    };
    let mut parts = Vec::new();
    let angle =
        view.and_then(|v| v.angle).or_else(|| crate::scene::scene_from_arg(&base).ok().map(|s| s.camera.angle_deg));
    if let Some(a) = angle {
        parts.push(format!("{a}°"));
    }
    if let Some(v) = view {
        if let Some(z) = v.azimuth {
            parts.push(format!("azimuth {z}°"));
        }
        if let Some(d) = v.depth_scale {
            parts.push(format!("depth scale {d}"));
        }
        if let Some(t) = v.tiling {
            parts.push(format!("tiling {t}"));
        }
    }
    (short_scene(&base).to_string(), parts.join(", "))
}

/// Every answer, scenes where the engine family was measured first, then in first-seen order.
pub(crate) fn build(data: &Data) -> Vec<Answer> {
    let mut out = Vec::new();
    for scene in data.scenes() {
        for size in data.sizes_of(&scene) {
            let rows: Vec<(&Row, &Pipeline)> = data
                .rows
                .iter()
                .filter(|r| {
                    r.status.is_ok() && r.metrics.scene == scene && r.metrics.size == size && data.is_indexed(r)
                })
                .map(|r| (r, &r.metrics.pipeline))
                .filter(|(_, p)| competes(p))
                .collect();
            let clock = clock_of(rows.iter().map(|(r, _)| *r));
            let mut cands = Vec::new();
            let mut not_finite = Vec::new();
            let mut adapters: Vec<String> = Vec::new();
            for (r, p) in rows {
                let speed = Speed {
                    ms: r.metrics.frame_ms_median,
                    paired: if clock == Clock::Median { None } else { Ratio::to_baseline(&r.metrics) },
                };
                if !(speed.rank().is_finite() && r.metrics.ref_err_t_rms.is_finite()) {
                    not_finite.push(r.metrics.pipeline.to_string());
                    continue;
                }
                if !adapters.contains(&r.metrics.adapter) {
                    adapters.push(r.metrics.adapter.clone());
                }
                cands.push(Cand {
                    pipeline: r.metrics.pipeline.to_string(),
                    speed,
                    err: r.metrics.ref_err_t_rms,
                    skipped: r.metrics.skipped_rate,
                    engine: is_engine_family(p),
                    cell_dir: r.cell_dir.clone(),
                });
            }
            if cands.is_empty() && not_finite.is_empty() {
                continue;
            }
            cands.sort_by(|a, b| a.speed.rank().total_cmp(&b.speed.rank()).then(a.err.total_cmp(&b.err)));
            let row_of = |c: &Cand| data.ok(&c.pipeline, &scene, size);
            let picks = levels()
                .iter()
                .map(|l| {
                    let reached = |c: &&Cand| row_of(c).is_some_and(|r| (l.reached)(r));
                    let best = cands.iter().position(|c| reached(&c));
                    let ties = match best {
                        Some(b) => (0..cands.len())
                            .filter(|&i| {
                                i != b && reached(&&cands[i]) && undecided(&cands[i].speed.over(&cands[b].speed))
                            })
                            .collect(),
                        None => Vec::new(),
                    };
                    Pick { best, engine: cands.iter().position(|c| c.engine && reached(&c)), ties }
                })
                .collect();
            let (base, view) = view_words(&scene);
            let title = if view.is_empty() { format!("{base}, {size}²") } else { format!("{base}, {view}, {size}²") };
            out.push(Answer {
                id: format!("answer-{}", super::text::anchor(&format!("{scene} s{size}"))),
                engine_measured: cands.iter().any(|c| c.engine),
                clock: clock.clone(),
                scene: scene.clone(),
                size,
                title,
                cands,
                picks,
                not_finite,
                adapters,
            });
        }
    }
    out.sort_by_key(|a| !a.engine_measured);
    out
}

/// How the rows of one answer are timed: by their paired ratios when every one has a ratio
/// to the same baseline (ratios to different baselines, or a row timed alone, do not
/// compare), by median frame times otherwise.
fn clock_of<'a>(rows: impl Iterator<Item = &'a Row>) -> Clock {
    let mut base: Option<&str> = None;
    for r in rows {
        let m = &r.metrics;
        if m.frame_ratio_to_baseline.is_none() || m.baseline.is_empty() || base.is_some_and(|b| b != m.baseline) {
            return Clock::Median;
        }
        base = Some(&m.baseline);
    }
    base.map_or(Clock::Median, |b| Clock::Paired(b.to_string()))
}

/// A row's ratio to the baseline as the tables print it, `—` without one.
fn fmt_paired(c: &Cand) -> String {
    match c.speed.paired {
        Some(r) if r.lo.is_finite() && r.hi.is_finite() => {
            format!("{} [{}, {}]", fmt_num(r.ratio, 3), fmt_num(r.lo, 3), fmt_num(r.hi, 3))
        }
        Some(r) => fmt_num(r.ratio, 3),
        None => "—".into(),
    }
}

/// The engine family's column at one level: its fastest pipeline, or why there is none.
fn engine_cell(a: &Answer, pick: &Pick) -> [String; 4] {
    match pick.engine {
        Some(j) => {
            let e = &a.cands[j];
            [format!("`{}`", e.pipeline), fmt_ms(e.speed.ms), fmt_paired(e), fmt_sci(e.err)]
        }
        None if a.engine_measured => ["unreachable".into(), String::new(), String::new(), String::new()],
        None => ["not measured".into(), String::new(), String::new(), String::new()],
    }
}

/// The ratio of the engine family's frame time to the fastest's at one level: with its
/// 95 % interval under paired timing, "not decided" where that interval reaches 1.
pub(crate) fn ratio_cell(a: &Answer, pick: &Pick) -> String {
    match (pick.best, pick.engine) {
        (Some(b), Some(e)) if b == e => "1× (the fastest is in the family)".into(),
        (Some(b), Some(e)) => fmt_times(&a.cands[e].speed.over(&a.cands[b].speed)),
        (Some(_), None) if a.engine_measured => "family unreachable".into(),
        (Some(_), None) => "family not measured".into(),
        (None, _) => "unreachable".into(),
    }
}

/// The rows not told apart from the fastest at one level: `—`, or up to `most` pipelines
/// and how many more.
pub(crate) fn ties_cell(a: &Answer, pick: &Pick, most: usize) -> String {
    if pick.ties.is_empty() {
        return "—".into();
    }
    let mut s =
        pick.ties.iter().take(most).map(|&i| format!("`{}`", a.cands[i].pipeline)).collect::<Vec<_>>().join(", ");
    if pick.ties.len() > most {
        s.push_str(&format!(" and {} more", pick.ties.len() - most));
    }
    s
}

/// The detailed table of one answer.
pub(crate) fn table(a: &Answer) -> TextTable {
    let mut rows = Vec::new();
    for (l, pick) in levels().iter().zip(&a.picks) {
        let best = match pick.best {
            Some(i) => {
                let c = &a.cands[i];
                [format!("`{}`", c.pipeline), fmt_ms(c.speed.ms), fmt_paired(c), fmt_sci(c.err), fmt_num(c.skipped, 4)]
            }
            None => ["unreachable".into(), String::new(), String::new(), String::new(), String::new()],
        };
        let mut row = vec![l.name.to_string()];
        row.extend(best);
        row.extend(engine_cell(a, pick));
        row.push(ratio_cell(a, pick));
        row.push(ties_cell(a, pick, 4));
        rows.push(row);
    }
    let timing = match &a.clock {
        Clock::Paired(base) => format!(
            "speed: each row's mean frame time over the baseline `{base}`'s, timed in alternating blocks in the row's own run \
             ({RATIO_NAME}); the family's ratio to the fastest is the quotient of the two with its 95 % interval, \
             and the verdict is not decided where that interval reaches 1; the last column names the rows \
             reaching the level whose quotient to the fastest reaches 1, any of which may be the fastest in another run"
        ),
        Clock::Median => format!("speed: {SPEED_NAME} of one run (no paired timing), so a ratio near 1 is within the noise"),
    };
    let mut notes = vec![format!(
        "{} competing rows ({} of the engine family, {ENGINE_FAMILY}){}. Accuracy: `ref_err_t_rms`; {timing}. \
         The ratio is the family's frame time over the fastest's. The last level asks for no ray \
         that skipped geometry and an RMS t error ≤ 1e-2: a search that stops early skips nothing \
         yet lands far short of the hit.",
        a.cands.len(),
        a.cands.iter().filter(|c| c.engine).count(),
        if a.adapters.is_empty() { String::new() } else { format!(" on {}", a.adapters.join("; ")) },
    )];
    if !a.not_finite.is_empty() {
        notes.push(format!(
            "Left out, their error or frame time is not a finite number: {}.",
            a.not_finite.iter().map(|p| format!("`{p}`")).collect::<Vec<_>>().join(", ")
        ));
    }
    TextTable {
        title: format!("Fastest at each accuracy: {}", a.title),
        notes,
        header: [
            "accuracy",
            "fastest pipeline",
            SPEED_NAME,
            RATIO_NAME,
            "ref_err_t_rms",
            "skipped_rate",
            "fastest of the engine family",
            SPEED_NAME,
            RATIO_NAME,
            "ref_err_t_rms",
            "family ÷ fastest",
            "not told apart from the fastest (95 %)",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect(),
        rows,
    }
}

/// The indices of the rows among `cands` (fastest first) that no faster row beats in error:
/// a Pareto front over speed and t error, the report's one front ([`super::pareto::front`]).
fn front(cands: &[Cand], keep: impl Fn(&Cand) -> bool) -> Vec<usize> {
    let kept: Vec<usize> = (0..cands.len()).filter(|&i| keep(&cands[i])).collect();
    let points: Vec<(f64, f64)> = kept.iter().map(|&i| (cands[i].speed.rank(), cands[i].err)).collect();
    super::pareto::front(&points).into_iter().map(|k| kept[k]).collect()
}

/// An answer's chart: the file and the key of its numbered points.
pub(crate) struct AnswerChart {
    /// Relative to the sweep folder.
    pub file: String,
    /// The numbered points, by number.
    pub key: Vec<Keyed>,
    pub note: Option<String>,
}

/// A numbered point of an answer's chart.
pub(crate) struct Keyed {
    pub number: usize,
    /// Index into the answer's rows.
    pub cand: usize,
    /// On the overall front / on the engine family's front.
    pub on_all: bool,
    pub on_family: bool,
    /// Whether its number is drawn (a number with no room left is only in the key).
    pub drawn: bool,
}

/// Writes the chart of an answer under `sub`: every competing row faint, the engine
/// family's rows in colour, the Pareto front as a staircase; the points of either front carry
/// numbers (placed so that none overlaps another), keyed beside the chart.
pub(crate) fn write_chart(a: &Answer, sub: &std::path::Path, warnings: &mut Vec<String>) -> Option<AnswerChart> {
    use super::charts::{svg_chart_axes, Line, Pt, Series};
    if a.cands.is_empty() {
        return None;
    }
    let all = front(&a.cands, |_| true);
    let fam = front(&a.cands, |c| c.engine);
    let mut numbered: Vec<usize> = all.iter().chain(&fam).copied().collect();
    numbered.sort_unstable();
    numbered.dedup();
    let mut key: Vec<Keyed> = numbered
        .iter()
        .enumerate()
        .map(|(k, &i)| Keyed {
            number: k + 1,
            cand: i,
            on_all: all.contains(&i),
            on_family: fam.contains(&i),
            drawn: false,
        })
        .collect();
    let number = |i: usize| numbered.iter().position(|&j| j == i).map(|k| (k + 1).to_string()).unwrap_or_default();
    let pt = |i: usize, label: String| Pt { x: a.cands[i].speed.rank(), y: a.cands[i].err, label };
    let mut series = vec![Series {
        name: "every competing row".into(),
        points: (0..a.cands.len()).map(|i| pt(i, String::new())).collect(),
        line: Line::None,
        faint: true,
    }];
    if a.engine_measured {
        series.push(Series {
            name: "engine family".into(),
            // Numbered here only when the overall front does not number it already.
            points: (0..a.cands.len())
                .filter(|&i| a.cands[i].engine)
                .map(|i| pt(i, if fam.contains(&i) && !all.contains(&i) { number(i) } else { String::new() }))
                .collect(),
            line: Line::None,
            faint: false,
        });
    }
    series.push(Series {
        name: "Pareto front".into(),
        points: all.iter().map(|&i| pt(i, number(i))).collect(),
        line: Line::Step,
        faint: false,
    });
    let chart = svg_chart_axes(
        &format!("Frame time against t error: {}", a.title),
        a.clock.name(),
        "ref_err_t_rms",
        &series,
        true,
    );
    let name = format!("answer_{}.svg", super::text::file_safe(&format!("{}_s{}", short_scene(&a.scene), a.size)));
    for k in key.iter_mut() {
        k.drawn = chart.labels.iter().any(|(text, _)| *text == k.number.to_string());
    }
    match std::fs::write(sub.join(&name), &chart.svg) {
        Ok(()) => Some(AnswerChart { file: format!("report/{name}"), key, note: chart.note }),
        Err(e) => {
            warnings.push(format!("cannot write {}: {e}", sub.join(&name).display()));
            None
        }
    }
}

/// The scene's height map as a grey PNG under `sub` (white = height 1, the top), scaled up
/// by whole texels to at least 256 pixels; `None` when the scene cannot be loaded (a file
/// that has moved) or the image cannot be written, with a warning for the latter.
pub(crate) fn write_height_map(scene: &str, sub: &std::path::Path, warnings: &mut Vec<String>) -> Option<String> {
    let base = match crate::scene::file::split_view(scene) {
        Some((b, _)) => b,
        None => scene,
    };
    let s = crate::scene::scene_from_arg(base).ok()?;
    let m = &s.height;
    if m.width == 0 || m.height == 0 {
        return None;
    }
    let k = 256usize.div_ceil(m.width.max(m.height)).max(1);
    let img = image::GrayImage::from_fn((m.width * k) as u32, (m.height * k) as u32, |x, y| {
        let v = m.data[(y as usize / k) * m.width + x as usize / k];
        image::Luma([(v.clamp(0.0, 1.0) * 255.0).round() as u8])
    });
    let name = format!("scene_{}.png", super::text::file_safe(short_scene(base)));
    let path = sub.join(&name);
    if !path.exists() {
        if let Err(e) = img.save(&path) {
            warnings.push(format!("cannot write {}: {e}", path.display()));
            return None;
        }
    }
    Some(format!("report/{name}"))
}

/// The answers in Markdown, for `tables.md`.
pub(crate) fn to_markdown(answers: &[Answer]) -> String {
    let mut md = String::from("## The answer: fastest pipeline at each accuracy\n\n");
    if answers.is_empty() {
        md.push_str("No ok row of a search pipeline.\n\n");
    }
    md.push_str(&format!("Engine family: {ENGINE_FAMILY}.\n\n"));
    for a in answers {
        md.push_str(&table(a).to_markdown(3));
    }
    md
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_engine_family_is_linear_dynamic_from_one_layer_with_interval_1_or_binary() {
        let yes =
            ["linear_dynamic(1, 16)+binary(5)", "linear_dynamic(1, 256)+interval(1)", "linear_dynamic(1, 8)+binary(8)"];
        let no = [
            "linear_dynamic(8, 32)+binary(5)",
            "linear_dynamic(1, 16)+interval(2)",
            "linear_dynamic(1, 16)",
            "linear(16)+binary(5)",
            "linear_dynamic(1, 16)+binary(5)+shadow=hard(8)",
            "linear_dynamic(1, 16)+binary(5)+lod=auto",
        ];
        for p in yes {
            assert!(is_engine_family(&p.parse().unwrap()), "{p}");
        }
        for p in no {
            assert!(!is_engine_family(&p.parse().unwrap()), "{p}");
        }
    }

    #[test]
    fn the_family_over_the_fastest_is_the_quotient_of_their_paired_ratios() {
        let paired = |ratio: f64, lo: f64, hi: f64| Speed { ms: 9.0, paired: Some(Ratio { ratio, lo, hi, pairs: 15 }) };
        // Both to one baseline: 1.5 / 1.0, and the interval of the quotient is wider than
        // either's: the log half-widths add in quadrature.
        let (fast, slow) = (paired(1.0, 0.98, 1.02), paired(1.5, 1.47, 1.53));
        let q = slow.over(&fast);
        assert!((q.ratio - 1.5).abs() < 1e-12);
        let half = |r: &Ratio| (r.hi / r.lo).ln() / 2.0;
        assert!(half(&q) > half(&Ratio { ratio: 1.5, lo: 1.47, hi: 1.53, pairs: 15 }));
        assert!(fmt_times(&q).starts_with("1.50× ["), "{}", fmt_times(&q));
        // Estimates 3 % apart with intervals of ±5 %: not decided.
        let close = slow.over(&paired(1.45, 1.38, 1.52));
        assert!(fmt_times(&close).starts_with("not decided: 1.03× ["), "{}", fmt_times(&close));
        // Timed alone: the medians' quotient, a point.
        let alone = |ms: f64| Speed { ms, paired: None };
        assert_eq!(fmt_times(&alone(2.0).over(&alone(1.5))), "1.33×");
    }
}
