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
//! - [`EdgeMode::Repeat`](crate::EdgeMode::Repeat): `width × height` cells. Cell `(i, j)` covers
//!   `X ∈ [i, i + 1], Y ∈ [j, j + 1]` (modulo the period); its corners are texels
//!   `(i, j), (i+1, j), (i, j+1), (i+1, j+1)` with indices wrapped. The cell of `(u, v)` is
//!   `i = floor(u · width − 0.5) mod width`, `j = floor(v · height − 0.5) mod height`.
//! - [`EdgeMode::Clamp`](crate::EdgeMode::Clamp): `(width + 1) × (height + 1)` cells. Storage column `i` in
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
//! The search (`search.rs`): a maximum-height quadtree over the cells (each cell's value the largest of
//! its four corners), visited nearest-bound first, dropping a node whose lower bound
//! `d_min / (h_max − apex)` is not below the best ratio found (with a relative margin of
//! `1e-9` so that rounding in the per-cell formula can never make a pruned cell smaller than
//! the bound); seeded with the 8 neighbouring cells and the cell that bound the previous
//! cell of the row (the tree search does not score those cells again). A node of 4 × 4
//! cells is not opened level by level: each of its cells is tested against its own bound
//! in one pass. Rows of cells run in parallel with rayon. The result is bit-identical to the brute-force minimum over all cells
//! (tested in `tests/cell_maps.rs`).
//!
//! What was measured and tried to make the search fast: `docs/notes/cell-map-search.md`.
//!
//! # Quantisation and the 3×3 pass
//!
//! Ratios and `n_z` round down, the apex channel rounds up ([`kind_rounding`](super::kind_rounding)):
//! a lower apex or a wider cone could reach the surface, a higher apex or narrower cone is
//! contained in the stored one. An unorm encoding must have `max_value ≥ 1` so the apex
//! (≤ 1) is representable (the CLI refuses otherwise). The 3×3 minimum pass is **not needed**
//! for cell maps: it exists because linear filtering of a texel cone map blends four cones
//! (Burger §4.3.1); a cell map is read at the one cell that contains the ray point, with no
//! filtering, so no blend is ever formed. Filtering a cell map would be wrong even after a
//! 3×3 pass (the apex would have to be blended upward), so the CLI refuses `--min3x3` here.

pub mod cone;
pub mod multi_cone;
pub mod patch;
pub mod relaxed_cone;

mod atlas;
mod bound;
mod geometry;
mod search;

pub use atlas::level_atlas;
pub(crate) use bound::PieceScorer;
pub use bound::{piece_ratio, piece_ratio_below, prune_ratio};
pub use geometry::{apex, gap, norm, CellGrid, Corner};
pub(crate) use search::CellTree;
pub use search::{CellFlags, CellScorer, Dir, Side};
