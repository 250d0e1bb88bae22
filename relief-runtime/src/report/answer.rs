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

use super::{fmt_ms, fmt_num, fmt_sci, short_scene, stage_steps, Data, TextTable};
use crate::results::Row;

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
}

/// The accuracy levels, coarsest first. A "skips no geometry" level joins them once rows
/// record which rays jumped over geometry.
pub(crate) fn levels() -> Vec<Level> {
    vec![
        Level { name: "t error ≤ 3e-2", reached: |r| r.metrics.ref_err_t_rms <= 3e-2 },
        Level { name: "t error ≤ 1e-2", reached: |r| r.metrics.ref_err_t_rms <= 1e-2 },
        Level { name: "t error ≤ 1e-3", reached: |r| r.metrics.ref_err_t_rms <= 1e-3 },
        Level { name: "t error ≤ 1e-6", reached: |r| r.metrics.ref_err_t_rms <= 1e-6 },
    ]
}

/// How fast a row is, as the answer ranks it: today the median frame time of the row's one
/// run (`interval` none). A measure with a confidence interval (a paired ratio to a baseline)
/// goes here; two rows whose intervals overlap are then "not decided".
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Speed {
    /// What ranks: smaller is faster.
    pub value: f64,
    /// A 95 % interval of `value`, when the row has one.
    pub interval: Option<(f64, f64)>,
}

impl Speed {
    pub fn of(r: &Row) -> Speed {
        Speed { value: r.metrics.frame_ms_median, interval: None }
    }

    /// Whether the two speeds cannot be told apart: both have intervals and they overlap.
    pub fn undecided(&self, other: &Speed) -> bool {
        match (self.interval, other.interval) {
            (Some((a0, a1)), Some((b0, b1))) => a0 <= b1 && b0 <= a1,
            _ => false,
        }
    }
}

/// What the answer says a speed is, in the table's words.
pub(crate) const SPEED_NAME: &str = "frame ms (median)";

/// One competing row.
pub(crate) struct Cand {
    pub pipeline: String,
    pub speed: Speed,
    pub err: f64,
    pub missed: f64,
    pub engine: bool,
    pub cell_dir: String,
}

/// The picks at one level: indices into [`Answer::cands`].
pub(crate) struct Pick {
    pub best: Option<usize>,
    pub engine: Option<usize>,
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
    /// One per [`levels`].
    pub picks: Vec<Pick>,
    /// Competing rows left out because their error or frame time is not a finite number.
    pub not_finite: Vec<String>,
    /// The adapters of the rows.
    pub adapters: Vec<String>,
}

impl Answer {
    /// The fastest exact row (t error ≤ 1e-6 and no missed ray), else the most accurate.
    pub fn exact_or_best(&self) -> Option<&Cand> {
        self.cands
            .iter()
            .find(|c| c.err <= 1e-6 && c.missed == 0.0)
            .or_else(|| self.cands.iter().min_by(|a, b| a.err.total_cmp(&b.err).then(a.speed.value.total_cmp(&b.speed.value))))
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
    let angle = view.and_then(|v| v.angle).or_else(|| crate::scene::scene_from_arg(&base).ok().map(|s| s.camera.angle_deg));
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
            let mut cands = Vec::new();
            let mut not_finite = Vec::new();
            let mut adapters: Vec<String> = Vec::new();
            for r in data.rows.iter().filter(|r| r.status == "ok" && r.metrics.scene == scene && r.metrics.size == size && data.is_indexed(r)) {
                let Ok(p) = r.metrics.pipeline.parse::<Pipeline>() else { continue };
                if !competes(&p) {
                    continue;
                }
                let speed = Speed::of(r);
                if !(speed.value.is_finite() && r.metrics.ref_err_t_rms.is_finite()) {
                    not_finite.push(r.metrics.pipeline.clone());
                    continue;
                }
                if !adapters.contains(&r.metrics.adapter) {
                    adapters.push(r.metrics.adapter.clone());
                }
                cands.push(Cand {
                    pipeline: r.metrics.pipeline.clone(),
                    speed,
                    err: r.metrics.ref_err_t_rms,
                    missed: r.metrics.missed_rate,
                    engine: is_engine_family(&p),
                    cell_dir: r.cell_dir.clone(),
                });
            }
            if cands.is_empty() && not_finite.is_empty() {
                continue;
            }
            cands.sort_by(|a, b| a.speed.value.total_cmp(&b.speed.value).then(a.err.total_cmp(&b.err)));
            let row_of = |c: &Cand| data.ok(&c.pipeline, &scene, size);
            let picks = levels()
                .iter()
                .map(|l| {
                    let reached = |c: &&Cand| row_of(c).is_some_and(|r| (l.reached)(r));
                    Pick {
                        best: cands.iter().position(|c| reached(&c)),
                        engine: cands.iter().position(|c| c.engine && reached(&c)),
                    }
                })
                .collect();
            let (base, view) = view_words(&scene);
            let title = if view.is_empty() { format!("{base}, {size}²") } else { format!("{base}, {view}, {size}²") };
            out.push(Answer {
                id: format!("answer-{}", super::anchor(&format!("{scene} s{size}"))),
                engine_measured: cands.iter().any(|c| c.engine),
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

/// The engine family's column at one level: its fastest pipeline, or why there is none.
fn engine_cell(a: &Answer, pick: &Pick) -> (String, String, String) {
    match pick.engine {
        Some(j) => {
            let e = &a.cands[j];
            (format!("`{}`", e.pipeline), fmt_ms(e.speed.value), fmt_sci(e.err))
        }
        None if a.engine_measured => ("unreachable".into(), String::new(), String::new()),
        None => ("not measured".into(), String::new(), String::new()),
    }
}

/// The ratio of the engine family's frame time to the fastest's at one level.
pub(crate) fn ratio_cell(a: &Answer, pick: &Pick) -> String {
    match (pick.best, pick.engine) {
        (Some(b), Some(e)) if b == e => "1× (the fastest is in the family)".into(),
        (Some(b), Some(e)) => {
            let (b, e) = (&a.cands[b], &a.cands[e]);
            if b.speed.undecided(&e.speed) {
                "not decided (intervals overlap)".into()
            } else {
                format!("{}×", fmt_num(e.speed.value / b.speed.value, 2))
            }
        }
        (Some(_), None) if a.engine_measured => "family unreachable".into(),
        (Some(_), None) => "family not measured".into(),
        (None, _) => "unreachable".into(),
    }
}

/// The detailed table of one answer.
pub(crate) fn table(a: &Answer) -> TextTable {
    let mut rows = Vec::new();
    for (l, pick) in levels().iter().zip(&a.picks) {
        let (bp, bms, berr, bmiss) = match pick.best {
            Some(i) => {
                let c = &a.cands[i];
                (format!("`{}`", c.pipeline), fmt_ms(c.speed.value), fmt_sci(c.err), fmt_num(c.missed, 4))
            }
            None => ("unreachable".into(), String::new(), String::new(), String::new()),
        };
        let (ep, ems, eerr) = engine_cell(a, pick);
        rows.push(vec![l.name.to_string(), bp, bms, berr, bmiss, ep, ems, eerr, ratio_cell(a, pick)]);
    }
    let mut notes = vec![format!(
        "{} competing rows ({} of the engine family, {ENGINE_FAMILY}). Accuracy: `ref_err_t_rms`; speed: {SPEED_NAME} of one run{}, \
         so a ratio near 1 is within the noise. The ratio is the family's frame time over the fastest's.",
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
            "accuracy (RMS)",
            "fastest pipeline",
            SPEED_NAME,
            "ref_err_t_rms",
            "missed_rate",
            "fastest of the engine family",
            SPEED_NAME,
            "ref_err_t_rms",
            "family ÷ fastest",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect(),
        rows,
    }
}

/// The indices of the rows among `cands` (fastest first) that no faster row beats in error:
/// a Pareto front over frame time and t error.
fn front(cands: &[Cand], keep: impl Fn(&Cand) -> bool) -> Vec<usize> {
    let mut out: Vec<usize> = Vec::new();
    for (i, c) in cands.iter().enumerate().filter(|(_, c)| keep(c)) {
        if out.last().is_none_or(|&j| c.err < cands[j].err) {
            out.push(i);
        }
    }
    out
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
        .map(|(k, &i)| Keyed { number: k + 1, cand: i, on_all: all.contains(&i), on_family: fam.contains(&i), drawn: false })
        .collect();
    let number = |i: usize| numbered.iter().position(|&j| j == i).map(|k| (k + 1).to_string()).unwrap_or_default();
    let pt = |i: usize, label: String| Pt { x: a.cands[i].speed.value, y: a.cands[i].err, label };
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
            points: (0..a.cands.len()).filter(|&i| a.cands[i].engine).map(|i| pt(i, if fam.contains(&i) && !all.contains(&i) { number(i) } else { String::new() })).collect(),
            line: Line::None,
            faint: false,
        });
    }
    series.push(Series { name: "Pareto front".into(), points: all.iter().map(|&i| pt(i, number(i))).collect(), line: Line::Step, faint: false });
    let chart = svg_chart_axes(&format!("Frame time against t error: {}", a.title), SPEED_NAME, "ref_err_t_rms", &series, true);
    let name = format!("answer_{}.svg", super::file_safe(&format!("{}_s{}", short_scene(&a.scene), a.size)));
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
    let name = format!("scene_{}.png", super::file_safe(short_scene(base)));
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
        let yes = ["linear_dynamic(1, 16)+binary(5)", "linear_dynamic(1, 256)+interval(1)", "linear_dynamic(1, 8)+binary(8)"];
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
    fn speeds_with_overlapping_intervals_are_not_decided() {
        let a = Speed { value: 1.0, interval: Some((0.9, 1.1)) };
        let b = Speed { value: 1.2, interval: Some((1.05, 1.3)) };
        let c = Speed { value: 1.5, interval: Some((1.4, 1.6)) };
        assert!(a.undecided(&b) && b.undecided(&a));
        assert!(!a.undecided(&c));
        // One run, no interval: decided by the values (and said to be one run).
        let d = Speed { value: 1.0, interval: None };
        assert!(!d.undecided(&a));
    }
}
