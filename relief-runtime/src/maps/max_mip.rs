//! Conservative image pyramids: maximum mipmaps (empty-space skipping over a height field)
//! and minimum mipmaps (conservative mip-mapping of cone maps).
//!
//! # Sources
//!
//! - Tevs, Ihrke & Seidel 2008, *Maximum Mipmaps for Fast, Accurate, and Scalable Dynamic
//!   Height Field Rendering* (I3D 2008): a mip chain whose every texel holds the **maximum**
//!   of the heights below it, so a ray that stays above a node's value over the node's
//!   footprint can skip the whole footprint. (Not in `/work/shared/papers`; the idea is the
//!   pyramidal scheme of Oh & Ki 2006 as surveyed by Szirmay-Kalos & Umenhoffer 2008,
//!   *Displacement Mapping on the GPU*, section 4.3.3 "Pyramidal displacement mapping",
//!   which stores the complementary minimum *difference* to the top.)
//! - Policarpo & Oliveira 2007, *Relaxed Cone Stepping* (GPU Gems 3 ch. 18, the
//!   paragraph on mip-mapping): cone maps must not be filtered linearly; a coarser level must
//!   take the **minimum** over each group of texels so it never promises more empty space than
//!   any texel below it. [`min_mip`] builds exactly that.
//!
//! # Layout (GPU-compatible)
//!
//! Level `L` has `max(1, w >> L) x max(1, h >> L)` entries, the same sizes as a full wgpu
//! mip chain of a `w x h` texture, and there are `floor(log2(max(w, h))) + 1` levels. Entry `n`
//! of level `L` covers the level-0 indices `[n << L, (n + 1) << L)`; the **last** entry of a
//! row (or column) also covers the odd remainder up to `w` (or `h`), so nothing is dropped when
//! a size is odd. A shader finds the node above level-0 index `i` as `min(i >> L, size_L - 1)`.
//!
//! Level 0 is either the texels themselves ([`max_mip`], [`min_mip`]) or the *cells* of the
//! bilinear surface (`cell_max_mip`): cell `(i, j)` is the square between the texel centres
//! `(i, j)`, `(i + 1, j)`, `(i, j + 1)`, `(i + 1, j + 1)`; a bilinear patch never exceeds its
//! largest corner, so the maximum of the four corners bounds the whole cell.

use crate::heightmap::{EdgeMode, HeightMap};

/// How four (or more) children combine into their parent.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Reducer {
    /// Parent = largest child (maximum mipmaps: a conservative upper bound on height).
    Max,
    /// Parent = smallest child (conservative cone-map mip-mapping).
    Min,
}

impl Reducer {
    /// Combines two values.
    #[inline]
    pub fn apply(self, a: f32, b: f32) -> f32 {
        match self {
            Reducer::Max => a.max(b),
            Reducer::Min => a.min(b),
        }
    }
}

/// One level of a pyramid: `w * h` values, row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct Level {
    /// Entries per row: `max(1, width >> L)` at level `L`.
    pub w: usize,
    /// Rows: `max(1, height >> L)` at level `L`.
    pub h: usize,
    /// Each entry the maximum (or minimum) of the level-0 entries it covers.
    pub data: Vec<f32>,
}

impl Level {
    /// The value at `(x, y)`; both must be in range.
    #[inline]
    pub fn get(&self, x: usize, y: usize) -> f32 {
        self.data[y * self.w + x]
    }
}

/// A pyramid node found from an unbounded level-0 index: its value and the half-open range
/// `[x0, x1) x [y0, y1)` of level-0 indices it stands for, in the same unbounded index space.
///
/// With [`EdgeMode::Clamp`] the first and last nodes of a row stand for everything beyond the
/// map as well; their open ends are `Node::UNBOUNDED` (negated for the lower end).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node {
    /// The node's entry: the maximum (or minimum) over its range.
    pub value: f32,
    /// First level-0 column of the range (inclusive); can be negative.
    pub x0: i64,
    /// End of the column range (exclusive).
    pub x1: i64,
    /// First level-0 row of the range (inclusive); can be negative.
    pub y0: i64,
    /// End of the row range (exclusive).
    pub y1: i64,
}

impl Node {
    /// Stands for "no end" in clamp mode (exactly representable in f64, far from overflow).
    pub(crate) const UNBOUNDED: i64 = 1 << 52;
}

/// A 2D conservative pyramid (see the module docs for the layout).
#[derive(Clone, Debug, PartialEq)]
pub struct Pyramid {
    /// Level 0 first, the single-entry (or single-row) top last.
    pub levels: Vec<Level>,
    /// How the levels were reduced.
    pub reducer: Reducer,
}

impl Pyramid {
    /// Builds every level from level-0 data (`width * height` values, row-major).
    pub fn build(width: usize, height: usize, data: Vec<f32>, reducer: Reducer) -> Pyramid {
        assert!(width > 0 && height > 0, "pyramid of an empty image");
        assert_eq!(data.len(), width * height, "pyramid level 0 has the wrong length");
        let mut levels = vec![Level { w: width, h: height, data }];
        while {
            let l = levels.last().unwrap();
            l.w > 1 || l.h > 1
        } {
            let next = reduce(levels.last().unwrap(), reducer);
            levels.push(next);
        }
        Pyramid { levels, reducer }
    }

    /// Number of levels (a full mip chain's `mip_level_count`).
    pub fn level_count(&self) -> usize {
        self.levels.len()
    }

    /// Index of the coarsest level.
    pub fn top(&self) -> usize {
        self.levels.len() - 1
    }

    /// Level 0's width and height.
    pub fn size(&self) -> (usize, usize) {
        (self.levels[0].w, self.levels[0].h)
    }

    /// The node of `level` that covers the (unbounded) level-0 index `(x, y)`, with indices
    /// outside the map resolved by `edge`: `Repeat` wraps (the node's range is shifted to the
    /// copy of the map that holds `(x, y)`), `Clamp` maps them to the border nodes, whose
    /// ranges then extend without end.
    pub fn node(&self, level: usize, x: i64, y: i64, edge: EdgeMode) -> Node {
        let lv = &self.levels[level];
        let (w, h) = self.size();
        let (nx, x0, x1) = axis(level, x, w, lv.w, edge);
        let (ny, y0, y1) = axis(level, y, h, lv.h, edge);
        Node { value: lv.get(nx, ny), x0, x1, y0, y1 }
    }
}

/// Resolves one axis: node index in the level, and the unbounded level-0 range it covers.
fn axis(level: usize, i: i64, n0: usize, nl: usize, edge: EdgeMode) -> (usize, i64, i64) {
    let n0i = n0 as i64;
    let (base, local) = match edge {
        EdgeMode::Repeat => (i.div_euclid(n0i) * n0i, i.rem_euclid(n0i)),
        EdgeMode::Clamp => (0, i.clamp(0, n0i - 1)),
    };
    let node = ((local >> level) as usize).min(nl - 1);
    let mut lo = base + ((node as i64) << level);
    let mut hi = if node == nl - 1 { base + n0i } else { base + ((node as i64 + 1) << level) };
    if edge == EdgeMode::Clamp {
        if node == 0 {
            lo = -Node::UNBOUNDED;
        }
        if node == nl - 1 {
            hi = Node::UNBOUNDED;
        }
    }
    (node, lo, hi)
}

/// One reduction step: sizes halve (rounding down, never below 1); the last row/column of
/// the parent also takes the odd leftover child.
fn reduce(src: &Level, r: Reducer) -> Level {
    let w = (src.w / 2).max(1);
    let h = (src.h / 2).max(1);
    let span = |n: usize, size: usize, src_size: usize| -> (usize, usize) {
        let lo = (2 * n).min(src_size - 1);
        let hi = if n == size - 1 { src_size } else { (2 * n + 2).min(src_size) };
        (lo, hi)
    };
    let mut data = Vec::with_capacity(w * h);
    for y in 0..h {
        let (ya, yb) = span(y, h, src.h);
        for x in 0..w {
            let (xa, xb) = span(x, w, src.w);
            let mut acc = src.get(xa, ya);
            for sy in ya..yb {
                for sx in xa..xb {
                    acc = r.apply(acc, src.get(sx, sy));
                }
            }
            data.push(acc);
        }
    }
    Level { w, h, data }
}

/// Maximum mipmap over the texels (Tevs et al. 2008): level 0 = the heights themselves.
/// Exact bound for nearest-texel sampling; for bilinear sampling use `cell_max_mip`.
pub fn max_mip(map: &HeightMap) -> Pyramid {
    Pyramid::build(map.width, map.height, map.data.clone(), Reducer::Max)
}

/// Minimum mipmap of any per-texel quantity (cone ratios, distances): every coarser entry is
/// the smallest value below it (Policarpo & Oliveira 2007, GPU Gems 3 ch. 18).
pub fn min_mip(width: usize, height: usize, data: &[f32]) -> Pyramid {
    Pyramid::build(width, height, data.to_vec(), Reducer::Min)
}

/// The level-0 values of a pyramid over the cells of the bilinear surface: cell `(i, j)`
/// reduces the four texels `(i..=i+1, j..=j+1)`, resolved with `edge` (so with `Repeat` the
/// last cell wraps to texel 0, with `Clamp` it is the flat half-texel border strip).
///
/// With `Clamp`, cells left of 0 (or below 0) have corners drawn only from column (row) 0,
/// which cell 0 already bounds; [`Pyramid::node`] maps them there, so the bound stays
/// conservative everywhere on the infinite clamped surface.
pub(crate) fn cell_values(map: &HeightMap, edge: EdgeMode, reducer: Reducer) -> Vec<f32> {
    let (w, h) = (map.width, map.height);
    let mut data = Vec::with_capacity(w * h);
    for y in 0..h as i64 {
        for x in 0..w as i64 {
            let a = reducer.apply(map.texel(x, y, edge), map.texel(x + 1, y, edge));
            let b = reducer.apply(map.texel(x, y + 1, edge), map.texel(x + 1, y + 1, edge));
            data.push(reducer.apply(a, b));
        }
    }
    data
}

/// Maximum mipmap over the cells of the bilinear surface (Tevs et al. 2008 build it this way
/// for their bilinear patches): every node bounds the bilinear surface over its footprint.
/// Level-0 index `i` is the cell between texel centres `i` and `i + 1`, i.e. texture
/// coordinate `u` lies in cell `floor(u * width - 0.5)`.
pub(crate) fn cell_max_mip(map: &HeightMap, edge: EdgeMode) -> Pyramid {
    Pyramid::build(map.width, map.height, cell_values(map, edge, Reducer::Max), Reducer::Max)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Deterministic pseudo-random heights.
    fn noise(w: usize, h: usize, seed: u64) -> HeightMap {
        let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
        HeightMap::from_fn(w, h, |_, _| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 40) as f32 / (1u64 << 24) as f32
        })
    }

    /// Brute-force definition: the node's value is the reduction of every level-0 value in
    /// its (edge-resolved, bounded to the map) range.
    fn brute(p: &Pyramid, level: usize, x: usize, y: usize) -> f32 {
        let (w, h) = p.size();
        let n = p.node(level, x as i64, y as i64, EdgeMode::Repeat);
        let l0 = &p.levels[0];
        let mut acc = None::<f32>;
        for yy in n.y0.max(0)..n.y1.min(h as i64) {
            for xx in n.x0.max(0)..n.x1.min(w as i64) {
                let v = l0.get(xx as usize, yy as usize);
                acc = Some(acc.map_or(v, |a| p.reducer.apply(a, v)));
            }
        }
        acc.unwrap()
    }

    #[test]
    fn sizes_follow_the_gpu_mip_chain() {
        for &(w, h) in &[(1, 1), (2, 2), (256, 256), (5, 3), (7, 1), (1, 9), (300, 17)] {
            let p = max_mip(&noise(w, h, 1));
            let max = w.max(h);
            assert_eq!(p.level_count(), (usize::BITS - max.leading_zeros()) as usize);
            for (l, lv) in p.levels.iter().enumerate() {
                assert_eq!((lv.w, lv.h), ((w >> l).max(1), (h >> l).max(1)), "{w}x{h} level {l}");
                assert_eq!(lv.data.len(), lv.w * lv.h);
            }
        }
    }

    #[test]
    fn every_node_is_the_reduction_of_its_footprint() {
        for &(w, h) in &[(8, 8), (5, 3), (13, 7), (1, 6), (33, 32)] {
            let m = noise(w, h, w as u64 * 31 + h as u64);
            for p in [max_mip(&m), min_mip(w, h, &m.data)] {
                for l in 0..p.level_count() {
                    for y in 0..h {
                        for x in 0..w {
                            let n = p.node(l, x as i64, y as i64, EdgeMode::Repeat);
                            assert!(n.x0 <= x as i64 && (x as i64) < n.x1);
                            assert!(n.y0 <= y as i64 && (y as i64) < n.y1);
                            assert_eq!(n.value, brute(&p, l, x, y), "{w}x{h} l{l} ({x},{y})");
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn top_is_global_max_or_min() {
        let m = noise(37, 21, 5);
        let mx = m.data.iter().cloned().fold(f32::MIN, f32::max);
        let mn = m.data.iter().cloned().fold(f32::MAX, f32::min);
        assert_eq!(max_mip(&m).levels.last().unwrap().data, vec![mx]);
        assert_eq!(min_mip(37, 21, &m.data).levels.last().unwrap().data, vec![mn]);
    }

    #[test]
    fn repeat_nodes_wrap_to_the_copy_that_holds_the_index() {
        let p = max_mip(&noise(8, 8, 2));
        let a = p.node(1, 3, 5, EdgeMode::Repeat);
        let b = p.node(1, 3 - 16, 5 + 8, EdgeMode::Repeat);
        assert_eq!(a.value, b.value);
        assert_eq!((b.x0, b.x1, b.y0, b.y1), (a.x0 - 16, a.x1 - 16, a.y0 + 8, a.y1 + 8));
        let top = p.node(p.top(), -1, 0, EdgeMode::Repeat);
        assert_eq!((top.x0, top.x1), (-8, 0));
    }

    #[test]
    fn clamp_border_nodes_extend_without_end() {
        let m = noise(8, 8, 3);
        let p = max_mip(&m);
        let n = p.node(0, -5, 20, EdgeMode::Clamp);
        assert_eq!(n.value, m.texel(0, 7, EdgeMode::Clamp));
        assert_eq!((n.x0, n.x1), (-Node::UNBOUNDED, 1));
        assert_eq!((n.y0, n.y1), (7, Node::UNBOUNDED));
        let inner = p.node(0, 3, 4, EdgeMode::Clamp);
        assert_eq!((inner.x0, inner.x1, inner.y0, inner.y1), (3, 4, 4, 5));
    }

    /// The cell pyramid bounds the bilinear surface everywhere, including past the edges.
    #[test]
    fn cell_max_mip_bounds_the_bilinear_surface() {
        let (w, h) = (9, 6);
        let m = noise(w, h, 4);
        for edge in [EdgeMode::Repeat, EdgeMode::Clamp] {
            let p = cell_max_mip(&m, edge);
            for k in 0..4000 {
                // Sample points on a grid that runs well past [0, 1].
                let u = -1.0 + 3.0 * ((k * 7919) % 4000) as f64 / 4000.0;
                let v = -1.0 + 3.0 * ((k * 104729) % 3989) as f64 / 3989.0;
                let s = m.bilinear(u, v, edge);
                let cx = (u * w as f64 - 0.5).floor() as i64;
                let cy = (v * h as f64 - 0.5).floor() as i64;
                for l in 0..p.level_count() {
                    let n = p.node(l, cx, cy, edge);
                    assert!(n.x0 <= cx && cx < n.x1 && n.y0 <= cy && cy < n.y1);
                    assert!(s <= n.value as f64 + 1e-6, "{edge:?} l{l} u{u} v{v}: {s} > {}", n.value);
                }
            }
            // Repeat: the cell pyramid's level 0 is exactly the max of the four corners.
            if edge == EdgeMode::Repeat {
                assert_eq!(
                    p.levels[0].get(w - 1, h - 1),
                    m.texel(w as i64 - 1, h as i64 - 1, edge)
                        .max(m.texel(0, h as i64 - 1, edge))
                        .max(m.texel(w as i64 - 1, 0, edge))
                        .max(m.texel(0, 0, edge))
                );
            }
        }
    }
}
