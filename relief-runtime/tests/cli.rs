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
    let files: Vec<_> =
        std::fs::read_dir(&out).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    assert_eq!(files.len(), relief_dsl::Pipeline::all_defaults().len() * 5);
    assert!(files.contains(&"linear_32__binary_5__shadow-soft_16.frag.glsl".to_string()));
    assert!(!files.iter().any(|f| f.ends_with(".tmp")));
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn render_writes_frame_error_metrics_and_hits() {
    let out = tmp("render");
    let o = relief()
        .args([
            "render",
            "linear(8)+binary(3)",
            "--scene",
            "scene:step",
            "--size",
            "32",
            "--frames",
            "2",
            "--dump-hits",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary = String::from_utf8_lossy(&o.stdout);
    assert_eq!(summary.lines().count(), 1, "{summary}");
    let m: serde_json::Value = serde_json::from_slice(&std::fs::read(out.join("metrics.json")).unwrap()).unwrap();
    for key in [
        "pipeline",
        "scene",
        "size",
        "adapter",
        "frame_ms_median",
        "frame_ms_p10",
        "frame_ms_p90",
        "mse_dissertation",
        "ref_err_t_rms",
        "ref_err_uv_texels_rms",
        "missed_rate",
        "past_rate",
        "skipped_rate",
        "ref_err_t_median",
        "ref_err_t_p90",
        "ref_err_t_p99",
        "mse_worst1_share",
        "nan_count",
        "avg_iterations",
        "avg_fetches",
        "frame_ms_mean",
        "mse_dissertation_mean",
        "outside_count",
        "nonconverged_rate",
        "avg_coarse_steps",
        "avg_refine_steps",
        "false_hit_rate",
    ] {
        assert!(m.get(key).is_some(), "metrics.json lacks {key}");
    }
    assert_eq!(m["pipeline"], "linear(8)+binary(3)");
    assert!(m["frame_ms_median"].as_f64().unwrap() > 0.0);
    // The shading constants an engine needs to reproduce the frame (issue 39): the render
    // entry's ambient share of 1/4, the dark blue-grey background, the scene's light.
    let sh = &m["shading"];
    assert_eq!(sh["ambient"].as_f64(), Some(0.25), "{sh}");
    let clear: Vec<f64> = sh["clear_color_linear"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    assert_eq!(clear, [0.02, 0.02, 0.03, 1.0]);
    let l = relief_runtime::Scene::by_name("step", None).unwrap().light_dir;
    let light: Vec<f64> = sh["light_dir"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    assert_eq!(light, [l.x as f64, l.y as f64, l.z as f64]);
    let formula = sh["formula"].as_str().unwrap();
    assert!(formula.contains("max(dot(n, l), 0)") && formula.contains("ambient * ao"), "{formula}");
    assert!(sh["texture_space"].as_str().unwrap().contains("row 0 at v = 0"));
    let csv = std::fs::read_to_string(out.join("hits.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        "x,y,origin_u,origin_v,dir_x,dir_y,dir_z,t,u,v,z,t_ref,u_ref,v_ref,coarse_steps,refine_steps,fetches,converged,clipped,height_at_hit,level,coarse_step_texels"
    );
    let rows: Vec<Vec<f64>> = lines.map(|l| l.split(',').map(|x| x.parse().unwrap()).collect()).collect();
    assert!(rows.len() > 32 * 32 / 2);
    // The new columns: lod=zero samples level 0; linear(8) steps 1/8 in t, |dir.xy|/8 in u, v,
    // times the map's side in texels; the mean of (height at hit − z)² is the metrics' MSE.
    let step = relief_runtime::Scene::by_name("step", None).unwrap();
    let texels = step.height.width.max(step.height.height) as f64;
    let mut sq = 0.0;
    for r in &rows {
        assert_eq!(r[20], 0.0);
        let want = (r[4] * r[4] + r[5] * r[5]).sqrt() * texels / 8.0;
        assert!((r[21] - want).abs() < 1e-5 * want.max(1.0), "step {} texels, want {want}", r[21]);
        sq += (r[19] - r[10]).powi(2);
    }
    let mse = m["mse_dissertation_mean"].as_f64().unwrap();
    assert!((sq / rows.len() as f64 - mse).abs() <= 1e-6 * mse.max(1e-12), "{} vs {mse}", sq / rows.len() as f64);
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
        vec!["render", "linear(8)", "--scene", "scene:step", "--view", "disertation", "--out", "/tmp/relief-x"],
        vec!["sweep", "--grid", "no_such_grid", "--out", "/tmp/relief-x"],
        vec!["report", "/tmp/relief-no-such-sweep-folder"],
        vec!["serve", "/tmp/relief-no-such-report-folder"],
        vec!["serve", "/etc/hostname"],
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
    // The patch map in f32: [h, w, 4] on the cell grid (256² cells under the scene's repeat).
    let patch = out.join("patch.npy");
    let o = relief().args(["maps", "scene:step", "--kind", "cell_patch", "--out"]).arg(&patch).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let bytes = std::fs::read(&patch).unwrap();
    let header = String::from_utf8_lossy(&bytes[10..128.min(bytes.len())]).to_string();
    assert!(header.contains("'<f4'") && header.contains("(256, 256, 4)"), "{header}");
    // Bad input: a kind that does not exist, a file that does not exist, the patch map
    // quantised (png's default unorm16, or f16 asked for).
    for args in [
        vec!["maps", "scene:step", "--kind", "cones", "--out", "/tmp/x.npy"],
        vec!["maps", "/no/such.png", "--kind", "cone", "--out", "/tmp/x.npy"],
        vec!["maps", "scene:step", "--kind", "cell_patch", "--out", "/tmp/x.png"],
        vec!["maps", "scene:step", "--kind", "cell_patch", "--encoding", "f16", "--out", "/tmp/x.npy"],
    ] {
        let o = relief().args(&args).output().unwrap();
        assert!(!o.status.success(), "{args:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        if args.contains(&"cell_patch") {
            assert!(err.contains("--encoding f32"), "{err}");
        }
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
            .args([
                "render",
                pipeline,
                "--scene",
                "scene:rocks",
                "--size",
                "64",
                "--frames",
                "1",
                "--write-depth",
                "--out",
            ])
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
    let o = relief()
        .args(["render", "linear(8)", "--scene", "scene:rocks", "--size", "32", "--frames", "1", "--out"])
        .arg(dir.join("plain"))
        .output()
        .unwrap();
    assert!(o.status.success());
    let m: serde_json::Value = serde_json::from_slice(&std::fs::read(dir.join("plain/metrics.json")).unwrap()).unwrap();
    assert!(m.get("depth_err_max").is_none());
    std::fs::remove_dir_all(&dir).ok();
}

/// A raw HTTP/1.1 request to 127.0.0.1:`port` (the target sent as given, unnormalised):
/// the status code, the headers and the body.
fn http(port: u16, request: &str) -> (u16, String, Vec<u8>) {
    use std::io::{Read, Write};
    let mut s = std::net::TcpStream::connect(("127.0.0.1", port)).unwrap();
    s.set_read_timeout(Some(std::time::Duration::from_secs(20))).unwrap();
    s.write_all(request.as_bytes()).unwrap();
    let mut reply = Vec::new();
    s.read_to_end(&mut reply).unwrap();
    let split = reply.windows(4).position(|w| w == b"\r\n\r\n").unwrap_or_else(|| panic!("no head in {reply:?}"));
    let head = String::from_utf8(reply[..split].to_vec()).unwrap();
    let code = head.split_whitespace().nth(1).unwrap().parse().unwrap();
    (code, head, reply[split + 4..].to_vec())
}

fn get(port: u16, target: &str) -> (u16, String, Vec<u8>) {
    http(port, &format!("GET {target} HTTP/1.1\r\nHost: localhost\r\n\r\n"))
}

/// The server stops when the test ends, passed or not.
struct Serving(std::process::Child);
impl Drop for Serving {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

#[test]
fn serve_answers_files_inside_its_folder_and_nothing_outside() {
    use std::io::BufRead;
    let base = tmp("serve");
    let (root, outside) = (base.join("report"), base.join("outside"));
    std::fs::create_dir_all(root.join("report")).unwrap();
    std::fs::create_dir_all(&outside).unwrap();
    std::fs::write(root.join("index.html"), "<!DOCTYPE html><title>r</title>").unwrap();
    std::fs::write(root.join("report/a b.svg"), "<svg xmlns=\"http://www.w3.org/2000/svg\"/>").unwrap();
    std::fs::write(outside.join("secret.txt"), "SECRET").unwrap();
    // Links that lead out of the folder, to a file and to a folder; one that stays inside.
    std::os::unix::fs::symlink("../outside/secret.txt", root.join("out-file")).unwrap();
    std::os::unix::fs::symlink("../outside", root.join("out-dir")).unwrap();
    std::os::unix::fs::symlink("index.html", root.join("in-link.html")).unwrap();

    let mut child =
        relief().args(["serve", "--port", "0"]).arg(&root).stdout(std::process::Stdio::piped()).spawn().unwrap();
    let stdout = child.stdout.take().unwrap();
    let _serving = Serving(child);
    let mut line = String::new();
    std::io::BufReader::new(stdout).read_line(&mut line).unwrap();
    let url =
        line.split_whitespace().find(|w| w.starts_with("http://")).unwrap_or_else(|| panic!("no URL in {line:?}"));
    let port: u16 = url
        .trim_start_matches("http://127.0.0.1:")
        .trim_end_matches([';', '/'])
        .parse()
        .unwrap_or_else(|_| panic!("not 127.0.0.1: {url}"));

    let (code, head, body) = get(port, "/");
    assert_eq!((code, body.as_slice()), (200, b"<!DOCTYPE html><title>r</title>".as_slice()));
    assert!(head.contains("Content-Type: text/html"), "{head}");
    let (code, head, _) = get(port, "/report/a%20b.svg?x=1#top");
    assert_eq!(code, 200);
    assert!(head.contains("Content-Type: image/svg+xml"), "{head}");
    assert_eq!(get(port, "/in-link.html").0, 200, "a link inside the folder is served");
    // A folder with a page: its URL gains the `/` its relative links need.
    std::fs::create_dir_all(root.join("sub")).unwrap();
    std::fs::write(root.join("sub/index.html"), "sub page").unwrap();
    let (code, head, _) = get(port, "/sub?x=1");
    assert_eq!(code, 301);
    assert!(head.contains("\r\nLocation: /sub/\r\n"), "{head}");
    assert_eq!(get(port, "/sub/").2, b"sub page");
    let (code, _, body) = http(port, "HEAD /index.html HTTP/1.1\r\n\r\n");
    assert_eq!((code, body.len()), (200, 0));

    for target in [
        "/../outside/secret.txt",
        "/report/../../outside/secret.txt",
        "/%2e%2e/outside/secret.txt",
        "/report%2F..%2F..%2Foutside%2Fsecret.txt",
        "/..%5Coutside%5Csecret.txt",
        &format!("/{}", outside.join("secret.txt").display()),
        &format!("/%2F{}", outside.join("secret.txt").display().to_string().trim_start_matches('/')),
        "/out-file",
        "/out-dir/secret.txt",
        "/no-such-file.html",
        "/report",
        "/%zz",
        "relative.html",
    ] {
        let (code, _, body) = get(port, target);
        assert_eq!(code, 404, "{target}");
        assert!(!String::from_utf8_lossy(&body).contains("SECRET"), "{target}");
    }
    assert_eq!(http(port, "POST /index.html HTTP/1.1\r\nContent-Length: 0\r\n\r\n").0, 405);
    assert_eq!(http(port, "nonsense\r\n\r\n").0, 400);
    // Bound to 127.0.0.1 itself: another loopback address is refused.
    assert!(std::net::TcpStream::connect(("127.0.0.2", port)).is_err(), "listening beyond 127.0.0.1");

    // A port in use: one line naming it, and a failure.
    let o = relief().args(["serve", "--port", &port.to_string()]).arg(&root).output().unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.starts_with("relief: error:") && err.contains(&format!("port {port}")) && err.contains("in use"),
        "{err}"
    );
    std::fs::remove_dir_all(&base).ok();
}
#[path = "cli/hostile.rs"]
mod hostile;

/// `relief render` on a scene file that names a mesh draws the mesh with a `curved=` pipeline
/// (`frame.png`, relief where the sphere is and the clear colour in the corners), and refuses
/// a flat pipeline there in one line; `relief scene measure` prints one row per mode.
#[test]
fn render_and_measure_draw_a_mesh_scene() {
    let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/meshes/sphere_rocks.toml");
    let out = tmp("mesh_render");
    let o = relief()
        .args(["render", "--size", "32", "--scene"])
        .arg(&scene)
        .arg("--out")
        .arg(&out)
        .arg("linear(16)+curved=quadric")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = image::open(out.join("frame.png")).unwrap().to_rgba8();
    let (corner, centre) = (img.get_pixel(0, 0).0, img.get_pixel(16, 16).0);
    assert_ne!(corner, centre, "the sphere covers the centre, not the corner");
    let o = relief()
        .args(["render", "--size", "32", "--scene"])
        .arg(&scene)
        .arg("--out")
        .arg(&out)
        .arg("linear(16)")
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && e.contains("curved=") && e.trim().lines().filter(|l| !l.contains("XDG")).count() == 1,
        "{e}"
    );
    let o = relief()
        .args(["scene", "measure", "--size", "16", "--pairs", "0", "--pipeline", "linear(8)"])
        .arg(&scene)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for mode in ["none", "quadric", "prism"] {
        assert!(text.lines().any(|l| l.starts_with(mode)), "{text}");
    }
}
