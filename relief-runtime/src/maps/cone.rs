//! Conservative cone map (Dummer 2006, *Cone Step Mapping*; as summarised in GPU Gems 3
//! ch. 18.3 (Policarpo & Oliveira 2007), and Burger 2018 §2.4 eq. 2.7).
//!
//! # Definition
//!
//! Texel `p` (height `h_p`, a point sample at its centre) gets the ratio
//!
//! ```text
//! r(p) = min over texels q with h_q > h_p of  dist(p, q) / (h_q - h_p)
//! ```
//!
//! `dist` is the horizontal distance in texture coordinates (the map spans [0, 1] in u and v,
//! so one texel step is `1 / width` in u and `1 / height` in v); with [`EdgeMode::Repeat`] the
//! offsets wrap and the shorter way round is taken. With [`EdgeMode::Clamp`] the border texels
//! extend outward, but an extended copy is never closer to an inner texel than the border
//! texel itself, so clamp simply means "no wrapping".
//!
//! The cone with apex `(p, h_p)` and this ratio (radius grows by `r` per unit of height) is the
//! widest upward cone that contains no texel sample of the surface.
//!
//! **No higher texel:** `r = +inf` (the cone is the whole half-space above `h_p`: every texel
//! is at most `h_p`, so a ray may drop to `h_p` in one step). The f32 map keeps `+inf`; the
//! encodings clamp it (unorm: to `max_value`; f16 keeps `inf`), and [`super::cone_normal`]
//! turns it into `n_z = 1`.
//!
//! **Rounding:** each ratio is evaluated in f64 and rounded *down* to f32 (never wider than the
//! exact value).
//!
//! **Bilinear surface:** the definition is over the texel samples. A bilinear patch between
//! higher texels can poke through such a cone by up to a fraction of a texel; a tracer that
//! needs a hard guarantee on the bilinear surface pads the step (see the property test in
//! `tests/maps.rs`) or uses [`super::filter::min3x3`].
//!
//! # Algorithm and complexity
//!
//! Branch and bound over a maximum-height quadtree ([`super::search`]): for every texel, first
//! its 8 neighbours give a starting ratio, then the tree is walked from the root, nearest
//! regions first; a region is skipped when its maximum height is not above `h_p`, or when
//! `(smallest distance into it) / (its max height - h_p)` is already no better than the best
//! ratio. Building the tree is Θ(N²) for N² texels; each query costs Θ(log N) descent plus the
//! regions inside the final cone's reach, so Θ(N² log N) on typical maps (worst case Θ(N⁴) on
//! adversarial maps). Texels are processed in parallel with rayon. The result is bit-identical
//! to the brute-force Θ(N⁴) minimum.

use super::search::{texel_distance, Axis, Best, MaxTree, Scorer};
use crate::heightmap::{EdgeMode, HeightMap};

/// Ratio score for an apex at height `apex` (a texel's height, or above it for stacked cones).
pub(crate) struct ConeScorer {
    pub apex: f64,
    pub w: usize,
    pub h: usize,
}

impl Scorer for ConeScorer {
    #[inline]
    fn bound(&self, ox: i64, oy: i64, hmax: f32, _aux: f32) -> Option<f64> {
        let dh = hmax as f64 - self.apex;
        (dh > 0.0).then(|| texel_distance(ox, oy, self.w, self.h) / dh)
    }
    #[inline]
    fn score(&self, sx: i64, sy: i64, hq: f32) -> Option<f64> {
        let dh = hq as f64 - self.apex;
        (dh > 0.0).then(|| texel_distance(sx, sy, self.w, self.h) / dh)
    }
}

/// Smallest score over the 8 neighbours of `(x, y)` (a cheap first bound for the search).
pub(crate) fn neighbour_seed<S: Scorer>(map: &HeightMap, edge: EdgeMode, x: usize, y: usize, s: &S) -> f64 {
    let (w, h) = (map.width as i64, map.height as i64);
    let (ax, ay) = (Axis::both(edge), Axis::both(edge));
    let mut best = f64::INFINITY;
    for dy in -1i64..=1 {
        for dx in -1i64..=1 {
            if dx == 0 && dy == 0 {
                continue;
            }
            let (qx, qy) = (x as i64 + dx, y as i64 + dy);
            if edge == EdgeMode::Clamp && (qx < 0 || qy < 0 || qx >= w || qy >= h) {
                continue;
            }
            let (qx, qy) = (qx.rem_euclid(w), qy.rem_euclid(h));
            let (Some(sx), Some(sy)) = (ax.offset(x as i64, qx, w), ay.offset(y as i64, qy, h)) else {
                continue;
            };
            if let Some(v) = s.score(sx, sy, map.data[(qy * w + qx) as usize]) {
                best = best.min(v);
            }
        }
    }
    best
}

/// The conservative cone ratio of texel `(x, y)` for an apex at height `apex` on its axis.
pub(crate) fn ratio_at(tree: &MaxTree, map: &HeightMap, edge: EdgeMode, x: usize, y: usize, apex: f64) -> f64 {
    let s = ConeScorer { apex, w: map.width, h: map.height };
    let seed = neighbour_seed(map, edge, x, y, &s);
    tree.search_min(x, y, Axis::both(edge), Axis::both(edge), &s, seed)
}

/// The smallest score at texel `(x, y)`, searched from a tight start: the 8 neighbours, and
/// `prev`, the texel that constrained the left neighbour (usually close to ours), which is
/// updated for the next texel of the row.
pub(crate) fn seeded_search<S: Scorer>(
    tree: &MaxTree,
    map: &HeightMap,
    edge: EdgeMode,
    x: usize,
    y: usize,
    s: &S,
    prev: &mut Option<(usize, usize)>,
) -> f64 {
    let (ax, ay) = (Axis::both(edge), Axis::both(edge));
    let mut start: Best = (neighbour_seed(map, edge, x, y, s), None);
    if let Some(v) = prev.and_then(|q| tree.score_of(x, y, q, ax, ay, s)) {
        if v < start.0 {
            start = (v, *prev);
        }
    }
    let best = tree.search_argmin(x, y, ax, ay, s, start);
    if best.1.is_some() {
        *prev = best.1;
    }
    best.0
}

/// Conservative cone ratios, one per texel, row-major (see the module docs).
pub fn cone_ratios(map: &HeightMap, edge: EdgeMode) -> Vec<f32> {
    let tree = MaxTree::new(map);
    super::search::per_row(map.width, map.height, 1, |y, row| {
        let mut prev: Option<(usize, usize)> = None;
        for (x, out) in row.iter_mut().enumerate() {
            let s = ConeScorer { apex: map.data[y * map.width + x] as f64, w: map.width, h: map.height };
            *out = super::encode::f32_down(seeded_search(&tree, map, edge, x, y, &s, &mut prev));
        }
    })
}
