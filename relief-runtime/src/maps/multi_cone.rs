//! Multiple cones per texel (Burger 2018, *Cone Normal Stepping*, §3.4):
//! method 1, K stacked cones at different heights (evaluated there as MCNS), and method 2,
//! K piecewise cones (proposed there, never evaluated).
//!
//! Both store K values of `n_z` per texel ([`super::cone_normal::normal_z`], `1` = flat),
//! channel `k` for cone `k`, rounded down (narrower = safe). With `h` the texel's height the
//! K heights used by both methods are
//!
//! ```text
//! b_k = h + (1 - h) k / K,   k = 0..K      (b_0 = h, b_K = 1)
//! ```
//!
//! # Method 1: stacked cones
//!
//! Cone `k` has its apex on the texel's axis at height `b_k` and is the conservative cone of
//! that apex: ratio `min over texels q with h_q > b_k of dist(p, q) / (h_q - b_k)`
//! (`+inf` if none). Cone 0 is the ordinary cone map. Each cone is free of texel samples, so
//! their union is too; a ray point at height `z` above the texel may use any cone with
//! `b_k <= z` and takes the one giving the longest step (Burger: "the cone that will lead to
//! the largest step or largest distance"). A higher apex sees fewer obstacles, so the upper
//! cones are wider.
//!
//! # Method 2: piecewise cones
//!
//! One surface of revolution `rho = R(z)` made of K straight pieces: piece `k` spans heights
//! `[b_k, b_{k+1}]` with slope `r_k` (horizontal per vertical), `R(b_0) = 0`,
//! `R(b_{k+1}) = R(b_k) + r_k (b_{k+1} - b_k)`. The region `rho <= R(z)` must contain no texel
//! column `{q} x [0, h_q]`, i.e. `R(z) <= dist(p, q)` for every `q` with `h_q > z`. Chosen
//! greedily from the bottom (each piece as wide as the pieces below allow):
//!
//! ```text
//! r_k = min over q with h_q > b_k of (dist(p, q) - R(b_k)) / (min(h_q, b_{k+1}) - b_k)
//! ```
//!
//! (clamped at 0; `+inf` if there is no such `q`, and then all later pieces are `+inf` too).
//! Piece 0 is at least as wide as the conservative cone, since it only has to clear the
//! surface up to `b_1`. The shader rebuilds `R` from the stored slopes; rounding every slope
//! down only narrows the whole profile.
//!
//! # Algorithm and complexity
//!
//! K max-quadtree branch-and-bound searches per texel (the bound of a region is the score with
//! its smallest distance and its largest height, clipped at `b_{k+1}` for method 2), so K times
//! the cost of [`super::cone`]: Θ(K N² log N) on typical maps.

use super::search::{texel_distance, Axis, MaxTree, Scorer};
use crate::heightmap::{EdgeMode, HeightMap};

/// The heights `b_k` (k = 0..=K) for a texel of height `h`.
pub fn cone_heights(h: f32, k_cones: usize) -> Vec<f64> {
    let h = h as f64;
    (0..=k_cones).map(|k| h + (1.0 - h) * k as f64 / k_cones as f64).collect()
}

/// Method 1: K stacked cones per texel as `n_z`, interleaved (K channels), row-major.
pub fn stacked_cone_normals(map: &HeightMap, edge: EdgeMode, k_cones: usize) -> Vec<f32> {
    let tree = MaxTree::new(map);
    let (w, h) = (map.width, map.height);
    let mut out = vec![0.0f32; w * h * k_cones];
    use rayon::prelude::*;
    out.par_chunks_mut(w * k_cones).enumerate().for_each(|(y, row)| {
        for x in 0..w {
            let b = cone_heights(map.data[y * w + x], k_cones);
            for k in 0..k_cones {
                let r = super::cone::ratio_at(&tree, map, edge, x, y, b[k]);
                row[x * k_cones + k] = super::cone_normal::normal_z(super::encode::f32_down(r));
            }
        }
    });
    out
}

struct PieceScorer {
    lo: f64,
    hi: f64,
    radius: f64,
    w: usize,
    h: usize,
}

impl Scorer for PieceScorer {
    #[inline]
    fn bound(&self, ox: i64, oy: i64, hmax: f32, _aux: f32) -> Option<f64> {
        let dh = (hmax as f64).min(self.hi) - self.lo;
        (hmax as f64 > self.lo && dh > 0.0)
            .then(|| (texel_distance(ox, oy, self.w, self.h) - self.radius).max(0.0) / dh)
    }
    #[inline]
    fn score(&self, sx: i64, sy: i64, hq: f32) -> Option<f64> {
        let dh = (hq as f64).min(self.hi) - self.lo;
        (hq as f64 > self.lo && dh > 0.0).then(|| (texel_distance(sx, sy, self.w, self.h) - self.radius).max(0.0) / dh)
    }
}

/// The piecewise slopes `r_k` (f64, before rounding) of texel `(x, y)`; used by the generator
/// and handy for checking.
pub(crate) fn piecewise_slopes(
    tree: &MaxTree,
    map: &HeightMap,
    edge: EdgeMode,
    x: usize,
    y: usize,
    k_cones: usize,
) -> Vec<f64> {
    let b = cone_heights(map.data[y * map.width + x], k_cones);
    let mut radius = 0.0f64;
    let mut out = Vec::with_capacity(k_cones);
    for k in 0..k_cones {
        if radius.is_infinite() {
            out.push(f64::INFINITY);
            continue;
        }
        let s = PieceScorer { lo: b[k], hi: b[k + 1], radius, w: map.width, h: map.height };
        let r = tree.search_min(x, y, Axis::both(edge), Axis::both(edge), &s, f64::INFINITY);
        // Later pieces start from the radius the shader will rebuild from rounded slopes.
        let r_stored = super::encode::f32_down(r) as f64;
        radius += r_stored * (b[k + 1] - b[k]);
        out.push(r);
    }
    out
}

/// Method 2: K piecewise cone slopes per texel as `n_z`, interleaved (K channels), row-major.
pub fn piecewise_cone_normals(map: &HeightMap, edge: EdgeMode, k_cones: usize) -> Vec<f32> {
    let tree = MaxTree::new(map);
    let (w, h) = (map.width, map.height);
    let mut out = vec![0.0f32; w * h * k_cones];
    use rayon::prelude::*;
    out.par_chunks_mut(w * k_cones).enumerate().for_each(|(y, row)| {
        for x in 0..w {
            let r = piecewise_slopes(&tree, map, edge, x, y, k_cones);
            for k in 0..k_cones {
                row[x * k_cones + k] = super::cone_normal::normal_z(super::encode::f32_down(r[k]));
            }
        }
    });
    out
}
