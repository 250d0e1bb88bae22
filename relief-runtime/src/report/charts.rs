//! Charts like Figures 4.5 and 4.7–4.11 as plain SVG (no fonts or plotting library needed):
//! x = frame time (Figure 4.5: refinement steps), y = error on a log scale, one series per
//! method, points labelled with step counts; one chart per error metric.

use std::fmt::Write as _;
use std::path::Path;

use relief_dsl::Pipeline;

use super::labels::{self, Rect};
use super::{data::short_scene, data::stage_steps, data::Data, data::Metric};
use crate::sweep::grids;

/// A chart written under `report/`.
pub(crate) struct Chart {
    /// `f4.8`.
    pub figure: String,
    /// File name under `report/`.
    pub file: String,
    pub title: String,
    /// What the chart shows, including any clamping to the log floor.
    pub caption: String,
}

/// How a series is drawn.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum Line {
    /// Markers only.
    None,
    /// Markers joined in the given order.
    Poly,
    /// A staircase (a Pareto front): horizontal, then down.
    Step,
}

pub(crate) struct Pt {
    pub x: f64,
    pub y: f64,
    pub label: String,
}

pub(crate) struct Series {
    pub name: String,
    pub points: Vec<Pt>,
    pub line: Line,
    /// A faint series (drawn grey, under the others).
    pub faint: bool,
}

pub(crate) const FIGURES: [(&str, &str); 6] = [
    ("f4.5", "Figure 4.5: binary vs interval refinement after linear(10)"),
    ("f4.7", "Figure 4.7: CSM + 4 binary steps in each scene"),
    ("f4.8", "Figure 4.8: coarse searches without refinement"),
    ("f4.9", "Figure 4.9: coarse searches + 3 binary steps"),
    ("f4.10", "Figure 4.10: coarse searches + 3 interval steps"),
    ("f4.11", "Figure 4.11: linear vs CSM, without / binary(3) / interval(3)"),
];

/// Writes every figure's charts that has measured points.
pub(crate) fn write_all(data: &Data, sub: &Path, warnings: &mut Vec<String>) -> Vec<Chart> {
    let grids = grids::builtin(None);
    let mut out = Vec::new();
    for (fig, title) in FIGURES {
        let Some(grid) = grids.iter().find(|g| g.name == fig) else { continue };
        let mut pipelines: Vec<Pipeline> = Vec::new();
        for (p, _) in &grid.cells {
            if !pipelines.contains(p) {
                pipelines.push(p.clone());
            }
        }
        // One chart per size: points of different sizes are different measurements.
        let sizes = data.sizes();
        for &size in &sizes {
            let scenes: Vec<String> = data
                .scenes()
                .into_iter()
                .filter(|s| pipelines.iter().any(|p| data.ok(&p.to_string(), s, size).is_some()))
                .collect();
            if scenes.is_empty() {
                continue;
            }
            for metric in Metric::ALL {
                let (series, not_finite) = figure_series(fig, data, &pipelines, &scenes, size, metric);
                if series.iter().all(|s| s.points.is_empty()) && not_finite.is_empty() {
                    continue;
                }
                let xlabel = if fig == "f4.5" { "refinement steps" } else { "frame time, mean (ms)" };
                let size_part = if sizes.len() > 1 { format!(" ({size}²)") } else { String::new() };
                let chart_title = format!("{title}{size_part} — {}", metric.name());
                let ChartSvg { svg, note: clamp_note, .. } = svg_chart(&chart_title, xlabel, metric.name(), &series);
                let file = if sizes.len() > 1 {
                    format!("{fig}_s{size}_{}.svg", metric.name())
                } else {
                    format!("{fig}_{}.svg", metric.name())
                };
                if let Err(e) = std::fs::write(sub.join(&file), svg) {
                    warnings.push(format!("cannot write {}: {e}", sub.join(&file).display()));
                    continue;
                }
                let scenes_text = scenes.iter().map(|s| short_scene(s)).collect::<Vec<_>>().join(", ");
                let mut caption = format!(
                    "{}; y = {} (log scale); scene{} {scenes_text}; points labelled with {}.",
                    if fig == "f4.5" {
                        "x = refinement steps after linear(10)"
                    } else {
                        "x = mean frame time (the dissertation's measure)"
                    },
                    metric.name(),
                    if scenes.len() > 1 { "s" } else { "" },
                    if fig == "f4.5" { "refinement steps" } else { "coarse step counts" },
                );
                if let Some(n) = clamp_note {
                    caption.push(' ');
                    caption.push_str(&n);
                }
                if !not_finite.is_empty() {
                    caption.push_str(&format!(
                        " Not drawn, their error or frame time is not a finite number (a failure, not a skipped ray): {}.",
                        not_finite.join(", ")
                    ));
                }
                out.push(Chart { figure: fig.into(), file, title: chart_title, caption });
            }
            if fig != "f4.5" {
                if let Some(c) =
                    model_chart(fig, title, data, &pipelines, &scenes, size, sizes.len() > 1, sub, warnings)
                {
                    out.push(c);
                }
            }
        }
    }
    out
}

/// The figure with the SIMD cost model on x: `mse_dissertation_mean` against `simd32_fetches`
/// (the largest fetch count of a group of 32 rays, averaged over groups; [`crate::simd`]),
/// what a GPU whose time goes into fetches would spend, beside the chart against lavapipe's
/// frame time.
#[allow(clippy::too_many_arguments)]
fn model_chart(
    fig: &str,
    title: &str,
    data: &Data,
    pipelines: &[Pipeline],
    scenes: &[String],
    size: u32,
    multi_size: bool,
    sub: &Path,
    warnings: &mut Vec<String>,
) -> Option<Chart> {
    let metric = Metric::Mse;
    let (series, not_finite) = series_with(fig, data, pipelines, scenes, size, metric, |r| r.metrics.simd32_fetches);
    if series.iter().all(|s| s.points.is_empty()) {
        return None;
    }
    let size_part = if multi_size { format!(" ({size}²)") } else { String::new() };
    let chart_title = format!("{title}{size_part} — {} against the model's simd32_fetches", metric.name());
    let ChartSvg { svg, note: clamp_note, .. } = svg_chart(
        &chart_title,
        "simd32_fetches (model: largest fetch count of a 32-ray group)",
        metric.name(),
        &series,
    );
    let file = if multi_size {
        format!("{fig}_s{size}_model_simd32_fetches.svg")
    } else {
        format!("{fig}_model_simd32_fetches.svg")
    };
    if let Err(e) = std::fs::write(sub.join(&file), svg) {
        warnings.push(format!("cannot write {}: {e}", sub.join(&file).display()));
        return None;
    }
    let mut caption = format!(
        "Model: x = simd32_fetches, the largest texture-fetch count of a group of 32 rays (8 × 4 pixels) averaged over groups, \
         the cost of a GPU whose time goes into fetches; y = {} (log scale); scenes {}; points labelled with coarse step counts.",
        metric.name(),
        scenes.iter().map(|s| short_scene(s)).collect::<Vec<_>>().join(", ")
    );
    if let Some(n) = clamp_note {
        caption.push(' ');
        caption.push_str(&n);
    }
    if !not_finite.is_empty() {
        caption.push_str(&format!(
            " Not drawn, their error or model cost is not a finite number: {}.",
            not_finite.join(", ")
        ));
    }
    Some(Chart { figure: fig.into(), file, title: chart_title, caption })
}

/// The series of one figure at one size, and the points that could not be drawn.
fn figure_series(
    fig: &str,
    data: &Data,
    pipelines: &[Pipeline],
    scenes: &[String],
    size: u32,
    metric: Metric,
) -> (Vec<Series>, Vec<String>) {
    series_with(fig, data, pipelines, scenes, size, metric, |r| r.metrics.frame_ms_mean)
}

/// [`figure_series`] with `x_of` in place of the mean frame time.
fn series_with(
    fig: &str,
    data: &Data,
    pipelines: &[Pipeline],
    scenes: &[String],
    size: u32,
    metric: Metric,
    x_of: fn(&crate::results::Row) -> f64,
) -> (Vec<Series>, Vec<String>) {
    let mut not_finite = Vec::new();
    let multi = scenes.len() > 1;
    let mut series: Vec<Series> = Vec::new();
    // (series name, order key, point)
    let mut pts: Vec<(String, u32, Pt)> = Vec::new();
    for scene in scenes {
        for p in pipelines {
            let Some(r) = data.ok(&p.to_string(), scene, size) else { continue };
            let (y, ms) = (metric.of(r), x_of(r));
            if !y.is_finite() || (!ms.is_finite() && fig != "f4.5") {
                not_finite.push(format!("`{p}` on {}", short_scene(scene)));
                continue;
            }
            let sc = short_scene(scene);
            let (name, x, order, label) = match fig {
                "f4.5" => {
                    let k = stage_steps(&p.refine);
                    (format!("{} @ {sc}", p.refine.name), k as f64, k, k.to_string())
                }
                "f4.7" => {
                    let n = stage_steps(&p.coarse);
                    (sc.to_string(), ms, n, n.to_string())
                }
                "f4.11" => {
                    let n = stage_steps(&p.coarse);
                    let refine = if p.refine.is_none() { String::new() } else { format!("+{}", p.refine) };
                    let name =
                        format!("{}{refine}{}", p.coarse.name, if multi { format!(" @ {sc}") } else { String::new() });
                    (name, ms, n, n.to_string())
                }
                _ => {
                    let n = stage_steps(&p.coarse);
                    let name = format!("{}{}", p.coarse.name, if multi { format!(" @ {sc}") } else { String::new() });
                    (name, ms, n, n.to_string())
                }
            };
            pts.push((name, order, Pt { x, y, label }));
        }
    }
    let mut keyed: Vec<(String, Vec<(u32, Pt)>)> = Vec::new();
    for (name, order, pt) in pts {
        match keyed.iter_mut().find(|(n, _)| *n == name) {
            Some((_, v)) => v.push((order, pt)),
            None => keyed.push((name, vec![(order, pt)])),
        }
    }
    for (name, mut v) in keyed {
        // Points in step order.
        v.sort_by_key(|(o, _)| *o);
        series.push(Series { name, points: v.into_iter().map(|(_, p)| p).collect(), line: Line::Poly, faint: false });
    }
    (series, not_finite)
}

const PALETTE: [&str; 10] =
    ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf", "#bcbd22", "#7f7f7f"];

pub(crate) fn esc(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// A "nice" tick step for a range (1, 2 or 5 × 10^k).
fn nice_step(range: f64, ticks: f64) -> f64 {
    if !(range.is_finite() && range > 0.0) {
        return 1.0;
    }
    let raw = range / ticks;
    let mag = 10f64.powf(raw.log10().floor());
    let f = raw / mag;
    let m = if f <= 1.0 {
        1.0
    } else if f <= 2.0 {
        2.0
    } else if f <= 5.0 {
        5.0
    } else {
        10.0
    };
    m * mag
}

fn fmt_tick(v: f64, step: f64) -> String {
    let decimals = if step >= 1.0 { 0 } else { (-step.log10().floor()) as usize };
    format!("{v:.decimals$}")
}

/// A chart as drawn by [`svg_chart`].
pub(crate) struct ChartSvg {
    pub svg: String,
    /// What the reader must know about the drawing: values clamped to the log floor, labels
    /// left out for lack of room.
    pub note: Option<String>,
    /// Each point label drawn, with its box ([`super::labels`]): no two intersect.
    pub labels: Vec<(String, Rect)>,
}

/// Renders a chart with a log-scale y axis. Values at or below zero are drawn at a floor
/// (a tenth of the smallest positive value) with hollow markers; the note says so. Point
/// labels (non-faint series) are placed so that none overlaps another or a marker
/// ([`super::labels::place`]); one with no room is left out and the note counts it.
pub(crate) fn svg_chart(title: &str, xlabel: &str, ylabel: &str, series: &[Series]) -> ChartSvg {
    svg_chart_axes(title, xlabel, ylabel, series, false)
}

/// [`svg_chart`], with a log-scale x axis too when `log_x` (and every x is positive):
/// frame times that span two decades stay apart.
pub(crate) fn svg_chart_axes(title: &str, xlabel: &str, ylabel: &str, series: &[Series], log_x: bool) -> ChartSvg {
    let (w, h) = (860.0, 500.0);
    let (l, r, t, b) = (80.0, 640.0, 50.0, 440.0);
    let all: Vec<&Pt> = series.iter().flat_map(|s| &s.points).filter(|p| p.x.is_finite() && p.y.is_finite()).collect();
    let min_pos = all.iter().map(|p| p.y).filter(|y| *y > 0.0).fold(f64::INFINITY, f64::min);
    let max_y = all.iter().map(|p| p.y).fold(f64::NEG_INFINITY, f64::max);
    let any_clamped = all.iter().any(|p| p.y <= 0.0);
    let floor = if min_pos.is_finite() { min_pos / 10.0 } else { 1e-6 };
    let mut note = any_clamped.then(|| {
        format!(
            "{} value(s) ≤ 0 cannot be shown on a log scale and are drawn at the floor {floor:.1e} with hollow markers.",
            all.iter().filter(|p| p.y <= 0.0).count()
        )
    });
    let ylo = if any_clamped {
        floor
    } else if min_pos.is_finite() {
        min_pos
    } else {
        floor
    };
    let yhi = if max_y.is_finite() && max_y > 0.0 { max_y } else { floor * 10.0 };
    let mut d0 = ylo.log10().floor();
    let mut d1 = yhi.log10().ceil();
    if d1 <= d0 {
        d1 = d0 + 1.0;
    }
    if !d0.is_finite() || !d1.is_finite() {
        d0 = -6.0;
        d1 = 0.0;
    }
    let xmin = all.iter().map(|p| p.x).fold(f64::INFINITY, f64::min);
    let xmax = all.iter().map(|p| p.x).fold(f64::NEG_INFINITY, f64::max);
    let (mut x0, mut x1) = if xmin.is_finite() { (xmin, xmax) } else { (0.0, 1.0) };
    let pad = if x1 > x0 { (x1 - x0) * 0.06 } else { x0.abs().max(1.0) * 0.1 };
    x0 -= pad;
    x1 += pad;
    if x0 < 0.0 && xmin >= 0.0 {
        x0 = 0.0;
    }
    let log_x = log_x && xmin.is_finite() && xmin > 0.0;
    if log_x {
        (x0, x1) = (xmin / 1.15, xmax * 1.15);
    }
    let sx = |x: f64| {
        if log_x {
            l + (x.log10() - x0.log10()) / (x1.log10() - x0.log10()) * (r - l)
        } else {
            l + (x - x0) / (x1 - x0) * (r - l)
        }
    };
    let sy = |y: f64| {
        let v = if y > 0.0 { y.log10() } else { floor.log10() };
        b - (v - d0) / (d1 - d0) * (b - t)
    };

    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif" font-size="12">"#
    );
    let _ = writeln!(s, r#"<rect x="0" y="0" width="{w}" height="{h}" fill="white"/>"#);
    let _ =
        writeln!(s, r#"<text x="{}" y="24" text-anchor="middle" font-size="15">{}</text>"#, (l + r) / 2.0, esc(title));
    // Grid and y ticks.
    let decades = (d1 - d0) as i32;
    for k in 0..=decades {
        let d = d0 + k as f64;
        let y = b - (d - d0) / (d1 - d0) * (b - t);
        let _ = writeln!(s, r##"<line x1="{l}" y1="{y:.1}" x2="{r}" y2="{y:.1}" stroke="#ccc"/>"##);
        let _ = writeln!(s, r#"<text x="{}" y="{:.1}" text-anchor="end">1e{}</text>"#, l - 6.0, y + 4.0, d as i32);
        if k < decades && decades <= 8 {
            for m in 2..10 {
                let yy = b - (d + (m as f64).log10() - d0) / (d1 - d0) * (b - t);
                let _ = writeln!(s, r##"<line x1="{l}" y1="{yy:.1}" x2="{r}" y2="{yy:.1}" stroke="#eee"/>"##);
            }
        }
    }
    // X ticks.
    let mut ticks: Vec<(f64, String)> = Vec::new();
    if log_x {
        let (k0, k1) = (x0.log10().floor() as i32, x1.log10().ceil() as i32);
        let few = k1 - k0 <= 1;
        for k in k0..=k1 {
            let ms: &[f64] = if few { &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0] } else { &[1.0, 2.0, 5.0] };
            for m in ms {
                let v = m * 10f64.powi(k);
                if v >= x0 && v <= x1 {
                    ticks.push((v, fmt_tick(v, 10f64.powi(k))));
                }
            }
        }
    } else {
        let step = nice_step(x1 - x0, 7.0);
        let mut xv = (x0 / step).ceil() * step;
        while xv <= x1 + 1e-12 && ticks.len() < 100 {
            ticks.push((xv, fmt_tick(xv, step)));
            xv += step;
        }
    }
    for (xv, text) in &ticks {
        let x = sx(*xv);
        let _ = writeln!(s, r##"<line x1="{x:.1}" y1="{t}" x2="{x:.1}" y2="{b}" stroke="#eee"/>"##);
        let _ = writeln!(s, r#"<text x="{x:.1}" y="{}" text-anchor="middle">{text}</text>"#, b + 18.0);
    }
    let _ = writeln!(s, r#"<rect x="{l}" y="{t}" width="{}" height="{}" fill="none" stroke="black"/>"#, r - l, b - t);
    let xlabel = if log_x { format!("{xlabel} (log scale)") } else { xlabel.to_string() };
    let _ = writeln!(s, r#"<text x="{}" y="{}" text-anchor="middle">{}</text>"#, (l + r) / 2.0, b + 42.0, esc(&xlabel));
    let _ = writeln!(
        s,
        r#"<text x="18" y="{}" text-anchor="middle" transform="rotate(-90 18 {})">{} (log scale)</text>"#,
        (t + b) / 2.0,
        (t + b) / 2.0,
        esc(ylabel)
    );
    // Labels of the non-faint points, placed clear of each other and of every marker.
    let mut wants = Vec::new();
    let mut texts = Vec::new();
    let mut markers = Vec::new();
    for se in series.iter().filter(|s| !s.faint) {
        for p in se.points.iter().filter(|p| p.x.is_finite() && p.y.is_finite()) {
            markers.push(Rect::around(sx(p.x), sy(p.y), 8.0, 8.0));
            if !p.label.is_empty() {
                let (lw, lh) = labels::text_size(&p.label);
                wants.push(labels::Want { px: sx(p.x), py: sy(p.y), w: lw, h: lh });
                texts.push(p.label.clone());
            }
        }
    }
    let placed = labels::place(&wants, &markers, Rect { x: l, y: t, w: r - l, h: b - t });
    let unplaced = placed.iter().filter(|p| p.is_none()).count();
    if unplaced > 0 {
        let n = format!("{unplaced} point label(s) left out for lack of room (hover a point for its values).");
        note = Some(match note {
            Some(x) => format!("{x} {n}"),
            None => n,
        });
    }
    let mut label_at = placed.iter().zip(&wants).zip(&texts);
    let mut drawn_labels = Vec::new();
    // Series: faint first.
    let mut order: Vec<usize> = (0..series.len()).collect();
    order.sort_by_key(|&i| !series[i].faint);
    let mut color_i = 0;
    let mut legend = Vec::new();
    for i in order {
        let se = &series[i];
        let color = if se.faint {
            "#bbb"
        } else {
            let c = PALETTE[color_i % PALETTE.len()];
            color_i += 1;
            c
        };
        let pts: Vec<&Pt> = se.points.iter().filter(|p| p.x.is_finite() && p.y.is_finite()).collect();
        if pts.is_empty() {
            continue;
        }
        legend.push((se.name.clone(), color, se.line));
        match se.line {
            Line::Poly if pts.len() > 1 => {
                let coords: Vec<String> = pts.iter().map(|p| format!("{:.1},{:.1}", sx(p.x), sy(p.y))).collect();
                let _ = writeln!(
                    s,
                    r#"<polyline points="{}" fill="none" stroke="{color}" stroke-width="1.5"/>"#,
                    coords.join(" ")
                );
            }
            Line::Step if !pts.is_empty() => {
                let mut d = format!("M{:.1},{:.1}", sx(pts[0].x), sy(pts[0].y));
                for w in pts.windows(2) {
                    let _ = write!(d, " H{:.1} V{:.1}", sx(w[1].x), sy(w[1].y));
                }
                let _ = write!(d, " H{r}");
                let _ = writeln!(s, r#"<path d="{d}" fill="none" stroke="{color}" stroke-width="2"/>"#);
            }
            _ => {}
        }
        for p in &pts {
            let (x, y) = (sx(p.x), sy(p.y));
            let fill = if p.y > 0.0 { color } else { "white" };
            let _ = writeln!(
                s,
                r#"<circle cx="{x:.1}" cy="{y:.1}" r="{}" fill="{fill}" stroke="{color}" stroke-width="1.5"><title>{}: x {:.4}, y {:.4e}</title></circle>"#,
                if se.faint { 2.5 } else { 3.5 },
                esc(&format!("{} {}", se.name, p.label)),
                p.x,
                p.y
            );
            if !p.label.is_empty() && !se.faint {
                // Labels come in the order they were placed: series by series, point by point.
                if let Some(((Some(pl), want), text)) = label_at.next() {
                    let rc = pl.rect;
                    if pl.leader {
                        let (ex, ey) = rc.nearest(want.px, want.py);
                        let _ = writeln!(
                            s,
                            r#"<line x1="{:.1}" y1="{:.1}" x2="{ex:.1}" y2="{ey:.1}" stroke="{color}" stroke-width="0.7"/>"#,
                            want.px, want.py
                        );
                    }
                    let _ = writeln!(
                        s,
                        r#"<text x="{:.1}" y="{:.1}" font-family="monospace" font-size="{}" fill="{color}">{}</text>"#,
                        rc.x + (rc.w - text.chars().count() as f64 * labels::CHAR_W) / 2.0,
                        rc.y + rc.h / 2.0 + 0.35 * labels::FONT,
                        labels::FONT,
                        esc(text)
                    );
                    drawn_labels.push((text.clone(), rc));
                }
            }
        }
    }
    // Legend.
    for (k, (name, color, line)) in legend.iter().enumerate() {
        let y = t + 10.0 + k as f64 * 18.0;
        let lx = r + 20.0;
        if *line != Line::None {
            let _ = writeln!(
                s,
                r#"<line x1="{lx}" y1="{y}" x2="{}" y2="{y}" stroke="{color}" stroke-width="2"/>"#,
                lx + 22.0
            );
        }
        let _ = writeln!(s, r#"<circle cx="{}" cy="{y}" r="3.5" fill="{color}"/>"#, lx + 11.0);
        let _ = writeln!(s, r#"<text x="{}" y="{}">{}</text>"#, lx + 30.0, y + 4.0, esc(name));
    }
    if let Some(n) = &note {
        let _ = writeln!(s, r##"<text x="{l}" y="{}" font-size="10" fill="#555">{}</text>"##, h - 8.0, esc(n));
    }
    s.push_str("</svg>\n");
    ChartSvg { svg: s, note, labels: drawn_labels }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A chart whose points crowd one corner (the Pareto chart's usual case): every label it
    /// draws is clear of every other, and each is drawn once at its box.
    #[test]
    fn point_labels_never_overlap() {
        for log_x in [false, true] {
            let points: Vec<Pt> = (0..40)
                .map(|i| Pt {
                    x: 1.0 + (i % 7) as f64 * 0.01,
                    y: 0.1 / (1.0 + (i / 7) as f64 * 0.05),
                    label: format!("{}", i + 1),
                })
                .collect();
            let far = vec![Pt { x: 500.0, y: 1e-8, label: "far".into() }];
            let series = vec![
                Series { name: "crowd".into(), points, line: Line::Step, faint: false },
                Series { name: "far".into(), points: far, line: Line::None, faint: false },
            ];
            let c = svg_chart_axes("t", "x", "y", &series, log_x);
            assert!(c.labels.len() >= 30, "{} of 41 labels placed", c.labels.len());
            for (i, (ta, a)) in c.labels.iter().enumerate() {
                for (tb, b) in &c.labels[i + 1..] {
                    assert!(!a.intersects(b), "labels {ta} and {tb} overlap: {a:?} {b:?}");
                }
                assert!(c.svg.contains(&format!(">{ta}</text>")));
            }
            let left_out = 41 - c.labels.len();
            if left_out > 0 {
                assert!(
                    c.note.as_deref().unwrap_or("").contains(&format!("{left_out} point label(s) left out")),
                    "{:?}",
                    c.note
                );
            }
        }
    }
}
