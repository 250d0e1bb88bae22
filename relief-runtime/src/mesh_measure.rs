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
        let prog = MeshProgram::new(&base.clone().with_curved(Some(mode)))?;
        out.push(measure_program(gpu, ms, &prog, (&none, &none_tex), reference, size, pairs)?);
    }
    Ok(out)
}

/// [`measure_modes`] for one compiled program `prog` (e.g. [`MeshProgram::unwalked`]): its
/// figures against `reference` and, with `pairs` > 0 and `prog` not `curved=none`, its frame
/// time over `none`'s (the `curved=none` program of the same stages, with its textures).
pub fn measure_program(
    gpu: &Gpu,
    ms: &MeshScene,
    prog: &MeshProgram,
    none: (&MeshProgram, &crate::gpu::SceneTextures),
    reference: &[Option<MeshHit>],
    size: u32,
    pairs: u32,
) -> crate::Result<ModeFigures> {
    let tex = mesh_textures(gpu, ms, prog)?;
    let probe = probe_mesh(gpu, prog, ms, &tex, size)?;
    let score = score(&probe, reference, ms);
    let time = if pairs > 0 && prog.curved != Curved::None {
        Some(paired_mesh_time(gpu, (prog, &tex), none, ms, size, pairs)?.ratio())
    } else {
        None
    };
    Ok(ModeFigures { pipeline: prog.pipeline.clone(), score, probe, time })
}

/// Why `curved=prism` left out a pixel the reference hits (issue 38's separation of its
/// missing pixels; docs/notes/meshes.md). Decided on the CPU, in f64, by
/// [`prism_miss_causes`], from the prism the host uploads (`mesh::vertices`) and the
/// fragment's trace as the shader writes it (`relief-dsl`'s `compose/mesh.rs`: the exact entry
/// and exit, the chord between them, the search on it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum PrismMiss {
    /// (a) The pixel's ray meets no face of the hit triangle's prism as it is rasterized (two
    /// planar triangles per side wall): the ray passes through the exact prism (the reference's
    /// hit is in it) but outside the drawn one, so no fragment of that prism runs.
    NoFace,
    /// (b) A face is met, but the chord from the exact entry to the exact exit (straight in
    /// texture space, where the view ray bends) does not meet the height field before its exit
    /// (or the ray does not cross the exact prism twice): the chord loses the hit.
    AfterExit,
    /// (c) The chord crosses the height field before its exit, and the search (`linear` then
    /// `binary` on the chord, emulated) does not end there: its steps skip the crossing.
    Search,
    /// (d) The CPU's emulation of the prism's fragment draws the pixel: the GPU's f32
    /// arithmetic or its rasterization rules decided otherwise.
    Other,
}

impl PrismMiss {
    /// Every cause, in the order the note's table gives them.
    pub const ALL: [PrismMiss; 4] = [PrismMiss::NoFace, PrismMiss::AfterExit, PrismMiss::Search, PrismMiss::Other];

    /// The cause's short name (`relief scene measure --causes`).
    pub fn name(self) -> &'static str {
        match self {
            PrismMiss::NoFace => "no-face",
            PrismMiss::AfterExit => "after-exit",
            PrismMiss::Search => "search",
            PrismMiss::Other => "other",
        }
    }
}

/// The shader's constants of the prism's trace (`compose/mesh.rs`): the slack past the exit in
/// the search's t (`PRISM_SLACK`), the slack of a crossing outside its face
/// (`PRISM_FACE_SLACK`), the chord length under which it is searched untilted
/// (`PRISM_SHORT_CHORD`), how far above the lifted field a hit may lie (`PRISM_ABOVE_SLACK`)
/// and the search's t at the exit.
const PRISM_SLACK: f64 = 1e-4;
const PRISM_FACE_SLACK: f64 = 1e-5;
const PRISM_SHORT_CHORD: f64 = 1e-3;
const PRISM_ABOVE_SLACK: f64 = 1.0 / 32.0;
/// The search's t at the exit of a chord searched whole (`PRISM_CHORD_END`).
const PRISM_CHORD_END: f64 = 15.0 / 16.0;

/// The steps of the dense march that finds the chord's first crossing (then refined by
/// bisection): a crossing narrower than 1/4096 of the chord can be missed by it.
const DENSE_STEPS: u32 = 4096;

/// A point where a ray crosses a prism's boundary: its distance `t` along the ray, the
/// barycentrics of corners 0 and 1 and the layer w (1 the top, 0 the floor).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrismCrossing {
    /// The distance along the ray (in units of `|d|`).
    pub t: f64,
    /// b₀, b₁ (b₂ = 1 − b₀ − b₁).
    pub b: DVec2,
    /// The layer.
    pub w: f64,
}

/// The first and the last crossing of the ray `o + t·d` with the prism of the triangle
/// `p` (corner points), `n` (corner normals), `depth` deep: the volume
/// `X(b, w) = Σ bᵢ (pᵢ − depth·(1 − w)·nᵢ)`, its top and floor flat triangles and its side
/// walls bilinear patches, as `compose/mesh.rs`'s `prism_chord` intersects them (in f64,
/// with its slacks); `None` where the ray crosses it fewer than twice. Any t, also negative.
pub fn prism_crossings(
    o: DVec3,
    d: DVec3,
    p: [DVec3; 3],
    n: [DVec3; 3],
    depth: f64,
) -> Option<(PrismCrossing, PrismCrossing)> {
    let mut all = Vec::new();
    let floor = [0, 1, 2].map(|k| p[k] - n[k] * depth);
    for (q, w) in [(p, 1.0), (floor, 0.0)] {
        let (e1, e2) = (q[1] - q[0], q[2] - q[0]);
        let pv = d.cross(e2);
        let det = e1.dot(pv);
        if det.abs() <= 1e-300 {
            continue;
        }
        let s = o - q[0];
        let (b1, qv) = (s.dot(pv) / det, s.cross(e1));
        let b2 = d.dot(qv) / det;
        if b1 >= -PRISM_FACE_SLACK && b2 >= -PRISM_FACE_SLACK && b1 + b2 <= 1.0 + PRISM_FACE_SLACK {
            all.push(PrismCrossing { t: e2.dot(qv) / det, b: DVec2::new(1.0 - b1 - b2, b1), w });
        }
    }
    for (i, j) in [(0usize, 1usize), (1, 2), (2, 0)] {
        for (t, sigma, w) in wall_crossings(o, d, floor[i], floor[j], n[i] * depth, n[j] * depth) {
            let mut bary = [0.0; 3];
            bary[i] = 1.0 - sigma;
            bary[j] = sigma;
            all.push(PrismCrossing { t, b: DVec2::new(bary[0], bary[1]), w });
        }
    }
    let first = all.iter().copied().min_by(|x, y| x.t.total_cmp(&y.t))?;
    let last = all.iter().copied().max_by(|x, y| x.t.total_cmp(&y.t))?;
    (first.t < last.t).then_some((first, last))
}

/// The crossings `(t, σ, w)` of the ray `o + t·d` with the bilinear side wall
/// `W(σ, w) = F_i + σ(F_j − F_i) + w·D_i + σw·(D_j − D_i)` (`fi`, `fj` the floor corners,
/// `di`, `dj` depth times the corner normals), σ and w within [`PRISM_FACE_SLACK`] of
/// [0, 1]: with the two planes through the ray (normals ⊥ d) a quadratic in σ, as the
/// shader's `ray_bilinear_wall` solves it.
fn wall_crossings(o: DVec3, d: DVec3, fi: DVec3, fj: DVec3, di: DVec3, dj: DVec3) -> Vec<(f64, f64, f64)> {
    let dn = d.normalize();
    let axis = if dn.x.abs() < 0.6 { DVec3::X } else { DVec3::Y };
    let n1 = dn.cross(axis).normalize();
    let n2 = dn.cross(n1);
    let (fi, e, dd) = (fi - o, fj - fi, dj - di);
    let on = |x: DVec3| DVec2::new(n1.dot(x), n2.dot(x));
    let (a, b, c, f) = (on(fi), on(e), on(di), on(dd));
    let qa = b.x * f.y - b.y * f.x;
    let qb = a.x * f.y + b.x * c.y - a.y * f.x - b.y * c.x;
    let qc = a.x * c.y - a.y * c.x;
    let disc = qb * qb - 4.0 * qa * qc;
    let mut out = Vec::new();
    if disc < 0.0 {
        return out;
    }
    let q = -0.5 * (qb + qb.signum() * disc.sqrt());
    let mut roots = Vec::new();
    if qa != 0.0 {
        roots.push(q / qa);
    }
    if q != 0.0 {
        roots.push(qc / q);
    }
    for sigma in roots {
        let (den, num) = (c + f * sigma, a + b * sigma);
        let (dv, nv) = if den.x.abs() >= den.y.abs() { (den.x, num.x) } else { (den.y, num.y) };
        if dv.abs() <= 1e-300 {
            continue;
        }
        let w = -nv / dv;
        let inside = |x: f64| (-PRISM_FACE_SLACK..=1.0 + PRISM_FACE_SLACK).contains(&x);
        if !(inside(sigma) && inside(w)) {
            continue;
        }
        let point = fi + e * sigma + di * w + dd * (sigma * w);
        out.push((point.dot(d) / d.length_squared(), sigma, w));
    }
    out
}

/// The prism's chord as the shader searches it: from the entry's uv at height 1, `dir.xy` the
/// uv change per unit of the search's t, over heights lifted by `lift0 + slope·(uv − origin)`;
/// the exit at the search's t = `k`. With a [`PrismPath`] other than the chord, the search's
/// point at t is moved onto (or toward) the view ray's curve through the prism's map.
struct Chord {
    origin: DVec2,
    dir: DVec2,
    lift0: f64,
    slope: DVec2,
    k: f64,
    path: Path,
    b_in: DVec2,
    b_out: DVec2,
}

/// What the emulated search's point at a chord parameter is bent by: nothing (the chord), the
/// shader's quadratic through the curve's middle (`duv`, `dw`, `db` its offsets there, `axis`
/// turns a texture point into its fraction of the chord), or the exact inversion at every
/// point.
enum Path {
    Chord,
    /// `pieces`: 0 for the quadratic, else that many straight pieces through its points.
    Bent {
        duv: DVec2,
        dw: f64,
        db: DVec2,
        axis: DVec2,
        pieces: u32,
    },
    Exact(Box<Inversion>),
}

/// The prism's map and the view ray, for the exact inversion of a point of the ray.
struct Inversion {
    p: [DVec3; 3],
    n: [DVec3; 3],
    uv: [DVec2; 3],
    depth: f64,
    o: DVec3,
    d: DVec3,
    entry: PrismCrossing,
    exit: PrismCrossing,
}

impl Inversion {
    /// The point `(b₀, b₁, w)` of the prism's map `X(b, w)` on the view ray at the chord's
    /// fraction `s` (t linear between entry and exit), by `steps` of Newton's method from the
    /// chord's point.
    fn at(&self, s: f64, steps: usize) -> (DVec2, f64) {
        let target = self.o + self.d * (self.entry.t + (self.exit.t - self.entry.t) * s);
        let mut b = self.entry.b + (self.exit.b - self.entry.b) * s;
        let mut w = self.entry.w + (self.exit.w - self.entry.w) * s;
        let (p, n, depth) = (self.p, self.n, self.depth);
        for _ in 0..steps {
            let bb = [b.x, b.y, 1.0 - b.x - b.y];
            let nn = n[0] * bb[0] + n[1] * bb[1] + n[2] * bb[2];
            let sink = depth * (1.0 - w);
            let x = (p[0] - n[0] * sink) * bb[0] + (p[1] - n[1] * sink) * bb[1] + (p[2] - n[2] * sink) * bb[2];
            let f = x - target;
            let c0 = (p[0] - p[2]) - (n[0] - n[2]) * sink;
            let c1 = (p[1] - p[2]) - (n[1] - n[2]) * sink;
            let c2 = nn * depth;
            let det = c0.dot(c1.cross(c2));
            if det.abs() <= 1e-30 {
                continue;
            }
            let rhs = -f;
            b.x += rhs.dot(c1.cross(c2)) / det;
            b.y += c0.dot(rhs.cross(c2)) / det;
            w += c0.dot(c1.cross(rhs)) / det;
        }
        (b, w)
    }

    fn uv(&self, b: DVec2) -> DVec2 {
        self.uv[2] + (self.uv[0] - self.uv[2]) * b.x + (self.uv[1] - self.uv[2]) * b.y
    }
}

/// How the emulation's search follows the view ray through a prism.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PrismPath {
    /// The straight texture-space chord from the entry to the exit (the shader before the
    /// bend, and the shader's path where the coarse stage reads maps).
    Chord,
    /// The chord bent by the quadratic through the view ray's point at its middle, found by
    /// [`PRISM_BEND_STEPS`] Newton steps from the chord's middle (the shader's `prism_bend`).
    Bent,
    /// The view ray's exact point at every read (Newton's inversion of the prism's map to
    /// convergence): what the bend approximates.
    Exact,
    /// The bent chord's quadratic followed by straight pieces through its points at `i/n`, n
    /// the fewest (at most the given count) that depart from it by at most
    /// 10⁻³ depths (`compose/mesh.rs`'s `piece_count`): the shader's path where
    /// the coarse stage reads maps (its piece search, a map's bounds holding along straight
    /// rays only).
    Pieces(u32),
}

impl PrismPath {
    /// The path's name in `relief scene measure --causes`'s lines.
    pub fn name(self) -> &'static str {
        match self {
            PrismPath::Chord => "chord",
            PrismPath::Bent => "bent chord",
            PrismPath::Exact => "exact curve",
            PrismPath::Pieces(_) => "pieces",
        }
    }
}

/// The shader's constants of the chord's bend (`compose/mesh.rs`: `PRISM_BEND_STEPS`,
/// `PRISM_BEND_MAX`, `PRISM_BEND_SHORT`).
pub const PRISM_BEND_STEPS: usize = 1;
const PRISM_BEND_MAX: f64 = 0.25;
const PRISM_BEND_SHORT: f64 = 1e-5;
/// The most straight pieces of the bent chord a coarse stage that reads maps follows, and how
/// far they may depart from its quadratic in the height comparison, in depths
/// (`compose/mesh.rs`: `PRISM_PIECES`, `PRISM_PIECE_TOLERANCE`; [`PrismPath::Pieces`]).
pub const PRISM_PIECES: u32 = 4;
const PRISM_PIECE_TOLERANCE: f64 = 1e-3;
/// Newton's steps of [`PrismPath::Exact`]: from the chord's point, far more than converge.
const EXACT_STEPS: usize = 8;

impl Chord {
    /// The chord between the crossings `entry` and `exit` of the prism with corner uvs `uv`,
    /// as `prism_chord` builds it; `None` where the shader discards it (a short chord that
    /// does not descend).
    fn new(entry: PrismCrossing, exit: PrismCrossing, uv: [DVec2; 3]) -> Option<Chord> {
        let at = |c: PrismCrossing| uv[2] + (uv[0] - uv[2]) * c.b.x + (uv[1] - uv[2]) * c.b.y;
        let (uv_in, uv_out) = (at(entry), at(exit));
        let duv = uv_out - uv_in;
        let r = entry.w - exit.w;
        let long = duv.length_squared() >= PRISM_SHORT_CHORD * PRISM_SHORT_CHORD || r <= 1e-4;
        if !long && r <= 0.0 {
            return None;
        }
        let k = if long { PRISM_CHORD_END } else { r };
        let slope = duv * (-(k - r) / duv.length_squared().max(1e-12));
        Some(Chord {
            origin: uv_in,
            dir: duv / k,
            lift0: 1.0 - entry.w,
            slope,
            k,
            path: Path::Chord,
            b_in: entry.b,
            b_out: exit.b,
        })
    }

    /// The chord bent along `path`, for the view ray and the prism `inv` holds, over a height
    /// map of `size` texels.
    fn bent(mut self, path: PrismPath, inv: Inversion, size: DVec2) -> Chord {
        self.path = match path {
            PrismPath::Chord => Path::Chord,
            PrismPath::Bent | PrismPath::Pieces(_) => {
                let (b, w) = inv.at(0.5, PRISM_BEND_STEPS);
                let (bc, wc) = ((inv.entry.b + inv.exit.b) * 0.5, (inv.entry.w + inv.exit.w) * 0.5);
                let (db, dw) = (b - bc, w - wc);
                let chord = inv.uv(inv.exit.b) - inv.uv(inv.entry.b);
                let len2 = chord.length_squared();
                let tame = db.x.abs() <= PRISM_BEND_MAX && db.y.abs() <= PRISM_BEND_MAX && dw.abs() <= PRISM_BEND_MAX;
                if tame && len2 >= PRISM_BEND_SHORT * PRISM_BEND_SHORT && db.is_finite() && dw.is_finite() {
                    let duv = inv.uv(b) - inv.uv(bc);
                    // `compose/mesh.rs`'s `piece_count`: |δ|/n² ≤ the tolerance, |δ| in layers
                    // plus texels along u and v.
                    let pieces = match path {
                        PrismPath::Pieces(most) => {
                            let sag = dw.abs() + (duv * size).abs().element_sum();
                            ((sag / PRISM_PIECE_TOLERANCE).sqrt().ceil() as u32).clamp(1, most)
                        }
                        _ => 0,
                    };
                    Path::Bent { duv, dw, db, axis: chord / len2, pieces }
                } else {
                    Path::Chord
                }
            }
            PrismPath::Exact => Path::Exact(Box::new(inv)),
        };
        self
    }

    /// The search's point at t: its uv and layer (on the chord, or bent), and its barycentrics
    /// where the path knows them.
    fn point(&self, t: f64) -> (DVec2, f64, Option<DVec2>) {
        let uv = self.origin + self.dir * t;
        let w = 1.0 - t - self.lift0 - self.slope.dot(uv - self.origin);
        match &self.path {
            Path::Chord => (uv, w, None),
            Path::Bent { duv, dw, db, axis, pieces } => {
                // The read's fraction from its texture point, as the shader's `bend` has it;
                // the barycentrics at the search's fraction, as `chord_search` carries them.
                let f = (uv - self.origin).dot(*axis);
                let bend = piece_weight(f, *pieces);
                let tau = (t / self.k).clamp(0.0, 1.0);
                let b = self.b_in + (self.b_out - self.b_in) * tau + *db * piece_weight(tau, *pieces);
                (uv + *duv * bend, w + dw * bend, Some(b))
            }
            Path::Exact(inv) => {
                let (b, w) = inv.at(t / self.k, EXACT_STEPS);
                (inv.uv(b), w, Some(b))
            }
        }
    }

    /// Whether the search's point at t lies on or below the height field.
    fn below(&self, ms: &MeshScene, t: f64) -> bool {
        let (uv, w, _) = self.point(t);
        height_at(ms, uv) >= w
    }
}

/// The bend's weight at the chord's fraction `f`: the quadratic `max(0, 4f(1 − f))`
/// (`stage::sampling::bend_weight`), or with `pieces` > 0 its straight pieces through its
/// values at `i/pieces` (0 outside the chord).
fn piece_weight(f: f64, pieces: u32) -> f64 {
    let q = |f: f64| (4.0 * f * (1.0 - f)).max(0.0);
    if pieces == 0 {
        return q(f);
    }
    if !(0.0..=1.0).contains(&f) {
        return 0.0;
    }
    let n = pieces as f64;
    let i = (f * n).floor().min(n - 1.0);
    let (a, b) = (i / n, (i + 1.0) / n);
    q(a) + (q(b) - q(a)) * (f - a) * n
}

/// The scene's height map, bilinear between texel centres under its edge mode (the
/// reference's `h`, `mesh::surface::Cell`).
fn height_at(ms: &MeshScene, uv: DVec2) -> f64 {
    let map = &ms.scene.height;
    let (x, y) = (uv.x * map.width as f64 - 0.5, uv.y * map.height as f64 - 0.5);
    let (i, j) = (x.floor() as i64, y.floor() as i64);
    crate::mesh::surface::Cell::new(map, ms.scene.edge, i, j).h(x, y)
}

/// The search `linear(steps)` then `binary(refine)` on the chord, as the stages write it
/// (`stage/coarse/linear.rs`, `stage/refine/binary.rs`): its t, and whether the shader draws
/// its result: not above the lifted field by more than its slack, not after the exit.
fn search_linear_binary(ms: &MeshScene, c: &Chord, steps: u32, refine: u32) -> (f64, bool) {
    let step = 1.0 / steps as f64;
    let mut t = 0.0;
    for _ in 0..steps {
        if c.below(ms, t) {
            break;
        }
        t += step;
    }
    let (above, bottom) = ((t - step).max(0.0), t);
    let t = if refine == 0 {
        bottom
    } else {
        let mut half = (bottom - above) / 2.0;
        let mut t = bottom - half;
        for _ in 0..refine {
            let b = c.below(ms, t);
            half /= 2.0;
            t += if b { -half } else { half };
        }
        t
    };
    let (uv, w, _) = c.point(t);
    (t, w - height_at(ms, uv) <= PRISM_ABOVE_SLACK && t <= c.k + PRISM_SLACK)
}

/// Whether the shader draws the search's result on the chord (`search_linear_binary`).
fn emulate_linear_binary(ms: &MeshScene, c: &Chord, steps: u32, refine: u32) -> bool {
    search_linear_binary(ms, c, steps, refine).1
}

/// The shader's polish constants (`compose/mesh.rs`: `POLISH_STEPS`, `POLISH_TOLERANCE`).
pub const POLISH_STEPS: usize = 3;
const POLISH_TOLERANCE: f64 = 1e-4;

/// The height map bilinear at `uv` and its gradient in texture units, from the four texels
/// (the shader's `height_and_gradient`, one gather, the scene's edge mode).
fn height_and_gradient(ms: &MeshScene, uv: DVec2) -> (f64, DVec2) {
    let map = &ms.scene.height;
    let size = DVec2::new(map.width as f64, map.height as f64);
    let g = uv * size - 0.5;
    let (i, j) = (g.x.floor() as i64, g.y.floor() as i64);
    let f = g - g.floor();
    let t = |x: i64, y: i64| map.texel(x, y, ms.scene.edge) as f64;
    let (h00, h10, h01, h11) = (t(i, j), t(i + 1, j), t(i, j + 1), t(i + 1, j + 1));
    let low = h00 + (h10 - h00) * f.x;
    let high = h01 + (h11 - h01) * f.x;
    let du = ((h10 - h00) * (1.0 - f.y) + (h11 - h01) * f.y) * size.x;
    let dv = ((h01 - h00) * (1.0 - f.x) + (h11 - h10) * f.x) * size.y;
    (low + (high - low) * f.y, DVec2::new(du, dv))
}

/// One prism's fragment as the CPU emulates it (f64): the hit it draws.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrismFragment {
    /// The triangle whose prism it is.
    pub triangle: usize,
    /// The drawn hit's distance along the ray (the polished point's where the polish was kept).
    pub t: f64,
    /// The search's hit on the chord, before the polish (its linear estimate along the ray).
    pub t_search: f64,
    /// Whether the polish was kept (converged to S within the prism, within a depth).
    pub polished: bool,
    /// What the polish ended at: `|F|` in depths, whether in the triangle, how far it moved
    /// along the ray in depths.
    pub polish_end: (f64, bool, f64),
    /// The search's resolution along the ray, in depths: its last bracket,
    /// `(t_exit − t_entry) / (k · steps · 2^refine)` (k the exit's t on the chord), how far an
    /// unpolished hit may move where f32 and f64 decide one step of the search differently.
    pub resolution: f64,
}

/// The fragment of the prism whose records include `v` on the ray `o + t·d` (d unit), as
/// `compose/mesh.rs` traces it: the exact entry and exit, the chord, `linear(steps)` then
/// `binary(refine)` on it, the discards, the search's hit carried to the view ray and
/// Newton's polish onto S (three steps from the search's (t, b), kept where it converges to
/// 1e-4 depths, stays in the triangle and moves at most a depth). `None`: discarded.
fn emulate_fragment(
    ms: &MeshScene,
    v: &MeshVertex,
    triangle: usize,
    o: DVec3,
    d: DVec3,
    (steps, refine): (u32, u32),
    rule: PolishRule,
) -> Option<PrismFragment> {
    let depth = ms.scene.depth_scale as f64;
    let (p, n, uv) = prism_corners(v);
    let (entry, exit) = prism_crossings(o, d, p, n, depth)?;
    let size = DVec2::new(ms.scene.height.width as f64, ms.scene.height.height as f64);
    let chord = Chord::new(entry, exit, uv)?.bent(rule.path, Inversion { p, n, uv, depth, o, d, entry, exit }, size);
    let (ts, drawn) = search_linear_binary(ms, &chord, steps, refine);
    if !drawn {
        return None;
    }
    let tau = (ts / chord.k).clamp(0.0, 1.0);
    let t0 = entry.t + (exit.t - entry.t) * tau;
    let b0 = chord.point(ts).2.unwrap_or(entry.b + (exit.b - entry.b) * tau);
    let (duv0, duv1) = (uv[0] - uv[2], uv[1] - uv[2]);
    let residual = |t: f64, b: DVec2| {
        let w = [b.x, b.y, 1.0 - b.x - b.y];
        let (h, grad) = height_and_gradient(ms, uv[2] + duv0 * b.x + duv1 * b.y);
        let pp = p[0] * w[0] + p[1] * w[1] + p[2] * w[2];
        let nn = n[0] * w[0] + n[1] * w[1] + n[2] * w[2];
        let sink = depth * (1.0 - h);
        let f = o + d * t - (pp - nn * sink);
        let column = |k: usize, duv: DVec2| -((p[k] - p[2]) - (n[k] - n[2]) * sink + nn * (depth * grad.dot(duv)));
        (f, column(0, duv0), column(1, duv1))
    };
    let (mut t, mut b) = (t0, b0);
    for _ in 0..rule.steps {
        let (f, c1, c2) = residual(t, b);
        let cross = c1.cross(c2);
        let det = d.dot(cross);
        if det.abs() > 1e-30 {
            let rhs = -f;
            t += rhs.dot(cross) / det;
            b += DVec2::new(d.dot(rhs.cross(c2)), d.dot(c1.cross(rhs))) / det;
        }
    }
    let (f, _, _) = residual(t, b);
    let inside = b.x >= -PRISM_FACE_SLACK && b.y >= -PRISM_FACE_SLACK && b.x + b.y <= 1.0 + PRISM_FACE_SLACK;
    let polished = f.length() <= depth * POLISH_TOLERANCE && inside && (t - t0).abs() <= depth;
    let converged_outside = f.length() <= depth * POLISH_TOLERANCE && !inside;
    if (rule.discard && !polished) || (rule.discard_outside && converged_outside) {
        return None;
    }
    Some(PrismFragment {
        triangle,
        t: if polished { t } else { t0 },
        t_search: t0,
        polished,
        polish_end: (f.length() / depth, inside, (t - t0) / depth),
        resolution: (exit.t - entry.t) / (chord.k * steps as f64 * 2f64.powi(refine as i32)) / depth,
    })
}

/// The nearest hit the prisms draw on the ray `o + t·d` (d unit) by the CPU's emulation of
/// every prism's fragment (`emulate_fragment`; the depth test keeps the nearest), or `None`.
/// Every prism the ray crosses is tried (the rasterized faces are not: a prism whose drawn
/// faces the ray misses counts too).
#[allow(clippy::too_many_arguments)]
pub fn emulate_prism_pixel(
    ms: &MeshScene,
    vertices: &[MeshVertex],
    indices: &[u32],
    o: DVec3,
    d: DVec3,
    search: (u32, u32),
    rule: PolishRule,
) -> Option<PrismFragment> {
    let depth = ms.scene.depth_scale as f64;
    (0..indices.len() / 24)
        .filter(|&tri| {
            // The prism's box (its six corners), widened by a hundredth of the depth: a ray that
            // misses it crosses no face of the prism.
            let v = &vertices[indices[tri * 24] as usize];
            let mut b =
                crate::mesh::surface::Aabb { lo: DVec3::splat(f64::INFINITY), hi: DVec3::splat(f64::NEG_INFINITY) };
            for (p, n) in [(v.prism_p0, v.prism_n0), (v.prism_p1, v.prism_n1), (v.prism_p2, v.prism_n2)] {
                let p = DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64);
                let n = DVec3::new(n[0] as f64, n[1] as f64, n[2] as f64);
                for c in [p, p - n * depth] {
                    b.lo = b.lo.min(c - 0.01 * depth);
                    b.hi = b.hi.max(c + 0.01 * depth);
                }
            }
            b.entry(o, d).is_some()
        })
        .filter_map(|tri| emulate_fragment(ms, &vertices[indices[tri * 24] as usize], tri, o, d, search, rule))
        .min_by(|a, b| a.t.total_cmp(&b.t))
}

/// The polish an emulated prism fragment runs: Newton's step count, and whether a fragment
/// whose polish is not kept is discarded (`false`: the shader's rule, the search's hit is
/// drawn; [`PolishRule::SHADER`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PolishRule {
    /// Newton steps.
    pub steps: usize,
    /// Discard where the polish is not kept.
    pub discard: bool,
    /// Discard where Newton converged onto S outside the triangle (the crossing it found is
    /// a neighbour's), keep the search's hit where it did not converge.
    pub discard_outside: bool,
    /// The path the search follows through the prism.
    pub path: PrismPath,
}

impl PolishRule {
    /// The shader's: [`POLISH_STEPS`] steps, the search's hit drawn where the polish is not kept.
    pub const SHADER: PolishRule =
        PolishRule { steps: POLISH_STEPS, discard: true, discard_outside: false, path: PrismPath::Bent };
}

/// Whether the chord meets the height field between its entry and its exit, by a dense march
/// (steps of 1/[`DENSE_STEPS`] of the chord).
fn chord_crosses(ms: &MeshScene, c: &Chord) -> bool {
    (0..=DENSE_STEPS).any(|k| c.below(ms, c.k * k as f64 / DENSE_STEPS as f64))
}

/// For each pixel that the reference hits and `probe` (a `curved=prism` measurement of `ms`
/// with `linear(steps)+binary(refine)`, `size²`) leaves out, its index and its cause
/// ([`PrismMiss`]). Every face of the prism of the reference's hit triangle computes the same
/// exact entry and exit, so the prism's trace is emulated once per pixel: its ray meets no
/// face of that prism as rasterized (`NoFace`); the CPU's emulation draws it (`Other`); the
/// chord crosses the height field before its exit and the search stepped over it (`Search`);
/// else `AfterExit`.
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
        let met = indices[tri * 24..tri * 24 + 24].chunks_exact(3).any(|f| {
            let [a, b, c] = [f[0], f[1], f[2]].map(|k| corner(&vertices[k as usize]));
            crate::mesh::reference::ray_triangle(o, d, a, b, c).is_some()
        });
        let cause = if !met {
            PrismMiss::NoFace
        } else {
            classify(ms, &vertices[indices[tri * 24] as usize], o, d, depth, steps, refine)
        };
        out.push((i, cause));
    }
    out
}

/// The prism's triangle as a prism record `v` carries it, in f64: its corners' points,
/// normals and uvs (`prism_p*`, `prism_n*`, `prism_a`/`prism_b.xy`).
fn prism_corners(v: &MeshVertex) -> ([DVec3; 3], [DVec3; 3], [DVec2; 3]) {
    let v3 = |a: [f32; 4]| DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64);
    let (pa, pb) = (v.prism_a, v.prism_b);
    (
        [v.prism_p0, v.prism_p1, v.prism_p2].map(v3),
        [v.prism_n0, v.prism_n1, v.prism_n2].map(v3),
        [
            DVec2::new(pa[0] as f64, pa[1] as f64),
            DVec2::new(pa[2] as f64, pa[3] as f64),
            DVec2::new(pb[0] as f64, pb[1] as f64),
        ],
    )
}

/// The cause of a missing pixel whose ray meets a face of the prism whose records include
/// `v` ([`prism_miss_causes`]).
fn classify(ms: &MeshScene, v: &MeshVertex, o: DVec3, d: DVec3, depth: f64, steps: u32, refine: u32) -> PrismMiss {
    let (p, n, uv) = prism_corners(v);
    let Some(chord) = prism_crossings(o, d, p, n, depth).and_then(|(entry, exit)| {
        let size = DVec2::new(ms.scene.height.width as f64, ms.scene.height.height as f64);
        Chord::new(entry, exit, uv)
            .map(|c| c.bent(PrismPath::Bent, Inversion { p, n, uv, depth, o, d, entry, exit }, size))
    }) else {
        return PrismMiss::AfterExit;
    };
    if emulate_linear_binary(ms, &chord, steps, refine) {
        PrismMiss::Other
    } else if chord_crosses(ms, &chord) {
        PrismMiss::Search
    } else {
        PrismMiss::AfterExit
    }
}

/// The t error a prism hit may carry and count as on the reference's: issue 38's RMS goal,
/// 1e-3 depths, taken per pixel ([`prism_t_causes`]).
pub const T_BOUND: f64 = 1e-3;

/// Why a pixel both hit has `|t_gpu − t_ref| > `[`T_BOUND`] depths under `curved=prism`
/// (docs/notes/meshes.md, "The t error by cause"); the first that holds, in this order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum PrismTCause {
    /// (iii) The GPU's hit or the reference's lies within [`T_BOUND`] depths, along the ray,
    /// of the ray's crossing with the wall of a uv seam (an edge two triangles share in space
    /// with different uvs, where the heights on its two sides may differ and S be open,
    /// [`seam_walls`]).
    Seam,
    /// (ii) The CPU's emulation of the prisms' fragments ([`emulate_prism_pixel`]) gives the
    /// GPU's t (within [`emulation_bound`]), and the prism that draws it did not keep its
    /// polish: the hit is the chord's estimate, off S.
    Polish,
    /// (i) The same pixel under a denser search (the `dense` probe of [`prism_t_causes`])
    /// meets the reference within [`T_BOUND`] depths: the search stepped over a crossing.
    Search,
    /// (i) Not that, but the prism of the reference's triangle, emulated with a search that
    /// cannot step over a crossing of its chord wider than 1/4096 of it (a dense march, then
    /// bisection), draws a hit within [`T_BOUND`] depths of the reference's: the crossing is
    /// narrower than the dense probe's steps, and both searches stepped over it.
    ThinSearch,
    /// The prism of the reference's triangle, emulated with that dense march, draws no hit
    /// within [`T_BOUND`] depths of the reference's: its chord, bent by a quadratic in texture
    /// space ([`PrismPath::Bent`]), does not meet the relief where the view ray does (prism's
    /// own).
    Chord,
    /// (iv) The CPU's emulation does not give the GPU's t (beyond [`emulation_bound`]), so the
    /// causes above, which read it, cannot be decided; or none of them holds.
    Other,
}

impl PrismTCause {
    /// Every cause, in the order they are decided.
    pub const ALL: [PrismTCause; 6] = [
        PrismTCause::Seam,
        PrismTCause::Polish,
        PrismTCause::Search,
        PrismTCause::ThinSearch,
        PrismTCause::Chord,
        PrismTCause::Other,
    ];

    /// The cause's short name (`relief scene measure --causes`).
    pub fn name(self) -> &'static str {
        match self {
            PrismTCause::Seam => "seam",
            PrismTCause::Polish => "polish",
            PrismTCause::Search => "search",
            PrismTCause::ThinSearch => "search-thin",
            PrismTCause::Chord => "chord",
            PrismTCause::Other => "other",
        }
    }
}

/// One pixel of [`prism_t_causes`]: its index, its error and what each check found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrismTError {
    /// The pixel (row-major).
    pub index: usize,
    /// `(t_gpu − t_ref) / depth`.
    pub dt: f64,
    /// The same for the dense probe (`None`: it does not hit the pixel).
    pub dense_dt: Option<f64>,
    /// `(t_emulated − t_ref) / depth` of the CPU's emulation (`None`: it draws nothing).
    pub emulated_dt: Option<f64>,
    /// Whether the emulation's drawing prism kept its polish (`None`: it draws nothing).
    pub polished: Option<bool>,
    /// The emulation's drawing fragment (`None`: it draws nothing).
    pub fragment: Option<PrismFragment>,
    /// Whether a hit lies at a seam wall ([`PrismTCause::Seam`]).
    pub seam: bool,
    /// The first cause that holds.
    pub cause: PrismTCause,
}

/// The side walls of the mesh's uv seams where S is open: each edge two triangles share in
/// space (positions equal to the bit) whose uvs differ on the two sides by other than whole
/// tiles under repeat edges (by anything under clamp), as `(F_i, F_j, D_i, D_j)` (the floor
/// corners and depth times the normals, the arguments of the wall's ray crossing).
pub fn seam_walls(ms: &MeshScene) -> Vec<[DVec3; 4]> {
    use std::collections::HashMap;
    let mesh = &ms.mesh;
    let depth = ms.scene.depth_scale as f64;
    let key = |i: u32| mesh.positions[i as usize].to_array().map(f32::to_bits);
    // A position's key (its bits), an edge's key (its two ends, ordered) and the edges of the
    // triangles that share it in space (vertex indices, in that order).
    type Key = [u32; 3];
    let mut edges: HashMap<(Key, Key), Vec<(u32, u32)>> = HashMap::new();
    for tri in &mesh.triangles {
        for (a, b) in [(tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])] {
            let (a, b) = if key(a) <= key(b) { (a, b) } else { (b, a) };
            edges.entry((key(a), key(b))).or_default().push((a, b));
        }
    }
    let differ = |x: f32, y: f32| {
        let d = (x - y) as f64;
        let d = if ms.scene.edge == EdgeMode::Repeat { d - d.round() } else { d };
        d.abs() > 1e-6
    };
    let mut out = Vec::new();
    for sides in edges.values() {
        let uv = |i: u32| mesh.uvs[i as usize];
        let open = sides.iter().any(|&(a, b)| {
            let (a0, b0) = sides[0];
            [(uv(a), uv(a0)), (uv(b), uv(b0))].iter().any(|(x, y)| differ(x.x, y.x) || differ(x.y, y.y))
        });
        if open {
            let (a, b) = sides[0];
            let (pa, pb) = (mesh.positions[a as usize].as_dvec3(), mesh.positions[b as usize].as_dvec3());
            let (na, nb) = (mesh.normals[a as usize].as_dvec3() * depth, mesh.normals[b as usize].as_dvec3() * depth);
            out.push([pa - na, pb - nb, na, nb]);
        }
    }
    out
}

/// Whether the point at `t` of the ray `o + t·d` lies within [`T_BOUND`] depths, along the
/// ray, of its crossing with one of the seam walls `walls` ([`seam_walls`]).
pub fn near_seam(walls: &[[DVec3; 4]], o: DVec3, d: DVec3, t: f64, depth: f64) -> bool {
    walls
        .iter()
        .any(|w| wall_crossings(o, d, w[0], w[1], w[2], w[3]).iter().any(|c| (c.0 - t).abs() <= T_BOUND * depth))
}

/// Whether the ray `o + t·d` crosses one of the seam walls `walls` ([`seam_walls`]) before
/// `t` (or within [`T_BOUND`] depths after it): a ray that passes S's crack at a uv seam.
pub fn crosses_a_seam_before(walls: &[[DVec3; 4]], o: DVec3, d: DVec3, t: f64, depth: f64) -> bool {
    walls.iter().any(|w| wall_crossings(o, d, w[0], w[1], w[2], w[3]).iter().any(|c| c.0 <= t + T_BOUND * depth))
}

/// For each pixel that `reference` and `probe` (a `curved=prism` measurement of `ms` with
/// `linear(steps)+binary(refine)`, `size²`) both hit with `|t_gpu − t_ref| > `[`T_BOUND`]
/// depths, its cause ([`PrismTCause`]); `dense` is a `curved=prism` measurement of the same
/// scene and size with a denser search (e.g. `linear(256)+binary(8)`), the check of
/// [`PrismTCause::Search`]. The polish is decided by the CPU's emulation of every prism's
/// fragment on the pixel's ray ([`emulate_prism_pixel`]), the seams by [`seam_walls`].
pub fn prism_t_causes(
    ms: &MeshScene,
    reference: &[Option<MeshHit>],
    probe: &MeshProbe,
    dense: &MeshProbe,
    size: u32,
    steps: u32,
    refine: u32,
) -> Vec<PrismTError> {
    let (vertices, indices) = crate::mesh::vertices::mesh_vertices(&ms.mesh, Curved::Prism);
    let rays = ms.rays(size, size);
    let depth = ms.scene.depth_scale as f64;
    let walls = seam_walls(ms);
    let mut out = Vec::new();
    for (i, (g, r)) in probe.hits.iter().zip(reference).enumerate() {
        let (true, Some(r)) = (g[3] > 0.5, r) else { continue };
        let dt = (g[2] as f64 - r.t) / depth;
        if dt.abs() <= T_BOUND {
            continue;
        }
        let ray = &rays[i];
        let (o, d) = (DVec3::from(ray.origin.map(|c| c as f64)), DVec3::from(ray.dir.map(|c| c as f64)));
        let seam = near_seam(&walls, o, d, g[2] as f64, depth) || near_seam(&walls, o, d, r.t, depth);
        let emulated = emulate_prism_pixel(ms, &vertices, &indices, o, d, (steps, refine), PolishRule::SHADER);
        let emulated_dt = emulated.map(|e| (e.t - r.t) / depth);
        let dense_dt = dense.hits.get(i).filter(|h| h[3] > 0.5).map(|h| (h[2] as f64 - r.t) / depth);
        let agrees = emulated.is_some_and(|e| ((e.t - r.t) / depth - dt).abs() <= emulation_bound(&e));
        let tri = r.triangle as usize;
        let cause = if seam {
            PrismTCause::Seam
        } else if !agrees {
            PrismTCause::Other
        } else if emulated.is_some_and(|e| !e.polished) {
            PrismTCause::Polish
        } else if dense_dt.is_some_and(|x| x.abs() <= T_BOUND) {
            PrismTCause::Search
        } else if chord_draws(ms, &vertices[indices[tri * 24] as usize], tri, o, d, r.t) {
            PrismTCause::ThinSearch
        } else {
            PrismTCause::Chord
        };
        out.push(PrismTError {
            index: i,
            dt,
            dense_dt,
            emulated_dt,
            polished: emulated.map(|e| e.polished),
            fragment: emulated,
            seam,
            cause,
        });
    }
    out
}

/// How far (depths) the GPU's t may lie from the CPU's emulation of the fragment `e` that
/// draws it: [`T_BOUND`], and for an unpolished hit two of the search's last brackets
/// ([`PrismFragment::resolution`]: f32 and f64 may decide a step differently).
pub fn emulation_bound(e: &PrismFragment) -> f64 {
    if e.polished {
        T_BOUND
    } else {
        T_BOUND + 2.0 * e.resolution
    }
}

/// Whether the prism of `triangle` (its records include `v`), its chord searched by a march
/// of [`DENSE_STEPS`] steps then 12 bisections, draws a hit within [`T_BOUND`] depths of
/// `t_ref` on the ray `o + t·d`.
fn chord_draws(ms: &MeshScene, v: &MeshVertex, triangle: usize, o: DVec3, d: DVec3, t_ref: f64) -> bool {
    let depth = ms.scene.depth_scale as f64;
    emulate_fragment(ms, v, triangle, o, d, (DENSE_STEPS, 12), PolishRule::SHADER)
        .is_some_and(|f| (f.t - t_ref).abs() <= T_BOUND * depth)
}

/// The RMS of `(t_gpu − t_ref) / depth` over the pixels `gpu` and `reference` both hit but
/// those in `leave_out` (NaN when none is left): [`MeshScore::rms_t`] without some pixels.
pub fn rms_t_without(gpu: &MeshProbe, reference: &[Option<MeshHit>], ms: &MeshScene, leave_out: &[usize]) -> f64 {
    let depth = ms.scene.depth_scale as f64;
    let skip: std::collections::HashSet<usize> = leave_out.iter().copied().collect();
    let (mut sum, mut n) = (0.0, 0usize);
    for (i, (g, r)) in gpu.hits.iter().zip(reference).enumerate() {
        if let (true, Some(r), false) = (g[3] > 0.5, r, skip.contains(&i)) {
            let dt = (g[2] as f64 - r.t) / depth;
            sum += dt * dt;
            n += 1;
        }
    }
    if n > 0 {
        (sum / n as f64).sqrt()
    } else {
        f64::NAN
    }
}
