//! The mesh grid `meshes` (`relief sweep --grid meshes`, issue 38; docs/meshes.md, "Drawing
//! and measuring"): a pipeline under `curved=none`, `quadric` and `prism` on mesh scenes,
//! each against the exact mesh reference ([`crate::mesh_measure`]), one results row per cell
//! (mesh scene with its view × `curved=` mode), with the cell's coverage picture.
//!
//! A cell's row ([`crate::results::Row`]) holds the pipeline with its `curved=` option, the
//! scene argument (its view after `@`), the size and the adapter as every row does, the
//! mode's frame time over `curved=none`'s with the same stages in paired blocks
//! (`baseline`, `frame_ratio_to_baseline` and its 95 % interval; `curved=none` itself has
//! none) and its figures in [`crate::results::MeshCells`]; every other metric is NaN. Its
//! folder ([`super::cell_dir`]) holds `coverage.png` (agree-hit grey, agree-miss black, extra
//! red, missing blue: [`crate::mesh_measure::Agreement::colour`]) and `frame.png`.
//!
//! The rows go to `results.jsonl` like any grid's, resumable the same way: a cell whose key
//! (pipeline, scene, size, adapter) is in the file is not measured again. The exact reference
//! is traced once per scene for the modes still to measure.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use relief_dsl::spec::Curved;
use relief_dsl::Pipeline;

use super::{cell_dir, pairs, Summary};
use crate::error::{Error, Result};
use crate::gpu::mesh::{mesh_textures, render_mesh, MeshProgram};
use crate::gpu::Gpu;
use crate::mesh::MeshScene;
use crate::mesh_measure::{coverage_picture, measure_modes, MeshScore, ModeFigures};
use crate::results::{self, MeshCells, Metrics, Row, Status};

/// The grid's name.
pub const MESHES: &str = "meshes";

/// The scenes the grid measures when none are given: the sphere and the torus with `rocks`
/// at 30° and 60° and at a grazing view (the sphere's limb, the torus's tube edge-on),
/// relative to the repository's root (found from the working folder or, failing that, from
/// where relief-runtime was built: [`locate`]).
pub const DEFAULT_SCENES: &[&str] = &[
    "relief-runtime/scenes/meshes/sphere_rocks.toml@angle=30",
    "relief-runtime/scenes/meshes/sphere_rocks.toml@angle=60",
    "relief-runtime/scenes/meshes/sphere_limb.toml",
    "relief-runtime/scenes/meshes/torus_grazing.toml@angle=30",
    "relief-runtime/scenes/meshes/torus_grazing.toml@angle=60",
    "relief-runtime/scenes/meshes/torus_grazing.toml",
];

/// The pipeline each mode is added to.
pub const PIPELINE: &str = "linear(32)+binary(5)";

/// The frame side the grid measures at unless `--size` says otherwise.
pub const DEFAULT_SIZE: u32 = 96;

/// The timed blocks per cell unless `--frames` says otherwise: 6 pairs against `curved=none`.
pub const DEFAULT_FRAMES: u32 = 12;

/// The modes of each scene, in the order they are measured.
pub const MODES: [Curved; 3] = Curved::ALL;

/// The scenes `scenes` names, or [`DEFAULT_SCENES`].
pub fn scene_names(scenes: Option<&[String]>) -> Vec<String> {
    match scenes {
        Some(s) if !s.is_empty() => s.to_vec(),
        _ => DEFAULT_SCENES.iter().map(|s| s.to_string()).collect(),
    }
}

/// The cells the grid measures on `scenes`: (pipeline with its mode, scene argument).
pub fn cells(scenes: &[String]) -> Vec<(Pipeline, String)> {
    let base = base_pipeline();
    scenes.iter().flat_map(|s| MODES.iter().map(|&m| (base.clone().with_curved(Some(m)), s.clone()))).collect()
}

fn base_pipeline() -> Pipeline {
    PIPELINE.parse().expect("the mesh grid's pipeline parses")
}

/// The scene argument as a path to load: a relative scene file that is not found from the
/// working folder is looked for under the repository root relief-runtime was built in, so
/// that [`DEFAULT_SCENES`] load from anywhere in a checkout. The view after `@` is kept.
pub fn locate(arg: &str) -> String {
    let (base, view) = match crate::scene::file::split_view(arg) {
        Some((base, _)) => (base, &arg[base.len()..]),
        None => (arg, ""),
    };
    let path = Path::new(base);
    if path.is_relative() && !path.exists() {
        if let Some(root) = Path::new(env!("CARGO_MANIFEST_DIR")).parent() {
            let there = root.join(path);
            if there.exists() {
                return format!("{}{view}", there.display());
            }
        }
    }
    arg.to_string()
}

/// How [`run`] measures.
pub struct MeshSetup {
    /// Side of the square frame, in pixels.
    pub size: u32,
    /// Timed blocks per timed cell ([`super::pairs`] of them alternate with `curved=none`).
    pub frames: u32,
    /// The output folder (created if missing).
    pub out: PathBuf,
    /// The GPU compiler that prices each mode's mesh module (`vs_mesh`, `fs_mesh`,
    /// `fs_mesh_depth`) on [`crate::cost::DEFAULT_FAMILIES`]; its `fs_mesh` figures go into the
    /// row's `gpu_FAMILY_vgprs`, `_instructions` and `_loop_body` columns
    /// ([`crate::cost::set_mesh_columns`]). `None`: no GPU columns.
    pub gpu_cost: Option<crate::cost::Compiler>,
}

/// Measures the grid's cells on `scenes` into `setup.out` (the module doc).
pub fn run(scenes: &[String], setup: &MeshSetup) -> Result<Summary> {
    crate::io::create_dir_all(&setup.out)?;
    let mut rows = results::read_for_append(&setup.out)?;
    let done: HashSet<_> = rows.iter().map(results::cell_key).collect();
    let all = cells(scenes);
    let gpu = Gpu::new()?;
    let adapter = format!("{} ({})", gpu.adapter, gpu.driver);
    let label = |s: &str| crate::scene::scene_spec(s);
    let is_done = |p: &Pipeline, s: &str| done.contains(&(p.to_string(), label(s), setup.size, adapter.clone(), None));
    let mut summary = Summary { cells: all.len(), ..Default::default() };
    let base = base_pipeline();
    let costs = mesh_costs(setup.gpu_cost.as_ref(), &base, &mut summary);
    for scene in scenes {
        let todo: Vec<Curved> =
            MODES.iter().copied().filter(|&m| !is_done(&base.clone().with_curved(Some(m)), scene)).collect();
        summary.skipped += MODES.len() - todo.len();
        if todo.is_empty() {
            continue;
        }
        let measured = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            measure_scene(&gpu, scene, &base, &todo, setup, &adapter, &costs)
        }))
        .unwrap_or_else(|panic| Err(Error::Input(format!("panicked: {}", super::panic_text(&*panic)))));
        let new_rows = match measured {
            Ok(r) => {
                summary.measured += r.len();
                r
            }
            Err(e) => {
                summary.failed += todo.len();
                todo.iter()
                    .map(|&m| {
                        let p = base.clone().with_curved(Some(m));
                        let metrics = Metrics::not_measured(p.clone(), label(scene), setup.size, adapter.clone());
                        Row {
                            grid: MESHES.into(),
                            status: Status::Error,
                            error: format!("scene {scene}: {e}"),
                            relief_version: env!("CARGO_PKG_VERSION").into(),
                            cell_dir: cell_dir(&label(scene), setup.size, &adapter, &p),
                            metrics,
                            mesh: None,
                            room: None,
                        }
                    })
                    .collect()
            }
        };
        for row in new_rows {
            results::append(&setup.out, &row)?;
            rows.push(row);
        }
        results::write_csv(&setup.out, &rows)?;
    }
    if summary.measured == 0 && summary.failed == 0 {
        results::write_csv(&setup.out, &rows)?;
    }
    Ok(summary)
}

/// Each mode's mesh module priced by `compiler` on the default families, by the pipeline's
/// text form; a failure is said once in `summary.gpu_note` and leaves the rows without GPU
/// columns.
fn mesh_costs(
    compiler: Option<&crate::cost::Compiler>,
    base: &Pipeline,
    summary: &mut Summary,
) -> std::collections::HashMap<String, Vec<crate::cost::MeshCost>> {
    let mut out = std::collections::HashMap::new();
    let Some(compiler) = compiler else {
        return out;
    };
    let families: Vec<String> = crate::cost::DEFAULT_FAMILIES.iter().map(|s| s.to_string()).collect();
    let pipelines: Vec<Pipeline> = MODES.iter().map(|&m| base.clone().with_curved(Some(m))).collect();
    match compiler.cost_mesh_each(&pipelines, &families, false) {
        Ok(each) => {
            for (p, c) in pipelines.iter().zip(each) {
                match c {
                    Ok(c) => {
                        out.insert(p.to_string(), c);
                    }
                    Err(e) => summary.gpu_note = Some(format!("no GPU compiler columns for {p}: {e}")),
                }
            }
        }
        Err(e) => summary.gpu_note = Some(format!("no GPU compiler columns for the mesh modules: {e}")),
    }
    out
}

/// The rows of `modes` on `scene`, their pictures written.
fn measure_scene(
    gpu: &Gpu,
    scene: &str,
    base: &Pipeline,
    modes: &[Curved],
    setup: &MeshSetup,
    adapter: &str,
    costs: &std::collections::HashMap<String, Vec<crate::cost::MeshCost>>,
) -> Result<Vec<Row>> {
    let label = crate::scene::scene_spec(scene);
    let ms = MeshScene::from_scene(crate::scene::scene_from_arg(&locate(scene))?)?;
    let size = setup.size;
    let reference = ms.reference_hits(size, size)?;
    let figures = measure_modes(gpu, &ms, base, modes, &reference, size, pairs(setup.frames))?;
    let none = base.clone().with_curved(Some(Curved::None));
    let mut rows = Vec::new();
    for ModeFigures { pipeline, score, probe, time } in figures {
        let dir = cell_dir(&label, size, adapter, &pipeline);
        let folder = setup.out.join(&dir);
        crate::io::create_dir_all(&folder)?;
        crate::io::png::write_rgba8(&folder.join("coverage.png"), size, size, coverage_picture(&probe, &reference))?;
        let prog = MeshProgram::new(&pipeline)?;
        let tex = mesh_textures(gpu, &ms, &prog)?;
        let frame = render_mesh(gpu, &prog, &ms, &tex, size)?;
        crate::io::png::write_rgba8(&folder.join("frame.png"), size, size, frame.rgba)?;
        let mut metrics = Metrics::not_measured(pipeline.clone(), label.clone(), size, adapter.to_string());
        if let Some(t) = time {
            metrics.baseline = none.to_string();
            metrics.frame_ratio_to_baseline = Some(t.ratio);
            metrics.frame_ratio_to_baseline_lo = Some(t.lo);
            metrics.frame_ratio_to_baseline_hi = Some(t.hi);
            metrics.timing_pairs = t.pairs;
        }
        if let Some(c) = costs.get(&pipeline.to_string()) {
            crate::cost::set_mesh_columns(&mut metrics, c);
        }
        rows.push(Row {
            grid: MESHES.into(),
            metrics,
            status: Status::Ok,
            error: String::new(),
            relief_version: env!("CARGO_PKG_VERSION").into(),
            cell_dir: dir,
            mesh: Some(cells_of(&ms.mesh.name, &score)),
            room: None,
        });
    }
    Ok(rows)
}

/// A score as a row's mesh columns.
fn cells_of(name: &str, s: &MeshScore) -> MeshCells {
    MeshCells {
        name: name.to_string(),
        pixels: s.pixels,
        both: s.both,
        extra: s.extra,
        missing: s.missing,
        coverage_error: s.coverage_error,
        iou: s.iou,
        rms_t: s.rms_t,
        earliest: s.earliest,
        uv_texels: s.uv_texels,
        depth: s.depth,
    }
}
