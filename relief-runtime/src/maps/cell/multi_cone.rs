//! `cell_multi_cone` and `cell_piecewise_cone`: Burger's multiple cones (2018, *Cone Normal
//! Stepping*, §3.4 methods 1 and 2) on bilinear cells, the cell-grid counterparts
//! of [`crate::maps::multi_cone`]. Grid and per-cell bound: [`super`].
//!
//! Both have `K + 1` channels per cell: channels `0..K` the `n_z` of cone (or piece) `k`
//! ([`crate::maps::cone_normal::normal_z`], rounded down), channel `K` the apex `A_C` (the
//! cell's largest corner). The heights are derived from the apex as in the texel version:
//!
//! ```text
//! b_k = A_C + (1 − A_C) k / K,   k = 0..=K
//! ```
//!
//! (f64 here). A shader that rebuilds `b_k` from an apex rounded **up** gets higher apexes
//! `b'_k ≥ b_k` (stacked: each stored cone sits inside its true cone) and a profile
//! `R'(z) ≤ R(z)` (piecewise: the pieces start higher and are shortened by the factor
//! `(1 − A')/(1 − A)`, while `R` is non-decreasing), so an encoded map stays conservative.
//!
//! # Method 1: stacked cones
//!
//! Cone `k` is the `cell_cone` of apex height `b_k` over the square `C`:
//! `r_k = min over D of piece_ratio(b_k, +inf, 0, D)` ([`super::piece_ratio`]), so
//! `S(y) ≤ b_k + dist(y, C) / r_k` everywhere. A ray point in `C` at height `z ≥ b_k` may use
//! cone `k`; cone 0 is `cell_cone`.
//!
//! # Method 2: piecewise cones
//!
//! One profile `rho = R(z)` of K straight pieces, `R(b_0) = 0`, piece `k` with slope `r_k` on
//! `[b_k, b_{k+1}]`. The solid `{(y, z) : dist(y, C) ≤ R(z), z ≥ b_0}` must hold no point
//! under the surface: for every `k` and every `y` with `S(y) > b_k`,
//! `R(b_k) + r_k (min(S(y), b_{k+1}) − b_k) ≤ dist(y, C)` (so no point of the solid at a height
//! below `S(y)` lies over `y`). Greedily from the bottom,
//! `r_k = min over D of piece_ratio(b_k, b_{k+1}, R(b_k), D)`, which certifies exactly that
//! condition per cell; the fallback `r = 0` of `piece_ratio` is valid because piece `k − 1`
//! already certified `R(b_k) ≤ dist(y, C)` wherever `S(y) > b_k`. `R(b_{k+1})` is rebuilt from
//! the f32 slope as the shader will (`R(b_k) + f32_down(r_k) (b_{k+1} − b_k)`). A `+inf`
//! piece makes every later piece `+inf`. Piece 0 is at least the `cell_cone` ratio.

use super::{CellTree, Dir, PieceScorer};
use crate::heightmap::{EdgeMode, HeightMap};
use crate::maps::cone_normal::normal_z;
use crate::maps::encode::f32_down;

/// The heights `b_k` (k = 0..=K) for apex `a`.
pub fn heights(a: f32, k_cones: usize) -> Vec<f64> {
    crate::maps::multi_cone::cone_heights(a, k_cones)
}

/// The stacked cones' ratios of cell `(i, j)` (f64, before rounding), searched with `tree`.
pub(crate) fn stacked_ratios(
    tree: &CellTree,
    i: usize,
    j: usize,
    k_cones: usize,
    prev: &mut [Option<(i64, i64)>],
) -> Vec<f64> {
    let a = super::apex(&tree.corners_of(j * tree.grid.cw + i));
    let b = heights(a, k_cones);
    (0..k_cones)
        .map(|k| {
            let s = PieceScorer { lo: b[k], hi: f64::INFINITY, rho: 0.0 };
            tree.seeded(i, j, Dir::Both, Dir::Both, &s, f64::INFINITY, &mut prev[k])
        })
        .collect()
}

/// `cell_multi_cone`: `[n_z(r_0) .. n_z(r_{K-1}), A_C]` per cell.
pub fn cell_multi_cone(map: &HeightMap, edge: EdgeMode, k_cones: usize) -> Vec<f32> {
    per_cell_cones(map, edge, k_cones, stacked_ratios)
}

/// The piecewise slopes of cell `(i, j)` (f64, before rounding), searched with `tree`.
pub(crate) fn piecewise_slopes(
    tree: &CellTree,
    i: usize,
    j: usize,
    k_cones: usize,
    prev: &mut [Option<(i64, i64)>],
) -> Vec<f64> {
    let a = super::apex(&tree.corners_of(j * tree.grid.cw + i));
    let b = heights(a, k_cones);
    let mut rho = 0.0f64;
    let mut out = Vec::with_capacity(k_cones);
    for k in 0..k_cones {
        if rho.is_infinite() {
            out.push(f64::INFINITY);
            continue;
        }
        let s = PieceScorer { lo: b[k], hi: b[k + 1], rho };
        let r = tree.seeded(i, j, Dir::Both, Dir::Both, &s, f64::INFINITY, &mut prev[k]);
        rho = if r.is_infinite() { f64::INFINITY } else { rho + f32_down(r) as f64 * (b[k + 1] - b[k]) };
        out.push(r);
    }
    out
}

/// `cell_piecewise_cone`: `[n_z(r_0) .. n_z(r_{K-1}), A_C]` per cell.
pub fn cell_piecewise_cone(map: &HeightMap, edge: EdgeMode, k_cones: usize) -> Vec<f32> {
    per_cell_cones(map, edge, k_cones, piecewise_slopes)
}

/// `[n_z(r_0) .. n_z(r_{K-1}), A_C]` per cell, the K ratios of each cell from `ratios` (rows
/// in parallel; `prev` carries each cone's last maximiser along a row as the search's seed).
fn per_cell_cones(
    map: &HeightMap,
    edge: EdgeMode,
    k_cones: usize,
    ratios: impl Fn(&CellTree, usize, usize, usize, &mut [Option<(i64, i64)>]) -> Vec<f64> + Sync,
) -> Vec<f32> {
    let tree = CellTree::new(map, edge);
    let cw = tree.grid.cw;
    let nc = k_cones + 1;
    crate::maps::search::per_row(cw, tree.grid.ch, nc, |j, row| {
        let mut prev = vec![None; k_cones];
        for i in 0..cw {
            let r = ratios(&tree, i, j, k_cones, &mut prev);
            for k in 0..k_cones {
                row[nc * i + k] = normal_z(f32_down(r[k]));
            }
            row[nc * i + k_cones] = super::apex(&tree.corners_of(j * cw + i));
        }
    })
}
