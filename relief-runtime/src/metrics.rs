//! Metrics of one run, under the names used in every results file.
//!
//! Accuracy is measured on the probe's hits against the exact reference for the *same* rays;
//! speed on the render entry's frame times.

use crate::heightmap::{EdgeMode, HeightMap};
use crate::reference::RefHit;
use crate::scene::ProbeRay;
use relief_dsl::abi::ProbeHit;

pub use crate::results::Metrics;

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

/// One texel of travel: the t it takes `ray` to cross one texel, horizontally (one texel of
/// a map `texels` texels a side) or vertically (1/`texels` of the depth), whichever comes
/// first. A hit further than that past the true first hit has missed geometry (the
/// `missed_rate` criterion), and the cone tests use the same measure.
pub fn one_texel_t(ray: &ProbeRay, texels: f64) -> f64 {
    let horizontal = ((ray.dir[0] as f64).powi(2) + (ray.dir[1] as f64).powi(2)).sqrt();
    let vertical = (ray.dir[2] as f64).abs();
    1.0 / (texels * horizontal.max(vertical))
}

/// Fills the frame-time fields from per-frame milliseconds.
pub fn set_timing(m: &mut Metrics, frame_ms: &[f64]) {
    m.frame_ms_median = percentile(frame_ms, 0.5);
    m.frame_ms_mean = if frame_ms.is_empty() { f64::NAN } else { frame_ms.iter().sum::<f64>() / frame_ms.len() as f64 };
    m.frame_ms_p10 = percentile(frame_ms, 0.1);
    m.frame_ms_p90 = percentile(frame_ms, 0.9);
}

/// A hit's z above the surface by more than this counts as ending above it.
pub const ABOVE_SURFACE: f64 = 1e-3;

/// A hit further than this in t past the exact first hit counts as past it: the f32
/// rounding of a t near 1 is ~1e-7, and of the ray's position on a ray nearly parallel to a
/// steep bilinear ramp up to ~1e-6 (the goal set for the safe cone methods: 1e-5).
pub const PAST_SLACK: f64 = 1e-5;

/// Accuracy of a set of probe hits against the reference hits of the same rays, from the
/// raw hits: nothing is clamped, filtered or skipped before it is counted.
///
/// A hit with a NaN or infinite coordinate is an error of the largest size a hit inside the
/// volume can have: height error 1 in the MSE, t error `t_max` (the ray's whole length in
/// the volume), uv error the ray's whole horizontal travel, and it counts as missed.
///
/// A hit the probe marks `clipped` (`silhouette=clip`: its (u, v) left the quad's square)
/// is a "no hit": missed where the reference has a hit (its raw t still enters the t error),
/// correct where the reference has none. A hit that is not clipped where the reference has
/// none is a false hit.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Accuracy {
    /// Rays scored: the shortest of the ray, hit and reference lists.
    pub rays: usize,
    /// Σ (h(hit.uv) − hit.z)² over all rays (Burger §4.1).
    pub mse_sum: f64,
    /// Rays the reference hits (the t and uv errors are over these).
    pub both: usize,
    /// Σ (t − t_ref)² over the `both` rays (a non-finite hit adds `t_max²`).
    pub t_sq_sum: f64,
    /// Largest |t − t_ref| over the `both` rays (`t_max` for a non-finite hit).
    pub t_abs_max: f64,
    /// Σ of the squared (u, v) distance to the reference hit, in level-0 texels (the
    /// longer side of the map), over the `both` rays.
    pub uv_texels_sq_sum: f64,
    /// Rays the reference hits where the hit is clipped or more than one texel of travel
    /// ([`one_texel_t`]) past the reference, plus every non-finite hit.
    pub missed: usize,
    /// Rays with a hit (not clipped) where the reference has none.
    pub false_hits: usize,
    /// Finite hits past the exact first hit by more than [`PAST_SLACK`] in t.
    pub past: usize,
    /// Hits with a NaN or infinite t, u, v or z.
    pub nan: usize,
    /// Finite hits outside the ray's volume
    /// ([`ProbeHit::outside`](relief_dsl::abi::ProbeHit::outside)).
    pub outside: usize,
    /// Hits whose coarse search ran out of steps (`converged == 0`).
    pub nonconverged: usize,
    /// Finite hits that end above the surface by more than [`ABOVE_SURFACE`].
    pub above_surface: usize,
    /// Σ of the coarse stage's loop passes over all rays.
    pub coarse_steps: u64,
    /// Σ of the refine stage's loop passes over all rays.
    pub refine_steps: u64,
    /// Σ of the texture samples over all rays.
    pub fetches: u64,
}

impl Accuracy {
    /// Scores `hits` against `refs` for the same `rays`, on the surface the shader samples
    /// (`heights`, bilinear, with `edge`).
    pub fn of(
        rays: &[ProbeRay],
        hits: &[ProbeHit],
        refs: &[Option<RefHit>],
        heights: &HeightMap,
        edge: EdgeMode,
    ) -> Accuracy {
        Accuracy::of_levels(rays, hits, refs, std::slice::from_ref(heights), &[], edge)
    }

    /// [`Accuracy::of`] for hits that sampled mip levels: ray i on level `levels[i]` of
    /// `chain` (level 0 for a ray past the end of `levels`), so that the surface a hit is
    /// scored against is the one its shader sampled. Distances in texels are in level-0
    /// texels throughout, so that they compare across levels.
    pub fn of_levels(
        rays: &[ProbeRay],
        hits: &[ProbeHit],
        refs: &[Option<RefHit>],
        chain: &[HeightMap],
        levels: &[usize],
        edge: EdgeMode,
    ) -> Accuracy {
        let heights = &chain[0];
        let n = hits.len().min(rays.len()).min(refs.len());
        let texels = heights.width.max(heights.height) as f64;
        let mut a = Accuracy { rays: n, ..Default::default() };
        for i in 0..n {
            let (r, h) = (&rays[i], &hits[i]);
            a.coarse_steps += h.coarse_steps as u64;
            a.refine_steps += h.refine_steps as u64;
            a.fetches += h.fetches as u64;
            a.nonconverged += (h.converged == 0) as usize;
            let t_max = 1.0 / -(r.dir[2] as f64);
            if !h.is_finite() {
                a.nan += 1;
                a.missed += 1;
                a.mse_sum += 1.0;
                if refs[i].is_some() {
                    let reach = ((r.dir[0] as f64).powi(2) + (r.dir[1] as f64).powi(2)).sqrt() * t_max * texels;
                    a.both += 1;
                    a.t_sq_sum += t_max * t_max;
                    a.t_abs_max = a.t_abs_max.max(t_max);
                    a.uv_texels_sq_sum += reach * reach;
                }
                continue;
            }
            a.outside += h.outside(r) as usize;
            let surface = chain[levels.get(i).copied().unwrap_or(0)].bilinear(h.u as f64, h.v as f64, edge);
            let e = surface - h.z as f64;
            a.mse_sum += e * e;
            a.above_surface += (h.z as f64 > surface + ABOVE_SURFACE) as usize;
            let no_hit = h.clipped != 0;
            match refs[i] {
                Some(rh) => {
                    a.both += 1;
                    let dt = h.t as f64 - rh.t;
                    a.t_sq_sum += dt * dt;
                    a.t_abs_max = a.t_abs_max.max(dt.abs());
                    let (du, dv) = (h.u as f64 - rh.u, h.v as f64 - rh.v);
                    a.uv_texels_sq_sum += (du * du + dv * dv) * texels * texels;
                    if no_hit || dt > one_texel_t(r, texels) {
                        a.missed += 1;
                    }
                    a.past += (dt > PAST_SLACK) as usize;
                }
                None => a.false_hits += !no_hit as usize,
            }
        }
        a
    }

    fn share(&self, count: usize) -> f64 {
        if self.rays > 0 {
            count as f64 / self.rays as f64
        } else {
            0.0
        }
    }
    fn per_ray(&self, sum: f64) -> f64 {
        if self.rays > 0 {
            sum / self.rays as f64
        } else {
            0.0
        }
    }
    /// RMS of t − t_ref over the rays the reference hits.
    pub fn t_rms(&self) -> f64 {
        if self.both > 0 {
            (self.t_sq_sum / self.both as f64).sqrt()
        } else {
            0.0
        }
    }
    /// `missed` as a share of all rays, in [0, 1]; 0 when there are no rays.
    pub fn missed_rate(&self) -> f64 {
        self.share(self.missed)
    }
    /// `false_hits` as a share of all rays, in [0, 1]; 0 when there are no rays.
    pub fn false_hit_rate(&self) -> f64 {
        self.share(self.false_hits)
    }
    /// `nonconverged` as a share of all rays, in [0, 1]; 0 when there are no rays.
    pub fn nonconverged_rate(&self) -> f64 {
        self.share(self.nonconverged)
    }
    /// `above_surface` as a share of all rays, in [0, 1]; 0 when there are no rays.
    pub fn above_surface_rate(&self) -> f64 {
        self.share(self.above_surface)
    }
}

/// The accuracy fields, from the probe's hits and the reference hits of the same rays, on
/// the surface the shader samples (`heights`, bilinear, with `edge`).
pub fn set_accuracy(
    m: &mut Metrics,
    rays: &[ProbeRay],
    hits: &[ProbeHit],
    refs: &[Option<RefHit>],
    heights: &HeightMap,
    edge: EdgeMode,
) {
    set_accuracy_levels(m, rays, hits, refs, std::slice::from_ref(heights), &[], edge)
}

/// [`set_accuracy`] for hits that sampled mip levels ([`Accuracy::of_levels`]).
pub fn set_accuracy_levels(
    m: &mut Metrics,
    rays: &[ProbeRay],
    hits: &[ProbeHit],
    refs: &[Option<RefHit>],
    chain: &[HeightMap],
    levels: &[usize],
    edge: EdgeMode,
) {
    let a = Accuracy::of_levels(rays, hits, refs, chain, levels, edge);
    m.mse_dissertation = a.mse_sum;
    m.mse_dissertation_mean = a.per_ray(a.mse_sum);
    m.ref_err_t_rms = a.t_rms();
    m.ref_err_uv_texels_rms = if a.both > 0 { (a.uv_texels_sq_sum / a.both as f64).sqrt() } else { 0.0 };
    m.missed_rate = a.missed_rate();
    m.false_hit_rate = a.false_hit_rate();
    m.nan_count = a.nan as u64;
    m.outside_count = a.outside as u64;
    m.nonconverged_rate = a.nonconverged_rate();
    m.avg_coarse_steps = a.per_ray(a.coarse_steps as f64);
    m.avg_refine_steps = a.per_ray(a.refine_steps as f64);
    m.avg_iterations = a.per_ray((a.coarse_steps + a.refine_steps) as f64);
    m.avg_fetches = a.per_ray(a.fetches as f64);
}
