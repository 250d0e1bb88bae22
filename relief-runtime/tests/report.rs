//! `relief report` on synthetic sweep folders: files, tables with the dissertation's numbers,
//! charts, strips and conclusions that are checked the right way round.

use std::path::{Path, PathBuf};

use relief_runtime::metrics::Metrics;
use relief_runtime::report::{self, Verdict};
use relief_runtime::sweep::Row;

fn fresh_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("relief-report-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn row(pipeline: &str, ms: f64, mse: f64, ref_t: f64, missed: f64) -> Row {
    Row {
        grid: "test".into(),
        metrics: Metrics {
            pipeline: pipeline.into(),
            scene: "scene:lion".into(),
            size: 32,
            adapter: "synthetic".into(),
            frame_ms_median: ms,
            frame_ms_mean: ms,
            frame_ms_p10: ms * 0.9,
            frame_ms_p90: ms * 1.1,
            mse_dissertation: mse,
            mse_dissertation_mean: mse / 1024.0,
            ref_err_t_rms: ref_t,
            ref_err_uv_texels_rms: ref_t * 10.0,
            missed_rate: missed,
            nan_count: 0,
            avg_iterations: 3.0,
            avg_fetches: 3.0,
            ..Default::default()
        },
        status: "ok".into(),
        error: String::new(),
        relief_version: "test".into(),
        cell_dir: format!("cells/lion/{}", relief_dsl::spec::file_safe(pipeline)),
    }
}

fn write_rows(dir: &Path, rows: &[Row], images: bool) {
    let mut text = String::new();
    for r in rows {
        text.push_str(&serde_json::to_string(r).unwrap());
        text.push('\n');
        if images && r.status == "ok" {
            let cell = dir.join(&r.cell_dir);
            std::fs::create_dir_all(&cell).unwrap();
            let img = image::RgbaImage::from_fn(16, 16, |x, y| image::Rgba([(x * 16) as u8, (y * 16) as u8, 128, 255]));
            img.save(cell.join("frame.png")).unwrap();
            img.save(cell.join("error.png")).unwrap();
        }
    }
    std::fs::write(dir.join("results.jsonl"), text).unwrap();
}

/// Linear search rows for Table 4.1 with the error falling (or rising) with the steps.
fn linear_rows(decreasing: bool) -> Vec<Row> {
    [5u32, 10, 15, 20, 25, 30, 40]
        .iter()
        .map(|&n| {
            let e = if decreasing { 1.0 / (n * n) as f64 } else { (n * n) as f64 * 1e-4 };
            row(&format!("linear({n})"), 0.4 + n as f64 * 0.01, e, e.sqrt(), 0.01)
        })
        .collect()
}

#[test]
fn report_writes_tables_charts_strips_and_checks_conclusions() {
    let dir = fresh_dir("full");
    let mut rows = linear_rows(true);
    // Table 4.2: linear(5) + binary(k), each step cutting the MSE 4x.
    for k in 1..=6u32 {
        let e = 0.04 / 4f64.powi(k as i32);
        rows.push(row(&format!("linear(5)+binary({k})"), 0.45 + 0.02 * k as f64, e, e.sqrt(), 0.0));
    }
    // Figure 4.8: a few coarse searches without refinement, one with zero error.
    for (m, scale) in [("csm", 0.1), ("qcsm", 0.05), ("rcs", 0.02)] {
        for n in [5u32, 10, 15] {
            let e = scale / n as f64;
            rows.push(row(&format!("{m}({n})"), 0.5 + n as f64 * 0.012, e, (e * 3.0).sqrt(), scale));
        }
    }
    rows.push(row("cns(5)", 0.6, 0.0, 0.0, 0.0));
    // A failed cell.
    let mut failed = row("linear(50)", 0.0, 0.0, 0.0, 0.0);
    failed.status = "error".into();
    failed.error = "device lost".into();
    rows.push(failed);
    write_rows(&dir, &rows, true);

    let t = std::time::Instant::now();
    let s = report::write(&dir).expect("report");
    assert!(t.elapsed().as_secs_f64() < 10.0);
    assert_eq!(s.rows, rows.len());
    assert_eq!(s.failed.len(), 1);
    assert_eq!(s.failed[0].2, "device lost");

    for f in ["tables.md", "index.html", "pareto.md"] {
        assert!(dir.join(f).is_file(), "{f} written");
    }
    let md = std::fs::read_to_string(dir.join("tables.md")).unwrap();
    assert!(md.contains("## Table 4.1: performance of linear search (Lion)"), "{md}");
    assert!(md.contains("## Table 4.2: performance of binary search after 5 and 10 linear steps (Lion)"));
    assert!(md.contains("## Table 4.15"));
    assert!(md.contains("| # | pipeline | base | frame ms (median) | frame ms (mean) | diss ms (mean of 500) |"), "header");
    // The dissertation's numbers next to ours.
    let line = md.lines().find(|l| l.contains("| `linear(10)` |")).expect("linear(10) row");
    assert!(line.contains("0.00515373") && line.contains("0.5052") && line.contains("6.099"), "{line}");
    assert!(line.contains("1.000e-2"), "our mse_dissertation: {line}");
    let failed_line = md.lines().find(|l| l.contains("| `linear(50)` |")).expect("linear(50) row");
    assert!(failed_line.contains("error") && failed_line.contains("0.00021447"), "{failed_line}");
    let missing = md.lines().find(|l| l.contains("| `linear(200)` |")).expect("linear(200) row");
    assert!(missing.contains("—") && missing.contains("0.00000997"));
    // Table 4.3's trend: frame time of the binary row relative to its paired linear-only row.
    let t43 = md.lines().find(|l| l.contains("| `linear(5)+binary(2)` |") && l.contains("0.4910")).expect("Table 4.3 pair row");
    assert!(t43.contains("#5"), "paired with linear(40): {t43}");
    assert!(md.contains("device lost"));

    // Conclusions.
    assert!(md.contains("## Conclusions"));
    let c41 = s.conclusions.iter().find(|c| c.table == "4.1" && c.claim.contains("lower the error")).unwrap();
    assert_eq!(c41.ours_mse, Verdict::Holds, "{}", c41.evidence_mse);
    assert_eq!(c41.ours_ref, Some(Verdict::Holds));
    assert_eq!(c41.diss, Verdict::Holds);
    let c42 = s.conclusions.iter().find(|c| c.table == "4.2").unwrap();
    assert_eq!(c42.ours_mse, Verdict::Holds, "{}", c42.evidence_mse);
    assert_eq!(c42.ours_ref, Some(Verdict::Holds), "{}", c42.evidence_ref);
    let c415 = s.conclusions.iter().find(|c| c.table == "4.15").unwrap();
    assert_eq!(c415.ours_mse, Verdict::NotMeasured);
    assert_eq!(c415.diss, Verdict::Holds);
    // Every conclusion holds on the dissertation's own numbers (the criteria say what it says),
    // except the min-of-4 claim, for which the dissertation prints no number (§4.3.1).
    for c in &s.conclusions {
        if c.claim.contains("minimum of four texels") {
            assert_eq!(c.diss, Verdict::NotMeasured, "{}", c.evidence_diss);
            continue;
        }
        assert_eq!(c.diss, Verdict::Holds, "{} {}: {}", c.table, c.claim, c.evidence_diss);
    }

    // Charts: Figure 4.8 with each metric, SVG with lines.
    for m in ["mse_dissertation_mean", "ref_err_t_rms", "missed_rate"] {
        let p = dir.join("report").join(format!("f4.8_{m}.svg"));
        let svg = std::fs::read_to_string(&p).unwrap_or_else(|_| panic!("{} written", p.display()));
        assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
        assert!(svg.contains("<polyline"));
        assert!(svg.contains(">csm<") && svg.contains(">qcsm<"));
    }
    // cns(5) has zero error: drawn at the floor, and said so.
    let svg = std::fs::read_to_string(dir.join("report/f4.8_mse_dissertation_mean.svg")).unwrap();
    assert!(svg.contains("drawn at the floor"));
    assert!(!dir.join("report/f4.10_mse_dissertation_mean.svg").exists(), "no rows of f4.10");

    // Strips: one per table with images, rows stacked.
    let strip = image::open(dir.join("report/strip_t4.1.png")).expect("strip").to_rgba8();
    assert_eq!(strip.height(), 13 * 128 + 12 * 4);
    assert!(!dir.join("report/strip_t4.9.png").exists());

    // Pareto.
    let pareto = std::fs::read_to_string(dir.join("pareto.md")).unwrap();
    assert!(pareto.contains("Pareto front, scene lion, by ref_err_t_rms"));
    assert!(dir.join("report/pareto_lion_ref_err_t_rms.svg").is_file());

    let html = std::fs::read_to_string(dir.join("index.html")).unwrap();
    assert!(html.contains("<img src=\"report/f4.8_mse_dissertation_mean.svg\""));
    assert!(html.contains("report/strip_t4.1.png"));
    assert!(html.contains("<td class=\"holds\">") || html.contains("class=\"holds\""));
    assert!(!html.contains("http://") || html.matches("http://").count() == 0);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_conclusion_that_our_rows_contradict_does_not_hold() {
    let dir = fresh_dir("reverse");
    write_rows(&dir, &linear_rows(false), false);
    let s = report::write(&dir).expect("report");
    let c41 = s.conclusions.iter().find(|c| c.table == "4.1" && c.claim.contains("lower the error")).unwrap();
    assert_eq!(c41.ours_mse, Verdict::DoesNotHold, "{}", c41.evidence_mse);
    assert_eq!(c41.ours_ref, Some(Verdict::DoesNotHold));
    let md = std::fs::read_to_string(dir.join("tables.md")).unwrap();
    assert!(md.contains("does not hold"));
    // No images anywhere: no strips, and no failure.
    assert!(!dir.join("report/strip_t4.1.png").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn missing_or_empty_folders_are_clear_errors() {
    let missing = std::env::temp_dir().join(format!("relief-report-{}-nope", std::process::id()));
    let e = report::write(&missing).unwrap_err().to_string();
    assert!(e.contains(&missing.display().to_string()) && e.contains("does not exist"), "{e}");

    let empty = fresh_dir("empty");
    let e = report::write(&empty).unwrap_err().to_string();
    assert!(e.contains(&empty.display().to_string()) && e.contains("no results"), "{e}");
    std::fs::write(empty.join("results.jsonl"), "").unwrap();
    assert!(report::write(&empty).is_err());

    // Unreadable lines are skipped and reported, not fatal; a null metric is NaN.
    let mut text = serde_json::to_string(&row("linear(10)", 0.5, 0.01, 0.1, 0.0)).unwrap();
    text = text.replace("\"ref_err_t_rms\":0.1", "\"ref_err_t_rms\":null");
    std::fs::write(empty.join("results.jsonl"), format!("{text}\nnot json\n{{\"grid\":1}}\n")).unwrap();
    let s = report::write(&empty).expect("report with a bad line");
    assert_eq!(s.rows, 1);
    assert_eq!(s.bad_lines.len(), 2);
    let md = std::fs::read_to_string(empty.join("tables.md")).unwrap();
    let line = md.lines().find(|l| l.contains("| `linear(10)` |")).unwrap();
    assert!(line.contains("NaN"), "{line}");
    let _ = std::fs::remove_dir_all(&empty);
}

/// Runs the report on a real sweep: `RELIEF_REPORT_DIR=out/sweep cargo test --release -p
/// relief-runtime --test report -- --ignored`.
#[test]
#[ignore]
fn report_on_a_real_sweep() {
    let Ok(dir) = std::env::var("RELIEF_REPORT_DIR") else { return };
    let s = report::write(Path::new(&dir)).expect("report");
    println!("{} rows, {} ok, {} failed, {} files", s.rows, s.ok, s.failed.len(), s.files.len());
    for c in &s.conclusions {
        println!("{:5} {:14} {:?} {:14} | {}", c.table, c.ours_mse.as_str(), c.ours_ref.map(|v| v.as_str()), c.diss.as_str(), c.claim);
    }
    for w in &s.warnings {
        println!("warning: {w}");
    }
}
