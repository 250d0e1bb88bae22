//! The displaced surface over a mesh, and a proven box around any piece of it.
//!
//! Over a triangle, with barycentrics λ, `P = Σ λᵢ Pᵢ` and `N = Σ λᵢ Nᵢ` (the vertex normals
//! interpolated and **not** renormalized), and h the height map bilinear between texel
//! centres (the scene's edge mode):
//!
//! ```text
//! S = P − depth · (1 − h) · N
//! ```
//!
//! so h = 1 lies on the mesh and h = 0 one `depth` below it along the interpolated normal: the
//! layer of height k is the flat triangle with vertices `Pᵢ − depth·(1 − k)·Nᵢ`, the prism
//! method's texture space exactly (docs/meshes.md).
//!
//! Everything here works in *grid coordinates* `g = (u·W − ½, v·H − ½)` (W × H texels), in
//! which texel centres sit on whole numbers and the bilinear cell `(i, j)` is the unit square
//! `[i, i+1] × [j, j+1]`. A triangle's barycentrics are affine in g (its uv triangle is not
//! degenerate, `Mesh::checked`), so P and N are affine in g too.
//!
//! # The box ([`Tri::piece_box`])
//!
//! A *piece* is a convex polygon Q inside one rectangle R ⊂ cell (i, j) (the triangle clipped
//! to R). Over Q:
//! * P and N are affine, so P(Q) and N(Q) lie in the convex hulls of their values at Q's
//!   corners, hence in the boxes of those values;
//! * h restricted to R is bilinear again, a convex combination of its values at R's four
//!   corners, so h(Q) ⊂ [h_min, h_max] of those four;
//! * so `S = P + γ·N` with `γ = −depth·(1 − h) ∈ [−depth(1 − h_min), −depth(1 − h_max)]`, and
//!   each coordinate of γ·N lies in the interval product of γ's range and N's.
//!
//! The box is the sum of P's box and that product, widened by [`PAD`] for the f64 rounding
//! of its own arithmetic.

use glam::{DVec2, DVec3};

use super::Mesh;
use crate::heightmap::{EdgeMode, HeightMap};

/// The relative widening of every box: its corners are computed in f64 from a handful of
/// products and sums, each within 1e-16 relative; 1e-12 of the box's magnitude covers them
/// a thousand times.
pub const PAD: f64 = 1e-12;

/// An axis-aligned box in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// The low corner.
    pub lo: DVec3,
    /// The high corner.
    pub hi: DVec3,
}

impl Aabb {
    /// The length of the diagonal.
    pub fn diagonal(&self) -> f64 {
        (self.hi - self.lo).length()
    }

    /// Where the ray `o + s·d` (s ≥ 0) enters the box, if it meets it (slab test; a zero
    /// component of d meets the slab only from inside it).
    pub fn entry(&self, o: DVec3, d: DVec3) -> Option<f64> {
        let (mut near, mut far) = (0.0f64, f64::INFINITY);
        for k in 0..3 {
            if d[k] == 0.0 {
                if o[k] < self.lo[k] || o[k] > self.hi[k] {
                    return None;
                }
                continue;
            }
            let (a, b) = ((self.lo[k] - o[k]) / d[k], (self.hi[k] - o[k]) / d[k]);
            near = near.max(a.min(b));
            far = far.min(a.max(b));
        }
        (near <= far).then_some(near)
    }
}

/// A convex polygon in grid coordinates (at most 3 + 4 corners: a triangle clipped by a
/// rectangle).
#[derive(Clone, Copy, Debug)]
pub struct Poly {
    /// The corners, counter-clockwise or clockwise as the triangle's uvs run.
    pub v: [DVec2; 8],
    /// How many of `v` are corners.
    pub n: usize,
}

impl Poly {
    /// The triangle `a, b, c`.
    pub fn triangle(a: DVec2, b: DVec2, c: DVec2) -> Poly {
        let mut v = [DVec2::ZERO; 8];
        v[..3].copy_from_slice(&[a, b, c]);
        Poly { v, n: 3 }
    }

    /// The corners.
    pub fn corners(&self) -> &[DVec2] {
        &self.v[..self.n]
    }

    /// This polygon clipped to the rectangle `[x0, x1] × [y0, y1]` (Sutherland & Hodgman
    /// 1974, one side at a time); `None` if nothing with area is left.
    pub fn clip(&self, [x0, x1, y0, y1]: [f64; 4]) -> Option<Poly> {
        let mut p = *self;
        // Each side as (axis, bound, keep the side with coordinate >= bound?).
        for (axis, bound, above) in [(0, x0, true), (0, x1, false), (1, y0, true), (1, y1, false)] {
            let inside = |q: DVec2| if above { q[axis] >= bound } else { q[axis] <= bound };
            let mut out = Poly { v: [DVec2::ZERO; 8], n: 0 };
            for k in 0..p.n {
                let (a, b) = (p.v[k], p.v[(k + 1) % p.n]);
                let (ia, ib) = (inside(a), inside(b));
                if ia {
                    out.push(a);
                }
                if ia != ib {
                    let s = (bound - a[axis]) / (b[axis] - a[axis]);
                    let mut q = a + (b - a) * s;
                    q[axis] = bound; // exactly on the side
                    out.push(q);
                }
            }
            if out.n < 3 {
                return None;
            }
            p = out;
        }
        (p.area() > 0.0).then_some(p)
    }

    fn push(&mut self, q: DVec2) {
        // A convex polygon clipped by four sides has at most 7 corners; 8 slots are enough.
        if self.n < self.v.len() {
            self.v[self.n] = q;
            self.n += 1;
        }
    }

    /// The area (shoelace formula), unsigned.
    pub fn area(&self) -> f64 {
        let c = self.corners();
        let mut a = 0.0;
        for k in 0..c.len() {
            a += c[k].perp_dot(c[(k + 1) % c.len()]);
        }
        0.5 * a.abs()
    }
}

/// One triangle of the mesh prepared for the surface: P and N as affine functions of the grid
/// coordinates.
#[derive(Clone, Copy, Debug)]
pub struct Tri {
    /// The grid coordinates of the three vertices.
    pub g: [DVec2; 3],
    p0: DVec3,
    p_dx: DVec3,
    p_dy: DVec3,
    n0: DVec3,
    n_dx: DVec3,
    n_dy: DVec3,
}

impl Tri {
    /// Triangle `t` of `mesh` on a `size = [W, H]` texel map.
    pub fn new(mesh: &Mesh, t: [u32; 3], size: [usize; 2]) -> Tri {
        let [a, b, c] = t.map(|i| i as usize);
        let grid = |i: usize| {
            let uv = mesh.uvs[i].as_dvec2();
            DVec2::new(uv.x * size[0] as f64 - 0.5, uv.y * size[1] as f64 - 0.5)
        };
        let g = [grid(a), grid(b), grid(c)];
        let (e1, e2) = (g[1] - g[0], g[2] - g[0]);
        let det = e1.perp_dot(e2);
        // λ1 and λ2 as functions of g: their gradients are the rows of the inverse of [e1 e2].
        let l1 = DVec2::new(e2.y, -e2.x) / det;
        let l2 = DVec2::new(-e1.y, e1.x) / det;
        let affine = |v: [DVec3; 3]| {
            let (d1, d2) = (v[1] - v[0], v[2] - v[0]);
            (v[0], d1 * l1.x + d2 * l2.x, d1 * l1.y + d2 * l2.y)
        };
        let (p0, p_dx, p_dy) = affine([a, b, c].map(|i| mesh.positions[i].as_dvec3()));
        let (n0, n_dx, n_dy) = affine([a, b, c].map(|i| mesh.normals[i].as_dvec3()));
        Tri { g, p0, p_dx, p_dy, n0, n_dx, n_dy }
    }

    /// The interpolated position at grid point `q`.
    pub fn position(&self, q: DVec2) -> DVec3 {
        let d = q - self.g[0];
        self.p0 + self.p_dx * d.x + self.p_dy * d.y
    }

    /// The interpolated (not renormalized) normal at grid point `q`.
    pub fn normal(&self, q: DVec2) -> DVec3 {
        let d = q - self.g[0];
        self.n0 + self.n_dx * d.x + self.n_dy * d.y
    }

    /// The grid rectangle holding the triangle's cells: `[i0, i1] × [j0, j1]` (inclusive).
    pub fn cells(&self) -> [i64; 4] {
        let lo = self.g[0].min(self.g[1]).min(self.g[2]);
        let hi = self.g[0].max(self.g[1]).max(self.g[2]);
        [lo.x.floor() as i64, hi.x.floor() as i64, lo.y.floor() as i64, hi.y.floor() as i64]
    }

    /// A proven box around S over the piece `poly` ⊂ `rect` ⊂ cell `(i, j)` (module docs).
    pub fn piece_box(&self, cell: &Cell, rect: [f64; 4], poly: &Poly, depth: f64) -> Aabb {
        let (mut plo, mut phi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        let (mut nlo, mut nhi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for &q in poly.corners() {
            let (p, n) = (self.position(q), self.normal(q));
            (plo, phi) = (plo.min(p), phi.max(p));
            (nlo, nhi) = (nlo.min(n), nhi.max(n));
        }
        let [x0, x1, y0, y1] = rect;
        let hs = [cell.h(x0, y0), cell.h(x1, y0), cell.h(x0, y1), cell.h(x1, y1)];
        let (hmin, hmax) =
            (hs.iter().copied().fold(f64::INFINITY, f64::min), hs.iter().copied().fold(f64::NEG_INFINITY, f64::max));
        let (glo, ghi) = (-depth * (1.0 - hmin), -depth * (1.0 - hmax));
        let mut lo = plo;
        let mut hi = phi;
        for k in 0..3 {
            let prods = [glo * nlo[k], glo * nhi[k], ghi * nlo[k], ghi * nhi[k]];
            lo[k] += prods.iter().copied().fold(f64::INFINITY, f64::min);
            hi[k] += prods.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        }
        let pad = PAD * (lo.abs().max(hi.abs()).max_element() + depth + 1.0);
        Aabb { lo: lo - pad, hi: hi + pad }
    }

    /// The surface point over grid point `q` of cell `cell`.
    pub fn surface(&self, cell: &Cell, q: DVec2, depth: f64) -> DVec3 {
        self.position(q) - depth * (1.0 - cell.h(q.x, q.y)) * self.normal(q)
    }
}

/// One bilinear cell: its corner heights.
#[derive(Clone, Copy, Debug)]
pub struct Cell {
    /// The cell's low corner in grid coordinates (texel `(i, j)`'s centre).
    pub i: i64,
    /// See `i`.
    pub j: i64,
    h00: f64,
    h10: f64,
    h01: f64,
    h11: f64,
}

impl Cell {
    /// Cell `(i, j)` of `map` with `edge`.
    pub fn new(map: &HeightMap, edge: EdgeMode, i: i64, j: i64) -> Cell {
        let t = |x: i64, y: i64| map.texel(x, y, edge) as f64;
        Cell { i, j, h00: t(i, j), h10: t(i + 1, j), h01: t(i, j + 1), h11: t(i + 1, j + 1) }
    }

    /// The bilinear height at grid point (x, y) of this cell.
    pub fn h(&self, x: f64, y: f64) -> f64 {
        let (fx, fy) = (x - self.i as f64, y - self.j as f64);
        let a = self.h00 + (self.h10 - self.h00) * fx;
        let b = self.h01 + (self.h11 - self.h01) * fx;
        a + (b - a) * fy
    }

    /// The cell's square in grid coordinates, `[x0, x1, y0, y1]`.
    pub fn rect(&self) -> [f64; 4] {
        [self.i as f64, self.i as f64 + 1.0, self.j as f64, self.j as f64 + 1.0]
    }
}
