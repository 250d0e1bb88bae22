//! The exact first hit of a ray with the displaced surface over a mesh ([`super::surface`]),
//! on the CPU.
//!
//! # Method
//!
//! 1. **Patches.** Each triangle is cut by the bilinear cells of the height map into patches
//!    (the triangle's uv image clipped to one cell): over a patch P and N are affine and h is
//!    one bilinear function, so [`Tri::piece_box`] gives a proven box around S over it.
//! 2. **BVH.** The patches' boxes (rounded outwards to f32 and widened by [`BVH_PAD`]) go into
//!    a BVH (`obvhs`, Griffin's PLOC builder). A closest-hit traversal visits every patch whose
//!    box the ray enters before the best hit found so far, so no patch that could hold an
//!    earlier hit is passed over.
//! 3. **Branch and bound in a patch.** The patch is refined by halving its cell rectangle
//!    (four quadrants, the triangle clipped again to each), best first by where the ray enters
//!    each piece's box. A piece whose box the ray misses, or enters after the best hit, cannot
//!    hold an earlier hit and is dropped; nothing else is.
//! 4. **Leaves.** A piece whose box's diagonal is at most the tolerance ε
//!    ([`MeshReference::tolerance`]) is replaced by the triangles fanned from S at its corners
//!    (points of S itself), which lie inside its box; the ray's first hit with them is the
//!    piece's hit.
//!
//! The result is the exact first hit of a surface that lies within ε of S everywhere (each
//! leaf triangle lies in a box of diagonal ≤ ε that holds the leaf's piece of S), in f64:
//! the hit point is within ε of S, and a ray that meets S but none of the leaf triangles (or
//! the reverse) passes within ε of S's silhouette or tangent to it. docs/meshes.md states it.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::surface::{Cell, Poly, Tri};
use super::Mesh;
use crate::heightmap::{EdgeMode, HeightMap};

/// The most patches (triangle ∩ cell) a reference is built over: a mesh whose uvs cross more
/// cells is refused before the patches are made.
pub const MAX_PATCHES: usize = 1 << 24;

/// The widening of the BVH's f32 boxes, relative to the mesh's extent (radius + depth + 1):
/// the f32 slab test of the traversal errs by a few units in the last place (1e-7 relative)
/// of coordinates and distances of the size of the scene; 1e-5 covers that for eyes up to a
/// hundred scene radii away.
pub const BVH_PAD: f64 = 1e-5;

/// The most halvings of a patch's rectangle; a leaf that deep is taken even if its box is
/// larger than ε (it is not, for finite data: the box shrinks with the rectangle).
const MAX_LEVELS: u32 = 48;

/// A first hit on the displaced surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshHit {
    /// Distance from the ray's origin along its unit direction (world units).
    pub t: f64,
    /// The hit's texture coordinates (as the mesh's uvs: tiling applied, not wrapped).
    pub u: f64,
    /// See `u`.
    pub v: f64,
    /// The triangle hit (index into `Mesh::triangles`).
    pub triangle: u32,
    /// The hit point, world space.
    pub point: [f64; 3],
}

/// A patch: triangle `tri` clipped to cell `(i, j)`.
#[derive(Clone, Copy, Debug)]
struct Patch {
    tri: u32,
    i: i64,
    j: i64,
}

struct BoxOf(obvhs::aabb::Aabb);

impl obvhs::Boundable for BoxOf {
    fn aabb(&self) -> obvhs::aabb::Aabb {
        self.0
    }
}

/// A mesh, a height map and a depth prepared for exact ray queries.
pub struct MeshReference {
    tris: Vec<Tri>,
    patches: Vec<Patch>,
    bvh: obvhs::bvh2::Bvh2,
    map: HeightMap,
    edge: EdgeMode,
    depth: f64,
    size: [usize; 2],
    eps: f64,
}

impl MeshReference {
    /// Prepares `mesh` (checked: no degenerate triangle, see `Mesh::checked`) with `map`
    /// (`edge`) displaced `depth` world units inwards. An error if the patches would exceed
    /// [`MAX_PATCHES`] or the map is empty.
    pub fn new(mesh: &Mesh, map: &HeightMap, edge: EdgeMode, depth: f64) -> Result<MeshReference, String> {
        let size = [map.width, map.height];
        if map.width == 0 || map.height == 0 {
            return Err("the height map has no texels".into());
        }
        if mesh.triangles.is_empty() {
            return Err("the mesh has no triangles".into());
        }
        let tris: Vec<Tri> = mesh.triangles.iter().map(|&t| Tri::new(mesh, t, size)).collect();
        let mut cells = 0usize;
        for t in &tris {
            let [i0, i1, j0, j1] = t.cells();
            let n = ((i1 - i0 + 1) as f64) * ((j1 - j0 + 1) as f64);
            cells = cells.saturating_add(if n.is_finite() { n.min(usize::MAX as f64) as usize } else { usize::MAX });
            if cells > MAX_PATCHES {
                return Err(format!("the mesh's uvs cross more than {MAX_PATCHES} texel cells"));
            }
        }
        let (centre, radius) = mesh.bounds();
        let extent = centre.as_dvec3().abs().max_element() + radius as f64 + depth + 1.0;
        let pad = BVH_PAD * extent;
        let mut patches = Vec::new();
        let mut boxes = Vec::new();
        for (k, t) in tris.iter().enumerate() {
            let [i0, i1, j0, j1] = t.cells();
            let whole = Poly::triangle(t.g[0], t.g[1], t.g[2]);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    let cell = Cell::new(map, edge, i, j);
                    let Some(poly) = whole.clip(cell.rect()) else { continue };
                    let b = t.piece_box(&cell, cell.rect(), &poly, depth);
                    let lo = (b.lo - pad).as_vec3();
                    let hi = (b.hi + pad).as_vec3();
                    boxes.push(BoxOf(obvhs::aabb::Aabb::new(
                        glam_bvh::Vec3A::from_array(lo.to_array()),
                        glam_bvh::Vec3A::from_array(hi.to_array()),
                    )));
                    patches.push(Patch { tri: k as u32, i, j });
                }
            }
        }
        let bvh = obvhs::bvh2::builder::build_bvh2(
            &boxes,
            obvhs::BvhBuildParams::medium_build(),
            &mut std::time::Duration::default(),
        );
        let eps = MeshReference::default_tolerance(mesh, depth);
        Ok(MeshReference { tris, patches, bvh, map: map.clone(), edge, depth, size, eps })
    }

    /// The tolerance ε a reference over `mesh` with relief `depth` takes unless
    /// [`MeshReference::with_tolerance`] sets it: 1e-6 of the mesh's radius plus the depth.
    pub fn default_tolerance(mesh: &Mesh, depth: f64) -> f64 {
        1e-6 * (mesh.bounds().1 as f64 + depth)
    }

    /// The same reference with leaves of box diagonal at most `eps` (world units).
    pub fn with_tolerance(mut self, eps: f64) -> MeshReference {
        self.eps = eps;
        self
    }

    /// ε, the largest box diagonal of a leaf (world units): 1e-6 of the mesh's radius plus
    /// the depth unless [`MeshReference::with_tolerance`] set it.
    pub fn tolerance(&self) -> f64 {
        self.eps
    }

    /// The number of patches (triangle ∩ cell).
    pub fn patch_count(&self) -> usize {
        self.patches.len()
    }

    /// The first hit of the ray `origin + t·dir` (t ≥ 0; `dir` need not be unit: t is in its
    /// units), or `None` (the ray misses: the silhouette). A non-finite ray misses.
    pub fn first_hit(&self, origin: [f32; 3], dir: [f32; 3]) -> Option<MeshHit> {
        let finite = origin.iter().chain(dir.iter()).all(|c| c.is_finite());
        if !finite || dir == [0.0; 3] {
            return None;
        }
        let (o, d) = (glam::Vec3::from(origin).as_dvec3(), glam::Vec3::from(dir).as_dvec3());
        let ray = obvhs::ray::Ray::new_inf(glam_bvh::Vec3A::from_array(origin), glam_bvh::Vec3A::from_array(dir));
        let mut best: Option<MeshHit> = None;
        let mut hit = obvhs::ray::RayHit::none();
        self.bvh.ray_traverse(ray, &mut hit, |_, id| {
            let p = self.patches[self.bvh.primitive_indices[id] as usize];
            let bound = best.map_or(f64::INFINITY, |b| b.t);
            match self.patch_hit(p, o, d, bound) {
                Some(h) => {
                    best = Some(h);
                    round_up(h.t)
                }
                None => f32::INFINITY,
            }
        });
        best
    }

    /// The first hit in patch `p` before `bound` (Method, steps 3 and 4).
    fn patch_hit(&self, p: Patch, o: DVec3, d: DVec3, bound: f64) -> Option<MeshHit> {
        let tri = &self.tris[p.tri as usize];
        let cell = Cell::new(&self.map, self.edge, p.i, p.j);
        let poly = Poly::triangle(tri.g[0], tri.g[1], tri.g[2]).clip(cell.rect())?;
        let mut best_t = bound;
        let mut found: Option<(f64, DVec2, DVec3)> = None;
        let mut heap = BinaryHeap::new();
        let push = |heap: &mut BinaryHeap<Piece>, rect: [f64; 4], poly: Poly, level: u32, best_t: f64| {
            let b = tri.piece_box(&cell, rect, &poly, self.depth);
            if let Some(entry) = b.entry(o, d) {
                if entry < best_t {
                    heap.push(Piece { entry, rect, poly, level, diag: b.diagonal() });
                }
            }
        };
        push(&mut heap, cell.rect(), poly, 0, best_t);
        while let Some(pc) = heap.pop() {
            if pc.entry >= best_t {
                break; // every piece left starts later
            }
            if pc.diag <= self.eps || pc.level >= MAX_LEVELS {
                if let Some((t, q, x)) = self.leaf_hit(tri, &cell, &pc.poly, o, d) {
                    if t < best_t {
                        best_t = t;
                        found = Some((t, q, x));
                    }
                }
                continue;
            }
            let [x0, x1, y0, y1] = pc.rect;
            let (xm, ym) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
            for r in [[x0, xm, y0, ym], [xm, x1, y0, ym], [x0, xm, ym, y1], [xm, x1, ym, y1]] {
                if let Some(q) = pc.poly.clip(r) {
                    push(&mut heap, r, q, pc.level + 1, best_t);
                }
            }
        }
        let (t, q, x) = found?;
        Some(MeshHit {
            t,
            u: (q.x + 0.5) / self.size[0] as f64,
            v: (q.y + 0.5) / self.size[1] as f64,
            triangle: p.tri,
            point: x.to_array(),
        })
    }

    /// The ray's first hit with the triangles fanned from S at the leaf's corners: `(t, grid
    /// point, world point)`.
    fn leaf_hit(&self, tri: &Tri, cell: &Cell, poly: &Poly, o: DVec3, d: DVec3) -> Option<(f64, DVec2, DVec3)> {
        let c = poly.corners();
        let s: Vec<DVec3> = c.iter().map(|&q| tri.surface(cell, q, self.depth)).collect();
        let mut best: Option<(f64, DVec2, DVec3)> = None;
        for k in 1..c.len() - 1 {
            if let Some((t, b1, b2)) = ray_triangle(o, d, s[0], s[k], s[k + 1]) {
                if best.is_none_or(|b| t < b.0) {
                    let q = c[0] + (c[k] - c[0]) * b1 + (c[k + 1] - c[0]) * b2;
                    best = Some((t, q, o + d * t));
                }
            }
        }
        best
    }

    /// [`MeshReference::first_hit`] for every ray, in parallel (rayon), in input order.
    pub fn trace_all(&self, rays: &[super::MeshRay]) -> Vec<Option<MeshHit>> {
        rays.par_iter().map(|r| self.first_hit(r.origin, r.dir)).collect()
    }
}

/// A piece waiting in the branch and bound, ordered so that the heap pops the earliest entry.
struct Piece {
    entry: f64,
    rect: [f64; 4],
    poly: Poly,
    level: u32,
    diag: f64,
}

impl PartialEq for Piece {
    fn eq(&self, o: &Self) -> bool {
        self.entry.total_cmp(&o.entry) == Ordering::Equal
    }
}
impl Eq for Piece {}
impl PartialOrd for Piece {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Piece {
    fn cmp(&self, o: &Self) -> Ordering {
        o.entry.total_cmp(&self.entry) // reversed: BinaryHeap is a max-heap
    }
}

/// `t` as an f32 no smaller than it, for the BVH's f32 bound.
fn round_up(t: f64) -> f32 {
    let f = t as f32;
    if (f as f64) < t {
        f.next_up()
    } else {
        f
    }
}

/// The ray `o + t·d` (t ≥ 0) against the triangle `a, b, c`, either side (Möller & Trumbore
/// 1997): `(t, b1, b2)` with the hit at `a + b1·(b − a) + b2·(c − a)`. Edges and corners count
/// (a tolerance of 1e-12 in the barycentrics), so that a ray through the shared edge of two
/// fan triangles is not lost between them.
pub(crate) fn ray_triangle(o: DVec3, d: DVec3, a: DVec3, b: DVec3, c: DVec3) -> Option<(f64, f64, f64)> {
    const SLACK: f64 = 1e-12;
    let (e1, e2) = (b - a, c - a);
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let s = o - a;
    let b1 = s.dot(p) / det;
    if !(-SLACK..=1.0 + SLACK).contains(&b1) {
        return None;
    }
    let q = s.cross(e1);
    let b2 = d.dot(q) / det;
    if b2 < -SLACK || b1 + b2 > 1.0 + SLACK {
        return None;
    }
    let t = e2.dot(q) / det;
    (t >= 0.0).then_some((t, b1, b2))
}
