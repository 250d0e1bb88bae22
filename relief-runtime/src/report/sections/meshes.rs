//! The mesh grid (`relief sweep --grid meshes`, issue 38), when the folders hold its rows:
//! each cell's figures against the exact mesh reference, the four goals met or missed
//! per scene, and each cell's coverage picture (agree-hit grey, agree-miss black, extra red,
//! missing blue: `crate::mesh_measure::Agreement::colour`). Nothing at all, not even a
//! heading, when there are no mesh rows.

use std::fmt::Write as _;
use std::path::Path;

use relief_dsl::spec::Curved;

use super::{Report, Section};
use crate::report::html::{esc, PageSection};
use crate::report::text::{fmt_num, fmt_sci, TextTable, DASH};
use crate::results::Row;

/// The meshes section.
pub(crate) struct Meshes;

impl Section for Meshes {
    fn markdown(&self, r: &Report) -> Option<String> {
        (!r.mesh_rows.is_empty()).then(|| to_markdown(&r.mesh_rows, &r.summary.dir))
    }
    fn html(&self, r: &Report) -> Option<PageSection> {
        (!r.mesh_rows.is_empty()).then(|| PageSection {
            id: "meshes".into(),
            nav: "Meshes".into(),
            html: to_html(&r.mesh_rows, &r.summary.dir),
        })
    }
    fn of_sweep(&self) -> bool {
        false
    }
}

/// Whether a row is the mesh grid's (its mesh columns, or a failed cell of the grid).
pub(crate) fn is_mesh_row(r: &Row) -> bool {
    r.mesh.is_some() || r.grid == crate::sweep::meshes::MESHES
}

const TITLE: &str = "Meshes: curved=none, quadric and prism against the exact mesh reference (issue 38)";

/// The goals, in the goals table's order.
const GOALS: [&str; 4] =
    ["quadric coverage ≤ 2 %", "prism coverage ≤ 0.5 %", "prism RMS t ≤ 1e-3", "prism time ≤ 2× none"];

/// One scene's cells: (scene, pipeline without `curved=`, size, adapter) and its rows in
/// mode order.
struct Group<'a> {
    scene: String,
    stages: String,
    size: u32,
    adapter: String,
    rows: Vec<&'a Row>,
}

impl Group<'_> {
    fn mode(&self, c: Curved) -> Option<&Row> {
        self.rows.iter().copied().find(|r| r.metrics.pipeline.curved == Some(c))
    }
}

fn groups(rows: &[Row]) -> Vec<Group<'_>> {
    let mut out: Vec<Group> = Vec::new();
    for r in rows {
        let m = &r.metrics;
        let stages = m.pipeline.clone().with_curved(None).to_string();
        match out
            .iter_mut()
            .find(|g| g.scene == m.scene && g.stages == stages && g.size == m.size && g.adapter == m.adapter)
        {
            Some(g) => g.rows.push(r),
            None => out.push(Group {
                scene: m.scene.clone(),
                stages,
                size: m.size,
                adapter: m.adapter.clone(),
                rows: vec![r],
            }),
        }
    }
    for g in &mut out {
        let order = |r: &Row| r.metrics.pipeline.curved.and_then(|c| Curved::ALL.iter().position(|x| *x == c));
        g.rows.sort_by_key(|r| order(r));
    }
    out
}

/// A goal's verdict on one scene's cells: `met (value)`, `missed (value)`, `not decided
/// (…)` for a time whose 95 % interval holds the bound, `not measured` without the cell.
fn verdict(g: &Group, goal: usize) -> String {
    let ok = |c| g.mode(c).filter(|r| r.status.is_ok()).and_then(|r| r.mesh.as_ref().map(|m| (r, m)));
    let below = |value: f64, bound: f64, shown: String| {
        if value.is_nan() {
            "not measured (NaN)".to_string()
        } else if value <= bound {
            format!("met ({shown})")
        } else {
            format!("missed ({shown})")
        }
    };
    let cov = |x: f64| format!("{:.2} %", 100.0 * x);
    match goal {
        0 => ok(Curved::Quadric).map(|(_, m)| below(m.coverage_error, 0.02, cov(m.coverage_error))),
        1 => ok(Curved::Prism).map(|(_, m)| below(m.coverage_error, 0.005, cov(m.coverage_error))),
        2 => ok(Curved::Prism).map(|(_, m)| below(m.rms_t, 1e-3, fmt_sci(m.rms_t))),
        _ => ok(Curved::Prism).map(|(r, _)| {
            let m = &r.metrics;
            match (m.frame_ratio_to_baseline, m.frame_ratio_to_baseline_lo, m.frame_ratio_to_baseline_hi) {
                (Some(x), Some(lo), Some(hi)) if lo.is_finite() && hi.is_finite() => {
                    let shown = format!("{x:.2}× [{lo:.2}, {hi:.2}]");
                    if hi <= 2.0 {
                        format!("met ({shown})")
                    } else if lo > 2.0 {
                        format!("missed ({shown})")
                    } else {
                        format!("not decided ({shown}: the interval holds 2)")
                    }
                }
                (Some(x), _, _) => format!("not decided ({x:.2}×, no interval)"),
                _ => "not measured (not timed)".to_string(),
            }
        }),
    }
    .unwrap_or_else(|| "not measured".to_string())
}

/// The goals table: one row per scene, one column per goal.
fn goals_table(gs: &[Group]) -> TextTable {
    let mut header = vec!["scene".to_string(), "pipeline".into(), "size".into()];
    header.extend(GOALS.iter().map(|g| g.to_string()));
    let mut t = TextTable {
        title: "Goals (issue 38)".into(),
        notes: vec![
            "Per scene: `curved=quadric` coverage error ≤ 2 % of pixels; `curved=prism` coverage error ≤ 0.5 % and RMS t error ≤ 1e-3 (in units of the relief's depth, on pixels both hit); prism's frame time ≤ 2× `curved=none`'s with the same stages (paired blocks, 95 % interval: **not decided** when the interval holds 2, as it may on a loaded machine).".into(),
        ],
        header,
        ..Default::default()
    };
    for g in gs {
        let mut row = vec![g.scene.clone(), g.stages.clone(), g.size.to_string()];
        row.extend((0..GOALS.len()).map(|i| verdict(g, i)));
        t.rows.push(row);
    }
    t
}

/// The figures table: one row per cell. `link` gives the coverage picture's cell, if any.
fn figures_table(gs: &[Group], link: &dyn Fn(&Row) -> Option<String>) -> TextTable {
    let priced = gs.iter().flat_map(|g| &g.rows).any(|r| r.metrics.gpu_driver.is_some());
    let header = [
        "scene",
        "pipeline",
        "coverage %",
        "IoU",
        "missing px",
        "extra px",
        "RMS t / depth",
        "earliest / depth",
        "uv texels",
        "depth (NDC)",
        "time / none [95 %]",
        "coverage picture",
    ];
    let mut t = TextTable {
        title: "Figures".into(),
        notes: vec![
            "Against the exact mesh reference on the same pixel-centre rays (docs/meshes.md, \"Measuring\"): coverage error, the share of pixels whose hit/miss disagrees; IoU of the covered pixels; missing (the reference hits, the pipeline draws nothing) and extra pixels; on pixels both hit, RMS t error and the earliest hit before the reference's, in units of the relief's depth, RMS uv error in texels and RMS NDC depth error; the frame time over `curved=none`'s with the same stages (paired blocks). The GPU compiler's modeled cost is not implemented for mesh modules.".into(),
        ],
        header: header.map(String::from).to_vec(),
        ..Default::default()
    };
    if priced {
        // Only when a row has them, so that a report without them is unchanged.
        let note = &mut t.notes[0];
        *note = note.replace(
            " The GPU compiler's modeled cost is not implemented for mesh modules.",
            " The GPU compiler's counts for the mode's `fs_mesh` (AMD's compiler through RADV's null device: a model, not a clock; docs/notes/gpu-cost.md): instructions, VGPRs and the top-level loops' bodies, on RDNA2 (navi21) and RDNA3 (gfx1100); no per-pixel figure (the mesh measurement has no pass counters).",
        );
        t.header
            .extend(["fs_mesh instr / VGPRs / loop (navi21)".into(), "fs_mesh instr / VGPRs / loop (gfx1100)".into()]);
    }
    for g in gs {
        for r in &g.rows {
            let m = &r.metrics;
            let mut row = vec![g.scene.clone(), m.pipeline.to_string()];
            match (&r.mesh, r.status.is_ok()) {
                (Some(c), true) => {
                    let time =
                        match (m.frame_ratio_to_baseline, m.frame_ratio_to_baseline_lo, m.frame_ratio_to_baseline_hi) {
                            (Some(x), Some(lo), Some(hi)) => format!("{x:.3} [{}, {}]", fmt_num(lo, 3), fmt_num(hi, 3)),
                            (Some(x), _, _) => format!("{x:.3}"),
                            _ => DASH.into(),
                        };
                    row.extend([
                        fmt_num(100.0 * c.coverage_error, 3),
                        fmt_num(c.iou, 4),
                        c.missing.to_string(),
                        c.extra.to_string(),
                        fmt_sci(c.rms_t),
                        fmt_sci(c.earliest),
                        fmt_num(c.uv_texels, 3),
                        fmt_sci(c.depth),
                        time,
                        link(r).unwrap_or_else(|| DASH.into()),
                    ]);
                }
                _ => row.extend(["error".to_string(), r.error.clone()]),
            }
            if priced && r.status.is_ok() {
                let fmt = |i: Option<u32>, v: Option<u32>, l: Option<u32>| match (i, v, l) {
                    (Some(i), Some(v), Some(l)) => format!("{i} / {v} / {l}"),
                    _ => DASH.to_string(),
                };
                row.push(fmt(m.gpu_navi21_instructions, m.gpu_navi21_vgprs, m.gpu_navi21_loop_body));
                row.push(fmt(m.gpu_gfx1100_instructions, m.gpu_gfx1100_vgprs, m.gpu_gfx1100_loop_body));
            }
            t.rows.push(row);
        }
    }
    t
}

/// The coverage picture of `r`, relative to the report's folder `dir`, when it is there.
fn picture(r: &Row, dir: &Path) -> Option<String> {
    if r.cell_dir.is_empty() || !r.status.is_ok() {
        return None;
    }
    let rel = format!("{}/coverage.png", r.cell_dir);
    dir.join(&rel).is_file().then_some(rel)
}

fn intro(rows: &[Row]) -> String {
    let ok = rows.iter().filter(|r| r.status.is_ok()).count();
    let mut adapters: Vec<&str> = rows.iter().map(|r| r.metrics.adapter.as_str()).collect();
    adapters.dedup();
    format!(
        "{} mesh cells ({ok} ok) on {}: a pipeline under each `curved=` mode on mesh scenes (`relief sweep --grid meshes`). Coverage pictures: agree-hit grey, agree-miss black, extra red (drawn where the reference has no relief), missing blue (the reference's relief not drawn).",
        rows.len(),
        adapters.join("; ")
    )
}

/// The section in Markdown.
pub(crate) fn to_markdown(rows: &[Row], dir: &Path) -> String {
    let gs = groups(rows);
    let mut md = format!("## {TITLE}\n\n{}\n\n", intro(rows));
    md.push_str(&goals_table(&gs).to_markdown(3));
    md.push_str(&figures_table(&gs, &|r| picture(r, dir).map(|p| format!("[coverage]({p})"))).to_markdown(3));
    md
}

/// The section in HTML: the tables, then each scene's coverage pictures side by side.
pub(crate) fn to_html(rows: &[Row], dir: &Path) -> String {
    let gs = groups(rows);
    let mut h =
        format!("<h2 id=\"meshes\">{}</h2>\n<p>{}</p>\n", esc(TITLE), crate::report::html::md_inline(&intro(rows)));
    h.push_str(&goals_table(&gs).to_html(3));
    h.push_str(&figures_table(&gs, &|r| picture(r, dir).map(|_| "below".to_string())).to_html(3));
    h.push_str("<h3 id=\"meshes-coverage\">Coverage pictures</h3>\n");
    for g in &gs {
        let _ = writeln!(h, "<h4>{} · {} · {}²</h4>\n<div>", esc(&g.scene), esc(&g.stages), g.size);
        for r in &g.rows {
            let mode = r.metrics.pipeline.curved.map(|c| c.to_string()).unwrap_or_default();
            match picture(r, dir) {
                Some(p) => {
                    let caption = r
                        .mesh
                        .as_ref()
                        .map(|c| {
                            format!(
                                "curved={mode}: {:.2} % ({} missing, {} extra)",
                                100.0 * c.coverage_error,
                                c.missing,
                                c.extra
                            )
                        })
                        .unwrap_or_default();
                    let _ = write!(
                        h,
                        "<div class=\"fig\"><a href=\"{p}\"><img src=\"{p}\" alt=\"coverage of curved={mode}\" width=\"{w}\" style=\"image-rendering: pixelated\" loading=\"lazy\"></a><br><small>{c}</small></div>",
                        p = esc(&p),
                        mode = esc(&mode),
                        w = (g.size * 2).clamp(96, 256),
                        c = esc(&caption)
                    );
                }
                None => {
                    let _ = write!(h, "<div class=\"fig\"><small>curved={}: no picture</small></div>", esc(&mode));
                }
            }
        }
        h.push_str("</div>\n");
    }
    h
}
