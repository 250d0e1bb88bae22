//! Issue 27: bad values refused up front, with their accepted range and their key.

use std::process::Command;

fn relief() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_relief"));
    c.env("LP_NUM_THREADS", "1").env("NODEVICE_SELECT", "1");
    c
}

fn tmpdir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("relief-robust-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&d).ok();
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// (exit status success, stderr) of a command.
fn run(mut c: Command) -> (bool, String) {
    let o = c.output().unwrap();
    (o.status.success(), String::from_utf8_lossy(&o.stderr).into_owned())
}

#[test]
fn depth_scales_and_tilings_beyond_their_range_are_refused_with_the_range_and_the_key() {
    let d = tmpdir("ranges");
    let map = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/tatarchuk/bump_NM_height.tga");
    std::fs::copy(&map, d.join("bump.tga")).unwrap();
    for (flag, value, says) in [
        ("--depth-scale", "3.4e38", "allowed 0 < depth scale <= 10"),
        ("--depth-scale", "1e30", "allowed 0 < depth scale <= 10"),
        ("--depth-scale", "0", "allowed 0 < depth scale <= 10"),
        ("--tiling", "1e30", "allowed 0 < tiling <= 1000"),
    ] {
        let start = std::time::Instant::now();
        let mut c = relief();
        c.args(["render", "linear(8)", "--scene", "scene:step", "--size", "16", "--frames", "1", "--out"])
            .arg(d.join("o"))
            .arg(format!("{flag}={value}"));
        let (ok, e) = run(c);
        assert!(!ok && e.contains(flag) && e.contains(says), "{flag}={value}: {e}");
        assert_eq!(e.trim_end().lines().count(), 1, "{e}");
        // Refused up front: long before a frame is rendered or the reference traced.
        assert!(start.elapsed() < std::time::Duration::from_secs(5), "{flag}={value} took {:?}", start.elapsed());
        assert!(!d.join("o").join("metrics.json").exists());
    }
    for (key, says) in [("depth_scale", "allowed 0 < depth scale <= 10"), ("tiling", "allowed 0 < tiling <= 1000")] {
        let file = d.join(format!("{key}.toml"));
        std::fs::write(&file, format!("{key} = 1e30\n[height_map]\npath = \"bump.tga\"\nchannel = \"a\"\n")).unwrap();
        let mut c = relief();
        c.args(["render", "linear(8)", "--size", "16", "--frames", "1", "--out"])
            .arg(d.join("o"))
            .arg("--scene")
            .arg(&file);
        let (ok, e) = run(c);
        assert!(
            !ok && e.contains(&format!("`{key}`")) && e.contains(says) && e.contains(&format!("{key}.toml")),
            "{e}"
        );
    }
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn a_grid_with_a_pipeline_that_cannot_be_built_is_refused_before_any_cell_runs() {
    let d = tmpdir("grid");
    let grid = d.join("g.grid");
    std::fs::write(&grid, "coarse: [linear(4), csm(4, form=safe, sample=min4), linear(8)]\n").unwrap();
    let mut c = relief();
    c.args(["sweep", "--grid"])
        .arg(&grid)
        .args(["--scene", "scene:step", "--size", "16", "--frames", "2", "--out"])
        .arg(d.join("out"));
    let (ok, e) = run(c);
    assert!(!ok, "{e}");
    assert!(e.contains("csm(4") && e.contains("sample=min4") && e.contains("no cell was run"), "{e}");
    assert_eq!(e.trim_end().lines().count(), 1, "{e}");
    assert!(!d.join("out").join("results.jsonl").exists(), "nothing measured");
    std::fs::remove_dir_all(&d).ok();
}
