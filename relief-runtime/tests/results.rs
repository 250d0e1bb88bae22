//! The results file as sweep and report read it: one reader, one cut-last-line rule.

use relief_runtime::metrics::Metrics;
use relief_runtime::results::{self, Row};

fn row(pipeline: &str, t_rms: f64) -> Row {
    Row {
        grid: "g".into(),
        metrics: Metrics {
            pipeline: pipeline.into(),
            scene: "scene:lion".into(),
            size: 16,
            ref_err_t_rms: t_rms,
            ..Default::default()
        },
        status: "ok".into(),
        ..Default::default()
    }
}

fn fresh_dir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("relief-results-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn a_cut_last_line_is_dropped_by_both_readers_and_only_the_appender_truncates() {
    let dir = fresh_dir("cut");
    let rows = [row("linear(10)", 0.5), row("linear(20)", f64::NAN), row("linear(30)", 0.25)];
    for r in &rows {
        results::append(&dir, r).unwrap();
    }
    let jsonl = dir.join("results.jsonl");
    let complete = std::fs::read_to_string(&jsonl).unwrap();
    assert_eq!(complete.lines().count(), 3);
    // What a kill in the middle of a write leaves.
    std::fs::write(&jsonl, format!("{complete}{{\"grid\":\"g\",\"pipeline\":\"lin")).unwrap();

    let read = results::read(&dir).unwrap();
    assert_eq!(read.rows.len(), 3);
    assert_eq!(read.bad_lines.len(), 1, "{:?}", read.bad_lines);
    assert!(read.bad_lines[0].starts_with("line 4:"), "{:?}", read.bad_lines);
    // NaN is written as null and reads back as NaN, the other values exactly.
    assert!(read.rows[1].metrics.ref_err_t_rms.is_nan());
    assert_eq!(read.rows[0], rows[0]);
    assert_eq!(read.rows[2], rows[2]);
    // The report's reader leaves the file as it is ...
    assert!(std::fs::read_to_string(&jsonl).unwrap().len() > complete.len());
    // ... the appender cuts it back to its last complete line, then appends after it.
    let again = results::read_for_append(&dir).unwrap();
    assert_eq!(again.len(), 3);
    assert_eq!(std::fs::read_to_string(&jsonl).unwrap(), complete);
    results::append(&dir, &row("linear(40)", 0.125)).unwrap();
    assert_eq!(results::read(&dir).unwrap().rows.len(), 4);

    // The CSV holds a header and one line per row, columns in order, NaN empty.
    results::write_csv(&dir, &again).unwrap();
    let csv = std::fs::read_to_string(dir.join("results.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 4);
    assert_eq!(lines[0], results::COLUMNS.join(","));
    let t_col = results::COLUMNS.iter().position(|c| *c == "ref_err_t_rms").unwrap();
    let cell = |l: &str| l.split(',').nth(t_col).unwrap().to_string();
    assert_eq!((cell(lines[1]), cell(lines[2]), cell(lines[3])), ("0.5".into(), String::new(), "0.25".into()));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_appender_refuses_a_file_with_an_unreadable_complete_line() {
    let dir = fresh_dir("bad");
    results::append(&dir, &row("linear(10)", 0.5)).unwrap();
    let jsonl = dir.join("results.jsonl");
    let text = std::fs::read_to_string(&jsonl).unwrap();
    std::fs::write(&jsonl, format!("{text}not json\n")).unwrap();
    let e = results::read_for_append(&dir).unwrap_err().to_string();
    assert!(e.contains("line 2"), "{e}");
    // The report's reader skips it and says so.
    let read = results::read(&dir).unwrap();
    assert_eq!((read.rows.len(), read.bad_lines.len()), (1, 1));
    let _ = std::fs::remove_dir_all(&dir);
}
