//! Bad values refused up front, with their accepted range and their key.

use std::process::Command;

/// The binary under test: this build's, or the one `RELIEF_HOSTILE_BIN` names (to count what an
/// older build fails, as `tests/cli/hostile.rs` does).
fn relief() -> Command {
    let bin = std::env::var_os("RELIEF_HOSTILE_BIN")
        .map_or_else(|| std::path::PathBuf::from(env!("CARGO_BIN_EXE_relief")), std::path::PathBuf::from);
    let mut c = Command::new(bin);
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
        let mut c = relief();
        c.args(["render", "linear(8)", "--scene", "scene:step", "--size", "16", "--frames", "1", "--out"])
            .arg(d.join("o"))
            .arg(format!("{flag}={value}"));
        let (ok, e) = run(c);
        assert!(!ok && e.contains(flag) && e.contains(says), "{flag}={value}: {e}");
        assert_eq!(e.trim_end().lines().count(), 1, "{e}");
        // Refused up front: no frame rendered, no metrics written.
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

/// How one fuzzed command ended.
enum End {
    /// Exited with a status (success or not) and its stderr.
    Exit(Option<i32>, String),
    /// Still running at the deadline (killed).
    Hung,
}

/// Runs `c` with stdin closed, killing it at `secs`.
fn run_bounded(mut c: Command, secs: u64) -> End {
    use std::io::Read;
    let mut child = c
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut err = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut s = Vec::new();
        let _ = err.read_to_end(&mut s);
        s
    });
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(secs);
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            let e = String::from_utf8_lossy(&reader.join().unwrap()).into_owned();
            return End::Exit(status.code(), e);
        }
        if std::time::Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            return End::Hung;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
}

/// A deterministic generator (SplitMix64).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// The fuzz-and-fault test, bounded in count (a fixed list and a fixed number of
/// seeded mutations) and in time (each command killed after 20 s, which counts as a hang):
/// malformed pipelines and parameters, bad numbers for every numeric flag, FIFOs and
/// folders given as inputs, the patch map (`relief maps --kind cell_patch`) from a folder and in
/// encodings that would round it, damaged mesh files and mesh scenes (`relief scene check`, `relief
/// sweep --grid meshes`, `relief export`, `relief scene measure --causes`), `relief stability`'s mesh
/// names, corrupted results rows under `relief report`, and
/// an older relief's damaged room rows under `relief report` and `relief sweep --grid rooms`. Every command must
/// end by itself, with status 0 or a plain failure (never a panic, exit 101, or a signal),
/// and a failure must be one line on stderr. The concurrent sweeps with the lock and the
/// kill-and-resume runs are in tests/sweep.rs. The count of commands run is printed.
#[test]
fn fuzzed_and_faulty_inputs_never_hang_panic_or_give_an_error_of_two_lines() {
    let d = tmpdir("fuzz");
    let out = d.join("out");
    let mut cases: Vec<(String, Command)> = Vec::new();
    let mut add = |name: String, args: Vec<std::ffi::OsString>| {
        let mut c = relief();
        c.args(&args);
        cases.push((name, c));
    };
    let os = |v: &[&str]| v.iter().map(std::ffi::OsString::from).collect::<Vec<_>>();
    // Malformed pipelines: hand-picked, then seeded mutations of good ones.
    let mut pipelines: Vec<String> = [
        "",
        "(",
        ")",
        "linear(",
        "linear()",
        "linear(,)",
        "linear(1,1,1,1)",
        "linear(-1)",
        "linear(1e400)",
        "linear(nan)",
        "linear(0)",
        "linear(4294967296)",
        "linea\nr(10)",
        "linear(10)+",
        "+binary(5)",
        "linear(10)+binary(5)+binary(5)",
        "csm(4, form=safe, sample=min4)",
        "csm(form=)",
        "csm(4,,)",
        "linear(10)+shadow=soft(nan)",
        "linear(10)@lod=9999",
        "linear(10)+curved=prizm",
        "linear(10)+curved=prism(3)",
        "linear(10)+silhouette=clip+curved=quadric",
        "linear(10)+lod=auto+curved=none",
        "\u{1b}[31m",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    pipelines.push(format!("linear({})", vec!["1"; 5000].join(",")));
    pipelines.push("(".repeat(5000));
    let good = [
        "linear(10)+binary(5)",
        "csm(8, form=textbook)+binary(4)",
        "sphere(16)+secant(3)+shadow=soft(8)",
        "linear(10)+binary(5)+curved=prism",
    ];
    let alphabet: Vec<char> = "()+,=.-0123456789eabcdlinrsz \n\t@~".chars().collect();
    let mut rng = Rng(27);
    for _ in 0..300 {
        let mut p: Vec<char> = good[rng.below(good.len())].chars().collect();
        for _ in 0..1 + rng.below(4) {
            let i = rng.below(p.len() + 1);
            match rng.below(3) {
                0 if i < p.len() => {
                    p.remove(i);
                }
                1 if i < p.len() => p[i] = alphabet[rng.below(alphabet.len())],
                _ => p.insert(i, alphabet[rng.below(alphabet.len())]),
            }
        }
        pipelines.push(p.into_iter().collect());
    }
    for p in &pipelines {
        let mut a = os(&["gen"]);
        a.push(p.into());
        a.push("--out".into());
        a.push(d.join("gen").into());
        add(format!("gen {p:?}"), a);
    }
    // A mesh pipeline where the flat tile's runtime is asked to draw it.
    let mut a =
        os(&["render", "linear(4)+curved=quadric", "--scene", "scene:step", "--size", "8", "--frames", "1", "--out"]);
    a.push(out.clone().into());
    add("render curved=quadric".into(), a);
    // Bad numbers for numeric flags.
    for v in ["nan", "inf", "-inf", "-1", "0", "1e39", "3.4e38", "1e30", "abc", "", "0x10", "99999999999999999999"] {
        for flag in ["--depth-scale", "--tiling", "--angle", "--azimuth", "--size", "--frames"] {
            let mut a = os(&["render", "linear(4)", "--scene", "scene:step", "--size", "8", "--frames", "1", "--out"]);
            a.push(out.clone().into());
            a.push(format!("{flag}={v}").into());
            add(format!("render {flag}={v}"), a);
        }
    }
    // `relief tune`: goals and views refused before any measurement.
    for v in ["nan", "inf", "-inf", "-1", "0", "abc", "", "0x10"] {
        add(format!("tune --error={v}"), os(&["tune", "scene:step", "--size", "8", &format!("--error={v}")]));
    }
    for v in ["nan", "inf", "-1", "90", "1e39", "abc", "", "30,"] {
        add(
            format!("tune --view={v}"),
            os(&["tune", "scene:step", "--size", "8", "--error", "1e-2", &format!("--view={v}")]),
        );
    }
    // FIFOs and folders given as inputs.
    let fifo = d.join("f.png");
    let made = Command::new("mkfifo").arg(&fifo).status().map(|s| s.success()).unwrap_or(false);
    let folder = d.join("folder.png");
    std::fs::create_dir_all(&folder).unwrap();
    let fifo_grid = d.join("f.grid");
    let _ = Command::new("mkfifo").arg(&fifo_grid).status();
    let mut inputs = vec![folder.clone()];
    if made {
        inputs.push(fifo.clone());
    }
    for input in &inputs {
        let mut a = os(&["maps"]);
        a.push(input.into());
        a.extend(os(&["--kind", "cone", "--out"]));
        a.push(d.join("o.npy").into());
        add(format!("maps {}", input.display()), a);
        let mut a = os(&["render", "linear(4)", "--size", "8", "--frames", "1", "--scene"]);
        a.push(input.into());
        a.push("--out".into());
        a.push(out.clone().into());
        add(format!("render --scene {}", input.display()), a);
        let mut a = os(&["tune"]);
        a.push(input.into());
        a.extend(os(&["--error", "1e-2", "--size", "8"]));
        add(format!("tune {}", input.display()), a);
    }
    // The patch map: from a folder, and asked for in an encoding that would round it.
    let mut a = os(&["maps"]);
    a.push(folder.clone().into());
    a.extend(os(&["--kind", "cell_patch", "--out"]));
    a.push(d.join("p.npy").into());
    add("maps --kind cell_patch (a folder)".into(), a);
    for (enc, ext) in [("f16", "ktx2"), ("unorm8", "npy"), ("unorm16", "png"), ("nosuch", "npy")] {
        let mut a = os(&["maps", "scene:step", "--kind", "cell_patch", "--encoding", enc, "--out"]);
        a.push(d.join(format!("p.{ext}")).into());
        add(format!("maps --kind cell_patch --encoding {enc} .{ext}"), a);
    }
    for g in [&fifo_grid, &folder] {
        let mut a = os(&["sweep", "--grid"]);
        a.push(g.into());
        a.extend(os(&["--scene", "scene:step", "--size", "8", "--frames", "2", "--out"]));
        a.push(d.join("sweep-fifo").into());
        add(format!("sweep --grid {}", g.display()), a);
    }
    // `relief cost`: malformed pipelines (the hand-picked ones and some mutations; a good one
    // compiles in a child where RADV is installed), bad families, grids that are FIFOs or
    // folders.
    for p in pipelines.iter().take(60) {
        let mut a = os(&["cost"]);
        a.push(p.into());
        add(format!("cost {p:?}"), a);
    }
    for f in ["", ",", "navi31", "gfx1030", "NAVI21,", "navi21,nosuch", "\u{1b}", "navi21,navi21"] {
        add(format!("cost --gpu {f:?}"), os(&["cost", "linear(4)", "--gpu", f]));
    }
    for g in [&fifo_grid, &folder] {
        let mut a = os(&["cost", "--grid"]);
        a.push(g.into());
        add(format!("cost --grid {}", g.display()), a);
    }
    add("cost --angle without --grid".into(), os(&["cost", "linear(4)", "--angle", "30"]));
    // Damaged files of recorded compiler figures under `relief sweep --gpu-costs`: refused
    // before any cell, or (a valid file that lacks the grid's pipelines) a run that says so.
    let good_costs = r#"[{"pipeline":"linear(4)","family":"navi21","device":"d","driver":"radv","fragment":{"executable":"Fragment Shader","subgroup_size":64,"vgprs":8,"sgprs":128,"spilled_vgprs":0,"spilled_sgprs":0,"scratch_bytes":0,"instructions":42,"code_bytes":232,"waves_per_simd":32,"shape":{"instructions":42,"loops":[]}},"probe":{"executable":"Compute Shader","subgroup_size":64,"vgprs":16,"sgprs":128,"spilled_vgprs":0,"spilled_sgprs":0,"scratch_bytes":0,"instructions":27,"code_bytes":144,"waves_per_simd":32,"shape":{"instructions":27,"loops":[]}},"stage_loops":{"base":0,"coarse":0,"refine":0,"lighting":0}}]"#;
    let mut cost_files: Vec<std::path::PathBuf> = vec![folder.clone(), d.join("no-such-costs.json")];
    if made {
        cost_files.push(fifo.clone());
    }
    for (i, bad) in [
        String::new(),
        "[]".to_string(),
        "{}".to_string(),
        good_costs[..good_costs.len() / 2].to_string(),
        good_costs.replace("navi21", "navi31"),
        good_costs.replace("42", "-42"),
        good_costs.replace("\"stage_loops\"", "\"x\""),
        "[".repeat(10000),
        String::from_utf8_lossy(&[0xff, 0xfe, b'[']).into_owned(),
    ]
    .iter()
    .enumerate()
    {
        let f = d.join(format!("costs{i}.json"));
        std::fs::write(&f, bad).unwrap();
        cost_files.push(f);
    }
    let tiny_grid = d.join("tiny.grid");
    std::fs::write(&tiny_grid, "coarse: linear(4)\n").unwrap();
    for f in &cost_files {
        let mut a = os(&["sweep", "--grid"]);
        a.push(tiny_grid.clone().into());
        a.extend(os(&["--scene", "scene:step", "--size", "8", "--frames", "2", "--gpu-costs"]));
        a.push(f.into());
        a.push("--out".into());
        a.push(d.join("sweep-costs").into());
        add(format!("sweep --gpu-costs {}", f.display()), a);
    }
    // Mesh files and mesh scenes under `relief scene check` (docs/meshes.md): truncated and
    // garbled .glb, .gltf with a damaged JSON or buffer, .obj with NaN, bad indices or garbage,
    // huge counts, several meshes and a missing name; each loaded by a scene file and, when
    // it loads, traced (`--reference 8`).
    {
        use super::meshes::{glb, square, GlbMesh};
        let m = d.join("meshes");
        std::fs::create_dir_all(&m).unwrap();
        image::GrayImage::from_pixel(4, 4, image::Luma([128])).save(m.join("h.png")).unwrap();
        let good = glb(&[square("A", 0.0, true), square("B", 1.0, true)]);
        let mut files: Vec<(String, Vec<u8>)> = Vec::new();
        for cut in [0, 4, 11, 12, 20, 28, good.len() / 2, good.len() - 1] {
            files.push((format!("cut{cut}.glb"), good[..cut].to_vec()));
        }
        let mut frng = Rng(38);
        for i in 0..40 {
            let mut g = good.clone();
            for _ in 0..1 + frng.below(8) {
                let k = frng.below(g.len());
                g[k] = frng.below(256) as u8;
            }
            files.push((format!("flip{i}.glb"), g));
        }
        let tri = |positions: Vec<[f32; 3]>, indices: Vec<u32>| GlbMesh {
            name: "T",
            positions,
            uvs: Some(vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]),
            indices,
        };
        let p3 = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        files.push((
            "nan.glb".into(),
            glb(&[tri(vec![[f32::NAN, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, f32::INFINITY]], vec![0, 1, 2])]),
        ));
        files.push(("oob.glb".into(), glb(&[tri(p3.clone(), vec![0, 1, 7])])));
        files.push((
            "huge_uv.glb".into(),
            glb(&[GlbMesh { uvs: Some(vec![[0.0, 0.0], [1e30, 0.0], [0.0, 1e30]]), ..tri(p3.clone(), vec![0, 1, 2]) }]),
        ));
        // The good file's JSON as a .gltf beside its buffer, then with its counts and offsets
        // damaged.
        let jlen = u32::from_le_bytes(good[12..16].try_into().unwrap()) as usize;
        let json = String::from_utf8(good[20..20 + jlen].to_vec()).unwrap();
        let bin = good[20 + jlen + 8..].to_vec();
        std::fs::write(m.join("m.bin"), &bin).unwrap();
        let gltf = json.replace(r#""buffers":[{"byteLength""#, r#""buffers":[{"uri":"m.bin","byteLength""#);
        for (i, bad) in [
            gltf.clone(),
            gltf.replacen(r#""count":4"#, r#""count":4000000000"#, 1),
            gltf.replacen(r#""count":6"#, r#""count":18446744073709551615"#, 1),
            gltf.replacen(r#""byteOffset":0"#, r#""byteOffset":4294967295"#, 1),
            gltf.replace("m.bin", "no-such.bin"),
            gltf.replace("m.bin", "f.png"),
            gltf.replace("m.bin", "folder.png"),
            gltf.replace(r#""nodes":[0,1]"#, r#""nodes":[0,0,1,1]"#),
            gltf.replace(r#"{"mesh":1}"#, r#"{"mesh":1,"children":[1]}"#),
            gltf[..gltf.len() / 2].to_string(),
            "{".repeat(10000),
        ]
        .iter()
        .enumerate()
        {
            files.push((format!("g{i}.gltf"), bad.clone().into_bytes()));
        }
        for (i, obj) in [
            "v nan nan nan\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 99999999999/3\n",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 -9/3\n",
            "v 1e39 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1e30 0\nvt 0 1e30\nf 1/1 2/2 3/3\n",
            "v 0 0 0\nv 1 0\nf 1 2\n",
            "f 1/1/1 2/2/2 3/3/3\n",
            "\u{0}\u{1}garbage\u{ff}",
            "",
        ]
        .iter()
        .enumerate()
        {
            files.push((format!("o{i}.obj"), obj.as_bytes().to_vec()));
        }
        files.push(("raw.bin".into(), vec![0u8; 64]));
        for (name, bytes) in &files {
            std::fs::write(m.join(name), bytes).unwrap();
            for mesh_name in ["", "name = \"Nope\"\n"] {
                let sc = m.join(format!("{name}{}.toml", mesh_name.len()));
                let body = format!("[height_map]\npath = \"h.png\"\n[mesh]\npath = \"{name}\"\n{mesh_name}");
                std::fs::write(&sc, body).unwrap();
                let mut a = os(&["scene", "check", "--reference", "8"]);
                a.push(sc.clone().into());
                add(format!("scene check {name} {mesh_name:?}"), a);
                // The fragment count reads the same mesh (8² frames).
                let mut a = os(&["scene", "fragments", "--size", "8"]);
                a.push(sc.clone().into());
                add(format!("scene fragments {name} {mesh_name:?}"), a);
                // The same scene under the mesh grid: failed rows or measured ones, never a
                // panic or a hang (8² frames, so a mesh that loads is traced quickly).
                let mut a = os(&["sweep", "--grid", "meshes", "--size", "8", "--frames", "1", "--scene"]);
                a.push(sc.into());
                a.push("--out".into());
                a.push(d.join(format!("mesh-sweep-{name}{}", mesh_name.len())).into());
                add(format!("sweep --grid meshes {name} {mesh_name:?}"), a);
            }
        }
        if made {
            let sc = m.join("fifo.toml");
            std::fs::write(
                &sc,
                format!("[height_map]\npath = \"h.png\"\n[mesh]\npath = {:?}\n", fifo.display().to_string()),
            )
            .unwrap();
            let mut a = os(&["scene", "check"]);
            a.push(sc.into());
            add("scene check on a FIFO mesh".into(), a);
        }
        for v in ["0", "-1", "nan", "99999"] {
            let sc = m.join("good.toml");
            std::fs::write(&sc, "[height_map]\npath = \"h.png\"\n[mesh]\nbuiltin = \"torus\"\n").unwrap();
            let mut a = os(&["scene", "check", &format!("--reference={v}")]);
            a.push(sc.into());
            add(format!("scene check --reference={v}"), a);
        }
        // `relief scene measure`: a bad size, a pipeline that does not parse or names curved=
        // itself, a flat scene (no mesh); each refused before the device is asked for.
        let good = m.join("good.toml");
        let flat = m.join("flat.toml");
        std::fs::write(&flat, "[height_map]\npath = \"h.png\"\n").unwrap();
        // The OBJ whose uvs are 1e30 (the walk's headroom refuses to bound them).
        let huge_uv = m.join("o4.obj0.toml");
        for (what, file, args) in [
            ("size 0", &good, vec!["--pipeline", "linear(8)", "--size", "0"]),
            ("size nan", &good, vec!["--pipeline", "linear(8)", "--size", "nan"]),
            ("bad pipeline", &good, vec!["--pipeline", "linear(8"]),
            ("curved pipeline", &good, vec!["--pipeline", "linear(8)+curved=prism"]),
            ("pairs", &good, vec!["--pipeline", "linear(8)", "--pairs", "99999"]),
            ("flat scene", &flat, vec!["--pipeline", "linear(8)"]),
            ("causes of a cone march", &good, vec!["--pipeline", "csm(8)", "--causes", "--size", "8"]),
            ("causes", &good, vec!["--pipeline", "linear(8)+binary(2)", "--causes", "--size", "8", "--pairs", "1"]),
            ("unwalked", &good, vec!["--pipeline", "linear(8)+binary(2)", "--unwalked", "--size", "8", "--pairs", "1"]),
            (
                "unwalked, huge uvs",
                &huge_uv,
                vec!["--pipeline", "linear(8)", "--unwalked", "--size", "8", "--pairs", "0"],
            ),
            ("unwalked, flat", &flat, vec!["--pipeline", "linear(8)", "--unwalked"]),
        ] {
            let mut a = os(&["scene", "measure"]);
            a.push(file.clone().into());
            a.extend(os(&args));
            add(format!("scene measure {what}"), a);
        }
        // `relief scene fragments`: a bad size, a flat scene (no mesh).
        for (what, file, args) in [
            ("size 0", &good, vec!["--size", "0"]),
            ("size nan", &good, vec!["--size", "nan"]),
            ("size huge", &good, vec!["--size", "99999999"]),
            ("flat scene", &flat, vec!["--size", "8"]),
        ] {
            let mut a = os(&["scene", "fragments"]);
            a.push(file.clone().into());
            a.extend(os(&args));
            add(format!("scene fragments {what}"), a);
        }
        // `relief export` with meshes: a curved= pipeline on a flat scene (file or built-in), a
        // mesh scene with a flat pipeline or with a target that has no mesh form, mesh files
        // that do not load, a bad mode; and the good case, which must succeed or fail in one line.
        let bad_mesh = m.join("o0.obj0.toml");
        let export_cases: [(&str, std::ffi::OsString, &str, &str); 11] = [
            ("curved on a flat file", flat.clone().into(), "linear(8)+curved=prism", "glsl-es"),
            ("curved on a built-in", "scene:rock_bump".into(), "linear(8)+curved=prism", "glsl-es"),
            ("flat on a mesh", good.clone().into(), "linear(8)", "glsl-es"),
            ("tsl", good.clone().into(), "linear(8)+curved=prism", "tsl"),
            ("unity", good.clone().into(), "linear(8)+curved=quadric", "unity"),
            ("unreal", good.clone().into(), "linear(8)+curved=none", "unreal"),
            ("bad mesh file", bad_mesh.into(), "linear(8)+curved=prism", "glsl-es"),
            ("bad glTF", m.join("g9.gltf0.toml").into(), "linear(8)+curved=prism", "wgsl"),
            ("bad mode", good.clone().into(), "linear(8)+curved=prisms", "glsl-es"),
            ("good prism", good.clone().into(), "linear(8)+curved=prism", "glsl-es"),
            ("good quadric", good.clone().into(), "linear(8)+curved=quadric", "hlsl"),
        ];
        for (i, (what, scene, pipe, target)) in export_cases.into_iter().enumerate() {
            let mut a = os(&["export", pipe, "--target", target, "--scene"]);
            a.push(scene);
            a.push("--out".into());
            a.push(d.join(format!("export-mesh{i}")).into());
            add(format!("export {what}"), a);
        }
    }
    // Corrupted results rows under `relief report` (each folder one kind of damage).
    let row = r#"{"grid":"g","pipeline":"linear(10)","scene":"scene:step","size":16,"adapter":"a","status":"ok","error":"","relief_version":"0","cell_dir":""}"#;
    let damages = [
        "{\"foo\": 1}".to_string(),
        row.replace("\"ok\"", "\"maybe\""),
        row.replace("linear(10)", "nosuch(1)"),
        row.to_string(),
        row.replace("16", "-16"),
        row.replace("16", "1e99"),
        row[..row.len() / 2].to_string(),
        "\u{0}\u{1}\u{2}".to_string(),
        "[1,2,3]".to_string(),
        "{".repeat(10000),
        String::from_utf8_lossy(&[0xff, 0xfe, b'{']).into_owned(),
    ];
    for (i, bad) in damages.iter().enumerate() {
        let dir = d.join(format!("rows{i}"));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("results.jsonl"), format!("{row}\n{bad}\n")).unwrap();
        let mut a = os(&["report"]);
        a.push(dir.into());
        add(format!("report with line {bad:.40?}"), a);
    }
    // `relief stability`'s mesh conditions: names that are none, and a flag that excludes them.
    for v in ["nosuch", "", "sphere,torus", "SPHERE", "\u{1b}"] {
        let mut a = os(&["stability", "--scene", "flat0", "--size", "8", &format!("--mesh={v}"), "--out"]);
        a.push(d.join("stability-mesh").into());
        add(format!("stability --mesh={v:?}"), a);
    }
    let mut a = os(&["stability", "--mesh", "sphere", "--no-meshes", "--out"]);
    a.push(d.join("stability-mesh").into());
    add("stability --mesh with --no-meshes".into(), a);
    // An older relief's room rows (`rooms.jsonl`, read once into results rows by `relief
    // report` and moved by the next `relief sweep --grid rooms`), damaged: hand-picked
    // replacements, cuts, and seeded byte flips of the committed older folder's file. The
    // sweep runs at that folder's size, so intact rows are kept and not measured again.
    let legacy =
        std::fs::read(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/rooms_before/rooms.jsonl"))
            .unwrap();
    let text = String::from_utf8(legacy.clone()).unwrap();
    let mut olds: Vec<Vec<u8>> = [
        text.replacen("\"ok\"", "\"maybe\"", 1),
        text.replacen("\"pipeline\":\"none\"", "\"pipeline\":\"nosuch(1)\"", 1),
        text.replacen("\"size\":24", "\"size\":-24", 1),
        text.replacen("\"size\":24", "\"size\":4294967297", 1),
        text.replacen("\"rays\":140", "\"rays\":-1", 1),
        text.replacen("\"frame_ms\":", "\"frame_ms\":null,\"x\":", 1),
        text.replacen("\"per_wall\":[", "\"per_wall\":7,\"y\":[", 1),
        text.replacen("\"room\":\"room:default\"", "\"room\":\"room:nosuch\"", 1),
        text.replacen("\"variant\":\"", "\"variant\":\"../../", 1),
        "{".repeat(10000),
        String::new(),
    ]
    .into_iter()
    .map(String::into_bytes)
    .collect();
    for cut in [1, legacy.len() / 3, legacy.len() - 2] {
        olds.push(legacy[..cut].to_vec());
    }
    olds.push(vec![0xff, 0xfe, b'{']);
    let mut lrng = Rng(40);
    for _ in 0..12 {
        let mut b = legacy.clone();
        for _ in 0..1 + lrng.below(6) {
            let k = lrng.below(b.len());
            b[k] = lrng.below(256) as u8;
        }
        olds.push(b);
    }
    for (i, bad) in olds.iter().enumerate() {
        for cmd in ["report", "sweep"] {
            let dir = d.join(format!("legacy-{cmd}{i}"));
            std::fs::create_dir_all(&dir).unwrap();
            std::fs::write(dir.join("rooms.jsonl"), bad).unwrap();
            let mut a = if cmd == "report" {
                os(&["report"])
            } else {
                os(&["sweep", "--grid", "rooms", "--size", "24", "--frames", "1", "--out"])
            };
            a.push(dir.into());
            add(format!("{cmd} over older room rows #{i}"), a);
        }
    }
    let total = cases.len();
    let mut failures = Vec::new();
    for (name, c) in cases {
        match run_bounded(c, 20) {
            End::Hung => failures.push(format!("{name}: did not end within 20 s")),
            End::Exit(None, e) => failures.push(format!("{name}: killed by a signal: {e}")),
            End::Exit(Some(101), e) => failures.push(format!("{name}: panicked: {e}")),
            End::Exit(Some(0), _) => {}
            End::Exit(Some(_), e) => {
                let lines: Vec<&str> = e.lines().filter(|l| !l.starts_with("warning: ")).collect();
                if lines.len() != 1 || !lines[0].starts_with("relief: ") {
                    failures.push(format!("{name}: the error is not one line: {e:?}"));
                }
                if e.contains("panicked") {
                    failures.push(format!("{name}: panicked: {e}"));
                }
            }
        }
    }
    println!("fuzz: {total} commands run, {} failures", failures.len());
    assert!(total >= 400, "the case list was cut: {total}");
    assert!(failures.is_empty(), "{} of {total} failed:\n{}", failures.len(), failures.join("\n"));
    std::fs::remove_dir_all(&d).ok();
}
