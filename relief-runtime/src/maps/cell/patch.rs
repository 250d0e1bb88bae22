//! `cell_patch`: the bilinear patch of every cell, as coefficients (issue 37, round 11 of
//! `docs/notes/safe-step.md`).
//!
//! Per cell (storage index on the cell grid of [`super`], the same grid as every cell map:
//! `w × h` under repeat, `(w + 1) × (h + 1)` under clamp with its border strips), four
//! channels: `h00`, `dx = h10 − h00`, `dy = h01 − h00` and `k = (h11 − h10) − dy`, so that over
//! the cell, with fractions `(fx, fy)` in [0, 1]², the surface is
//! `h00 + dx·fx + dy·fy + k·fx·fy`. Each is computed in f32 in exactly the order the shader's
//! `Coeffs::of_corners` (relief-dsl's `stage::coarse::cell`) computes it from the four
//! corners it gathers, so a patch read from this map is the gathered patch bit for bit, and
//! the safe marches that read it (`csm`, `cns`, `csm_relax`, `qcsm`) give the same answers as with
//! the gather. Not to be quantised (the CLI refuses any encoding but f32): a rounded
//! coefficient is another surface.

use super::CellGrid;
use crate::heightmap::{EdgeMode, HeightMap};

/// `cell_patch`: `[h00, dx, dy, k]` per cell, row-major over the cell grid.
///
/// ```
/// use relief_runtime::{maps::cell::patch::cell_patch, EdgeMode, HeightMap};
/// // Texels h00 = 0, h10 = 1, h01 = 2, h11 = 4: dx = 1, dy = 2, k = (4 − 1) − 2 = 1.
/// let hm = HeightMap::new(2, 2, vec![0.0, 1.0, 2.0, 4.0]);
/// assert_eq!(&cell_patch(&hm, EdgeMode::Repeat)[..4], &[0.0, 1.0, 2.0, 1.0]);
/// ```
pub fn cell_patch(map: &HeightMap, edge: EdgeMode) -> Vec<f32> {
    let grid = CellGrid::new(map.width, map.height, edge);
    let mut out = Vec::with_capacity(grid.cw * grid.ch * 4);
    for j in 0..grid.ch {
        for i in 0..grid.cw {
            let [h00, h10, h01, h11] = grid.corners(map, i, j);
            let (dx, dy) = (h10 - h00, h01 - h00);
            out.extend([h00, dx, dy, h11 - h10 - dy]);
        }
    }
    out
}
