//! `relief report DIR --add FILE` through the binary on a synthetic sweep folder (no GPU):
//! the browser's hits are made here from the exact first hits themselves, each moved a known
//! distance along its ray, so the RMS t error the command must score is known beforehand.

use std::path::PathBuf;
use std::process::Command;

use relief_runtime::gpu;
use relief_runtime::results::{self, Metrics, Row};
use relief_runtime::scene_from_arg;
use relief_runtime::{reference_hits, Sampling};

const PIPELINE: &str = "linear(16)+binary(5)";
/// How far past its exact first hit every browser hit lies, in t.
const DT: f64 = 1e-3;

fn relief(args: &[&str]) -> (bool, String, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_relief")).args(args).output().unwrap();
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

#[test]
fn add_scores_a_browsers_hits_sets_aside_what_the_sweep_lacks_and_refuses_a_second_add() {
    let dir = std::env::temp_dir().join(format!("relief-report-add-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let native = Row {
        grid: "g".into(),
        metrics: Metrics {
            pipeline: PIPELINE.parse().unwrap(),
            scene: "scene:rocks".into(),
            size: 32,
            adapter: "synthetic".into(),
            frame_ms_median: 1.0,
            ref_err_t_rms: 0.01,
            ..Default::default()
        },
        status: relief_runtime::results::Status::Ok,
        relief_version: "test".into(),
        ..Default::default()
    };
    results::append(&dir, &native).unwrap();

    // The exact hits of the shipped rays on the heights as stored, each moved DT along its ray.
    let scene = scene_from_arg("scene:rocks").unwrap();
    let mut on_device = scene.clone();
    on_device.height.data = gpu::scene_uploads(&scene, true).height_levels[0].data.clone();
    let rays = scene.rays(32);
    let refs = reference_hits(&on_device, &rays, Sampling::Bilinear).unwrap();
    assert!(refs.iter().all(|r| r.is_some()), "a repeating scene: every ray hits");
    let mut bytes = Vec::new();
    for (r, h) in rays.iter().zip(&refs) {
        let t = h.unwrap().t + DT;
        let hit = relief_dsl::abi::ProbeHit {
            t: t as f32,
            u: (r.origin[0] as f64 + r.dir[0] as f64 * t) as f32,
            v: (r.origin[1] as f64 + r.dir[1] as f64 * t) as f32,
            z: (1.0 + r.dir[2] as f64 * t) as f32,
            coarse_steps: 4,
            refine_steps: 5,
            fetches: 10,
            converged: 1,
            clipped: 0,
        };
        bytes.extend_from_slice(bytemuck::bytes_of(&hit));
    }
    let row = |size: u32| {
        serde_json::json!({ "pipeline": PIPELINE, "scene": "scene:rocks", "size": size, "frame_ms": [2.0, 4.0, 3.0],
            "frames_per_block": 8, "probe_rays": rays.len(), "probe_stride": 1,
            "hits_b64": relief_runtime::io::base64::encode(&bytes) })
    };
    let file: PathBuf = dir.join("browser.json");
    let body = serde_json::json!({ "format": "relief-browser-results", "version": 1, "relief_version": "test",
        "adapter": "Test GPU", "timer": "wall-clock", "user_agent": "test", "rows": [row(32), row(48)] });
    std::fs::write(&file, body.to_string()).unwrap();
    let (d, f) = (dir.to_str().unwrap(), file.to_str().unwrap());

    let (ok, out, err) = relief(&["report", d, "--add", f]);
    assert!(ok, "{out}\n{err}");
    assert!(out.contains("1 rows added under `Test GPU (WebGPU, wall-clock)`"), "{out}");
    assert!(out.contains(&format!("set aside: `{PIPELINE}` on scene:rocks at 48²: not in the sweep")), "{out}");
    let rows = results::read(&dir).unwrap().rows;
    assert_eq!(rows.len(), 2);
    let m = &rows[1].metrics;
    assert_eq!(m.adapter, "Test GPU (WebGPU, wall-clock)");
    // Every hit is DT past the exact one; rounding t (≤ 2) and the hit to f32 moves it by
    // at most ~2.4e-7.
    assert!((m.ref_err_t_rms - DT).abs() < 1e-6, "{}", m.ref_err_t_rms);
    assert_eq!((m.frame_ms_median, m.avg_fetches, m.avg_coarse_steps, m.frames_per_block), (3.0, 10.0, 4.0, 8));
    assert_eq!(m.nan_count, 0);
    let tables = std::fs::read_to_string(dir.join("tables.md")).unwrap();
    assert!(tables.contains("Test GPU (WebGPU, wall-clock): frame ms (median)"), "no column set for the browser");
    assert!(tables.contains("not in the sweep"), "the report does not list what was set aside");

    // Again: refused in one line; with --replace, the row is replaced.
    let (ok, _, err) = relief(&["report", d, "--add", f]);
    assert!(
        !ok && err.contains("already holds 1 rows") && err.contains("--replace") && err.trim().lines().count() == 1,
        "{err}"
    );
    let (ok, out, err) = relief(&["report", d, "--add", f, "--replace"]);
    assert!(ok && out.contains("1 earlier rows replaced"), "{out}\n{err}");
    assert_eq!(results::read(&dir).unwrap().rows.len(), 2);
    // --add goes into one folder; --replace means nothing without --add.
    let (ok, _, err) = relief(&["report", d, d, "--add", f]);
    assert!(!ok && err.contains("--add adds to one sweep folder; 2 were given"), "{err}");
    let (ok, _, err) = relief(&["report", d, "--replace"]);
    assert!(!ok && err.contains("--add"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
