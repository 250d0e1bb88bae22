//! Relaxed cone map (Policarpo & Oliveira, *Relaxed Cone Stepping for Relief Mapping*,
//! GPU Gems 3 ch. 18.4.1, Listings 18-1 and 18-2, paper 001).
//!
//! # Definition
//!
//! A relaxed cone may be pierced by the surface, as long as a ray travelling inside it
//! crosses into the surface at most once. Listing 18-1 builds it from rays: from the point at
//! the top of the volume above the source texel `p`, `A = (p, 1)`, shoot a ray through the
//! surface point `B = (q, h_q)` of every destination texel `q`; follow the ray past `B` to
//! the point `E` where it is outside the surface again; `E` must not lie inside the cone, so
//! the ratio is at most `dist(p, E) / (z_E - h_p)` whenever `E` is above `h_p`.
//!
//! This module uses the texel-exact form of that rule. An exit point `E` is where the ray
//! passes from inside to outside, which happens at a surface point behind which the surface
//! falls away faster than the ray descends. Taking the exit points at texel samples:
//!
//! ```text
//! r(p) = min over texels q with h_q > h_p and exit(p, q) of  dist(p, q) / (h_q - h_p)
//! exit(p, q):  S(q + δ e) < h_q - δ (1 - h_q) / dist(p, q)
//! ```
//!
//! where `e` is the unit horizontal direction from `p` to `q` (shorter way round with
//! [`EdgeMode::Repeat`]), `δ = 1 / max(width, height)` (one texel), `S` the bilinear surface
//! (with the edge mode) and the right-hand side the height of the ray from `A` through `B`
//! one texel past `B`. In words: `q` constrains the cone when the ray that grazes `q` from
//! above `p` is outside the surface just beyond `q`. A texel on a slope facing `p` (the ray
//! goes on into the surface) does not constrain it; that is where the relaxed cone gains over
//! the conservative one, which takes every higher texel. The constraint set is a subset of the
//! conservative one, so `relaxed >= conservative` texel by texel (exactly, same arithmetic).
//! Where Listing 18-2 marches 128 fixed steps and samples bilinearly, this rule looks at each
//! texel, so the result does not depend on a step count. No constraining texel: `+inf`
//! (Listing 18-1 starts from 1.0 only because its output is an 8-bit texture; here only an
//! encoding clamps). Ratios are rounded down to f32.
//!
//! # Algorithm and complexity
//!
//! The constraint is the conservative cone's constraint restricted to exit texels, so the
//! conservative bound `dist / (max height - h_p)` still bounds every region, and the same
//! max-quadtree branch and bound as [`super::cone`] applies; at each surviving texel the exit
//! test costs one bilinear sample. The relaxed cones are wider, so more of the tree is opened
//! than for the conservative map; typical cost Θ(N² log N) with a larger constant; worst case
//! Θ(N⁴). Parallel over rows with rayon.

use super::search::{texel_distance, Axis, MaxTree, Scorer};
use crate::heightmap::{EdgeMode, HeightMap};

struct RelaxedScorer<'a> {
    map: &'a HeightMap,
    edge: EdgeMode,
    h0: f64,
    /// Texture coordinates of the source texel.
    u0: f64,
    v0: f64,
}

impl Scorer for RelaxedScorer<'_> {
    #[inline]
    fn bound(&self, ox: i64, oy: i64, hmax: f32) -> Option<f64> {
        let dh = hmax as f64 - self.h0;
        (dh > 0.0).then(|| texel_distance(ox, oy, self.map.width, self.map.height) / dh)
    }
    #[inline]
    fn score(&self, sx: i64, sy: i64, hq: f32) -> Option<f64> {
        let dh = hq as f64 - self.h0;
        if dh <= 0.0 {
            return None;
        }
        let d = texel_distance(sx, sy, self.map.width, self.map.height);
        exits(self.map, self.edge, self.u0, self.v0, sx, sy, hq).then(|| d / dh)
    }
}

/// The exit test of the module docs: is the ray from `(u0, v0, 1)` through the surface point of
/// the texel at signed offset `(sx, sy)` (height `hq`) outside the surface one texel beyond it?
pub fn exits(map: &HeightMap, edge: EdgeMode, u0: f64, v0: f64, sx: i64, sy: i64, hq: f32) -> bool {
    let (w, h) = (map.width as f64, map.height as f64);
    let d = texel_distance(sx, sy, map.width, map.height);
    if d == 0.0 {
        return false;
    }
    let (du, dv) = (sx as f64 / w, sy as f64 / h);
    let delta = 1.0 / w.max(h);
    let (eu, ev) = (du / d, dv / d);
    let hq = hq as f64;
    let ray = hq - delta * (1.0 - hq) / d;
    let s = map.bilinear(u0 + du + delta * eu, v0 + dv + delta * ev, edge);
    s < ray
}

/// Relaxed cone ratios, one per texel, row-major (see the module docs).
pub fn relaxed_cone_ratios(map: &HeightMap, edge: EdgeMode) -> Vec<f32> {
    let tree = MaxTree::new(map);
    let (w, h) = (map.width, map.height);
    super::search::per_texel::<1>(w, h, |x, y| {
        let s = RelaxedScorer {
            map,
            edge,
            h0: map.data[y * w + x] as f64,
            u0: (x as f64 + 0.5) / w as f64,
            v0: (y as f64 + 0.5) / h as f64,
        };
        let seed = super::cone::neighbour_seed(map, edge, x, y, &s);
        let r = tree.search_min(x, y, Axis::both(edge), Axis::both(edge), &s, seed);
        [super::encode::f32_down(r)]
    })
}
