//! A `curved=` bundle of `relief export` (issue 38, item 5): the mesh as relief draws it, in
//! `mesh.glb`, read back by an independent reader (the `gltf` crate), and drawn by three.js
//! in headless Chromium (`tests/browser/pages/threejs_mesh.html`: three's own GLTFLoader and
//! KTX2Loader, the glsl-es mesh library in a `RawShaderMaterial`) against `relief render`'s
//! frame by the bar of `tests/threejs.rs` (a mean absolute difference of at most 1 of 255,
//! at most 1 % of pixels off by more than 8), with two variants broken on purpose that must
//! miss it.

use crate::common::browser;
use crate::common::exe::{export, relief_exe};
use crate::common::frames::{engine_picture, frame_difference, from_hex, ENGINE_SIZE as SIZE};

use std::path::{Path, PathBuf};
use std::time::Duration;

use browser::{run_page, Page};
use gltf::mesh::Semantic;
use relief::dsl::compose::mesh::MeshVertex;
use relief::dsl::spec::Curved;
use relief::runtime::gpu::mesh::{mesh_textures, render_mesh, MeshProgram};
use relief::runtime::gpu::Gpu;
use relief::runtime::mesh::vertices::mesh_vertices;
use relief::runtime::mesh::MeshScene;
use relief::runtime::scene_from_arg;
use relief::Pipeline;
use serde_json::json;

/// The mesh scene the tests export: rocks on the unit sphere.
fn sphere_rocks() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("relief-runtime/scenes/meshes/sphere_rocks.toml").display().to_string()
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("relief-threejs-mesh-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A `MeshVertex` member, read from the record.
type Member = fn(&MeshVertex) -> [f32; 4];

/// The f32 values of the accessor of `semantic`, `N` per vertex.
fn read<const N: usize>(
    prim: &gltf::Primitive<'_>,
    buffers: &[gltf::buffer::Data],
    semantic: Semantic,
) -> Vec<[f32; N]> {
    let acc = prim.get(&semantic).unwrap_or_else(|| panic!("no attribute {semantic:?}"));
    assert_eq!(acc.data_type(), gltf::accessor::DataType::F32, "{semantic:?}");
    assert_eq!(acc.dimensions().multiplicity(), N, "{semantic:?}");
    let get = |b: gltf::Buffer<'_>| Some(&buffers[b.index()].0[..]);
    if N == 1 {
        let it = gltf::accessor::Iter::<f32>::new(acc, get).unwrap();
        return it.map(|x| [x; N]).collect();
    }
    match N {
        2 => gltf::accessor::Iter::<[f32; 2]>::new(acc, get).unwrap().map(|x| std::array::from_fn(|i| x[i])).collect(),
        3 => gltf::accessor::Iter::<[f32; 3]>::new(acc, get).unwrap().map(|x| std::array::from_fn(|i| x[i])).collect(),
        4 => gltf::accessor::Iter::<[f32; 4]>::new(acc, get).unwrap().map(|x| std::array::from_fn(|i| x[i])).collect(),
        _ => unreachable!(),
    }
}

/// `relief export` of each mode on the sphere scene writes `mesh.glb`, which the `gltf` crate
/// opens (its validation on), and every attribute value and index it reads equals, bit for
/// bit, `mesh_vertices`'s records of that mode for the scene's mesh, each attribute on the
/// `MeshVertex` member relief.json names; the members a mode does not read are absent.
#[test]
fn export_writes_the_mesh_as_relief_draws_it_and_the_gltf_crate_reads_it_back() {
    let dir = tmp("readback");
    let scene = sphere_rocks();
    let ms = MeshScene::from_scene(scene_from_arg(&scene).unwrap()).unwrap();
    for (curved, target) in [(Curved::Prism, "glsl-es"), (Curved::Quadric, "wgsl"), (Curved::None, "hlsl")] {
        let out = dir.join(curved.name());
        export(&format!("linear(16)+binary(4)+curved={curved}"), &scene, target, &out);
        let rj: serde_json::Value = serde_json::from_slice(&std::fs::read(out.join("relief.json")).unwrap()).unwrap();
        let mesh = &rj["mesh"];
        assert_eq!(mesh["curved"], curved.name());
        let (doc, buffers, _) = gltf::import(out.join(mesh["file"].as_str().unwrap())).unwrap();
        let (want, want_idx) = mesh_vertices(&ms.mesh, curved);
        assert_eq!(doc.meshes().count(), 1);
        let prim = doc.meshes().next().unwrap().primitives().next().unwrap();
        assert_eq!(prim.mode(), gltf::mesh::Mode::Triangles);
        let idx: Vec<u32> =
            prim.reader(|b| Some(&buffers[b.index()].0[..])).read_indices().unwrap().into_u32().collect();
        assert_eq!(idx, want_idx, "{curved}: indices");
        let members = mesh["attributes"].as_object().unwrap();
        let expect_members: &[&str] = match curved {
            Curved::None => &["position.xyz", "normal.xyz", "tangent", "uv.xy", "uv.zw"],
            Curved::Quadric => &["position.xyz", "normal.xyz", "tangent", "uv.xy", "uv.zw", "curvature.xy"],
            Curved::Prism => &[
                "position.xyz",
                "position.w",
                "normal.xyz",
                "tangent",
                "uv.xy",
                "uv.zw",
                "prism_a",
                "prism_b.xy",
                "prism_p0.xyz",
                "prism_p1.xyz",
                "prism_p2.xyz",
                "prism_n0.xyz",
                "prism_n1.xyz",
                "prism_n2.xyz",
            ],
        };
        let mut named: Vec<&str> = members.keys().map(String::as_str).collect();
        named.sort();
        let mut expect = expect_members.to_vec();
        expect.sort();
        assert_eq!(named, expect, "{curved}: the members relief.json maps");
        assert_eq!(prim.attributes().count(), expect.len(), "{curved}: attributes in the file");
        for (member, name) in members {
            let name = name.as_str().unwrap();
            let semantic = match name {
                "POSITION" => Semantic::Positions,
                "NORMAL" => Semantic::Normals,
                "TANGENT" => Semantic::Tangents,
                "TEXCOORD_0" => Semantic::TexCoords(0),
                custom => Semantic::Extras(custom.strip_prefix('_').expect("a custom attribute starts with _").into()),
            };
            // The member's components in the record, by name: the independent statement.
            let (field, first, n): (Member, usize, usize) = match member.as_str() {
                "position.xyz" => (|v| v.position, 0, 3),
                "position.w" => (|v| v.position, 3, 1),
                "normal.xyz" => (|v| v.normal, 0, 3),
                "tangent" => (|v| v.tangent, 0, 4),
                "uv.xy" => (|v| v.uv, 0, 2),
                "uv.zw" => (|v| v.uv, 2, 2),
                "curvature.xy" => (|v| v.curvature, 0, 2),
                "prism_a" => (|v| v.prism_a, 0, 4),
                "prism_b.xy" => (|v| v.prism_b, 0, 2),
                "prism_p0.xyz" => (|v| v.prism_p0, 0, 3),
                "prism_p1.xyz" => (|v| v.prism_p1, 0, 3),
                "prism_p2.xyz" => (|v| v.prism_p2, 0, 3),
                "prism_n0.xyz" => (|v| v.prism_n0, 0, 3),
                "prism_n1.xyz" => (|v| v.prism_n1, 0, 3),
                "prism_n2.xyz" => (|v| v.prism_n2, 0, 3),
                other => panic!("relief.json maps an unknown member {other}"),
            };
            let got: Vec<Vec<f32>> = match n {
                1 => read::<1>(&prim, &buffers, semantic).into_iter().map(|x| x.to_vec()).collect(),
                2 => read::<2>(&prim, &buffers, semantic).into_iter().map(|x| x.to_vec()).collect(),
                3 => read::<3>(&prim, &buffers, semantic).into_iter().map(|x| x.to_vec()).collect(),
                _ => read::<4>(&prim, &buffers, semantic).into_iter().map(|x| x.to_vec()).collect(),
            };
            assert_eq!(got.len(), want.len(), "{curved} {member}: vertex count");
            for (i, (g, w)) in got.iter().zip(&want).enumerate() {
                let w = &field(w)[first..first + n];
                let same = g.iter().zip(w).all(|(a, b)| a.to_bits() == b.to_bits());
                assert!(same, "{curved} {member} ({name}) at vertex {i}: {g:?} in the file, {w:?} drawn");
            }
        }
        // Params the mesh needs, as relief draws the scene.
        let cam = ms.scene.camera;
        let eye = cam.camera_position();
        let p = &mesh["params"]["camera"];
        assert_eq!(p, &json!([eye.x, eye.y, eye.z, ms.scene.depth_scale]), "{curved}: camera");
        let vp: Vec<f32> = serde_json::from_value(mesh["view"]["view_proj_square"].clone()).unwrap();
        assert_eq!(vp, cam.view_proj(1.0).to_cols_array().to_vec(), "{curved}: view_proj");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// The refusals of `relief export` with meshes, each one line that says what is wrong.
#[test]
fn export_refuses_a_curved_pipeline_on_a_flat_scene_and_a_mesh_target_without_a_mesh_form() {
    let dir = tmp("refuse");
    let scene = sphere_rocks();
    for (pipe, arg, target, says) in [
        ("linear(8)+curved=prism", "scene:rock_bump", "glsl-es", "names none"),
        ("linear(8)", scene.as_str(), "glsl-es", "needs curved="),
        ("linear(8)+curved=prism", scene.as_str(), "tsl", "has no tsl form"),
        ("linear(8)+curved=none", scene.as_str(), "unity", "has no unity form"),
    ] {
        let out = std::process::Command::new(relief_exe())
            .args(["export", pipe, "--scene", arg, "--target", target, "--out"])
            .arg(dir.join("out"))
            .env("LP_NUM_THREADS", "1")
            .env("NODEVICE_SELECT", "1")
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        let lines: Vec<&str> = err.lines().filter(|l| !l.contains("XDG_RUNTIME_DIR")).collect();
        assert!(!out.status.success(), "{pipe} on {arg} for {target} was not refused");
        assert!(lines.len() == 1 && lines[0].contains(says), "{pipe} on {arg} for {target}: {err}");
        assert!(!dir.join("out").join("mesh.glb").exists(), "{pipe}: wrote a mesh before refusing");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// three.js (WebGL2 on SwiftShader) draws the sphere with `curved=prism` from the bundle and
/// meets the bar against `relief render`'s frame; with the floor vertices left on the surface,
/// or prism_b's components swapped, it must miss the bar.
#[test]
fn threejs_draws_the_prism_sphere_from_the_export_bundle_as_relief_renders_it() {
    let pipe = "linear(32)+binary(5)+shadow=soft(16)+curved=prism";
    let dir = tmp("draw");
    let scene = sphere_rocks();
    export(pipe, &scene, "glsl-es", &dir.join("bundle"));
    let p: Pipeline = pipe.parse().unwrap();
    let ms = MeshScene::from_scene(scene_from_arg(&scene).unwrap()).unwrap();
    let g = Gpu::new().unwrap();
    let prog = MeshProgram::new(&p).unwrap();
    let tex = mesh_textures(&g, &ms, &prog).unwrap();
    let reference = render_mesh(&g, &prog, &ms, &tex, SIZE).unwrap().rgba;
    let variants = ["", "no_floor_push", "prism_b_swapped"];
    let cases: Vec<_> = variants.iter().map(|b| json!({ "bundle": "bundle", "broken": b })).collect();
    std::fs::write(dir.join("manifest.json"), json!({ "size": SIZE, "cases": cases }).to_string()).unwrap();
    let mut page = Page::new("pages/threejs_mesh.html");
    page.mounts.push(("data", &dir));
    page.size = (SIZE, SIZE);
    page.timeout = Duration::from_secs(120);
    let r = run_page(&page);
    let keep = std::env::var_os("RELIEF_THREEJS_KEEP").is_some();
    let pic =
        |i: usize| from_hex(r["cases"][i]["rgba"].as_str().unwrap_or_else(|| panic!("case {i}: {}", r["cases"][i])));
    let what = format!("{pipe} on sphere_rocks, WebGL2 (three.js {}, GLTFLoader, KTX2Loader)", r["three"]);
    let failure = engine_picture("three.js", &what, &pic(0), &reference, &dir, "prism", keep);
    assert!(failure.is_none(), "three.js's picture differs from relief render's: {}", failure.unwrap_or_default());
    for (i, broken) in variants.iter().enumerate().skip(1) {
        let (mad, share) = frame_difference(&pic(i), &reference);
        println!("broken on purpose ({broken}): mean |difference| {mad:.4} of 255, {:.3} % off by > 8", share * 100.0);
        assert!(mad > 1.0 || share > 0.01, "{broken}: a broken drawing meets the bar ({mad:.4}, {share:.4})");
    }
    if !keep {
        std::fs::remove_dir_all(&dir).ok();
    }
}
