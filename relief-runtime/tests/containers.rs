//! `relief maps … --out FILE.ktx2|.dds` (issue 39, item 1): every map kind written by the
//! command line, read back with readers independent of relief's writer (the `ktx2` and
//! `ddsfile` crates) and compared texel for texel, level for level, with what the runtime
//! uploads (`gpu::map_upload_of`, `gpu::scene_uploads`).

use std::path::{Path, PathBuf};
use std::process::Command;

use relief_runtime::gpu::{self, Upload};
use relief_runtime::{EdgeMode, HeightMap, MapKey, MapKind, MapParams, Scene};

fn relief() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_relief"));
    c.env("LP_NUM_THREADS", "1").env("NODEVICE_SELECT", "1");
    c
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("relief-containers-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&d).ok();
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A 16×16 height map with hills and a pit, written as `.npy` (the CLI's raw float input).
fn heights(dir: &Path) -> (HeightMap, PathBuf) {
    let (w, h) = (16usize, 16usize);
    let data: Vec<f32> = (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f32, (i / w) as f32);
            (0.5 + 0.3 * (x * 0.7).sin() * (y * 0.45).cos()
                - if (x - 5.0).abs() + (y - 9.0).abs() < 3.0 { 0.3 } else { 0.0 })
            .clamp(0.0, 1.0)
        })
        .collect();
    let mut npy = b"\x93NUMPY\x01\x00".to_vec();
    let mut head = format!("{{'descr': '<f4', 'fortran_order': False, 'shape': ({h}, {w}), }}");
    while (10 + head.len() + 1) % 64 != 0 {
        head.push(' ');
    }
    head.push('\n');
    npy.extend((head.len() as u16).to_le_bytes());
    npy.extend(head.as_bytes());
    npy.extend(data.iter().flat_map(|x| x.to_le_bytes()));
    let path = dir.join("h.npy");
    std::fs::write(&path, npy).unwrap();
    (HeightMap::new(w, h, data), path)
}

/// Vulkan and DXGI format numbers, from the specifications (not from relief's writer).
fn vk_dxgi(f: wgpu::TextureFormat) -> (u32, u32) {
    match f {
        wgpu::TextureFormat::R32Float => (100, 41),
        wgpu::TextureFormat::Rg32Float => (103, 16),
        wgpu::TextureFormat::Rgba32Float => (109, 2),
        wgpu::TextureFormat::R16Float => (76, 54),
        wgpu::TextureFormat::Rg16Float => (83, 34),
        wgpu::TextureFormat::Rgba16Float => (97, 10),
        wgpu::TextureFormat::Rgba8Unorm => (37, 28),
        wgpu::TextureFormat::Rgba8UnormSrgb => (43, 29),
        f => panic!("unexpected upload format {f:?}"),
    }
}

/// Reads `path` with the `ktx2` crate and asserts it holds `want`: format, size, 2D or 3D,
/// every level's bytes, and row 0 at the top (`KTXorientation`).
fn check_ktx2(path: &Path, want: &Upload, what: &str) {
    let bytes = std::fs::read(path).unwrap();
    let r = ktx2::Reader::new(&bytes[..]).unwrap_or_else(|e| panic!("{what}: ktx2 refuses it: {e:?}"));
    let h = r.header();
    assert_eq!(h.format.map(|f| f.value()), Some(vk_dxgi(want.format).0), "{what}: format");
    assert_eq!((h.pixel_width, h.pixel_height), (want.width, want.height), "{what}: size");
    assert_eq!(h.pixel_depth, if want.depth > 1 { want.depth } else { 0 }, "{what}: depth");
    assert_eq!((h.layer_count, h.face_count, h.supercompression_scheme), (0, 1, None), "{what}");
    assert_eq!(h.level_count as usize, want.levels.len(), "{what}: levels");
    assert!(r.basic_dfd().is_some(), "{what}: no basic data format descriptor");
    for (i, (got, want)) in r.levels().zip(&want.levels).enumerate() {
        assert!(got.data == &want[..], "{what}: level {i} differs ({} vs {} bytes)", got.data.len(), want.len());
    }
    let orientation = r.key_value_data().find(|(k, _)| *k == "KTXorientation").map(|(_, v)| v.to_vec());
    let o = if want.depth > 1 { &b"rdi\0"[..] } else { &b"rd\0"[..] };
    assert_eq!(orientation.as_deref(), Some(o), "{what}: orientation");
}

/// Reads `path` with the `ddsfile` crate and asserts it holds `want`.
fn check_dds(path: &Path, want: &Upload, what: &str) {
    let dds = ddsfile::Dds::read(std::fs::File::open(path).unwrap()).unwrap_or_else(|e| panic!("{what}: {e}"));
    assert_eq!(dds.get_dxgi_format().map(|f| f as u32), Some(vk_dxgi(want.format).1), "{what}: format");
    assert_eq!((dds.get_width(), dds.get_height(), dds.get_depth()), (want.width, want.height, want.depth), "{what}");
    assert_eq!(dds.get_num_mipmap_levels() as usize, want.levels.len(), "{what}: levels");
    let dim = dds.header10.as_ref().map(|h| h.resource_dimension);
    let want_dim = if want.depth > 1 {
        ddsfile::D3D10ResourceDimension::Texture3D
    } else {
        ddsfile::D3D10ResourceDimension::Texture2D
    };
    assert_eq!(dim, Some(want_dim), "{what}");
    assert!(dds.data == want.levels.concat(), "{what}: texels differ");
}

fn run_ok(args: &[&str], out: &Path) {
    let o = relief().args(args).arg(out).output().unwrap();
    assert!(o.status.success(), "{args:?}: {}", String::from_utf8_lossy(&o.stderr));
}

/// Every kind, in both containers, as f32 and as f16, is the runtime's upload: the max-mip
/// chain as mip levels, the distance field as a 3D texture, the cell maps in RG32F where
/// (ratio, apex) is all the device reads; the patch map in f32 only.
#[test]
fn every_kind_in_ktx2_and_dds_is_the_runtime_upload() {
    let dir = tmp("kinds");
    let (hm, input) = heights(&dir);
    let input = input.to_str().unwrap().to_string();
    let (mut saw_chain, mut saw_3d, mut saw_rg) = (false, false, false);
    for (n, kind) in MapKind::ALL.into_iter().enumerate() {
        let edge = if n % 2 == 0 { EdgeMode::Repeat } else { EdgeMode::Clamp };
        let mut scene = Scene::from_height_map("t", hm.clone());
        scene.edge = edge;
        let params = MapParams { cones: 4, z_resolution: 8 };
        let want = gpu::map_upload_of(&scene, MapKey { kind, params }).unwrap();
        saw_chain |= want.levels.len() > 1;
        saw_3d |= want.depth > 1;
        saw_rg |= want.format == wgpu::TextureFormat::Rg32Float;
        let edge_arg = if edge == EdgeMode::Repeat { "repeat" } else { "clamp" };
        let name = kind.to_string();
        let base = ["maps", &input, "--kind", &name, "--edge", edge_arg, "--z-resolution", "8"];
        for ext in ["ktx2", "dds"] {
            let out = dir.join(format!("{name}.{ext}"));
            run_ok(&[&base[..], &["--out"]].concat(), &out);
            let what = format!("{name} ({edge_arg}) .{ext}");
            if ext == "ktx2" {
                check_ktx2(&out, &want, &what)
            } else {
                check_dds(&out, &want, &what)
            }
            // The 16-bit float form: each value rounded to the nearest f16; refused, in one
            // line, for the patch map, whose coefficients the marches must read unrounded.
            let out16 = dir.join(format!("{name}.f16.{ext}"));
            if kind == MapKind::CellPatch {
                let args = [&base[..], &["--encoding", "f16", "--out"]].concat();
                let o = relief().args(&args).arg(&out16).output().unwrap();
                let err = String::from_utf8_lossy(&o.stderr);
                assert!(!o.status.success() && err.trim().lines().count() == 1, "{args:?}: {err}");
                assert!(!out16.exists(), "{what}: a refused f16 file was written");
                continue;
            }
            run_ok(&[&base[..], &["--encoding", "f16", "--out"]].concat(), &out16);
            let half_format = match want.format {
                wgpu::TextureFormat::R32Float => wgpu::TextureFormat::R16Float,
                wgpu::TextureFormat::Rg32Float => wgpu::TextureFormat::Rg16Float,
                _ => wgpu::TextureFormat::Rgba16Float,
            };
            let halves = Upload {
                format: half_format,
                levels: want
                    .levels
                    .iter()
                    .map(|l| {
                        bytemuck::cast_slice::<u8, f32>(l)
                            .iter()
                            .flat_map(|&x| half::f16::from_f32(x).to_bits().to_le_bytes())
                            .collect()
                    })
                    .collect(),
                ..want.clone()
            };
            if ext == "ktx2" {
                check_ktx2(&out16, &halves, &format!("{what} f16"))
            } else {
                check_dds(&out16, &halves, &format!("{what} f16"))
            }
        }
    }
    assert!(saw_chain && saw_3d && saw_rg, "chain {saw_chain}, 3D {saw_3d}, RG {saw_rg}");
    std::fs::remove_dir_all(&dir).ok();
}

/// A scene's own textures: the height map with its mip chain (the levels `lod=auto` reads),
/// the normal and albedo maps, as the runtime uploads them.
#[test]
fn scene_textures_in_ktx2_and_dds_are_the_runtime_upload() {
    let dir = tmp("scene");
    let scene = Scene::by_name("step", None).unwrap();
    let ups = gpu::scene_uploads(&scene, true);
    for (kind, want) in [("height", &ups.height), ("normal", &ups.normal), ("albedo", &ups.albedo)] {
        // The step scene's albedo is one plain texel; the height and normal maps have chains.
        assert!(kind == "albedo" || want.levels.len() > 1, "{kind}: a chain");
        for ext in ["ktx2", "dds"] {
            let out = dir.join(format!("{kind}.{ext}"));
            run_ok(&["maps", "scene:step", "--kind", kind, "--out"], &out);
            if ext == "ktx2" {
                check_ktx2(&out, want, kind)
            } else {
                check_dds(&out, want, kind)
            }
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// What a container cannot hold is one line naming the kind and the format, and no file.
#[test]
fn what_a_container_cannot_hold_is_a_one_line_error() {
    let dir = tmp("bad");
    let (_, input) = heights(&dir);
    let input = input.to_str().unwrap();
    for (args, says) in [
        (vec!["maps", input, "--kind", "cone", "--encoding", "unorm16"], vec!["cone", "Unorm16", ".ktx2"]),
        (vec!["maps", input, "--kind", "cell_cone", "--encoding", "unorm8"], vec!["cell_cone", "Unorm8", ".ktx2"]),
        (vec!["maps", input, "--kind", "multi_cone", "--cones", "8"], vec!["multi_cone", "8 channels"]),
        (vec!["maps", input, "--kind", "cone", "--sqrt"], vec!["--sqrt", ".ktx2"]),
    ] {
        let out = dir.join("x.ktx2");
        let o = relief().args(&args).arg("--out").arg(&out).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{args:?} accepted");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        for s in says {
            assert!(err.contains(s), "{args:?}: `{s}` not in {err}");
        }
        assert!(!out.exists(), "{args:?} wrote a file");
    }
    let o = relief().args(["maps", input, "--kind", "height", "--out"]).arg(dir.join("h.png")).output().unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains(".ktx2 or .dds"));
    std::fs::remove_dir_all(&dir).ok();
}

fn format_named(s: &str) -> wgpu::TextureFormat {
    match s {
        "R32Float" => wgpu::TextureFormat::R32Float,
        "Rg32Float" => wgpu::TextureFormat::Rg32Float,
        "Rgba32Float" => wgpu::TextureFormat::Rgba32Float,
        "Rgba8Unorm" => wgpu::TextureFormat::Rgba8Unorm,
        "Rgba8UnormSrgb" => wgpu::TextureFormat::Rgba8UnormSrgb,
        o => panic!("unexpected format {o}"),
    }
}

/// A `tsl` bundle's `relief.json` lists no nearest sampler (the `tsl` form reads its
/// nearest textures with `textureLoad`, and three.js binds no sampler for a NearestFilter
/// texture), and lists every resource the library's functions take: each name on the
/// header's `+ resource arguments:` lines is a binding of the json.
fn check_tsl_bindings(out: &Path, j: &serde_json::Value, pipe: &str) {
    let bindings = j["bindings"].as_array().unwrap();
    let nearest_sampler = bindings.iter().find(|b| b["kind"] == "sampler" && b["filter"] == "nearest");
    assert!(nearest_sampler.is_none(), "{pipe} (tsl): relief.json lists a nearest sampler: {nearest_sampler:?}");
    let names: Vec<&str> = bindings.iter().filter_map(|b| b["name"].as_str()).collect();
    let lib = std::fs::read_to_string(out.join(j["library"][0].as_str().unwrap())).unwrap();
    let args: Vec<&str> = lib
        .lines()
        .filter_map(|l| l.split("+ resource arguments: ").nth(1))
        .flat_map(|l| l.split(", ").map(str::trim))
        .collect();
    assert!(args.iter().any(|a| a.ends_with("_nearest")), "{pipe} (tsl): the library reads no nearest map: {args:?}");
    for a in &args {
        assert!(names.contains(a), "{pipe} (tsl): the library reads `{a}`, which relief.json does not list: {names:?}");
    }
}

/// `relief export` (issue 39, item 2): `relief.json` lists exactly the textures and samplers
/// of the module's binding table (`Compiled::bindings`, less the normal and albedo maps that
/// only relief's own shading reads), each texture's file read back with the `ktx2` crate is
/// the runtime's upload in the format the json names, the levels read are maxmip's chain and
/// the cell cone map's level 0, and a folder holding other files is refused without `--force`.
#[test]
fn export_writes_a_bundle_whose_relief_json_is_the_binding_table() {
    use relief_dsl::ir::{Filter, Image, Resource};
    use std::collections::BTreeSet;
    let scene = Scene::by_name("step", None).unwrap();
    let ups = gpu::scene_uploads(&scene, true);
    for (pipe, target) in [
        ("csm(64)", "glsl-es"),
        ("maxmip(96)", "wgsl"),
        ("linear(32)+binary(5)+shadow=soft(16)", "hlsl"),
        ("csm(64)", "tsl"),
    ] {
        let out = tmp("export").join("bundle");
        run_ok(&["export", pipe, "--scene", "scene:step", "--target", target, "--out"], &out);
        let j: serde_json::Value = serde_json::from_slice(&std::fs::read(out.join("relief.json")).unwrap()).unwrap();
        let p: relief_dsl::Pipeline = pipe.parse().unwrap();
        let compiled = relief_dsl::compile(&p).unwrap();
        let fname = |f: Filter| if f == Filter::Nearest { "nearest" } else { "linear" }.to_string();
        let (mut want_tex, mut want_samplers) = (BTreeSet::new(), BTreeSet::new());
        for e in compiled.bindings.iter() {
            match e.resource {
                Resource::Texture { image: Image::Normal | Image::Albedo, .. } => {}
                Resource::Texture { image, filter, .. } => {
                    want_tex.insert((image.texture_name(), fname(filter)));
                }
                Resource::Sampler(f) => {
                    want_samplers.insert(fname(f));
                }
                _ => {}
            }
        }
        let bindings = j["bindings"].as_array().unwrap();
        let s = |v: &serde_json::Value| v.as_str().unwrap_or_else(|| panic!("{pipe}: {v}")).to_string();
        let got_tex: BTreeSet<(String, String)> =
            bindings.iter().filter(|b| b["kind"] != "sampler").map(|b| (s(&b["image"]), s(&b["filter"]))).collect();
        let got_samplers: BTreeSet<String> =
            bindings.iter().filter(|b| b["kind"] == "sampler").map(|b| s(&b["filter"])).collect();
        assert_eq!(got_tex, want_tex, "{pipe}");
        assert_eq!(got_samplers.iter().filter(|f| want_samplers.contains(*f)).count(), got_samplers.len(), "{pipe}");
        assert_eq!(j["edge"], "repeat", "{pipe}");
        assert_eq!(j["edge_define"], "RELIEF_EDGE_REPEAT", "{pipe}");
        assert_eq!(j["depth_scale"].as_f64(), Some(scene.depth_scale as f64), "{pipe}");
        assert!(s(&j["texture_space"]).contains("row 0 of every file is v = 0"), "{pipe}");
        for f in j["library"].as_array().unwrap() {
            let text = std::fs::read_to_string(out.join(s(f))).unwrap();
            assert!(text.contains("relief_trace"), "{pipe}: {f}");
        }
        for b in bindings.iter().filter(|b| b["kind"] != "sampler") {
            let image = s(&b["image"]);
            let want = match image.as_str() {
                "height_map" => ups.height.clone(),
                name => {
                    let kind: MapKind = name.trim_end_matches("_map").parse().unwrap();
                    gpu::map_upload_of(&scene, MapKey { kind, params: MapParams::default() }).unwrap()
                }
            };
            assert_eq!(format_named(&s(&b["format"])), want.format, "{pipe}: {image}");
            assert_eq!(b["levels_in_file"].as_u64(), Some(want.levels.len() as u64), "{pipe}: {image}");
            check_ktx2(&out.join(s(&b["file"])), &want, &format!("{pipe}: {image}"));
            let read = s(&b["levels_read"]);
            match image.as_str() {
                "max_mip_map" => assert_eq!(read, "all", "{pipe}"),
                "cell_cone_map" | "height_map" => assert_eq!(read, "0", "{pipe}: {image}"),
                _ => {}
            }
        }
        for (name, want) in [("normal", &ups.normal), ("albedo", &ups.albedo), ("height", &ups.height)] {
            check_ktx2(&out.join(s(&j["textures"][name]["file"])), want, name);
        }
        if target == "tsl" {
            check_tsl_bindings(&out, &j, pipe);
        }
        if target == "glsl-es" {
            assert!(j["paste"].as_array().unwrap().iter().any(|l| l == "#define RELIEF_EDGE_REPEAT"), "{}", j["paste"]);
        }
        // The folder now holds the bundle: refused without --force, in one line; rewritten with it.
        let o = relief()
            .args(["export", pipe, "--scene", "scene:step", "--target", target, "--out"])
            .arg(&out)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains("--force") && err.trim().lines().count() == 1, "{err}");
        run_ok(&["export", pipe, "--scene", "scene:step", "--target", target, "--force", "--out"], &out);
        std::fs::remove_dir_all(out.parent().unwrap()).ok();
    }
}
