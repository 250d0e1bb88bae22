//! A mesh as the mesh module's vertices ([`MeshVertex`], relief-dsl's `compose/mesh.rs`):
//! what the runtime uploads for `curved=none`, `quadric` and `prism` (docs/meshes.md).
//!
//! - **Scales** (`uv.zw`): texture units per object unit along the tangent and the
//!   bitangent, `1 / |∂P/∂u|` and `1 / |∂P/∂v|`. Each triangle's `∂P/∂u`, `∂P/∂v` solve
//!   `P₁ − P₀ = ∂P/∂u·Δu₁ + ∂P/∂v·Δv₁`, `P₂ − P₀ = ∂P/∂u·Δu₂ + ∂P/∂v·Δv₂` (the linear map
//!   the triangle is); a vertex takes the mean of its triangles', weighted by their uv area.
//! - **Curvature** (`curvature.xy`, `quadric` only): see [`curvature`].
//! - **Prisms** (`prism` only): see [`prism_vertices`]; the walk's draw and buffer,
//!   [`prism_walk`].

use glam::{DMat2, DVec3, Vec3};
use relief_dsl::compose::mesh::{MeshVertex, PrismCell};
use relief_dsl::spec::Curved;

use super::Mesh;
use crate::heightmap::{EdgeMode, HeightMap};

/// The vertices and triangle indices of `mesh` for the mode `curved`: one record per mesh
/// vertex and the mesh's triangles for `none` and `quadric`, the prisms for `prism`.
pub fn mesh_vertices(mesh: &Mesh, curved: Curved) -> (Vec<MeshVertex>, Vec<u32>) {
    let base = base_vertices(mesh, curved == Curved::Quadric);
    match curved {
        Curved::None | Curved::Quadric => (base, mesh.triangles.iter().flatten().copied().collect()),
        Curved::Prism => prism_vertices(mesh, &base),
    }
}

/// One record per mesh vertex at the surface (`position.w` = 1), with its scales, and its
/// curvature `with_curvature`.
fn base_vertices(mesh: &Mesh, with_curvature: bool) -> Vec<MeshVertex> {
    let scales = scales(mesh);
    let curv = if with_curvature { curvature(mesh, &scales) } else { vec![[0.0; 2]; mesh.positions.len()] };
    (0..mesh.positions.len())
        .map(|i| {
            let (p, n, t, uv) = (mesh.positions[i], mesh.normals[i], mesh.tangents[i], mesh.uvs[i]);
            MeshVertex {
                position: [p.x, p.y, p.z, 1.0],
                normal: [n.x, n.y, n.z, 0.0],
                tangent: t.to_array(),
                uv: [uv.x, uv.y, scales[i][0] as f32, scales[i][1] as f32],
                curvature: [curv[i][0] as f32, curv[i][1] as f32, 0.0, 0.0],
                ..Default::default()
            }
        })
        .collect()
}

/// A triangle's `∂P/∂u` and `∂P/∂v` and its uv area; `None` where its uvs are singular.
fn derivatives(mesh: &Mesh, t: [u32; 3]) -> Option<(DVec3, DVec3, f64)> {
    let p = t.map(|i| mesh.positions[i as usize].as_dvec3());
    let uv = t.map(|i| mesh.uvs[i as usize].as_dvec2());
    let m = DMat2::from_cols(uv[1] - uv[0], uv[2] - uv[0]);
    let det = m.determinant();
    if det.abs().partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let inv = m.inverse();
    let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
    // [∂P/∂u ∂P/∂v] = [e1 e2] · inv
    let dpdu = e1 * inv.x_axis.x + e2 * inv.x_axis.y;
    let dpdv = e1 * inv.y_axis.x + e2 * inv.y_axis.y;
    Some((dpdu, dpdv, det.abs() * 0.5))
}

/// Each vertex's texture units per object unit along T and B (module doc); 1 for a vertex
/// in no triangle with regular uvs.
fn scales(mesh: &Mesh) -> Vec<[f64; 2]> {
    let mut acc = vec![[0.0f64; 3]; mesh.positions.len()];
    for &t in &mesh.triangles {
        let Some((dpdu, dpdv, area)) = derivatives(mesh, t) else { continue };
        for i in t {
            let a = &mut acc[i as usize];
            a[0] += area * dpdu.length();
            a[1] += area * dpdv.length();
            a[2] += area;
        }
    }
    acc.iter()
        .map(|a| if a[2] > 0.0 && a[0] > 0.0 && a[1] > 0.0 { [a[2] / a[0], a[2] / a[1]] } else { [1.0, 1.0] })
        .collect()
}

/// Each vertex's quadric coefficients a, b (object units, `MeshVertex::curvature`):
/// `a = −κ_T / (2 s_u²)`, `b = −κ_B / (2 s_v²)`, with κ_T, κ_B the base surface's normal
/// curvatures along the vertex's tangent and bitangent and s_u, s_v its scales.
///
/// How κ is estimated: along each mesh edge from the vertex i to a neighbour j, the normals'
/// change gives the normal curvature in the edge's direction,
/// `κ_e = (N_j − N_i)·(P_j − P_i) / |P_j − P_i|²` (exact on a sphere, where N = P / R: every
/// edge gives 1/R). Euler's formula writes κ in a tangent direction (c, s) = (cos θ, sin θ)
/// from T as `κ_T c² + 2τ cs + κ_B s²`; κ_T, τ, κ_B are fitted to the edges' κ_e by least
/// squares (the edge projected into the tangent plane gives its θ), and a, b take κ_T and κ_B
/// (the record has no cross term). Vertices at one position (a seam) pool their edges. Where the fit is singular (fewer than three edge
/// directions), every direction takes the edges' mean κ.
pub fn curvature(mesh: &Mesh, scales: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let n = mesh.positions.len();
    // Vertices at one position (a uv seam, a pole) are one point of the surface: their
    // neighbours are pooled, so that a seam's vertex sees the edges on both sides.
    // Positions are compared on a grid of 1e-5 of the mesh's radius (a seam's two vertices
    // come from angles 0 and 2π, equal only to rounding).
    let grid = (mesh.bounds().1 as f64 * 1e-5).max(f64::MIN_POSITIVE);
    let mut point_of: std::collections::HashMap<[i64; 3], usize> = std::collections::HashMap::new();
    let welded: Vec<usize> = (0..n)
        .map(|i| {
            let key = mesh.positions[i].as_dvec3().to_array().map(|c| (c / grid).round() as i64);
            let next = point_of.len();
            *point_of.entry(key).or_insert(next)
        })
        .collect();
    let mut neighbours: Vec<Vec<u32>> = vec![Vec::new(); point_of.len()];
    for t in &mesh.triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            for (x, y) in [(a, b), (b, a)] {
                let list = &mut neighbours[welded[x as usize]];
                if welded[y as usize] != welded[x as usize]
                    && !list.iter().any(|&z| welded[z as usize] == welded[y as usize])
                {
                    list.push(y);
                }
            }
        }
    }
    (0..n)
        .map(|i| {
            let (p, nrm) = (mesh.positions[i].as_dvec3(), mesh.normals[i].as_dvec3());
            let tan = mesh.tangents[i];
            let t = (Vec3::new(tan.x, tan.y, tan.z).as_dvec3() - nrm * nrm.dot(tan.truncate().as_dvec3())).normalize();
            let b = nrm.cross(t) * tan.w as f64;
            // Normal equations of the fit κ_e ≈ κ_T c² + 2τ cs + κ_B s².
            let mut ata = [[0.0f64; 3]; 3];
            let mut atk = [0.0f64; 3];
            let (mut sum, mut count) = (0.0, 0usize);
            for &j in &neighbours[welded[i]] {
                let e = mesh.positions[j as usize].as_dvec3() - p;
                let len2 = e.length_squared();
                if len2.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
                    continue;
                }
                let k = (mesh.normals[j as usize].as_dvec3() - nrm).dot(e) / len2;
                let d = e - nrm * nrm.dot(e);
                let dl = d.length();
                if dl.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) || !k.is_finite() {
                    continue;
                }
                let (c, s) = (d.dot(t) / dl, d.dot(b) / dl);
                let row = [c * c, 2.0 * c * s, s * s];
                for r in 0..3 {
                    for q in 0..3 {
                        ata[r][q] += row[r] * row[q];
                    }
                    atk[r] += row[r] * k;
                }
                sum += k;
                count += 1;
            }
            let (kt, kb) = match solve3(ata, atk) {
                Some(x) => (x[0], x[2]),
                None if count > 0 => (sum / count as f64, sum / count as f64),
                None => (0.0, 0.0),
            };
            let [su, sv] = scales[i];
            [-kt / (2.0 * su * su), -kb / (2.0 * sv * sv)]
        })
        .collect()
}

/// The solution of the 3 × 3 system `a·x = y` by Cramer's rule; `None` where `a` is singular
/// (its determinant below 1e-9 of the product of its rows' lengths: the edges span fewer than
/// three directions of the fit).
fn solve3(a: [[f64; 3]; 3], y: [f64; 3]) -> Option<[f64; 3]> {
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(a);
    let scale: f64 = a.iter().map(|r| r.iter().map(|x| x * x).sum::<f64>().sqrt()).product();
    if d.abs().partial_cmp(&(1e-9 * scale)) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let mut x = [0.0; 3];
    for (c, xc) in x.iter_mut().enumerate() {
        let mut m = a;
        for r in 0..3 {
            m[r][c] = y[r];
        }
        *xc = det(m) / d;
    }
    Some(x)
}

/// The prisms: each triangle extruded along its vertex normals as deep as the relief (the
/// vertex entry moves a vertex with `position.w` = 0 the relief's depth along −N). Per
/// triangle six records (its corners at w = 1, the top, and at w = 0, the floor), each with
/// `prism_a`, `prism_b` the triangle's three uvs and `prism_p*`, `prism_n*` its three points and
/// normals (for the exact entry and exit), and eight triangles: the top cap, the
/// bottom cap and two per side wall (corners k, k+1 at the top and at the floor).
/// `prism_b.z` holds the faces that allow the early-out behind the hit: the sealed walls
/// ([`sealed_walls`]) and the floor (bit 3), as `MeshVertex::prism_b` documents.
pub fn prism_vertices(mesh: &Mesh, base: &[MeshVertex]) -> (Vec<MeshVertex>, Vec<u32>) {
    let mut vertices = Vec::with_capacity(mesh.triangles.len() * 6);
    let mut indices = Vec::with_capacity(mesh.triangles.len() * 24);
    let sealed = sealed_walls(mesh);
    for (t, &sealed) in mesh.triangles.iter().zip(&sealed) {
        let early = f32::from(sealed | FLOOR_EARLY_OUT);
        let uv = t.map(|i| mesh.uvs[i as usize]);
        let first = vertices.len() as u32;
        let (point, normal) = (|k: usize| corner_point(mesh, t, k, 0.0), |k: usize| corner_normal(mesh, t, k));
        for w in [1.0, 0.0] {
            for &i in t {
                let mut v = base[i as usize];
                v.position[3] = w;
                v.prism_a = [uv[0].x, uv[0].y, uv[1].x, uv[1].y];
                v.prism_b = [uv[2].x, uv[2].y, early, 0.0];
                [v.prism_p0, v.prism_p1, v.prism_p2] = [point(0), point(1), point(2)];
                [v.prism_n0, v.prism_n1, v.prism_n2] = [normal(0), normal(1), normal(2)];
                vertices.push(v);
            }
        }
        // Top corners first + 0..3, floor corners first + 3..6.
        let (top, floor) = (|k: u32| first + k % 3, |k: u32| first + 3 + k % 3);
        indices.extend([top(0), top(1), top(2), floor(0), floor(2), floor(1)]);
        for k in 0..3 {
            indices.extend([top(k), floor(k), floor(k + 1), top(k), floor(k + 1), top(k + 1)]);
        }
    }
    (vertices, indices)
}

/// The prism walk's draw and buffer (relief-dsl's `compose::Options::prism_walk`): the
/// vertices of [`prism_vertices`] with `prism_b.w` the triangle's index, the indices of the
/// faces a ray can enter the relief's shell through, each prism's top cap and its side walls
/// that are not [joined](joined_walls) to another triangle's (a joined wall is entered from
/// the prism across it, whose fragment walks on; the floors face the inside of the shell),
/// and one [`PrismCell`] per triangle: its corners, across each joined wall the other
/// triangle, and with `heights` (the scene's height map and edge mode) its headroom
/// ([`headroom`]; 0 without). The joined walls that are not [sealed](sealed_walls) (uv
/// seams, a pole's fan) are drawn too: few, and each a second way into the shell where the
/// rasterizer and the exact crossings disagree at an edge.
///
/// Fails with a one-line error when the mesh has more triangles than a float names exactly
/// (2²⁴): the shader reads the indices as floats.
pub fn prism_walk(
    mesh: &Mesh,
    base: &[MeshVertex],
    heights: Option<(&HeightMap, EdgeMode)>,
) -> Result<PrismWalk, String> {
    const EXACT: usize = 1 << 24;
    if mesh.triangles.len() > EXACT {
        return Err(format!(
            "mesh `{}` has {} triangles; the prism walk names at most 2^24 (use the unwalked draw)",
            mesh.name,
            mesh.triangles.len()
        ));
    }
    let (mut vertices, _) = prism_vertices(mesh, base);
    let across = joined_walls(mesh);
    let sealed = sealed_walls(mesh);
    let mut indices = Vec::with_capacity(mesh.triangles.len() * 9);
    let mut cells = Vec::with_capacity(mesh.triangles.len());
    for (i, t) in mesh.triangles.iter().enumerate() {
        let first = 6 * i as u32;
        for v in &mut vertices[6 * i..6 * i + 6] {
            v.prism_b[3] = i as f32;
        }
        let (top, floor) = (|k: u32| first + k % 3, |k: u32| first + 3 + k % 3);
        indices.extend([top(0), top(1), top(2)]);
        for k in 0..3u32 {
            if sealed[i] & (1 << k) == 0 {
                indices.extend([top(k), floor(k), floor(k + 1), top(k), floor(k + 1), top(k + 1)]);
            }
        }
        let (corner, normal) = (|k: usize, w: f32| corner_point(mesh, t, k, w), |k: usize| corner_normal(mesh, t, k));
        let uv = t.map(|k| mesh.uvs[k as usize]);
        let next = |k: usize| across[i][k].map_or(-1.0, |j| j as f32);
        let room = heights.map_or(0.0, |(map, edge)| headroom(map, edge, uv));
        let scale = |k: usize| [base[t[k] as usize].uv[2], base[t[k] as usize].uv[3]];
        cells.push(PrismCell {
            p0: corner(0, next(0)),
            p1: corner(1, next(1)),
            p2: corner(2, next(2)),
            n0: normal(0),
            n1: normal(1),
            n2: normal(2),
            uv01: [uv[0].x, uv[0].y, uv[1].x, uv[1].y],
            uv2: [uv[2].x, uv[2].y, room, 0.0],
            t0: base[t[0] as usize].tangent,
            t1: base[t[1] as usize].tangent,
            t2: base[t[2] as usize].tangent,
            scale01: [scale(0)[0], scale(0)[1], scale(1)[0], scale(1)[1]],
            scale2: [scale(2)[0], scale(2)[1], 0.0, 0.0],
        });
    }
    Ok(PrismWalk { vertices, indices, cells })
}

/// Corner `k`'s point of triangle `t`, with `w` for the fourth component.
fn corner_point(mesh: &Mesh, t: &[u32; 3], k: usize, w: f32) -> [f32; 4] {
    let p = mesh.positions[t[k] as usize];
    [p.x, p.y, p.z, w]
}

/// Corner `k`'s normal of triangle `t`, 0 for the fourth component.
fn corner_normal(mesh: &Mesh, t: &[u32; 3], k: usize) -> [f32; 4] {
    let n = mesh.normals[t[k] as usize];
    [n.x, n.y, n.z, 0.0]
}

/// The prism walk's draw and buffer ([`prism_walk`]).
pub struct PrismWalk {
    /// The prisms' vertices ([`prism_vertices`]'s, `prism_b.w` the triangle's index).
    pub vertices: Vec<MeshVertex>,
    /// The faces drawn: the tops and the unsealed walls.
    pub indices: Vec<u32>,
    /// One record per triangle.
    pub cells: Vec<PrismCell>,
}

/// A prism's headroom for the walk's skip (relief-dsl's `PrismCell::uv2`): 1 minus the
/// largest texel of `map` that a bilinear read (texel centres at half-integers, `edge`'s
/// wrap or clamp) anywhere in the triangle with texture coordinates `uv` blends. A read at
/// `uv` blends texels `⌊uv·size − ½⌋` and the next along each axis, so a texel counts where
/// its support square (one texel each way from its centre) meets the triangle (`touches`),
/// within the box of the triangle's uv widened by one more texel each way. A box that wraps
/// to the whole map or reaches past a clamped border takes every texel in it.
pub fn headroom(map: &HeightMap, edge: EdgeMode, uv: [glam::Vec2; 3]) -> f32 {
    if !uv.iter().all(|p| p.is_finite() && p.abs().max_element() < 1e9) {
        return 0.0;
    }
    // Each axis's texel range, and whether it is the triangle's own (not wrapped to the whole
    // map, not clamped to the border).
    let span = |a: f32, b: f32, c: f32, n: usize| {
        let lo = (a.min(b).min(c) as f64 * n as f64 - 0.5).floor() as i64 - 1;
        let hi = (a.max(b).max(c) as f64 * n as f64 - 0.5).floor() as i64 + 2;
        let last = n as i64 - 1;
        let range = match edge {
            // Any n consecutive texels are the whole map.
            EdgeMode::Repeat => (lo, hi.min(lo + last)),
            EdgeMode::Clamp => (lo.clamp(0, last), hi.clamp(0, last)),
        };
        (range, range == (lo, hi))
    };
    let ((x0, x1), own_x) = span(uv[0].x, uv[1].x, uv[2].x, map.width);
    let ((y0, y1), own_y) = span(uv[0].y, uv[1].y, uv[2].y, map.height);
    // The triangle in texel coordinates (texel (x, y)'s centre at (x, y)); texel (x, y)
    // weighs in a bilinear read only inside the square (x ± 1, y ± 1). Where the range is
    // not the triangle's own (wrapped or clamped), every texel in it counts.
    let g = uv.map(|p| glam::DVec2::new(p.x as f64 * map.width as f64 - 0.5, p.y as f64 * map.height as f64 - 0.5));
    let whole = !(own_x && own_y);
    let mut top = f32::NEG_INFINITY;
    for y in y0..=y1 {
        for x in x0..=x1 {
            if whole || touches(g, glam::DVec2::new(x as f64, y as f64)) {
                top = top.max(map.texel(x, y, edge));
            }
        }
    }
    // A range always holds a texel whose square meets the triangle; 0 (no skip) otherwise.
    if top == f32::NEG_INFINITY {
        return 0.0;
    }
    (1.0 - top).max(0.0)
}

/// Whether the triangle `g` (texel coordinates) meets the square of half-width
/// 1 + [`TOUCH_SLACK`] around `c`: no separating axis among the square's two and the
/// triangle's three edge normals.
fn touches(g: [glam::DVec2; 3], c: glam::DVec2) -> bool {
    let half = 1.0 + TOUCH_SLACK;
    let mut axes = vec![glam::DVec2::X, glam::DVec2::Y];
    axes.extend((0..3).map(|k| (g[(k + 1) % 3] - g[k]).perp()));
    axes.iter().all(|&a| {
        let reach = half * (a.x.abs() + a.y.abs());
        let (lo, hi) = g
            .iter()
            .map(|p| (*p - c).dot(a))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), d| (l.min(d), h.max(d)));
        lo <= reach && hi >= -reach
    })
}

/// How far (texels) beyond a texel's support square [`headroom`] still counts a triangle as
/// touching it: the prism's crossings may lie outside the triangle by 1e-5 in barycentrics and
/// the search's hit 1e-4 of the chord past the exit, both below 1e-3 texels on triangles a
/// few hundred texels wide; 0.01 texels is ten times that.
const TOUCH_SLACK: f64 = 0.01;

/// Per triangle, the triangle across each of its side walls where the two prisms share the
/// wall, `None` elsewhere: the wall over the edge from corner k to corner k + 1 (mod 3) is
/// *joined* where exactly one other triangle has an edge whose ends carry the same points and
/// normals (`weld`; the uvs may differ, as across a uv seam or in a pole's fan). The two
/// prisms' walls are then one ruled surface (a wall depends on its ends' points and normals
/// only), so a ray leaving one prism through it enters the other. A walk recomputes each
/// prism's chord from that prism's own corners, so a seam's jump in uv does not matter to it.
/// Sealed walls ([`sealed_walls`], the uvs equal too) are joined; an open boundary, a crease
/// (normals differ) or an edge of three or more triangles is not.
pub fn joined_walls(mesh: &Mesh) -> Vec<[Option<u32>; 3]> {
    let id = weld(mesh);
    let key = |t: &[u32; 3], k: usize| {
        let (a, b) = (id[t[k] as usize], id[t[(k + 1) % 3] as usize]);
        (a.min(b), a.max(b))
    };
    let mut owners = std::collections::HashMap::<(u32, u32), Vec<u32>>::new();
    for (i, t) in mesh.triangles.iter().enumerate() {
        for k in 0..3 {
            owners.entry(key(t, k)).or_default().push(i as u32);
        }
    }
    mesh.triangles
        .iter()
        .enumerate()
        .map(|(i, t)| {
            [0, 1, 2].map(|k| match owners[&key(t, k)].as_slice() {
                [a, b] if *a == i as u32 => Some(*b),
                [a, b] if *b == i as u32 => Some(*a),
                _ => None,
            })
        })
        .collect()
}

/// How far apart (object units, per unit of the mesh's largest coordinate) two vertices'
/// points, and their unit normals, may lie and still be one vertex to [`joined_walls`]: the
/// built-in meshes make a seam's two columns from angles 0 and 2π, whose f32 sines and
/// cosines differ by ~2e-7, and a pole's vertices with ±0; 1e-5 joins those, and is a
/// tenth of a thousandth of the smallest relief depth the scenes use (0.01) per unit size.
const WELD: f32 = 1e-5;

/// Each vertex's representative: the first vertex (in index order) whose point and normal
/// both lie within [`WELD`] of its own in every coordinate (the points' tolerance scaled by
/// the mesh's size), found through a grid of cells [`WELD`] wide and their 27 neighbours.
fn weld(mesh: &Mesh) -> Vec<u32> {
    let size = mesh.positions.iter().fold(1.0f32, |m, p| m.max(p.abs().max_element()));
    let eps = WELD * size;
    let cell = |p: Vec3| (p / eps).floor().as_ivec3();
    let mut grid = std::collections::HashMap::<glam::IVec3, Vec<u32>>::new();
    let mut id = Vec::with_capacity(mesh.positions.len());
    for (v, (&p, &n)) in mesh.positions.iter().zip(&mesh.normals).enumerate() {
        let c = cell(p);
        let near = |r: u32| {
            let (q, m) = (mesh.positions[r as usize], mesh.normals[r as usize]);
            (q - p).abs().max_element() <= eps && (m - n).abs().max_element() <= WELD
        };
        let mut found = None;
        'search: for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    if let Some(rs) = grid.get(&(c + glam::IVec3::new(dx, dy, dz))) {
                        if let Some(&r) = rs.iter().find(|&&r| near(r)) {
                            found = Some(r);
                            break 'search;
                        }
                    }
                }
            }
        }
        let r = found.unwrap_or_else(|| {
            grid.entry(c).or_default().push(v as u32);
            v as u32
        });
        id.push(r);
    }
    id
}

/// The bit of `prism_b.z` that lets a fragment entering its prism through the floor below S
/// stop before the search (relief-dsl's `compose::mesh::early_out`).
pub const FLOOR_EARLY_OUT: u8 = 8;

/// One end of an edge as S sees it: the bits of its point, normal and uv.
type EdgeEnd = [u32; 8];

/// Per triangle, which of its three side walls are *sealed*: bit k for the wall over the edge
/// from corner k to corner k + 1 (mod 3), set where exactly two triangles of the mesh have an
/// edge whose two ends carry bitwise the same point, normal and uv as this one's (in either
/// order). There S and the prisms' map are continuous across the wall, which the early-out
/// behind the hit needs; a uv seam, a pole's fan, an open boundary or an edge of three or more
/// triangles leaves the wall unsealed.
pub fn sealed_walls(mesh: &Mesh) -> Vec<u8> {
    let mut count = std::collections::HashMap::<(EdgeEnd, EdgeEnd), u32>::new();
    for t in &mesh.triangles {
        for k in 0..3 {
            *count.entry(edge_key(mesh, t, k)).or_default() += 1;
        }
    }
    mesh.triangles
        .iter()
        .map(|t| (0..3).filter(|&k| count[&edge_key(mesh, t, k)] == 2).fold(0u8, |m, k| m | 1 << k))
        .collect()
}

/// The edge of triangle `t` from corner k to corner k + 1 (mod 3) as S sees it: its two
/// ends' bits ([`EdgeEnd`]), in either order.
fn edge_key(mesh: &Mesh, t: &[u32; 3], k: usize) -> (EdgeEnd, EdgeEnd) {
    let end = |i: u32| -> EdgeEnd {
        let (p, n, uv) = (mesh.positions[i as usize], mesh.normals[i as usize], mesh.uvs[i as usize]);
        [p.x, p.y, p.z, n.x, n.y, n.z, uv.x, uv.y].map(f32::to_bits)
    };
    let (a, b) = (end(t[k]), end(t[(k + 1) % 3]));
    if a <= b {
        (a, b)
    } else {
        (b, a)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On the built-in sphere of radius 1 (u = φ/2π·ru, v = (π − θ)/π·rv), the scales are
    /// `ru / (2π sin θ)` along T and `rv / π` along B, and the quadric's a, b are
    /// `−1 / (2 s²)` with κ = 1 (independent statements from the parametrization).
    #[test]
    fn sphere_scales_and_curvature_match_the_parametrization() {
        let (nu, nv, ru, rv) = (96, 48, 4.0f64, 2.0f64);
        let m = super::super::builtin::sphere(nu, nv, [ru as f32, rv as f32]);
        let (verts, _) = mesh_vertices(&m, Curved::Quadric);
        let pi = std::f64::consts::PI;
        let mut checked = 0;
        for (i, v) in verts.iter().enumerate() {
            let p = m.positions[i].as_dvec3();
            let sin_theta = (1.0 - p.z * p.z).max(0.0).sqrt();
            if sin_theta < 0.3 {
                continue; // near the poles a triangle's chord departs from the tangent plane
            }
            let (su, sv) = (ru / (2.0 * pi * sin_theta), rv / pi);
            // The vertex's triangles reach one row up and down, where sin θ differs by up to
            // Δθ·|cos θ| (Δθ = π/nv), and a chord of the 96-gon is sin(x)/x shorter than its arc.
            let bound_u = pi / nv as f64 * (1.0 - sin_theta * sin_theta).sqrt() / sin_theta + 1e-3;
            assert!((v.uv[2] as f64 / su - 1.0).abs() < bound_u, "su at {i}: {} vs {su}", v.uv[2]);
            assert!((v.uv[3] as f64 / sv - 1.0).abs() < 2e-3, "sv at {i}: {} vs {sv}", v.uv[3]);
            // κ = 1 in every direction: a, b are −1/(2s²) with the vertex's own scales.
            let (su, sv) = (v.uv[2] as f64, v.uv[3] as f64);
            let (a, b) = (-1.0 / (2.0 * su * su), -1.0 / (2.0 * sv * sv));
            assert!((v.curvature[0] as f64 / a - 1.0).abs() < 1e-2, "a at {i}: {} vs {a}", v.curvature[0]);
            assert!((v.curvature[1] as f64 / b - 1.0).abs() < 1e-2, "b at {i}: {} vs {b}", v.curvature[1]);
            checked += 1;
        }
        assert!(checked > 1000);
    }

    /// A torus's principal curvatures along the tube (1/r) and around z (cos ψ / (R + r cos ψ))
    /// differ, and a, b follow them with their signs (the inner equator curves the other way
    /// around z).
    #[test]
    fn torus_curvatures_follow_the_two_principal_directions() {
        let (big, small) = (1.0f64, 0.5f64);
        let m = super::super::builtin::torus(96, 48, big as f32, small as f32, [1.0, 1.0]);
        let sc = scales(&m);
        let c = curvature(&m, &sc);
        for i in 0..m.positions.len() {
            let p = m.positions[i].as_dvec3();
            let rho = (p.x * p.x + p.y * p.y).sqrt();
            let cos_psi = (rho - big) / small;
            let k_t = cos_psi / rho; // around z
            let k_b = 1.0 / small; // along the tube
            let (a, b) = (-k_t / (2.0 * sc[i][0].powi(2)), -k_b / (2.0 * sc[i][1].powi(2)));
            assert!((c[i][1] - b).abs() <= 0.01 * b.abs(), "b at {i}: {} vs {b}", c[i][1]);
            assert!((c[i][0] - a).abs() <= 0.01 * b.abs(), "a at {i}: {} vs {a}", c[i][0]);
        }
    }

    /// A prism's records: the triangle's corners at the top and the floor, its uvs in
    /// `prism_a`/`prism_b` at all six, and eight triangles covering the caps and each wall's
    /// four corners.
    #[test]
    fn a_prism_is_two_caps_and_three_walls() {
        let m = super::super::builtin::sphere(8, 4, [1.0, 1.0]);
        let (v, idx) = mesh_vertices(&m, Curved::Prism);
        assert_eq!((v.len(), idx.len()), (m.triangles.len() * 6, m.triangles.len() * 24));
        for (k, t) in m.triangles.iter().enumerate() {
            let rec = &v[k * 6..k * 6 + 6];
            for (c, r) in rec.iter().enumerate() {
                let corner = t[c % 3] as usize;
                assert_eq!(r.position[3], if c < 3 { 1.0 } else { 0.0 });
                assert_eq!(&r.position[..3], &m.positions[corner].to_array());
                let uv = t.map(|i| m.uvs[i as usize]);
                assert_eq!(r.prism_a, [uv[0].x, uv[0].y, uv[1].x, uv[1].y]);
                assert_eq!(&r.prism_b[..2], &[uv[2].x, uv[2].y]);
                for (k, (p, n)) in [(r.prism_p0, r.prism_n0), (r.prism_p1, r.prism_n1), (r.prism_p2, r.prism_n2)]
                    .into_iter()
                    .enumerate()
                {
                    let i = t[k] as usize;
                    assert_eq!((&p[..3], &n[..3]), (&m.positions[i].to_array()[..], &m.normals[i].to_array()[..]));
                }
            }
            let tri = &idx[k * 24..k * 24 + 24];
            assert!(tri.iter().all(|&i| (k * 6..k * 6 + 6).contains(&(i as usize))));
            // Each wall (corners c, c+1) uses exactly its four records.
            for c in 0..3u32 {
                let wall = &tri[6 + 6 * c as usize..12 + 6 * c as usize];
                let first = (k * 6) as u32;
                let want = [c, (c + 1) % 3, 3 + c, 3 + (c + 1) % 3].map(|x| first + x);
                assert!(wall.iter().all(|i| want.contains(i)) && want.iter().all(|i| wall.contains(i)), "{wall:?}");
            }
        }
    }

    #[test]
    fn scales_use_the_uv_map() {
        // A flat square 2 × 1 object units carrying uv [0, 1]²: 0.5 and 1 texture units per unit.
        let m = Mesh {
            name: "sq".into(),
            positions: vec![Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0), Vec3::new(2.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)],
            normals: vec![Vec3::Z; 4],
            tangents: vec![glam::Vec4::new(1.0, 0.0, 0.0, 1.0); 4],
            uvs: vec![glam::Vec2::ZERO, glam::Vec2::new(1.0, 0.0), glam::Vec2::ONE, glam::Vec2::new(0.0, 1.0)],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
        };
        let s = scales(&m);
        assert!(s.iter().all(|s| (s[0] - 0.5).abs() < 1e-12 && (s[1] - 1.0).abs() < 1e-12), "{s:?}");
    }
}
