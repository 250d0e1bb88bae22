//! The results file as sweep and report read it: one reader, one cut-last-line rule.

use relief_runtime::metrics::Metrics;
use relief_runtime::results::{self, Row};

fn row(pipeline: &str, t_rms: f64) -> Row {
    Row {
        grid: "g".into(),
        metrics: Metrics {
            pipeline: pipeline.parse().unwrap(),
            scene: "scene:lion".into(),
            size: 16,
            ref_err_t_rms: t_rms,
            ..Default::default()
        },
        status: relief_runtime::results::Status::Ok,
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
    let e = results::read_for_append(&dir).unwrap_err();
    // A caller can match the line without reading the message.
    assert!(matches!(&e, results::ResultsError::BadLine { line: 2, path, .. } if *path == jsonl), "{e:?}");
    let e = e.to_string();
    assert!(e.contains("line 2"), "{e}");
    // The report's reader skips it and says so.
    let read = results::read(&dir).unwrap();
    assert_eq!((read.rows.len(), read.bad_lines.len()), (1, 1));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn lines_that_are_not_results_rows_are_named_and_never_counted() {
    let dir = fresh_dir("notrows");
    results::append(&dir, &row("linear(10)", 0.5)).unwrap();
    let jsonl = dir.join("results.jsonl");
    let good = std::fs::read_to_string(&jsonl).unwrap();
    let bad = [
        ("{\"foo\": 1}", "no `pipeline`"),
        ("{\"pipeline\": \"linear(10)\", \"scene\": \"s\", \"size\": 16}", "no `status`"),
        ("{\"pipeline\": \"linear(10)\", \"scene\": \"s\", \"status\": \"ok\"}", "no `size`"),
        ("{\"pipeline\": \"linear(10)\", \"size\": 16, \"status\": \"ok\"}", "no `scene`"),
        ("{\"pipeline\": \"linear(10)\", \"scene\": \"s\", \"size\": 16, \"status\": \"done\"}", "status `done`"),
        ("{\"pipeline\": \"no_such_method(3)\", \"scene\": \"s\", \"size\": 16, \"status\": \"ok\"}", "no_such_method"),
        ("{\"pipeline\": null, \"scene\": \"s\", \"size\": 16, \"status\": \"ok\"}", "no `pipeline`"),
    ];
    for (line, reason) in bad {
        std::fs::write(&jsonl, format!("{good}{line}\n")).unwrap();
        let read = results::read(&dir).unwrap();
        assert_eq!(read.rows.len(), 1, "{line}");
        assert_eq!(read.bad_lines.len(), 1, "{line}");
        assert!(read.bad_lines[0].starts_with("line 2:") && read.bad_lines[0].contains(reason), "{:?}", read.bad_lines);
        let e = results::read_for_append(&dir).unwrap_err();
        assert!(matches!(e, results::ResultsError::BadLine { line: 2, .. }), "{e:?}");
        let e = e.to_string();
        assert!(e.contains("line 2") && e.contains(reason) && !e.contains('\n'), "{e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn two_rows_for_one_cell_are_both_left_out_and_named_but_other_adapters_are_other_cells() {
    let dir = fresh_dir("dups");
    let mut zero = row("linear(10)", 0.0);
    zero.status = relief_runtime::results::Status::Ok;
    let mut other_adapter = row("linear(10)", 0.75);
    other_adapter.metrics.adapter = "Some GPU (WebGPU, timestamp-query)".into();
    // Line 3 is the cell of line 1 written another way (spaces): the same canonical pipeline.
    for r in [&row("linear(10)", 0.5), &row("linear(20)", 0.25)] {
        results::append(&dir, r).unwrap();
    }
    let spaced = serde_json::to_string(&row("linear(10)", 0.5)).unwrap().replace("\"linear(10)\"", "\"linear( 10 )\"");
    assert!(spaced.contains("linear( 10 )"));
    let jsonl = dir.join("results.jsonl");
    std::fs::write(&jsonl, format!("{}{spaced}\n", std::fs::read_to_string(&jsonl).unwrap())).unwrap();
    for r in [&other_adapter, &zero] {
        results::append(&dir, r).unwrap();
    }
    let read = results::read(&dir).unwrap();
    let pipelines: Vec<(String, &str)> =
        read.rows.iter().map(|r| (r.metrics.pipeline.to_string(), r.metrics.adapter.as_str())).collect();
    assert_eq!(
        pipelines,
        [("linear(20)".to_string(), ""), ("linear(10)".to_string(), "Some GPU (WebGPU, timestamp-query)")]
    );
    assert_eq!(read.bad_lines.len(), 1, "{:?}", read.bad_lines);
    let m = &read.bad_lines[0];
    assert!(
        m.starts_with("lines 1, 3, 5: 3 rows for one cell") && m.contains("linear(10)") && m.contains("size 16"),
        "{m}"
    );
    let e = results::read_for_append(&dir).unwrap_err();
    assert!(matches!(e, results::ResultsError::BadLine { line: 1, .. }), "the first of the lines: {e:?}");
    let e = e.to_string();
    assert!(e.contains("lines 1, 3, 5"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A small deterministic generator (SplitMix64) for the round-trip tests.
fn splitmix(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

#[test]
fn every_value_written_to_the_csv_and_the_jsonl_reads_back_as_the_same_number() {
    let dir = fresh_dir("roundtrip");
    let mut state = 27;
    let mut rows = Vec::new();
    // Finite doubles of every exponent (random bit patterns), values in [0, 1) like the
    // rates and errors, and a value once seen to change in its last digit.
    let mut values = vec![0.019671713345102298, 0.2240283, 5e-324, f64::MAX, f64::MIN_POSITIVE];
    while values.len() < 1000 {
        let bits = splitmix(&mut state);
        let x = f64::from_bits(bits);
        if x.is_finite() {
            values.push(x);
        }
        values.push((splitmix(&mut state) >> 11) as f64 / (1u64 << 53) as f64);
    }
    for (i, v) in values.iter().enumerate() {
        let mut r = row("linear(10)", *v);
        r.metrics.scene = format!("scene:s{i}");
        r.metrics.frame_ms_median = -*v;
        r.metrics.frame_ratio_to_baseline = Some(*v);
        rows.push(r);
    }
    for r in &rows {
        results::append(&dir, r).unwrap();
    }
    let back = results::read(&dir).unwrap();
    assert!(back.bad_lines.is_empty(), "{:?}", back.bad_lines);
    assert_eq!(back.rows, rows, "results.jsonl");
    results::write_csv(&dir, &rows).unwrap();
    let mut csv = csv::Reader::from_path(dir.join("results.csv")).unwrap();
    let headers = csv.headers().unwrap().clone();
    let col = |name: &str| headers.iter().position(|h| h == name).unwrap();
    let (t, f, ratio) = (col("ref_err_t_rms"), col("frame_ms_median"), col("frame_ratio_to_baseline"));
    let mut n = 0;
    for (rec, v) in csv.records().zip(&values) {
        let rec = rec.unwrap();
        let num = |c: usize| rec[c].parse::<f64>().unwrap().to_bits();
        assert_eq!((num(t), num(f), num(ratio)), (v.to_bits(), (-v).to_bits(), v.to_bits()), "{v:e}: {:?}", &rec);
        n += 1;
    }
    assert_eq!(n, values.len());
    let _ = std::fs::remove_dir_all(&dir);
}
