//! Relaxed cone map (Policarpo & Oliveira 2007, *Relaxed Cone Stepping for Relief Mapping*,
//! GPU Gems 3 ch. 18.4.1, Listings 18-1 and 18-2).
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
//! test costs one bilinear sample. A second per-node maximum, the exit rate `g` of
//! `exit_rates`, adds the bound "an exit texel is at least `δ / g` away", and the search starts
//! from the left neighbour's constraining texel. Parallel over rows with rayon.
//!
//! Cost: on rough maps (white noise) close to the conservative map (1024² in about 2 s on
//! 2 loaded cores). On smooth maps the relaxed cones are wide and most higher texels are
//! entries, which the height bound cannot exclude, so the search opens most of the cone's
//! reach: up to Θ(N⁴) in the worst case (6-octave value noise: about 1 s at 256², well over
//! 10 s at 1024²). A faster exact method for smooth maps is open work.

use super::search::{texel_distance, MaxTree, Scorer};
use crate::heightmap::{EdgeMode, HeightMap};

struct RelaxedScorer<'a> {
    map: &'a HeightMap,
    edge: EdgeMode,
    h0: f64,
    /// Texture coordinates of the source texel.
    u0: f64,
    v0: f64,
    delta: f64,
}

/// Per texel `q`, an upper bound of the rate `g(q)` with which the surface can fall away
/// right past `q`, relative to the height left above it: `g = (h_q - min 3x3(q)) / (1 - h_q)`
/// (plus a tiny margin; `+inf` at `h_q = 1`). The bilinear surface within one texel of `q`
/// never goes below the 3×3 minimum, so `exit(p, q)` needs
/// `h_q - min3x3 > δ (1 - h_q) / dist(p, q)`, i.e. `dist(p, q) > δ / g(q)`: exit texels are
/// never closer than `δ / max g` to `p`, which prunes whole regions of gentle slopes.
fn exit_rates(map: &HeightMap, edge: EdgeMode) -> Vec<f32> {
    let (w, h) = (map.width, map.height);
    let mut out = Vec::with_capacity(w * h);
    for y in 0..h as i64 {
        for x in 0..w as i64 {
            let hq = map.texel(x, y, edge);
            let mut lo = hq;
            for dy in -1..=1 {
                for dx in -1..=1 {
                    lo = lo.min(map.texel(x + dx, y + dy, edge));
                }
            }
            let drop = (hq as f64 - lo as f64).max(0.0) + 1e-9;
            let left = 1.0 - hq as f64;
            out.push(if left <= 0.0 { f32::INFINITY } else { super::encode::f32_up(drop / left * (1.0 + 1e-6)) });
        }
    }
    out
}

impl Scorer for RelaxedScorer<'_> {
    #[inline]
    fn bound(&self, ox: i64, oy: i64, hmax: f32, gmax: f32) -> Option<f64> {
        let dh = hmax as f64 - self.h0;
        if dh <= 0.0 {
            return None;
        }
        // An exit texel lies farther than delta / g (see `exit_rates`).
        let d = texel_distance(ox, oy, self.map.width, self.map.height);
        let far = self.delta / gmax as f64 * (1.0 - 1e-6);
        Some(d.max(far) / dh)
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
    let tree = MaxTree::with_aux(map, exit_rates(map, edge));
    let (w, h) = (map.width, map.height);
    let delta = 1.0 / (w.max(h) as f64);
    super::search::per_row(w, h, 1, |y, row| {
        let mut prev: Option<(usize, usize)> = None;
        for (x, out) in row.iter_mut().enumerate() {
            let s = RelaxedScorer {
                map,
                edge,
                h0: map.data[y * w + x] as f64,
                u0: (x as f64 + 0.5) / w as f64,
                v0: (y as f64 + 0.5) / h as f64,
                delta,
            };
            *out = super::encode::f32_down(super::cone::seeded_search(&tree, map, edge, x, y, &s, &mut prev));
        }
    })
}
