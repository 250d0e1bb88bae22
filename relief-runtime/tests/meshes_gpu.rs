//! Mesh scenes drawn on the device (issue 38, docs/meshes.md "Drawing and measuring"): the
//! mesh module's picture and measurement entries against independent computations on the
//! CPU (a brute-force ray–triangle test over the base mesh, the exact reference).

use glam::DVec3;
use relief_dsl::spec::Curved;
use relief_dsl::Pipeline;
use relief_runtime::gpu::mesh::{mesh_textures, probe_mesh, render_mesh, MeshProgram};
use relief_runtime::mesh::{Mesh, MeshScene};
use relief_runtime::mesh_measure::score;
use relief_runtime::{EdgeMode, Gpu};

const SIZE: u32 = 64;
const BASE: &str = "linear(32)+binary(5)";

fn gpu() -> Gpu {
    Gpu::new().unwrap_or_else(|e| panic!("{e}"))
}

fn scene(name: &str, edge: EdgeMode) -> MeshScene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("scenes/meshes/{name}.toml"));
    let mut s = relief_runtime::load_scene_file(&path).unwrap();
    s.edge = edge;
    MeshScene::from_scene(s).unwrap()
}

fn pipeline(mode: Curved) -> Pipeline {
    BASE.parse::<Pipeline>().unwrap().with_curved(Some(mode))
}

/// Whether the ray `o + t·d` meets the base mesh with every triangle's barycentric
/// coordinates widened by `margin` (negative: narrowed), Möller–Trumbore in f64, every
/// triangle tried.
fn meets_base(mesh: &Mesh, o: DVec3, d: DVec3, margin: f64) -> bool {
    mesh.triangles.iter().any(|t| {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize].as_dvec3());
        let (e1, e2) = (b - a, c - a);
        let p = d.cross(e2);
        let det = e1.dot(p);
        if det.abs() < 1e-14 {
            return false;
        }
        let s = o - a;
        let u = s.dot(p) / det;
        let q = s.cross(e1);
        let v = d.dot(q) / det;
        let t = e2.dot(q) / det;
        t > 0.0 && u >= -margin && v >= -margin && u + v <= 1.0 + margin
    })
}

/// `curved=none` draws every fragment of the base mesh (it discards nothing): its covered
/// pixels are those whose pixel-centre ray meets the base mesh, by a ray–triangle test written
/// here. A pixel is left out only where widening or narrowing every triangle by 1e-4 in
/// barycentric terms (far more than f32 rasterization's error on a unit mesh) changes the
/// answer: its ray grazes the base mesh's outline. On the limb and the grazing torus, in both
/// edge modes; a discard in `none` (or a wrong vertex layout or camera) would fail it.
#[test]
fn curved_none_covers_exactly_the_base_mesh() {
    let g = gpu();
    for name in ["sphere_limb", "torus_grazing"] {
        for edge in [EdgeMode::Repeat, EdgeMode::Clamp] {
            let ms = scene(name, edge);
            let prog = MeshProgram::new(&pipeline(Curved::None)).unwrap();
            let tex = mesh_textures(&g, &ms, &prog).unwrap();
            let probe = probe_mesh(&g, &prog, &ms, &tex, SIZE).unwrap();
            let (mut checked, mut covered) = (0u32, 0u32);
            for (r, hit) in ms.rays(SIZE, SIZE).iter().zip(&probe.hits) {
                let (o, d) = (DVec3::from(r.origin.map(f64::from)), DVec3::from(r.dir.map(f64::from)));
                let (wide, narrow) = (meets_base(&ms.mesh, o, d, 1e-4), meets_base(&ms.mesh, o, d, -1e-4));
                if wide != narrow {
                    continue;
                }
                checked += 1;
                covered += wide as u32;
                assert_eq!(hit[3] > 0.5, wide, "{name} {edge:?}: pixel ({}, {})", r.x, r.y);
            }
            // Both kinds of pixel are there: the frame holds the outline.
            assert!(checked > SIZE * SIZE * 9 / 10 && covered > 100 && checked - covered > 100, "{name}");
        }
    }
}

/// The picture and the measurement share the trace and the discards: the pixels the
/// measurement covers are exactly those the picture draws (not the clear colour), in each
/// mode.
#[test]
fn the_picture_draws_exactly_the_pixels_the_measurement_covers() {
    let g = gpu();
    let ms = scene("sphere_limb", EdgeMode::Repeat);
    let clear = {
        let c = relief_runtime::gpu::CLEAR;
        // Linear → sRGB bytes, as the target encodes the clear colour.
        let enc = |x: f64| {
            let s = if x <= 0.0031308 { 12.92 * x } else { 1.055 * x.powf(1.0 / 2.4) - 0.055 };
            (s * 255.0).round() as u8
        };
        [enc(c.r), enc(c.g), enc(c.b)]
    };
    for mode in [Curved::None, Curved::Quadric, Curved::Prism] {
        let prog = MeshProgram::new(&pipeline(mode)).unwrap();
        let tex = mesh_textures(&g, &ms, &prog).unwrap();
        let probe = probe_mesh(&g, &prog, &ms, &tex, SIZE).unwrap();
        let frame = render_mesh(&g, &prog, &ms, &tex, SIZE).unwrap();
        let mut differ = 0;
        for (i, h) in probe.hits.iter().enumerate() {
            let px = &frame.rgba[i * 4..i * 4 + 3];
            let drawn = px.iter().zip(clear).any(|(&a, b)| a.abs_diff(b) > 1);
            // A drawn pixel can be as dark as the clear colour only in a full shadow: none here
            // (no shadow stage, ambient 0.25 of a grey albedo).
            differ += (drawn != (h[3] > 0.5)) as usize;
        }
        assert_eq!(differ, 0, "{mode}");
        // The depth buffer holds the hit's depth where covered, the clear value elsewhere.
        for (h, d) in probe.hits.iter().zip(&probe.depth) {
            assert_eq!(h[3] > 0.5, *d < 1.0, "{mode}");
        }
    }
}

/// `quadric` and `prism` exist to draw the displaced surface's silhouette instead of the base
/// mesh's: on the limb and the grazing torus, in both edge modes, each draws fewer pixels
/// where the exact reference sees no relief than `none` (which draws the whole base mesh), and
/// `prism` has fewer pixels whose coverage disagrees with the reference than `none`. Not
/// asserted because it is false: `quadric`'s total coverage error is above `none`'s on the
/// limb with clamp edges (its search stops at the floor plane, so it loses hits on the deep
/// clamped border below that plane; docs/notes/meshes.md). The goals (prism ≤ 0.5 %,
/// quadric ≤ 2 %) are measured in that note, not asserted here.
#[test]
fn quadric_and_prism_silhouettes_are_closer_to_the_reference_than_the_base_mesh() {
    let g = gpu();
    for name in ["sphere_limb", "torus_grazing"] {
        for edge in [EdgeMode::Repeat, EdgeMode::Clamp] {
            let ms = scene(name, edge);
            let reference = ms.reference_hits(SIZE, SIZE).unwrap();
            let figures: Vec<_> = [Curved::None, Curved::Quadric, Curved::Prism]
                .map(|mode| {
                    let prog = MeshProgram::new(&pipeline(mode)).unwrap();
                    let tex = mesh_textures(&g, &ms, &prog).unwrap();
                    score(&probe_mesh(&g, &prog, &ms, &tex, SIZE).unwrap(), &reference, &ms)
                })
                .into();
            let none = &figures[0];
            assert!(
                none.extra > 0 && none.missing == 0,
                "{name} {edge:?}: none covers the base mesh, outside S: {none:?}"
            );
            for (mode, f) in ["quadric", "prism"].iter().zip(&figures[1..]) {
                assert!(f.extra < none.extra, "{name} {edge:?} {mode}: {f:?} vs none {none:?}");
            }
            let prism = &figures[2];
            assert!(prism.coverage_error < none.coverage_error, "{name} {edge:?} prism: {prism:?} vs none {none:?}");
        }
    }
}

/// The flat tile's paths refuse a mesh pipeline in one line, naming the mode; the mesh
/// program refuses a flat one.
#[test]
fn flat_paths_refuse_mesh_pipelines_and_the_reverse() {
    let e = relief_runtime::Program::new(&pipeline(Curved::Prism)).err().unwrap().to_string();
    assert!(e.contains("curved=prism") && !e.contains('\n'), "{e}");
    let e = MeshProgram::new(&BASE.parse().unwrap()).err().unwrap().to_string();
    assert!(e.contains("curved=") && !e.contains('\n'), "{e}");
}
