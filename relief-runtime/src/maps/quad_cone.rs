//! Quad-directional cone map (QCSM; Policarpo & Oliveira 2007, GPU Gems 3 ch. 18.4.1 and
//! Figure 18-8b; Burger 2018 §2.4).
//!
//! # Definition
//!
//! Four conservative cone ratios per texel, one per quadrant of horizontal ray directions.
//! A ray whose horizontal direction `(du, dv)` has `du >= 0, dv >= 0` can only reach texels
//! whose offset from the current texel lies in the closed quadrant `u >= 0, v >= 0`, so its
//! cone only has to avoid those texels. Channel order:
//!
//! | channel | quadrant of the ray direction |
//! | --- | --- |
//! | 0 | `+u, +v` |
//! | 1 | `-u, +v` |
//! | 2 | `-u, -v` |
//! | 3 | `+u, -v` |
//!
//! Each channel is `min dist / (h_q - h_p)` over the higher texels `q` of that closed
//! quadrant (texels on an axis belong to both neighbouring quadrants, so a ray exactly along
//! an axis may use either channel). A shader picks the channel from the signs of the ray
//! direction. With [`EdgeMode::Repeat`] the quadrant is followed around the torus the way the
//! ray goes: the offset to `q` is `(q - p) mod n` for a `+` axis and `(p - q) mod n` for a `-`
//! axis (a ray heading `+u` meets the copy of `q` ahead of it, not the one behind). With
//! [`EdgeMode::Clamp`] offsets are plain differences and texels outside the quadrant are
//! ignored. No higher texel in the quadrant: `+inf`. Ratios are rounded down to f32.
//! Every channel is at least the isotropic [`super::cone`] ratio.
//!
//! # Algorithm and complexity
//!
//! The same max-quadtree branch and bound as [`super::cone`], with the distance bound of a
//! region measured inside the quadrant only (regions outside it are skipped): four searches
//! per texel, Θ(N² log N) on typical maps, bit-identical to brute force.

use super::cone::ConeScorer;
use super::search::{Axis, MaxTree};
use crate::heightmap::{EdgeMode, HeightMap};

/// The axes of the four quadrants, in channel order.
pub(crate) fn quadrant_axes(edge: EdgeMode) -> [(Axis, Axis); 4] {
    let wrap = edge == EdgeMode::Repeat;
    let (f, b) = (Axis::Forward { wrap }, Axis::Backward { wrap });
    [(f, f), (b, f), (b, b), (f, b)]
}

/// Quad cone ratios: 4 channels per texel, interleaved, row-major.
pub fn quad_cone_ratios(map: &HeightMap, edge: EdgeMode) -> Vec<f32> {
    let tree = MaxTree::new(map);
    let axes = quadrant_axes(edge);
    super::search::per_texel::<4>(map.width, map.height, |x, y| {
        let s = ConeScorer { apex: map.data[y * map.width + x] as f64, w: map.width, h: map.height };
        axes.map(|(ax, ay)| super::encode::f32_down(tree.search_min(x, y, ax, ay, &s, f64::INFINITY)))
    })
}
