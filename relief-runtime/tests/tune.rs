//! `relief tune`: the pick meets the goal at every view (checked with `relief render`, the
//! measure code, on the same views), the count stays within a quarter of the frontier's
//! cells, an unreachable goal and bad inputs are one-line errors.

use std::process::Command;

fn relief() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_relief"));
    c.env("LP_NUM_THREADS", "1").env("NODEVICE_SELECT", "1");
    c
}

fn tmpdir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("relief-tune-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&d).ok();
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The frontier grid's pipelines (6 × 3 engine, 5 × 4 safe cones, 2 × 4 sphere and maxmip,
/// 2 × 4 relaxed cones).
const FRONTIER_PIPELINES: usize = 54;

#[test]
fn the_pick_reaches_the_goal_at_every_view_within_a_quarter_of_the_cells() {
    let d = tmpdir("pick");
    let error = 1e-2;
    let views = ["45", "70"];
    let o = relief()
        .args(["tune", "rocks", "--error", "1e-2", "--view", views[0], "--view", views[1], "--size", "48"])
        .args(["--frames", "6", "--no-gpu-cost"])
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(o.status.success(), "{out}{}", String::from_utf8_lossy(&o.stderr));
    let pick = out.lines().find_map(|l| l.strip_prefix("pick: ")).expect(&out);
    let pick = pick.split("  ").next().unwrap().to_string();
    let counted = out.lines().find_map(|l| l.strip_prefix("measured ")).expect(&out);
    let words: Vec<&str> = counted.split_whitespace().collect();
    let (n, cells): (usize, usize) = (words[0].parse().unwrap(), words[5].parse().unwrap());
    assert_eq!(cells, FRONTIER_PIPELINES * views.len(), "{out}");
    assert!(n >= 1 && n <= cells / 4, "{n} of {cells}: {out}");
    // The pick measured independently (relief render: the measure code) at each view.
    for v in views {
        let dir = d.join(v);
        let r = relief()
            .args(["render", &pick, "--scene", "rocks", "--angle", v, "--size", "48", "--frames", "2", "--out"])
            .arg(&dir)
            .output()
            .unwrap();
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        let m: serde_json::Value = serde_json::from_slice(&std::fs::read(dir.join("metrics.json")).unwrap()).unwrap();
        let err = m["ref_err_t_rms"].as_f64().unwrap();
        let skipped = m["skipped_rate"].as_f64().unwrap();
        assert!(err <= error && skipped == 0.0, "{pick} at {v}°: t error {err}, skipped {skipped}");
    }
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn an_unreachable_goal_is_one_line_naming_the_closest() {
    // A probe hit is an f32 t near 1, whose rounding alone is ~6e-8: an RMS t error of 1e-12
    // is out of reach of every pipeline.
    let o = relief()
        .args(["tune", "rocks", "--error", "1e-12", "--view", "70", "--size", "32", "--frames", "4", "--no-gpu-cost"])
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{e}");
    assert_eq!(e.trim_end().lines().count(), 1, "{e}");
    assert!(e.starts_with("relief: error: ") && e.contains("the closest measured: ") && e.contains("t error"), "{e}");
}

#[test]
fn bad_inputs_are_one_line_errors() {
    let d = tmpdir("bad");
    let fifo = d.join("f.png");
    let made = Command::new("mkfifo").arg(&fifo).status().map(|s| s.success()).unwrap_or(false);
    let mut cases: Vec<Vec<std::ffi::OsString>> = Vec::new();
    let os = |v: &[&str]| v.iter().map(std::ffi::OsString::from).collect::<Vec<_>>();
    for e in ["nan", "-1", "0", "inf", "abc"] {
        cases.push(os(&["tune", "rocks", "--error", e]));
    }
    for v in ["90", "-1", "nan", "abc"] {
        cases.push(os(&["tune", "rocks", "--error", "1e-2", "--view", v]));
    }
    cases.push(os(&["tune", "/nonexistent/relief/map.png", "--error", "1e-2"]));
    cases.push(os(&["tune", "rocks", "--error", "1e-2", "--target", "nosuch", "--out", "/tmp/x"]));
    if made {
        let mut a = os(&["tune"]);
        a.push(fifo.clone().into());
        a.extend(os(&["--error", "1e-2"]));
        cases.push(a);
    }
    for a in cases {
        let o = relief().args(&a).stdin(std::process::Stdio::null()).output().unwrap();
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && o.status.code() != Some(101), "{a:?}: {e}");
        assert_eq!(e.trim_end().lines().count(), 1, "{a:?}: {e}");
        assert!(e.starts_with("relief: error: "), "{a:?}: {e}");
    }
    std::fs::remove_dir_all(&d).ok();
}
