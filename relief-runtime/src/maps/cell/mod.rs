//! Cone maps on the **bilinear cells** of a height map, conservative for the surface the
//! shaders actually intersect.
//!
//! The texel-sample cone maps ([`super::cone`] and friends; Dummer 2006, *Cone Step Mapping*;
//! Policarpo & Oliveira 2007, GPU Gems 3 ch. 18; Burger 2018)
//! keep their cones clear of the texel *samples* only. Between texel centres the shaders
//! sample the bilinear surface, which can rise above a texel-sample cone. The kinds here are
//! defined on the continuous surface instead.
//!
//! # The cell grid
//!
//! Work in texel-centre coordinates `X = u · width − 0.5`, `Y = v · height − 0.5`: texel
//! `(x, y)` sits at `(X, Y) = (x, y)`. The bilinear surface `S` is one bilinear patch per
//! *cell*, the square between four neighbouring texel centres.
//!
//! - [`EdgeMode::Repeat`]: `width × height` cells. Cell `(i, j)` covers
//!   `X ∈ [i, i + 1], Y ∈ [j, j + 1]` (modulo the period); its corners are texels
//!   `(i, j), (i+1, j), (i, j+1), (i+1, j+1)` with indices wrapped. The cell of `(u, v)` is
//!   `i = floor(u · width − 0.5) mod width`, `j = floor(v · height − 0.5) mod height`.
//! - [`EdgeMode::Clamp`]: `(width + 1) × (height + 1)` cells. Storage column `i` in
//!   `0..=width` covers `X ∈ [max(i − 1, −0.5), min(i, width − 0.5)]` (the map's domain is
//!   `X ∈ [−0.5, width − 0.5]`, i.e. `u ∈ [0, 1]`), corners texel columns `clamp(i − 1)` and
//!   `clamp(i)`: the first and last columns are half-texel border strips where the surface is
//!   the constant extension of the border texels (both corner columns are the same texel).
//!   The cell of `(u, v)` is `i = clamp(floor(u · width + 0.5), 0, width)`, same for `j`.
//!   Outside `[0, 1]` the clamped surface keeps extending the border; every bound below also
//!   holds there, because a point beyond the border has the height of its projection onto the
//!   border and is no nearer to any cell than that projection.
//!
//! Cell maps are `cells_x × cells_y` (the sizes above), row-major, channels interleaved, and
//! must be read with `textureLoad` / nearest sampling at the cell index (a blend of two cells'
//! cones is neither cell's cone).
//!
//! # Distances
//!
//! `dist(y, C)` is the horizontal Euclidean distance in texture units (the map spans [0, 1]
//! in u and v, as in [`super::cone`]) from point `y` to the closed square `C`; a cone ratio is
//! horizontal distance per unit of height. With `Repeat` the plane is unrolled: the surface is
//! periodic and `C` is the copy the ray starts in.
//!
//! # The per-cell bound (exactly decidable from corners)
//!
//! Fix the cone's cell `C` and another cell `D`. Along each axis `D` lies on one side of `C`
//! (or in the same column/row), so the gap `g_x(y) = max(0, C.x0 − X, X − C.x1) / width` is
//! affine on `D`, and so is `g_y`; `dist(y, C) = |(g_x(y), g_y(y))|`. For any unit vector
//! `e ≥ 0`, Cauchy–Schwarz gives the affine lower bound
//!
//! ```text
//! ℓ_e(y) = e_x g_x(y) + e_y g_y(y) ≤ dist(y, C)     on D,
//! ```
//!
//! with equality where `(g_x, g_y)` is parallel to `e`. `S` is bilinear on `D`, so for
//! constants `ρ`, `r`, `lo` the function `r (S(y) − lo) + ρ − ℓ_e(y)` is bilinear on `D` and
//! its maximum over `D` is at a corner: "it is ≤ 0 on all of `D`" holds iff it holds at the
//! four corners. That is the check every kind uses ([`piece_ratio`]); the candidate `e` are
//! the directions of `D`'s four corner gap vectors, and the best one is kept.
//!
//! Tightness: for `D` in the same row or column as `C` the gap along one axis is 0, `ℓ_e` is
//! the distance itself and the check is exact (the bound is the largest ratio). For diagonal
//! `D` the bound is exact at the corner whose direction is used and below the distance
//! elsewhere on `D` (by a factor `cos` of the angle between the gap vectors, at most
//! `cos 45°` next to `C`, tending to 1 far away), so the ratio can be smaller than the
//! largest one when the binding point of `D` is not a corner.
//!
//! # Search
//!
//! `CellTree::search`: a maximum-height quadtree over the cells (each cell's value the largest of
//! its four corners), visited nearest-bound first, dropping a node whose lower bound
//! `d_min / (h_max − apex)` is not below the best ratio found (with a relative margin of
//! `1e-9` so that rounding in the per-cell formula can never make a pruned cell smaller than
//! the bound); seeded with the 8 neighbouring cells and the cell that bound the previous
//! cell of the row (the tree search does not score those cells again). Rows of cells run in
//! parallel with rayon. The result is bit-identical to the brute-force minimum over all cells
//! (tested in `tests/cell_maps.rs`).
//!
//! What was measured and tried to make the search fast: `docs/notes/cell-map-search.md`.
//!
//! # Quantisation and the 3×3 pass
//!
//! Ratios and `n_z` round down, the apex channel rounds up ([`MapKind::channel_rounding`]):
//! a lower apex or a wider cone could reach the surface, a higher apex or narrower cone is
//! contained in the stored one. An unorm encoding must have `max_value ≥ 1` so the apex
//! (≤ 1) is representable (the CLI refuses otherwise). The 3×3 minimum pass is **not needed**
//! for cell maps: it exists because linear filtering of a texel cone map blends four cones
//! (Burger §4.3.1); a cell map is read at the one cell that contains the ray point, with no
//! filtering, so no blend is ever formed. Filtering a cell map would be wrong even after a
//! 3×3 pass (the apex would have to be blended upward), so the CLI refuses `--min3x3` here.
//!
//! [`MapKind::channel_rounding`]: super::MapKind::channel_rounding

pub mod cone;
pub mod multi_cone;
pub mod relaxed_cone;

use crate::heightmap::{EdgeMode, HeightMap};
use crate::maps::search::reduce_pyramid;

/// The cell grid of a height map (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CellGrid {
    /// Texels per row: the height map's width.
    pub width: usize,
    /// Texel rows: the height map's height.
    pub height: usize,
    /// The edge mode; it decides the cell counts and how corner indices are resolved.
    pub edge: EdgeMode,
    /// Cells per row: `width` (repeat) or `width + 1` (clamp).
    pub cw: usize,
    /// Cell rows: `height` (repeat) or `height + 1` (clamp).
    pub ch: usize,
}

impl CellGrid {
    /// The cell grid of a `w x h` height map under `edge`.
    pub fn new(w: usize, h: usize, edge: EdgeMode) -> CellGrid {
        let extra = usize::from(edge == EdgeMode::Clamp);
        CellGrid { width: w, height: h, edge, cw: w + extra, ch: h + extra }
    }

    /// The storage index of the cell that contains `(u, v)` (see the module docs).
    pub fn cell_of_uv(&self, u: f64, v: f64) -> (usize, usize) {
        (axis_cell(u, self.width, self.edge), axis_cell(v, self.height, self.edge))
    }

    /// Texel indices (resolved) of the two corner columns of cell column `i`, and the cell's
    /// extent in texel-centre coordinates `X` (one period for repeat: `[i, i + 1]`).
    pub fn col(&self, i: usize) -> (usize, usize, f64, f64) {
        axis_extent(i, self.width, self.edge)
    }

    /// Same for cell row `j`.
    pub fn row(&self, j: usize) -> (usize, usize, f64, f64) {
        axis_extent(j, self.height, self.edge)
    }

    /// The four corner heights of cell `(i, j)`: `[h00, h10, h01, h11]` (x fastest).
    pub fn corners(&self, map: &HeightMap, i: usize, j: usize) -> [f32; 4] {
        let (x0, x1, _, _) = self.col(i);
        let (y0, y1, _, _) = self.row(j);
        let t = |x: usize, y: usize| map.data[y * map.width + x];
        [t(x0, y0), t(x1, y0), t(x0, y1), t(x1, y1)]
    }

    /// Corner heights of every cell, row-major.
    pub fn all_corners(&self, map: &HeightMap) -> Vec<[f32; 4]> {
        let mut out = Vec::with_capacity(self.cw * self.ch);
        for j in 0..self.ch {
            for i in 0..self.cw {
                out.push(self.corners(map, i, j));
            }
        }
        out
    }
}

fn axis_cell(u: f64, n: usize, edge: EdgeMode) -> usize {
    match edge {
        EdgeMode::Repeat => ((u * n as f64 - 0.5).floor() as i64).rem_euclid(n as i64) as usize,
        EdgeMode::Clamp => ((u * n as f64 + 0.5).floor() as i64).clamp(0, n as i64) as usize,
    }
}

fn axis_extent(i: usize, n: usize, edge: EdgeMode) -> (usize, usize, f64, f64) {
    match edge {
        // `i < n`: the wrap is one comparison (an integer division here cost more than the
        // rest of a cell's corner lookup).
        EdgeMode::Repeat => (i, if i + 1 == n { 0 } else { i + 1 }, i as f64, i as f64 + 1.0),
        EdgeMode::Clamp => {
            let a = i.saturating_sub(1).min(n - 1);
            let b = i.min(n - 1);
            ((a), b, (i as f64 - 1.0).max(-0.5), (i as f64).min(n as f64 - 0.5))
        }
    }
}

/// The largest of four corner heights: the apex `A_C` of a cell cone (a bilinear patch never
/// exceeds its largest corner).
#[inline]
pub fn apex(c: &[f32; 4]) -> f32 {
    c[0].max(c[1]).max(c[2]).max(c[3])
}

/// Gap (in cell units, ≥ 0) from coordinate `x` to the interval `[c0, c1]`.
#[inline]
pub fn gap(x: f64, c0: f64, c1: f64) -> f64 {
    (c0 - x).max(x - c1).max(0.0)
}

/// One corner of a cell `D` seen from the cone's cell `C`: physical gap vector (texture
/// units, both ≥ 0) and height.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Corner {
    /// Gap along u from `C` to the corner, in texture units, ≥ 0 (0 inside `C`'s column).
    pub gx: f64,
    /// Gap along v from `C` to the corner, in texture units, ≥ 0 (0 inside `C`'s row).
    pub gy: f64,
    /// The corner's height, in [0, 1].
    pub height: f64,
}

/// The four corners of `D` seen from `C`, from the two cells' extents in texel-centre
/// coordinates (`dx = [D.x0, D.x1]`, `cx = [C.x0, C.x1]`, same for y) and `D`'s corner
/// heights `[h00, h10, h01, h11]`. `w`, `h`: the map's texel counts (cell units → texture units).
#[inline]
pub(crate) fn corners_seen_from(
    dx: [f64; 2],
    dy: [f64; 2],
    cx: [f64; 2],
    cy: [f64; 2],
    hd: &[f32; 4],
    w: usize,
    h: usize,
) -> [Corner; 4] {
    let gx = [gap(dx[0], cx[0], cx[1]) / w as f64, gap(dx[1], cx[0], cx[1]) / w as f64];
    let gy = [gap(dy[0], cy[0], cy[1]) / h as f64, gap(dy[1], cy[0], cy[1]) / h as f64];
    [
        Corner { gx: gx[0], gy: gy[0], height: hd[0] as f64 },
        Corner { gx: gx[1], gy: gy[0], height: hd[1] as f64 },
        Corner { gx: gx[0], gy: gy[1], height: hd[2] as f64 },
        Corner { gx: gx[1], gy: gy[1], height: hd[3] as f64 },
    ]
}

/// Horizontal distance for a physical gap vector (the one formula used for corners and for
/// the search's node bounds).
#[inline]
pub fn norm(gx: f64, gy: f64) -> f64 {
    (gx * gx + gy * gy).sqrt()
}

/// The largest slope `r ≥ 0` that this module certifies for one cell `D` (corners `c`, seen
/// from `C`), for a cone piece starting at height `lo` with radius `rho` (texture units) and
/// ending at height `hi`:
///
/// ```text
/// ρ + r (min(S(y), hi) − lo) ≤ dist(y, C)   for every y in D with S(y) > lo.
/// ```
///
/// The plain cell cone is `lo = A_C, hi = +inf, rho = 0`: then the condition reads
/// `S(y) ≤ A_C + dist(y, C) / r`. Returns `+inf` when no corner is above `lo` (the bilinear
/// patch is then nowhere above `lo`). The result is the largest of these certified values:
///
/// 1. for each candidate direction `e` (the unit gap vector of each corner with a non-zero
///    gap), the largest `r` with `r (S_c − lo) ≤ ℓ_e(c) − ρ` at all four corners `c`; since
///    `r (S − lo) + ρ − ℓ_e` is bilinear on `D` (module docs), that makes it hold on all of
///    `D`, and `min(S, hi) ≤ S`, `ℓ_e ≤ dist` give the condition. Corners with `S_c ≤ lo`
///    bound `r` from below when `ℓ_e(c) < ρ`; an empty range gives no value;
/// 2. `(d_min − ρ) / (min(M, hi) − lo)` with `M` the largest corner and `d_min` the smallest
///    corner distance (the exact minimum of `dist` over `D`), when `d_min ≥ ρ`: then
///    `ρ + r (min(S, hi) − lo) ≤ ρ + r (min(M, hi) − lo) ≤ d_min ≤ dist`;
/// 3. `0` (callers guarantee `ρ ≤ dist(y, C)` wherever `S(y) > lo`: for `ρ = 0` trivially,
///    for the pieces of [`multi_cone`] by the piece below).
///
/// The condition is monotone in `r` (smaller `r` keeps it true), so the minimum over cells
/// of these values is certified for every cell at once.
pub fn piece_ratio(lo: f64, hi: f64, rho: f64, c: &[Corner; 4]) -> f64 {
    let m = c[0].height.max(c[1].height).max(c[2].height).max(c[3].height);
    if m <= lo {
        return f64::INFINITY;
    }
    let dmin = norm(c[0].gx.min(c[1].gx), c[0].gy.min(c[2].gy));
    let top = m.min(hi) - lo;
    let mut best = 0.0f64;
    if dmin >= rho {
        best = best.max((dmin - rho) / top);
    }
    for e in c {
        let n = norm(e.gx, e.gy);
        if n <= 0.0 {
            continue;
        }
        let (ex, ey) = (e.gx / n, e.gy / n);
        let (mut lower, mut upper) = (0.0f64, f64::INFINITY);
        let mut feasible = true;
        for q in c {
            let l = ex * q.gx + ey * q.gy - rho;
            let ds = q.height - lo;
            if ds > 0.0 {
                upper = upper.min(l / ds);
            } else if l < 0.0 {
                if ds == 0.0 {
                    feasible = false;
                } else {
                    lower = lower.max(l / ds);
                }
            }
        }
        if feasible && upper >= lower && upper > best {
            best = upper;
        }
    }
    best
}

/// [`piece_ratio`] when it is below `best`, else `None`: the search only needs a cell whose
/// value can lower the minimum. Bit-identical to [`piece_ratio`] where it returns a value
/// (the same operations on the same operands; a maximum does not depend on the order of its
/// terms), and faster: it stops as soon as one certified term reaches `best` (the maximum is
/// then `≥ best`), drops a candidate direction once its running minimum falls to the largest
/// term so far (it can no longer be the maximum), and tries the direction of the highest
/// corner first (the usual binding point, so the usual early stop). With `ρ = 0` that first
/// direction is checked against `best` without divisions before anything else
/// (`reaches_along`); most cells the search scores cannot lower the minimum and leave there.
#[inline]
pub fn piece_ratio_below(lo: f64, hi: f64, rho: f64, c: &[Corner; 4], best: f64) -> Option<f64> {
    let mut top_k = 0;
    for k in 1..4 {
        if c[k].height > c[top_k].height {
            top_k = k;
        }
    }
    let m = c[top_k].height;
    if m <= lo {
        return None;
    }
    if rho == 0.0 && reaches_along(c, &c[top_k], lo, best) {
        return None;
    }
    let dmin = norm(c[0].gx.min(c[1].gx), c[0].gy.min(c[2].gy));
    let top = m.min(hi) - lo;
    let mut v = 0.0f64;
    if dmin >= rho {
        v = v.max((dmin - rho) / top);
    }
    if v >= best {
        return None;
    }
    for o in 0..4 {
        let e = &c[(top_k + o) & 3];
        let n = norm(e.gx, e.gy);
        if n <= 0.0 {
            continue;
        }
        let (ex, ey) = (e.gx / n, e.gy / n);
        let (mut lower, mut upper) = (0.0f64, f64::INFINITY);
        let mut feasible = true;
        for q in c {
            let l = ex * q.gx + ey * q.gy - rho;
            let ds = q.height - lo;
            if ds > 0.0 {
                upper = upper.min(l / ds);
                if upper <= v {
                    feasible = false;
                    break;
                }
            } else if l < 0.0 {
                if ds == 0.0 {
                    feasible = false;
                    break;
                } else {
                    lower = lower.max(l / ds);
                }
            }
        }
        if feasible && upper >= lower && upper > v {
            if upper >= best {
                return None;
            }
            v = upper;
        }
    }
    Some(v)
}

/// Whether option 1 of [`piece_ratio`] (`ρ = 0`) along the gap vector of corner `e` is
/// certainly at least `best`, decided without divisions: with `n = |g_e|`, the term is the
/// minimum over corners `q` above `lo` of `(g_e · g_q) / (n (S_q − lo))`, and each such
/// corner is checked as `g_e · g_q ≥ best · n · (S_q − lo) · (1 + 1e-12)` (a margin far
/// above the few ulp by which the division form can differ). `true` means the cell cannot
/// score below `best` (the maximum over options is at least that term), so
/// [`piece_ratio_below`] would return `None`.
#[inline]
fn reaches_along(c: &[Corner; 4], e: &Corner, lo: f64, best: f64) -> bool {
    let n = norm(e.gx, e.gy);
    if n <= 0.0 || best == f64::INFINITY {
        return false;
    }
    let bar = best * n * (1.0 + 1e-12);
    c.iter().all(|q| {
        let ds = q.height - lo;
        ds <= 0.0 || e.gx * q.gx + e.gy * q.gy >= bar * ds
    })
}

/// The node test for a bound `sqrt(d2) / dh` (`dh > 0`): `None` when it reaches `best` with
/// the search's margin, decided first without a square root or division: `d2 ≥ (best dh)²
/// (1 + 4e-9)` implies `sqrt(d2) / dh ≥ best (1 + 2e-9)` up to a few ulp, so such a node is
/// also dropped by the margin test `b (1 − 1e-9) ≥ best` on the bound itself.
#[inline]
pub fn prune_ratio(d2: f64, dh: f64, best: f64) -> Option<f64> {
    let t = best * dh;
    if d2 >= t * t * (1.0 + 4e-9) {
        return None;
    }
    let b = d2.sqrt() / dh;
    (b * (1.0 - 1e-9) < best).then_some(b)
}

/// Which cells a search may use along one axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dir {
    /// All cells (with repeat: plane offsets `-(n-1)..=n-1`, see `CellTree::search`).
    Both,
    /// Cells at or after `C` (repeat: plane offsets `0..=n-1`).
    Forward,
    /// Cells at or before `C` (repeat: plane offsets `-(n-1)..=0`).
    Backward,
}

/// Where a node lies relative to `C` along one axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// Every cell after `C` (gap grows with the coordinate).
    Pos,
    /// Every cell before `C`.
    Neg,
    /// `C`'s own column (or row) only.
    Zero,
    /// Several of the above.
    Mixed,
}

/// What a search minimises.
pub trait CellScorer: Sync {
    /// A lower bound of [`CellScorer::leaf`] over every cell of a node whose cells are at
    /// least `dmin` away (texture units), no corner above `hmax`, and whose per-cell flags
    /// AND to `flags`; `None`: no cell of the node can score.
    fn bound(&self, dmin: f64, hmax: f32, flags: u8, sx: Side, sy: Side) -> Option<f64>;
    /// The search's test of a node: `None` if [`CellScorer::bound`] (with `dmin = sqrt(d2)`)
    /// is `None` or reaches `best` with the search's relative margin `1e-9`, else the bound.
    /// A scorer may decide the first case without the square root and the division (the
    /// search is latency-bound on them), as long as it drops only nodes that the bound
    /// itself, with that margin, would drop.
    #[inline]
    fn prune(&self, d2: f64, hmax: f32, flags: u8, sx: Side, sy: Side, best: f64) -> Option<f64> {
        self.bound(d2.sqrt(), hmax, flags, sx, sy).filter(|b| b * (1.0 - 1e-9) < best)
    }
    /// The score of cell `D` (storage index `d`): its corners seen from `C`; `None`: no
    /// constraint. `dx`, `dy`: `D`'s extent (texel-centre units, relative for repeat),
    /// `cx`, `cy`: `C`'s.
    #[allow(clippy::too_many_arguments)]
    fn leaf(
        &self,
        d: usize,
        corners: &[Corner; 4],
        dx: [f64; 2],
        dy: [f64; 2],
        cx: [f64; 2],
        cy: [f64; 2],
        sx: Side,
        sy: Side,
    ) -> Option<f64>;
    /// [`CellScorer::leaf`] when it is below `best`, else `None` (what the search uses; a
    /// scorer may override it with a faster equivalent).
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn leaf_below(
        &self,
        d: usize,
        corners: &[Corner; 4],
        dx: [f64; 2],
        dy: [f64; 2],
        cx: [f64; 2],
        cy: [f64; 2],
        sx: Side,
        sy: Side,
        best: f64,
    ) -> Option<f64> {
        self.leaf(d, corners, dx, dy, cx, cy, sx, sy).filter(|&v| v < best)
    }
}

/// A per-cell flag byte computed from the cell's corners `[h00, h10, h01, h11]`.
pub type CellFlags = dyn Fn(&[f32; 4]) -> u8;

/// The cell map `kind` of every level of the height map's mip chain `chain` in one 2D
/// texture, for stages that sample at a level (`lod` other than zero): the levels stacked by
/// rows from level 0 down, each at the left edge, as relief-dsl's `FnBuilder::cell_map_texel`
/// addresses them (the rows above level k are `Σ_{j<k}` of the levels' cell rows). Texels
/// right of a narrower level are 0 and never read. An error if a level's cell grid is not
/// the one that addressing assumes (`h_k` rows, `h_k + 1` under clamp).
pub fn level_atlas(
    chain: &[HeightMap],
    kind: crate::maps::MapKind,
    params: &crate::maps::MapParams,
    edge: EdgeMode,
) -> Result<crate::maps::Map, crate::maps::MapError> {
    let levels = chain.iter().map(|h| crate::maps::build(h, kind, params, edge)).collect::<Result<Vec<_>, _>>()?;
    let border = (edge == EdgeMode::Clamp) as usize;
    for (h, m) in chain.iter().zip(&levels) {
        if m.height != h.height + border || m.width != h.width + border {
            return Err(crate::maps::MapError::Params {
                kind,
                message: format!("a {}×{} level has a {}×{} cell map; the atlas assumes one cell per texel (plus a border under clamp)", h.width, h.height, m.width, m.height),
            });
        }
    }
    let (w, c) = (levels[0].width, levels[0].channels);
    let rows: usize = levels.iter().map(|m| m.height).sum();
    let mut data = vec![0.0f32; w * rows * c];
    let mut row = 0;
    for m in &levels {
        for y in 0..m.height {
            let dst = (row + y) * w * c;
            data[dst..dst + m.width * c].copy_from_slice(&m.data[y * m.width * c..(y + 1) * m.width * c]);
        }
        row += m.height;
    }
    Ok(crate::maps::Map::new_2d(w, rows, c, data))
}

/// Maximum-corner quadtree over cells, with an optional AND of per-cell flags.
pub(crate) struct CellTree {
    /// The grid whose cells are the tree's leaves.
    pub grid: CellGrid,
    /// The height map's texels (corners are looked up, not stored: a 16-byte-per-cell array
    /// made 1024² searches cache-bound).
    heights: Vec<f32>,
    levels: Vec<(usize, usize, Vec<f32>)>,
    flags: Vec<Vec<u8>>,
}

impl CellTree {
    /// The tree over `map`'s cells under `edge`, without flags.
    pub fn new(map: &HeightMap, edge: EdgeMode) -> CellTree {
        Self::with_flags(map, edge, None)
    }

    /// With one flag byte per cell (node value: the AND of its cells' flags).
    pub fn with_flags(map: &HeightMap, edge: EdgeMode, flags: Option<&CellFlags>) -> CellTree {
        let grid = CellGrid::new(map.width, map.height, edge);
        let corners = grid.all_corners(map);
        let base: Vec<f32> = corners.iter().map(apex).collect();
        let heights = map.data.clone();
        let levels = reduce_pyramid(grid.cw, grid.ch, base, f32::NEG_INFINITY, f32::max);
        let fl = match flags {
            Some(f) => {
                let base = corners.iter().map(f).collect::<Vec<u8>>();
                reduce_pyramid(grid.cw, grid.ch, base, 0xff, |a, b| a & b).into_iter().map(|l| l.2).collect()
            }
            None => Vec::new(),
        };
        CellTree { grid, heights, levels, flags: fl }
    }

    /// The corners `[h00, h10, h01, h11]` of cell `d` (storage index).
    #[inline]
    pub fn corners_of(&self, d: usize) -> [f32; 4] {
        self.corners_at(d % self.grid.cw, d / self.grid.cw)
    }

    /// The corners of cell `(i, j)` (storage column and row).
    #[inline]
    pub fn corners_at(&self, i: usize, j: usize) -> [f32; 4] {
        let (x0, x1, _, _) = self.grid.col(i);
        let (y0, y1, _, _) = self.grid.row(j);
        let w = self.grid.width;
        let t = |x: usize, y: usize| self.heights[y * w + x];
        [t(x0, y0), t(x1, y0), t(x0, y1), t(x1, y1)]
    }

    /// Minimum score over the cells reachable from cell `(ci, cj)` with directions
    /// `(ax, ay)`, starting from `best` (and its binding cell, a plane position, see
    /// [`CellTree::leaf_below_at`]). Returns the minimum and the plane position of the cell that
    /// gave it. `seeds`: cells the caller has already scored against a bar no lower than
    /// the search's (they cannot lower it again and are not scored twice).
    #[allow(clippy::too_many_arguments)]
    pub fn search<S: CellScorer>(
        &self,
        ci: usize,
        cj: usize,
        ax: Dir,
        ay: Dir,
        s: &S,
        start: (f64, Option<(i64, i64)>),
        seeds: Seeds,
    ) -> (f64, Option<(i64, i64)>) {
        let mut best = start;
        let top = self.levels.len() - 1;
        let q = Query { xa: self.axis_query(ci, ax, true), ya: self.axis_query(cj, ay, false), ci, cj, ax, ay, seeds };
        let shifts: &[i64] = if self.grid.edge == EdgeMode::Repeat { &[0, -1, 1] } else { &[0] };
        for &my in shifts {
            for &mx in shifts {
                if top == 0 {
                    let (px, py) = (mx * self.grid.cw as i64, my * self.grid.ch as i64);
                    if let Some(v) = self.leaf_below_at(px, py, ci, cj, ax, ay, s, best.0) {
                        best = (v, Some((px, py)));
                    }
                } else {
                    self.visit(top, 0, 0, mx, my, &q, s, &mut best);
                }
            }
        }
        best
    }

    fn axis_query(&self, c: usize, dir: Dir, is_x: bool) -> AxisQuery {
        let (n, cn) = if is_x { (self.grid.width, self.grid.cw) } else { (self.grid.height, self.grid.ch) };
        let (_, _, c0, c1) = axis_extent(c, n, self.grid.edge);
        AxisQuery {
            repeat: self.grid.edge == EdgeMode::Repeat,
            n: n as i64,
            cn: cn as i64,
            c: c as i64,
            dir,
            c0,
            c1,
            scale: 1.0 / n as f64,
        }
    }

    /// The score of the cell at plane position `(px, py)` (repeat: any integers, the cell is
    /// `px mod w`; clamp: the storage index) if it is reachable and scores below `best`, else
    /// `None`.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub fn leaf_below_at<S: CellScorer>(
        &self,
        px: i64,
        py: i64,
        ci: usize,
        cj: usize,
        ax: Dir,
        ay: Dir,
        s: &S,
        best: f64,
    ) -> Option<f64> {
        let x = self.axis_leaf(px, ci, self.grid.cw, self.grid.width, ax, true)?;
        let y = self.axis_leaf(py, cj, self.grid.ch, self.grid.height, ay, false)?;
        let d = y.0 * self.grid.cw + x.0;
        let c = corners_seen_from(x.1, y.1, x.2, y.2, &self.corners_at(x.0, y.0), self.grid.width, self.grid.height);
        s.leaf_below(d, &c, x.1, y.1, x.2, y.2, x.3, y.3, best)
    }

    /// One axis of a leaf: storage index, D extent, C extent, side.
    #[allow(clippy::type_complexity)]
    fn axis_leaf(
        &self,
        p: i64,
        c: usize,
        cn: usize,
        n: usize,
        dir: Dir,
        is_x: bool,
    ) -> Option<(usize, [f64; 2], [f64; 2], Side)> {
        match self.grid.edge {
            EdgeMode::Repeat => {
                let k = p - c as i64;
                let n = n as i64;
                let ok = match dir {
                    Dir::Both => -(n - 1) <= k && k < n,
                    Dir::Forward => (0..n).contains(&k),
                    Dir::Backward => -(n - 1) <= k && k <= 0,
                };
                if !ok {
                    return None;
                }
                let side = side_of(k, k);
                // Plane positions are within one period of the storage range (shifts of
                // -1, 0, 1 periods): wrap without an integer division.
                let r = if p < 0 {
                    p + n
                } else if p >= n {
                    p - n
                } else {
                    p
                };
                let r = if (0..n).contains(&r) { r } else { p.rem_euclid(n) };
                Some((r as usize, [k as f64, k as f64 + 1.0], [0.0, 1.0], side))
            }
            EdgeMode::Clamp => {
                if p < 0 || p >= cn as i64 {
                    return None;
                }
                let k = p - c as i64;
                let ok = match dir {
                    Dir::Both => true,
                    Dir::Forward => k >= 0,
                    Dir::Backward => k <= 0,
                };
                if !ok {
                    return None;
                }
                let (_, _, d0, d1) = if is_x { self.grid.col(p as usize) } else { self.grid.row(p as usize) };
                let (_, _, c0, c1) = if is_x { self.grid.col(c) } else { self.grid.row(c) };
                Some((p as usize, [d0, d1], [c0, c1], side_of(k, k)))
            }
        }
    }

    /// Visits the children of node `(i, j)` of level `k ≥ 1` (plane shift `mx`, `my`):
    /// children whose bound reaches `best` are dropped, the others visited nearest bound
    /// first (at level 1 the children are cells and are scored).
    #[allow(clippy::too_many_arguments)]
    fn visit<S: CellScorer>(
        &self,
        k: usize,
        i: usize,
        j: usize,
        mx: i64,
        my: i64,
        q: &Query,
        s: &S,
        best: &mut (f64, Option<(i64, i64)>),
    ) {
        let (cw, ch) = (self.grid.cw, self.grid.ch);
        let (lw, lh, ref ld) = self.levels[k - 1];
        let lf: &[u8] = if self.flags.is_empty() { &[] } else { &self.flags[k - 1] };
        let shift = k - 1;
        // The (at most) two child columns and rows, each decided once.
        let mut xs = [(0usize, 0.0f64, Side::Zero); 2];
        let mut nx = 0;
        for ci2 in 2 * i..(2 * i + 2).min(lw) {
            let (x0, x1) = (ci2 << shift, ((ci2 + 1) << shift).min(cw) - 1);
            if let Some((g, sd)) = q.xa.node(x0, x1, mx) {
                xs[nx] = (ci2, g, sd);
                nx += 1;
            }
        }
        if nx == 0 {
            return;
        }
        let mut ys = [(0usize, 0.0f64, Side::Zero); 2];
        let mut ny = 0;
        for cj2 in 2 * j..(2 * j + 2).min(lh) {
            let (y0, y1) = (cj2 << shift, ((cj2 + 1) << shift).min(ch) - 1);
            if let Some((g, sd)) = q.ya.node(y0, y1, my) {
                ys[ny] = (cj2, g, sd);
                ny += 1;
            }
        }
        let mut kids: [(f64, usize, usize); 4] = [(0.0, 0, 0); 4];
        let mut n = 0;
        for &(cj2, gy, sy) in &ys[..ny] {
            for &(ci2, gx, sx) in &xs[..nx] {
                let o = cj2 * lw + ci2;
                let fl = if lf.is_empty() { 0 } else { lf[o] };
                let Some(b) = s.prune(gx * gx + gy * gy, ld[o], fl, sx, sy, best.0) else { continue };
                // Insertion into the sorted list of children (nearest bound first).
                let mut p = n;
                while p > 0 && kids[p - 1].0 > b {
                    kids[p] = kids[p - 1];
                    p -= 1;
                }
                kids[p] = (b, ci2, cj2);
                n += 1;
            }
        }
        for &(b, ci2, cj2) in &kids[..n] {
            if b * (1.0 - 1e-9) >= best.0 {
                // Sorted: every later child is dropped too.
                break;
            }
            if k == 1 {
                let px = ci2 as i64 + mx * cw as i64;
                let py = cj2 as i64 + my * ch as i64;
                if q.seeds.has(px, py, q.ci, q.cj) {
                    continue;
                }
                if let Some(v) = self.leaf_below_at(px, py, q.ci, q.cj, q.ax, q.ay, s, best.0) {
                    *best = (v, Some((px, py)));
                }
            } else {
                self.visit(k - 1, ci2, cj2, mx, my, q, s, best);
            }
        }
    }

    /// The search seeded with the 8 neighbours of `C` and `prev` (updated to the binding
    /// cell's plane position).
    #[allow(clippy::too_many_arguments)]
    pub fn seeded<S: CellScorer>(
        &self,
        ci: usize,
        cj: usize,
        ax: Dir,
        ay: Dir,
        s: &S,
        init: f64,
        prev: &mut Option<(i64, i64)>,
    ) -> f64 {
        let mut best: (f64, Option<(i64, i64)>) = (init, None);
        let try_at = |px: i64, py: i64, best: &mut (f64, Option<(i64, i64)>)| {
            if let Some(v) = self.leaf_below_at(px, py, ci, cj, ax, ay, s, best.0) {
                *best = (v, Some((px, py)));
            }
        };
        if let Some((px, py)) = *prev {
            try_at(px, py, &mut best);
        }
        for dy in -1i64..=1 {
            for dx in -1i64..=1 {
                if dx != 0 || dy != 0 {
                    try_at(ci as i64 + dx, cj as i64 + dy, &mut best);
                }
            }
        }
        let r = self.search(ci, cj, ax, ay, s, best, Seeds { neighbours: true, prev: *prev });
        if r.1.is_some() {
            *prev = r.1;
        }
        r.0
    }
}

/// One axis of a search: the cone's cell `c`, the reachable direction, `C`'s extent.
struct AxisQuery {
    repeat: bool,
    /// Texels and cells along the axis.
    n: i64,
    cn: i64,
    c: i64,
    dir: Dir,
    /// `C`'s extent (texel-centre units; clamp only).
    c0: f64,
    c1: f64,
    /// Cell units to texture units.
    scale: f64,
}

impl AxisQuery {
    /// A node's range along the axis (storage `a..=b`, shift `m` periods): min gap in
    /// texture units and side, or `None` if no cell of it is reachable.
    #[inline]
    fn node(&self, a: usize, b: usize, m: i64) -> Option<(f64, Side)> {
        let (a, b, c) = (a as i64, b as i64, self.c);
        if self.repeat {
            let n = self.n;
            let (lo, hi) = match self.dir {
                Dir::Both => (-(n - 1), n - 1),
                Dir::Forward => (0, n - 1),
                Dir::Backward => (-(n - 1), 0),
            };
            let ka = (a - c + m * n).max(lo);
            let kb = (b - c + m * n).min(hi);
            if ka > kb {
                return None;
            }
            let g = if ka >= 1 {
                (ka - 1) as f64
            } else if kb <= -1 {
                (-kb - 1) as f64
            } else {
                0.0
            };
            Some((g * self.scale, side_of(ka, kb)))
        } else {
            let (lo, hi) = match self.dir {
                Dir::Both => (a, b),
                Dir::Forward => (a.max(c), b),
                Dir::Backward => (a, b.min(c)),
            };
            if lo > hi {
                return None;
            }
            debug_assert!(hi < self.cn);
            // Clamp extents (module docs): column `i` covers `[max(i - 1, -0.5), min(i, n - 0.5)]`.
            let x0 = ((lo - 1) as f64).max(-0.5);
            let x1 = (hi as f64).min(self.n as f64 - 0.5);
            Some(((self.c0 - x1).max(x0 - self.c1).max(0.0) * self.scale, side_of(lo - c, hi - c)))
        }
    }
}

/// A search's fixed parameters.
struct Query {
    xa: AxisQuery,
    ya: AxisQuery,
    ci: usize,
    cj: usize,
    ax: Dir,
    ay: Dir,
    seeds: Seeds,
}

/// Cells a search need not score (see [`CellTree::search`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Seeds {
    /// The 8 cells around `C` (plane positions `C ± 1`).
    pub neighbours: bool,
    /// One more plane position.
    pub prev: Option<(i64, i64)>,
}

impl Seeds {
    #[inline]
    fn has(&self, px: i64, py: i64, ci: usize, cj: usize) -> bool {
        (self.neighbours && (px - ci as i64).abs() <= 1 && (py - cj as i64).abs() <= 1) || self.prev == Some((px, py))
    }
}

fn side_of(ka: i64, kb: i64) -> Side {
    if ka >= 1 {
        Side::Pos
    } else if kb <= -1 {
        Side::Neg
    } else if ka == 0 && kb == 0 {
        Side::Zero
    } else {
        Side::Mixed
    }
}

/// Runs `f(j, row)` for every row of cells in parallel; `row` holds `cw * c` values.
pub(crate) fn per_cell_row(cw: usize, ch: usize, c: usize, f: impl Fn(usize, &mut [f32]) + Sync) -> Vec<f32> {
    use rayon::prelude::*;
    let mut out = vec![0.0f32; cw * ch * c];
    out.par_chunks_mut(cw * c).enumerate().for_each(|(j, row)| f(j, row));
    out
}

/// Scorer of a cone piece: [`piece_ratio`] with fixed `lo`, `hi`, `rho`.
pub(crate) struct PieceScorer {
    pub lo: f64,
    pub hi: f64,
    pub rho: f64,
}

impl CellScorer for PieceScorer {
    #[inline]
    fn bound(&self, dmin: f64, hmax: f32, _flags: u8, _sx: Side, _sy: Side) -> Option<f64> {
        let hmax = hmax as f64;
        if hmax <= self.lo {
            return None;
        }
        // Option 2 of `piece_ratio` with the node's smallest distance and largest height.
        Some(((dmin - self.rho) / (hmax.min(self.hi) - self.lo)).max(0.0))
    }
    #[inline]
    fn prune(&self, d2: f64, hmax: f32, _flags: u8, _sx: Side, _sy: Side, best: f64) -> Option<f64> {
        let hmax = hmax as f64;
        if hmax <= self.lo {
            return None;
        }
        let dh = hmax.min(self.hi) - self.lo;
        if self.rho == 0.0 {
            return prune_ratio(d2, dh, best);
        }
        let b = ((d2.sqrt() - self.rho) / dh).max(0.0);
        (b * (1.0 - 1e-9) < best).then_some(b)
    }
    #[inline]
    fn leaf(
        &self,
        _d: usize,
        c: &[Corner; 4],
        _dx: [f64; 2],
        _dy: [f64; 2],
        _cx: [f64; 2],
        _cy: [f64; 2],
        _sx: Side,
        _sy: Side,
    ) -> Option<f64> {
        let r = piece_ratio(self.lo, self.hi, self.rho, c);
        (r < f64::INFINITY).then_some(r)
    }
    #[inline]
    fn leaf_below(
        &self,
        _d: usize,
        c: &[Corner; 4],
        _dx: [f64; 2],
        _dy: [f64; 2],
        _cx: [f64; 2],
        _cy: [f64; 2],
        _sx: Side,
        _sy: Side,
        best: f64,
    ) -> Option<f64> {
        piece_ratio_below(self.lo, self.hi, self.rho, c, best)
    }
}
