//! Meshes (issue 38, docs/meshes.md): built-ins, files and their bad input, scenes, and the
//! exact reference against a brute-force twin written here apart from it (no BVH, no boxes:
//! a uniform tessellation with a stated error bound, every triangle tried).

use glam::{DVec2, DVec3, Vec3};
use relief_runtime::mesh::file::load_mesh_file;
use relief_runtime::mesh::{builtin, Mesh, MeshReference, MeshScene};
use relief_runtime::{EdgeMode, HeightMap};

fn tmpdir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("relief-meshes-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A deterministic map of `n × n` heights in [0, 1].
fn noise_map(n: usize, seed: u64) -> HeightMap {
    let mut s = seed;
    HeightMap::from_fn(n, n, |_, _| {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((s >> 33) as f64 / (1u64 << 31) as f64) as f32
    })
}

// ---------------------------------------------------------------------------------------------
// The brute-force twin
// ---------------------------------------------------------------------------------------------

/// The displaced surface tessellated on k × k squares per bilinear cell, and the bound `e` on
/// its distance from S (docs/meshes.md): `e = M / k²`, M = depth·(|c|max·|N|max + 2·|∇h|max·|∇N|max).
pub(crate) struct Twin {
    tris: Vec<[DVec3; 3]>,
    pub(crate) e: f64,
}

pub(crate) fn twin(mesh: &Mesh, map: &HeightMap, edge: EdgeMode, depth: f64, k: usize) -> Twin {
    let (w, h) = (map.width as f64, map.height as f64);
    let t = |x: i64, y: i64| map.texel(x, y, edge) as f64;
    let (mut dmax, mut cmax) = (0.0f64, 0.0f64);
    for y in -1..=map.height as i64 {
        for x in -1..=map.width as i64 {
            dmax = dmax.max((t(x + 1, y) - t(x, y)).abs()).max((t(x, y + 1) - t(x, y)).abs());
            cmax = cmax.max((t(x, y) - t(x + 1, y) - t(x, y + 1) + t(x + 1, y + 1)).abs());
        }
    }
    let grid = |i: u32| {
        let uv = mesh.uvs[i as usize].as_dvec2();
        DVec2::new(uv.x * w - 0.5, uv.y * h - 0.5)
    };
    let (mut gn, mut nmax) = (0.0f64, 0.0f64);
    let mut tris = Vec::new();
    for tri in &mesh.triangles {
        let q = tri.map(grid);
        let p = tri.map(|i| mesh.positions[i as usize].as_dvec3());
        let n = tri.map(|i| mesh.normals[i as usize].as_dvec3());
        // Barycentrics of a grid point (Cramer's rule on the uv triangle).
        let det = (q[1] - q[0]).perp_dot(q[2] - q[0]);
        let bary = |x: DVec2| {
            let l1 = (x - q[0]).perp_dot(q[2] - q[0]) / det;
            let l2 = (q[1] - q[0]).perp_dot(x - q[0]) / det;
            [1.0 - l1 - l2, l1, l2]
        };
        // |∇N| (Frobenius) from N at three points a unit apart in x and y.
        let nat = |x: DVec2| {
            let l = bary(x);
            n[0] * l[0] + n[1] * l[1] + n[2] * l[2]
        };
        let (n0, nx, ny) = (nat(q[0]), nat(q[0] + DVec2::X), nat(q[0] + DVec2::Y));
        gn = gn.max(((nx - n0).length_squared() + (ny - n0).length_squared()).sqrt());
        nmax = nmax.max(n.iter().map(|v| v.length()).fold(0.0, f64::max));
        let s = |x: DVec2| {
            let l = bary(x);
            let pp = p[0] * l[0] + p[1] * l[1] + p[2] * l[2];
            let nn = n[0] * l[0] + n[1] * l[1] + n[2] * l[2];
            let hh = map.bilinear((x.x + 0.5) / w, (x.y + 0.5) / h, edge);
            pp - depth * (1.0 - hh) * nn
        };
        let lo = q[0].min(q[1]).min(q[2]);
        let hi = q[0].max(q[1]).max(q[2]);
        let kf = k as f64;
        for sy in (lo.y * kf).floor() as i64..(hi.y * kf).ceil() as i64 {
            for sx in (lo.x * kf).floor() as i64..(hi.x * kf).ceil() as i64 {
                let (x0, y0) = (sx as f64 / kf, sy as f64 / kf);
                let (x1, y1) = ((sx + 1) as f64 / kf, (sy + 1) as f64 / kf);
                let mut poly: Vec<DVec2> = q.to_vec();
                // Keep the part on the inner side of each of the square's four lines.
                for (nrm, off) in [(DVec2::X, x0), (-DVec2::X, -x1), (DVec2::Y, y0), (-DVec2::Y, -y1)] {
                    let mut out = Vec::new();
                    for i in 0..poly.len() {
                        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
                        let (da, db) = (nrm.dot(a) - off, nrm.dot(b) - off);
                        if da >= 0.0 {
                            out.push(a);
                        }
                        if (da >= 0.0) != (db >= 0.0) {
                            out.push(a + (b - a) * (da / (da - db)));
                        }
                    }
                    poly = out;
                    if poly.len() < 3 {
                        break;
                    }
                }
                if poly.len() < 3 {
                    continue;
                }
                let sp: Vec<DVec3> = poly.iter().map(|&x| s(x)).collect();
                for i in 1..sp.len() - 1 {
                    tris.push([sp[0], sp[i], sp[i + 1]]);
                }
            }
        }
    }
    let m = depth * (cmax * nmax + 2.0 * 2f64.sqrt() * dmax * gn);
    Twin { tris, e: m / (k * k) as f64 }
}

impl Twin {
    /// The first hit over every triangle: `(t, unit normal of the triangle hit)`.
    pub(crate) fn hit(&self, o: DVec3, d: DVec3) -> Option<(f64, DVec3)> {
        let mut best: Option<(f64, DVec3)> = None;
        for [a, b, c] in &self.tris {
            let (e1, e2) = (*b - *a, *c - *a);
            let n = e1.cross(e2);
            let den = -d.dot(n);
            if den == 0.0 {
                continue;
            }
            let ao = o - *a;
            let t = ao.dot(n) / den;
            let dao = ao.cross(-d);
            // Cramer's rule on o + t·d = a + v·e1 + w·e2.
            let v = -e2.dot(dao) / den;
            let w = e1.dot(dao) / den;
            let tol = 1e-12;
            if t >= 0.0 && v >= -tol && w >= -tol && v + w <= 1.0 + tol && best.is_none_or(|bb| t < bb.0) {
                best = Some((t, n.normalize()));
            }
        }
        best
    }
}

/// The reference and the twin on every ray: they agree (both miss, or both hit with t within
/// (e + ε)/cos θ), or the ray is within e + ε of changing the twin's answer to the
/// reference's (moved by that much across it, in 8 directions). Returns (rays that hit,
/// rays that miss, ambiguous rays).
pub(crate) fn compare(r: &MeshReference, tw: &Twin, rays: &[(DVec3, DVec3)]) -> (usize, usize, usize) {
    let tol = tw.e + r.tolerance();
    let agrees = |o: DVec3, d: DVec3, ref_t: Option<f64>| match (ref_t, tw.hit(o, d)) {
        (None, None) => true,
        (Some(a), Some((b, n))) => (a - b).abs() <= tol / d.dot(n).abs().max(1e-300) + 1e-9,
        _ => false,
    };
    let (mut hits, mut misses, mut ambiguous) = (0, 0, 0);
    for &(o, d) in rays {
        let of = o.as_vec3();
        let df = d.as_vec3();
        let (o, d) = (of.as_dvec3(), df.as_dvec3());
        let rh = r.first_hit(of.to_array(), df.to_array()).map(|h| h.t);
        if rh.is_some() {
            hits += 1;
        } else {
            misses += 1;
        }
        if agrees(o, d, rh) {
            continue;
        }
        // Moved by (e + ε)/cos(π/8): one of 8 directions lies within π/8 of any.
        let (a, b) = d.any_orthonormal_pair();
        let shift = tol / (std::f64::consts::PI / 8.0).cos();
        let near = (0..8).any(|i| {
            let phi = i as f64 * std::f64::consts::FRAC_PI_4;
            let oo = o + (a * phi.cos() + b * phi.sin()) * shift;
            agrees(oo, d, rh)
        });
        assert!(
            near,
            "ray {o} + t·{d}: reference {rh:?}, twin {:?} (e = {}, ε = {})",
            tw.hit(o, d),
            tw.e,
            r.tolerance()
        );
        ambiguous += 1;
    }
    (hits, misses, ambiguous)
}

/// Rays from `eye` through a `n × n` grid of points on the rectangle `centre ± (a, b)`.
fn fan(eye: DVec3, centre: DVec3, a: DVec3, b: DVec3, n: usize) -> Vec<(DVec3, DVec3)> {
    let mut out = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let (s, t) = (2.0 * (i as f64 + 0.5) / n as f64 - 1.0, 2.0 * (j as f64 + 0.5) / n as f64 - 1.0);
            out.push((eye, (centre + a * s + b * t - eye).normalize()));
        }
    }
    out
}

#[test]
fn the_reference_agrees_with_its_twin_across_a_silhouette_edge_in_both_edge_modes() {
    let map = noise_map(4, 7);
    for (edge, repeats) in [(EdgeMode::Repeat, [1.0, 1.0]), (EdgeMode::Clamp, [2.0, 1.5])] {
        let mesh = builtin::sphere(8, 4, repeats);
        let depth = 0.15;
        let r = MeshReference::new(&mesh, &map, edge, depth).unwrap();
        let tw = twin(&mesh, &map, edge, depth, 48);
        assert!(tw.e < 2e-3, "the twin's bound {} is too loose to test anything", tw.e);
        let eye = DVec3::new(0.3, -3.0, 0.4);
        let rays = fan(eye, DVec3::new(0.9, 0.0, 0.0), DVec3::X * 0.3, DVec3::Z * 0.9, 20);
        let (hits, misses, ambiguous) = compare(&r, &tw, &rays);
        assert!(hits > 50 && misses > 50, "{edge:?}: {hits} hits, {misses} misses: the silhouette is not in view");
        assert!(ambiguous * 50 <= rays.len(), "{edge:?}: {ambiguous} of {} rays within e + ε of a change", rays.len());
    }
}

#[test]
fn the_reference_agrees_with_its_twin_on_a_one_texel_wall_at_the_silhouette_and_grazing_rays() {
    // Texel column 4 of 8 (u ≈ 0.5625, longitude 202.5°) is a wall of height 1 on a floor of
    // 0: on the sphere's left limb as seen from −y.
    let map = HeightMap::from_fn(8, 8, |x, _| if x == 4 { 1.0 } else { 0.0 });
    let mesh = builtin::sphere(12, 6, [1.0, 1.0]);
    let depth = 0.2;
    let r = MeshReference::new(&mesh, &map, EdgeMode::Repeat, depth).unwrap();
    let tw = twin(&mesh, &map, EdgeMode::Repeat, depth, 40);
    assert!(tw.e < 4e-3, "the twin's bound {} is too loose", tw.e);
    let eye = DVec3::new(0.0, -3.0, 0.0);
    let wall = fan(eye, DVec3::new(-0.95, 0.0, 0.0), DVec3::X * 0.2, DVec3::Z * 0.5, 16);
    let (hits, misses, amb) = compare(&r, &tw, &wall);
    assert!(hits > 20 && misses > 20 && amb * 20 <= wall.len(), "wall: {hits} hits, {misses} misses, {amb} ambiguous");
    // Grazing: a line of rays from far away sweeping across the right limb, all within a few
    // degrees of tangent where they hit.
    let far = DVec3::new(0.0, -40.0, 0.05);
    let grazing: Vec<(DVec3, DVec3)> =
        (0..120).map(|i| (far, (DVec3::new(0.7 + 0.0035 * i as f64, 0.0, 0.05) - far).normalize())).collect();
    let (hits, misses, amb) = compare(&r, &tw, &grazing);
    assert!(
        hits > 10 && misses > 10 && amb * 10 <= grazing.len(),
        "grazing: {hits} hits, {misses} misses, {amb} ambiguous"
    );
}

#[test]
fn with_every_height_at_one_the_reference_is_the_mesh_itself() {
    // h ≡ 1: S = P, the flat triangles; every ray's first hit is an ordinary ray-triangle one.
    let mesh = builtin::torus(16, 8, 1.0, 0.5, [2.0, 1.0]);
    let map = HeightMap::from_fn(4, 4, |_, _| 1.0);
    let r = MeshReference::new(&mesh, &map, EdgeMode::Repeat, 0.1).unwrap();
    let eye = DVec3::new(0.2, -3.0, 1.5);
    let rays = fan(eye, DVec3::ZERO, DVec3::X * 1.6, DVec3::new(0.0, 0.5, 0.9), 24);
    let (mut hits, mut misses) = (0, 0);
    for (o, d) in rays {
        let (of, df) = (o.as_vec3(), d.as_vec3());
        let (o, d) = (of.as_dvec3(), df.as_dvec3());
        let mut best: Option<f64> = None;
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize].as_dvec3());
            // Plane, then inside-test by the signs of three edge functions.
            let n = (b - a).cross(c - a);
            let tt = (a - o).dot(n) / d.dot(n);
            let x = o + d * tt;
            let inside = [(a, b), (b, c), (c, a)].iter().all(|(p, q)| (*q - *p).cross(x - *p).dot(n) >= 0.0);
            if tt >= 0.0 && inside && best.is_none_or(|bb| tt < bb) {
                best = Some(tt);
            }
        }
        let got = r.first_hit(of.to_array(), df.to_array()).map(|h| h.t);
        match (got, best) {
            (Some(g), Some(b)) => {
                hits += 1;
                assert!((g - b).abs() < 1e-6, "t {g} against {b}")
            }
            (None, None) => misses += 1,
            (g, b) => panic!("ray {o} + t·{d}: reference {g:?}, mesh {b:?}"),
        }
    }
    assert!(hits > 100 && misses > 100, "{hits} hits, {misses} misses");
}

// ---------------------------------------------------------------------------------------------
// Built-ins and tangents
// ---------------------------------------------------------------------------------------------

#[test]
fn built_in_frames_are_unit_right_handed_and_follow_the_uvs() {
    for mesh in [
        builtin::sphere(24, 12, [2.0, 1.0]),
        builtin::cylinder(24, 4, [3.0, 1.0]),
        builtin::torus(24, 12, 1.0, 0.5, [2.0, 1.0]),
    ] {
        let (checked, skipped) = mesh.clone().checked().unwrap();
        assert_eq!(skipped, 0, "{}: degenerate triangles in a built-in", mesh.name);
        assert_eq!(checked.triangles.len(), mesh.triangles.len());
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|i| i as usize);
            let (p, uv) = ([a, b, c].map(|i| mesh.positions[i]), [a, b, c].map(|i| mesh.uvs[i]));
            // dP/du and dP/dv over the triangle, from its corners.
            let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
            let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
            let det = d1.perp_dot(d2);
            let dpu = (e1 * d2.y - e2 * d1.y) / det;
            let dpv = (e2 * d1.x - e1 * d2.x) / det;
            // Counter-clockwise from outside: the face normal points out like the vertex normals.
            let face = e1.cross(e2);
            for &i in &[a, b, c] {
                let (n, tg) = (mesh.normals[i], mesh.tangents[i]);
                assert!((n.length() - 1.0).abs() < 1e-5 && (tg.truncate().length() - 1.0).abs() < 1e-5);
                assert!(n.dot(tg.truncate()).abs() < 1e-5, "{}: tangent not perpendicular", mesh.name);
                assert!(face.dot(n) > 0.0, "{}: triangle {t:?} faces inwards", mesh.name);
                assert!(tg.truncate().dot(dpu.normalize()) > 0.9, "{}: tangent does not follow +u", mesh.name);
                let bitangent = tg.w * n.cross(tg.truncate());
                assert!(bitangent.dot(dpv.normalize()) > 0.9, "{}: bitangent does not follow +v", mesh.name);
            }
        }
    }
    // The sphere is the unit sphere; the torus's points are 0.5 from its centre line.
    let s = builtin::sphere(24, 12, [1.0, 1.0]);
    assert!(s.positions.iter().all(|p| (p.length() - 1.0).abs() < 1e-5));
    let t = builtin::torus(24, 12, 1.0, 0.5, [1.0, 1.0]);
    assert!(t.positions.iter().all(|p| ((p.truncate().length() - 1.0).powi(2) + p.z * p.z - 0.25).abs() < 1e-5));
}

#[test]
fn mikktspace_tangents_match_the_analytic_ones_on_the_sphere() {
    let analytic = builtin::sphere(32, 16, [2.0, 1.0]);
    let mut m = analytic.clone();
    relief_runtime::mesh::tangent::generate(&mut m).unwrap();
    let mut compared = 0;
    for (i, (a, g)) in analytic.tangents.iter().zip(&m.tangents).enumerate() {
        if analytic.positions[i].z.abs() > 0.95 {
            continue; // near the poles the analytic tangent is a choice
        }
        assert_eq!(a.w, g.w, "handedness at vertex {i}");
        assert!(a.truncate().dot(g.truncate()) > 0.99, "vertex {i}: {a} against {g}");
        compared += 1;
    }
    assert!(compared > 300);
}

// ---------------------------------------------------------------------------------------------
// Files and bad input
// ---------------------------------------------------------------------------------------------

/// One mesh for [`glb`]: positions, normals and uvs per vertex (uvs optional), triangles.
pub(crate) struct GlbMesh {
    pub name: &'static str,
    pub positions: Vec<[f32; 3]>,
    pub uvs: Option<Vec<[f32; 2]>>,
    pub indices: Vec<u32>,
}

/// A binary glTF file holding `meshes`, each on its own node of the one scene.
pub(crate) fn glb(meshes: &[GlbMesh]) -> Vec<u8> {
    let mut bin: Vec<u8> = Vec::new();
    let (mut views, mut accessors, mut json_meshes, mut nodes) = (vec![], vec![], vec![], vec![]);
    let mut add =
        |bin: &mut Vec<u8>, bytes: &[u8], count: usize, ty: &str, comp: u32, minmax: Option<([f32; 3], [f32; 3])>| {
            let off = bin.len();
            bin.extend_from_slice(bytes);
            while !bin.len().is_multiple_of(4) {
                bin.push(0);
            }
            views.push(format!(r#"{{"buffer":0,"byteOffset":{off},"byteLength":{}}}"#, bytes.len()));
            let mm = minmax.map(|(lo, hi)| format!(r#","min":{lo:?},"max":{hi:?}"#)).unwrap_or_default();
            accessors.push(format!(
                r#"{{"bufferView":{},"componentType":{comp},"count":{count},"type":"{ty}"{mm}}}"#,
                views.len() - 1
            ));
            accessors.len() - 1
        };
    for (k, m) in meshes.iter().enumerate() {
        let pb: Vec<u8> = m.positions.iter().flatten().flat_map(|f| f.to_le_bytes()).collect();
        let lo = m.positions.iter().fold([f32::MAX; 3], |a, p| [a[0].min(p[0]), a[1].min(p[1]), a[2].min(p[2])]);
        let hi = m.positions.iter().fold([f32::MIN; 3], |a, p| [a[0].max(p[0]), a[1].max(p[1]), a[2].max(p[2])]);
        let pa = add(&mut bin, &pb, m.positions.len(), "VEC3", 5126, Some((lo, hi)));
        let mut attrs = format!(r#""POSITION":{pa}"#);
        if let Some(uvs) = &m.uvs {
            let ub: Vec<u8> = uvs.iter().flatten().flat_map(|f| f.to_le_bytes()).collect();
            let ua = add(&mut bin, &ub, uvs.len(), "VEC2", 5126, None);
            attrs += &format!(r#","TEXCOORD_0":{ua}"#);
        }
        let ib: Vec<u8> = m.indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        let ia = add(&mut bin, &ib, m.indices.len(), "SCALAR", 5125, None);
        json_meshes
            .push(format!(r#"{{"name":"{}","primitives":[{{"attributes":{{{attrs}}},"indices":{ia}}}]}}"#, m.name));
        nodes.push(format!(r#"{{"mesh":{k}}}"#));
    }
    let node_ids: Vec<String> = (0..meshes.len()).map(|i| i.to_string()).collect();
    let mut json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[{}]}}],"nodes":[{}],"meshes":[{}],"accessors":[{}],"bufferViews":[{}],"buffers":[{{"byteLength":{}}}]}}"#,
        node_ids.join(","),
        nodes.join(","),
        json_meshes.join(","),
        accessors.join(","),
        views.join(","),
        bin.len()
    );
    while !json.len().is_multiple_of(4) {
        json.push(' ');
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::new();
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(json.as_bytes());
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    out
}

/// The scene of the flat-square tests: `sphere_rocks.toml`'s settings with an 8² map of
/// constant height ½ (so S is the plane z = −depth/2 over [`flat_square`]), the given depth
/// and a 40° camera at `angle_deg` from the normal, `azimuth_deg`, `distance` from the origin.
pub(crate) fn level_scene(depth: f32, angle_deg: f32, azimuth_deg: f32, distance: f32) -> relief_runtime::Scene {
    let mut sc = {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/meshes/sphere_rocks.toml");
        relief_runtime::load_scene_file(&path).unwrap()
    };
    sc.height = HeightMap::new(8, 8, vec![0.5; 64]);
    sc.depth_scale = depth;
    sc.camera.angle_deg = angle_deg;
    sc.camera.azimuth_deg = azimuth_deg;
    sc.camera.distance = distance;
    sc.camera.fov_deg = 40.0;
    sc.camera.target = Vec3::ZERO;
    sc
}

/// The square (−1..1)² in z = 0 as a mesh: two triangles, A = (0, 1, 2) below the diagonal
/// y = x and B = (0, 2, 3) above it, normal +z, tangent +x, uv = (p + 1)/2.
pub(crate) fn flat_square() -> Mesh {
    use glam::{Vec2, Vec4};
    let corners = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]].map(|[x, y]| Vec3::new(x, y, 0.0));
    Mesh {
        name: "square".into(),
        positions: corners.to_vec(),
        normals: vec![Vec3::Z; 4],
        tangents: vec![Vec4::new(1.0, 0.0, 0.0, 1.0); 4],
        uvs: corners.iter().map(|c| Vec2::new(c.x + 1.0, c.y + 1.0) * 0.5).collect(),
        triangles: vec![[0, 1, 2], [0, 2, 3]],
    }
}

/// A unit square in the plane z = `z` (two triangles), with uvs unless `uvs` is false.
pub(crate) fn square(name: &'static str, z: f32, uvs: bool) -> GlbMesh {
    GlbMesh {
        name,
        positions: vec![[0.0, 0.0, z], [1.0, 0.0, z], [1.0, 1.0, z], [0.0, 1.0, z]],
        uvs: uvs.then(|| vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]),
        indices: vec![0, 1, 2, 0, 2, 3],
    }
}

#[test]
fn a_mesh_without_uvs_is_one_error_line_naming_the_file() {
    let d = tmpdir("nouv");
    let obj = d.join("no_uv.obj");
    std::fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let g = d.join("no_uv.glb");
    std::fs::write(&g, glb(&[square("plain", 0.0, false)])).unwrap();
    for f in [&obj, &g] {
        let e = load_mesh_file(f, None).unwrap_err().to_string();
        assert!(e.contains(&f.display().to_string()) && e.contains("texture coordinates"), "{e}");
        assert_eq!(e.lines().count(), 1, "{e}");
    }
}

#[test]
fn missing_tangents_are_generated_and_said_once_and_degenerate_triangles_counted() {
    let d = tmpdir("tangents");
    let obj = d.join("quad.obj");
    // Two good triangles, one with a repeated corner (no area), one with no uv area.
    std::fs::write(
        &obj,
        "o quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
         f 1/1 2/2 3/3\nf 1/1 3/3 4/4\nf 1/1 2/2 2/2\nf 1/1 2/1 3/1\n",
    )
    .unwrap();
    let (mesh, notes) = load_mesh_file(&obj, None).unwrap();
    assert_eq!(mesh.triangles.len(), 2);
    assert_eq!(notes.degenerate_triangles, 2);
    assert_eq!(notes.generated_tangents, vec!["quad".to_string()]);
    let w = notes.warning().unwrap();
    assert_eq!(w.lines().count(), 1);
    assert!(w.contains("MikkTSpace") && w.contains("2 degenerate"), "{w}");
    // OBJ's v runs up the image: read as 1 − v, so +u is +x and +v is −y here; the generated
    // frame says so (tangent +x, bitangent −y).
    let i = mesh.triangles[0][0] as usize;
    let (n, t) = (mesh.normals[i], mesh.tangents[i]);
    assert!((t.truncate() - Vec3::X).length() < 1e-4, "{t}");
    assert!((t.w * n.cross(t.truncate()) + Vec3::Y).length() < 1e-4, "{t} {n}");
}

#[test]
fn a_file_of_several_meshes_draws_all_or_the_one_named() {
    let d = tmpdir("several");
    let f = d.join("two.glb");
    std::fs::write(&f, glb(&[square("Floor", 0.0, true), square("Roof", 1.0, true)])).unwrap();
    let (all, _) = load_mesh_file(&f, None).unwrap();
    assert_eq!(all.triangles.len(), 4);
    let (roof, notes) = load_mesh_file(&f, Some("Roof")).unwrap();
    assert_eq!(roof.triangles.len(), 2);
    assert!(roof.positions.iter().all(|p| p.z == 1.0));
    assert_eq!(notes.generated_tangents, vec!["Roof".to_string()]);
    let e = load_mesh_file(&f, Some("Wall")).unwrap_err().to_string();
    assert!(e.contains("`Floor`") && e.contains("`Roof`") && e.contains("Wall") && e.lines().count() == 1, "{e}");
}

#[test]
fn a_scene_file_names_its_mesh_and_the_reference_sees_its_silhouette() {
    let d = tmpdir("scene");
    let hm = d.join("h.png");
    image::GrayImage::from_fn(8, 8, |x, y| image::Luma([((x * 31 + y * 17) % 256) as u8])).save(&hm).unwrap();
    let sc = d.join("s.toml");
    std::fs::write(
        &sc,
        "depth_scale = 0.05\n[height_map]\npath = \"h.png\"\n[mesh]\nbuiltin = \"sphere\"\n[camera]\nangle = 60\n",
    )
    .unwrap();
    let scene = relief_runtime::load_scene_file(&sc).unwrap();
    assert_eq!(scene.camera.target, Vec3::ZERO);
    let ms = MeshScene::from_scene(scene).unwrap();
    assert_eq!(ms.notes.warning(), None);
    let hits = ms.reference_hits(24, 24).unwrap();
    assert_eq!(hits.len(), 24 * 24);
    // The unit sphere at distance 3 under a 40° field of view covers a disc of angular radius
    // asin(1/3) = 19.47° about the centre: pixels well inside are hit, well outside missed.
    let half = (20f64.to_radians()).tan();
    for (k, h) in hits.iter().enumerate() {
        let (x, y) = ((k % 24) as f64, (k / 24) as f64);
        let (nx, ny) = ((2.0 * (x + 0.5) / 24.0 - 1.0) * half, (1.0 - 2.0 * (y + 0.5) / 24.0) * half);
        let angle = (nx * nx + ny * ny).sqrt().atan().to_degrees();
        if angle < 17.0 {
            assert!(h.is_some(), "pixel {k} at {angle}° missed");
        } else if angle > 20.0 {
            assert!(h.is_none(), "pixel {k} at {angle}° hit");
        }
    }
    // Bad `[mesh]` tables: one error line naming the file and the key.
    for (body, key) in [
        ("[mesh]\n", "mesh"),
        ("[mesh]\nbuiltin = \"cube\"\n", "mesh.builtin"),
        ("[mesh]\nbuiltin = \"sphere\"\npath = \"a.obj\"\n", "mesh"),
        ("[mesh]\nbuiltin = \"sphere\"\nname = \"a\"\n", "mesh.name"),
        ("[mesh]\nbuiltn = \"sphere\"\n", "mesh.builtn"),
    ] {
        std::fs::write(&sc, format!("[height_map]\npath = \"h.png\"\n{body}")).unwrap();
        let e = relief_runtime::load_scene_file(&sc).unwrap_err().to_string();
        assert!(e.contains("s.toml") && e.contains(&format!("`{key}`")) && e.lines().count() == 1, "{e}");
    }
}

#[test]
fn the_mesh_scene_files_load() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/meshes");
    let mut n = 0;
    for e in std::fs::read_dir(&dir).unwrap() {
        let p = e.unwrap().path();
        let scene = relief_runtime::load_scene_file(&p).unwrap_or_else(|e| panic!("{e}"));
        let ms = MeshScene::from_scene(scene).unwrap_or_else(|e| panic!("{e}"));
        assert!(ms.mesh.triangles.len() > 1000 && ms.notes.warning().is_none(), "{}", p.display());
        n += 1;
    }
    assert!(n >= 4);
}

// ---------------------------------------------------------------------------------------------
// Why curved=prism misses a pixel (mesh_measure::prism_miss_causes)
// ---------------------------------------------------------------------------------------------

/// The classification of prism's missing pixels on a case whose answer follows from plane
/// geometry alone: a flat square (two triangles A below the diagonal y = x, B above it; normals
/// +z, so the prisms are exact and vertical) under a constant height ½, seen at 60°. The probe
/// says that the GPU drew nothing, so every pixel the surface holds is "missing". Each pixel's
/// hit (the ray at z = −depth/2) is computed here; the hit is handed to the classifier as its
/// own triangle's (that prism's fragment finds it on the CPU: `Other`, nothing the prism
/// method lacks) or as the other triangle's, and then where the ray meets the other's prism
/// decides, from the ray's points at z = 0 (the top), −depth/2 (the hit) and −depth (the
/// floor): the ray enters the other's top (its straight ray crosses the plane past its wall:
/// `AfterExit`), it crosses into the other below the
/// hit (the other's wall fragment enters below the plane: its search, from the entry, ends at
/// the entry, inside that prism, and the CPU draws it: `Other`; before the search ran from the
/// entry it stopped at the plane in front of the entry, the cause the fix removed), it stays in
/// its own triangle (`NoFace`).
#[test]
fn prism_miss_causes_follow_the_prisms_geometry_on_a_flat_square() {
    use relief_runtime::gpu::mesh::MeshProbe;
    use relief_runtime::mesh::MeshHit;
    use relief_runtime::mesh_measure::{prism_miss_causes, PrismMiss};
    let ms = MeshScene { scene: level_scene(0.1, 60.0, -90.0, 4.0), mesh: flat_square(), notes: Default::default() };
    let depth = ms.scene.depth_scale as f64;
    let size = 48u32;
    // Where a point lies: in A or B by more than `m` from the diagonal and the square's border.
    let m = 2e-3;
    let inside = |p: DVec3| p.x.abs() < 1.0 - m && p.y.abs() < 1.0 - m;
    // Triangle 0 (A) lies below the diagonal y = x, triangle 1 (B) above it.
    let in_tri = |p: DVec3, k: u32| inside(p) && if k == 0 { p.x - p.y > m } else { p.y - p.x > m };
    let mut reference = Vec::new();
    let mut want = Vec::new();
    for (i, r) in ms.rays(size, size).iter().enumerate() {
        let (o, d) = (DVec3::from(r.origin.map(f64::from)), DVec3::from(r.dir.map(f64::from)));
        let at = |z: f64| o + d * ((z - o.z) / d.z);
        let (top, hit, floor) = (at(0.0), at(-0.5 * depth), at(-depth));
        let Some(own) = (0..2).find(|&k| in_tri(hit, k)).filter(|_| inside(top) && inside(floor)) else {
            reference.push(None);
            continue;
        };
        let other = 1 - own;
        let mk = |triangle| {
            Some(MeshHit {
                t: (hit - o).length(),
                u: (hit.x + 1.0) * 0.5,
                v: (hit.y + 1.0) * 0.5,
                triangle,
                point: hit.to_array(),
            })
        };
        // Where the ray meets the other triangle's prism, if the hit is handed to it.
        let expect = if in_tri(top, other) {
            Some(PrismMiss::AfterExit)
        } else if in_tri(top, own) && in_tri(floor, other) {
            Some(PrismMiss::Other)
        } else if in_tri(top, own) && in_tri(floor, own) {
            Some(PrismMiss::NoFace)
        } else {
            None // within the margin of the diagonal: not asserted
        };
        // Every other pixel keeps its own triangle (drawn by its prism on the CPU: Other); the
        // others are handed to the other triangle.
        match expect {
            Some(c) if i % 2 == 0 => {
                reference.push(mk(other));
                want.push((i, c));
            }
            Some(_) => {
                reference.push(mk(own));
                want.push((i, PrismMiss::Other));
            }
            None => reference.push(None),
        }
    }
    let probe = MeshProbe { hits: vec![[0.0; 4]; (size * size) as usize], depth: vec![1.0; (size * size) as usize] };
    let got = prism_miss_causes(&ms, &reference, &probe, size, 32, 5);
    let got: std::collections::HashMap<usize, PrismMiss> = got.into_iter().collect();
    let mut seen = std::collections::HashMap::new();
    for (i, c) in &want {
        assert_eq!(got.get(i), Some(c), "pixel {i}");
        *seen.entry(*c).or_insert(0) += 1;
    }
    for c in [PrismMiss::NoFace, PrismMiss::AfterExit, PrismMiss::Other] {
        assert!(seen.get(&c).copied().unwrap_or(0) >= 5, "too few pixels of {c:?}: {seen:?}");
    }
}

// ---------------------------------------------------------------------------------------------
// The prism's exact entry and exit (mesh_measure::prism_crossings, the shader's prism_chord)
// ---------------------------------------------------------------------------------------------

/// Whether `x` lies in the prism `X(b, w) = Σ bᵢ (pᵢ − depth·(1 − w)·nᵢ)`, b in the triangle,
/// w in [0, 1], decided here apart from the crossing code: the layers w where x lies in the
/// layer's plane are the roots of the cubic `(x − Q₀(w))·((Q₁ − Q₀) × (Q₂ − Q₀))(w)`, found by
/// sign changes over 100 samples and bisection; at each, b by Cramer's rule in that layer.
/// `slack` widens b and w.
fn in_prism(x: DVec3, p: [DVec3; 3], n: [DVec3; 3], depth: f64, slack: f64) -> bool {
    let q = |w: f64, k: usize| p[k] - n[k] * (depth * (1.0 - w));
    let f = |w: f64| (x - q(w, 0)).dot((q(w, 1) - q(w, 0)).cross(q(w, 2) - q(w, 0)));
    let bary = |w: f64| {
        let (e1, e2, r) = (q(w, 1) - q(w, 0), q(w, 2) - q(w, 0), x - q(w, 0));
        let (d11, d12, d22, r1, r2) = (e1.dot(e1), e1.dot(e2), e2.dot(e2), r.dot(e1), r.dot(e2));
        let det = d11 * d22 - d12 * d12;
        let (b1, b2) = ((r1 * d22 - r2 * d12) / det, (r2 * d11 - r1 * d12) / det);
        b1 >= -slack && b2 >= -slack && b1 + b2 <= 1.0 + slack
    };
    let samples = 100;
    let (lo_w, hi_w) = (-slack, 1.0 + slack);
    let mut prev = (lo_w, f(lo_w));
    for k in 1..=samples {
        let w = lo_w + (hi_w - lo_w) * k as f64 / samples as f64;
        let v = f(w);
        if prev.1 == 0.0 && bary(prev.0) {
            return true;
        }
        if prev.1.signum() != v.signum() {
            let (mut a, mut b) = (prev.0, w);
            for _ in 0..60 {
                let m = 0.5 * (a + b);
                if f(m).signum() == f(a).signum() {
                    a = m;
                } else {
                    b = m;
                }
            }
            if bary(0.5 * (a + b)) {
                return true;
            }
        }
        prev = (w, v);
    }
    false
}

/// The prism's exact entry and exit against a dense march of the volume's membership test
/// ([`in_prism`], written here): a triangle whose vertex normals splay outward by 35° (so its
/// side walls twist, bilinear and not planar), 0.3 deep, and rays in many directions, grazing
/// ones among them. Where the march finds the ray inside the prism, the first and last inside
/// points lie within one march step (plus the membership slack's reach) of the entry and the
/// exit; the crossings' (b, w) map back to their points; and where the march never finds the
/// ray inside, the crossings are none (or a grazing pair within a step of each other).
#[test]
fn the_prisms_exact_entry_and_exit_match_a_march_of_its_volume() {
    use relief_runtime::mesh_measure::prism_crossings;
    let splay = 35f64.to_radians();
    let p = [0.0, 1.0, 2.0].map(|k: f64| {
        let a = std::f64::consts::TAU * k / 3.0 + 0.3;
        DVec3::new(a.cos(), 0.8 * a.sin(), 0.1 * k)
    });
    let centre = (p[0] + p[1] + p[2]) / 3.0;
    let n = p.map(|c| {
        let out = (c - centre).normalize();
        DVec3::Z * splay.cos() + out * splay.sin()
    });
    let depth = 0.3;
    let mut seed = 7u64;
    let mut rnd = || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let (mut crossed, mut grazing) = (0, 0);
    for _ in 0..200 {
        // A target in the prism's box, a direction anywhere (a third of them within 10° of
        // level with the triangle).
        let target = centre + DVec3::new(2.4 * rnd() - 1.2, 2.0 * rnd() - 1.0, -0.35 * rnd() + 0.05);
        let level = rnd() < 0.33;
        let elev = if level { (rnd() * 20.0 - 10.0).to_radians() } else { (rnd() * 170.0 - 85.0).to_radians() };
        let az = rnd() * std::f64::consts::TAU;
        let d = DVec3::new(elev.cos() * az.cos(), elev.cos() * az.sin(), elev.sin());
        let o = target - d * 4.0;
        // March the part of the ray in the box of the six corners (which holds the prism).
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for k in 0..3 {
            for c in [p[k], p[k] - n[k] * depth] {
                (lo, hi) = (lo.min(c), hi.max(c));
            }
        }
        let (mut a, mut b) = (0.0f64, 8.0f64);
        for k in 0..3 {
            let (t0, t1) = ((lo[k] - o[k]) / d[k], (hi[k] - o[k]) / d[k]);
            (a, b) = (a.max(t0.min(t1)), b.min(t0.max(t1)));
        }
        let step = 1e-3;
        let inside: Vec<f64> = (0..((b - a) / step).max(0.0) as usize + 1)
            .map(|k| a + k as f64 * step)
            .filter(|&t| in_prism(o + d * t, p, n, depth, 0.0))
            .collect();
        let got = prism_crossings(o, d, p, n, depth);
        match (inside.first(), inside.last(), got) {
            (Some(&first), Some(&last), Some((entry, exit))) => {
                crossed += 1;
                grazing += level as usize;
                assert!(
                    entry.t <= first + 1e-9 && entry.t >= first - step - 1e-6,
                    "entry {} vs march {first}",
                    entry.t
                );
                assert!(exit.t >= last - 1e-9 && exit.t <= last + step + 1e-6, "exit {} vs march {last}", exit.t);
                for c in [entry, exit] {
                    let b = [c.b.x, c.b.y, 1.0 - c.b.x - c.b.y];
                    let x: DVec3 = (0..3).map(|k| (p[k] - n[k] * (depth * (1.0 - c.w))) * b[k]).sum();
                    assert!((x - (o + d * c.t)).length() < 1e-9, "crossing off its point: {c:?}");
                    assert!(in_prism(x, p, n, depth, 1e-6), "crossing outside the prism: {c:?}");
                }
            }
            (Some(&first), _, None) => panic!("the march finds the ray inside at t = {first}, no crossing"),
            (None, _, Some((entry, exit))) => {
                assert!(exit.t - entry.t <= step + 1e-6, "crossings {entry:?} {exit:?} where the march finds none")
            }
            (None, _, None) => {}
            (Some(_), None, _) => unreachable!(),
        }
    }
    assert!(crossed >= 40 && grazing >= 8, "too few rays through the prism: {crossed}, {grazing} grazing");
}
