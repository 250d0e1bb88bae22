//! The `relief` binary: files written, and one-line errors with a non-zero exit.

use std::process::Command;

fn relief() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_relief"));
    c.env("LP_NUM_THREADS", "1").env("NODEVICE_SELECT", "1");
    c
}

fn tmp(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("relief-cli-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&d).ok();
    d
}

#[test]
fn gen_all_writes_five_files_per_combination() {
    let out = tmp("gen");
    let st = relief().args(["gen", "--all", "--out"]).arg(&out).status().unwrap();
    assert!(st.success());
    let files: Vec<_> = std::fs::read_dir(&out).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    assert_eq!(files.len(), relief_dsl::Pipeline::all_defaults().len() * 5);
    assert!(files.contains(&"linear_32__binary_5__shadow-soft_16.frag.glsl".to_string()));
    assert!(!files.iter().any(|f| f.ends_with(".tmp")));
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn render_writes_frame_error_metrics_and_hits() {
    let out = tmp("render");
    let o = relief()
        .args(["render", "linear(8)+binary(3)", "--scene", "scene:step", "--size", "32", "--frames", "2", "--dump-hits", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary = String::from_utf8_lossy(&o.stdout);
    assert_eq!(summary.lines().count(), 1, "{summary}");
    let m: serde_json::Value = serde_json::from_slice(&std::fs::read(out.join("metrics.json")).unwrap()).unwrap();
    for key in [
        "pipeline", "scene", "size", "adapter", "frame_ms_median", "frame_ms_p10", "frame_ms_p90", "mse_dissertation",
        "ref_err_t_rms", "ref_err_uv_texels_rms", "missed_rate", "nan_count", "avg_iterations", "avg_fetches", "frame_ms_mean",
        "mse_dissertation_mean", "outside_count", "nonconverged_rate", "avg_coarse_steps", "avg_refine_steps", "false_hit_rate",
    ] {
        assert!(m.get(key).is_some(), "metrics.json lacks {key}");
    }
    assert_eq!(m["pipeline"], "linear(8)+binary(3)");
    assert!(m["frame_ms_median"].as_f64().unwrap() > 0.0);
    let csv = std::fs::read_to_string(out.join("hits.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        "x,y,origin_u,origin_v,dir_x,dir_y,dir_z,t,u,v,z,t_ref,u_ref,v_ref,coarse_steps,refine_steps,fetches,converged,clipped"
    );
    let rows: Vec<Vec<f64>> = lines.map(|l| l.split(',').map(|x| x.parse().unwrap()).collect()).collect();
    assert!(rows.len() > 32 * 32 / 2);
    // The documented ray: the point at t is (origin + t·dir.xy, 1 + t·dir.z), the hit's z.
    for r in &rows {
        let (t, z, dz) = (r[7], r[10], r[6]);
        assert!((1.0 + t * dz - z).abs() < 1e-5);
        // At most 8 linear passes, then exactly 3 binary passes; linear always converges
        // (the floor is surface).
        assert!((1.0..=8.0).contains(&r[14]), "coarse steps {}", r[14]);
        assert_eq!((r[15], r[17]), (3.0, 1.0));
    }
    for f in ["frame.png", "error.png"] {
        let img = image::open(out.join(f)).unwrap();
        assert!(img.width() >= 32);
    }
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn bad_input_gives_one_line_and_a_failure() {
    for args in [
        vec!["render", "linear(8)", "--scene", "scene:nope", "--out", "/tmp/relief-x"],
        vec!["render", "lnear(8)", "--scene", "scene:step", "--out", "/tmp/relief-x"],
        vec!["gen", "linear(0)", "--out", "/tmp/relief-x"],
        vec!["gen", "linear(5)", "--out", "/proc/relief-cannot-write-here"],
        vec!["gen", "--no-such-flag"],
        vec!["render", "linear(8)"],
        vec!["sweep", "--grid", "no_such_grid", "--out", "/tmp/relief-x"],
        vec!["report", "/tmp/relief-no-such-sweep-folder"],
        vec!["frobnicate"],
    ] {
        let o = relief().args(&args).output().unwrap();
        assert!(!o.status.success(), "{args:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(err.starts_with("relief: error:"), "{err}");
    }
}

#[test]
fn maps_writes_png_and_npy_from_a_scene_or_a_file() {
    let out = tmp("maps");
    std::fs::create_dir_all(&out).unwrap();
    // A scene by name, to NumPy's format: float32, shape [h, w].
    let npy = out.join("cone.npy");
    let o = relief().args(["maps", "scene:step", "--kind", "cone", "--out"]).arg(&npy).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let bytes = std::fs::read(&npy).unwrap();
    assert!(bytes.starts_with(b"\x93NUMPY"));
    let header = String::from_utf8_lossy(&bytes[10..128.min(bytes.len())]).to_string();
    assert!(header.contains("'<f4'") && header.contains("(256, 256)"), "{header}");
    // An image file; .png defaults to a 16-bit encoding.
    let img = out.join("h.png");
    image::GrayImage::from_fn(16, 16, |x, _| image::Luma([(x * 16) as u8])).save(&img).unwrap();
    let png = out.join("cone.png");
    let o = relief().args(["maps"]).arg(&img).args(["--kind", "cone_normal", "--out"]).arg(&png).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let decoded = image::open(&png).unwrap();
    assert_eq!((decoded.width(), decoded.height()), (16, 16));
    assert!(matches!(decoded, image::DynamicImage::ImageLuma16(_)));
    // Bad input: a kind that does not exist, a file that does not exist.
    for args in [vec!["maps", "scene:step", "--kind", "cones", "--out", "/tmp/x.npy"], vec!["maps", "/no/such.png", "--kind", "cone", "--out", "/tmp/x.npy"]] {
        let o = relief().args(&args).output().unwrap();
        assert!(!o.status.success());
        assert_eq!(String::from_utf8_lossy(&o.stderr).trim().lines().count(), 1);
    }
    std::fs::remove_dir_all(&out).ok();
}

/// `--write-depth`: the depth buffer holds the hit's depth (a pixel depth offset). Exact
/// methods agree with the reference hits' NDC depth to 1e-4 (the goal; measured
/// ~2e-7 on lavapipe), a coarse linear search does not, and depth.png / depth.npy are written.
#[test]
fn render_writes_the_depth_of_the_hit() {
    let dir = std::env::temp_dir().join(format!("relief-depth-{}", std::process::id()));
    let depth_err = |pipeline: &str| -> f64 {
        let o = relief()
            .args(["render", pipeline, "--scene", "scene:rocks", "--size", "64", "--frames", "1", "--write-depth", "--out"])
            .arg(&dir)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let m: serde_json::Value = serde_json::from_slice(&std::fs::read(dir.join("metrics.json")).unwrap()).unwrap();
        m["depth_err_max"].as_f64().expect("depth_err_max in metrics.json")
    };
    for exact in ["maxmip(96)", "linear(400)+interval(8)"] {
        let e = depth_err(exact);
        assert!(e < 1e-4, "{exact}: depth error {e}");
    }
    let e = depth_err("linear(8)");
    assert!(e > 1e-4, "linear(8) ends far from the first hit on rocks, and its depth shows it: {e}");
    let npy = std::fs::read(dir.join("depth.npy")).unwrap();
    assert_eq!(npy.len() % 4, 0);
    assert!(image::open(dir.join("depth.png")).unwrap().width() == 64);
    // Without the flag there is no depth.
    let o = relief().args(["render", "linear(8)", "--scene", "scene:rocks", "--size", "32", "--frames", "1", "--out"]).arg(dir.join("plain")).output().unwrap();
    assert!(o.status.success());
    let m: serde_json::Value = serde_json::from_slice(&std::fs::read(dir.join("plain/metrics.json")).unwrap()).unwrap();
    assert!(m.get("depth_err_max").is_none());
    std::fs::remove_dir_all(&dir).ok();
}
