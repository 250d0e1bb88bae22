//! A `curved=` pipeline on a mesh scene against the exact reference (docs/meshes.md,
//! "Measuring"): per pixel, the GPU's measurement entry (`gpu::mesh::probe_mesh`) beside
//! [`MeshScene::reference_hits`] on the same pixel-centre rays, and the frame time of a mode
//! against `curved=none` with the same stages, in paired blocks.
//!
//! The figures ([`MeshScore`]):
//! - **coverage error**: the share of pixels whose hit/miss disagrees with the reference's;
//! - **IoU**: covered pixels of both over covered pixels of either (1 when neither covers any);
//! - **RMS t**: on pixels both hit, the root mean square of the difference of the hit's
//!   distance from the eye along the pixel's ray, **in units of the relief's depth**
//!   (`depth_scale`): `(t_gpu − t_ref) / depth`; the flat tile's t (t = 1 descends the
//!   depth along the normal) is this times the view's cosine, so it is never larger;
//!   A pixel whose GPU hit lies on another part of the surface than the reference's (the
//!   ray passes above S where the mode's approximate surface stops it, and the reference
//!   hits a bump further on or the far side of a torus's tube) adds tens of depths, so the
//!   RMS is dominated by a few such pixels (docs/notes/meshes.md); hence also:
//! - **median t**: the median of `|t_gpu − t_ref| / depth` on pixels both hit;
//! - **far**: the pixels both hit whose hits lie more than one depth apart along the ray;
//! - **earliest**: the largest `(t_ref − t_gpu) / depth` on pixels both hit: how far a hit
//!   came before the reference's (positive: in front of the exact first hit);
//! - **past**: the pixels both hit whose GPU hit lies after the reference's by more than
//!   [`past_slack`] (what the flat matrix's `past_count` counts, on a mesh); **t max** the
//!   largest `|t_gpu − t_ref| / depth` on pixels both hit;
//! - **uv error**: RMS of the hit's texture-space distance, in texels (repeat edges: the
//!   difference taken modulo one tile);
//! - **depth error**: RMS of the NDC depth difference, the reference's hit point projected
//!   by the scene's `view_proj`.

use glam::{DVec3, Vec4};
use relief_dsl::spec::Curved;
use relief_dsl::Pipeline;

use crate::gpu::mesh::{mesh_textures, paired_mesh_time, probe_mesh, MeshProbe, MeshProgram};
use crate::gpu::Gpu;
use crate::heightmap::EdgeMode;
use crate::mesh::{MeshHit, MeshScene};
use crate::timing::Ratio;

/// One mode's figures against the reference (module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct MeshScore {
    /// Pixels in the frame.
    pub pixels: usize,
    /// Pixels both hit, the GPU only (extra), the reference only (missing).
    pub both: usize,
    /// See `both`.
    pub extra: usize,
    /// See `both`.
    pub missing: usize,
    /// `(extra + missing) / pixels`.
    pub coverage_error: f64,
    /// `both / (both + extra + missing)` (1 when that is 0).
    pub iou: f64,
    /// RMS of `(t_gpu − t_ref) / depth` on pixels both hit (NaN when none).
    pub rms_t: f64,
    /// The median of `|t_gpu − t_ref| / depth` on pixels both hit (NaN when none).
    pub median_t: f64,
    /// Pixels both hit with `|t_gpu − t_ref| / depth > 1`.
    pub far: usize,
    /// The largest `(t_ref − t_gpu) / depth` on pixels both hit (−∞ when none).
    pub earliest: f64,
    /// Pixels both hit whose GPU hit lies after the reference's by more than [`past_slack`].
    pub past: usize,
    /// The largest `|t_gpu − t_ref| / depth` on pixels both hit (NaN when none).
    pub t_max: f64,
    /// RMS uv distance in texels on pixels both hit.
    pub uv_texels: f64,
    /// RMS NDC depth difference on pixels both hit.
    pub depth: f64,
}

/// What each pixel is, for the coverage picture.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Agreement {
    /// Both hit.
    Hit,
    /// Both miss.
    Miss,
    /// The GPU draws relief the reference does not have.
    Extra,
    /// The reference has relief the GPU does not draw.
    Missing,
}

impl Agreement {
    /// The pixel's colour in the coverage picture: agree-hit grey, agree-miss black, extra
    /// red, missing blue.
    pub fn colour(self) -> [u8; 4] {
        match self {
            Agreement::Hit => [150, 150, 150, 255],
            Agreement::Miss => [0, 0, 0, 255],
            Agreement::Extra => [230, 40, 40, 255],
            Agreement::Missing => [40, 90, 240, 255],
        }
    }
}

/// Each pixel's agreement of `gpu` (w > 0.5: a hit) with `reference`.
pub fn agreement(gpu: &MeshProbe, reference: &[Option<MeshHit>]) -> Vec<Agreement> {
    gpu.hits
        .iter()
        .zip(reference)
        .map(|(g, r)| match (g[3] > 0.5, r.is_some()) {
            (true, true) => Agreement::Hit,
            (false, false) => Agreement::Miss,
            (true, false) => Agreement::Extra,
            (false, true) => Agreement::Missing,
        })
        .collect()
}

/// The coverage picture (RGBA8, row-major) of [`agreement`].
pub fn coverage_picture(gpu: &MeshProbe, reference: &[Option<MeshHit>]) -> Vec<u8> {
    agreement(gpu, reference).iter().flat_map(|a| a.colour()).collect()
}

/// How far after the reference's hit, in units of the depth along the ray, a GPU hit may lie
/// and not count as past it: the flat matrix's [`crate::metrics::PAST_SLACK`], plus the
/// reference's own error (its tolerance ε, [`crate::mesh::MeshReference::default_tolerance`])
/// and sixteen f32 roundings of the distance `t_ref` (16 · 2⁻²⁴ < 1e-6 of it), both in
/// world units over `depth`.
pub fn past_slack(tolerance: f64, t_ref: f64, depth: f64) -> f64 {
    crate::metrics::PAST_SLACK + (tolerance + 1e-6 * t_ref.abs()) / depth
}

/// The figures of `gpu` against `reference` on `ms` (module doc).
pub fn score(gpu: &MeshProbe, reference: &[Option<MeshHit>], ms: &MeshScene) -> MeshScore {
    let pixels = reference.len();
    let depth = ms.scene.depth_scale as f64;
    let (w, h) = (ms.scene.height.width as f64, ms.scene.height.height as f64);
    let view_proj = ms.scene.camera.view_proj(1.0);
    let wrap = |d: f64| if ms.scene.edge == EdgeMode::Repeat { d - d.round() } else { d };
    let (mut both, mut extra, mut missing) = (0, 0, 0);
    let (mut st, mut suv, mut sd, mut earliest) = (0.0, 0.0, 0.0, f64::NEG_INFINITY);
    let mut dts = Vec::new();
    let tolerance = crate::mesh::MeshReference::default_tolerance(&ms.mesh, depth);
    let mut past = 0;
    for (i, (g, r)) in gpu.hits.iter().zip(reference).enumerate() {
        match (g[3] > 0.5, r) {
            (true, Some(r)) => {
                both += 1;
                let dt = (g[2] as f64 - r.t) / depth;
                st += dt * dt;
                dts.push(dt.abs());
                earliest = earliest.max(-dt);
                past += usize::from(dt > past_slack(tolerance, r.t, depth));
                let (du, dv) = (wrap(g[0] as f64 - r.u) * w, wrap(g[1] as f64 - r.v) * h);
                suv += du * du + dv * dv;
                let p = DVec3::from(r.point).as_vec3();
                let c = view_proj * Vec4::new(p.x, p.y, p.z, 1.0);
                let dz = gpu.depth.get(i).copied().unwrap_or(1.0) as f64 - (c.z / c.w) as f64;
                sd += dz * dz;
            }
            (true, None) => extra += 1,
            (false, Some(_)) => missing += 1,
            (false, None) => {}
        }
    }
    let rms = |s: f64| if both > 0 { (s / both as f64).sqrt() } else { f64::NAN };
    let union = both + extra + missing;
    dts.sort_by(f64::total_cmp);
    let median_t = match dts.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => dts[n / 2],
        n => 0.5 * (dts[n / 2 - 1] + dts[n / 2]),
    };
    let far = dts.iter().filter(|&&d| d > 1.0).count();
    let t_max = dts.last().copied().unwrap_or(f64::NAN);
    MeshScore {
        pixels,
        both,
        extra,
        missing,
        coverage_error: (extra + missing) as f64 / pixels.max(1) as f64,
        iou: if union > 0 { both as f64 / union as f64 } else { 1.0 },
        rms_t: rms(st),
        median_t,
        far,
        earliest,
        past,
        t_max,
        uv_texels: rms(suv),
        depth: rms(sd),
    }
}

/// One mode's row of `relief scene measure`.
pub struct ModeFigures {
    /// The pipeline measured (the base with `curved=` the mode).
    pub pipeline: Pipeline,
    /// Its figures against the reference.
    pub score: MeshScore,
    /// Its per-pixel measurement (for the coverage picture).
    pub probe: MeshProbe,
    /// Its mean frame time over `curved=none`'s with the same stages, paired blocks (`None`
    /// for `none` itself, or when timing was not asked for).
    pub time: Option<Ratio>,
}

/// `base` under each mode in `modes` on `ms` at `size²`, against `reference` (the scene's
/// [`MeshScene::reference_hits`] at that size); with `pairs` > 0, each mode but `none` is
/// timed against `none` in that many pairs of blocks.
pub fn measure_modes(
    gpu: &Gpu,
    ms: &MeshScene,
    base: &Pipeline,
    modes: &[Curved],
    reference: &[Option<MeshHit>],
    size: u32,
    pairs: u32,
) -> crate::Result<Vec<ModeFigures>> {
    let none = MeshProgram::new(&base.clone().with_curved(Some(Curved::None)))?;
    let none_tex = mesh_textures(gpu, ms, &none)?;
    let mut out = Vec::new();
    for &mode in modes {
        let p = base.clone().with_curved(Some(mode));
        let prog = MeshProgram::new(&p)?;
        let tex = mesh_textures(gpu, ms, &prog)?;
        let probe = probe_mesh(gpu, &prog, ms, &tex, size)?;
        let score = score(&probe, reference, ms);
        let time = if pairs > 0 && mode != Curved::None {
            Some(paired_mesh_time(gpu, (&prog, &tex), (&none, &none_tex), ms, size, pairs)?.ratio())
        } else {
            None
        };
        out.push(ModeFigures { pipeline: p, score, probe, time });
    }
    Ok(out)
}
