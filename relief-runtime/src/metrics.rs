//! Metrics of one run, under the names used in every results file.
//!
//! Accuracy is measured on the probe's hits against the exact reference for the *same* rays;
//! speed on the render entry's frame times.

use serde::{Deserialize, Serialize};

use crate::gpu::GpuHit;
use crate::heightmap::{EdgeMode, HeightMap};
use crate::reference::RefHit;
use crate::scene::ProbeRay;

/// One run's metrics (the names are the column names of results files).
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct Metrics {
    pub pipeline: String,
    pub scene: String,
    pub size: u32,
    pub adapter: String,
    pub frame_ms_median: f64,
    /// Mean frame time over the timed frames (the dissertation reports the mean of 500).
    #[serde(default)]
    pub frame_ms_mean: f64,
    pub frame_ms_p10: f64,
    pub frame_ms_p90: f64,
    /// Burger 2018 §4.1: Σ over pixels of (h(hit.uv) − hit.z)², summed as the dissertation
    /// reports it.
    pub mse_dissertation: f64,
    /// The same, divided by the number of rays.
    pub mse_dissertation_mean: f64,
    /// RMS of (t − t_ref) over rays both hit.
    pub ref_err_t_rms: f64,
    /// RMS distance between hit and reference hit in texels.
    pub ref_err_uv_texels_rms: f64,
    /// Share of rays whose hit lies beyond the true first hit by more than one texel of
    /// travel, or that report no (finite) hit where the reference hits.
    pub missed_rate: f64,
    /// Hits with NaN or Inf anywhere.
    pub nan_count: u64,
    /// Hits whose raw t lies outside the volume (`t < 0` or `t > t_max`), counted before any
    /// clamp.
    #[serde(default)]
    pub outside_count: u64,
    /// Share of rays whose coarse search ran out of steps without finding the surface.
    #[serde(default)]
    pub nonconverged_rate: f64,
    /// Loop passes of the coarse search per ray (the dissertation's "avg steps").
    #[serde(default)]
    pub avg_coarse_steps: f64,
    /// Loop passes of the refine search per ray.
    #[serde(default)]
    pub avg_refine_steps: f64,
    /// Loop passes over all stages per ray (coarse + refine).
    pub avg_iterations: f64,
    /// Texture fetches per ray over all stages.
    pub avg_fetches: f64,
}

/// Percentile `q` in [0, 1] of `xs` (nearest rank on the sorted values).
pub fn percentile(xs: &[f64], q: f64) -> f64 {
    if xs.is_empty() {
        return f64::NAN;
    }
    let mut v = xs.to_vec();
    v.sort_by(f64::total_cmp);
    let i = ((v.len() - 1) as f64 * q).round() as usize;
    v[i]
}

/// One texel of travel: the t it takes `ray` to cross one texel horizontally on a map of
/// `texels` texels a side. A hit further than that past the true first hit has missed
/// geometry (the `missed_rate` criterion).
pub fn one_texel_t(ray: &ProbeRay, texels: f64) -> f64 {
    let horizontal = ((ray.dir[0] as f64).powi(2) + (ray.dir[1] as f64).powi(2)).sqrt();
    1.0 / (texels * horizontal.max(1e-9))
}

/// Fills the frame-time fields from per-frame milliseconds.
pub fn set_timing(m: &mut Metrics, frame_ms: &[f64]) {
    m.frame_ms_median = percentile(frame_ms, 0.5);
    m.frame_ms_mean = if frame_ms.is_empty() { f64::NAN } else { frame_ms.iter().sum::<f64>() / frame_ms.len() as f64 };
    m.frame_ms_p10 = percentile(frame_ms, 0.1);
    m.frame_ms_p90 = percentile(frame_ms, 0.9);
}

/// The accuracy fields, from the probe's hits and the reference hits of the same rays, on
/// the surface the shader samples (`heights`, bilinear, with `edge`).
pub fn set_accuracy(m: &mut Metrics, rays: &[ProbeRay], hits: &[GpuHit], refs: &[Option<RefHit>], heights: &HeightMap, edge: EdgeMode) {
    let n = hits.len().min(rays.len()).min(refs.len());
    let texels = heights.width.max(heights.height) as f64;
    let (mut sq_sum, mut t_sq, mut uv_sq, mut both) = (0.0, 0.0, 0.0, 0usize);
    let (mut missed, mut nans, mut iters, mut fetches) = (0usize, 0u64, 0u64, 0u64);
    for i in 0..n {
        let (r, h) = (&rays[i], &hits[i]);
        iters += h.iterations as u64;
        fetches += h.fetches as u64;
        let finite = [h.t, h.u, h.v, h.z].iter().all(|x| x.is_finite());
        if !finite {
            nans += 1;
            if refs[i].is_some() {
                missed += 1;
            }
            continue;
        }
        let e = heights.bilinear(h.u as f64, h.v as f64, edge) - h.z as f64;
        sq_sum += e * e;
        if let Some(rh) = refs[i] {
            both += 1;
            let dt = h.t as f64 - rh.t;
            t_sq += dt * dt;
            let (du, dv) = (h.u as f64 - rh.u, h.v as f64 - rh.v);
            uv_sq += (du * du + dv * dv) * texels * texels;
            if dt > one_texel_t(r, texels) {
                missed += 1;
            }
        }
    }
    m.mse_dissertation = sq_sum;
    m.mse_dissertation_mean = if n > 0 { sq_sum / n as f64 } else { 0.0 };
    m.ref_err_t_rms = if both > 0 { (t_sq / both as f64).sqrt() } else { 0.0 };
    m.ref_err_uv_texels_rms = if both > 0 { (uv_sq / both as f64).sqrt() } else { 0.0 };
    m.missed_rate = if n > 0 { missed as f64 / n as f64 } else { 0.0 };
    m.nan_count = nans;
    m.avg_iterations = if n > 0 { iters as f64 / n as f64 } else { 0.0 };
    m.avg_fetches = if n > 0 { fetches as f64 / n as f64 } else { 0.0 };
}
