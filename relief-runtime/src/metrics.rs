//! Metrics of one run, under the names used in every results file.
//!
//! Accuracy is measured on the probe's hits against the exact reference for the *same* rays;
//! speed on the render entry's frame times.

use crate::heightmap::{EdgeMode, HeightMap};
use crate::reference::{rises_above, RefHit};
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
/// first. A hit further than that past the true first hit counts in `past_rate` (which says
/// nothing of skipped geometry: a linear step on a large map spans several texels), and the
/// cone tests use the same measure.
pub fn one_texel_t(ray: &ProbeRay, texels: f64) -> f64 {
    one_texel_t_along(ray.dir.map(f64::from), texels)
}

/// [`one_texel_t`] for a ray direction `dir` in f64 (a room wall's ray, for one).
pub(crate) fn one_texel_t_along(dir: [f64; 3], texels: f64) -> f64 {
    let horizontal = (dir[0] * dir[0] + dir[1] * dir[1]).sqrt();
    1.0 / (texels * horizontal.max(dir[2].abs()))
}

/// Whether a hit at `t` on the ray `(origin, 1) + t·dir` is past the exact first hit at
/// `t_ref` by more than one texel of travel ([`one_texel_t_along`]) on a map `texels`
/// texels a side: what `past_rate` counts.
pub(crate) fn is_past(dir: [f64; 3], texels: f64, t_ref: f64, t: f64) -> bool {
    t - t_ref > one_texel_t_along(dir, texels)
}

/// Whether the ray `(origin, 1) + t·dir`, after its exact first hit at `t_ref`, comes back
/// above `level`'s bilinear surface before `t` ([`rises_above`] with [`SKIP_SLACK`]),
/// looked at only up to the floor (below it no surface lies under the ray): a hit at `t`
/// jumped over geometry, what `skipped_rate` counts.
pub(crate) fn is_skipped(
    level: &HeightMap,
    edge: EdgeMode,
    origin: [f64; 2],
    dir: [f64; 3],
    t_ref: f64,
    t: f64,
) -> bool {
    let t_floor = 1.0 / -dir[2];
    rises_above(level, edge, origin, dir, t_ref, t.min(t_floor), SKIP_SLACK)
}

/// Fills the frame-time fields from per-frame milliseconds.
pub(crate) fn set_timing(m: &mut Metrics, frame_ms: &[f64]) {
    m.frame_ms_median = percentile(frame_ms, 0.5);
    m.frame_ms_mean = if frame_ms.is_empty() { f64::NAN } else { frame_ms.iter().sum::<f64>() / frame_ms.len() as f64 };
    m.frame_ms_p10 = percentile(frame_ms, 0.1);
    m.frame_ms_p90 = percentile(frame_ms, 0.9);
}

/// A hit's z above the surface by more than this counts as ending above it.
pub(crate) const ABOVE_SURFACE: f64 = 1e-3;

/// A hit further than this in t past the exact first hit counts as past it: the f32
/// rounding of a t near 1 is ~1e-7, and of the ray's position on a ray nearly parallel to a
/// steep bilinear ramp up to ~1e-6 (the goal set for the safe cone methods: 1e-5).
pub const PAST_SLACK: f64 = 1e-5;

/// A ray above the surface by more than this in height, between the exact first hit and the
/// reported one, has come back out of it (`skipped_rate`): a height in [0, 1] rounds to f32
/// within 6e-8, and the exact first hit is found in f64, so a rise of 1e-6 is no rounding;
/// a ray that only grazes a ridge by less than that has not jumped over anything a picture
/// shows.
pub(crate) const SKIP_SLACK: f64 = 1e-6;

/// Share of the rays with the largest squared height errors in `mse_worst1_share`.
pub(crate) const WORST_SHARE: f64 = 0.01;

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
    /// ([`one_texel_t`]) past the reference, plus every non-finite hit (`past_rate`).
    pub missed: usize,
    /// Rays the reference hits whose reported hit lies beyond a point where the ray, after
    /// the exact first hit, is back above the surface the ray sampled by more than
    /// `SKIP_SLACK` (`rises_above`): it jumped over geometry. Plus the clipped hits
    /// the reference has a hit for, and every non-finite hit (`skipped_rate`).
    pub skipped: usize,
    /// |t − t_ref| of each ray the reference hits (`t_max` for a non-finite hit), in ray
    /// order: the percentiles' list.
    pub t_abs: Vec<f64>,
    /// (h(hit.uv) − hit.z)² of each ray (1 for a non-finite hit), in ray order: the terms
    /// of `mse_sum`.
    pub mse_terms: Vec<f64>,
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
    /// Finite hits that end above the surface by more than `ABOVE_SURFACE`.
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
                a.skipped += 1;
                a.mse_sum += 1.0;
                a.mse_terms.push(1.0);
                if refs[i].is_some() {
                    let reach = ((r.dir[0] as f64).powi(2) + (r.dir[1] as f64).powi(2)).sqrt() * t_max * texels;
                    a.both += 1;
                    a.t_sq_sum += t_max * t_max;
                    a.t_abs_max = a.t_abs_max.max(t_max);
                    a.t_abs.push(t_max);
                    a.uv_texels_sq_sum += reach * reach;
                }
                continue;
            }
            a.outside += h.outside(r) as usize;
            let level = &chain[levels.get(i).copied().unwrap_or(0)];
            let surface = level.bilinear(h.u as f64, h.v as f64, edge);
            let e = surface - h.z as f64;
            a.mse_sum += e * e;
            a.mse_terms.push(e * e);
            a.above_surface += (h.z as f64 > surface + ABOVE_SURFACE) as usize;
            let no_hit = h.clipped != 0;
            match refs[i] {
                Some(rh) => {
                    a.both += 1;
                    let dt = h.t as f64 - rh.t;
                    a.t_sq_sum += dt * dt;
                    a.t_abs_max = a.t_abs_max.max(dt.abs());
                    a.t_abs.push(dt.abs());
                    let (du, dv) = (h.u as f64 - rh.u, h.v as f64 - rh.v);
                    a.uv_texels_sq_sum += (du * du + dv * dv) * texels * texels;
                    let dir = r.dir.map(f64::from);
                    if no_hit || is_past(dir, texels, rh.t, h.t as f64) {
                        a.missed += 1;
                    }
                    if no_hit || is_skipped(level, edge, r.origin.map(f64::from), dir, rh.t, h.t as f64) {
                        a.skipped += 1;
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
    /// `missed` as a share of all rays, in [0, 1]; 0 when there are no rays (`past_rate`).
    pub fn missed_rate(&self) -> f64 {
        self.share(self.missed)
    }
    /// `skipped` as a share of all rays, in [0, 1]; 0 when there are no rays.
    pub fn skipped_rate(&self) -> f64 {
        self.share(self.skipped)
    }
    /// Percentile `q` of |t − t_ref| over the rays the reference hits ([`percentile`]);
    /// NaN when there are none.
    pub(crate) fn t_abs_percentile(&self, q: f64) -> f64 {
        percentile(&self.t_abs, q)
    }
    /// The share of the MSE that the worst `fraction` of the rays carry: the sum of the
    /// ⌈fraction · rays⌉ largest squared height errors over the sum of all ([`worst_share`]).
    pub(crate) fn mse_worst_share(&self, fraction: f64) -> f64 {
        worst_share(&self.mse_terms, fraction)
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

/// The sum of the ⌈`fraction` · n⌉ largest of `terms` (n of them) over the sum of all; NaN
/// when the sum is 0 or there are no terms (no error to share out).
pub(crate) fn worst_share(terms: &[f64], fraction: f64) -> f64 {
    let total: f64 = terms.iter().sum();
    if terms.is_empty() || total <= 0.0 {
        return f64::NAN;
    }
    let mut v = terms.to_vec();
    v.sort_by(|a, b| b.total_cmp(a));
    let k = ((fraction * v.len() as f64).ceil() as usize).clamp(1, v.len());
    v[..k].iter().sum::<f64>() / total
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
    m.skipped_rate = a.skipped_rate();
    m.past_rate = a.missed_rate();
    m.missed_rate = m.past_rate;
    m.ref_err_t_median = a.t_abs_percentile(0.5);
    m.ref_err_t_p90 = a.t_abs_percentile(0.9);
    m.ref_err_t_p99 = a.t_abs_percentile(0.99);
    m.mse_worst1_share = a.mse_worst_share(WORST_SHARE);
    m.false_hit_rate = a.false_hit_rate();
    m.nan_count = a.nan as u64;
    m.outside_count = a.outside as u64;
    m.nonconverged_rate = a.nonconverged_rate();
    m.avg_coarse_steps = a.per_ray(a.coarse_steps as f64);
    m.avg_refine_steps = a.per_ray(a.refine_steps as f64);
    m.avg_iterations = a.per_ray((a.coarse_steps + a.refine_steps) as f64);
    m.avg_fetches = a.per_ray(a.fetches as f64);
}

/// The coarse search's step along `ray` in level-0 texels of a map `texels` texels a side
/// (the ray's horizontal travel per step), for the searches whose step is fixed per ray:
/// `linear(N)` steps 1/N in t; `linear_dynamic(min, max)` 1/n with n = ⌊mix(max, min,
/// cos θ)⌋ (at least 1), θ the view ray's angle from the normal, computed as the probe
/// computes it from the ray and the scene's `depth_scale`. `None` for any other search.
pub fn coarse_step_texels(
    pipeline: &relief_dsl::Pipeline,
    ray: &ProbeRay,
    depth_scale: f32,
    texels: f64,
) -> Option<f64> {
    let c = &pipeline.coarse;
    let n = match c.name.as_str() {
        "linear" => c.int("steps") as f64,
        "linear_dynamic" => {
            let (min, max) = (c.int("min") as f32, c.int("max") as f32);
            let vz = ray.dir[2] * depth_scale;
            let cos = -vz / (ray.dir[0] * ray.dir[0] + ray.dir[1] * ray.dir[1] + vz * vz).sqrt();
            (max + (min - max) * cos).floor().max(1.0) as f64
        }
        _ => return None,
    };
    let horizontal = ((ray.dir[0] as f64).powi(2) + (ray.dir[1] as f64).powi(2)).sqrt();
    Some(horizontal * texels / n)
}
