//! Branch-and-bound search over a maximum-height quadtree, shared by the cone generators.
//!
//! Every cone-like quantity here is a minimum over texels `q` of a score that only depends on
//! the offset from the centre texel `p` to `q` and on `h(q)`, and that can be bounded from
//! below for a whole rectangle of texels knowing only the smallest offset into the rectangle
//! and the largest height inside it. A quadtree of maximum heights (each node the max of its
//! up-to-four children, sides halved with rounding up) gives those maxima. The search visits
//! nodes depth first, children in order of increasing bound, and drops a node whose bound is
//! not below the best score found so far. Regions no higher than the centre are dropped at
//! once, and so are regions too far away to matter. This is the max-mip pruning of Valasek &
//! Bán (Eurographics 2022), run on the CPU per texel.
//!
//! Exactness: the bound is computed with the same floating-point expressions as the score on
//! offsets and heights that are each no larger (no smaller) than any texel's, and IEEE
//! arithmetic rounds monotonically, so a pruned texel could never have lowered the minimum.
//! The result is bit-identical to a brute-force minimum over all texels.

use crate::heightmap::{EdgeMode, HeightMap};

/// Which offsets along one axis a search may use, and how they are measured.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Axis {
    /// Both directions; with wrapping the shorter way round (ties go to the positive side).
    Both { wrap: bool },
    /// Only offsets `>= 0` (with wrapping: the forward way round, `0..n`).
    Forward { wrap: bool },
    /// Only offsets `<= 0` (with wrapping: the backward way round).
    Backward { wrap: bool },
}

impl Axis {
    pub(crate) fn both(edge: EdgeMode) -> Axis {
        Axis::Both { wrap: edge == EdgeMode::Repeat }
    }

    /// Signed offset from `p` to texel `q` (both in `0..n`), or `None` if unreachable.
    #[inline]
    pub(crate) fn offset(self, p: i64, q: i64, n: i64) -> Option<i64> {
        // `p`, `q` in 0..n, so `q - p` in (-n, n): one conditional add replaces `rem_euclid`.
        let d = q - p;
        let fwd = if d < 0 { d + n } else { d };
        match self {
            Axis::Both { wrap: true } => Some(if fwd <= n - fwd { fwd } else { fwd - n }),
            Axis::Both { wrap: false } => Some(d),
            Axis::Forward { wrap: true } => Some(fwd),
            Axis::Forward { wrap: false } => (d >= 0).then_some(d),
            Axis::Backward { wrap: true } => Some(if d > 0 { d - n } else { d }),
            Axis::Backward { wrap: false } => (d <= 0).then_some(d),
        }
    }

    /// Smallest `|offset|` from `p` to any texel of `a..=b` (all in `0..n`), or `None` if
    /// none is reachable.
    #[inline]
    pub(crate) fn min_offset(self, p: i64, a: i64, b: i64, n: i64) -> Option<i64> {
        if a <= p && p <= b {
            return Some(0);
        }
        let right = a > p; // the interval lies after p (else before it)
        match self {
            Axis::Both { wrap } => Some(if !wrap {
                if right {
                    a - p
                } else {
                    p - b
                }
            } else if right {
                (a - p).min(p - b + n)
            } else {
                (p - b).min(a - p + n)
            }),
            Axis::Forward { wrap } => {
                if right {
                    Some(a - p)
                } else if wrap {
                    Some(a - p + n)
                } else {
                    None
                }
            }
            Axis::Backward { wrap } => {
                if !right {
                    Some(p - b)
                } else if wrap {
                    Some(p - b + n)
                } else {
                    None
                }
            }
        }
    }
}

/// Horizontal distance in texture coordinates for a texel offset, on a `w x h` map.
/// The one formula every generator and every brute-force test uses.
#[inline]
pub fn texel_distance(ox: i64, oy: i64, w: usize, h: usize) -> f64 {
    let du = ox as f64 / w as f64;
    let dv = oy as f64 / h as f64;
    (du * du + dv * dv).sqrt()
}

/// A score to minimise over texels.
pub(crate) trait Scorer {
    /// A lower bound of [`Scorer::score`] over texels with `|offset|` at least `(ox, oy)` and
    /// height at most `hmax`; `None` if no such texel can score.
    /// `aux` is the node's maximum of the tree's auxiliary per-texel value (0 if none).
    fn bound(&self, ox: i64, oy: i64, hmax: f32, aux: f32) -> Option<f64>;
    /// The score of the texel at signed offset `(sx, sy)` with height `hq`; `None`: no constraint.
    fn score(&self, sx: i64, sy: i64, hq: f32) -> Option<f64>;
}

/// A best score and the texel that reached it.
pub(crate) type Best = (f64, Option<(usize, usize)>);

/// Maximum-height quadtree. Level 0 is the map; level `k` node `(i, j)` covers texels
/// `x in [i << k, min((i + 1) << k, w))`, same for y.
pub(crate) struct MaxTree {
    pub(crate) w: usize,
    pub(crate) h: usize,
    levels: Vec<(usize, usize, Vec<f32>)>,
    /// Per-node maxima of an optional second per-texel value (same shapes), for scorers
    /// whose bound needs more than the height.
    aux: Vec<Vec<f32>>,
}

impl MaxTree {
    pub(crate) fn new(map: &HeightMap) -> MaxTree {
        let levels = Self::pyramid(map.width, map.height, map.data.clone());
        MaxTree { w: map.width, h: map.height, levels, aux: Vec::new() }
    }

    /// A tree that also keeps per-node maxima of `aux` (one value per texel).
    pub(crate) fn with_aux(map: &HeightMap, aux: Vec<f32>) -> MaxTree {
        let mut t = Self::new(map);
        t.aux = Self::pyramid(map.width, map.height, aux).into_iter().map(|l| l.2).collect();
        t
    }

    fn pyramid(w0: usize, h0: usize, data: Vec<f32>) -> Vec<(usize, usize, Vec<f32>)> {
        reduce_pyramid(w0, h0, data, f32::NEG_INFINITY, f32::max)
    }

    #[inline]
    pub(crate) fn height(&self, x: usize, y: usize) -> f32 {
        self.levels[0].2[y * self.w + x]
    }

    /// Minimum score over all texels reachable from `(px, py)`, starting from `best`
    /// (returned unchanged if nothing scores lower).
    pub(crate) fn search_min<S: Scorer>(&self, px: usize, py: usize, ax: Axis, ay: Axis, s: &S, best: f64) -> f64 {
        self.search_argmin(px, py, ax, ay, s, (best, None)).0
    }

    /// As [`MaxTree::search_min`], also returning the texel that gave the minimum (the one
    /// passed in `start` if nothing beat it).
    pub(crate) fn search_argmin<S: Scorer>(
        &self,
        px: usize,
        py: usize,
        ax: Axis,
        ay: Axis,
        s: &S,
        start: Best,
    ) -> Best {
        let mut q = TexelSearch { tree: self, px: px as i64, py: py as i64, ax, ay, s, best: start };
        descend(&mut q, self.levels.len() - 1, 0, 0);
        q.best
    }

    /// The score of texel `q` seen from `p` (a valid starting bound: it is a real candidate).
    pub(crate) fn score_of<S: Scorer>(
        &self,
        px: usize,
        py: usize,
        q: (usize, usize),
        ax: Axis,
        ay: Axis,
        s: &S,
    ) -> Option<f64> {
        let (w, h) = (self.w as i64, self.h as i64);
        let sx = ax.offset(px as i64, q.0 as i64, w)?;
        let sy = ay.offset(py as i64, q.1 as i64, h)?;
        s.score(sx, sy, self.height(q.0, q.1))
    }
}

/// One search of [`MaxTree`]: the centre texel, the axes, the scorer and the running best.
struct TexelSearch<'a, S> {
    tree: &'a MaxTree,
    px: i64,
    py: i64,
    ax: Axis,
    ay: Axis,
    s: &'a S,
    best: Best,
}

impl<S: Scorer> Descent for TexelSearch<'_, S> {
    #[inline]
    fn closed(&self, b: f64) -> bool {
        b >= self.best.0
    }

    #[inline]
    fn children(&mut self, k: usize, i: usize, j: usize, kids: &mut [(f64, usize, usize); 4]) -> usize {
        let t = self.tree;
        let (w, h) = (t.w as i64, t.h as i64);
        let (cw, ch, ref cd) = t.levels[k - 1];
        let mut n = 0;
        for cj in 2 * j..(2 * j + 2).min(ch) {
            for ci in 2 * i..(2 * i + 2).min(cw) {
                let hmax = cd[cj * cw + ci];
                let aux = if t.aux.is_empty() { 0.0 } else { t.aux[k - 1][cj * cw + ci] };
                let shift = k - 1;
                let (x0, x1) = ((ci << shift) as i64, (((ci + 1) << shift) as i64).min(w) - 1);
                let (y0, y1) = ((cj << shift) as i64, (((cj + 1) << shift) as i64).min(h) - 1);
                let (Some(ox), Some(oy)) =
                    (self.ax.min_offset(self.px, x0, x1, w), self.ay.min_offset(self.py, y0, y1, h))
                else {
                    continue;
                };
                let Some(b) = self.s.bound(ox, oy, hmax, aux) else { continue };
                if b >= self.best.0 {
                    continue;
                }
                kids[n] = (b, ci, cj);
                n += 1;
            }
        }
        n
    }

    #[inline]
    fn leaf(&mut self, i: usize, j: usize) {
        let t = self.tree;
        let (w, h) = (t.w as i64, t.h as i64);
        let (Some(sx), Some(sy)) = (self.ax.offset(self.px, i as i64, w), self.ay.offset(self.py, j as i64, h)) else {
            return;
        };
        if let Some(v) = self.s.score(sx, sy, t.height(i, j)) {
            if v < self.best.0 {
                self.best = (v, Some((i, j)));
            }
        }
    }
}

/// One branch-and-bound search over a quadtree (level 0 the leaves, each level halving the
/// one below, rounding up), as [`descend`] drives it: the texel search of [`MaxTree`] and
/// the cell search of `maps::cell` are the two.
pub(crate) trait Descent {
    /// Whether a child whose bound is `b` can no longer hold a score below the best found
    /// so far (the search's pruning test, margin included).
    fn closed(&self, b: f64) -> bool;
    /// The children of node `(i, j)` of level `k ≥ 1` (nodes of level `k − 1`) that may hold
    /// a score below the best, with their bounds, written to the front of `kids` in any
    /// order; returns how many.
    fn children(&mut self, k: usize, i: usize, j: usize, kids: &mut [(f64, usize, usize); 4]) -> usize;
    /// Scores leaf `(i, j)` and keeps it as the best if it scores lower.
    fn leaf(&mut self, i: usize, j: usize);
    /// The level up to which [`descend`] hands a node to [`Descent::block`] instead of
    /// opening it; 0 (the default): none, every node is opened down to its leaves.
    #[inline]
    fn block_level(&self) -> usize {
        0
    }
    /// Visits every leaf under node `(i, j)` of level `k` (`1 ≤ k ≤ block_level`) that may
    /// hold a score below the best, in any order, without the nodes in between.
    #[inline]
    fn block(&mut self, _k: usize, _i: usize, _j: usize) {
        unreachable!("a search with a block level of 0 has no blocks")
    }
}

/// Visits node `(i, j)` of level `k`: a leaf is scored; an inner node's children are visited
/// depth first in increasing order of bound (ties in the order `children` gave them),
/// each unless [`Descent::closed`] by then.
pub(crate) fn descend<D: Descent>(d: &mut D, k: usize, i: usize, j: usize) {
    if k == 0 {
        d.leaf(i, j);
        return;
    }
    if k <= d.block_level() {
        d.block(k, i, j);
        return;
    }
    let mut kids: [(f64, usize, usize); 4] = [(0.0, 0, 0); 4];
    let n = d.children(k, i, j, &mut kids);
    // Insertion sort: at most four children, ties keep their order.
    for a in 1..n {
        let x = kids[a];
        let mut p = a;
        while p > 0 && kids[p - 1].0 > x.0 {
            kids[p] = kids[p - 1];
            p -= 1;
        }
        kids[p] = x;
    }
    for &(b, ci, cj) in &kids[..n] {
        if !d.closed(b) {
            descend(d, k - 1, ci, cj);
        }
    }
}

/// Runs `f(y, row)` for every row in parallel; `row` holds `w * c` values (`c` per texel or
/// per cell).
pub(crate) fn per_row(w: usize, h: usize, c: usize, f: impl Fn(usize, &mut [f32]) + Sync) -> Vec<f32> {
    use rayon::prelude::*;
    let mut out = vec![0.0f32; w * h * c];
    out.par_chunks_mut(w * c).enumerate().for_each(|(y, row)| f(y, row));
    out
}

/// Runs `f(x, y)` for every texel in parallel (rows split over rayon's threads) and collects
/// `C` values per texel, row-major.
pub(crate) fn per_texel<const C: usize>(w: usize, h: usize, f: impl Fn(usize, usize) -> [f32; C] + Sync) -> Vec<f32> {
    use rayon::prelude::*;
    let mut out = vec![0.0f32; w * h * C];
    out.par_chunks_mut(w * C).enumerate().for_each(|(y, row)| {
        for x in 0..w {
            row[x * C..(x + 1) * C].copy_from_slice(&f(x, y));
        }
    });
    out
}

/// A quadtree pyramid over a `w0 × h0` grid: each level halves the size (rounding up) and a
/// node is `combine` over its (up to four) children, starting from `empty`; the last level is
/// 1 × 1. Level 0 is `data`.
pub(crate) fn reduce_pyramid<T: Copy>(
    w0: usize,
    h0: usize,
    data: Vec<T>,
    empty: T,
    combine: fn(T, T) -> T,
) -> Vec<(usize, usize, Vec<T>)> {
    let mut levels = vec![(w0, h0, data)];
    loop {
        let (w, h, ref d) = *levels.last().unwrap();
        if w == 1 && h == 1 {
            break;
        }
        let (nw, nh) = (w.div_ceil(2), h.div_ceil(2));
        let mut nd = vec![empty; nw * nh];
        for y in 0..h {
            for x in 0..w {
                let o = &mut nd[(y / 2) * nw + x / 2];
                *o = combine(*o, d[y * w + x]);
            }
        }
        levels.push((nw, nh, nd));
    }
    levels
}
