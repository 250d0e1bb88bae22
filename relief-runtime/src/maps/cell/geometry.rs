//! The cell grid and the corners of a cell seen from another (the cell grid and distances of
//! the [`super`] docs).

use crate::heightmap::{EdgeMode, HeightMap};

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
    pub(crate) fn all_corners(&self, map: &HeightMap) -> Vec<[f32; 4]> {
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

pub(super) fn axis_extent(i: usize, n: usize, edge: EdgeMode) -> (usize, usize, f64, f64) {
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
    larger(larger(c0 - x, x - c1), 0.0)
}

/// `a.max(b)` for values that are not NaN (coordinates), as one comparison: `f64::max`'s
/// handling of NaN operands costs several instructions, four times per scored cell. A
/// zero gap may come out `+0` where `f64::max` could give `-0`; both square to `+0`, and
/// the scores compare them as equal.
#[inline(always)]
fn larger(a: f64, b: f64) -> f64 {
    if a > b {
        a
    } else {
        b
    }
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
