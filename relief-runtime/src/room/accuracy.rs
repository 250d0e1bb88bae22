//! Per-wall accuracy of the room probe's hits against the exact reference: for each ray,
//! the wall the host computes ([`Room::wall_ray`], Amaro & Gustafsson 2022, eq. 1–4, in f64) and the first
//! hit on that wall's bilinear surface ([`crate::reference::Reference`] on the heights as
//! the device stores them, edge mode clamp), in the wall's normalized tangent space.

use serde::Serialize;

use super::{PixelRay, Room, RoomHit, WALLS, WALL_NAMES};
use crate::heightmap::{EdgeMode, HeightMap};
use crate::reference::{Reference, ReferenceError, Sampling};

/// Accuracy on one wall.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct WallAccuracy {
    /// The wall's name.
    pub wall: String,
    /// Rays the host sends to this wall.
    pub rays: usize,
    /// Of those, rays the probe sent to another wall.
    pub wall_mismatch: usize,
    /// RMS of |t − t_ref| over the rays both send here.
    pub t_err_rms: f64,
    /// Largest |t − t_ref|.
    pub t_err_max: f64,
    /// Rays that jumped over geometry: after the exact first hit the ray is back above the
    /// wall's surface before its reported hit (`crate::metrics::is_skipped`, the sweep's
    /// `skipped_rate` rule), or the hit is not finite, or on another wall.
    pub skipped: usize,
    /// `skipped / rays`.
    pub skipped_rate: f64,
    /// Rays whose hit lies more than one texel of travel past the exact first hit
    /// (`crate::metrics::is_past`, the sweep's `past_rate` rule), or is not finite, or
    /// on another wall.
    pub past: usize,
    /// `past / rays`.
    pub past_rate: f64,
    /// The old name of `past`, kept beside it (the same count) for one release.
    pub missed: usize,
    /// The old name of `past_rate`, kept beside it (the same value) for one release.
    pub missed_rate: f64,
}

/// The exact hits of `rays` (per ray: the host's wall and the reference hit on it).
pub fn reference_hits(
    room: &Room,
    heights: &[Vec<f32>],
    rays: &[PixelRay],
) -> Result<Vec<(usize, Option<crate::reference::RefHit>)>, ReferenceError> {
    use rayon::prelude::*;
    let refs: Vec<Reference> = (0..WALLS)
        .map(|k| {
            let m = &room.walls[k].height;
            Reference::new(&HeightMap::new(m.width, m.height, heights[k].clone()), EdgeMode::Clamp, Sampling::Bilinear)
        })
        .collect();
    rays.par_iter()
        .map(|r| {
            let wr = room.wall_ray(&r.ray);
            Ok((wr.wall, refs[wr.wall].first_hit(wr.origin, wr.dir)?))
        })
        .collect()
}

/// Per-wall accuracy of `hits` (the probe's, one per ray of `rays`) against `refs`
/// ([`reference_hits`] on the same `heights`, each wall's heights as the device stores them).
pub fn room_accuracy(
    room: &Room,
    heights: &[Vec<f32>],
    rays: &[PixelRay],
    hits: &[RoomHit],
    refs: &[(usize, Option<crate::reference::RefHit>)],
) -> Vec<WallAccuracy> {
    use crate::metrics::{is_past, is_skipped};
    let maps: Vec<HeightMap> = (0..WALLS)
        .map(|k| {
            let m = &room.walls[k].height;
            HeightMap::new(m.width, m.height, heights[k].clone())
        })
        .collect();
    let mut acc: Vec<WallAccuracy> =
        WALL_NAMES.iter().map(|n| WallAccuracy { wall: n.to_string(), ..Default::default() }).collect();
    let mut sq = [0.0f64; WALLS];
    let mut compared = [0usize; WALLS];
    for ((r, h), (k, rf)) in rays.iter().zip(hits).zip(refs) {
        let a = &mut acc[*k];
        a.rays += 1;
        if h.wall as usize != *k {
            a.wall_mismatch += 1;
            a.past += 1;
            a.skipped += 1;
            continue;
        }
        let Some(rf) = rf else { continue };
        let wr = room.wall_ray(&r.ray);
        let t = h.t as f64;
        let err = if t.is_finite() { (t - rf.t).abs() } else { f64::INFINITY };
        let map = &maps[*k];
        let texels = map.width.max(map.height) as f64;
        if !t.is_finite() || is_past(wr.dir, texels, rf.t, t) {
            a.past += 1;
        }
        if !t.is_finite() || is_skipped(map, EdgeMode::Clamp, wr.origin, wr.dir, rf.t, t) {
            a.skipped += 1;
        }
        if err.is_finite() {
            sq[*k] += err * err;
            compared[*k] += 1;
            a.t_err_max = a.t_err_max.max(err);
        } else {
            a.t_err_max = f64::INFINITY;
        }
    }
    for k in 0..WALLS {
        let a = &mut acc[k];
        a.t_err_rms = if compared[k] > 0 { (sq[k] / compared[k] as f64).sqrt() } else { f64::NAN };
        let rate = |n: usize| if a.rays > 0 { n as f64 / a.rays as f64 } else { f64::NAN };
        (a.skipped_rate, a.past_rate) = (rate(a.skipped), rate(a.past));
        (a.missed, a.missed_rate) = (a.past, a.past_rate);
    }
    acc
}
