//! Cone normal maps (Burger 2018, *Cone Normal Stepping*, §3.1-3.3): the cone is
//! stored as the z component of the unit normal of its side instead of its ratio.
//!
//! # Definition
//!
//! Slice a cone of ratio `r` (radius grows by `r` per unit of height, [`super::cone`]) through
//! its axis: the side is the line `rho = r z`. Its unit normal pointing into the cone, in the
//! unscaled (u, v, height) space of the map, is `(-1, r) / sqrt(1 + r²)` in (rho, z), so
//!
//! ```text
//! n_z = r / sqrt(1 + r²)         (r = +inf gives n_z = 1)
//! ```
//!
//! in [0, 1]. Burger's distance estimate for a point at height `h` above the apex is `h n_z`
//! (eq. 3.1) and the cone-plane step is `t = -h n_z / (n . d)` (eq. 3.2). Unlike a clamped
//! ratio, `n_z` represents every angle up to a flat cone (90°, `n_z = 1`): there is no cap.
//! `cone_normal` converts the conservative map ([`super::cone`]), `relaxed_cone_normal` the
//! relaxed one ([`super::relaxed_cone`]). Values are rounded down to f32 (a narrower cone).
//!
//! # Algorithm and complexity
//!
//! One pass over the ratio map: the cost is that of the ratio generator.

use crate::heightmap::{EdgeMode, HeightMap};

/// `n_z` of the side of a cone with ratio `r`, rounded down to f32.
pub fn normal_z(r: f32) -> f32 {
    let r = r as f64;
    if r.is_infinite() {
        return 1.0;
    }
    if r.is_nan() || r <= 0.0 {
        return 0.0;
    }
    super::encode::f32_down(r / (1.0 + r * r).sqrt())
}

/// Conservative cone normals (CNS), one `n_z` per texel.
pub fn cone_normals(map: &HeightMap, edge: EdgeMode) -> Vec<f32> {
    super::cone::cone_ratios(map, edge).into_iter().map(normal_z).collect()
}

/// Relaxed cone normals (RCNS), one `n_z` per texel.
pub fn relaxed_cone_normals(map: &HeightMap, edge: EdgeMode) -> Vec<f32> {
    super::relaxed_cone::relaxed_cone_ratios(map, edge).into_iter().map(normal_z).collect()
}
