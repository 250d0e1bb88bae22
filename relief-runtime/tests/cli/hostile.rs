//! Hostile input to the `relief` binary: every command run here must end within its
//! deadline (a hang is killed and fails the test), exit non-zero on bad input with one line
//! on stderr, and never die by a signal.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// What one bounded run gave.
pub struct Outcome {
    /// The exit code; `None` when killed at the deadline or ended by a signal.
    pub code: Option<i32>,
    pub stderr: String,
    pub timed_out: bool,
}

/// The binary under test: this build's, or the one `RELIEF_HOSTILE_BIN` names (to count
/// what an older build fails).
pub fn binary() -> PathBuf {
    std::env::var_os("RELIEF_HOSTILE_BIN").map_or_else(|| PathBuf::from(env!("CARGO_BIN_EXE_relief")), PathBuf::from)
}

/// Runs `relief ARGS` in `dir`, killed at `deadline`.
pub fn run_bounded(dir: &Path, args: &[&str], deadline: Duration) -> Outcome {
    let mut child = Command::new(binary())
        .args(args)
        .current_dir(dir)
        .env("LP_NUM_THREADS", "1")
        .env("NODEVICE_SELECT", "1")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stderr = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut s = Vec::new();
        std::io::Read::read_to_end(&mut stderr, &mut s).ok();
        String::from_utf8_lossy(&s).into_owned()
    });
    let start = Instant::now();
    let (status, timed_out) = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break (Some(s), false);
        }
        if start.elapsed() > deadline {
            child.kill().ok();
            break (child.wait().ok(), true);
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let code = if timed_out { None } else { status.and_then(|s| s.code()) };
    Outcome { code, stderr: reader.join().unwrap_or_default(), timed_out }
}

/// A fresh scratch folder.
pub fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("relief-hostile-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&d).ok();
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn mkfifo(path: &Path) {
    let st = Command::new("mkfifo").arg(path).status().expect("mkfifo");
    assert!(st.success());
}

/// Checks a refusal: a non-zero exit within the deadline, one line on stderr that contains
/// `needle`.
fn assert_refused(dir: &Path, args: &[&str], needle: &str) {
    let o = run_bounded(dir, args, Duration::from_secs(30));
    assert!(!o.timed_out, "{args:?}: still running after 30 s (hangs)");
    assert!(matches!(o.code, Some(c) if c != 0), "{args:?}: exit {:?}, {}", o.code, o.stderr);
    assert_eq!(o.stderr.trim_end().lines().count(), 1, "{args:?}: {}", o.stderr);
    assert!(o.stderr.contains(needle), "{args:?}: {}", o.stderr);
}

/// A FIFO, a directory or another non-regular file, wherever the command line reads a
/// file, is refused with one line before anything blocks reading it: opening a FIFO waits
/// for a writer that never comes.
#[test]
fn non_regular_files_are_refused_before_any_read() {
    let d = scratch("fifo");
    for f in ["f.png", "f.npy", "f.toml", "f.grid", "w.png"] {
        mkfifo(&d.join(f));
    }
    std::fs::create_dir_all(d.join("dir.png")).unwrap();
    std::fs::write(d.join("scene.toml"), "[height_map]\npath = \"f.png\"\n").unwrap();
    std::fs::write(d.join("wall.toml"), "[walls.back]\nheight_map = \"f.png\"\n").unwrap();
    std::fs::write(d.join("window.toml"), "window = \"w.png\"\n").unwrap();
    let fifo = "not a regular file (a FIFO)";
    assert_refused(&d, &["maps", "f.png", "--kind", "cone", "--out", "o.npy"], fifo);
    assert_refused(&d, &["maps", "f.npy", "--kind", "cone", "--out", "o.npy"], fifo);
    assert_refused(&d, &["maps", "dir.png", "--kind", "cone", "--out", "o.npy"], "not a regular file (a directory)");
    assert_refused(&d, &["render", "linear(8)", "--scene", "scene.toml", "--size", "16", "--out", "o"], fifo);
    assert_refused(&d, &["render", "linear(8)", "--scene", "f.toml", "--size", "16", "--out", "o"], fifo);
    assert_refused(&d, &["room", "linear(8)", "--scene", "wall.toml", "--size", "16", "--out", "o"], fifo);
    assert_refused(&d, &["room", "linear(8)", "--scene", "window.toml", "--size", "16", "--out", "o"], fifo);
    assert_refused(&d, &["sweep", "--grid", "f.grid", "--out", "o"], fifo);
    std::fs::remove_dir_all(&d).ok();
}

/// Echoed input never breaks the one-line error: control characters come back escaped, and
/// a long input is shortened with an ellipsis (a 100 KB pipeline once gave a 300 KB line).
#[test]
fn errors_escape_control_characters_and_shorten_long_input() {
    let d = scratch("echo");
    let o = run_bounded(&d, &["gen", "linea\nr(10)", "--out", "o"], Duration::from_secs(30));
    assert_eq!(o.code, Some(1), "{}", o.stderr);
    assert_eq!(o.stderr.trim_end().lines().count(), 1, "{}", o.stderr);
    assert!(o.stderr.contains("`linea\\nr(10)`"), "{}", o.stderr);
    let o = run_bounded(
        &d,
        &["gen", "linear(8)", "--library", "--prefix", "a\u{1b}\nb", "--out", "o"],
        Duration::from_secs(30),
    );
    assert!(matches!(o.code, Some(c) if c != 0), "{}", o.stderr);
    assert_eq!(o.stderr.trim_end().lines().count(), 1, "{}", o.stderr);
    assert!(!o.stderr.contains('\u{1b}'), "{}", o.stderr);
    let long = format!("linear({})", "x".repeat(100_000));
    let o = run_bounded(&d, &["gen", &long, "--out", "o"], Duration::from_secs(30));
    assert_eq!(o.code, Some(1), "{}", &o.stderr[..o.stderr.len().min(300)]);
    assert_eq!(o.stderr.trim_end().lines().count(), 1);
    assert!(o.stderr.chars().count() < 1000 && o.stderr.contains('…'), "{} characters", o.stderr.chars().count());
    std::fs::remove_dir_all(&d).ok();
}

/// Parsing and grid expansion are linear in the input: 50,000 parameters are refused at
/// once (they took minutes when each parameter copied the ones before it), and a grid file of
/// 98,304 cells starts its sweep (creates its folder) well within the deadline. The
/// deadlines are hang guards, far above the expected times (well under a second), not speed goals.
#[test]
fn long_parameter_lists_and_large_grids_do_not_stall() {
    let d = scratch("linear");
    let params = format!("linear({})", vec!["1"; 50_000].join(","));
    let o = run_bounded(&d, &["gen", &params, "--out", "o"], Duration::from_secs(20));
    assert!(!o.timed_out, "50,000 parameters still parsing after 20 s");
    assert!(o.stderr.contains("takes at most 1 parameter"), "{}", &o.stderr[..o.stderr.len().min(300)]);
    std::fs::write(d.join("big.grid"), "coarse: [linear(1..=4096 step 1)]\nrefine: [none, binary(1..=23 step 1)]\n")
        .unwrap();
    let mut child = Command::new(binary())
        .args(["sweep", "--grid", "big.grid", "--size", "8", "--frames", "2", "--out", "o"])
        .current_dir(&d)
        .env("LP_NUM_THREADS", "1")
        .env("NODEVICE_SELECT", "1")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while !d.join("o").exists() && start.elapsed() < Duration::from_secs(20) && child.try_wait().unwrap().is_none() {
        std::thread::sleep(Duration::from_millis(20));
    }
    let started = d.join("o").exists();
    child.kill().ok();
    child.wait().ok();
    assert!(started, "a 98,304-cell grid had not started after {:.1} s", start.elapsed().as_secs_f64());
    // Over the limit: refused before any work, naming the limit.
    std::fs::write(d.join("huge.grid"), "coarse: [linear(1..=4096 step 1)]\nrefine: [none, binary(1..=30 step 1)]\n")
        .unwrap();
    assert_refused(&d, &["sweep", "--grid", "huge.grid", "--out", "huge"], "more than 100000");
    assert!(!d.join("huge").exists());
    std::fs::remove_dir_all(&d).ok();
}

/// A count that leaves nothing to measure is refused up front with its range, before any
/// scene is read (`render --frames 0` printed a frame time from no frame).
#[test]
fn render_refuses_zero_frames_with_the_range() {
    let d = scratch("frames");
    assert_refused(
        &d,
        &["render", "linear(8)", "--scene", "scene:step", "--frames", "0", "--out", "o"],
        "allowed 1..=100000",
    );
    assert!(!d.join("o").exists());
    std::fs::remove_dir_all(&d).ok();
}
