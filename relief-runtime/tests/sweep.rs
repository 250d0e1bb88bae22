//! A small grid end to end: sweep, kill mid-run, resume; no row lost or duplicated.

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn relief() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_relief"));
    c.env("LP_NUM_THREADS", "1").env("NODEVICE_SELECT", "1");
    c
}

const GRID: &str =
    "# a small grid for the tests\ncoarse: [linear(4..=32 step 4), csm([4, 8])]\nrefine: [none, binary(3)]\n";

fn rows(dir: &std::path::Path) -> Vec<serde_json::Value> {
    let text = std::fs::read_to_string(dir.join("results.jsonl")).unwrap_or_default();
    text.lines().map(|l| serde_json::from_str(l).expect("every line is a whole row")).collect()
}

#[test]
fn sweep_survives_a_kill_and_resumes_without_losing_or_repeating_cells() {
    let dir = std::env::temp_dir().join(format!("relief-sweep-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    let grid = dir.join("small.grid");
    std::fs::write(&grid, GRID).unwrap();
    let out = dir.join("out");
    let args = |c: &mut Command| {
        c.args(["sweep", "--grid"])
            .arg(&grid)
            .args(["--scene", "scene:rock_bump", "--scene", "scene:step", "--size", "48", "--frames", "3", "--out"])
            .arg(&out);
    };
    let cells = 20 * 2;

    // Start, and kill as soon as a few rows are in.
    let mut cmd = relief();
    args(&mut cmd);
    let mut child = cmd.stdout(Stdio::null()).stderr(Stdio::null()).spawn().unwrap();
    let start = Instant::now();
    while rows(&out).len() < 3 && start.elapsed() < Duration::from_secs(120) {
        std::thread::sleep(Duration::from_millis(20));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    let before = rows(&out).len();
    assert!(before >= 3 && before < cells, "killed after {before} of {cells} cells");
    // Simulate a kill in the middle of a write: a cut line at the end of the file.
    let jsonl = out.join("results.jsonl");
    let mut text = std::fs::read_to_string(&jsonl).unwrap();
    text.push_str("{\"grid\":\"small\",\"pipeline\":\"linear(4)");
    std::fs::write(&jsonl, text).unwrap();

    // Resume: the cut line is dropped, finished cells are skipped, the rest measured.
    let mut cmd = relief();
    args(&mut cmd);
    let o = cmd.output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary = String::from_utf8_lossy(&o.stdout);
    assert!(summary.contains(&format!("{before} already done")), "{summary}");
    let all = rows(&out);
    assert_eq!(all.len(), cells);
    let mut keys: Vec<(String, String)> = all
        .iter()
        .map(|r| (r["pipeline"].as_str().unwrap().to_string(), r["scene"].as_str().unwrap().to_string()))
        .collect();
    keys.sort();
    keys.dedup();
    assert_eq!(keys.len(), cells, "no cell measured twice");
    assert!(all.iter().all(|r| r["status"] == "ok"), "{:?}", all.iter().find(|r| r["status"] != "ok"));
    // The CSV holds the same rows.
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    assert_eq!(csv.lines().count(), cells + 1);
    assert!(csv.starts_with("grid,pipeline,scene,size,adapter,status,error,relief_version,frame_ms_median"));
    // Every cell has its pictures.
    for r in &all {
        let cell = out.join(r["cell_dir"].as_str().unwrap());
        assert!(cell.join("frame.png").exists() && cell.join("error.png").exists(), "{}", cell.display());
    }
    // The report runs on the result.
    let o = relief().arg("report").arg(&out).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let index = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(index.contains("tables.md") || index.contains("<table"), "index.html links the tables");
    assert!(out.join("tables.md").exists() && out.join("pareto.md").exists());
    // A third run has nothing left to do.
    let mut cmd = relief();
    args(&mut cmd);
    let o = cmd.output().unwrap();
    assert!(String::from_utf8_lossy(&o.stdout).contains(&format!("{cells} already done")));
    assert_eq!(rows(&out).len(), cells);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_failing_cell_is_recorded_and_the_sweep_goes_on() {
    let dir = std::env::temp_dir().join(format!("relief-sweep-fail-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    let grid = dir.join("g.grid");
    std::fs::write(&grid, "coarse: linear([4, 8])\n").unwrap();
    let out = dir.join("out");
    // A scene that does not exist fails every cell on it, the other scene's cells succeed.
    let o = relief()
        .args(["sweep", "--grid"])
        .arg(&grid)
        .args(["--scene", "scene:step", "--scene", "scene:no_such_scene", "--size", "32", "--frames", "2", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let all = rows(&out);
    assert_eq!(all.len(), 4);
    let failed: Vec<_> = all.iter().filter(|r| r["status"] == "error").collect();
    assert_eq!(failed.len(), 2);
    assert!(failed[0]["error"].as_str().unwrap().contains("no_such_scene"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn sweep_list_shows_every_grid_with_its_cell_count() {
    let o = relief().args(["sweep", "--list"]).output().unwrap();
    let text = String::from_utf8_lossy(&o.stdout);
    for name in ["t4.1 ", "t4.15", "f4.5", "f4.11", "dissertation"] {
        assert!(text.contains(name), "{name} missing from\n{text}");
    }
    assert!(text.lines().any(|l| l.starts_with("t4.1 ") && l.contains(" 13 cells")));
    // The room comparison is listed like the other grids: four variants in each of the two
    // default rooms, or in each room named.
    assert!(text.lines().any(|l| l.starts_with("rooms ") && l.contains(" 8 cells")), "{text}");
    let o = relief().args(["sweep", "--list", "--scene", "room:default"]).output().unwrap();
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.lines().any(|l| l.starts_with("rooms ") && l.contains(" 4 cells")), "{text}");
}

/// The room comparison refuses what it does not implement, in one line naming the flag,
/// before measuring anything.
#[test]
fn the_room_grid_refuses_view_overrides_and_shards_in_one_line() {
    let dir = std::env::temp_dir().join(format!("relief-sweep-rooms-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    for (flag, value, says) in [("--angle", "30", "--angle"), ("--shard", "1/2", "--shard is not implemented")] {
        let o = relief()
            .args(["sweep", "--grid", "rooms", "--size", "16", "--frames", "1", flag, value, "--out"])
            .arg(&dir)
            .output()
            .unwrap();
        let e = String::from_utf8_lossy(&o.stderr);
        let e = e.lines().filter(|l| !l.contains("XDG_RUNTIME_DIR")).collect::<Vec<_>>();
        assert!(!o.status.success() && e.len() == 1 && e[0].contains(says), "{flag}: {e:?}");
        assert!(!dir.join("results.jsonl").exists(), "{flag}: a room was measured");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// `relief cost --grid rooms` asks the sweep's plan what the grid is and refuses the room
/// comparison in one line (its walls are not relief pipelines), pricing nothing.
#[test]
fn relief_cost_refuses_the_room_grid_in_one_line() {
    let o = relief().args(["cost", "--grid", "rooms"]).output().unwrap();
    let e = String::from_utf8_lossy(&o.stderr);
    let e = e.lines().filter(|l| !l.contains("XDG_RUNTIME_DIR")).collect::<Vec<_>>();
    assert!(
        !o.status.success() && e.len() == 1 && e[0].contains("--grid rooms: the room grid's pipelines are not priced"),
        "{e:?}"
    );
}

/// Two maps of one kind with different parameters (mcns's K) must not share an upload: the
/// cells of a two-cell grid, swept together on one prepared scene, equal the same cells swept
/// alone, bit for bit in every accuracy and work column (frame times are timings and differ).
#[test]
fn cells_that_read_one_map_kind_with_different_parameters_match_their_solo_runs() {
    let dir = std::env::temp_dir().join(format!("relief-sweep-keys-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    let sweep = |name: &str, coarse: &str| -> Vec<serde_json::Value> {
        let grid = dir.join(format!("{name}.grid"));
        std::fs::write(&grid, format!("coarse: [{coarse}]\nrefine: [binary(5)]\n")).unwrap();
        let out = dir.join(name);
        let o = relief()
            .args(["sweep", "--grid"])
            .arg(&grid)
            .args(["--scene", "scene:rock_bump", "--size", "32", "--frames", "1", "--out"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        rows(&out)
    };
    let both = sweep("both", "mcns(15, 2), mcns(15, 4)");
    assert_eq!(both.len(), 2);
    for (i, coarse) in ["mcns(15, 2)", "mcns(15, 4)"].iter().enumerate() {
        let solo = sweep(&format!("solo{i}"), coarse);
        let together = both.iter().find(|r| r["pipeline"].as_str().unwrap().starts_with(coarse)).unwrap();
        for col in [
            "mse_dissertation",
            "ref_err_t_rms",
            "ref_err_uv_texels_rms",
            "missed_rate",
            "avg_coarse_steps",
            "avg_fetches",
            "nonconverged_rate",
        ] {
            assert_eq!(
                together[col], solo[0][col],
                "{coarse}: `{col}` swept with the other cell differs from swept alone"
            );
        }
    }
    // The two cells read different maps: their results differ.
    assert_ne!(both[0]["mse_dissertation"], both[1]["mse_dissertation"]);
}

/// A sweep with `lod=auto` (and the same cells at `lod=zero`) runs on every one of the
/// dissertation's main scenes (real and procedural), each auto cell scored on the levels it
/// sampled, and the report puts the conclusions at both levels side by side.
#[test]
fn a_lod_auto_sweep_runs_on_every_main_scene() {
    let dir = std::env::temp_dir().join(format!("relief-sweep-lod-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    let grid = dir.join("lod.grid");
    std::fs::write(&grid, "coarse: [linear(8), csm(4, form=[safe, textbook])]\nrefine: binary(2)\nshadow: [none, hard(8)]\nlod: [zero, auto]\n").unwrap();
    let out = dir.join("out");
    let scenes = relief_runtime::sweep::grids::FIVE_SCENES;
    let mut cmd = relief();
    cmd.args(["sweep", "--grid"]).arg(&grid);
    for s in scenes {
        cmd.args(["--scene", s]);
    }
    let o = cmd.args(["--size", "32", "--frames", "2", "--out"]).arg(&out).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let all = rows(&out);
    assert_eq!(all.len(), 3 * 2 * 2 * scenes.len());
    for r in &all {
        assert_eq!(r["status"], "ok", "{r}");
        assert_eq!(r["nan_count"], 0, "{r}");
        assert!(r["ref_err_t_rms"].as_f64().is_some_and(f64::is_finite), "{r}");
    }
    for s in scenes {
        let auto = all
            .iter()
            .filter(|r| {
                r["pipeline"].as_str().unwrap().ends_with("+lod=auto") && r["scene"].as_str().unwrap().ends_with(s)
            })
            .count();
        assert_eq!(auto, 6, "{s}");
    }
    let o = relief().arg("report").arg(&out).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let md = std::fs::read_to_string(out.join("tables.md")).unwrap();
    assert!(md.contains("Conclusions at the footprint level (`lod=auto`)"));
    std::fs::remove_dir_all(&dir).ok();
}

/// `--shard K/N`: three shards of a grid, each swept into its own folder and merged by the
/// report, hold the same cells as the grid swept whole, equal in every column that is not a
/// timing or a provenance column (accuracy, work and the cost model are bit-identical run to
/// run); no cell is in two shards.
#[test]
fn a_grid_swept_as_three_shards_and_merged_equals_the_grid_swept_whole() {
    let dir = std::env::temp_dir().join(format!("relief-sweep-shards-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    let grid = dir.join("g.grid");
    std::fs::write(&grid, "coarse: [linear([4, 8]), csm(4)]\nrefine: [none, binary(2)]\n").unwrap();
    let sweep = |out: &std::path::Path, shard: Option<&str>| {
        let mut c = relief();
        c.args(["sweep", "--grid"])
            .arg(&grid)
            .args(["--scene", "scene:rock_bump", "--scene", "scene:step", "--size", "24", "--frames", "2", "--out"])
            .arg(out);
        if let Some(s) = shard {
            c.args(["--shard", s]);
        }
        let o = c.output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    sweep(&dir.join("whole"), None);
    let mut shards = Vec::new();
    for k in 1..=3 {
        let out = dir.join(format!("shard{k}"));
        let text = sweep(&out, Some(&format!("{k}/3")));
        assert!(text.starts_with(&format!("shard {k}/3: 4 cells")), "12 cells dealt 4, 4, 4: {text}");
        shards.push(out);
    }
    // Both through the report's merge (which writes the rows it read to its own folder), so
    // that both tables take the same path from results.jsonl to results.csv.
    let report = |dirs: &[std::path::PathBuf], out: &std::path::Path| {
        let o = relief().arg("report").args(dirs).arg("--out").arg(out).output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };
    let merged = dir.join("merged");
    report(&shards, &merged);
    report(&[dir.join("whole")], &dir.join("whole_report"));
    let table = |path: std::path::PathBuf| -> Vec<std::collections::BTreeMap<String, String>> {
        let mut r = csv::Reader::from_path(&path).unwrap();
        let h = r.headers().unwrap().clone();
        r.records()
            .map(|rec| h.iter().zip(rec.unwrap().iter()).map(|(k, v)| (k.to_string(), v.to_string())).collect())
            .collect()
    };
    let timing = |c: &str| {
        c.starts_with("frame_")
            || ["timing_pairs", "frames_per_block", "timestamp_period_ns", "cell_dir", "grid"].contains(&c)
    };
    let key = |r: &std::collections::BTreeMap<String, String>| (r["pipeline"].clone(), r["scene"].clone());
    let mut whole = table(dir.join("whole_report/results.csv"));
    let mut parts = table(merged.join("results.csv"));
    whole.sort_by_key(key);
    parts.sort_by_key(key);
    assert_eq!(whole.len(), 12);
    assert_eq!(
        parts.iter().map(key).collect::<Vec<_>>(),
        whole.iter().map(key).collect::<Vec<_>>(),
        "the same cells, none twice"
    );
    let columns: Vec<&String> = whole[0].keys().filter(|c| !timing(c)).collect();
    assert!(
        columns.iter().any(|c| *c == "mse_dissertation") && columns.iter().any(|c| *c == "simd32_fetches"),
        "{columns:?}"
    );
    for (w, p) in whole.iter().zip(&parts) {
        for c in &columns {
            assert_eq!(w[*c], p[*c], "{c} of {:?}", key(w));
        }
        assert_eq!(w["status"], "ok");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// A scene named with a view (`scene:step@angle=70`, as results name a scene swept with
/// `--angle 70`) is that scene at that view: the same row as `--angle 70`, under the same
/// name; an override that would replace a cell's own view is refused.
#[test]
fn a_scene_with_a_view_is_the_scene_swept_at_that_view() {
    let dir = std::env::temp_dir().join(format!("relief-sweep-view-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    let grid = dir.join("g.grid");
    std::fs::write(&grid, "coarse: linear(8)\nrefine: binary(2)\n").unwrap();
    let sweep = |out: &str, args: &[&str]| {
        let o = relief()
            .args(["sweep", "--grid"])
            .arg(&grid)
            .args(args)
            .args(["--size", "32", "--frames", "1", "--out"])
            .arg(dir.join(out))
            .output()
            .unwrap();
        (o.status.success(), String::from_utf8_lossy(&o.stderr).into_owned())
    };
    let (ok, err) = sweep("named", &["--scene", "step@angle=70"]);
    assert!(ok, "{err}");
    let (ok, err) = sweep("flag", &["--scene", "step", "--angle", "70"]);
    assert!(ok, "{err}");
    let (named, flag) = (rows(&dir.join("named")), rows(&dir.join("flag")));
    assert_eq!(named[0]["scene"], "scene:step@angle=70");
    assert_eq!(named[0]["scene"], flag[0]["scene"]);
    for col in ["mse_dissertation", "ref_err_t_rms", "missed_rate", "avg_coarse_steps", "avg_fetches"] {
        assert_eq!(named[0][col], flag[0][col], "{col}");
    }
    // The 70° view differs from the scene's own.
    let (ok, err) = sweep("own", &["--scene", "step"]);
    assert!(ok, "{err}");
    assert_ne!(rows(&dir.join("own"))[0]["avg_coarse_steps"], named[0]["avg_coarse_steps"]);
    // An override of the same key is refused, naming the flag and the scene; another key is fine.
    let (ok, err) = sweep("clash", &["--scene", "step@angle=70", "--angle", "30"]);
    assert!(!ok && err.contains("--angle") && err.contains("step@angle=70"), "{err}");
    let (ok, err) = sweep("bad", &["--scene", "step@angle=95"]);
    assert!(ok, "a bad view fails its cells, not the sweep: {err}");
    assert!(rows(&dir.join("bad"))[0]["error"].as_str().unwrap().contains("angle"), "{:?}", rows(&dir.join("bad")));
    std::fs::remove_dir_all(&dir).ok();
}

/// An empty folder under the system's temporary folder, for this process.
fn fresh(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("relief-sweep-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// (width, height) from a PNG's header.
fn png_size(path: &std::path::Path) -> (u32, u32) {
    let b = std::fs::read(path).unwrap();
    (u32::from_be_bytes(b[16..20].try_into().unwrap()), u32::from_be_bytes(b[20..24].try_into().unwrap()))
}

/// Cell folders are keyed by every part of the cell key: a size-32 sweep into a size-24
/// folder keeps the size-24 pictures, and scene files `sc/trav.toml` and `sc_trav.toml` (one
/// name once `/` is made file-safe by a lossy mapping) get a folder each.
#[test]
fn cells_of_other_sizes_and_of_look_alike_scene_paths_never_share_a_folder() {
    let dir = fresh("folders");
    std::fs::create_dir_all(dir.join("sc")).unwrap();
    let map = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/tatarchuk/bump_NM_height.tga");
    std::fs::copy(&map, dir.join("bump.tga")).unwrap();
    std::fs::write(dir.join("sc/trav.toml"), "[height_map]\npath = \"../bump.tga\"\nchannel = \"a\"\n").unwrap();
    std::fs::write(dir.join("sc_trav.toml"), "[height_map]\npath = \"bump.tga\"\nchannel = \"a\"\n").unwrap();
    let grid = dir.join("g.grid");
    std::fs::write(&grid, "coarse: linear(4)\n").unwrap();
    let out = dir.join("out");
    for size in ["24", "32"] {
        let o = relief()
            .current_dir(&dir)
            .args(["sweep", "--grid"])
            .arg(&grid)
            .args(["--scene", "sc/trav.toml", "--scene", "sc_trav.toml", "--size", size, "--frames", "2", "--out"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let all = rows(&out);
    assert_eq!(all.len(), 4);
    let mut folders: Vec<&str> = all.iter().map(|r| r["cell_dir"].as_str().unwrap()).collect();
    folders.sort();
    folders.dedup();
    assert_eq!(folders.len(), 4, "{folders:?}");
    for r in &all {
        let size = r["size"].as_u64().unwrap() as u32;
        let frame = out.join(r["cell_dir"].as_str().unwrap()).join("frame.png");
        assert_eq!(png_size(&frame), (size, size), "{}", frame.display());
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// Two processes, one folder: a second sweep and a report refuse while a sweep holds the
/// folder's lock, naming its pid on one line; a sweep started with `--wait` waits, takes the
/// lock over when the holder is killed (SIGKILL: nothing of it is left to release), and
/// finishes the grid, each cell once.
#[test]
fn a_locked_folder_is_refused_or_waited_for_and_a_killed_holder_frees_it() {
    let dir = fresh("lock");
    let grid = dir.join("g.grid");
    std::fs::write(&grid, "coarse: linear(4..=40 step 4)\nrefine: [none, binary(3)]\n").unwrap();
    let out = dir.join("out");
    let sweep = |extra: &[&str]| {
        let mut c = relief();
        c.args(["sweep", "--grid"])
            .arg(&grid)
            .args(["--scene", "scene:step", "--size", "48", "--frames", "4", "--out"])
            .arg(&out)
            .args(extra);
        c
    };
    let mut holder = sweep(&[]).stdout(Stdio::null()).stderr(Stdio::null()).spawn().unwrap();
    let lock = out.join(".relief.lock");
    let start = Instant::now();
    while !std::fs::read_to_string(&lock).unwrap_or_default().starts_with("pid") {
        assert!(start.elapsed() < Duration::from_secs(60), "the sweep never took its lock");
        std::thread::sleep(Duration::from_millis(10));
    }
    let pid = format!("pid {}", holder.id());
    for mut refused in [sweep(&[]), {
        let mut c = relief();
        c.arg("report").arg(&out);
        c
    }] {
        let o = refused.output().unwrap();
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{e}");
        assert!(e.contains("in use by another relief process") && e.contains(&pid), "{e}");
        assert_eq!(e.trim_end().lines().count(), 1, "{e}");
    }
    let mut waiter = sweep(&["--wait"]).stdout(Stdio::null()).stderr(Stdio::piped()).spawn().unwrap();
    // Kill the holder only once the waiter says it waits (a fixed sleep races a slow start).
    let (said, heard) = std::sync::mpsc::channel();
    let stderr = waiter.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut all = String::new();
        for line in std::io::BufRead::lines(std::io::BufReader::new(stderr)).map_while(Result::ok) {
            if line.contains("waiting for the results folder's lock") {
                said.send(()).ok();
            }
            all += &line;
            all.push('\n');
        }
        all
    });
    let waited = heard.recv_timeout(Duration::from_secs(60)).is_ok();
    holder.kill().unwrap();
    holder.wait().unwrap();
    let status = waiter.wait().unwrap();
    let e = reader.join().unwrap();
    assert!(waited, "the --wait sweep never said it waits: {e}");
    assert!(status.success(), "{e}");
    assert!(e.contains("waiting for the results folder's lock") && e.contains(&pid), "{e}");
    let all = rows(&out);
    let mut keys: Vec<&str> = all.iter().map(|r| r["pipeline"].as_str().unwrap()).collect();
    keys.sort();
    keys.dedup();
    assert_eq!((all.len(), keys.len()), (20, 20));
    assert_eq!(std::fs::read_to_string(&lock).unwrap(), "", "released");
    std::fs::remove_dir_all(&dir).ok();
}

/// On a terminal the bar is there from the start, saying what is prepared before the first
/// cell (a large grid takes a while to check). `script` (util-linux) gives the sweep a
/// terminal.
#[test]
fn on_a_terminal_the_progress_bar_shows_from_the_start() {
    let dir = fresh("bar");
    let grid = dir.join("g.grid");
    std::fs::write(&grid, "coarse: linear([4, 8])\n").unwrap();
    let line = format!(
        "{} sweep --grid {} --scene scene:step --size 16 --frames 2 --out {}",
        env!("CARGO_BIN_EXE_relief"),
        grid.display(),
        dir.join("out").display()
    );
    let typescript = dir.join("typescript");
    let o = Command::new("script")
        .arg("-qc")
        .arg(&line)
        .arg(&typescript)
        .env("LP_NUM_THREADS", "1")
        .env("NODEVICE_SELECT", "1")
        .stdout(Stdio::null())
        .status()
        .expect("`script` (util-linux) runs");
    assert!(o.success());
    let text = String::from_utf8_lossy(&std::fs::read(&typescript).unwrap()).into_owned();
    let prep = text.find("0/2 cells, ETA").map(|i| &text[i..]).unwrap_or("");
    assert!(prep.contains("preparing 2 cells"), "{text}");
    assert_eq!(rows(&dir.join("out")).len(), 2);
    std::fs::remove_dir_all(&dir).ok();
}
