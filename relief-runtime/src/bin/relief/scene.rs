//! `relief scene check FILE`: a scene file loaded, with its mesh if it names one, and what was
//! found printed, or one error line. With `--reference N`, the mesh's exact reference of an
//! N × N frame is traced and timed (docs/meshes.md).
//!
//! `relief scene measure FILE --pipeline P`: the pipeline under `curved=none`, `quadric` and
//! `prism` on the scene's mesh against the exact reference, one table row per mode
//! (`relief_runtime::mesh_measure`), and with `--out DIR` each mode's coverage picture and
//! picture (docs/meshes.md, "Measuring").
//!
//! `relief scene fragments FILE`: per mode, the fragments the mesh's draw runs per pixel,
//! counted on the CPU (`relief_runtime::mesh::fragments`), against the reference's coverage.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Context;
use relief_runtime::mesh::MeshScene;

/// Arguments of `relief scene`.
#[derive(clap::Args, Debug)]
pub struct SceneArgs {
    #[command(subcommand)]
    pub command: SceneCommand,
}

/// What `relief scene` does.
#[derive(clap::Subcommand, Debug)]
pub enum SceneCommand {
    /// Load a scene file (and its mesh) and say what it holds.
    Check {
        /// The scene file (`.toml`).
        file: PathBuf,
        /// Also trace the mesh's exact reference for an N × N frame and print its time and
        /// coverage.
        #[arg(long, value_name = "N")]
        reference: Option<u32>,
    },
    /// Draw the scene's mesh with a pipeline under curved=none, quadric and prism and measure
    /// each against the exact reference: coverage error, IoU, t, uv and depth error, and
    /// frame time over curved=none (paired blocks).
    Measure {
        /// The scene file (`.toml`), which names a mesh.
        file: PathBuf,
        /// The pipeline's stages, without `curved=` (each mode is added to it).
        #[arg(long)]
        pipeline: String,
        /// Frame side in pixels.
        #[arg(long, default_value_t = 128)]
        size: u32,
        /// Pairs of timed blocks per mode (0: no timing).
        #[arg(long, default_value_t = 10)]
        pairs: u32,
        /// Write `coverage_MODE.png` (agree-hit grey, agree-miss black, extra red, missing
        /// blue) and `frame_MODE.png` for each mode here.
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        /// Also sort prism's missing pixels by cause (no face of the hit's prism met, first
        /// crossing before the entry or after the exit, the search, other;
        /// `mesh_measure::prism_miss_causes`) and its pixels whose t is off by more than
        /// 1e-3 depths (`mesh_measure::prism_t_causes`, with a second prism probe at
        /// `linear(256)+binary(8)`); the pipeline must be `linear(n)+binary(m)`.
        #[arg(long)]
        causes: bool,
        /// Also measure curved=prism drawn unwalked (every face of every prism drawn, each
        /// fragment tracing its own prism: the library form's arrangement), as a fourth row
        /// `prism-unwalked`, timed against curved=none in the same run.
        #[arg(long)]
        unwalked: bool,
    },
    /// Count the fragments the scene's mesh draw runs per pixel under curved=none, quadric
    /// and prism (a CPU emulation of the rasterizer: the triangles each pixel-centre ray
    /// meets, prism's back faces culled), per pixel the exact reference covers.
    Fragments {
        /// The scene file (`.toml`), which names a mesh.
        file: PathBuf,
        /// Frame side in pixels.
        #[arg(long, default_value_t = 128)]
        size: u32,
    },
}

pub fn run(a: &SceneArgs) -> anyhow::Result<()> {
    let (file, reference) = match &a.command {
        SceneCommand::Check { file, reference } => (file, reference),
        SceneCommand::Measure { file, pipeline, size, pairs, out, causes, unwalked } => {
            return measure(file, pipeline, *size, *pairs, out.as_deref(), *causes, *unwalked)
        }
        SceneCommand::Fragments { file, size } => return fragments(file, *size),
    };
    let scene = relief_runtime::load_scene_file(file)?;
    println!("{scene}");
    if scene.mesh.is_none() {
        return Ok(());
    }
    let ms = MeshScene::from_scene(scene)?;
    if let Some(w) = ms.notes.warning() {
        eprintln!("{w}");
    }
    println!("mesh {}: {} vertices, {} triangles", ms.mesh.name, ms.mesh.positions.len(), ms.mesh.triangles.len());
    if let Some(n) = *reference {
        anyhow::ensure!((1..=4096).contains(&n), "--reference {n}: expected a frame side from 1 to 4096");
        let start = Instant::now();
        let r = ms.reference().context("the exact reference")?;
        let built = start.elapsed().as_secs_f64();
        let hits = r.trace_all(&ms.rays(n, n));
        let total = start.elapsed().as_secs_f64();
        let covered = hits.iter().filter(|h| h.is_some()).count();
        println!(
            "reference {n}x{n}: {} patches, built in {built:.2} s, traced in {:.2} s; {covered} of {} pixels covered",
            r.patch_count(),
            total - built,
            hits.len()
        );
    }
    Ok(())
}

/// `relief scene fragments` (the module doc).
fn fragments(file: &Path, size: u32) -> anyhow::Result<()> {
    use relief_dsl::spec::Curved;
    anyhow::ensure!((8..=2048).contains(&size), "--size {size}: expected a frame side from 8 to 2048");
    let ms = MeshScene::from_scene(relief_runtime::load_scene_file(file)?)?;
    if let Some(w) = ms.notes.warning() {
        eprintln!("{w}");
    }
    let reference = ms.reference_hits(size, size).context("the exact reference")?;
    println!("{} at {size}x{size}: fragments per pixel, CPU emulation of the rasterizer", ms.mesh.name);
    println!(
        "{:<8} {:>8} {:>10} {:>8} {:>12} {:>14} {:>10} {:>7} {:>5}",
        "curved", "drawn", "fragments", "covered", "on covered", "per covered", "before hit", "floors", "most"
    );
    for mode in [Curved::None, Curved::Quadric, Curved::Prism] {
        let c = relief_runtime::mesh::fragments::fragment_counts(&ms, mode, size, &reference);
        println!(
            "{:<8} {:>8} {:>10} {:>8} {:>12} {:>14.3} {:>10} {:>7} {:>5}",
            mode.to_string(),
            c.drawn,
            c.fragments,
            c.covered,
            c.on_covered,
            c.per_covered(),
            c.before_hit,
            c.floors,
            c.most
        );
    }
    Ok(())
}

/// `relief scene measure` (the module doc).
fn measure(
    file: &Path,
    pipeline: &str,
    size: u32,
    pairs: u32,
    out: Option<&Path>,
    causes: bool,
    unwalked: bool,
) -> anyhow::Result<()> {
    use relief_dsl::spec::Curved;
    use relief_runtime::gpu::mesh::{mesh_textures, render_mesh, MeshProgram};
    anyhow::ensure!((8..=2048).contains(&size), "--size {size}: expected a frame side from 8 to 2048");
    anyhow::ensure!(pairs <= 1000, "--pairs {pairs}: expected at most 1000");
    let base: relief_dsl::Pipeline = pipeline.parse().map_err(|e| anyhow::anyhow!("--pipeline: {e}"))?;
    anyhow::ensure!(
        base.curved.is_none(),
        "--pipeline `{pipeline}` names curved=; the command measures each of none, quadric and prism"
    );
    // The search the causes emulate: linear(n) then binary(m) (or no refinement).
    let search = (base.coarse.name == "linear" && ["binary", "none"].contains(&base.refine.name.as_str()))
        .then(|| (base.coarse.int("steps"), if base.refine.name == "none" { 0 } else { base.refine.int("steps") }));
    anyhow::ensure!(
        !causes || search.is_some(),
        "--causes emulates linear(n)+binary(m) only, and the pipeline is `{pipeline}`"
    );
    let scene = relief_runtime::load_scene_file(file)?;
    let ms = MeshScene::from_scene(scene)?;
    if let Some(w) = ms.notes.warning() {
        eprintln!("{w}");
    }
    let gpu = relief_runtime::Gpu::new()?;
    let reference = ms.reference_hits(size, size).context("the exact reference")?;
    let modes = [Curved::None, Curved::Quadric, Curved::Prism];
    let mut rows = relief_runtime::mesh_measure::measure_modes(&gpu, &ms, &base, &modes, &reference, size, pairs)?;
    let mut names: Vec<String> = modes.iter().map(|m| m.to_string()).collect();
    if unwalked {
        let none = MeshProgram::new(&base.clone().with_curved(Some(Curved::None)))?;
        let none_tex = mesh_textures(&gpu, &ms, &none)?;
        let prog = MeshProgram::unwalked(&base.clone().with_curved(Some(Curved::Prism)))?;
        let none = (&none, &none_tex);
        rows.push(relief_runtime::mesh_measure::measure_program(&gpu, &ms, &prog, none, &reference, size, pairs)?);
        names.push("prism-unwalked".into());
    }
    println!("{} with {} at {size}x{size} on {}", ms.mesh.name, base, gpu.adapter);
    println!(
        "{:<8} {:>10} {:>7} {:>10} {:>10} {:>6} {:>10} {:>9} {:>9} {:>7} {:>7}  time/none (95 %)",
        "curved",
        "coverage%",
        "IoU",
        "rms_t/d",
        "median_t/d",
        "far",
        "earliest/d",
        "uv_texel",
        "depth",
        "extra",
        "missing"
    );
    for (mode, r) in names.iter().zip(&rows) {
        let s = &r.score;
        let time = match &r.time {
            Some(t) => format!("{:.3} [{:.3}, {:.3}]", t.ratio, t.lo, t.hi),
            None => "-".into(),
        };
        println!(
            "{:<8} {:>10.3} {:>7.4} {:>10.2e} {:>10.2e} {:>6} {:>10.2e} {:>9.3} {:>9.2e} {:>7} {:>7}  {time}",
            mode,
            100.0 * s.coverage_error,
            s.iou,
            s.rms_t,
            s.median_t,
            s.far,
            s.earliest,
            s.uv_texels,
            s.depth,
            s.extra,
            s.missing
        );
    }
    let prism = &rows[modes.iter().position(|&m| m == Curved::Prism).expect("prism is measured")].probe;
    if let Some((mean, most)) = prism.walk_passes() {
        println!(
            "prism walk: {mean:.2} prisms searched per drawn pixel (most {most}), {} pixels stopped at the limit of {}",
            prism.walk_limit_pixels(),
            relief_dsl::compose::mesh::PRISM_WALK_LIMIT
        );
    }
    if unwalked {
        walk_against_unwalked(&rows[2].probe, &rows[3].probe, &reference, ms.scene.depth_scale as f64, size);
    }
    if let (true, Some((steps, refine))) = (causes, search) {
        // The emulation searches every prism's chord with all of the stage's layers, as the
        // full draw does; the walk the runtime draws gives each chord its share of them, so
        // the causes are decided on the walk with all its layers.
        let whole = MeshProgram::walked_with_all_layers(&base.clone().with_curved(Some(Curved::Prism)))?;
        let whole_tex = mesh_textures(&gpu, &ms, &whole)?;
        let whole = relief_runtime::gpu::mesh::probe_mesh(&gpu, &whole, &ms, &whole_tex, size)?;
        println!("the causes below are of the walk with all its layers (the emulation's search)");
        let found = relief_runtime::mesh_measure::prism_miss_causes(&ms, &reference, &whole, size, steps, refine);
        let counts: Vec<String> = relief_runtime::mesh_measure::PrismMiss::ALL
            .iter()
            .map(|c| format!("{} {}", c.name(), found.iter().filter(|(_, f)| f == c).count()))
            .collect();
        println!("prism missing {}: {}", found.len(), counts.join(", "));
        prism_t_report(&gpu, &ms, &base, &reference, &whole, size, steps, refine)?;
    }
    if let Some(dir) = out {
        std::fs::create_dir_all(dir).with_context(|| format!("{}: cannot create the folder", dir.display()))?;
        for (mode, r) in names.iter().zip(&rows) {
            let pic = relief_runtime::mesh_measure::coverage_picture(&r.probe, &reference);
            relief_runtime::io::png::write_rgba8(&dir.join(format!("coverage_{mode}.png")), size, size, pic)?;
            let prog = if mode == "prism-unwalked" {
                MeshProgram::unwalked(&r.pipeline)?
            } else {
                MeshProgram::new(&r.pipeline)?
            };
            let tex = mesh_textures(&gpu, &ms, &prog)?;
            let f = render_mesh(&gpu, &prog, &ms, &tex, size)?;
            relief_runtime::io::png::write_rgba8(&dir.join(format!("frame_{mode}.png")), size, size, f.rgba)?;
        }
        println!("pictures in {}", dir.display());
    }
    Ok(())
}

/// `--unwalked`: the pixels where the walk's probe and the unwalked one disagree, in
/// coverage or by more than 1e-3 depths along the ray, with the first few of them.
fn walk_against_unwalked(
    walk: &relief_runtime::gpu::mesh::MeshProbe,
    unwalked: &relief_runtime::gpu::mesh::MeshProbe,
    reference: &[Option<relief_runtime::mesh::MeshHit>],
    depth: f64,
    size: u32,
) {
    let mut differ = Vec::new();
    for (i, (a, b)) in walk.hits.iter().zip(&unwalked.hits).enumerate() {
        let (ha, hb) = (a[3] > 0.5, b[3] > 0.5);
        if ha != hb || (ha && ((a[2] - b[2]) as f64).abs() > 1e-3 * depth) {
            differ.push(i);
        }
    }
    println!("walk against unwalked: {} pixels differ (coverage, or t by more than 1e-3 depths)", differ.len());
    for &i in differ.iter().take(8) {
        let r = reference[i].as_ref().map_or("miss".to_string(), |r| format!("t {:.5}", r.t));
        let (a, b) = (walk.hits[i], unwalked.hits[i]);
        println!(
            "  pixel ({}, {}): walk {:?}, unwalked {:?}, reference {r}",
            i as u32 % size,
            i as u32 / size,
            a.map(|x| (x * 1e5).round() / 1e5),
            b.map(|x| (x * 1e5).round() / 1e5)
        );
    }
}

/// `--causes`: prism's pixels whose t is off by more than `mesh_measure::T_BOUND` depths, by
/// cause (`mesh_measure::prism_t_causes`, against a `linear(256)+binary(8)` probe of the same
/// scene), the RMS t with and without each cause's pixels, and the dense probe's own figures.
#[allow(clippy::too_many_arguments)]
fn prism_t_report(
    gpu: &relief_runtime::Gpu,
    ms: &MeshScene,
    base: &relief_dsl::Pipeline,
    reference: &[Option<relief_runtime::mesh::MeshHit>],
    probe: &relief_runtime::gpu::mesh::MeshProbe,
    size: u32,
    steps: u32,
    refine: u32,
) -> anyhow::Result<()> {
    use relief_dsl::spec::Curved;
    use relief_runtime::mesh_measure::{
        emulate_prism_pixel, measure_modes, near_seam, prism_t_causes, rms_t_without, score, PolishRule, PrismPath,
        PrismTCause, PRISM_PIECES,
    };
    let mut dense: relief_dsl::Pipeline = "linear(256)+binary(8)".parse().map_err(|e| anyhow::anyhow!("{e}"))?;
    dense.shadow = base.shadow.clone();
    dense.ao = base.ao.clone();
    let dense_rows = measure_modes(gpu, ms, &dense, &[Curved::Prism], reference, size, 0)?;
    let d = &dense_rows[0].score;
    println!(
        "prism with linear(256)+binary(8): coverage {:.3} %, rms_t {:.2e}, median_t {:.2e}, far {}, earliest {:.2e}, extra {}, missing {}",
        100.0 * d.coverage_error,
        d.rms_t,
        d.median_t,
        d.far,
        d.earliest,
        d.extra,
        d.missing
    );
    let found = prism_t_causes(ms, reference, probe, &dense_rows[0].probe, size, steps, refine);
    let all = score(probe, reference, ms).rms_t;
    let every: Vec<usize> = found.iter().map(|f| f.index).collect();
    println!(
        "prism t over {}: {} pixels, rms_t {all:.2e}, without them {:.2e}",
        relief_runtime::mesh_measure::T_BOUND,
        found.len(),
        rms_t_without(probe, reference, ms, &every)
    );
    for c in PrismTCause::ALL {
        let those: Vec<usize> = found.iter().filter(|f| f.cause == c).map(|f| f.index).collect();
        println!(
            "  {:<7} {:>4} pixels, rms_t without them {:.2e}",
            c.name(),
            those.len(),
            rms_t_without(probe, reference, ms, &those)
        );
    }
    // The CPU's emulation of every pixel under the shader's polish and under others: what a
    // change of the polish would do (coverage and t against the reference), before it is made.
    let (vertices, indices) = relief_runtime::mesh::vertices::mesh_vertices(&ms.mesh, Curved::Prism);
    let rays = ms.rays(size, size);
    let depth = ms.scene.depth_scale as f64;
    let walls = relief_runtime::mesh_measure::seam_walls(ms);
    // The last three: a dense search (1024 layers, 16 bisections), as a coarse stage that reads
    // maps (an exact march) finds crossings, on the straight chord (that shader before the
    // pieces), on the pieces it follows now, and on the bent quadratic.
    let dense = (1024, 16);
    for (rule, (steps, refine)) in [
        (PolishRule::SHADER, (steps, refine)),
        (PolishRule { steps: 6, ..PolishRule::SHADER }, (steps, refine)),
        (PolishRule { discard: false, ..PolishRule::SHADER }, (steps, refine)),
        (PolishRule { discard: false, discard_outside: true, ..PolishRule::SHADER }, (steps, refine)),
        (PolishRule { discard: false, path: PrismPath::Chord, ..PolishRule::SHADER }, (steps, refine)),
        (PolishRule { path: PrismPath::Chord, ..PolishRule::SHADER }, (steps, refine)),
        (PolishRule { path: PrismPath::Exact, ..PolishRule::SHADER }, (steps, refine)),
        (PolishRule::SHADER, (256, 8)),
        (PolishRule { path: PrismPath::Chord, ..PolishRule::SHADER }, dense),
        (PolishRule { path: PrismPath::Pieces(PRISM_PIECES), ..PolishRule::SHADER }, dense),
        (PolishRule::SHADER, dense),
    ] {
        let (mut extra, mut missing, mut sum, mut both, mut over, mut gpu_differ) = (0, 0, 0.0, 0usize, 0, 0);
        let (mut sum_off_seams, mut seam_pixels) = (0.0, 0usize);
        for (i, ray) in rays.iter().enumerate() {
            let (o, d) =
                (glam::DVec3::from(ray.origin.map(|c| c as f64)), glam::DVec3::from(ray.dir.map(|c| c as f64)));
            let e = emulate_prism_pixel(ms, &vertices, &indices, o, d, (steps, refine), rule);
            gpu_differ += usize::from(e.is_some() != (probe.hits[i][3] > 0.5));
            match (e, &reference[i]) {
                (Some(e), Some(r)) => {
                    let dt = (e.t - r.t) / depth;
                    sum += dt * dt;
                    both += 1;
                    over += usize::from(dt.abs() > relief_runtime::mesh_measure::T_BOUND);
                    if dt.abs() > relief_runtime::mesh_measure::T_BOUND
                        && (near_seam(&walls, o, d, e.t, depth) || near_seam(&walls, o, d, r.t, depth))
                    {
                        seam_pixels += 1;
                    } else {
                        sum_off_seams += dt * dt;
                    }
                }
                (Some(_), None) => extra += 1,
                (None, Some(_)) => missing += 1,
                (None, None) => {}
            }
        }
        println!(
            "emulated linear({steps})+binary({refine}) {}, polish {} steps{}: extra {extra}, missing {missing}, rms_t {:.2e}, over the bound {over}, coverage unlike the GPU's {gpu_differ}; without the {seam_pixels} seam pixels over the bound rms_t {:.2e}",
            rule.path.name(),
            rule.steps,
            if rule.discard {
                ", discard where not kept"
            } else if rule.discard_outside {
                ", discard where converged outside the triangle"
            } else {
                ""
            },
            (sum / both.max(1) as f64).sqrt(),
            (sum_off_seams / (both - seam_pixels).max(1) as f64).sqrt()
        );
    }
    for f in &found {
        let fmt = |x: Option<f64>| x.map_or("-".to_string(), |x| format!("{x:.3e}"));
        println!(
            "  pixel ({}, {}): dt {:.3e}, dense {}, emulated {} polished {:?} {:?}, seam {}: {}",
            f.index as u32 % size,
            f.index as u32 / size,
            f.dt,
            fmt(f.dense_dt),
            fmt(f.emulated_dt),
            f.polished,
            f.fragment.map(|e| e.polish_end),
            f.seam,
            f.cause.name()
        );
    }
    Ok(())
}
