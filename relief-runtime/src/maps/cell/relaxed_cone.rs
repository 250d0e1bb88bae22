//! `cell_relaxed_cone`: a relaxed cone per bilinear cell with a rule that is provably safe
//! (the relaxed cones of Policarpo & Oliveira 2007, GPU Gems 3 ch. 18.4.1, on cells;
//! grid and per-cell bound: [`super`]).
//!
//! # Channels
//!
//! 2 per cell: channel 0 the relaxed ratio `R_C`, channel 1 the apex `A_C` (largest corner).
//! The cone is `K = {(y, z) : z ≥ A_C + dist(y, C) / R_C}`.
//!
//! # The guarantee
//!
//! Let a ray start at a point `p = (y0, z0)` with `y0 ∈ C`, `A_C ≤ z0 ≤ 1`, with a
//! non-increasing height along it (any horizontal direction). Let `[0, t_K]` be the part of
//! the ray inside `K` (it is one interval: from a point of `C`, `dist(y(t), C)` never
//! decreases, and `z(t)` never increases). Then `g(t) = z(t) − S(y(t))` changes sign at most
//! once on `[0, t_K]` (from `+` to `−`): so if the ray is above the surface at `p` and below
//! it at `t_K`, the first crossing is the only one in between and a binary search on
//! `[0, t_K]` finds it.
//!
//! # The rule
//!
//! Call a cell `D` **rising from `C`** when
//!
//! ```text
//! ∇S(y) · (y − c) ≥ 0      for every y in D and every c in C,
//! ```
//!
//! i.e. the surface in `D` does not descend in any direction a ray from `C` can cross `D` in.
//! `∇S · (y − c)` is linear in `c` and, on a bilinear patch, bilinear in `y` (`∂S/∂X` is
//! linear in `Y` alone, `∂S/∂Y` in `X` alone), so the condition holds iff it holds for the
//! 4 × 4 pairs of corners of `D` and `C` ([`rising`]); the products are of f32 height
//! differences and multiples of ½, exact in f64, so the test is decided exactly. Then
//!
//! ```text
//! R_C = max( R_cons, min( cap, min over cells D not rising from C of piece_ratio(A_C, +inf, 0, D) ) )
//! ```
//!
//! where `R_cons` is the `cell_cone` ratio (which alone makes `g > 0` on `K`) and `cap` is
//! `+inf` for clamp and `G / (1 − A_C)` for repeat with `G = min((w − 1)/w, (h − 1)/h)`: the
//! points of `K` below height 1 are within `G` of `C`, so they lie in the cells of plane
//! offset `|k| ≤ n − 1` that the minimum runs over (farther copies are not rising in general,
//! and are not searched).
//!
//! *Proof.* If `R_C = R_cons`, `g ≥ 0` on `K` by the conservative bound (no sign change).
//! Otherwise take `t1` with `g(t1) < 0`. Every point of the ray in `K` with `g < 0` has
//! `S(y) > z ≥ A_C + dist(y, C)/R_C`, so its cell `D` is not certified by `piece_ratio` at
//! `R_C` (that certificate gives `S ≤ A_C + dist/R_C` on all of `D`, and `R_C` is at most
//! every non-rising cell's value), hence `D` is rising from `C`. There, with `d` the ray's
//! horizontal direction, `y − y0 = τ d` with `τ > 0` and `y0 ∈ C`, so `∇S · d ≥ 0`:
//! `S` does not decrease along the ray while `z` does not increase, so `g' ≤ 0` wherever
//! `g < 0` (at cell edges, one-sided; `g` is Lipschitz). If `g` became `≥ 0` again at some
//! `t2 > t1` inside `K`, at the first such `t*` we would have `g < 0` on `[t1, t*)` with
//! `g' ≤ 0`, so `g(t*) ≤ g(t1) < 0`, a contradiction. Smaller `R` keeps the property (the
//! inside of a smaller cone is a prefix of the inside of the larger one), which is why the
//! cap and the minimum may only lower the ratio. ∎
//!
//! A cell facing `C` (rising towards it, like the wall of a valley seen from the valley
//! floor) does not constrain the cone: that is the relaxation. Cells behind a ridge (falling
//! away) constrain it as a conservative cone would. Compared with Listing 18-1, which shoots
//! rays from the top of the volume only and checks samples along them, this rule covers every
//! ray start in `C` above `A_C` and the continuous surface.
//!
//! # Search
//!
//! The max-corner quadtree of `CellTree` with a flag byte per cell (monotone in `+X`,
//! `−X`, `+Y`, `−Y` over the whole patch), AND-ed per node: a node lying entirely after `C` in
//! `X` whose cells all rise in `+X` (and likewise for `Y`; a node overlapping `C`'s column
//! needs `∂S/∂X = 0`) holds only rising cells and is skipped. The tree also keeps, per node,
//! the range of its cells' scaled partial derivatives (`CellTree::with_slopes`): `rising`'s
//! sum `(∂S/∂X) l_y (D.x − C.x) + (∂S/∂Y) l_x (D.y − C.y)` is at least the smallest product
//! of the node's slope range and offset range along X plus the same along Y, so a node
//! whose two smallest products sum to `≥ 0` holds only rising cells and is skipped too.
//! That catches what the flags cannot: a slope facing `C` across its row or column, or
//! falling slightly along one axis while rising steeply along the other. Otherwise the
//! conservative bound `d_min / (h_max − A_C)` prunes as for `cell_cone`.

use super::{CellScorer, CellTree, Corner, Dir, PieceScorer, Side};
use crate::heightmap::{EdgeMode, HeightMap};
use crate::maps::encode::f32_down;

const X_UP: u8 = 1;
const X_DOWN: u8 = 2;
const Y_UP: u8 = 4;
const Y_DOWN: u8 = 8;

/// Monotonicity flags of a cell from its corners `[h00, h10, h01, h11]`.
pub(crate) fn monotone_flags(c: &[f32; 4]) -> u8 {
    let mut f = 0;
    if c[1] >= c[0] && c[3] >= c[2] {
        f |= X_UP;
    }
    if c[1] <= c[0] && c[3] <= c[2] {
        f |= X_DOWN;
    }
    if c[2] >= c[0] && c[3] >= c[1] {
        f |= Y_UP;
    }
    if c[2] <= c[0] && c[3] <= c[1] {
        f |= Y_DOWN;
    }
    f
}

fn needed(s: Side, up: u8, down: u8) -> u8 {
    match s {
        Side::Pos => up,
        Side::Neg => down,
        Side::Zero | Side::Mixed => up | down,
    }
}

/// Whether cell `D` (extent `dx`, `dy` in texel-centre units, corners `hd`) is rising from
/// cell `C` (extent `cx`, `cy`), decided exactly at the 4 × 4 corner pairs (module docs).
pub fn rising(hd: &[f32; 4], dx: [f64; 2], dy: [f64; 2], cx: [f64; 2], cy: [f64; 2]) -> bool {
    let (lx, ly) = (dx[1] - dx[0], dy[1] - dy[0]);
    let h: [f64; 4] = hd.map(|v| v as f64);
    // Scaled partial derivatives at the corners: (dS/dX) lx at fy = 0, 1; (dS/dY) ly at fx = 0, 1.
    let sx = [h[1] - h[0], h[3] - h[2]];
    let sy = [h[2] - h[0], h[3] - h[1]];
    for (fy, &yy) in dy.iter().enumerate() {
        for (fx, &xx) in dx.iter().enumerate() {
            for &ccx in &cx {
                for &ccy in &cy {
                    // sign of grad S . (y - c), times lx ly > 0
                    let v = sx[fy] * ly * (xx - ccx) + sy[fx] * lx * (yy - ccy);
                    if v < 0.0 {
                        return false;
                    }
                }
            }
        }
    }
    true
}

struct RelaxedScorer<'a> {
    tree: &'a CellTree,
    apex: f64,
}

impl RelaxedScorer<'_> {
    /// How far a node's highest corner rises above the apex, or `None` where the node cannot
    /// bound the ratio: nothing in it rises above the apex, or every cell in it is monotone
    /// in both directions the node lies in from the apex cell.
    #[inline]
    fn rise(&self, hmax: f32, flags: u8, sx: Side, sy: Side) -> Option<f64> {
        let dh = hmax as f64 - self.apex;
        let need = needed(sx, X_UP, X_DOWN) | needed(sy, Y_UP, Y_DOWN);
        (dh > 0.0 && flags & need != need).then_some(dh)
    }
}

impl CellScorer for RelaxedScorer<'_> {
    const SKIPS_RISING: bool = true;

    #[inline]
    fn bound(&self, dmin: f64, hmax: f32, flags: u8, sx: Side, sy: Side) -> Option<f64> {
        self.rise(hmax, flags, sx, sy).map(|dh| dmin / dh)
    }
    #[inline]
    fn prune(&self, d2: f64, hmax: f32, flags: u8, sx: Side, sy: Side, best: f64) -> Option<f64> {
        self.rise(hmax, flags, sx, sy).and_then(|dh| super::prune_ratio(d2, dh, best))
    }
    #[inline]
    fn leaf(
        &self,
        d: usize,
        c: &[Corner; 4],
        dx: [f64; 2],
        dy: [f64; 2],
        cx: [f64; 2],
        cy: [f64; 2],
        _sx: Side,
        _sy: Side,
    ) -> Option<f64> {
        let r = super::piece_ratio(self.apex, f64::INFINITY, 0.0, c);
        if r == f64::INFINITY || rising(&self.tree.corners_of(d), dx, dy, cx, cy) {
            return None;
        }
        Some(r)
    }
    #[inline]
    fn leaf_below(
        &self,
        d: usize,
        c: &[Corner; 4],
        dx: [f64; 2],
        dy: [f64; 2],
        cx: [f64; 2],
        cy: [f64; 2],
        _sx: Side,
        _sy: Side,
        best: f64,
    ) -> Option<f64> {
        let r = super::piece_ratio_below(self.apex, f64::INFINITY, 0.0, c, best)?;
        // The corner heights are f32 values widened to f64: narrowing them back is exact
        // (and saves the lookup of `d`'s corners).
        let _ = d;
        (!rising(&c.map(|q| q.height as f32), dx, dy, cx, cy)).then_some(r)
    }
}

/// The repeat-mode cap `G / (1 - A)` (module docs); `+inf` for clamp or `A >= 1`.
pub fn cap(w: usize, h: usize, edge: EdgeMode, apex: f32) -> f64 {
    if edge == EdgeMode::Clamp || apex >= 1.0 {
        return f64::INFINITY;
    }
    let g = ((w - 1) as f64 / w as f64).min((h - 1) as f64 / h as f64);
    g / (1.0 - apex as f64)
}

/// `cell_relaxed_cone`: `[R_C, A_C]` per cell (module docs).
pub fn cell_relaxed_cone(map: &HeightMap, edge: EdgeMode) -> Vec<f32> {
    let tree = CellTree::with_flags(map, edge, Some(&monotone_flags)).with_slopes();
    let cw = tree.grid.cw;
    crate::maps::search::per_row(cw, tree.grid.ch, 2, |j, row| {
        let (mut prev, mut prev_cons) = (None, None);
        for i in 0..cw {
            let a = super::apex(&tree.corners_of(j * cw + i));
            let cap = cap(map.width, map.height, edge, a);
            let s = RelaxedScorer { tree: &tree, apex: a as f64 };
            let mut r = tree.seeded(i, j, Dir::Both, Dir::Both, &s, cap, &mut prev);
            if r >= cap && cap < f64::INFINITY {
                let c = PieceScorer { lo: a as f64, hi: f64::INFINITY, rho: 0.0 };
                r = r.max(tree.seeded(i, j, Dir::Both, Dir::Both, &c, f64::INFINITY, &mut prev_cons));
            }
            row[2 * i] = f32_down(r);
            row[2 * i + 1] = a;
        }
    })
}
