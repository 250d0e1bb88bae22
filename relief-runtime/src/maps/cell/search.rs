//! The search behind every cell map: a maximum-corner quadtree over the cells, visited
//! nearest bound first, each node dropped when its bound shows that no cell in it can lower
//! the minimum (the search section of the [`super`] docs). What was measured and tried:
//! `docs/notes/cell-map-search.md`.

use super::apex;
use super::geometry::{axis_extent, corners_seen_from, CellGrid, Corner};
use crate::heightmap::{EdgeMode, HeightMap};
use crate::maps::encode::{f32_down, f32_up};
use crate::maps::search::{descend, reduce_pyramid, Descent};

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
    /// Whether the scorer gives no score to a cell rising from `C`
    /// ([`rising`](super::relaxed_cone::rising)): the search may then skip a node all of
    /// whose cells are rising (`CellTree::with_slopes`).
    const SKIPS_RISING: bool = false;

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

/// Maximum-corner quadtree over cells, with an optional AND of per-cell flags.
pub(crate) struct CellTree {
    /// The grid whose cells are the tree's leaves.
    pub grid: CellGrid,
    /// The height map's texels (corners are looked up, not stored: a 16-byte-per-cell array
    /// made 1024² searches cache-bound).
    heights: Vec<f32>,
    levels: Vec<(usize, usize, Vec<f32>)>,
    flags: Vec<Vec<u8>>,
    /// Optional (`CellTree::with_slopes`): per node, ranges that hold its cells' slopes
    /// (`CellTree::cell_slopes`) rounded outwards to f32; level 1 is left empty.
    slopes: Vec<Vec<[f32; 4]>>,
}

impl CellTree {
    /// The tree over `map`'s cells under `edge`, without flags.
    pub(crate) fn new(map: &HeightMap, edge: EdgeMode) -> CellTree {
        Self::with_flags(map, edge, None)
    }

    /// With one flag byte per cell (node value: the AND of its cells' flags).
    pub(crate) fn with_flags(map: &HeightMap, edge: EdgeMode, flags: Option<&CellFlags>) -> CellTree {
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
        CellTree { grid, heights, levels, flags: fl, slopes: Vec::new() }
    }

    /// The tree with the ranges of its nodes' slopes, from which the search of a scorer that
    /// skips rising cells (`CellScorer::SKIPS_RISING`) proves a whole node rising
    /// (`CellSearch::all_rising`): 16 bytes per cell and a third more for the levels above,
    /// but level 1, which the search never tests (its blocks are of level 2).
    pub(crate) fn with_slopes(mut self) -> CellTree {
        let g = self.grid;
        let outwards = |r: [f64; 4]| [f32_down(r[0]), f32_up(r[1]), f32_down(r[2]), f32_up(r[3])];
        let base = (0..g.ch)
            .flat_map(|j| (0..g.cw).map(move |i| (i, j)))
            .map(|(i, j)| outwards(self.cell_slopes(i, j)))
            .collect();
        let empty = [f32::INFINITY, f32::NEG_INFINITY, f32::INFINITY, f32::NEG_INFINITY];
        let join = |a: [f32; 4], b: [f32; 4]| [a[0].min(b[0]), a[1].max(b[1]), a[2].min(b[2]), a[3].max(b[3])];
        self.slopes = reduce_pyramid(g.cw, g.ch, base, empty, join).into_iter().map(|l| l.2).collect();
        if let Some(level) = self.slopes.get_mut(1) {
            *level = Vec::new();
        }
        self
    }

    /// The slopes of cell `(i, j)` as [`rising`](super::relaxed_cone::rising) forms them,
    /// with the same operations: `[min, max]` of `∂S/∂X · l_y` over its two rows of
    /// corners, then `[min, max]` of `∂S/∂Y · l_x` over its two columns (`l_x`, `l_y`: the
    /// cell's extent, 1 but at a clamp border).
    #[inline]
    fn cell_slopes(&self, i: usize, j: usize) -> [f64; 4] {
        let (_, _, x0, x1) = self.grid.col(i);
        let (_, _, y0, y1) = self.grid.row(j);
        let h = self.corners_at(i, j).map(|v| v as f64);
        let sx = [(h[1] - h[0]) * (y1 - y0), (h[3] - h[2]) * (y1 - y0)];
        let sy = [(h[2] - h[0]) * (x1 - x0), (h[3] - h[1]) * (x1 - x0)];
        [sx[0].min(sx[1]), sx[0].max(sx[1]), sy[0].min(sy[1]), sy[0].max(sy[1])]
    }

    /// The corners `[h00, h10, h01, h11]` of cell `d` (storage index).
    #[inline]
    pub(crate) fn corners_of(&self, d: usize) -> [f32; 4] {
        self.corners_at(d % self.grid.cw, d / self.grid.cw)
    }

    /// The corners of cell `(i, j)` (storage column and row).
    #[inline]
    pub(crate) fn corners_at(&self, i: usize, j: usize) -> [f32; 4] {
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
    pub(crate) fn search<S: CellScorer>(
        &self,
        ci: usize,
        cj: usize,
        ax: Dir,
        ay: Dir,
        s: &S,
        start: (f64, Option<(i64, i64)>),
        seeds: Seeds,
    ) -> (f64, Option<(i64, i64)>) {
        let q = Query { xa: self.axis_query(ci, ax, true), ya: self.axis_query(cj, ay, false), ci, cj, seeds };
        let mut d = CellSearch { tree: self, q: &q, s, mx: 0, my: 0, best: start };
        let shifts: &[i64] = if self.grid.edge == EdgeMode::Repeat { &[0, -1, 1] } else { &[0] };
        for &my in shifts {
            for &mx in shifts {
                (d.mx, d.my) = (mx, my);
                if d.root_open() {
                    descend(&mut d, self.levels.len() - 1, 0, 0);
                }
            }
        }
        d.best
    }

    fn axis_query(&self, c: usize, dir: Dir, is_x: bool) -> AxisQuery {
        let (n, cn) = if is_x { (self.grid.width, self.grid.cw) } else { (self.grid.height, self.grid.ch) };
        let (_, _, c0, c1) = axis_extent(c, n, self.grid.edge);
        let m = n as i64 - 1;
        let (klo, khi) = match dir {
            Dir::Both => (-m, m),
            Dir::Forward => (0, m),
            Dir::Backward => (-m, 0),
        };
        AxisQuery {
            repeat: self.grid.edge == EdgeMode::Repeat,
            n: n as i64,
            cn: cn as i64,
            c: c as i64,
            dir,
            klo,
            khi,
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
    pub(crate) fn leaf_below_at<S: CellScorer>(
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

    /// The search seeded with the 8 neighbours of `C` and `prev` (updated to the binding
    /// cell's plane position).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn seeded<S: CellScorer>(
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

/// One search of a [`CellTree`] in one copy of the plane (shift `mx`, `my` periods).
struct CellSearch<'a, S> {
    tree: &'a CellTree,
    q: &'a Query,
    s: &'a S,
    mx: i64,
    my: i64,
    best: (f64, Option<(i64, i64)>),
}

impl<S: CellScorer> CellSearch<'_, S> {
    /// Whether every cell of node `(i, j)` of level `k` (index `o` in its level) is rising
    /// from `C`, for a scorer that gives rising cells no score; `false` when that is not
    /// proven. `rising` checks `S_x (D.x − C.x) + S_y (D.y − C.y) ≥ 0` at every pair of
    /// corners, `S_x`, `S_y` a cell's slopes (`CellTree::cell_slopes`); each product is at
    /// least the smallest over the node's range of slopes (rounded outwards, so it holds
    /// every cell's) and its range of offsets ([`least_product`]), so a sum of those two
    /// minima that is `≥ 0` proves every cell of the node rising, with `rising`'s own
    /// rounding.
    #[inline]
    fn all_rising(&self, k: usize, i: usize, j: usize, o: usize) -> bool {
        let t = self.tree;
        if !S::SKIPS_RISING || t.slopes.is_empty() || t.slopes[k].is_empty() {
            return false;
        }
        let sl = t.slopes[k][o].map(f64::from);
        let x = self.q.xa.span(i << k, ((i + 1) << k).min(t.grid.cw) - 1, self.mx);
        let y = self.q.ya.span(j << k, ((j + 1) << k).min(t.grid.ch) - 1, self.my);
        least_product(sl[0], sl[1], x.0, x.1) + least_product(sl[2], sl[3], y.0, y.1) >= 0.0
    }

    /// Whether this copy of the plane may hold a cell below the best: its root passes the
    /// test its children get. Most copies other than `C`'s own are closed here, before
    /// [`descend`] opens their root.
    fn root_open(&self) -> bool {
        let t = self.tree;
        let top = t.levels.len() - 1;
        let (Some((gx, sx)), Some((gy, sy))) =
            (self.q.xa.node(0, t.grid.cw - 1, self.mx), self.q.ya.node(0, t.grid.ch - 1, self.my))
        else {
            return false;
        };
        let fl = if t.flags.is_empty() { 0 } else { t.flags[top][0] };
        self.s.prune(gx * gx + gy * gy, t.levels[top].2[0], fl, sx, sy, self.best.0).is_some()
    }
}

impl<S: CellScorer> Descent for CellSearch<'_, S> {
    #[inline]
    fn closed(&self, b: f64) -> bool {
        b * (1.0 - 1e-9) >= self.best.0
    }

    /// The children whose bound (`CellScorer::prune`) does not reach the best.
    #[inline]
    fn children(&mut self, k: usize, i: usize, j: usize, kids: &mut [(f64, usize, usize); 4]) -> usize {
        let t = self.tree;
        let q = self.q;
        let (cw, ch) = (t.grid.cw, t.grid.ch);
        let (lw, lh, ref ld) = t.levels[k - 1];
        let lf: &[u8] = if t.flags.is_empty() { &[] } else { &t.flags[k - 1] };
        let shift = k - 1;
        // The (at most) two child columns and rows, each decided once.
        let mut xs = [(0usize, 0.0f64, Side::Zero); 2];
        let mut nx = 0;
        for ci2 in 2 * i..(2 * i + 2).min(lw) {
            let (x0, x1) = (ci2 << shift, ((ci2 + 1) << shift).min(cw) - 1);
            if let Some((g, sd)) = q.xa.node(x0, x1, self.mx) {
                xs[nx] = (ci2, g, sd);
                nx += 1;
            }
        }
        if nx == 0 {
            return 0;
        }
        let mut ys = [(0usize, 0.0f64, Side::Zero); 2];
        let mut ny = 0;
        for cj2 in 2 * j..(2 * j + 2).min(lh) {
            let (y0, y1) = (cj2 << shift, ((cj2 + 1) << shift).min(ch) - 1);
            if let Some((g, sd)) = q.ya.node(y0, y1, self.my) {
                ys[ny] = (cj2, g, sd);
                ny += 1;
            }
        }
        let mut n = 0;
        for &(cj2, gy, sy) in &ys[..ny] {
            for &(ci2, gx, sx) in &xs[..nx] {
                let o = cj2 * lw + ci2;
                let fl = if lf.is_empty() { 0 } else { lf[o] };
                let Some(b) = self.s.prune(gx * gx + gy * gy, ld[o], fl, sx, sy, self.best.0) else { continue };
                if self.all_rising(k - 1, ci2, cj2, o) {
                    continue;
                }
                kids[n] = (b, ci2, cj2);
                n += 1;
            }
        }
        n
    }

    /// The nodes of 4 × 4 cells: opening them level by level cost more than testing their
    /// cells in one pass (`CellSearch::block`).
    #[inline]
    fn block_level(&self) -> usize {
        2
    }

    /// Tests each cell of the node against its own bound and scores those that may lower
    /// the best (and are not proven rising, for a scorer that skips rising cells); the gaps
    /// of the node's columns and rows are found once.
    #[inline]
    fn block(&mut self, k: usize, i: usize, j: usize) {
        const SIDE: usize = 4;
        debug_assert!(k <= 2);
        let t = self.tree;
        let (cw, ch) = (t.grid.cw, t.grid.ch);
        let mut xs = [(0usize, 0.0f64, Side::Zero); SIDE];
        let mut nx = 0;
        for x in i << k..((i + 1) << k).min(cw) {
            if let Some((g, sd)) = self.q.xa.node(x, x, self.mx) {
                xs[nx] = (x, g * g, sd);
                nx += 1;
            }
        }
        let mut ys = [(0usize, 0.0f64, Side::Zero); SIDE];
        let mut ny = 0;
        for y in j << k..((j + 1) << k).min(ch) {
            if let Some((g, sd)) = self.q.ya.node(y, y, self.my) {
                ys[ny] = (y, g * g, sd);
                ny += 1;
            }
        }
        let tops = &t.levels[0].2;
        let flags: &[u8] = if t.flags.is_empty() { &[] } else { &t.flags[0] };
        for &(y, gy2, sy) in &ys[..ny] {
            for &(x, gx2, sx) in &xs[..nx] {
                let o = y * cw + x;
                let fl = if flags.is_empty() { 0 } else { flags[o] };
                if self.s.prune(gx2 + gy2, tops[o], fl, sx, sy, self.best.0).is_some() && !self.all_rising(0, x, y, o) {
                    self.leaf(x, y);
                }
            }
        }
    }

    /// Scores the cell at storage `(i, j)` in this copy of the plane, unless it is a seed.
    #[inline]
    fn leaf(&mut self, i: usize, j: usize) {
        let (t, q) = (self.tree, self.q);
        let px = i as i64 + self.mx * t.grid.cw as i64;
        let py = j as i64 + self.my * t.grid.ch as i64;
        if q.seeds.has(px, py, q.ci, q.cj) {
            return;
        }
        // The cell passed its node test, so it is reachable: its extents follow from the
        // storage index without `axis_leaf`'s checks.
        let (dx, cx, sx) = q.xa.leaf(i, px);
        let (dy, cy, sy) = q.ya.leaf(j, py);
        let c = corners_seen_from(dx, dy, cx, cy, &t.corners_at(i, j), t.grid.width, t.grid.height);
        if let Some(v) = self.s.leaf_below(j * t.grid.cw + i, &c, dx, dy, cx, cy, sx, sy, self.best.0) {
            self.best = (v, Some((px, py)));
        }
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
    /// Repeat: the reachable plane offsets from `C`, `klo..=khi` (decided once per search,
    /// not per node).
    klo: i64,
    khi: i64,
    /// `C`'s extent (texel-centre units; clamp only).
    c0: f64,
    c1: f64,
    /// Cell units to texture units.
    scale: f64,
}

impl AxisQuery {
    /// A node's range along the axis (storage `a..=b`, shift `m` periods): min gap in
    /// texture units and side, or `None` if no cell of it is reachable.
    #[inline(always)]
    fn node(&self, a: usize, b: usize, m: i64) -> Option<(f64, Side)> {
        let (a, b, c) = (a as i64, b as i64, self.c);
        if self.repeat {
            let o = m * self.n - c;
            let ka = (a + o).max(self.klo);
            let kb = (b + o).min(self.khi);
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

impl AxisQuery {
    /// The range of `D.x − C.x` over the corners of the reachable cells of storage range
    /// `a..=b` (shift `m` periods) and of `C`, in the coordinates `rising` is given
    /// (texel-centre units, relative to `C` with repeat); `a..=b` holds a reachable cell.
    #[inline]
    fn span(&self, a: usize, b: usize, m: i64) -> (f64, f64) {
        let (a, b, c) = (a as i64, b as i64, self.c);
        if self.repeat {
            let o = m * self.n - c;
            let ka = (a + o).max(self.klo);
            let kb = (b + o).min(self.khi);
            ((ka - 1) as f64, (kb + 1) as f64)
        } else {
            let (lo, hi) = match self.dir {
                Dir::Both => (a, b),
                Dir::Forward => (a.max(c), b),
                Dir::Backward => (a, b.min(c)),
            };
            let (_, _, d0, _) = axis_extent(lo as usize, self.n as usize, EdgeMode::Clamp);
            let (_, _, _, d1) = axis_extent(hi as usize, self.n as usize, EdgeMode::Clamp);
            (d0 - self.c1, d1 - self.c0)
        }
    }

    /// The extents (texel-centre units: `D`'s, then `C`'s) and side of the reachable cell
    /// at storage index `i`, plane position `p`, as `CellTree::axis_leaf` gives them.
    #[inline(always)]
    fn leaf(&self, i: usize, p: i64) -> ([f64; 2], [f64; 2], Side) {
        let k = p - self.c;
        if self.repeat {
            ([k as f64, k as f64 + 1.0], [0.0, 1.0], side_of(k, k))
        } else {
            let (_, _, d0, d1) = axis_extent(i, self.n as usize, EdgeMode::Clamp);
            ([d0, d1], [self.c0, self.c1], side_of(k, k))
        }
    }
}

/// A search's fixed parameters.
struct Query {
    xa: AxisQuery,
    ya: AxisQuery,
    ci: usize,
    cj: usize,
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

/// The smallest product of a value in `[lo, hi]` and one in `[a, b]`. A product is
/// bilinear, so its smallest value over the box is at a corner; rounding is monotone, so no
/// rounded product of the box is below the smallest rounded product of a corner.
#[inline]
fn least_product(lo: f64, hi: f64, a: f64, b: f64) -> f64 {
    (lo * a).min(lo * b).min(hi * a).min(hi * b)
}

#[inline(always)]
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
