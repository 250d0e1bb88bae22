//! One measurement: a pipeline on a prepared scene — frame times from the render entry,
//! hits from the probe entry, the exact reference for the same rays, and the metrics.
//! `relief render` measures one; `relief sweep` measures a grid, preparing each scene once.

use std::path::Path;

use crate::error::{Error, Result};
use crate::gpu::{self, Clock, Gpu, GpuHit, Program, RenderResult, Renderer, SceneTextures};
use crate::heightmap::{EdgeMode, HeightMap};
use crate::io;
use crate::metrics::{self, Metrics};
use crate::reference::{clip_to_square, ray_levels, reference_hits, reference_hits_at_levels, RefHit, Sampling};
use crate::scene::{ProbeRay, Scene};
use relief_dsl::spec::{Lod, Silhouette};

/// A scene on the device, with its probe rays and their exact first hits (computed once,
/// shared by every pipeline measured on it).
pub struct Prepared {
    /// The scene as given (heights as loaded).
    pub scene: Scene,
    /// The scene with the heights as the device stores them: the surface measured against.
    pub on_device: Scene,
    /// The scene's textures on the device; each measurement adds the maps it needs.
    pub textures: SceneTextures,
    /// One probe ray per pixel that sees the quad, row-major ([`Scene::rays`]).
    pub rays: Vec<ProbeRay>,
    /// The exact first hit of each ray in `rays` (same index) on `on_device`'s bilinear
    /// surface at level 0; `None` where the reference finds none.
    pub refs: Vec<Option<RefHit>>,
    /// Side of the square frame, in pixels.
    pub size: u32,
    /// Per `lod` other than zero: the level each ray samples and its exact hits on that
    /// level's surface (computed on first use).
    pub lod_refs: std::collections::HashMap<Lod, (Vec<usize>, Vec<Option<RefHit>>)>,
    /// The baseline's renderer on this scene, for paired timing (built on first use).
    baseline: Option<Baseline>,
}

/// The pipeline every cell of a sweep is timed against, in alternating blocks on the same
/// scene ([`measure_paired`]): 32 linear steps then 5 binary steps (Burger 2018, Algorithms
/// 1 and 2), the common relief-mapping search; it reads the height map only (no map to
/// build, the same work on every scene's kind of map) and is the pipeline of the
/// hand-written benchmark. It is measured on each scene under that scene's `lod` policy.
pub const BASELINE: &str = "linear(32)+binary(5)";

/// The baseline drawn on a prepared scene, with its frames per block.
struct Baseline {
    pipeline: String,
    renderer: Renderer,
    frames_per_block: u32,
}

impl Prepared {
    /// Uploads `scene` and traces the reference for one ray per pixel at `size²`.
    pub fn new(gpu: &Gpu, scene: Scene, size: u32) -> Result<Prepared> {
        let textures = SceneTextures::new(gpu, &scene);
        let mut on_device = scene.clone();
        on_device.height.data = textures.heights_on_device.clone();
        let rays = scene.rays(size);
        let refs =
            reference_hits(&on_device, &rays, Sampling::Bilinear).map_err(|e| Error::from(e).in_scene(&scene.name))?;
        Ok(Prepared { scene, on_device, textures, rays, refs, size, lod_refs: Default::default(), baseline: None })
    }

    /// The exact hits under `lod`, once [`Prepared::refs_for`] has computed them (a panic
    /// before: never the level-0 hits in their place).
    pub(crate) fn refs_at(&self, lod: Lod) -> &[Option<RefHit>] {
        if lod == Lod::Zero {
            return &self.refs;
        }
        let (_, r) = self.lod_refs.get(&lod).unwrap_or_else(|| panic!("refs_at(lod={lod}) before refs_for"));
        r
    }

    /// The level of each ray and the exact hits on those levels' surfaces under `lod`
    /// (`ray_levels`, `reference_hits_at_levels` on the chain as the device stores it).
    pub fn refs_for(&mut self, lod: Lod) -> Result<(&[usize], &[Option<RefHit>])> {
        if lod == Lod::Zero {
            return Ok((&[], &self.refs));
        }
        if !self.lod_refs.contains_key(&lod) {
            let chain = &self.textures.height_levels;
            let size = [chain[0].width, chain[0].height];
            let levels = ray_levels(&self.scene, &self.rays, lod, size, chain.len()).map_err(Error::Input)?;
            let refs = reference_hits_at_levels(chain, self.scene.edge, &self.rays, &levels, Sampling::Bilinear)
                .map_err(|e| Error::from(e).in_scene(format!("{} at lod={lod}", self.scene.name)))?;
            self.lod_refs.insert(lod, (levels, refs));
        }
        let (l, r) = &self.lod_refs[&lod];
        Ok((l, r))
    }
}

/// The outcome of measuring one pipeline.
pub struct Measured {
    /// The metrics of the run, as a results row records them.
    pub metrics: Metrics,
    /// The timed frame times and the last frame's pixels.
    pub frame: RenderResult,
    /// The probe's raw hit for each ray of [`Prepared::rays`], same order.
    pub hits: Vec<GpuHit>,
    /// The reference hits the metrics compared with: the prepared scene's on the level the
    /// pipeline's `lod` samples, clipped to the quad's square for `silhouette=clip`.
    pub refs: Vec<Option<RefHit>>,
    /// The pipeline's `lod`.
    pub lod: Lod,
}

/// Builds the maps `pipeline` needs (once per scene), renders `frames` timed frames after
/// `warmup`, probes every ray, and compares with the reference.
pub fn measure(
    gpu: &Gpu,
    prep: &mut Prepared,
    pipeline: &relief_dsl::Pipeline,
    warmup: u32,
    frames: u32,
) -> Result<Measured> {
    measure_with(gpu, prep, pipeline, &relief_dsl::compose::Options::default(), warmup, frames)
}

/// [`measure`] with compose `options`; with `frag_depth`, the frame's depth buffer is kept
/// and compared with the reference hits' depth ([`depth_errors`]).
pub fn measure_with(
    gpu: &Gpu,
    prep: &mut Prepared,
    pipeline: &relief_dsl::Pipeline,
    options: &relief_dsl::compose::Options,
    warmup: u32,
    frames: u32,
) -> Result<Measured> {
    let cell = Cell::new(gpu, prep, pipeline, options)?;
    let frame = gpu::render(gpu, &cell.program, &prep.scene, &prep.textures, prep.size, warmup, frames)?;
    let mut m = cell.metrics(gpu, prep);
    metrics::set_timing(&mut m, &frame.frame_ms);
    m.frames_per_block = frame.frames_per_block;
    m.timestamp_period_ns = frame.timestamp_period_ns;
    cell.finish(gpu, prep, m, frame)
}

/// [`measure`] with paired timing: the pipeline's frames are timed in blocks alternating
/// with blocks of the scene's [`BASELINE`] (`pairs` pairs, after `warmup` untimed frames of
/// each and the blocks that calibrate their lengths; `gpu::paired_blocks`). The metrics'
/// frame times are the pipeline's blocks, and `frame_ratio_to_baseline` with its 95 %
/// interval compares them with the baseline's blocks of the same pairs
/// (`crate::timing::paired_ratio`).
pub fn measure_paired(
    gpu: &Gpu,
    prep: &mut Prepared,
    pipeline: &relief_dsl::Pipeline,
    warmup: u32,
    pairs: u32,
) -> Result<Measured> {
    measure_paired_against(gpu, prep, pipeline, BASELINE, warmup, pairs)
}

/// [`measure_paired`] against another baseline than [`BASELINE`]: `baseline` in the text
/// form, drawn under the scene's `lod` policy (`relief tune` times against Bevy's default).
/// The prepared scene keeps one baseline renderer; another baseline replaces it.
pub(crate) fn measure_paired_against(
    gpu: &Gpu,
    prep: &mut Prepared,
    pipeline: &relief_dsl::Pipeline,
    baseline: &str,
    warmup: u32,
    pairs: u32,
) -> Result<Measured> {
    let cell = Cell::new(gpu, prep, pipeline, &relief_dsl::compose::Options::default())?;
    let clock = Clock::new(gpu)?;
    prep.baseline(gpu, &clock, baseline, warmup)?;
    let base = prep.baseline.as_ref().expect("built above");
    let r = Renderer::new(gpu, &cell.program, &prep.scene, &prep.textures, prep.size)?;
    let draw = |p: &mut wgpu::RenderPass<'_>| r.draw(p);
    r.target.untimed(gpu, warmup, &draw)?;
    let k = clock.calibrate(gpu, &r.target, &draw)?;
    let blocks = gpu::paired_blocks(gpu, &clock, &r, &base.renderer, [k, base.frames_per_block], pairs)?;
    let ratio = blocks.ratio();
    let f = r.target.read(gpu, blocks.a_ms.clone())?;
    let frame = RenderResult {
        frame_ms: f.frame_ms,
        rgba: f.rgba,
        size: prep.size,
        depth: f.depth,
        frames_per_block: k,
        timestamp_period_ns: clock.period_ns,
    };
    let mut m = cell.metrics(gpu, prep);
    metrics::set_timing(&mut m, &frame.frame_ms);
    m.frames_per_block = k;
    m.timestamp_period_ns = clock.period_ns;
    m.baseline = base.pipeline.clone();
    m.timing_pairs = ratio.pairs;
    let finite = |v: f64| v.is_finite().then_some(v);
    m.frame_ratio_to_baseline = finite(ratio.ratio);
    m.frame_ratio_to_baseline_lo = finite(ratio.lo);
    m.frame_ratio_to_baseline_hi = finite(ratio.hi);
    cell.finish(gpu, prep, m, frame)
}

/// One pipeline's accuracy on a prepared scene, without frames: the probe on every ray
/// scored against the reference ([`score`]); the metrics' frame-time fields stay unset.
/// What `relief tune` measures at the views where it does not time.
pub(crate) fn measure_accuracy(gpu: &Gpu, prep: &mut Prepared, pipeline: &relief_dsl::Pipeline) -> Result<Metrics> {
    let cell = Cell::new(gpu, prep, pipeline, &relief_dsl::compose::Options::default())?;
    let mut m = cell.metrics(gpu, prep);
    cell.probe_and_score(gpu, prep, &mut m)?;
    Ok(m)
}

impl Prepared {
    /// Builds the scene's baseline renderer on first use (`baseline`, [`BASELINE`] for a
    /// sweep, under the scene's `lod` policy): its maps, `warmup` untimed frames, its frames
    /// per block. A renderer of another baseline is replaced.
    fn baseline(&mut self, gpu: &Gpu, clock: &Clock, baseline: &str, warmup: u32) -> Result<()> {
        let base: relief_dsl::Pipeline = baseline
            .parse()
            .map_err(|e| Error::Input(format!("baseline `{}`: {e}", relief_dsl::spec::echo(baseline))))?;
        let p = self.scene.pipeline_for(&base);
        if self.baseline.as_ref().is_some_and(|b| b.pipeline == p.to_string()) {
            return Ok(());
        }
        let program = Program::new(&p)?;
        self.textures.add_maps_lod(gpu, &self.scene, &p.required_maps(), p.lod)?;
        let renderer = Renderer::new(gpu, &program, &self.scene, &self.textures, self.size)?;
        let draw = |pass: &mut wgpu::RenderPass<'_>| renderer.draw(pass);
        renderer.target.untimed(gpu, warmup, &draw)?;
        let frames_per_block = clock.calibrate(gpu, &renderer.target, &draw)?;
        self.baseline = Some(Baseline { pipeline: p.to_string(), renderer, frames_per_block });
        Ok(())
    }
}

/// A pipeline being measured on a prepared scene: as measured (the scene's `lod` policy
/// applied), compiled, its maps and reference hits ready.
struct Cell {
    pipeline: relief_dsl::Pipeline,
    program: Program,
}

impl Cell {
    fn new(
        gpu: &Gpu,
        prep: &mut Prepared,
        pipeline: &relief_dsl::Pipeline,
        options: &relief_dsl::compose::Options,
    ) -> Result<Cell> {
        // The scene's level policy applies to a pipeline that names no lod; the metrics record
        // the pipeline as measured.
        let pipeline = prep.scene.pipeline_for(pipeline);
        if pipeline.silhouette == Silhouette::Clip && prep.scene.edge != EdgeMode::Clamp {
            return Err(Error::Input(format!(
                "silhouette=clip needs a scene with clamp edges; scene `{}` repeats its height map (set `edge = \"clamp\"` in a scene file)",
                prep.scene.name
            )));
        }
        let program = Program::new_with(&pipeline, options)?;
        // Checked before the GPU runs: a level the map does not have is an error.
        prep.refs_for(pipeline.lod)?;
        prep.textures.add_maps_lod(gpu, &prep.scene, &pipeline.required_maps(), pipeline.lod)?;
        Ok(Cell { pipeline, program })
    }

    /// The row's naming fields.
    fn metrics(&self, gpu: &Gpu, prep: &Prepared) -> Metrics {
        Metrics {
            pipeline: self.pipeline.clone(),
            scene: prep.scene.name.clone(),
            size: prep.size,
            adapter: format!("{} ({})", gpu.adapter, gpu.driver),
            ..Default::default()
        }
    }

    /// Probes every ray and scores the hits ([`score`]; and the depth buffer).
    fn finish(self, gpu: &Gpu, prep: &mut Prepared, mut m: Metrics, frame: RenderResult) -> Result<Measured> {
        let (hits, refs) = self.probe_and_score(gpu, prep, &mut m)?;
        if let Some(depth) = &frame.depth {
            m.depth_err_max = Some(depth_errors(prep, &refs, depth).into_iter().fold(0.0, f64::max));
        }
        Ok(Measured { metrics: m, frame, hits, refs, lod: self.pipeline.lod })
    }

    /// Probes every ray and scores the hits into `m` ([`score`]): the hits and the reference
    /// hits scored against.
    fn probe_and_score(
        &self,
        gpu: &Gpu,
        prep: &mut Prepared,
        m: &mut Metrics,
    ) -> Result<(Vec<GpuHit>, Vec<Option<RefHit>>)> {
        let pipeline = &self.pipeline;
        let hits = gpu::probe(gpu, &self.program, &prep.scene, &prep.textures, &prep.rays)?;
        let levels = match pipeline.lod {
            Lod::Zero => Vec::new(),
            lod => prep.refs_for(lod)?.0.to_vec(),
        };
        let chain = match pipeline.lod {
            Lod::Zero => std::slice::from_ref(&prep.on_device.height),
            _ => &prep.textures.height_levels[..],
        };
        let reference = Reference {
            rays: &prep.rays,
            refs: prep.refs_at(pipeline.lod),
            chain,
            levels: &levels,
            edge: prep.scene.edge,
            tiling: prep.scene.tiling as f64,
            whole_frame: true,
        };
        let refs = score(m, pipeline, &reference, &hits)?;
        Ok((hits, refs))
    }
}

/// What a pipeline's raw probe hits are scored against ([`score`]).
pub struct Reference<'a> {
    /// The probe rays, in the order of the hits.
    pub rays: &'a [ProbeRay],
    /// The exact first hit of each ray (same index) on the surface it samples; `None`
    /// where the reference finds none.
    pub refs: &'a [Option<RefHit>],
    /// The height levels as the device stores them, level 0 first (one level for a
    /// pipeline under `lod=zero`).
    pub chain: &'a [HeightMap],
    /// The level each ray samples (empty: level 0 for every ray).
    pub levels: &'a [usize],
    /// The scene's edge mode.
    pub edge: EdgeMode,
    /// The scene's tiling: the square `silhouette=clip` keeps hits in is [0, tiling]².
    pub tiling: f64,
    /// Whether `rays` are every ray of the frame. The SIMD cost model groups neighbouring
    /// pixels, so on a subsample (every k-th ray) its fields are NaN (not measured).
    pub whole_frame: bool,
}

/// Scores a pipeline's raw probe hits against the reference: the accuracy fields of `m`
/// ([`metrics::set_accuracy_levels`], the rules of [`metrics::Accuracy`]) and the SIMD cost
/// model (`crate::simd::simd_cost`). The one scoring of the sweep, `relief render` and
/// the hits a browser measured (`relief report --add`). Returns the reference hits scored
/// against: `reference.refs`, clipped to the quad's square for `silhouette=clip`.
///
/// Hits and rays of different counts are an error: scoring the shorter list would hide
/// the rays without a hit.
pub fn score(
    m: &mut Metrics,
    pipeline: &relief_dsl::Pipeline,
    reference: &Reference<'_>,
    hits: &[GpuHit],
) -> Result<Vec<Option<RefHit>>> {
    let r = reference;
    if hits.len() != r.rays.len() || r.refs.len() != r.rays.len() {
        return Err(Error::Input(format!(
            "`{pipeline}`: {} probe hits and {} reference hits for {} rays",
            hits.len(),
            r.refs.len(),
            r.rays.len()
        )));
    }
    let refs = if pipeline.silhouette == Silhouette::Clip { clip_to_square(r.refs, r.tiling) } else { r.refs.to_vec() };
    metrics::set_accuracy_levels(m, r.rays, hits, &refs, r.chain, r.levels, r.edge);
    let cost = crate::simd::simd_cost(r.rays, hits);
    let whole = |x: f64| if r.whole_frame { x } else { f64::NAN };
    m.simd32_steps = whole(cost.simd32_steps);
    m.simd64_steps = whole(cost.simd64_steps);
    m.simd32_fetches = whole(cost.simd32_fetches);
    m.simd32_divergence = whole(cost.simd32_divergence);
    Ok(refs)
}

/// What [`compare`] measured: two pipelines timed in alternating blocks on one scene.
pub struct Comparison {
    /// The two pipelines as measured (the scene's `lod` policy applied), A first.
    pub pipelines: [String; 2],
    /// The ratio of A's mean frame time to B's, with its 95 % interval.
    pub ratio: crate::timing::Ratio,
    /// The blocks behind it.
    pub blocks: gpu::PairedBlocks,
    /// The SIMD cost model of each (`crate::simd`), from the probe on the frame's rays.
    pub cost: [crate::simd::SimdCost; 2],
}

/// Times pipelines `a` and `b` on `scene` at `size²` in `pairs` pairs of alternating blocks
/// (after `warmup` untimed frames of each and the blocks that calibrate their lengths), and
/// probes each once for the SIMD cost model. No reference is traced: this is timing only.
pub fn compare(
    gpu: &Gpu,
    scene: &Scene,
    size: u32,
    a: &relief_dsl::Pipeline,
    b: &relief_dsl::Pipeline,
    warmup: u32,
    pairs: u32,
) -> Result<Comparison> {
    let mut tex = SceneTextures::new(gpu, scene);
    let rays = scene.rays(size);
    let clock = Clock::new(gpu)?;
    let mut sides = Vec::new();
    for p in [a, b] {
        let p = scene.pipeline_for(p);
        if p.silhouette == Silhouette::Clip && scene.edge != EdgeMode::Clamp {
            return Err(Error::Input(format!(
                "`{p}`: silhouette=clip needs a scene with clamp edges; scene `{}` repeats its height map",
                scene.name
            )));
        }
        let program = Program::new(&p)?;
        tex.add_maps_lod(gpu, scene, &p.required_maps(), p.lod)?;
        let r = Renderer::new(gpu, &program, scene, &tex, size)?;
        let draw = |pass: &mut wgpu::RenderPass<'_>| r.draw(pass);
        r.target.untimed(gpu, warmup, &draw)?;
        let k = clock.calibrate(gpu, &r.target, &draw)?;
        let hits = gpu::probe(gpu, &program, scene, &tex, &rays)?;
        sides.push((p.to_string(), r, k, crate::simd::simd_cost(&rays, &hits)));
    }
    let blocks = gpu::paired_blocks(gpu, &clock, &sides[0].1, &sides[1].1, [sides[0].2, sides[1].2], pairs)?;
    Ok(Comparison {
        pipelines: [sides[0].0.clone(), sides[1].0.clone()],
        ratio: blocks.ratio(),
        blocks,
        cost: [sides[0].3, sides[1].3],
    })
}

/// The NDC depth of the reference hit of every probe ray (one per covered pixel) against the
/// depth buffer at that pixel: |depth − depth_ref|. The reference hit `(u, v, z)` lies at
/// `(u, v, (z − 1)·depth_scale)` in the quad's space, and its depth is that point under the
/// camera's view-projection, in f64. Where the reference has no hit (`silhouette=clip`) the
/// pixel must keep the cleared depth 1: error 0 if it does, infinite if anything was drawn.
pub fn depth_errors(prep: &Prepared, refs: &[Option<RefHit>], depth: &[f32]) -> Vec<f64> {
    let vp = prep.scene.camera.view_proj(1.0).as_dmat4();
    let d = prep.scene.depth_scale as f64;
    prep.rays
        .iter()
        .zip(refs)
        .map(|(r, rf)| {
            let at = depth[(r.y * prep.size + r.x) as usize] as f64;
            let Some(h) = rf else { return if at == 1.0 { 0.0 } else { f64::INFINITY } };
            let clip = vp * glam::DVec4::new(h.u, h.v, (h.z - 1.0) * d, 1.0);
            (at - clip.z / clip.w).abs()
        })
        .collect()
}

/// Writes `frame.png` and `error.png` of a measurement into `dir`.
pub fn write_images(dir: &Path, prep: &Prepared, m: &Measured) -> Result<()> {
    io::create_dir_all(dir)?;
    let size = prep.size;
    io::png::write_rgba8(&dir.join("frame.png"), size, size, m.frame.rgba.clone())?;
    let errors: Vec<(u32, u32, f64)> = prep
        .rays
        .iter()
        .zip(&m.hits)
        .zip(&m.refs)
        .map(|((r, h), rf)| {
            let e = match rf {
                Some(rf) if h.t.is_finite() => (h.t as f64 - rf.t).abs(),
                _ => f64::INFINITY,
            };
            (r.x, r.y, e)
        })
        .collect();
    let (w, h, rgba) = crate::picture::error_map(size, &errors);
    Ok(io::png::write_rgba8(&dir.join("error.png"), w, h, rgba)?)
}
