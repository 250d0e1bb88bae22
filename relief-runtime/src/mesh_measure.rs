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

use glam::{DVec2, DVec3, Vec4};
use relief_dsl::compose::mesh::MeshVertex;
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

/// Why `curved=prism` left out a pixel the reference hits (issue 38's separation of its
/// missing pixels; docs/notes/meshes.md). Decided on the CPU, in f64, by
/// [`prism_miss_causes`], from the prism the host uploads (`mesh::vertices`) and the
/// fragment's trace as the shader writes it (`relief-dsl`'s `compose/mesh.rs`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum PrismMiss {
    /// (a) The pixel's ray meets no face of the hit triangle's prism as it is rasterized (two
    /// planar triangles per side wall): the ray passes through the exact prism (the reference's
    /// hit is in it) but outside the drawn one, so no fragment of that prism runs.
    NoFace,
    /// (b) A face is met, but the fragment's straight texture-space ray, from its entry on,
    /// meets the height field only after its exit from the planar prism (or not at all): the
    /// prism's texture-space map (the fragment's frame, the planar walls) loses the hit.
    AfterExit,
    /// (c) The fragment's straight ray crosses the height field between its entry and its exit,
    /// and the search (`linear` then `binary` from the entry, emulated) does not end there:
    /// its steps skip the crossing.
    Search,
    /// (b) Every face met is a fragment whose view ray does not descend along the fragment's
    /// normal (`v·N ≥ 0`, N the interpolated normal): the shader takes it for a ray entering
    /// from below and discards it. These are rays that enter the shell through a side wall near
    /// the silhouette, level with or rising against the fragment's tangent plane, which the
    /// fragment's frame (a descending ray in texture space) cannot express.
    FacingAway,
    /// (d) The CPU's emulation of one of the prism's fragments draws the pixel: the GPU's f32
    /// arithmetic or its rasterization rules decided otherwise.
    Other,
}

impl PrismMiss {
    /// Every cause, in the order the note's table gives them.
    pub const ALL: [PrismMiss; 5] =
        [PrismMiss::NoFace, PrismMiss::AfterExit, PrismMiss::FacingAway, PrismMiss::Search, PrismMiss::Other];

    /// The cause's short name (`relief scene measure --causes`).
    pub fn name(self) -> &'static str {
        match self {
            PrismMiss::NoFace => "no-face",
            PrismMiss::AfterExit => "after-exit",
            PrismMiss::Search => "search",
            PrismMiss::FacingAway => "facing-away",
            PrismMiss::Other => "other",
        }
    }
}

/// The slack in t of the shader's prism test (`PRISM_SLACK` in `compose/mesh.rs`).
const PRISM_SLACK: f64 = 1e-4;

/// The steps of the dense march that finds a fragment ray's first crossing (then refined by
/// bisection): a crossing narrower than 1/4096 of the ray's t range can be missed by it.
const DENSE_STEPS: u32 = 4096;

/// A prism fragment as the shader sees it, in f64: its texture-space ray, its entry, its exit
/// from the planar prism and whether it enters from below.
struct PrismFragment {
    origin: DVec2,
    dir: DVec3,
    t_entry: f64,
    exit: f64,
    from_below: bool,
}

/// The scene's height map, bilinear between texel centres under its edge mode (the
/// reference's `h`, `mesh::surface::Cell`).
fn height_at(ms: &MeshScene, uv: DVec2) -> f64 {
    let map = &ms.scene.height;
    let (x, y) = (uv.x * map.width as f64 - 0.5, uv.y * map.height as f64 - 0.5);
    let (i, j) = (x.floor() as i64, y.floor() as i64);
    crate::mesh::surface::Cell::new(map, ms.scene.edge, i, j).h(x, y)
}

/// The search `linear(steps)` then `binary(refine)` of a prism fragment, as the stages write
/// it (`stage/coarse/linear.rs`, `stage/refine/binary.rs`) and the fragment runs it
/// (`compose/mesh.rs`, `search`): from the entry, at height 1 over heights lifted by
/// `t_entry`; the t it returns, on the ray from the virtual entry (`t_entry` added).
fn emulate_linear_binary(ms: &MeshScene, f: &PrismFragment, steps: u32, refine: u32) -> f64 {
    let below = |t: f64| {
        let p = f.origin + f.dir.truncate() * (t + f.t_entry);
        height_at(ms, p) + f.t_entry >= 1.0 + f.dir.z * t
    };
    let step = 1.0 / steps as f64;
    let mut t = 0.0;
    for _ in 0..steps {
        if below(t) {
            break;
        }
        t += step;
    }
    let (above, bottom) = ((t - step).max(0.0), t);
    if refine == 0 {
        return bottom + f.t_entry;
    }
    let mut half = (bottom - above) / 2.0;
    let mut t = bottom - half;
    for _ in 0..refine {
        let b = below(t);
        half /= 2.0;
        t += if b { -half } else { half };
    }
    t + f.t_entry
}

/// The first t in [`from`, 1] where the fragment's straight texture-space ray meets the height
/// field (`h ≥ z`), by a dense march (steps of 1/[`DENSE_STEPS`]) and bisection; 1 (the floor)
/// at the latest.
fn first_crossing(ms: &MeshScene, f: &PrismFragment, from: f64) -> f64 {
    let below = |t: f64| {
        let p = f.origin + f.dir.truncate() * t;
        height_at(ms, p) >= 1.0 + f.dir.z * t
    };
    let from = from.clamp(0.0, 1.0);
    let n = ((1.0 - from) * DENSE_STEPS as f64).ceil().max(1.0) as u32;
    let mut prev = from;
    for k in 0..=n {
        let t = from + (1.0 - from) * k as f64 / n as f64;
        if below(t) {
            if k == 0 {
                return from;
            }
            let (mut lo, mut hi) = (prev, t);
            for _ in 0..40 {
                let mid = 0.5 * (lo + hi);
                if below(mid) {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            return hi;
        }
        prev = t;
    }
    1.0
}

/// The fragment of the prism face `face` (three records) where the ray `o + s·d` meets it at
/// barycentrics (b1, b2): the varyings interpolated (perspective-correct interpolation of an
/// attribute affine over the face is its object-space barycentric mix) and the shader's ray,
/// entry, exit and below test (`mesh_ray`, `prism_exit`, `covered` in `compose/mesh.rs`).
fn prism_fragment(face: [&MeshVertex; 3], b: (f64, f64), eye: DVec3, depth: f64) -> PrismFragment {
    let w = [1.0 - b.0 - b.1, b.0, b.1];
    let mix = |get: &dyn Fn(&MeshVertex) -> [f32; 4]| {
        let mut out = [0.0f64; 4];
        for (wk, v) in w.iter().zip(face) {
            for (o, x) in out.iter_mut().zip(get(v)) {
                *o += wk * x as f64;
            }
        }
        out
    };
    // The vertex entry's point: the layer-w vertex moved (1 − w)·depth along −N.
    let point_of = |v: &MeshVertex| {
        let p = v.position.map(|c| c as f64);
        let n = v.normal.map(|c| c as f64);
        let k = (1.0 - p[3]) * depth;
        [(p[0] - n[0] * k) as f32, (p[1] - n[1] * k) as f32, (p[2] - n[2] * k) as f32, v.position[3]]
    };
    let point = mix(&point_of);
    let normal = mix(&|v| v.normal);
    let tangent = mix(&|v| v.tangent);
    let uv = mix(&|v| v.uv);
    let (pa, pb) = (face[0].prism_a, face[0].prism_b);
    let corners = [
        DVec2::new(pa[0] as f64, pa[1] as f64),
        DVec2::new(pa[2] as f64, pa[3] as f64),
        DVec2::new(pb[0] as f64, pb[1] as f64),
    ];
    let n_raw = DVec3::new(normal[0], normal[1], normal[2]);
    let n = n_raw.normalize();
    let t0 = DVec3::new(tangent[0], tangent[1], tangent[2]);
    let t = (t0 - n * n.dot(t0)).normalize();
    let bt = n.cross(t) * tangent[3];
    let depth_n = depth * n_raw.length();
    let view = (DVec3::new(point[0], point[1], point[2]) - eye).normalize();
    let v_n = view.dot(n);
    let cos_view = (-v_n).max(1e-6);
    let k = depth_n / cos_view;
    let dir = DVec3::new(view.dot(t) * uv[2] * k, view.dot(bt) * uv[3] * k, -1.0);
    let t_entry = 1.0 - point[3];
    let origin = DVec2::new(uv[0], uv[1]) - dir.truncate() * t_entry;
    let mut exit = 1.0f64;
    for (p, q, r) in [(0, 1, 2), (1, 2, 0), (2, 0, 1)] {
        let (p, q, r) = (corners[p], corners[q], corners[r]);
        let e = q - p;
        let n0 = DVec2::new(-e.y, e.x);
        let nn = if n0.dot(r - p) < 0.0 { -n0 } else { n0 };
        let toward = nn.dot(dir.truncate());
        if toward < 0.0 {
            exit = exit.min(nn.dot(p - origin) / toward);
        }
    }
    PrismFragment { origin, dir, t_entry, exit, from_below: v_n >= 0.0 }
}

/// For each pixel that the reference hits and `probe` (a `curved=prism` measurement of `ms`
/// with `linear(steps)+binary(refine)`, `size²`) leaves out, its index and its cause
/// ([`PrismMiss`]). Every face of the prism of the reference's hit triangle that the pixel's
/// ray meets (either side: the mesh pipeline does not cull) is a fragment the shader ran;
/// the pixel's cause is the first of these that holds: none is met (`NoFace`); the CPU's
/// emulation draws one of them (`Other`); on one of them the straight texture-space ray,
/// from its entry on, first crosses the height field before its exit, and the search stepped
/// over it (`Search`); else `AfterExit`, or `FacingAway` where every face met is one the shader takes for a ray
/// entering from below.
pub fn prism_miss_causes(
    ms: &MeshScene,
    reference: &[Option<MeshHit>],
    probe: &MeshProbe,
    size: u32,
    steps: u32,
    refine: u32,
) -> Vec<(usize, PrismMiss)> {
    let (vertices, indices) = crate::mesh::vertices::mesh_vertices(&ms.mesh, Curved::Prism);
    let rays = ms.rays(size, size);
    let depth = ms.scene.depth_scale as f64;
    let mut out = Vec::new();
    for (i, a) in agreement(probe, reference).into_iter().enumerate() {
        let (Agreement::Missing, Some(hit)) = (a, reference[i]) else { continue };
        let ray = &rays[i];
        let (o, d) = (DVec3::from(ray.origin.map(|c| c as f64)), DVec3::from(ray.dir.map(|c| c as f64)));
        let tri = hit.triangle as usize;
        let mut fragments = Vec::new();
        for f in indices[tri * 24..tri * 24 + 24].chunks_exact(3) {
            let face = [f[0], f[1], f[2]].map(|k| &vertices[k as usize]);
            let corner = |v: &MeshVertex| {
                let p = v.position.map(|c| c as f64);
                let n = v.normal.map(|c| c as f64);
                let k = (1.0 - p[3]) * depth;
                DVec3::new(
                    (p[0] - n[0] * k) as f32 as f64,
                    (p[1] - n[1] * k) as f32 as f64,
                    (p[2] - n[2] * k) as f32 as f64,
                )
            };
            let [a, b, c] = face.map(corner);
            if let Some((s, b1, b2)) = crate::mesh::reference::ray_triangle(o, d, a, b, c) {
                fragments.push((s, prism_fragment(face, (b1, b2), o, depth)));
            }
        }
        fragments.sort_by(|x, y| x.0.total_cmp(&y.0));
        let cause = classify(ms, &fragments, steps, refine);
        out.push((i, cause));
    }
    out
}

/// The cause of a missing pixel from the fragments its ray makes on the hit triangle's prism,
/// nearest first ([`prism_miss_causes`]).
fn classify(ms: &MeshScene, fragments: &[(f64, PrismFragment)], steps: u32, refine: u32) -> PrismMiss {
    if fragments.is_empty() {
        return PrismMiss::NoFace;
    }
    let inside = |f: &PrismFragment, t: f64| t >= f.t_entry - PRISM_SLACK && t <= f.exit + PRISM_SLACK;
    let traced: Vec<f64> = fragments.iter().map(|(_, f)| emulate_linear_binary(ms, f, steps, refine)).collect();
    if fragments.iter().zip(&traced).any(|((_, f), &t)| !f.from_below && inside(f, t)) {
        return PrismMiss::Other;
    }
    let mut found = None;
    for (_, f) in fragments.iter().filter(|(_, f)| !f.from_below) {
        // The straight ray's first crossing from the entry on: the hit a search between the
        // entry and the exit would find.
        if inside(f, first_crossing(ms, f, f.t_entry.max(0.0))) {
            found = Some(PrismMiss::Search);
        }
    }
    match (found, fragments.iter().any(|(_, f)| !f.from_below)) {
        (Some(c), _) => c,
        (None, true) => PrismMiss::AfterExit,
        (None, false) => PrismMiss::FacingAway,
    }
}
