//! A mesh scene drawn with a `curved=` pipeline's mesh module (relief-dsl's `compose/mesh.rs`,
//! docs/meshes.md): its vertices from [`crate::mesh::vertices`], the scene's textures and
//! maps as the flat tile binds them ([`SceneTextures`]), a depth buffer with the depth test
//! `Less` (the fragment writes the hit's depth), every pipeline from the runtime's one `Draw`.
//!
//! `curved=prism` is drawn as a walk (relief-dsl's `compose::Options::prism_walk`): the
//! prisms' tops and unsealed walls, each fragment walking on from prism to prism through the
//! joined walls ([`crate::mesh::vertices::prism_walk`]); [`MeshProgram::unwalked`] draws every
//! face of every prism, each running its own trace (the library form's arrangement).
//!
//! Three draws of the same vertices: the picture (`vs_mesh` + `fs_mesh`), the measurement
//! (`fs_mesh_probe` into an `Rgba32Float` target: hit u, v, distance along the view ray, 1;
//! cleared to 0, so w = 0 is a miss) and the paired timing of two modes' pictures.

use relief_dsl::abi::binding::PRISM_CELLS;
use relief_dsl::compose::mesh::{vertex_members_for, MeshVertex, PROBE_ENTRY};
use relief_dsl::spec::{Curved, Lod};
use relief_dsl::{CompileError, Pipeline};
use wgpu::util::DeviceExt;

use super::render::{MeshBuffers, Target};
use super::{paired_blocks, render_pipeline, Clock, Draw, Frames, Gpu, GpuError, PairedBlocks, Program, Renderer};
use super::{SceneTextures, CLEAR, FORMAT};
use crate::mesh::vertices::{mesh_vertices, prism_walk};
use crate::mesh::MeshScene;

/// A `curved=` pipeline compiled for the device, with its measurement entry.
pub struct MeshProgram {
    /// The module as the device loads it; `render_bindings` are those of `vs_mesh` and
    /// `fs_mesh`, `probe_bindings` those of `vs_mesh` and `fs_mesh_probe`.
    pub program: Program,
    /// The pipeline's mode.
    pub curved: Curved,
    /// The pipeline's `lod` (the level its maps are read at).
    pub lod: Lod,
    /// `curved=prism` drawn as a walk (the module doc); false for the other modes.
    pub walk: bool,
    /// The pipeline compiled.
    pub pipeline: Pipeline,
}

impl MeshProgram {
    /// Compiles `p`, which must have a `curved=` option (else a one-line error); under
    /// `curved=prism` its fragments walk from prism to prism (the module doc).
    pub fn new(p: &Pipeline) -> Result<MeshProgram, CompileError> {
        MeshProgram::with_walk(p, true, false)
    }

    /// As [`MeshProgram::new`], but the walk searches every prism's chord with all of its
    /// linear search's layers, as the unwalked draw does, not the chord's share of them
    /// (relief-dsl's `compose::Options::prism_walk_all_layers`): the walk's check against
    /// the unwalked draw.
    pub fn walked_with_all_layers(p: &Pipeline) -> Result<MeshProgram, CompileError> {
        MeshProgram::with_walk(p, true, true)
    }

    /// As [`MeshProgram::new`], but `curved=prism` draws every face of every prism, each
    /// fragment tracing its own prism only (what the library form does; the walk's check).
    pub fn unwalked(p: &Pipeline) -> Result<MeshProgram, CompileError> {
        MeshProgram::with_walk(p, false, false)
    }

    fn with_walk(p: &Pipeline, walk: bool, all_layers: bool) -> Result<MeshProgram, CompileError> {
        let Some(curved) = p.curved else {
            return Err(CompileError {
                stage: "mesh".into(),
                message: format!("`{p}` has no curved= option: a mesh is drawn with curved=none, quadric or prism"),
            });
        };
        let walk = walk && curved == Curved::Prism;
        let options = relief_dsl::compose::Options {
            mesh_probe: true,
            prism_walk: walk,
            prism_walk_all_layers: all_layers,
            ..Default::default()
        };
        let c = relief_dsl::compose::compile_with(p, &options)?;
        let wgsl = relief_dsl::emit::wgsl(&c)?;
        let used = |names: &[&str]| super::used_bindings(&c, names);
        let program = Program {
            wgsl,
            bindings: c.bindings.clone(),
            render_bindings: used(&["vs_mesh", "fs_mesh"]),
            probe_bindings: used(&["vs_mesh", PROBE_ENTRY]),
            maps: p.required_maps(),
            writes_depth: true,
            map_levels: p.lod != Lod::Zero,
        };
        Ok(MeshProgram { program, curved, lod: p.lod, walk, pipeline: p.clone() })
    }
}

/// The vertex layout of [`MeshVertex`]: member k at location k, each a `vec4<f32>`; a mode's
/// pipeline takes the first [`vertex_members_for`] of them.
const ATTRIBUTES: [wgpu::VertexAttribute; 13] = wgpu::vertex_attr_array![
    0 => Float32x4, 1 => Float32x4, 2 => Float32x4, 3 => Float32x4, 4 => Float32x4, 5 => Float32x4, 6 => Float32x4,
    7 => Float32x4, 8 => Float32x4, 9 => Float32x4, 10 => Float32x4, 11 => Float32x4, 12 => Float32x4
];

/// The mesh of `ms` as `curved`'s vertices, uploaded; without `early_out`, `prism`'s exact
/// early-outs off: the mask of the early-out behind the hit (`prism_b.z`) and the walk's
/// headrooms (`PrismCell::uv2.z`, its skip of prisms above the relief) zeroed. With `walk`
/// (`curved=prism` only) the walk's draw and its buffer of triangles, the second value.
fn upload(
    gpu: &Gpu,
    ms: &MeshScene,
    curved: Curved,
    early_out: bool,
    walk: bool,
) -> Result<(MeshBuffers, Option<wgpu::Buffer>), GpuError> {
    let (mut vertices, indices, cells) = if walk {
        let base = mesh_vertices(&ms.mesh, Curved::None).0;
        let heights = early_out.then_some((&ms.scene.height, ms.scene.edge));
        let w = prism_walk(&ms.mesh, &base, heights).map_err(GpuError::Device)?;
        (w.vertices, w.indices, Some(w.cells))
    } else {
        let (v, i) = mesh_vertices(&ms.mesh, curved);
        (v, i, None)
    };
    if !early_out {
        vertices.iter_mut().for_each(|v| v.prism_b[2] = 0.0);
    }
    let count = u32::try_from(indices.len())
        .map_err(|_| GpuError::Device(format!("{} indices: more than one draw takes", indices.len())))?;
    let buffer = |label, contents: &[u8], usage| {
        gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
    };
    let cells = cells.map(|c| buffer("prism cells", bytemuck::cast_slice(&c), wgpu::BufferUsages::STORAGE));
    let buffers = MeshBuffers {
        vertices: buffer(
            "mesh vertices",
            bytemuck::cast_slice::<MeshVertex, u8>(&vertices),
            wgpu::BufferUsages::VERTEX,
        ),
        indices: buffer("mesh indices", bytemuck::cast_slice(&indices), wgpu::BufferUsages::INDEX),
        count,
    };
    Ok((buffers, cells))
}

/// The renderer of `prog`'s picture (`fs_mesh` into [`FORMAT`] over [`CLEAR`]) or, with
/// `probe`, its measurement (`fs_mesh_probe` into `Rgba32Float` over 0) on `ms` at `size²`,
/// with a depth buffer and the test `Less`.
fn renderer(
    gpu: &Gpu,
    prog: &MeshProgram,
    ms: &MeshScene,
    tex: &SceneTextures,
    size: u32,
    probe: bool,
) -> Result<Renderer, GpuError> {
    let pipeline = mesh_pipeline(gpu, prog, probe)?;
    renderer_with(gpu, prog, pipeline, ms, tex, size, probe, true)
}

/// The target format, its clear colour and the bindings of `prog`'s picture or, with `probe`,
/// its measurement.
fn output(prog: &MeshProgram, probe: bool) -> (&'static str, wgpu::TextureFormat, wgpu::Color, &[u32]) {
    if probe {
        (PROBE_ENTRY, wgpu::TextureFormat::Rgba32Float, wgpu::Color::TRANSPARENT, &prog.program.probe_bindings)
    } else {
        ("fs_mesh", FORMAT, CLEAR, &prog.program.render_bindings)
    }
}

/// `prog`'s render pipeline of the picture or, with `probe`, of the measurement: the part of a
/// renderer that depends on the program only (the device compiles the shaders here).
fn mesh_pipeline(gpu: &Gpu, prog: &MeshProgram, probe: bool) -> Result<wgpu::RenderPipeline, GpuError> {
    let (entry, format, _, _) = output(prog, probe);
    let module = prog.program.shader_module(gpu)?;
    let layout = [Some(wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<MeshVertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &ATTRIBUTES[..vertex_members_for(prog.curved, prog.walk)],
    })];
    render_pipeline(
        gpu,
        &module,
        &Draw {
            label: "mesh",
            entries: ("vs_mesh", entry),
            buffers: &layout,
            topology: wgpu::PrimitiveTopology::TriangleList,
            depth: Some(wgpu::CompareFunction::Less),
            format,
            cull: (prog.curved == Curved::Prism).then_some(wgpu::Face::Back),
        },
    )
}

/// [`renderer`] with its pipeline already built ([`mesh_pipeline`] of the same `prog` and
/// `probe`): the scene's parameters, bind group, target and vertices (`prism`'s early-out
/// mask zeroed without `early_out`).
#[allow(clippy::too_many_arguments)]
fn renderer_with(
    gpu: &Gpu,
    prog: &MeshProgram,
    pipeline: wgpu::RenderPipeline,
    ms: &MeshScene,
    tex: &SceneTextures,
    size: u32,
    probe: bool,
    early_out: bool,
) -> Result<Renderer, GpuError> {
    let (_, format, clear, bindings) = output(prog, probe);
    // Object space is world space: the scene's camera, light and depth are the mesh's Params.
    let params = SceneTextures::params(gpu, &ms.scene, 1.0, 0.0);
    let (mesh, cells) = upload(gpu, ms, prog.curved, early_out, prog.walk)?;
    let storage: Vec<(u32, &wgpu::Buffer)> = cells.iter().map(|c| (PRISM_CELLS, c)).collect();
    let layout = pipeline.get_bind_group_layout(0);
    let bind_group = tex.bind_group(gpu, &layout, bindings, &prog.program, &params, &storage)?;
    let target = Target::with_format(gpu, size, true, clear, format);
    Ok(Renderer { pipeline, bind_group, target, mesh: Some(mesh) })
}

/// The scene's textures with the maps `prog` reads.
pub fn mesh_textures(gpu: &Gpu, ms: &MeshScene, prog: &MeshProgram) -> Result<SceneTextures, crate::maps::MapError> {
    let mut tex = SceneTextures::new(gpu, &ms.scene);
    tex.add_maps_lod(gpu, &ms.scene, &prog.program.maps, prog.lod)?;
    Ok(tex)
}

/// One frame of `prog` on `ms`, `size²`: the picture (RGBA8 sRGB) and its depth.
pub fn render_mesh(
    gpu: &Gpu,
    prog: &MeshProgram,
    ms: &MeshScene,
    tex: &SceneTextures,
    size: u32,
) -> Result<Frames, GpuError> {
    let r = renderer(gpu, prog, ms, tex, size, false)?;
    r.target.untimed(gpu, 1, &|p| r.draw(p))?;
    r.target.read(gpu, Vec::new())
}

/// The measurement of one frame: per pixel, row-major from the top.
pub struct MeshProbe {
    /// `(u, v, distance, 1)` where the frame shows relief, `(0, 0, 0, 0)` where it does not.
    /// A walking `curved=prism` program writes the number of prisms the pixel's walk searched
    /// for the 1, and `(0, 0, 0, −1)` where the only walks at the pixel stopped at the walk's
    /// limit (not drawn: the picture discards them).
    pub hits: Vec<[f32; 4]>,
    /// The depth buffer (NDC depth, cleared to 1).
    pub depth: Vec<f32>,
}

impl MeshProbe {
    /// The pixels whose walk stopped at relief-dsl's `PRISM_WALK_LIMIT` and that no other
    /// fragment draws (0 for a program that does not walk).
    pub fn walk_limit_pixels(&self) -> usize {
        self.hits.iter().filter(|h| h[3] < -0.5).count()
    }

    /// Over the drawn pixels, the mean and the largest number of prisms the drawn
    /// fragment's walk searched (`None` when no pixel is drawn; 1 for a program that does
    /// not walk).
    pub fn walk_passes(&self) -> Option<(f64, u32)> {
        let drawn: Vec<f32> = self.hits.iter().map(|h| h[3]).filter(|&w| w > 0.5).collect();
        let max = drawn.iter().copied().fold(0.0f32, f32::max);
        (!drawn.is_empty())
            .then(|| (drawn.iter().map(|&w| w as f64).sum::<f64>() / drawn.len() as f64, max.round() as u32))
    }
}

/// `prog`'s measurement entry on `ms`, `size²` (the same trace, discards and depth test as
/// the picture).
pub fn probe_mesh(
    gpu: &Gpu,
    prog: &MeshProgram,
    ms: &MeshScene,
    tex: &SceneTextures,
    size: u32,
) -> Result<MeshProbe, GpuError> {
    MeshProber::new(gpu, prog)?.probe(gpu, ms, tex, size)
}

/// A program's measurement pipeline, compiled once for the device, to probe many scenes with
/// ([`probe_mesh`] compiles it per call; `relief stability` probes each program on every mesh
/// condition).
pub struct MeshProber<'a> {
    prog: &'a MeshProgram,
    pipeline: wgpu::RenderPipeline,
}

impl<'a> MeshProber<'a> {
    /// Compiles `prog`'s measurement pipeline on `gpu`.
    pub fn new(gpu: &Gpu, prog: &'a MeshProgram) -> Result<MeshProber<'a>, GpuError> {
        Ok(MeshProber { prog, pipeline: mesh_pipeline(gpu, prog, true)? })
    }

    /// The program it measures.
    pub fn program(&self) -> &'a MeshProgram {
        self.prog
    }

    /// The measurement of `ms`, `size²`, as [`probe_mesh`] (`gpu` the device it was compiled on).
    pub fn probe(&self, gpu: &Gpu, ms: &MeshScene, tex: &SceneTextures, size: u32) -> Result<MeshProbe, GpuError> {
        self.probe_with(gpu, ms, tex, size, true)
    }

    /// As [`MeshProber::probe`], with `prism`'s exact early-outs turned off (the early-out
    /// behind the hit's mask `prism_b.z` and the walk's headrooms zeroed): the picture they
    /// must not change (a check's hook).
    pub fn probe_without_early_out(
        &self,
        gpu: &Gpu,
        ms: &MeshScene,
        tex: &SceneTextures,
        size: u32,
    ) -> Result<MeshProbe, GpuError> {
        self.probe_with(gpu, ms, tex, size, false)
    }

    fn probe_with(
        &self,
        gpu: &Gpu,
        ms: &MeshScene,
        tex: &SceneTextures,
        size: u32,
        early_out: bool,
    ) -> Result<MeshProbe, GpuError> {
        let r = renderer_with(gpu, self.prog, self.pipeline.clone(), ms, tex, size, true, early_out)?;
        r.target.untimed(gpu, 1, &|p| r.draw(p))?;
        let f = r.target.read(gpu, Vec::new())?;
        let floats: Vec<f32> = bytemuck::pod_collect_to_vec(&f.rgba);
        let hits = floats.chunks_exact(4).map(|c| [c[0], c[1], c[2], c[3]]).collect();
        Ok(MeshProbe { hits, depth: f.depth.unwrap_or_default() })
    }
}

/// Frame times of `a` and `b` (their pictures) on `ms`, `size²`, in `pairs` alternating
/// pairs of blocks ([`PairedBlocks`]; each side's block length calibrated first).
pub fn paired_mesh_time(
    gpu: &Gpu,
    a: (&MeshProgram, &SceneTextures),
    b: (&MeshProgram, &SceneTextures),
    ms: &MeshScene,
    size: u32,
    pairs: u32,
) -> Result<PairedBlocks, GpuError> {
    let clock = Clock::new(gpu)?;
    let ra = renderer(gpu, a.0, ms, a.1, size, false)?;
    let rb = renderer(gpu, b.0, ms, b.1, size, false)?;
    let ka = clock.calibrate(gpu, &ra.target, &|p| ra.draw(p))?;
    let kb = clock.calibrate(gpu, &rb.target, &|p| rb.draw(p))?;
    paired_blocks(gpu, &clock, &ra, &rb, [ka, kb], pairs)
}
