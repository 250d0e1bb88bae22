//! The real scenes (the POM sample's height maps, embedded) and TOML scene files.
//!
//! Heights are checked against the TGA files in `relief-runtime/scenes/tatarchuk/` decoded
//! here by hand (an uncompressed 32-bit TGA is an 18-byte header and BGRA rows), so neither
//! the image crate nor the embedding is trusted.

use std::path::{Path, PathBuf};

use relief_runtime::{load_scene_file, scene_from_arg, Scene, SceneError, REAL_SCENES};
use relief_runtime::{EdgeMode, HeightMap, LoadOptions};

fn repo_file(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

/// (width, height, RGBA rows top first) of an uncompressed true-colour 32-bit TGA.
fn decode_tga(bytes: &[u8]) -> (usize, usize, Vec<[u8; 4]>) {
    assert_eq!(bytes[2], 2, "uncompressed true-colour");
    assert_eq!(bytes[16], 32, "32 bits per pixel");
    let id_len = bytes[0] as usize;
    let w = u16::from_le_bytes([bytes[12], bytes[13]]) as usize;
    let h = u16::from_le_bytes([bytes[14], bytes[15]]) as usize;
    let top_first = bytes[17] & 0x20 != 0;
    let body = &bytes[18 + id_len..];
    let mut out = vec![[0u8; 4]; w * h];
    for row in 0..h {
        let y = if top_first { row } else { h - 1 - row };
        for x in 0..w {
            let p = &body[(row * w + x) * 4..];
            out[y * w + x] = [p[2], p[1], p[0], p[3]];
        }
    }
    (w, h, out)
}

fn tga(file: &str) -> (usize, usize, Vec<[u8; 4]>) {
    decode_tga(&std::fs::read(repo_file(&format!("scenes/tatarchuk/{file}"))).unwrap())
}

#[test]
fn every_real_scene_loads_with_its_size_and_the_alpha_as_height() {
    assert_eq!(REAL_SCENES.len(), 7);
    for r in REAL_SCENES {
        let (w, h, px) = tga(r.file);
        let s = Scene::by_name(r.name, None).unwrap();
        assert_eq!(s.name, format!("scene:{}", r.name));
        assert_eq!((s.height.width, s.height.height), (w, h), "{}", r.name);
        assert_eq!(w, if ["bump", "dent"].contains(&r.name) { 128 } else { 256 });
        // Every texel is alpha / 255 (no inversion, rows in the same order).
        for (i, (a, p)) in s.height.data.iter().zip(&px).enumerate() {
            assert_eq!(*a, p[3] as f32 / 255.0, "{} texel {i}", r.name);
        }
        let (lo, hi) = px.iter().fold((255u8, 0u8), |(lo, hi), p| (lo.min(p[3]), hi.max(p[3])));
        let (slo, shi) = s.height.data.iter().fold((1f32, 0f32), |(lo, hi), &v| (lo.min(v), hi.max(v)));
        assert_eq!((slo, shi), (lo as f32 / 255.0, hi as f32 / 255.0), "{}", r.name);
        assert!(hi > lo + 50, "{}: a real relief spans a good part of [0, 1]", r.name);
        assert_eq!(s.edge, EdgeMode::Repeat);
        assert_eq!(s.depth_scale, r.depth_scale);
        assert_eq!(s.normal.is_some(), !["bump", "dent"].contains(&r.name), "{}", r.name);
        // A scene argument gives the same scene.
        assert_eq!(scene_from_arg(&format!("scene:{}", r.name)).unwrap(), s);
    }
}

#[test]
fn the_depth_scales_are_the_samples_height_scales() {
    // The POM sample's own height scales (fraction of the width), from its README.
    let want = [
        ("rocks", 0.1),
        ("stones", 0.02),
        ("wall", 0.06),
        ("four", 0.2),
        ("saint", 0.08),
        ("bump", 0.2),
        ("dent", 0.2),
    ];
    for (name, d) in want {
        assert_eq!(Scene::by_name(name, None).unwrap().depth_scale, d, "{name}");
    }
}

#[test]
fn smaller_sizes_are_box_filtered_and_others_refused() {
    for (name, size) in [("rocks", 64usize), ("dent", 64), ("four", 128)] {
        let r = REAL_SCENES.iter().find(|r| r.name == name).unwrap();
        let (w, _, px) = tga(r.file);
        let k = w / size;
        let s = Scene::by_name(name, Some(size)).unwrap();
        assert_eq!((s.height.width, s.height.height), (size, size));
        for y in 0..size {
            for x in 0..size {
                let mut sum = 0u32;
                for j in 0..k {
                    for i in 0..k {
                        sum += px[(y * k + j) * w + x * k + i][3] as u32;
                    }
                }
                let want = sum as f64 / (255.0 * (k * k) as f64);
                assert!((s.height.data[y * size + x] as f64 - want).abs() < 1e-6, "{name} ({x}, {y})");
            }
        }
        if let Some(n) = &s.normal {
            assert_eq!((n.width, n.height), (size, size));
            assert!(n.data.iter().all(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2] - 1.0).abs() < 1e-4));
        }
    }
    for (name, size) in [("rocks", 100usize), ("rocks", 512), ("bump", 256)] {
        let e = Scene::by_name(name, Some(size)).unwrap_err();
        assert!(matches!(e, SceneError::BadRealSize { .. }), "{e}");
        let m = e.to_string();
        assert!(m.contains(name) && m.contains(&size.to_string()) && !m.contains('\n'), "{m}");
    }
}

/// Normals of the surface z = depth · h by central differences (x along +u, y along +v).
fn central_difference_normals(m: &HeightMap, depth: f32) -> Vec<[f32; 3]> {
    let (w, h) = (m.width as i64, m.height as i64);
    let mut out = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let e = EdgeMode::Repeat;
            let dx = (m.texel(x + 1, y, e) - m.texel(x - 1, y, e)) * depth * w as f32 / 2.0;
            let dy = (m.texel(x, y + 1, e) - m.texel(x, y - 1, e)) * depth * h as f32 / 2.0;
            let l = (dx * dx + dy * dy + 1.0).sqrt();
            out.push([-dx / l, -dy / l, 1.0 / l]);
        }
    }
    out
}

/// Per axis, the share of texels with a clear slope (|derived component| > 0.05) where the
/// RGB normal's component has the same sign as the derived one.
fn sign_agreement(rgb: &[[f32; 3]], derived: &[[f32; 3]]) -> [f64; 2] {
    let mut out = [0.0; 2];
    for (axis, o) in out.iter_mut().enumerate() {
        let (mut agree, mut n) = (0usize, 0usize);
        for (a, b) in rgb.iter().zip(derived) {
            if b[axis].abs() > 0.05 {
                n += 1;
                agree += (a[axis].signum() == b[axis].signum()) as usize;
            }
        }
        *o = agree as f64 / n.max(1) as f64;
    }
    out
}

#[test]
fn rgb_normals_agree_with_the_height() {
    // The RGB normals are read as x = red along +u, y = −green along +v (green points to the
    // image's top): on every map that keeps them, their signs agree with the alpha's slopes on
    // both axes at most texels (the 0.75 goal fails for a flipped axis, which agrees at ~0).
    for name in ["rocks", "stones", "wall", "four", "saint"] {
        let s = Scene::by_name(name, None).unwrap();
        let n = s.normal.as_ref().unwrap();
        let [ax, ay] = sign_agreement(&n.data, &central_difference_normals(&s.height, s.depth_scale));
        eprintln!("{name}: sign agreement x {ax:.3}, y {ay:.3}");
        assert!(ax > 0.75 && ay > 0.75, "{name}: RGB normals disagree with the height: x {ax:.3}, y {ay:.3}");
    }
    // bump and dent share one RGB, which disagrees with each one's own alpha on one axis:
    // that is why their normals are derived.
    for name in ["bump", "dent"] {
        let r = REAL_SCENES.iter().find(|r| r.name == name).unwrap();
        let (_, _, px) = tga(r.file);
        // Read the way the other maps are (green towards the image's top, −v).
        let c = |v: u8| 2.0 * v as f32 / 255.0 - 1.0;
        let rgb: Vec<[f32; 3]> = px.iter().map(|p| [c(p[0]), -c(p[1]), c(p[2])]).collect();
        let s = Scene::by_name(name, None).unwrap();
        let [ax, ay] = sign_agreement(&rgb, &central_difference_normals(&s.height, s.depth_scale));
        eprintln!("{name} (RGB, not used): sign agreement x {ax:.3}, y {ay:.3}");
        assert!(ax.min(ay) < 0.5, "{name}: the RGB agrees on both axes ({ax:.3}, {ay:.3}); the docs say it does not");
    }
}

fn tmpdir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("relief-scenes-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&d).ok();
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn the_shipped_scene_file_is_the_builtin_rocks() {
    let f = load_scene_file(&repo_file("scenes/rocks.toml")).unwrap();
    let b = Scene::by_name("rocks", None).unwrap();
    assert_eq!(f.name, "rocks");
    assert_eq!(f.height, b.height);
    assert_eq!(f.normal, b.normal);
    assert_eq!(
        (f.depth_scale, f.tiling, f.edge, f.camera, f.light_dir),
        (b.depth_scale, b.tiling, b.edge, b.camera, b.light_dir)
    );
}

#[test]
fn a_scene_file_round_trips_every_key() {
    let d = tmpdir("roundtrip");
    std::fs::create_dir_all(d.join("maps")).unwrap();
    // Height in the green channel, written as a depth map (white = deep); albedo and normals.
    let img = image::RgbaImage::from_fn(8, 4, |x, y| image::Rgba([10, (x * 30 + y) as u8, 200, 255]));
    img.save(d.join("maps/h.png")).unwrap();
    // Normals tilted towards the image's top in green: −v with `normal_green = "up"`.
    image::RgbaImage::from_fn(8, 4, |_, _| image::Rgba([128, 255, 128, 255])).save(d.join("maps/n.png")).unwrap();
    image::RgbaImage::from_fn(2, 2, |x, _| image::Rgba([x as u8 * 200, 50, 60, 255])).save(d.join("a.png")).unwrap();
    let toml = r#"
name = "mine"
depth_scale = 0.05
tiling = 2
edge = "clamp"
light = [0, 0, 2]
albedo = "a.png"
normal_map = "maps/n.png"
normal_green = "up"
lod = "zero"
[height_map]
path = "maps/h.png"
channel = "g"
white = "depth"
[camera]
angle = 60
azimuth = 30.5
distance = 4.0
fov = 35
"#;
    std::fs::write(d.join("s.toml"), toml).unwrap();
    let s = load_scene_file(&d.join("s.toml")).unwrap();
    assert_eq!(s.name, "mine");
    assert_eq!((s.height.width, s.height.height), (8, 4));
    for y in 0..4 {
        for x in 0..8 {
            assert_eq!(s.height.data[y * 8 + x], 1.0 - (x * 30 + y) as f32 / 255.0);
        }
    }
    assert_eq!((s.depth_scale, s.tiling, s.edge), (0.05, 2.0, EdgeMode::Clamp));
    assert_eq!(
        (s.camera.angle_deg, s.camera.azimuth_deg, s.camera.distance, s.camera.fov_deg),
        (60.0, 30.5, 4.0, 35.0)
    );
    assert_eq!(s.camera.target, glam::Vec3::new(1.0, 1.0, 0.0), "the camera looks at the centre of the tiled quad");
    assert_eq!(s.light_dir, glam::Vec3::Z);
    let a = s.albedo.as_ref().unwrap();
    assert_eq!((a.width, a.height, a.rgba[4]), (2, 2, 200));
    let n = s.normal.as_ref().unwrap();
    assert_eq!((n.width, n.height), (8, 4));
    assert!(n.data.iter().all(|v| v[1] < -0.99 && v[0].abs() < 0.01), "{:?}", n.data[0]);
    std::fs::write(
        d.join("down.toml"),
        "normal_map = \"maps/n.png\"\nnormal_green = \"down\"\n[height_map]\npath = \"maps/h.png\"\n",
    )
    .unwrap();
    let down = load_scene_file(&d.join("down.toml")).unwrap();
    assert!(down.normal.unwrap().data.iter().all(|v| v[1] > 0.99));
    // The same height map through the loader directly.
    let direct =
        HeightMap::load(d.join("maps/h.png"), &LoadOptions { channel: Some("g".parse().unwrap()), depth: true })
            .unwrap();
    assert_eq!(direct, s.height);
    // Only the height map is required; the rest takes the defaults of a loaded file.
    std::fs::write(d.join("min.toml"), "[height_map]\npath = \"maps/h.png\"\n").unwrap();
    let m = load_scene_file(&d.join("min.toml")).unwrap();
    let plain = scene_from_arg(d.join("maps/h.png").to_str().unwrap()).unwrap();
    assert_eq!(m.name, "min");
    assert_eq!(
        (m.height, m.depth_scale, m.tiling, m.edge, m.camera),
        (plain.height, plain.depth_scale, plain.tiling, plain.edge, plain.camera)
    );
    // A .toml argument is a scene file.
    assert_eq!(scene_from_arg(d.join("s.toml").to_str().unwrap()).unwrap(), s);
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn bad_scene_files_give_one_line_naming_the_file_and_the_key() {
    let d = tmpdir("errors");
    image::GrayImage::from_fn(4, 4, |x, _| image::Luma([x as u8 * 60])).save(d.join("h.png")).unwrap();
    let ok = "[height_map]\npath = \"h.png\"\n";
    // (file text, the key the message must name, words it must contain)
    let cases: &[(&str, String, &str, &[&str])] = &[
        ("unknown", format!("depth_scal = 0.1\n{ok}"), "depth_scal", &["unknown key", "did you mean `depth_scale`"]),
        (
            "unknown_nested",
            format!("{ok}[camera]\nangel = 3\n"),
            "camera.angel",
            &["unknown key", "did you mean `camera.angle`"],
        ),
        ("wrong_type", format!("tiling = \"two\"\n{ok}"), "tiling", &["expected number", "string"]),
        ("wrong_type_light", format!("light = [1, 2]\n{ok}"), "light", &["expected array of 3 numbers"]),
        ("missing_map", "[height_map]\npath = \"nope.png\"\n".into(), "height_map.path", &["nope.png", "not found"]),
        ("no_height_map", "depth_scale = 0.1\n".into(), "height_map", &["missing"]),
        ("no_path", "[height_map]\nchannel = \"r\"\n".into(), "height_map.path", &["missing"]),
        ("bad_edge", format!("edge = \"mirror\"\n{ok}"), "edge", &["mirror", "repeat", "clamp"]),
        ("bad_angle", format!("{ok}[camera]\nangle = 95\n"), "camera.angle", &["95", "out of range"]),
        ("bad_depth", format!("depth_scale = -1\n{ok}"), "depth_scale", &["positive"]),
        ("bad_channel", "[height_map]\npath = \"h.png\"\nchannel = \"q\"\n".into(), "height_map.channel", &["`q`"]),
        ("bad_white", "[height_map]\npath = \"h.png\"\nwhite = \"black\"\n".into(), "height_map.white", &["black"]),
        ("lod_level", format!("lod = \"level(99)\"\n{ok}"), "lod", &["level(99)", "out of range"]),
        ("bad_green", format!("normal_green = \"left\"\n{ok}"), "normal_green", &["left", "up", "down"]),
        ("lod_bad", format!("lod = \"high\"\n{ok}"), "lod", &["high", "zero"]),
        ("missing_albedo", format!("albedo = \"none.png\"\n{ok}"), "albedo", &["none.png", "not found"]),
    ];
    for (name, text, key, words) in cases {
        let path = d.join(format!("{name}.toml"));
        std::fs::write(&path, text).unwrap();
        let m = load_scene_file(&path).unwrap_err().to_string();
        assert_eq!(m.lines().count(), 1, "{name}: {m}");
        assert!(m.starts_with(&path.display().to_string()), "{name}: names the file: {m}");
        assert!(m.contains(&format!("key `{key}`")), "{name}: names `{key}`: {m}");
        for w in *words {
            assert!(m.contains(w), "{name}: says `{w}`: {m}");
        }
    }
    // Not TOML at all, and no file: one line naming the file.
    std::fs::write(d.join("broken.toml"), "[height_map\npath = 1").unwrap();
    let m = load_scene_file(&d.join("broken.toml")).unwrap_err().to_string();
    assert!(m.lines().count() == 1 && m.contains("broken.toml") && m.contains("not valid TOML at line 1"), "{m}");
    let m = load_scene_file(&d.join("absent.toml")).unwrap_err().to_string();
    assert!(m.lines().count() == 1 && m.contains("absent.toml") && m.contains("not found"), "{m}");
    std::fs::remove_dir_all(&d).ok();
}

// ---------------------------------------------------------------------------------------------
// The command line and the device
// ---------------------------------------------------------------------------------------------

fn relief() -> std::process::Command {
    let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_relief"));
    c.env("LP_NUM_THREADS", "1").env("NODEVICE_SELECT", "1");
    c
}

fn metrics_json(dir: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(dir.join("metrics.json")).unwrap()).unwrap()
}

#[test]
fn render_takes_a_scene_file_and_the_overrides_change_what_is_recorded() {
    let d = tmpdir("cli-render");
    // A scene file next to a copy of a real map (paths are relative to the file).
    std::fs::copy(repo_file("scenes/tatarchuk/bump_NM_height.tga"), d.join("bump.tga")).unwrap();
    let file = d.join("bump.toml");
    std::fs::write(
        &file,
        "depth_scale = 0.2\n[height_map]\npath = \"bump.tga\"\nchannel = \"a\"\n[camera]\nangle = 30\nazimuth = -90\n",
    )
    .unwrap();
    let run = |out: &str, extra: &[&str]| {
        let out = d.join(out);
        let o = relief()
            .args(["render", "linear(8)+binary(3)", "--scene"])
            .arg(&file)
            .args(["--size", "24", "--frames", "2", "--out"])
            .arg(&out)
            .args(extra)
            .output()
            .unwrap();
        assert!(o.status.success(), "{extra:?}: {}", String::from_utf8_lossy(&o.stderr));
        metrics_json(&out)
    };
    let plain = run("plain", &[]);
    assert_eq!(plain["scene"], "bump");
    assert_eq!(plain["camera"]["angle_deg"], 30.0);
    assert_eq!(plain["depth_scale"].as_f64().unwrap() as f32, 0.2);
    assert_eq!(plain["tiling"], 1.0);
    let angled = run("angled", &["--angle", "60"]);
    assert_eq!(angled["scene"], "bump@angle=60");
    assert_eq!(angled["camera"]["angle_deg"], 60.0);
    assert_eq!(angled["camera"]["azimuth_deg"], -90.0);
    let all = run("all", &["--angle", "60", "--azimuth", "10", "--depth-scale", "0.05", "--tiling", "2"]);
    assert_eq!(all["scene"], "bump@depth_scale=0.05,tiling=2,angle=60,azimuth=10");
    assert_eq!((all["camera"]["angle_deg"].as_f64(), all["camera"]["azimuth_deg"].as_f64()), (Some(60.0), Some(10.0)));
    assert_eq!(all["depth_scale"].as_f64().unwrap() as f32, 0.05);
    assert_eq!(all["tiling"], 2.0);
    // A steeper view of a deeper relief costs a coarse search more: the measurement moved.
    assert_ne!(plain["avg_iterations"], angled["avg_iterations"]);
    // Built-in real scenes by name, with an override.
    let o = relief()
        .args(["render", "linear(8)", "--scene", "rocks", "--azimuth", "45", "--size", "16", "--frames", "1", "--out"])
        .arg(d.join("rocks"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(metrics_json(&d.join("rocks"))["scene"], "scene:rocks@azimuth=45");
    // Bad overrides and bad files: one line, non-zero exit.
    std::fs::write(d.join("bad.toml"), "tilling = 2\n[height_map]\npath = \"bump.tga\"\n").unwrap();
    for extra in [
        vec!["--scene", file.to_str().unwrap(), "--angle", "90"],
        vec!["--scene", file.to_str().unwrap(), "--depth-scale", "0"],
        vec!["--scene", d.join("bad.toml").to_str().unwrap()],
        vec!["--scene", d.join("absent.toml").to_str().unwrap()],
    ] {
        let o = relief().args(["render", "linear(8)", "--out"]).arg(d.join("x")).args(&extra).output().unwrap();
        assert!(!o.status.success(), "{extra:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(err.trim().lines().count(), 1, "{extra:?}: {err}");
    }
    let o = relief()
        .args(["render", "linear(8)", "--out"])
        .arg(d.join("x"))
        .arg("--scene")
        .arg(d.join("bad.toml"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("bad.toml") && err.contains("key `tilling`") && err.contains("did you mean `tiling`"),
        "{err}"
    );
    std::fs::remove_dir_all(&d).ok();
}

/// A scene file's `lod` is the level policy of every pipeline measured on it that names
/// none: the measurement is the explicit `+lod=` one, bit for bit, and rows record it; a
/// pipeline's own lod wins (`level(0)` keeps mip 0); resuming a sweep on the file skips what
/// it recorded.
#[test]
fn a_scene_files_lod_applies_to_pipelines_that_name_none() {
    let d = tmpdir("lod-policy");
    std::fs::copy(repo_file("scenes/tatarchuk/dent_NM_height.tga"), d.join("dent.tga")).unwrap();
    let file = d.join("dent.toml");
    std::fs::write(&file, "lod = \"auto\"\nedge = \"clamp\"\n[height_map]\npath = \"dent.tga\"\nchannel = \"a\"\n")
        .unwrap();
    let scene = load_scene_file(&file).unwrap();
    assert_eq!(scene.lod, Some(relief_dsl::spec::Lod::Auto));
    std::fs::write(d.join("l2.toml"), "lod = \"level(2)\"\n[height_map]\npath = \"dent.tga\"\nchannel = \"a\"\n")
        .unwrap();
    assert_eq!(load_scene_file(&d.join("l2.toml")).unwrap().lod, Some(relief_dsl::spec::Lod::Level(2)));

    let g = relief_runtime::gpu::Gpu::new().unwrap();
    let mut prep = relief_runtime::measure::Prepared::new(&g, scene, 64).unwrap();
    let measure = |prep: &mut relief_runtime::measure::Prepared, text: &str| {
        relief_runtime::measure::measure(&g, prep, &text.parse().unwrap(), 0, 1).unwrap().metrics
    };
    let by_scene = measure(&mut prep, "linear(64)+binary(5)");
    let explicit = measure(&mut prep, "linear(64)+binary(5)+lod=auto");
    assert_eq!(by_scene.pipeline.to_string(), "linear(64)+binary(5)+lod=auto");
    assert_eq!(
        (by_scene.ref_err_t_rms, by_scene.mse_dissertation),
        (explicit.ref_err_t_rms, explicit.mse_dissertation)
    );
    let own = measure(&mut prep, "linear(64)+binary(5)+lod=level(0)");
    assert_eq!(own.pipeline.to_string(), "linear(64)+binary(5)+lod=level(0)");
    assert_ne!(own.ref_err_t_rms, by_scene.ref_err_t_rms, "the footprint level is not level 0 here");

    let grid = d.join("g.grid");
    std::fs::write(&grid, "coarse: linear(8)\n").unwrap();
    let out = d.join("sweep");
    let sweep = || {
        let o = relief()
            .args(["sweep", "--grid"])
            .arg(&grid)
            .arg("--scene")
            .arg(&file)
            .args(["--size", "32", "--frames", "1", "--out"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).to_string()
    };
    sweep();
    let again = sweep();
    assert!(again.contains("1 already done"), "{again}");
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    assert!(csv.contains("linear(8)+lod=auto"), "{csv}");
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn sweep_and_maps_take_a_scene_file() {
    let d = tmpdir("cli-sweep");
    std::fs::copy(repo_file("scenes/tatarchuk/dent_NM_height.tga"), d.join("dent.tga")).unwrap();
    let file = d.join("dent.toml");
    std::fs::write(&file, "depth_scale = 0.2\n[height_map]\npath = \"dent.tga\"\nchannel = \"a\"\n").unwrap();
    let grid = d.join("g.grid");
    std::fs::write(&grid, "# one cell\ncoarse: linear(4)\n").unwrap();
    let out = d.join("sweep");
    let sweep = |extra: &[&str]| {
        let o = relief()
            .args(["sweep", "--grid"])
            .arg(&grid)
            .arg("--scene")
            .arg(&file)
            .args(["--size", "16", "--frames", "1", "--out"])
            .arg(&out)
            .args(extra)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).to_string()
    };
    sweep(&[]);
    sweep(&["--angle", "70"]);
    // The second run measured a new cell (the overridden scene), a third skips both.
    let again = sweep(&["--angle", "70"]);
    assert!(again.contains("1 already done"), "{again}");
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    let label = file.display().to_string();
    assert_eq!(csv.lines().filter(|l| l.contains(&label) && l.contains(",ok,")).count(), 2, "{csv}");
    assert!(csv.contains(&format!("{label}@angle=70")), "{csv}");
    // relief maps: --scene (a file or a built-in name) as well as INPUT.
    for scene in [file.to_str().unwrap(), "scene:dent"] {
        let npy = d.join("mm.npy");
        let o = relief().args(["maps", "--scene", scene, "--kind", "max_mip", "--out"]).arg(&npy).output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let bytes = std::fs::read(&npy).unwrap();
        let header = String::from_utf8_lossy(&bytes[10..128]).to_string();
        assert!(header.contains("(128, 128)"), "{header}");
    }
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn real_rocks_measure_against_the_exact_reference_on_the_device() {
    use relief_runtime::gpu::{self, Gpu, Program, SceneTextures};
    use relief_runtime::metrics::{self, Metrics};
    use relief_runtime::{reference_hits, Sampling};
    let g = Gpu::new().unwrap_or_else(|e| panic!("{e}"));
    let scene = Scene::by_name("rocks", None).unwrap();
    let (steps, refine) = (64u32, 5u32);
    let pipeline = format!("linear({steps})+binary({refine})");
    let program = Program::new(&pipeline.parse().unwrap()).unwrap();
    let tex = SceneTextures::new(&g, &scene);
    let size = 64;
    let rays = scene.rays(size);
    assert!(rays.len() > (size * size / 2) as usize);
    let hits = gpu::probe(&g, &program, &scene, &tex, &rays).unwrap_or_else(|e| panic!("{e}"));
    let mut on_device = scene.clone();
    on_device.height.data = tex.heights_on_device.clone();
    let refs = reference_hits(&on_device, &rays, Sampling::Bilinear).unwrap();
    let mut m = Metrics { pipeline: pipeline.parse().unwrap(), scene: scene.name.clone(), size, ..Default::default() };
    metrics::set_accuracy(&mut m, &rays, &hits, &refs, &on_device.height, scene.edge);
    eprintln!("{pipeline} on rocks: {m:?}");
    assert_eq!(m.nan_count, 0);
    assert_eq!(m.outside_count, 0);
    // Where the linear bracket holds the first hit, 5 halvings leave an interval of
    // 1 / (64 · 2⁵) in t, and the answer lies in it: |t − t_ref| <= 1/2048 (+ f32 rounding).
    // Rays whose first hit linear search stepped over are the exception; the goal is that
    // they are rare on this smooth, 25.6-texel-deep map (64 steps ≈ 0.4 texel apart at 45°).
    let bound = 1.0 / (steps as f64 * (1u32 << refine) as f64) + 1e-5;
    let mut within = 0usize;
    let mut total = 0usize;
    for (h, r) in hits.iter().zip(&refs) {
        if let Some(r) = r {
            total += 1;
            within += ((h.t as f64 - r.t).abs() <= bound) as usize;
        }
    }
    let share = within as f64 / total as f64;
    eprintln!("{within} of {total} rays within {bound:.2e} in t ({:.2}%)", 100.0 * share);
    assert!(total > rays.len() / 2);
    assert!(share > 0.98, "only {:.2}% of rays within the binary bracket", 100.0 * share);
    assert!(m.past_rate < 0.02, "missed {}", m.past_rate);
    // The frame draws with the RGB normal map uploaded.
    let r = gpu::render(&g, &program, &scene, &tex, 32, 1, 2).unwrap_or_else(|e| panic!("{e}"));
    assert!(r.frame_ms.iter().all(|t| *t > 0.0));
}

#[test]
fn the_stability_matrix_holds_the_real_scenes_box_filtered_to_64() {
    use relief_runtime::stability;
    for r in REAL_SCENES {
        assert!(stability::SCENES.contains(&r.name), "{} is not in the stability matrix", r.name);
        let s = stability::scene(r.name, 64).unwrap();
        assert_eq!((s.height.width, s.height.height), (64, 64));
        assert_eq!(s.height, Scene::by_name(r.name, Some(64)).unwrap().height);
    }
    // Every method stays finite and inside the volume on two real maps at every angle.
    let gpu = relief_runtime::gpu::Gpu::new().unwrap();
    let methods = stability::methods();
    let cells = stability::run(&gpu, 8, &methods, &["rocks", "scene:four"], &stability::ANGLES, |_, _| {}).unwrap();
    assert_eq!(cells.len(), methods.len() * 2 * stability::ANGLES.len());
    let bad: Vec<_> = cells.iter().filter(|c| c.nan_count > 0 || c.outside_count > 0).collect();
    assert!(bad.is_empty(), "{} bad cells, e.g. {:?}", bad.len(), &bad[..bad.len().min(3)]);
}

/// The dissertation's view (the Steep Parallax demo's: depth scale 0.05, the quad 20° from
/// facing the eye, 25° field of view, lod=auto), by name in a scene argument, as an override
/// and in a scene file; its probe rays against the camera's geometry.
#[test]
fn the_dissertation_view_sets_depth_camera_and_lod() {
    use relief_dsl::spec::Lod;
    use relief_runtime::{scene_from_arg, Overrides, View};
    let s = scene_from_arg("scene:rocks@view=dissertation").unwrap();
    assert_eq!((s.depth_scale, s.camera.angle_deg, s.camera.fov_deg, s.lod), (0.05, 20.0, 25.0, Some(Lod::Auto)));
    let plain = scene_from_arg("scene:rocks").unwrap();
    assert_eq!(
        (s.camera.azimuth_deg, s.camera.distance),
        (plain.camera.azimuth_deg, plain.camera.distance),
        "the rest of the camera is the scene's"
    );
    let o = Overrides { view: Some(View::Dissertation), ..Default::default() };
    assert_eq!(o.suffix(), "@view=dissertation");
    let by_flag = o.apply(plain.clone());
    assert_eq!(
        (by_flag.depth_scale, by_flag.camera.angle_deg, by_flag.camera.fov_deg, by_flag.lod),
        (0.05, 20.0, 25.0, Some(Lod::Auto))
    );
    assert_eq!(by_flag.name, s.name);
    // A pipeline that names no lod is measured at the footprint level.
    assert_eq!(s.pipeline_for(&"linear(8)".parse().unwrap()).lod, Lod::Auto);
    // The rays of a 65² frame: the centre pixel looks along the camera's axis, 20° from the
    // normal; the centre column's top and bottom pixel centres are 2·atan((1 − 1/65)·tan 12.5°)
    // apart. A probe ray's unscaled view direction is (d.x, d.y, d.z · depth_scale).
    let size = 65;
    let rays = s.rays(size);
    assert_eq!(rays.len(), (size * size) as usize, "at 25° the quad fills the frame");
    let view = |x: u32, y: u32| {
        let r = rays.iter().find(|r| (r.x, r.y) == (x, y)).unwrap();
        glam::DVec3::new(r.dir[0] as f64, r.dir[1] as f64, r.dir[2] as f64 * s.depth_scale as f64).normalize()
    };
    let centre = view(32, 32);
    assert!(
        (centre.z.abs().acos().to_degrees() - 20.0).abs() < 1e-3,
        "centre ray {}° from the normal",
        centre.z.abs().acos().to_degrees()
    );
    let want = 2.0 * ((1.0 - 1.0 / size as f64) * 12.5f64.to_radians().tan()).atan();
    let got = view(32, 0).dot(view(32, size - 1)).clamp(-1.0, 1.0).acos();
    assert!(
        (got - want).abs() < 1e-4,
        "vertical field of view between pixel centres: {}° (want {}°)",
        got.to_degrees(),
        want.to_degrees()
    );
    // In a scene file, as defaults the file's own keys override.
    let d = tmpdir("view");
    std::fs::create_dir_all(&d).unwrap();
    image::GrayImage::from_fn(8, 8, |x, _| image::Luma([(x * 30) as u8])).save(d.join("h.png")).unwrap();
    std::fs::write(d.join("v.toml"), "view = \"dissertation\"\n[height_map]\npath = \"h.png\"\n[camera]\nangle = 30\n")
        .unwrap();
    let f = relief_runtime::load_scene_file(&d.join("v.toml")).unwrap();
    assert_eq!((f.depth_scale, f.camera.angle_deg, f.camera.fov_deg, f.lod), (0.05, 30.0, 25.0, Some(Lod::Auto)));
    std::fs::write(d.join("bad.toml"), "view = \"disertation\"\n[height_map]\npath = \"h.png\"\n").unwrap();
    let e = relief_runtime::load_scene_file(&d.join("bad.toml")).unwrap_err().to_string();
    assert!(e.contains("key `view`") && e.contains("did you mean `dissertation`?") && !e.contains('\n'), "{e}");
    assert!(scene_from_arg("scene:rocks@view=nope").is_err());
}
