//! `curved=prism` drawn as a walk (relief-dsl's `compose::Options::prism_walk`, the runtime's
//! draw): the joined walls it walks across and the headrooms it skips prisms by, against
//! independent computations, and its picture against the unwalked draw's and the exact
//! reference on the hard scenes (a limb, a grazing torus, an open cylinder's rims, both edge
//! modes).

use relief_runtime::mesh::builtin::builtin;
use relief_runtime::mesh::vertices::{headroom, joined_walls};
use relief_runtime::mesh::Mesh;
use relief_runtime::{EdgeMode, HeightMap};

/// The ends of triangle `t`'s edge k (corner k, corner k + 1).
fn edge(t: &[u32; 3], k: usize) -> (u32, u32) {
    (t[k], t[(k + 1) % 3])
}

/// Whether two vertices are one point with one normal, to 1e-5 (the built-in meshes' seams
/// differ by f32 roundings of sin 2π, ~2e-7).
fn same_vertex(m: &Mesh, i: u32, j: u32) -> bool {
    let (i, j) = (i as usize, j as usize);
    (m.positions[i] - m.positions[j]).abs().max_element() <= 1e-5
        && (m.normals[i] - m.normals[j]).abs().max_element() <= 1e-5
}

/// On the closed built-ins (sphere, torus) every side wall is joined, and to the triangle
/// whose edge has the same two ends (compared here pairwise, by value), the relation being
/// mutual; on the cylinder, open at both ends, exactly the walls over the two rims (one
/// edge per segment each) are joined to nothing. Counts from the parametrization: 96
/// segments around.
#[test]
fn walls_join_where_two_triangles_share_an_edges_points_and_normals() {
    for (name, open) in [("sphere", 0), ("torus", 0), ("cylinder", 2 * 96)] {
        let m = builtin(name, 1.0).unwrap();
        let across = joined_walls(&m);
        let mut unjoined = 0;
        for (i, t) in m.triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = edge(t, k);
                // The partners, found by comparing with every other triangle's edges.
                let partners: Vec<u32> = (0..m.triangles.len() as u32)
                    .filter(|&j| j != i as u32)
                    .filter(|&j| {
                        (0..3).any(|l| {
                            let (c, d) = edge(&m.triangles[j as usize], l);
                            (same_vertex(&m, a, d) && same_vertex(&m, b, c))
                                || (same_vertex(&m, a, c) && same_vertex(&m, b, d))
                        })
                    })
                    .collect();
                match across[i][k] {
                    Some(j) => {
                        assert_eq!(partners, [j], "{name}: triangle {i} wall {k}");
                        assert!(across[j as usize].contains(&Some(i as u32)), "{name}: {i} → {j} not mutual");
                    }
                    None => {
                        assert!(partners.len() != 1, "{name}: triangle {i} wall {k} has one partner {partners:?}");
                        unjoined += 1;
                    }
                }
            }
        }
        assert_eq!(unjoined, open, "{name}");
    }
}

/// A small deterministic generator (no dependency for tests' random numbers).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// The headroom bounds every height a bilinear read anywhere in the triangle returns (the
/// host's `HeightMap::bilinear`, texel centres at half-integers, on a barycentric grid with
/// the edges and the corners), on a random map and on a one-texel pillar, under both edge
/// modes, for triangles inside the map, across its edges and much larger than it. It is
/// also local: a small triangle two texels away from the pillar does not see it.
#[test]
fn headroom_bounds_every_bilinear_read_in_the_triangle() {
    let n = 16usize;
    let mut rng = Lcg(7);
    let random = HeightMap::new(n, n, (0..n * n).map(|_| 0.8 * rng.next()).collect());
    let mut pillar = vec![0.25f32; n * n];
    pillar[5 * n + 9] = 1.0;
    let pillar = HeightMap::new(n, n, pillar);
    for (map_name, map) in [("random", &random), ("pillar", &pillar)] {
        for edge in [EdgeMode::Repeat, EdgeMode::Clamp] {
            for case in 0..200 {
                let spread = [0.05f32, 0.3, 3.0][case % 3];
                let centre = glam::Vec2::new(rng.next() * 1.4 - 0.2, rng.next() * 1.4 - 0.2);
                let uv = [0; 3].map(|_| centre + spread * glam::Vec2::new(rng.next() - 0.5, rng.next() - 0.5));
                let room = headroom(map, edge, uv);
                let steps = 24;
                for i in 0..=steps {
                    for j in 0..=steps - i {
                        let (a, b) = (i as f32 / steps as f32, j as f32 / steps as f32);
                        let p = uv[0] * a + uv[1] * b + uv[2] * (1.0 - a - b);
                        let h = map.bilinear(p.x as f64, p.y as f64, edge);
                        assert!(
                            h <= (1.0 - room) as f64 + 1e-6,
                            "{map_name} {edge:?} case {case}: h {h} at {p} over the bound {}",
                            1.0 - room
                        );
                    }
                }
            }
        }
    }
    // Texel (9, 5) is the pillar: a triangle around texel (2, 12)'s centre, far from it, sees
    // only the ground; one over the pillar's centre sees the pillar.
    let centre = |x: f32, y: f32| glam::Vec2::new((x + 0.5) / n as f32, (y + 0.5) / n as f32);
    let small = |c: glam::Vec2| [c, c + glam::Vec2::new(0.01, 0.0), c + glam::Vec2::new(0.0, 0.01)];
    for edge in [EdgeMode::Repeat, EdgeMode::Clamp] {
        assert_eq!(headroom(&pillar, edge, small(centre(2.0, 12.0))), 0.75, "{edge:?}");
        assert_eq!(headroom(&pillar, edge, small(centre(9.0, 5.0))), 0.0, "{edge:?}");
    }
}

/// The walk's picture against the unwalked draw's and the exact reference, 64², the goals'
/// pipeline `linear(32)+binary(5)`: on the sphere face-on (repeat and clamp edges), at its
/// limb, the grazing torus and the open cylinder seen from its side at 85° (its rims' walls
/// are joined to nothing and drawn; from steeper views the cylinder shows the back of its
/// relief through the open end, which neither draw draws: docs/meshes-shaders.md). Goals (stated, not taken from a run):
/// the walk the runtime draws (each chord searched with its share of the layers) has a
/// coverage error against the reference of at most issue 38's 0.5 %, no pixel left at the
/// walk's limit, and its skip of prisms above the relief changes no pixel (the probe with
/// the headrooms zeroed, bit for bit); the walk that gives every chord all of its layers, as
/// the unwalked draw does, meets what the unwalked draw meets: at most 0.1 % of the frame (a
/// fifth of the coverage goal) differing, in coverage or by more than 1e-3 depths along the
/// ray; and the walk does walk (some drawn pixel searched more than one prism).
#[test]
fn the_walk_draws_what_the_unwalked_draw_draws() {
    use relief_dsl::spec::Curved;
    use relief_dsl::Pipeline;
    use relief_runtime::gpu::mesh::{mesh_textures, MeshProber, MeshProgram};
    use relief_runtime::mesh::MeshScene;
    let g = relief_runtime::Gpu::new().unwrap_or_else(|e| panic!("{e}"));
    let pipeline = "linear(32)+binary(5)".parse::<Pipeline>().unwrap().with_curved(Some(Curved::Prism));
    let (walk, unwalked) = (MeshProgram::new(&pipeline).unwrap(), MeshProgram::unwalked(&pipeline).unwrap());
    let whole = MeshProgram::walked_with_all_layers(&pipeline).unwrap();
    assert!(walk.walk && whole.walk && !unwalked.walk);
    let (walk_probe, unwalked_probe) = (MeshProber::new(&g, &walk).unwrap(), MeshProber::new(&g, &unwalked).unwrap());
    let whole_probe = MeshProber::new(&g, &whole).unwrap();
    let size = 64;
    let mut most = 0;
    for (name, edge, angle) in [
        ("sphere_rocks", EdgeMode::Repeat, None),
        ("sphere_rocks", EdgeMode::Clamp, None),
        ("sphere_limb", EdgeMode::Repeat, None),
        ("torus_grazing", EdgeMode::Repeat, None),
        ("cylinder_wall", EdgeMode::Repeat, Some(85.0)),
    ] {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("scenes/meshes/{name}.toml"));
        let mut ms = MeshScene::from_scene(relief_runtime::load_scene_file(&path).unwrap()).unwrap();
        ms.scene.edge = edge;
        if let Some(angle) = angle {
            ms.scene.camera.angle_deg = angle;
        }
        let tex = mesh_textures(&g, &ms, &walk).unwrap();
        let a = walk_probe.probe(&g, &ms, &tex, size).unwrap();
        let b = unwalked_probe.probe(&g, &ms, &tex, size).unwrap();
        let reference = ms.reference_hits(size, size).unwrap();
        let score = relief_runtime::mesh_measure::score(&a, &reference, &ms);
        assert!(score.coverage_error <= 0.005, "{name} {edge:?}: coverage error {}", score.coverage_error);
        let depth = ms.scene.depth_scale;
        let w = whole_probe.probe(&g, &ms, &tex, size).unwrap();
        let differ = (0..w.hits.len())
            .filter(|&i| {
                let (hw, hb) = (w.hits[i][3] > 0.5, b.hits[i][3] > 0.5);
                hw != hb || (hw && (w.hits[i][2] - b.hits[i][2]).abs() > 1e-3 * depth)
            })
            .count();
        assert!(differ * 1000 <= w.hits.len(), "{name} {edge:?}: {differ} pixels differ from the unwalked draw");
        assert_eq!(a.walk_limit_pixels(), 0, "{name} {edge:?}");
        assert_eq!(w.walk_limit_pixels(), 0, "{name} {edge:?}");
        most = most.max(a.walk_passes().unwrap().1);
        assert_eq!(b.walk_passes().unwrap().1, 1, "{name}: the unwalked probe marks one prism");
        let unskipped = walk_probe.probe_without_early_out(&g, &ms, &tex, size).unwrap();
        let changed = (0..a.hits.len()).filter(|&i| a.hits[i] != unskipped.hits[i]).count();
        assert_eq!(changed, 0, "{name} {edge:?}: the skip changed pixels");
    }
    assert!(most > 1, "no pixel walked past its first prism");
}

/// The walk's picture is the full draw's: colour, with a shadow stage (which searches from
/// the hit in the hit's tangent frame), on the sphere face-on and the grazing torus, 96²,
/// by the bar the engines' pictures meet against `relief render` (tests/threejs_mesh.rs:
/// mean |difference| ≤ 1 of 255 over RGB, ≤ 1 % of pixels off by more than 8 in a channel).
/// The walk's fragment is the entry prism's, often several prisms from the hit; its own
/// varyings would shade the hit in the entry's frame (shading so, this test sees the sphere's
/// picture miss the bar: mean 1.70, 3.6 % of pixels off), so the walk shades with the hit
/// prism's (`compose::mesh::walk_frame`).
#[test]
fn the_walks_picture_is_the_full_draws() {
    use relief_dsl::spec::Curved;
    use relief_dsl::Pipeline;
    use relief_runtime::gpu::mesh::{mesh_textures, render_mesh, MeshProgram};
    use relief_runtime::mesh::MeshScene;
    let g = relief_runtime::Gpu::new().unwrap_or_else(|e| panic!("{e}"));
    let pipeline = "linear(32)+binary(5)+shadow=soft(16)".parse::<Pipeline>().unwrap().with_curved(Some(Curved::Prism));
    let (walk, unwalked) = (MeshProgram::new(&pipeline).unwrap(), MeshProgram::unwalked(&pipeline).unwrap());
    for name in ["sphere_rocks", "torus_grazing"] {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("scenes/meshes/{name}.toml"));
        let ms = MeshScene::from_scene(relief_runtime::load_scene_file(&path).unwrap()).unwrap();
        let tex = mesh_textures(&g, &ms, &walk).unwrap();
        let a = render_mesh(&g, &walk, &ms, &tex, 96).unwrap().rgba;
        let b = render_mesh(&g, &unwalked, &ms, &tex, 96).unwrap().rgba;
        let (mut sum, mut big) = (0u64, 0usize);
        for (pa, pb) in a.chunks(4).zip(b.chunks(4)) {
            let d: Vec<u32> = (0..3).map(|c| (pa[c] as i32 - pb[c] as i32).unsigned_abs()).collect();
            sum += d.iter().map(|&x| x as u64).sum::<u64>();
            big += usize::from(d.iter().any(|&x| x > 8));
        }
        let pixels = a.len() / 4;
        let mad = sum as f64 / (3 * pixels) as f64;
        let share = big as f64 / pixels as f64;
        assert!(mad <= 1.0 && share <= 0.01, "{name}: mean |difference| {mad:.4}, {:.3} % off by > 8", share * 100.0);
    }
}
