//! Charts like Figures 4.5 and 4.7–4.11 as plain SVG (no fonts or plotting library needed):
//! x = frame time (Figure 4.5: refinement steps), y = error on a log scale, one series per
//! method, points labelled with step counts; one chart per error metric.

use std::fmt::Write as _;
use std::path::Path;

use relief_dsl::Pipeline;

use super::{short_scene, stage_steps, Data, Metric};
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
            let scenes: Vec<String> =
                data.scenes().into_iter().filter(|s| pipelines.iter().any(|p| data.ok(&p.to_string(), s, size).is_some())).collect();
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
                let (svg, clamp_note) = svg_chart(&chart_title, xlabel, metric.name(), &series);
                let file = if sizes.len() > 1 { format!("{fig}_s{size}_{}.svg", metric.name()) } else { format!("{fig}_{}.svg", metric.name()) };
                if let Err(e) = std::fs::write(sub.join(&file), svg) {
                    warnings.push(format!("cannot write {}: {e}", sub.join(&file).display()));
                    continue;
                }
                let scenes_text = scenes.iter().map(|s| short_scene(s)).collect::<Vec<_>>().join(", ");
                let mut caption = format!(
                    "{}; y = {} (log scale); scene{} {scenes_text}; points labelled with {}.",
                    if fig == "f4.5" { "x = refinement steps after linear(10)" } else { "x = mean frame time (the dissertation's measure)" },
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
                if let Some(c) = model_chart(fig, title, data, &pipelines, &scenes, size, sizes.len() > 1, sub, warnings) {
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
fn model_chart(fig: &str, title: &str, data: &Data, pipelines: &[Pipeline], scenes: &[String], size: u32, multi_size: bool, sub: &Path, warnings: &mut Vec<String>) -> Option<Chart> {
    let metric = Metric::Mse;
    let (series, not_finite) = series_with(fig, data, pipelines, scenes, size, metric, |r| r.metrics.simd32_fetches);
    if series.iter().all(|s| s.points.is_empty()) {
        return None;
    }
    let size_part = if multi_size { format!(" ({size}²)") } else { String::new() };
    let chart_title = format!("{title}{size_part} — {} against the model's simd32_fetches", metric.name());
    let (svg, clamp_note) = svg_chart(&chart_title, "simd32_fetches (model: largest fetch count of a 32-ray group)", metric.name(), &series);
    let file = if multi_size { format!("{fig}_s{size}_model_simd32_fetches.svg") } else { format!("{fig}_model_simd32_fetches.svg") };
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
        caption.push_str(&format!(" Not drawn, their error or model cost is not a finite number: {}.", not_finite.join(", ")));
    }
    Some(Chart { figure: fig.into(), file, title: chart_title, caption })
}

/// The series of one figure at one size, and the points that could not be drawn.
fn figure_series(fig: &str, data: &Data, pipelines: &[Pipeline], scenes: &[String], size: u32, metric: Metric) -> (Vec<Series>, Vec<String>) {
    series_with(fig, data, pipelines, scenes, size, metric, |r| r.metrics.frame_ms_mean)
}

/// [`figure_series`] with `x_of` in place of the mean frame time.
fn series_with(fig: &str, data: &Data, pipelines: &[Pipeline], scenes: &[String], size: u32, metric: Metric, x_of: fn(&crate::results::Row) -> f64) -> (Vec<Series>, Vec<String>) {
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
                    let name = format!("{}{refine}{}", p.coarse.name, if multi { format!(" @ {sc}") } else { String::new() });
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

const PALETTE: [&str; 10] = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf", "#bcbd22", "#7f7f7f"];

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

/// Renders a chart with a log-scale y axis. Values at or below zero are drawn at a floor
/// (a tenth of the smallest positive value) with hollow markers; the returned note says so.
pub(crate) fn svg_chart(title: &str, xlabel: &str, ylabel: &str, series: &[Series]) -> (String, Option<String>) {
    let (w, h) = (860.0, 500.0);
    let (l, r, t, b) = (80.0, 640.0, 50.0, 440.0);
    let all: Vec<&Pt> = series.iter().flat_map(|s| &s.points).filter(|p| p.x.is_finite() && p.y.is_finite()).collect();
    let min_pos = all.iter().map(|p| p.y).filter(|y| *y > 0.0).fold(f64::INFINITY, f64::min);
    let max_y = all.iter().map(|p| p.y).fold(f64::NEG_INFINITY, f64::max);
    let any_clamped = all.iter().any(|p| p.y <= 0.0);
    let floor = if min_pos.is_finite() { min_pos / 10.0 } else { 1e-6 };
    let note = any_clamped.then(|| {
        format!(
            "{} value(s) ≤ 0 cannot be shown on a log scale and are drawn at the floor {floor:.1e} with hollow markers.",
            all.iter().filter(|p| p.y <= 0.0).count()
        )
    });
    let ylo = if any_clamped { floor } else if min_pos.is_finite() { min_pos } else { floor };
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
    let sx = |x: f64| l + (x - x0) / (x1 - x0) * (r - l);
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
    let _ = writeln!(s, r#"<text x="{}" y="24" text-anchor="middle" font-size="15">{}</text>"#, (l + r) / 2.0, esc(title));
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
    let step = nice_step(x1 - x0, 7.0);
    let mut xv = (x0 / step).ceil() * step;
    let mut guard = 0;
    while xv <= x1 + 1e-12 && guard < 100 {
        let x = sx(xv);
        let _ = writeln!(s, r##"<line x1="{x:.1}" y1="{t}" x2="{x:.1}" y2="{b}" stroke="#eee"/>"##);
        let _ = writeln!(s, r#"<text x="{x:.1}" y="{}" text-anchor="middle">{}</text>"#, b + 18.0, fmt_tick(xv, step));
        xv += step;
        guard += 1;
    }
    let _ = writeln!(s, r#"<rect x="{l}" y="{t}" width="{}" height="{}" fill="none" stroke="black"/>"#, r - l, b - t);
    let _ = writeln!(s, r#"<text x="{}" y="{}" text-anchor="middle">{}</text>"#, (l + r) / 2.0, b + 42.0, esc(xlabel));
    let _ = writeln!(
        s,
        r#"<text x="18" y="{}" text-anchor="middle" transform="rotate(-90 18 {})">{} (log scale)</text>"#,
        (t + b) / 2.0,
        (t + b) / 2.0,
        esc(ylabel)
    );
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
                let _ = writeln!(s, r#"<polyline points="{}" fill="none" stroke="{color}" stroke-width="1.5"/>"#, coords.join(" "));
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
                let _ = writeln!(s, r#"<text x="{:.1}" y="{:.1}" font-size="9" fill="{color}">{}</text>"#, x + 4.0, y - 5.0, esc(&p.label));
            }
        }
    }
    // Legend.
    for (k, (name, color, line)) in legend.iter().enumerate() {
        let y = t + 10.0 + k as f64 * 18.0;
        let lx = r + 20.0;
        if *line != Line::None {
            let _ = writeln!(s, r#"<line x1="{lx}" y1="{y}" x2="{}" y2="{y}" stroke="{color}" stroke-width="2"/>"#, lx + 22.0);
        }
        let _ = writeln!(s, r#"<circle cx="{}" cy="{y}" r="3.5" fill="{color}"/>"#, lx + 11.0);
        let _ = writeln!(s, r#"<text x="{}" y="{}">{}</text>"#, lx + 30.0, y + 4.0, esc(name));
    }
    if let Some(n) = &note {
        let _ = writeln!(s, r##"<text x="{l}" y="{}" font-size="10" fill="#555">{}</text>"##, h - 8.0, esc(n));
    }
    s.push_str("</svg>\n");
    (s, note)
}
