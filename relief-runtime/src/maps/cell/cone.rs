//! `cell_cone`, `cell_quad_cone` and `cell_cone_normal`: conservative cones of bilinear cells
//! (the cell-grid version of Dummer 2006's cone step mapping, and of QCSM and CNS,
//! Policarpo & Oliveira 2007, GPU Gems 3 ch. 18.4.1; Burger 2018 §2.4 and §3.1).
//! Grid, distances and the per-cell bound: [`super`].
//!
//! # `cell_cone` (2 channels)
//!
//! Per cell `C` (storage index, [`super::CellGrid`]): channel 0 the ratio `R_C`, channel 1
//! the apex `A_C` = the largest of `C`'s four corners. The cone is the solid
//! `{(y, z) : z ≥ A_C + dist(y, C) / R_C}` around the square `C`, and
//!
//! ```text
//! S(y) ≤ A_C + dist(y, C) / R_C        for every point y of the (unrolled) surface.
//! ```
//!
//! `R_C = min over cells D ≠ C of piece_ratio(A_C, +inf, 0, corners of D seen from C)`
//! ([`super::piece_ratio`]); `+inf` if no cell rises above `A_C`. Inside `C` the bound holds
//! because `S ≤ A_C` there. With repeat, every copy of `D` with plane offset
//! `|k| ≤ n − 1` cells along each axis is taken (up to 4 per cell): a copy farther away has
//! the same corners and larger gaps, so it is dominated, and the point of the torus nearest
//! to `C` always has a copy within that range. A stage at a point above `A_C` in `C` may step
//! along the ray to where it meets the cone's side: the textbook cone step with apex height
//! `A_C` and horizontal distance measured to the square `C` (0 inside it).
//! Ratio rounded down to f32, apex stored exactly (it is a height of the map).
//!
//! # `cell_quad_cone` (5 channels)
//!
//! Channels 0–3: the ratio for each quadrant of the horizontal ray direction, in the order of
//! [`crate::maps::quad_cone`]: `+u+v`, `−u+v`, `−u−v`, `+u−v`; channel 4 the apex `A_C`. A ray
//! that starts in `C` heading `+u` never reaches `X < C.x0`, so the `+u` channels take only
//! the cells in `C`'s column or after it (repeat: plane offsets `0..=n−1`; a copy one period
//! farther is dominated as above), and the same for the other signs. A ray exactly along an
//! axis may use either neighbouring channel. Every channel is ≥ the `cell_cone` ratio.
//!
//! The map kind `cell_quad_cone` stores these per cell as 2 × 2 texels of 2 channels
//! ([`quadrant_texels`]): texel `(2i + qx, 2j + qy)` of cell `(i, j)` holds `[R_q, A_C]` for
//! the quadrant `q` a ray moving toward `+u` (`qx` = 1) or `−u` (`qx` = 0), `+v` (`qy` = 1) or
//! `−v` (`qy` = 0) reads, so that a pass of the safe march reads its ratio and the apex in one
//! texel (relief-dsl's `MapReq::cell_texels`).
//!
//! # `cell_cone_normal` (2 channels)
//!
//! Channel 0: `n_z = R / sqrt(1 + R²)` of the `cell_cone` ratio, rounded down
//! ([`crate::maps::cone_normal::normal_z`], Burger §3.1); channel 1: the apex `A_C`.

use super::{CellGrid, CellTree, Dir, PieceScorer};
use crate::heightmap::{EdgeMode, HeightMap};
use crate::maps::encode::f32_down;

/// The cell grid of `map` (sizes of every cell map).
pub fn grid(map: &HeightMap, edge: EdgeMode) -> CellGrid {
    CellGrid::new(map.width, map.height, edge)
}

/// `cell_cone`: `[R_C, A_C]` per cell, row-major over the cell grid.
pub fn cell_cone(map: &HeightMap, edge: EdgeMode) -> Vec<f32> {
    let tree = CellTree::new(map, edge);
    let cw = tree.grid.cw;
    crate::maps::search::per_row(cw, tree.grid.ch, 2, |j, row| {
        let mut prev = None;
        for i in 0..cw {
            let a = super::apex(&tree.corners_of(j * cw + i));
            let s = PieceScorer { lo: a as f64, hi: f64::INFINITY, rho: 0.0 };
            let r = tree.seeded(i, j, Dir::Both, Dir::Both, &s, f64::INFINITY, &mut prev);
            row[2 * i] = f32_down(r);
            row[2 * i + 1] = a;
        }
    })
}

/// The `(x, y)` directions of the four quadrants, in channel order.
pub const QUADRANTS: [(Dir, Dir); 4] = [
    (Dir::Forward, Dir::Forward),
    (Dir::Backward, Dir::Forward),
    (Dir::Backward, Dir::Backward),
    (Dir::Forward, Dir::Backward),
];

/// `cell_quad_cone`: `[R_{+u+v}, R_{-u+v}, R_{-u-v}, R_{+u-v}, A_C]` per cell.
pub fn cell_quad_cone(map: &HeightMap, edge: EdgeMode) -> Vec<f32> {
    let tree = CellTree::new(map, edge);
    let cw = tree.grid.cw;
    crate::maps::search::per_row(cw, tree.grid.ch, 5, |j, row| {
        let mut prev = [None; 4];
        for i in 0..cw {
            let a = super::apex(&tree.corners_of(j * cw + i));
            let s = PieceScorer { lo: a as f64, hi: f64::INFINITY, rho: 0.0 };
            for (q, &(ax, ay)) in QUADRANTS.iter().enumerate() {
                row[5 * i + q] = f32_down(tree.seeded(i, j, ax, ay, &s, f64::INFINITY, &mut prev[q]));
            }
            row[5 * i + 4] = a;
        }
    })
}

/// The quad cones `quad` ([`cell_quad_cone`]: 5 values per cell of a `cw × ch` cell grid) as
/// the map kind `cell_quad_cone` stores them: `2cw × 2ch` texels of `[R_q, A_C]`, texel
/// `(2i + qx, 2j + qy)` the quadrant with `qx` = 1 toward `+u` and `qy` = 1 toward `+v` (the
/// channel of [`QUADRANTS`] with those directions).
///
/// Under clamp (`edge_texels_hold_both_quadrants`) the outermost columns and rows hold the
/// narrower of their cell's two quadrants across that edge.
pub fn quadrant_texels(quad: &[f32], cw: usize, ch: usize, edge: EdgeMode) -> Vec<f32> {
    assert_eq!(quad.len(), 5 * cw * ch, "5 values a cell of a {cw} × {ch} grid");
    let w = 2 * cw;
    let mut out = vec![0.0f32; 2 * w * 2 * ch];
    for (q, &(ax, ay)) in QUADRANTS.iter().enumerate() {
        let (qx, qy) = ((ax == Dir::Forward) as usize, (ay == Dir::Forward) as usize);
        for j in 0..ch {
            for i in 0..cw {
                let (c, t) = (j * cw + i, (2 * j + qy) * w + 2 * i + qx);
                out[2 * t] = quad[5 * c + q];
                out[2 * t + 1] = quad[5 * c + 4];
            }
        }
    }
    if edge == EdgeMode::Clamp {
        edge_texels_hold_both_quadrants(&mut out, w, 2 * ch);
    }
    out
}

/// Under clamp, the ratio of each texel in the outermost columns and rows of the quad cone map
/// (`w × h` texels of `[ratio, apex]`) becomes the smaller of its own and that of its cell's
/// other quadrant across the edge (the texel beside it): columns first, then rows, so that a
/// corner texel holds the smallest of its cell's four.
///
/// Why: a point beyond the map's edge reads its border strip's entry, and the shader lets the
/// sampler's clamp to the edge find it, with no clamp of its own (four `min`/`max` a pass;
/// about 5 % of a pass on lavapipe, `docs/notes/safe-step.md`, round 12). That clamp gives
/// such a point the outermost texel whichever quadrant the ray heads into, and the narrower
/// of the two cones is valid for both (a narrower cone is contained in the wider one, so the
/// surface stays outside it). The cells inside, and every cell under repeat, keep their own.
fn edge_texels_hold_both_quadrants(texels: &mut [f32], w: usize, h: usize) {
    let mut narrow = |a: usize, b: usize| texels[2 * a] = texels[2 * a].min(texels[2 * b]);
    for y in 0..h {
        narrow(y * w, y * w + 1);
        narrow(y * w + w - 1, y * w + w - 2);
    }
    for x in 0..w {
        narrow(x, w + x);
        narrow((h - 1) * w + x, (h - 2) * w + x);
    }
}

/// `cell_cone_normal`: `[n_z(R_C), A_C]` per cell.
pub fn cell_cone_normal(map: &HeightMap, edge: EdgeMode) -> Vec<f32> {
    let mut v = cell_cone(map, edge);
    for c in v.chunks_exact_mut(2) {
        c[0] = crate::maps::cone_normal::normal_z(c[0]);
    }
    v
}
