//! How many fragments a mesh module's draw runs per pixel, counted on the CPU (issue 38, the
//! price of `curved=prism`; docs/notes/meshes.md "The price of prism").
//!
//! A rasterizer runs one fragment of a triangle at a pixel when the pixel's centre lies inside
//! the triangle's projection in front of the eye and the triangle is not culled; that is when
//! the pixel-centre ray from the eye meets the triangle at t ≥ 0. So the count here is, per
//! pixel, the triangles of the draw ([`super::vertices::mesh_vertices`], the vertices placed
//! as the vertex entry places them) that its ray meets, the culled ones left out: `prism`'s
//! back faces (the runtime culls them, `gpu::mesh`), none under `none` and `quadric` (drawn
//! with both faces). Every such fragment runs the whole trace: the module writes the depth,
//! so no depth test can stop it before its shader has run. The emulation counts a ray through
//! a shared edge for both triangles, where a rasterizer's tie rule gives it to one: pixel
//! centres on an edge are rare, and the count may exceed the rasterizer's by those.

use glam::DVec3;
use relief_dsl::compose::mesh::MeshVertex;
use relief_dsl::spec::Curved;

use super::reference::ray_triangle;
use super::{MeshHit, MeshScene};

/// The fragment counts of one draw of a `size × size` frame ([`fragment_counts`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FragmentCount {
    /// Pixels with at least one fragment.
    pub drawn: usize,
    /// Fragments in all.
    pub fragments: usize,
    /// Pixels the exact reference covers, and the fragments run on those.
    pub covered: usize,
    /// See `covered`.
    pub on_covered: usize,
    /// Of `on_covered`, the fragments whose face the ray meets before the reference's hit
    /// (the others lie behind it: their answers are occluded whatever they trace).
    pub before_hit: usize,
    /// Fragments of `prism`'s floor faces (the ray enters the prism from below its floor).
    pub floors: usize,
    /// The most fragments at one pixel.
    pub most: usize,
}

impl FragmentCount {
    /// Fragments per pixel the reference covers (NaN when it covers none).
    pub fn per_covered(&self) -> f64 {
        self.on_covered as f64 / self.covered as f64
    }
}

/// The draw's triangles as the vertex entry places them: object-space corners, the prism's
/// floor corners `depth` below the surface along the vertex normal, in f32 as the shader
/// computes them.
fn placed_triangles(ms: &MeshScene, curved: Curved) -> Vec<[DVec3; 3]> {
    let (vertices, indices) = super::vertices::mesh_vertices(&ms.mesh, curved);
    let depth = ms.scene.depth_scale;
    let place = |v: &MeshVertex| {
        let (p, n) = (v.position, v.normal);
        let k = (1.0 - p[3]) * depth;
        DVec3::new((p[0] - n[0] * k) as f64, (p[1] - n[1] * k) as f64, (p[2] - n[2] * k) as f64)
    };
    indices.chunks_exact(3).map(|f| [f[0], f[1], f[2]].map(|k| place(&vertices[k as usize]))).collect()
}

/// Per pixel of a `size × size` frame of `ms` drawn under `curved` (row major), the draw's
/// fragments there (the module doc): each as the index of its triangle in the draw's index
/// list (a prism's eight: the top, the floor, then two per wall) and the distance along the
/// pixel's unit ray at which the ray meets it.
pub fn fragments_per_pixel(ms: &MeshScene, curved: Curved, size: u32) -> Vec<Vec<(usize, f64)>> {
    let triangles = placed_triangles(ms, curved);
    let cull = curved == Curved::Prism;
    ms.rays(size, size)
        .iter()
        .map(|ray| {
            let o = DVec3::from(ray.origin.map(|c| c as f64));
            let d = DVec3::from(ray.dir.map(|c| c as f64));
            let mut out = Vec::new();
            for (k, [a, b, c]) in triangles.iter().enumerate() {
                // Wound counter-clockwise seen from outside: the cross product points out.
                if cull && (*b - *a).cross(*c - *a).dot(d) >= 0.0 {
                    continue;
                }
                if let Some((t, _, _)) = ray_triangle(o, d, *a, *b, *c) {
                    out.push((k, t * d.length()));
                }
            }
            out
        })
        .collect()
}

/// [`fragments_per_pixel`] summed ([`FragmentCount`]); `reference` (the exact first hits of
/// the same frame, row major) says which pixels are covered and where their hits lie.
pub fn fragment_counts(ms: &MeshScene, curved: Curved, size: u32, reference: &[Option<MeshHit>]) -> FragmentCount {
    let prism = curved == Curved::Prism;
    let mut out = FragmentCount::default();
    for (i, frags) in fragments_per_pixel(ms, curved, size).iter().enumerate() {
        let n = frags.len();
        let hit = reference.get(i).copied().flatten();
        out.drawn += usize::from(n > 0);
        out.fragments += n;
        out.most = out.most.max(n);
        out.floors += frags.iter().filter(|(k, _)| prism && k % 8 == 1).count();
        if let Some(h) = hit {
            out.covered += 1;
            out.on_covered += n;
            out.before_hit += frags.iter().filter(|(_, t)| *t < h.t).count();
        }
    }
    out
}
