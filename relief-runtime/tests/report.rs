//! `relief report` on synthetic sweep folders: files, tables with the dissertation's numbers,
//! charts, strips and conclusions that are checked the right way round.

use std::path::{Path, PathBuf};

use relief_runtime::metrics::Metrics;
use relief_runtime::report::{self, Verdict};
use relief_runtime::results::Row;

fn fresh_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("relief-report-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn row(pipeline: &str, ms: f64, mse: f64, ref_t: f64, skipped: f64) -> Row {
    Row {
        grid: "test".into(),
        metrics: Metrics {
            pipeline: pipeline.parse().unwrap(),
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
            skipped_rate: skipped,
            past_rate: skipped,
            missed_rate: skipped,
            nan_count: 0,
            avg_iterations: 3.0,
            avg_fetches: 3.0,
            ..Default::default()
        },
        status: relief_runtime::results::Status::Ok,
        error: String::new(),
        relief_version: "test".into(),
        cell_dir: format!("cells/lion/{}", relief_dsl::spec::file_safe(pipeline)),
        room: None,
        mesh: None,
    }
}

fn write_rows(dir: &Path, rows: &[Row], images: bool) {
    let mut text = String::new();
    for r in rows {
        text.push_str(&serde_json::to_string(r).unwrap());
        text.push('\n');
        if images && r.status.is_ok() {
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
    failed.status = relief_runtime::results::Status::Error;
    failed.error = "device lost".into();
    rows.push(failed);
    write_rows(&dir, &rows, true);

    let s = report::write(&dir).expect("report");
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
    assert!(
        md.contains("| # | pipeline | base | frame ms (median) | frame ms (mean) | diss ms (mean of 500) |"),
        "header"
    );
    // The dissertation's numbers next to ours.
    let line = md.lines().find(|l| l.contains("| `linear(10)` |")).expect("linear(10) row");
    assert!(line.contains("0.00515373") && line.contains("0.5052") && line.contains("6.099"), "{line}");
    assert!(line.contains("1.000e-2"), "our mse_dissertation: {line}");
    let failed_line = md.lines().find(|l| l.contains("| `linear(50)` |")).expect("linear(50) row");
    assert!(failed_line.contains("error") && failed_line.contains("0.00021447"), "{failed_line}");
    let missing = md.lines().find(|l| l.contains("| `linear(200)` |")).expect("linear(200) row");
    assert!(missing.contains("—") && missing.contains("0.00000997"));
    // Table 4.3's trend: frame time of the binary row relative to its paired linear-only row.
    let t43 = md
        .lines()
        .find(|l| l.contains("| `linear(5)+binary(2)` |") && l.contains("0.4910"))
        .expect("Table 4.3 pair row");
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
    for m in ["mse_dissertation_mean", "ref_err_t_rms", "skipped_rate"] {
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

    // Strips: one page per table with images, its rows stacked in table order, each showing
    // the cell's own frame and error (linked, not copied: no PNG strip is written).
    let strip = std::fs::read_to_string(dir.join("report/strip_t4.1.html")).expect("strip");
    assert_eq!(strip.matches("<div class=\"row\">").count(), 13, "one row per table row");
    assert!(strip.contains(".row img{height:256px;"), "tiles 256 pixels high");
    let srcs: Vec<&str> = strip.split("<img src=\"").skip(1).map(|s| &s[..s.find('"').unwrap()]).collect();
    // Table 4.1's rows with a cell: the seven linear rows (frame and error each), in order.
    let want: Vec<String> = [5, 10, 15, 20, 25, 30, 40]
        .iter()
        .flat_map(|n| ["frame", "error"].map(|w| format!("../cells/lion/linear_{n}/{w}.png")))
        .collect();
    assert_eq!(srcs, want);
    for src in &srcs {
        assert!(dir.join("report").join(src).is_file(), "{src} resolves from report/");
    }
    assert_eq!(strip.matches("<div class=\"none\"></div>").count(), 2 * (13 - 7), "grey tiles for rows without a cell");
    assert!(!dir.join("report/strip_t4.1.png").exists(), "no copy of the pictures");
    assert!(!dir.join("report/strip_t4.9.html").exists());

    // Pareto.
    let pareto = std::fs::read_to_string(dir.join("pareto.md")).unwrap();
    assert!(pareto.contains("Pareto front, scene lion, by ref_err_t_rms"));
    assert!(dir.join("report/pareto_lion_ref_err_t_rms.svg").is_file());

    let html = std::fs::read_to_string(dir.join("index.html")).unwrap();
    assert!(html.contains("<img src=\"report/f4.8_mse_dissertation_mean.svg\""));
    assert!(html.contains("<a href=\"report/strip_t4.1.html\">all rows on one page</a>"));
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
    assert!(!dir.join("report/strip_t4.1.html").exists());
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

/// Runs the report on a real sweep: `RELIEF_REPORT_DIR=out/sweep cargo test --release --test
/// runtime report:: -- --ignored`.
#[test]
#[ignore]
fn report_on_a_real_sweep() {
    let Ok(dir) = std::env::var("RELIEF_REPORT_DIR") else { return };
    let s = report::write(Path::new(&dir)).expect("report");
    println!("{} rows, {} ok, {} failed, {} files", s.rows, s.ok, s.failed.len(), s.files.len());
    for c in &s.conclusions {
        println!(
            "{:5} {:14} {:?} {:14} | {}",
            c.table,
            c.ours_mse.as_str(),
            c.ours_ref.map(|v| v.as_str()),
            c.diss.as_str(),
            c.claim
        );
    }
    for w in &s.warnings {
        println!("warning: {w}");
    }
}

// ---------------------------------------------------------------------------------------
// The numbers mean what they say.

/// A row built from `row` with some metrics changed.
fn rowm(pipeline: &str, f: impl FnOnce(&mut Metrics)) -> Row {
    let mut r = row(pipeline, 0.5, 1e-3, 1e-3f64.sqrt(), 0.0);
    f(&mut r.metrics);
    r
}

/// Consistent errors: `mse` as the per-ray mean (the sum over 1024 rays) and its root as
/// `ref_err_t_rms`, so that both metrics must give the same verdict.
fn with_err(m: &mut Metrics, mse_mean: f64) {
    m.mse_dissertation_mean = mse_mean;
    m.mse_dissertation = mse_mean * 1024.0;
    m.ref_err_t_rms = mse_mean.sqrt();
}

fn with_ms(m: &mut Metrics, ms: f64) {
    m.frame_ms_mean = ms;
    m.frame_ms_median = ms;
}

fn report_of(name: &str, rows: &[Row]) -> (PathBuf, report::ReportSummary) {
    let dir = fresh_dir(name);
    write_rows(&dir, rows, false);
    let s = report::write(&dir).expect("report");
    (dir, s)
}

fn conclusion<'a>(s: &'a report::ReportSummary, table: &str, claim_part: &str) -> &'a report::Conclusion {
    s.conclusions
        .iter()
        .find(|c| c.table == table && c.claim.contains(claim_part))
        .unwrap_or_else(|| panic!("no conclusion {table} '{claim_part}'"))
}

/// The conclusion checked on the cone methods' `form` rows.
fn conclusion_in_form<'a>(
    s: &'a report::ReportSummary,
    table: &str,
    claim_part: &str,
    form: &str,
) -> &'a report::Conclusion {
    s.conclusions
        .iter()
        .find(|c| c.table == table && c.claim.contains(claim_part) && c.form == form)
        .unwrap_or_else(|| panic!("no conclusion {table} '{claim_part}' in form={form}"))
}

/// The cells of the Markdown table row for `pipeline` in the section titled `section`, with
/// the header's cells.
fn md_row(md: &str, section: &str, pipeline: &str) -> (Vec<String>, Vec<String>) {
    let start = md.find(section).unwrap_or_else(|| panic!("no section {section}"));
    let rest = &md[start..];
    let end = rest[section.len()..].find("\n## ").map(|e| e + section.len()).unwrap_or(rest.len());
    let sec = &rest[..end];
    let cells = |l: &str| l.trim().trim_matches('|').split(" | ").map(|c| c.trim().to_string()).collect::<Vec<_>>();
    let header = sec.lines().find(|l| l.starts_with("| # |")).map(cells).expect("header");
    let row = sec
        .lines()
        .find(|l| l.contains(&format!("| `{pipeline}` |")))
        .map(cells)
        .unwrap_or_else(|| panic!("no row {pipeline}"));
    (header, row)
}

fn col(header: &[String], name: &str) -> usize {
    header.iter().position(|h| h == name).unwrap_or_else(|| panic!("no column {name} in {header:?}"))
}

#[test]
fn steps_columns_split_coarse_and_refine_and_the_dissertation_sits_next_to_coarse() {
    let r = rowm("csm(5)+binary(5)", |m| {
        m.avg_coarse_steps = 2.0;
        m.avg_refine_steps = 5.0;
        m.avg_iterations = 7.0;
        m.avg_fetches = 9.0;
    });
    let (dir, _) = report_of("steps", &[r]);
    let md = std::fs::read_to_string(dir.join("tables.md")).unwrap();
    let (h, row) = md_row(&md, "## Table 4.11", "csm(5)+binary(5)");
    let c = col(&h, "avg coarse steps");
    assert_eq!(row[c], "2.000");
    // The dissertation's "avg steps" (2.016 for csm(5)+binary(5), coarse only) next to it.
    assert_eq!(h[c + 1], "diss avg steps (coarse)");
    assert_eq!(row[c + 1], "2.016");
    assert_eq!(row[col(&h, "avg refine steps")], "5.000");
    assert_eq!(row[col(&h, "avg iter (total)")], "7.00");
    assert_eq!(row[col(&h, "avg fetches (total)")], "9.00");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn conclusions_use_the_per_ray_mean_and_tables_show_it_beside_the_sum() {
    // The mean falls with N while the sum rises (more rays counted at larger N): the
    // conclusion must follow the mean, the dissertation's measure.
    let rows: Vec<Row> = [5u32, 10, 15, 20, 25, 30, 40]
        .iter()
        .map(|&n| {
            rowm(&format!("linear({n})"), |m| {
                let mean = 1.0 / f64::from(n * n);
                m.mse_dissertation_mean = mean;
                m.mse_dissertation = mean * f64::from(n * n * n);
                m.ref_err_t_rms = mean.sqrt();
            })
        })
        .collect();
    let (dir, s) = report_of("mean", &rows);
    let c = conclusion(&s, "4.1", "lower the error");
    assert_eq!(c.ours_mse, Verdict::Holds, "{}", c.evidence_mse);
    let md = std::fs::read_to_string(dir.join("tables.md")).unwrap();
    let (h, row) = md_row(&md, "## Table 4.1", "linear(10)");
    assert_eq!(row[col(&h, "mse_dissertation_mean")], format!("{:.3e}", 0.01));
    assert_eq!(row[col(&h, "mse_dissertation (sum)")], format!("{:.3e}", 10.0));
    assert_eq!(h[col(&h, "mse_dissertation_mean") + 1], "diss MSE");
    assert_eq!(row[col(&h, "diss MSE")], "0.00515373");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_nan_error_counts_as_an_error_not_as_a_skipped_cell() {
    let mut rows = Vec::new();
    for n in [5u32, 10, 15, 20, 25, 30, 40, 50] {
        rows.push(rowm(&format!("csm({n})"), |m| with_err(m, 1e-4)));
        rows.push(rowm(&format!("csm({n})+binary(2)"), |m| {
            m.mse_dissertation = f64::NAN;
            m.mse_dissertation_mean = f64::NAN;
            m.ref_err_t_rms = f64::NAN;
            m.nan_count = 17;
        }));
    }
    let (dir, s) = report_of("nan", &rows);
    let c = conclusion(&s, "4.6", "binary steps after cone");
    assert_eq!(c.ours_mse, Verdict::DoesNotHold, "{}", c.evidence_mse);
    assert_eq!(c.ours_ref, Some(Verdict::DoesNotHold), "{}", c.evidence_ref);
    assert!(c.evidence_mse.starts_with("0/8"), "{}", c.evidence_mse);
    let md = std::fs::read_to_string(dir.join("tables.md")).unwrap();
    let (h, row) = md_row(&md, "## Table 4.6", "csm(10)+binary(2)");
    assert_eq!(row[col(&h, "mse_dissertation_mean")], "NaN");
    assert_eq!(row[col(&h, "nan_count")], "17");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn frame_time_columns_say_median_or_mean_and_timing_claims_use_the_mean() {
    // Interval is slower than binary by the mean (the dissertation's measure), faster by the
    // median.
    let mut rows = Vec::new();
    for k in 1..=6u32 {
        rows.push(rowm(&format!("linear(10)+binary({k})"), |m| {
            m.frame_ms_median = 0.60;
            m.frame_ms_mean = 0.60;
        }));
        rows.push(rowm(&format!("linear(10)+interval({k})"), |m| {
            m.frame_ms_median = 0.55;
            m.frame_ms_mean = 0.70;
        }));
    }
    let (dir, s) = report_of("mean-ms", &rows);
    let c = conclusion(&s, "4.5", "costs more frame time");
    assert_eq!(c.ours_mse, Verdict::Holds, "{}", c.evidence_mse);
    let md = std::fs::read_to_string(dir.join("tables.md")).unwrap();
    let (h, row) = md_row(&md, "## Table 4.5", "linear(10)+interval(3)");
    assert_eq!(row[col(&h, "frame ms (median)")], "0.550");
    assert_eq!(row[col(&h, "frame ms (mean)")], "0.700");
    assert_eq!(h[col(&h, "frame ms (mean)") + 1], "diss ms (mean of 500)");
    // Every frame-time column of every table names its statistic.
    for l in md.lines().filter(|l| l.starts_with("| # |") || l.starts_with("| budget")) {
        for cell in l.trim_matches('|').split(" | ") {
            if cell.split(|ch: char| !ch.is_alphanumeric()).any(|w| w == "ms") {
                assert!(cell.contains("median") || cell.contains("mean"), "'{cell}' in {l}");
            }
        }
    }
    let pareto = std::fs::read_to_string(dir.join("pareto.md")).unwrap();
    assert!(pareto.contains("mean frame ms"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn rows_are_keyed_by_size_and_a_conclusion_never_mixes_sizes() {
    let mut rows = Vec::new();
    for size in [32u32, 64] {
        for n in [5u32, 10, 15, 20] {
            let mut r = rowm(&format!("linear({n})"), |m| with_err(m, 1.0 / f64::from(n * n * size)));
            r.metrics.size = size;
            rows.push(r);
        }
    }
    let (dir, s) = report_of("sizes", &rows);
    // Both sizes' rows are kept, each in its own table.
    let md = std::fs::read_to_string(dir.join("tables.md")).unwrap();
    for size in [32, 64] {
        let title = format!("## Table 4.1: performance of linear search (Lion) — size {size}²");
        assert_eq!(md.matches(&title).count(), 1, "{title}");
        let (h, row) = md_row(&md, &title, "linear(10)");
        assert_eq!(row[col(&h, "mse_dissertation_mean")], format!("{:.3e}", 1.0 / f64::from(100 * size)));
    }
    // The conclusion would read both sizes: refused, naming them.
    let c = conclusion(&s, "4.1", "lower the error");
    assert_eq!(c.ours_mse, Verdict::NotMeasured, "{}", c.evidence_mse);
    assert!(c.evidence_mse.contains("32²") && c.evidence_mse.contains("64²"), "{}", c.evidence_mse);
    let _ = std::fs::remove_dir_all(&dir);

    // Two halves of one comparison at different sizes: refused too.
    let mut rows = Vec::new();
    for k in 1..=6u32 {
        let mut b = rowm(&format!("linear(10)+binary({k})"), |m| with_ms(m, 0.5));
        b.metrics.size = 32;
        let mut i = rowm(&format!("linear(10)+interval({k})"), |m| with_ms(m, 0.6));
        i.metrics.size = 64;
        rows.extend([b, i]);
    }
    let (dir, s) = report_of("sizes2", &rows);
    let c = conclusion(&s, "4.5", "costs more frame time");
    assert_eq!(c.ours_mse, Verdict::NotMeasured, "{}", c.evidence_mse);
    assert!(c.evidence_mse.contains("refused"), "{}", c.evidence_mse);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn cone_comparisons_read_csm_with_nearest_filtering_like_the_others() {
    let steps = [5u32, 8, 10, 15, 20, 30];
    let mut rows = Vec::new();
    for n in steps {
        let e = 1e-3 / f64::from(n);
        rows.push(rowm(&format!("cns({n}, form=textbook)+binary(5)"), |m| {
            with_err(m, e);
            with_ms(m, 0.60);
        }));
        // CSM read nearest: about the same error as CNS, and faster.
        rows.push(rowm(&format!("csm({n}, form=textbook, sample=nearest)+binary(5)"), |m| {
            with_err(m, e * 1.02);
            with_ms(m, 0.55);
        }));
        // CSM read linearly: three times the error, and slower.
        rows.push(rowm(&format!("csm({n}, form=textbook)+binary(5)"), |m| {
            with_err(m, e * 3.0);
            with_ms(m, 0.65);
        }));
    }
    let (dir, s) = report_of("sampling", &rows);
    // The textbook form's rows decide the textbook verdict; the safe form has none here.
    let safe = conclusion(&s, "4.11", "same error as CSM");
    assert_eq!((safe.form.as_str(), safe.ours_mse), ("safe", Verdict::NotMeasured), "{}", safe.evidence_mse);
    let err = conclusion_in_form(&s, "4.11", "same error as CSM", "textbook");
    assert_eq!(err.ours_mse, Verdict::Holds, "{}", err.evidence_mse);
    assert_eq!(err.ours_ref, Some(Verdict::Holds), "{}", err.evidence_ref);
    assert!(err.criterion.contains("sample=nearest"));
    let time = conclusion_in_form(&s, "4.11", "slower than CSM", "textbook");
    assert_eq!(time.ours_mse, Verdict::Holds, "{}", time.evidence_mse);
    assert!(time.criterion.contains("sample=nearest"));
    assert!(conclusion(&s, "4.9", "relaxed cone stepping beats").criterion.contains("sample=nearest"));
    let _ = std::fs::remove_dir_all(&dir);

    // The grids hold the cells these conclusions read.
    let grids = relief_runtime::sweep::grids::builtin(None);
    let cells = |name: &str| -> Vec<String> {
        grids.iter().find(|g| g.name == name).unwrap().cells.iter().map(|(p, _)| p.to_string()).collect()
    };
    for n in steps {
        assert!(
            cells("t4.11").contains(&format!("csm({n}, form=textbook, sample=nearest)+binary(5)")),
            "t4.11 csm({n}) nearest"
        );
    }
    for n in [5u32, 10, 15, 20, 25] {
        assert!(
            cells("t4.9").contains(&format!("csm({n}, form=textbook, sample=nearest)+binary(5)")),
            "t4.9 csm({n}) nearest"
        );
    }
    for n in [5u32, 10, 15, 20, 25, 30, 40, 50] {
        assert!(cells("t4.6").contains(&format!("csm({n}, form=textbook, sample=min4)")), "t4.6 csm({n}) min4");
    }
}

#[test]
fn rms_criteria_square_before_ratio_thresholds() {
    // RCNS 6% worse than RCS in RMS is 12.4% worse in squared error: not "within 10%".
    let mut rows = Vec::new();
    for n in [5u32, 8, 10, 15, 20, 30] {
        let e = 1e-4 / f64::from(n);
        rows.push(rowm(&format!("rcs({n})+binary(5)"), |m| with_err(m, e)));
        rows.push(rowm(&format!("rcns({n})+binary(5)"), |m| with_err(m, e * 1.06 * 1.06)));
    }
    // Table 4.3: the binary rows have 1.3× the linear rows' RMS, 1.69× their MSE: not
    // "similar" (at most 1.5× the squared error).
    for (n, k) in [(25u32, 3u32), (30, 4), (40, 5), (50, 7), (60, 8), (75, 10), (100, 14)] {
        rows.push(rowm(&format!("linear({n})"), |m| {
            with_err(m, 1e-4);
            with_ms(m, 0.9);
        }));
        rows.push(rowm(&format!("linear({k})+binary(2)"), |m| {
            with_err(m, 1e-4 * 1.69);
            with_ms(m, 0.5);
        }));
    }
    let (dir, s) = report_of("rms", &rows);
    for (t, part) in [("4.12", "same error as relaxed"), ("4.3", "Two binary steps")] {
        let c = conclusion(&s, t, part);
        assert_eq!(c.ours_mse, Verdict::DoesNotHold, "{t}: {}", c.evidence_mse);
        assert_eq!(c.ours_ref, Some(Verdict::DoesNotHold), "{t}: {}", c.evidence_ref);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A deterministic pseudo-random number in [0, 1) (64-bit LCG).
fn lcg(state: &mut u64) -> f64 {
    *state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    (*state >> 11) as f64 / (1u64 << 53) as f64
}

#[test]
fn every_error_criterion_agrees_when_the_rms_is_the_root_of_the_mse() {
    // Every cell of the dissertation grid, errors spread over three decades and with
    // ref_err_t_rms = sqrt(mse): a criterion whose thresholds are converted for an RMS gives
    // the same verdict with both metrics, whatever the numbers. Several seeds, so that
    // ratios land near every threshold.
    let grids = relief_runtime::sweep::grids::builtin(None);
    let all = grids.iter().find(|g| g.name == "dissertation").unwrap();
    let mut seen = std::collections::HashSet::new();
    for seed in 1..=12u64 {
        let mut st = seed;
        let mut rows = Vec::new();
        for (p, _) in &all.cells {
            let text = p.to_string();
            if !seen.insert((seed, text.clone())) {
                continue;
            }
            let e = 1e-6 * 10f64.powf(3.0 * lcg(&mut st));
            let ms = 0.4 + 0.4 * lcg(&mut st);
            rows.push(rowm(&text, |m| {
                with_err(m, e);
                with_ms(m, ms);
            }));
        }
        let (dir, s) = report_of(&format!("agree{seed}"), &rows);
        for c in &s.conclusions {
            if let Some(v) = c.ours_ref {
                assert_eq!(
                    v, c.ours_mse,
                    "seed {seed}, {} {}: mse {} | ref {}",
                    c.table, c.claim, c.evidence_mse, c.evidence_ref
                );
            }
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}

#[test]
fn thresholds_other_than_the_common_share_say_why() {
    let (dir, s) = report_of("why", &linear_rows(true));
    for c in &s.conclusions {
        let text = &c.criterion;
        let other_pct = text
            .split(|ch: char| !(ch.is_ascii_digit() || ch == '%' || ch == '.'))
            .any(|w| w.ends_with('%') && w != "75%");
        let other = other_pct
            || text.contains('×')
            || text.contains("ρ")
            || text.contains("Spearman")
            || text.contains('[')
            || text.contains("every");
        if other {
            assert!(!c.why.trim().is_empty(), "{} '{}' has thresholds of its own and no reason", c.table, c.claim);
        }
    }
    let md = std::fs::read_to_string(dir.join("tables.md")).unwrap();
    assert!(md.contains("Thresholds: "));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_dissertations_headline_claims_are_checked() {
    // (a) Figures 4.10/4.11: linear + interval(3) is the most accurate for its frame time;
    // csm without refinement is fastest.
    let figure_rows = |linear_interval_wins: bool| -> Vec<Row> {
        let mut rows = Vec::new();
        for n in [5u32, 10, 15, 20, 25, 30, 35] {
            let x = f64::from(n);
            rows.push(rowm(&format!("csm({n})"), |m| {
                with_err(m, 1e-3 / x);
                with_ms(m, 0.30 + 0.01 * x);
            }));
            rows.push(rowm(&format!("linear({n})+interval(3)"), |m| {
                with_err(m, if linear_interval_wins { 1e-7 / x } else { 1e-4 / x });
                with_ms(m, 0.50 + 0.01 * x);
            }));
            rows.push(rowm(&format!("csm({n})+interval(3)"), |m| {
                with_err(m, if linear_interval_wins { 1e-5 / x } else { 1e-8 / x });
                with_ms(m, 0.52 + 0.01 * x);
            }));
            rows.push(rowm(&format!("linear({n})"), |m| {
                with_err(m, 1e-2 / x);
                with_ms(m, 0.35 + 0.01 * x);
            }));
        }
        rows
    };
    let (dir, s) = report_of("claim-a", &figure_rows(true));
    let c = conclusion(&s, "4.10/4.11", "interval mapping gives the best");
    assert_eq!(c.ours_mse, Verdict::Holds, "{}", c.evidence_mse);
    assert_eq!(c.ours_ref, Some(Verdict::Holds), "{}", c.evidence_ref);
    assert_eq!(c.diss, Verdict::Holds, "{}", c.evidence_diss);
    let _ = std::fs::remove_dir_all(&dir);
    let (dir, s) = report_of("claim-a2", &figure_rows(false));
    let c = conclusion(&s, "4.10/4.11", "interval mapping gives the best");
    assert_eq!(c.ours_mse, Verdict::DoesNotHold, "{}", c.evidence_mse);
    let _ = std::fs::remove_dir_all(&dir);

    // (b) Figure 4.8: CSM is the best coarse search without refinement.
    let f48 = |csm_wins: bool| -> Vec<Row> {
        let mut rows = Vec::new();
        for n in [5u32, 10, 15, 20, 25, 30, 35] {
            let x = f64::from(n);
            for (m_name, good) in [("csm", csm_wins), ("qcsm", !csm_wins)] {
                rows.push(rowm(&format!("{m_name}({n})"), |m| {
                    with_err(m, if good { 1e-5 / x } else { 1e-3 / x });
                    with_ms(m, 0.4 + 0.01 * x);
                }));
            }
            rows.push(rowm(&format!("rcs({n})"), |m| {
                with_err(m, 1e-2);
                with_ms(m, 0.45 + 0.01 * x);
            }));
        }
        rows
    };
    let (dir, s) = report_of("claim-b", &f48(true));
    let c = conclusion(&s, "4.8", "CSM is the best coarse search");
    assert_eq!(c.ours_mse, Verdict::Holds, "{}", c.evidence_mse);
    assert_eq!(c.ours_ref, Some(Verdict::Holds), "{}", c.evidence_ref);
    assert_eq!(c.diss, Verdict::Holds, "{}", c.evidence_diss);
    let _ = std::fs::remove_dir_all(&dir);
    let (dir, s) = report_of("claim-b2", &f48(false));
    let c = conclusion(&s, "4.8", "CSM is the best coarse search");
    assert_eq!(c.ours_mse, Verdict::DoesNotHold, "{}", c.evidence_mse);
    let _ = std::fs::remove_dir_all(&dir);

    // (c) §4.3.1: min-of-4 sampling costs more frame time than linear sampling.
    let min4 = |slower: bool| -> Vec<Row> {
        let mut rows = Vec::new();
        for n in [5u32, 10, 15, 20, 25, 30, 40, 50] {
            rows.push(rowm(&format!("csm({n}, form=textbook)"), |m| with_ms(m, 0.5)));
            rows.push(rowm(&format!("csm({n}, form=textbook, sample=min4)"), |m| {
                with_ms(m, if slower { 0.6 } else { 0.4 })
            }));
        }
        rows
    };
    let (dir, s) = report_of("claim-c", &min4(true));
    // Min-of-4 is a sampling of the textbook form's texel map: the safe form has none.
    assert_eq!(conclusion(&s, "§4.3.1", "minimum of four texels").ours_mse, Verdict::NotMeasured);
    let c = conclusion_in_form(&s, "§4.3.1", "minimum of four texels", "textbook");
    assert_eq!(c.ours_mse, Verdict::Holds, "{}", c.evidence_mse);
    assert_eq!(c.ours_ref, None, "a frame-time claim");
    assert_eq!(c.diss, Verdict::NotMeasured, "the dissertation prints no min-of-4 timing: {}", c.evidence_diss);
    let _ = std::fs::remove_dir_all(&dir);
    let (dir, s) = report_of("claim-c2", &min4(false));
    assert_eq!(conclusion_in_form(&s, "§4.3.1", "minimum of four texels", "textbook").ours_mse, Verdict::DoesNotHold);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn stability_table_is_html_and_strip_frames_are_captioned() {
    let dir = fresh_dir("html");
    let rows = vec![row("linear(5)", 0.45, 0.02, 0.1, 0.01), row("linear(10)", 0.5, 0.01, 0.05, 0.0)];
    write_rows(&dir, &rows, true);
    std::fs::create_dir_all(dir.join("stability")).unwrap();
    std::fs::write(
        dir.join("stability/worst.md"),
        "# Worst condition per method\n\nOne line of prose.\n\n| method | worst scene | nan_count |\n|---|---|---|\n| `csm(5)` | lion \\| steep | 3 |\n",
    )
    .unwrap();
    let s = report::write(&dir).expect("report");
    assert_eq!(s.rows, 2);
    let html = std::fs::read_to_string(dir.join("index.html")).unwrap();
    let stab = &html[html.find("id=\"stability\"").expect("stability section")..];
    let stab = &stab[..stab.find("id=\"conclusions\"").unwrap_or(stab.len())];
    assert!(!stab.contains("<pre>"), "{stab}");
    assert!(stab.contains("<th>method</th><th>worst scene</th><th>nan_count</th>"), "{stab}");
    assert!(stab.contains("<td><code>csm(5)</code></td><td>lion | steep</td><td>3</td>"), "{stab}");
    assert!(!stab.contains("|---|"));
    // The per-method table is folded.
    assert!(stab.contains("<details id=\"stability-worst\"><summary>"), "{stab}");
    // Each frame of Table 4.1's strip carries its pipeline, frame time, t error and share of rays that skipped geometry.
    let expect = format!(
        "<figcaption>#2 <code>linear(10)</code><br>{:.3} ms (median; mean {:.3}) · t error {:.3e} (RMS) · skipped {:.4} · MSE mean {:.3e} · 32²</figcaption>",
        0.5,
        0.5,
        0.05,
        0.0,
        0.01 / 1024.0,
    );
    assert!(html.contains(&expect), "{expect} missing");
    // Frame and error side by side, each a link to its full-size PNG.
    let cell = "cells/lion/linear_10";
    assert!(
        html.contains(&format!("<a href=\"{cell}/frame.png\"><img src=\"{cell}/frame.png\""))
            && html.contains(&format!("<a href=\"{cell}/error.png\"><img src=\"{cell}/error.png\"")),
        "frames shown and linked"
    );
    let md = std::fs::read_to_string(dir.join("tables.md")).unwrap();
    assert!(md.contains("- 2. linear(10): 0.500 ms (median; mean 0.500)"), "captions in tables.md");
    let _ = std::fs::remove_dir_all(&dir);
}

// ---------------------------------------------------------------------------------------
// The answer first.

/// A row of `pipeline` on `scene` with frame time `ms` (median and mean) and RMS t error `t`.
fn answer_row(scene: &str, pipeline: &str, ms: f64, t: f64) -> Row {
    let mut r = row(pipeline, ms, t * t * 1024.0, t, 0.0);
    r.metrics.scene = scene.into();
    r.cell_dir = format!(
        "cells/{}/{}",
        scene.trim_start_matches("scene:").replace(['@', '=', ','], "_"),
        relief_dsl::spec::file_safe(pipeline)
    );
    r
}

/// The rows of the answer tests: on rocks at its own view, the engine family and safe
/// methods with known times and errors, plus rows that must not compete; at 70°, no
/// engine-family row.
fn answer_rows() -> Vec<Row> {
    let rocks = "scene:rocks";
    let mut rows = vec![
        answer_row(rocks, "linear_dynamic(1, 16)+binary(5)", 1.0, 2e-2),
        answer_row(rocks, "linear_dynamic(1, 64)+binary(5)", 2.0, 5e-3),
        answer_row(rocks, "linear_dynamic(1, 256)+interval(1)", 6.0, 5e-4),
        answer_row(rocks, "csm(16)", 1.5, 8e-3),
        answer_row(rocks, "qcsm(32)", 2.5, 2e-4),
        answer_row(rocks, "csm(64)", 3.0, 3e-8),
        // Faster and exact, but with a shadow stage, at another level, or clipped: not searches
        // that compete.
        answer_row(rocks, "linear(8)+binary(5)+shadow=hard(8)", 0.1, 0.0),
        answer_row(rocks, "linear(8)+binary(5)+lod=auto", 0.1, 0.0),
        answer_row(rocks, "linear(8)+binary(5)+silhouette=clip", 0.1, 0.0),
        // Outside the family: a minimum of 8 layers, and interval with more than one step.
        answer_row(rocks, "linear_dynamic(8, 32)+binary(5)", 1.8, 4e-3),
        answer_row(rocks, "linear_dynamic(1, 32)+interval(2)", 1.9, 3e-3),
        // No finite frame time: left out and named.
        answer_row(rocks, "sphere(16)", f64::NAN, 1e-3),
    ];
    let at70 = "scene:rocks@angle=70";
    rows.push(answer_row(at70, "csm(16)", 1.2, 2e-2));
    rows.push(answer_row(at70, "csm(64)", 2.4, 1e-8));
    rows
}

/// The cells of a Markdown table line.
fn md_line_cells(line: &str) -> Vec<String> {
    line.trim().trim_matches('|').split('|').map(|c| c.trim().to_string()).collect()
}

#[test]
fn the_answer_names_the_fastest_pipeline_at_each_accuracy_and_the_engine_familys_ratio() {
    let rows = answer_rows();
    let (dir, _) = {
        let dir = fresh_dir("answer");
        write_rows(&dir, &rows, true);
        let s = report::write(&dir).expect("report");
        (dir, s)
    };
    let md = std::fs::read_to_string(dir.join("tables.md")).unwrap();
    let section = |title: &str| -> Vec<Vec<String>> {
        let start = md.find(title).unwrap_or_else(|| panic!("{title} missing from\n{md}"));
        md[start..]
            .lines()
            .skip_while(|l| !l.starts_with("| accuracy"))
            .skip(2)
            .take_while(|l| l.starts_with('|'))
            .map(md_line_cells)
            .collect()
    };
    let own = section("### Fastest at each accuracy: rocks, 45°, 32²");
    assert_eq!(own.len(), 5, "{own:?}");
    // Level 3e-2: the family's linear_dynamic(1, 16)+binary(5) is the fastest of all.
    assert_eq!(own[0][1], "`linear_dynamic(1, 16)+binary(5)`");
    assert_eq!(own[0][10], "1× (the fastest is in the family)");
    // 1e-2: csm(16) at 1.5 ms; the family's best there is linear_dynamic(1, 64)+binary(5) at
    // 2.0 ms: 2.0 / 1.5 = 1.33. linear_dynamic(8, 32) and interval(2) are not the family.
    assert_eq!((own[1][1].as_str(), own[1][2].as_str()), ("`csm(16)`", "1.500"));
    assert_eq!((own[1][6].as_str(), own[1][7].as_str()), ("`linear_dynamic(1, 64)+binary(5)`", "2.000"));
    assert_eq!(own[1][10], "1.33×");
    // 1e-3: linear_dynamic(1, 32)+interval(2) (1.9 ms, 3e-3) does not reach it; qcsm(32) at
    // 2.5 ms does; the family gets there with 256 layers at 6.0 ms: 2.40×. The shadow, lod and
    // silhouette rows (0.1 ms, exact) never compete.
    assert_eq!(own[2][1], "`qcsm(32)`");
    assert_eq!(own[2][6], "`linear_dynamic(1, 256)+interval(1)`");
    assert_eq!(own[2][10], "2.40×");
    // 1e-6: only csm(64); the family never gets there although it was measured.
    assert_eq!(own[3][1], "`csm(64)`");
    assert_eq!(own[3][6], "unreachable");
    assert_eq!(own[3][10], "family unreachable");
    assert!(md.contains("Left out, their error or frame time is not a finite number: `sphere(16)`."));
    // At 70° no row of the family was measured: "not measured", not "unreachable".
    let at70 = section("### Fastest at each accuracy: rocks, 70°, 32²");
    assert_eq!(at70[0][1], "`csm(16)`");
    assert_eq!(at70[0][6], "not measured");
    assert_eq!(at70[0][10], "family not measured");
    assert_eq!(at70[1][1], "`csm(64)`");

    // The page: the answer comes first, its overview table before any other section, one row
    // per scene and view, each linking to its own section.
    let html = std::fs::read_to_string(dir.join("index.html")).unwrap();
    let at = |needle: &str| html.find(needle).unwrap_or_else(|| panic!("{needle} missing"));
    assert!(at("id=\"answer-table\"") < at("<section id=\"conclusions\""));
    let overview = &html[at("id=\"answer-table\"")..];
    let overview = &overview[..overview.find("</table>").unwrap()];
    assert_eq!(
        overview.matches("<tr><td><a href=\"#answer-").count()
            + overview.matches("<tr class=\"unmeasured\"><td><a href=\"#answer-").count(),
        2,
        "{overview}"
    );
    assert!(overview.contains("<code>csm(16)</code> 1.500 ms<span class=\"fam\"><span title=\"the engine family's fastest here: linear_dynamic(1, 64)+binary(5)\">family: 1.33×</span></span>"), "{overview}");
    // The scene's picture: its height map (at least 256 pixels) and the exact row's frame.
    let map = image::open(dir.join("report/scene_rocks.png")).expect("height map").to_luma8();
    assert!(map.width() >= 256 && map.height() >= 256);
    let rocks = relief_runtime::scene_from_arg("scene:rocks").unwrap();
    let k = map.width() as usize / rocks.height.width;
    for (x, y) in [(0usize, 0usize), (17, 99), (255, 128)] {
        let want = (rocks.height.data[y * rocks.height.width + x] * 255.0).round() as u8;
        assert_eq!(map.get_pixel((x * k) as u32, (y * k) as u32).0[0], want, "texel ({x}, {y})");
    }
    assert!(html.contains("exact: 3.000 ms · t error 3.000e-8"), "the fastest exact row's frame");
    // The chart: numbered points keyed beside it, every number drawn.
    let svg = std::fs::read_to_string(dir.join("report/answer_rocks_s32.svg")).expect("answer chart");
    assert!(svg.contains("(log scale)"));
    let key = &html[at("<ol class=\"key\">")..];
    let key = &key[..key.find("</ol>").unwrap()];
    assert!(key.contains("<code>csm(64)</code> 3.000 ms"), "{key}");
    assert!(!key.contains("no room"), "{key}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The last level, "skips no geometry and t error ≤ 1e-2", is `skipped_rate` exactly 0 and
/// `ref_err_t_rms` at most 1e-2: the fastest row there is chosen among those only (a search
/// that stops early, skipping nothing but far short, does not win it), and a family whose
/// every row skips some geometry is "unreachable" there.
#[test]
fn the_skips_no_geometry_level_keeps_only_rows_with_skipped_rate_zero_and_a_small_t_error() {
    let rocks = "scene:rocks";
    // (pipeline, ms, t error, skipped_rate)
    let cells = [
        // The fastest row, and in the family, but one ray in a hundred skips geometry.
        ("linear_dynamic(1, 16)+binary(5)", 1.0, 2e-2, 1e-2),
        ("linear_dynamic(1, 256)+interval(1)", 6.0, 5e-4, 1e-4),
        // Faster than csm(16) and more accurate, but it skips: not chosen.
        ("rcs(8)+binary(5)", 1.2, 4e-3, 1e-2),
        // No share measured: a NaN never reaches the level.
        ("linear(8)+binary(5)", 0.5, 3e-2, f64::NAN),
        // Skips nothing and is the fastest of all, but stops early: t error 0.1 > 1e-2.
        ("rcs(2)+binary(1)", 0.3, 1e-1, 0.0),
        // Skips nothing, t error just over the bound: not chosen.
        ("csm(8)", 1.1, 1.1e-2, 0.0),
        // The fastest that skips nothing with t error ≤ 1e-2, larger than rcs(8)'s.
        ("csm(16)", 1.5, 8e-3, 0.0),
        ("csm(64)", 3.0, 3e-8, 0.0),
    ];
    let rows: Vec<Row> = cells
        .iter()
        .map(|&(p, ms, t, skipped)| {
            let mut r = answer_row(rocks, p, ms, t);
            r.metrics.skipped_rate = skipped;
            r
        })
        .collect();
    let dir = fresh_dir("answer-skips");
    write_rows(&dir, &rows, false);
    report::write(&dir).expect("report");
    let md = std::fs::read_to_string(dir.join("tables.md")).unwrap();
    let start = md.find("### Fastest at each accuracy: rocks, 45°, 32²").expect("the answer's table");
    let table: Vec<Vec<String>> = md[start..]
        .lines()
        .skip_while(|l| !l.starts_with("| accuracy"))
        .skip(2)
        .take_while(|l| l.starts_with('|'))
        .map(md_line_cells)
        .collect();
    assert_eq!(table.len(), 5, "{table:?}");
    let last = &table[4];
    assert_eq!(last[0], "skips no geometry and t error ≤ 1e-2 (skipped_rate = 0)", "placed last and named");
    assert_eq!((last[1].as_str(), last[2].as_str()), ("`csm(16)`", "1.500"));
    assert_eq!(last[6], "unreachable", "every family row skips some geometry");
    assert_eq!(last[10], "family unreachable");
    // The RMS levels still take the skipping rows: at 1e-2 rcs(8)+binary(5) is the fastest.
    assert_eq!(table[1][1], "`rcs(8)+binary(5)`");
    // The page's overview has the level as its last column, the pick's t error beside it
    // (the level does not bound it).
    let html = std::fs::read_to_string(dir.join("index.html")).unwrap();
    let overview = &html[html.find("id=\"answer-table\"").expect("overview")..];
    let overview = &overview[..overview.find("</table>").unwrap()];
    assert!(overview.contains("<th>skips no geometry and t error ≤ 1e-2 (skipped_rate = 0)</th></tr>"), "{overview}");
    // The table says what the level asks.
    assert!(md[start..].contains("no ray that skipped geometry and an RMS t error ≤ 1e-2"), "{md}");
    assert!(
        overview.contains("<td><code>csm(16)</code> 1.500 ms · t error 8.000e-3<span class=\"fam\">family unreachable</span></td></tr>"),
        "{overview}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Under paired timing the answer ranks by each row's ratio to the baseline, not by the
/// medians of separate runs, and the family's multiple is the quotient of two ratios with its
/// interval: decided where the interval clears 1, "not decided" where it reaches 1. One row
/// timed alone puts its scene back on medians.
#[test]
fn the_answer_ranks_by_paired_ratios_and_says_not_decided_where_the_interval_reaches_one() {
    let rocks = "scene:rocks";
    // (pipeline, median ms, ratio, lo, hi, t error)
    let cells = [
        ("linear_dynamic(1, 16)+binary(5)", 1.0, 1.00, 0.98, 1.02, 2e-2),
        // csm(16)'s median is the slower of the two, its paired ratio the faster.
        ("csm(16)", 1.8, 1.10, 1.08, 1.12, 8e-3),
        ("linear_dynamic(1, 64)+binary(5)", 1.5, 1.20, 1.17, 1.23, 5e-3),
        ("qcsm(32)", 2.0, 1.60, 1.55, 1.65, 2e-4),
        ("linear_dynamic(1, 256)+interval(1)", 3.0, 1.65, 1.55, 1.75, 5e-4),
        ("csm(64)", 2.5, 2.00, 1.96, 2.04, 3e-8),
    ];
    let mut rows: Vec<Row> = cells
        .iter()
        .map(|&(p, ms, r, lo, hi, t)| {
            let mut row = answer_row(rocks, p, ms, t);
            with_ratio(&mut row.metrics, r, lo, hi);
            row
        })
        .collect();
    // At 70°: the same two rows, one of them timed alone.
    let at70 = "scene:rocks@angle=70";
    let mut timed = answer_row(at70, "csm(16)", 1.8, 8e-3);
    with_ratio(&mut timed.metrics, 1.10, 1.08, 1.12);
    rows.push(timed);
    rows.push(answer_row(at70, "linear_dynamic(1, 64)+binary(5)", 1.5, 5e-3));
    let dir = fresh_dir("answer-paired");
    write_rows(&dir, &rows, false);
    report::write(&dir).expect("report");
    let md = std::fs::read_to_string(dir.join("tables.md")).unwrap();
    let section = |title: &str| -> Vec<Vec<String>> {
        let start = md.find(title).unwrap_or_else(|| panic!("{title} missing from\n{md}"));
        md[start..]
            .lines()
            .skip_while(|l| !l.starts_with("| accuracy"))
            .skip(2)
            .take_while(|l| l.starts_with('|'))
            .map(md_line_cells)
            .collect()
    };
    let own = section("### Fastest at each accuracy: rocks, 45°, 32²");
    assert_eq!(own[0][10], "1× (the fastest is in the family)");
    // 1e-2: csm(16) by its ratio 1.10 (its median, 1.8 ms, is above the family's 1.5 ms).
    assert_eq!(
        (own[1][1].as_str(), own[1][2].as_str(), own[1][3].as_str()),
        ("`csm(16)`", "1.800", "1.100 [1.080, 1.120]")
    );
    assert_eq!(own[1][6], "`linear_dynamic(1, 64)+binary(5)`");
    // 1.20 / 1.10 = 1.09; the log half-widths (0.0092 and 0.0125 in ln, over t(0.975, 19))
    // add in quadrature: the interval is about [1.06, 1.12], clear of 1.
    assert!(own[1][10].starts_with("1.09× [1.0") && !own[1][10].contains("not decided"), "{}", own[1][10]);
    let bounds: Vec<f64> = own[1][10]
        .trim_start_matches("1.09× [")
        .trim_end_matches(']')
        .split(", ")
        .map(|x| x.parse().unwrap())
        .collect();
    assert!(bounds[0] > 1.04 && bounds[0] < 1.08 && bounds[1] > 1.10 && bounds[1] < 1.14, "{bounds:?}");
    // 1e-3: qcsm(32) at 1.60 against the family's 1.65: 3 % apart with intervals of ±3 % and
    // ±6 %: not decided.
    assert_eq!((own[2][1].as_str(), own[2][6].as_str()), ("`qcsm(32)`", "`linear_dynamic(1, 256)+interval(1)`"));
    assert!(own[2][10].starts_with("not decided: 1.03× ["), "{}", own[2][10]);
    // The rows not told apart from the fastest: at 1e-3 the family's 256 layers (1.03×, its
    // interval reaches 1), not csm(64) (1.25× [1.20, 1.30]); at 1e-2 none (1.09×, decided).
    assert_eq!(own[2][11], "`linear_dynamic(1, 256)+interval(1)`");
    assert_eq!(own[1][11], "—");
    assert!(md.contains("timed in alternating blocks"), "the note says how rows are timed");
    // At 70° one row has no ratio: medians rank, the ratio is a point, the column is empty.
    let a70 = section("### Fastest at each accuracy: rocks, 70°, 32²");
    assert_eq!((a70[1][1].as_str(), a70[1][3].as_str()), ("`linear_dynamic(1, 64)+binary(5)`", "—"));
    assert_eq!(a70[0][1], "`linear_dynamic(1, 64)+binary(5)`");
    let html = std::fs::read_to_string(dir.join("index.html")).unwrap();
    assert!(
        html.contains("<code>csm(16)</code> 1.800 ms · 1.10× baseline<span class=\"fam\"><span title=\"the engine family's fastest here: linear_dynamic(1, 64)+binary(5)\">family: 1.09× ["),
        "overview cell"
    );
    assert!(html.contains("<span title=\"not told apart from the fastest in this run (95 %): linear_dynamic(1, 256)+interval(1)\">≈ 1 other</span>"), "overview ties");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The page holds together: no external resource, every in-page link has its target, ids
/// are unique, tables are folded, sortable and filterable, both colour schemes are styled.
#[test]
fn the_page_is_self_contained_and_every_in_page_link_lands() {
    let dir = fresh_dir("page");
    let mut rows = linear_rows(true);
    rows.extend(answer_rows());
    write_rows(&dir, &rows, true);
    std::fs::create_dir_all(dir.join("stability")).unwrap();
    std::fs::write(dir.join("stability/worst.md"), "| method | worst |\n|---|---|\n| `csm(5)` | lion |\n").unwrap();
    std::fs::write(dir.join("stability/stability_nan_count.svg"), "<svg xmlns=\"http://www.w3.org/2000/svg\"/>")
        .unwrap();
    report::write(&dir).expect("report");
    let html = std::fs::read_to_string(dir.join("index.html")).unwrap();
    for bad in ["src=\"http", "href=\"http", "src=\"//", "href=\"//", "@import", "url(http"] {
        assert!(!html.contains(bad), "external resource: {bad}");
    }
    let attr = |name: &str| -> Vec<String> {
        let pat = format!("{name}=\"");
        html.match_indices(&pat).map(|(i, _)| html[i + pat.len()..].split('"').next().unwrap().to_string()).collect()
    };
    let ids = attr("id");
    for (i, id) in ids.iter().enumerate() {
        assert!(!ids[..i].contains(id), "id `{id}` twice");
    }
    let links: Vec<String> = attr("href").into_iter().filter(|h| h.starts_with('#')).collect();
    for want in [
        "#answer",
        "#answer-scene-rocks-angle-70-s32",
        "#conclusions",
        "#tables",
        "#table-4-1-performance-of-linear-search-lion",
    ] {
        assert!(links.iter().any(|l| l == want), "no link {want}: {links:?}");
    }
    for l in &links {
        assert!(ids.contains(&l[1..].to_string()), "link {l} has no target");
    }
    // Files the page links to exist.
    for f in attr("href").into_iter().chain(attr("src")).filter(|h| !h.starts_with('#') && !h.starts_with("data:")) {
        assert!(dir.join(&f).exists(), "{f} linked but missing");
    }
    // Every table of the tables section is folded, sortable and has a filter.
    let tables = &html[html.find("<section id=\"tables\"").unwrap()..];
    let tables = &tables[..tables.find("</section>").unwrap()];
    let n = tables.matches("<table class=\"sortable\"").count();
    assert!(n >= 15, "{n}");
    assert_eq!(tables.matches("<details id=").count(), n, "each table folded");
    assert!(!tables.contains("<details id=\"table-4-1") || !tables.contains(" open>"), "folded by default");
    assert_eq!(tables.matches("<input class=\"filter\"").count(), n);
    // The stylesheet and script are the files under web/, embedded.
    assert!(html.contains(include_str!("../web/report.css")) && html.contains(include_str!("../web/report.js")));
    assert!(include_str!("../web/report.css").contains("prefers-color-scheme: dark"));
    // Verdicts are badges.
    assert!(html.contains("<span class=\"badge holds\">holds</span>"));
    // Stability: the heat maps before the folded per-method table.
    let stab = &html[html.find("<section id=\"stability\"").unwrap()..];
    assert!(
        stab.find("stability/stability_nan_count.svg").unwrap() < stab.find("<details id=\"stability-worst\"").unwrap()
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A row timed against the baseline: ratio `r` with its 95 % interval `[lo, hi]`.
fn with_ratio(m: &mut Metrics, r: f64, lo: f64, hi: f64) {
    m.baseline = "linear(32)+binary(5)".into();
    m.frame_ratio_to_baseline = Some(r);
    m.frame_ratio_to_baseline_lo = Some(lo);
    m.frame_ratio_to_baseline_hi = Some(hi);
    m.timing_pairs = 20;
}

/// Table 4.5's twelve cells: interval(k) and binary(k) after linear(10), k = 1…6, with the
/// given ratios to the baseline (interval's, binary's) and a half-width in log units.
fn t45_rows(interval: f64, binary: f64, half: f64) -> Vec<Row> {
    let mut rows = Vec::new();
    for k in 1..=6u32 {
        for (refine, r) in [("interval", interval), ("binary", binary)] {
            rows.push(rowm(&format!("linear(10)+{refine}({k})"), |m| {
                // Mean frame times that say the opposite: the ratios must be what is read.
                with_ms(m, if refine == "interval" { 0.4 } else { 0.6 });
                with_ratio(m, r, r * (-half).exp(), r * half.exp());
                m.simd32_fetches = if refine == "interval" { 14.0 } else { 12.0 };
            }));
        }
    }
    rows
}

#[test]
fn timing_criteria_read_the_paired_ratios_and_are_not_decided_when_the_intervals_straddle() {
    // Separated intervals: interval(k) is decidedly slower (1.30 vs 1.00, ±3 %).
    let (dir, s) = report_of("ratio-decided", &t45_rows(1.30, 1.00, 0.03));
    let c = conclusion(&s, "4.5", "costs more frame time");
    assert_eq!(c.ours_mse, Verdict::Holds, "{}", c.evidence_mse);
    assert!(c.evidence_mse.contains("paired ratios"), "{}", c.evidence_mse);
    // The model judges it on simd32_fetches (14 > 12): holds too, labelled.
    assert_eq!(c.model, Some(Verdict::Holds), "{}", c.evidence_model);
    assert!(c.evidence_model.contains("model"), "{}", c.evidence_model);
    // An error criterion reads no frame time: no model verdict.
    assert_eq!(conclusion(&s, "4.5", "lower error").model, None);
    let md = std::fs::read_to_string(dir.join("tables.md")).unwrap();
    let (h, row) = md_row(&md, "## Table 4.5", "linear(10)+interval(3)");
    assert_eq!(
        row[col(&h, "frame ÷ baseline (95 %)")],
        format!("1.300 [{:.3}, {:.3}]", 1.3 * (-0.03f64).exp(), 1.3 * 0.03f64.exp())
    );
    assert_eq!(row[col(&h, "simd32 fetches (model)")], "14.00");
    let _ = std::fs::remove_dir_all(&dir);

    // 3 % apart with ±10 % intervals: the quotient's interval holds 1, not decided.
    let (dir, s) = report_of("ratio-open", &t45_rows(1.03, 1.00, 0.10));
    let c = conclusion(&s, "4.5", "costs more frame time");
    assert_eq!(c.ours_mse, Verdict::NotDecided, "{}", c.evidence_mse);
    assert!(c.evidence_mse.contains("6 not decided"), "{}", c.evidence_mse);
    let _ = std::fs::remove_dir_all(&dir);

    // Decidedly faster: does not hold.
    let (dir, s) = report_of("ratio-no", &t45_rows(0.80, 1.00, 0.03));
    assert_eq!(conclusion(&s, "4.5", "costs more frame time").ours_mse, Verdict::DoesNotHold);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn rows_from_several_folders_merge_and_each_adapters_timing_verdicts_sit_side_by_side() {
    // Two machines: on A interval is decidedly slower, on B decidedly faster.
    let (a, b) = (fresh_dir("adapter-a"), fresh_dir("adapter-b"));
    let named = |rows: Vec<Row>, adapter: &str| -> Vec<Row> {
        rows.into_iter()
            .map(|mut r| {
                r.metrics.adapter = adapter.into();
                r
            })
            .collect()
    };
    // A has more rows (Table 4.1's too): it is the adapter the tables show.
    let mut rows_a = named(t45_rows(1.30, 1.00, 0.03), "GPU A (driver 1)");
    let timed_linear = linear_rows(true).into_iter().map(|mut r| {
        with_ratio(&mut r.metrics, 1.0, 0.97, 1.03);
        r
    });
    rows_a.extend(named(timed_linear.collect(), "GPU A (driver 1)"));
    write_rows(&a, &rows_a, true);
    write_rows(&b, &named(t45_rows(0.80, 1.00, 0.03), "GPU B (driver 2)"), false);
    let out = fresh_dir("adapter-merged");
    let s = report::write_many(&[a.clone(), b.clone()], &out).expect("merged report");
    assert_eq!(s.rows, rows_a.len() + 12);
    assert_eq!(s.adapters, ["GPU A (driver 1)", "GPU B (driver 2)"]);
    assert_eq!(conclusion(&s, "4.5", "costs more frame time").ours_mse, Verdict::Holds, "the tables' adapter is A");
    let md = std::fs::read_to_string(out.join("tables.md")).unwrap();
    let sec = &md[md.find("## Timing conclusions per adapter").expect("per-adapter section")..];
    let header = sec.lines().find(|l| l.starts_with("| table |")).unwrap();
    assert!(
        header.contains("GPU A (driver 1)") && header.contains("GPU B (driver 2)") && header.contains("model"),
        "{header}"
    );
    let line = sec.lines().find(|l| l.contains("costs more frame time")).unwrap();
    let cells: Vec<&str> = line.trim_matches('|').split(" | ").map(str::trim).collect();
    assert!(cells[2].starts_with("holds") && cells[3].starts_with("does not hold"), "{line}");
    // Merged rows are written to the new folder, and the strips find A's images there.
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    assert_eq!(csv.lines().count(), rows_a.len() + 12 + 1);
    assert!(
        std::fs::read_dir(out.join("report")).unwrap().any(|e| e
            .unwrap()
            .file_name()
            .to_string_lossy()
            .starts_with("strip_")),
        "strips from the merged folders' images"
    );
    for d in [a, b, out] {
        let _ = std::fs::remove_dir_all(&d);
    }
}

/// Lion's rows under the names a sweep at the dissertation's view gives them: the view's
/// scene label, the pipeline with the view's `lod=auto`.
fn at_the_view(rows: Vec<Row>) -> impl Iterator<Item = Row> {
    rows.into_iter().map(|mut r| {
        r.metrics.scene = "scene:lion@view=dissertation".into();
        r.metrics.pipeline.lod = relief_dsl::spec::Lod::Auto;
        r.cell_dir = format!("cells/lion_view/{}", relief_dsl::spec::file_safe(&r.metrics.pipeline.to_string()));
        r
    })
}

/// Rows of Table 4.1 on Lion at its own view (the error falls as 1/N²: K = 3N²·MSE flat at
/// 3) and at the dissertation's (the error rises with N), under the names a sweep gives
/// them: the view's scene label, the pipeline with the view's `lod=auto`.
#[test]
fn the_report_shows_verdicts_at_both_views_and_the_pre_asymptotic_note() {
    let dir = fresh_dir("views");
    let mut rows = linear_rows(true);
    rows.extend(at_the_view(linear_rows(false)));
    write_rows(&dir, &rows, false);
    report::write(&dir).expect("report");
    let md = std::fs::read_to_string(dir.join("tables.md")).unwrap();
    let section = &md[md.find("Conclusions at the dissertation's view").expect("the views section")..];
    let line =
        section.lines().find(|l| l.contains("More linear steps lower the error.")).expect("Table 4.1's error claim");
    assert!(line.contains("| holds / holds | does not hold / does not hold | changes |"), "{line}");
    // The table at the dissertation's view is found under the view's lod (the rows say
    // `+lod=auto`), and its K rises: 3N²·N²·1e-4 from N = 30 to 40.
    let at_view = &md[md.find("scene lion@view=dissertation").expect("Table 4.1 at the view")..];
    assert!(
        at_view.contains("Pre-asymptotic: K = 3N²·MSE of linear search still rises"),
        "{}",
        &at_view[..at_view.len().min(2000)]
    );
    assert!(
        at_view.contains(
            "Avg coarse steps: the stand-in takes 0.00·N on average over these rows, the dissertation's Lion 0.6"
        ),
        "Lion's step note"
    );
    let own = &md[md.find("# Table 4.1").or_else(|| md.find("Table 4.1")).unwrap()
        ..md.find("scene lion@view=dissertation").unwrap()];
    assert!(!own.contains("Pre-asymptotic"), "K = 3 at every N on the own view: no note");
}

/// The conclusions at both views carry the regime note where K = 3N²·MSE still rises, and
/// only there: Lion's own view falls as 1/N² (per-ray MSE 1/(1024·N²): K = 3/1024 at every
/// N, flat), the dissertation's view rises as N²·1e-4/1024 (K = 3·30⁴·1e-4/1024 = 0.237 at
/// N = 30, 3·40⁴·1e-4/1024 = 0.750 at N = 40). A criterion measured at one view only (CSM's safe form, which the view's
/// `lod=auto` leaves out) is marked so, not as a change.
#[test]
fn the_view_conclusions_note_the_pre_asymptotic_view_and_one_view_verdicts() {
    let dir = fresh_dir("views-regime");
    let mut rows = linear_rows(true);
    for n in [5u32, 10, 15, 20] {
        let e = 1e-3 / n as f64;
        rows.push(row(&format!("csm({n})"), 0.5, e, e.sqrt(), 0.0));
    }
    rows.extend(at_the_view(linear_rows(false)));
    write_rows(&dir, &rows, false);
    report::write(&dir).expect("report");
    let md = std::fs::read_to_string(dir.join("tables.md")).unwrap();
    let start = md.find("## Conclusions at the dissertation's view").expect("the views section");
    let section = &md[start..];
    let section = &section[..section[3..].find("\n## ").map_or(section.len(), |i| i + 3)];
    assert!(
        section.contains(
            "lion at the dissertation's view: K = 3N²·MSE of linear search still rises (0.237 at N = 30, 0.750 at N = 40)"
        ),
        "{section}"
    );
    assert!(!section.contains("lion at its own view: K"), "K is flat at 3 on the own view: {section}");
    let safe = section
        .lines()
        .find(|l| l.contains("Cone step mapping has a lower error than linear search") && l.contains("`form=safe`"))
        .expect("Table 4.7's claim, safe form");
    assert!(safe.ends_with("| one view only |"), "{safe}");
    std::fs::remove_dir_all(&dir).ok();
}

/// The stability section with mesh cells (`relief stability`'s files written by
/// `stability::write`): their heat maps are shown, with the paragraph that says what they are,
/// and the mesh table is in the folded worst table; a folder whose stability run had no mesh
/// cells gives the same page as before this paragraph existed (no paragraph, no mesh maps).
#[test]
fn the_stability_section_shows_the_mesh_conditions_only_when_there_are_some() {
    use relief_runtime::stability::{self, Cell};
    let flat = super::stability::flat_cell("linear(8)", "scene:flat1", 60.0, 0.1);
    let mesh = Cell {
        method: "linear(32)+binary(5)+curved=prism".into(),
        scene: "torus:rocks".into(),
        angle: 89.0,
        rays: 400,
        coverage_error: Some(0.01),
        extra: Some(1),
        missing: Some(3),
        ..flat.clone()
    };
    let page = |cells: &[Cell], name: &str| {
        let dir = fresh_dir(name);
        write_rows(&dir, &[row("linear(5)", 0.45, 0.02, 0.1, 0.01)], true);
        stability::write(&dir.join("stability"), cells).unwrap();
        report::write(&dir).expect("report");
        let html = std::fs::read_to_string(dir.join("index.html")).unwrap();
        let stab = html[html.find("<section id=\"stability\"").expect("stability section")..].to_string();
        let _ = std::fs::remove_dir_all(&dir);
        stab[..stab.find("</section>").unwrap()].to_string()
    };
    let with = page(&[flat.clone(), mesh], "stab-mesh");
    let without = page(std::slice::from_ref(&flat), "stab-flat");
    assert!(with.contains("stability/stability_meshes_coverage_error.svg"), "{with}");
    assert!(with.contains("are the mesh conditions"), "{with}");
    assert!(
        with.contains(
            "<td><code>linear(32)+binary(5)+curved=prism</code></td><td>torus:rocks at 89°</td><td>1.00%</td>"
        ),
        "{with}"
    );
    assert!(!without.contains("meshes") && !without.contains("mesh conditions"), "{without}");
}
