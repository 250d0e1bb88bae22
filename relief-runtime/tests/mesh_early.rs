//! The sealed walls of the prisms (`relief_runtime::mesh::vertices::sealed_walls`, the faces
//! that allow `curved=prism`'s early-out behind the hit), against independent counts on the
//! built-in sphere.

use relief_dsl::spec::Curved;
use relief_runtime::mesh::builtin::sphere;
use relief_runtime::mesh::vertices::{mesh_vertices, sealed_walls, FLOOR_EARLY_OUT};
use relief_runtime::mesh::Mesh;

/// Whether the edges (a, b) and (c, d) of `m` carry the same point, normal and uv at both
/// ends, in either order (compared as values, not as bits: the sphere has no −0 or NaN).
fn same_edge(m: &Mesh, (a, b): (u32, u32), (c, d): (u32, u32)) -> bool {
    let same = |i: u32, j: u32| {
        let (i, j) = (i as usize, j as usize);
        m.positions[i] == m.positions[j] && m.normals[i] == m.normals[j] && m.uvs[i] == m.uvs[j]
    };
    (same(a, c) && same(b, d)) || (same(a, d) && same(b, c))
}

/// On the sphere (nu segments, nv rings) a wall is sealed exactly where its edge has one
/// partner edge in another triangle with equal ends (found here by comparing every pair of
/// edges); and the walls left unsealed are the ones the parametrization says: at each pole
/// the fan's radial edges (each segment has its own pole vertex, with its own u), two per
/// triangle, and in each of the other nv − 2 bands the seam (u = 0 on one side, u = 1 on the
/// other), one wall on each side. The prism records carry the mask in `prism_b.z` with the
/// floor's bit.
#[test]
fn the_spheres_sealed_walls_are_the_edges_two_triangles_share_but_the_seam_and_the_poles() {
    let (nu, nv) = (12, 6);
    let m = sphere(nu, nv, [2.0, 1.0]);
    let mask = sealed_walls(&m);
    assert_eq!(mask.len(), m.triangles.len());
    let edges: Vec<(u32, u32)> = m.triangles.iter().flat_map(|t| (0..3).map(move |k| (t[k], t[(k + 1) % 3]))).collect();
    let mut unsealed = 0;
    for (e, &edge) in edges.iter().enumerate() {
        let partners = edges.iter().enumerate().filter(|&(f, &other)| f != e && same_edge(&m, edge, other)).count();
        let sealed = mask[e / 3] & (1 << (e % 3)) != 0;
        assert_eq!(sealed, partners == 1, "triangle {} wall {}: {partners} partners", e / 3, e % 3);
        unsealed += usize::from(!sealed);
    }
    assert_eq!(unsealed, 2 * 2 * nu + 2 * (nv - 2));
    let (v, _) = mesh_vertices(&m, Curved::Prism);
    for (k, &bits) in mask.iter().enumerate() {
        for r in &v[k * 6..k * 6 + 6] {
            assert_eq!(r.prism_b[2], f32::from(bits | FLOOR_EARLY_OUT), "triangle {k}");
        }
    }
}

/// The early-out changes no pixel: on the sphere (face-on and at its limb) and the grazing torus (64², the
/// goals' pipeline under `curved=prism`, drawn unwalked: every face of every prism, where the
/// early-out acts), the probe with the early-out and the probe with its
/// mask zeroed (every fragment runs the whole trace) cover the same pixels and give each the
/// same hit (uv and distance along the view ray, bit for bit: the discarded fragments lie
/// strictly behind a nearer one that the depth test keeps either way).
#[test]
fn the_early_out_leaves_the_prism_picture_as_it_was() {
    use relief_dsl::Pipeline;
    use relief_runtime::gpu::mesh::{mesh_textures, MeshProber, MeshProgram};
    use relief_runtime::mesh::MeshScene;
    let g = relief_runtime::Gpu::new().unwrap_or_else(|e| panic!("{e}"));
    let pipeline = "linear(32)+binary(5)".parse::<Pipeline>().unwrap().with_curved(Some(Curved::Prism));
    let prog = MeshProgram::unwalked(&pipeline).unwrap();
    let prober = MeshProber::new(&g, &prog).unwrap();
    for name in ["sphere_rocks", "torus_grazing", "sphere_limb"] {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("scenes/meshes/{name}.toml"));
        let ms = MeshScene::from_scene(relief_runtime::load_scene_file(&path).unwrap()).unwrap();
        let tex = mesh_textures(&g, &ms, &prog).unwrap();
        let with = prober.probe(&g, &ms, &tex, 64).unwrap();
        let without = prober.probe_without_early_out(&g, &ms, &tex, 64).unwrap();
        let covered = without.hits.iter().filter(|h| h[3] > 0.0).count();
        assert!(covered > 64 * 64 / 10, "{name}: {covered} pixels covered");
        let differ: Vec<usize> = (0..with.hits.len()).filter(|&i| with.hits[i] != without.hits[i]).collect();
        assert!(
            differ.is_empty(),
            "{name}: {} pixels differ, first {:?}",
            differ.len(),
            differ.first().map(|&i| (with.hits[i], without.hits[i]))
        );
    }
}
