//! The GPU side: a headless wgpu device, the scene's textures, the render entry timed with
//! render-pass timestamp queries, and the probe entry dispatched over CPU-made rays.
//!
//! Timing uses render-pass timestamps only: on Mesa's lavapipe compute-pass timestamps are
//! wrong (ARCHITECTURE.md, "Environment facts").

mod device;
pub mod mesh;
mod probe;
mod render;
mod resources;

pub use crate::maps::MapKey;
pub use device::{adapters, choose, Gpu, GpuError, ADAPTER_VAR};
pub use mesh::{MeshProbe, MeshProgram};
pub(crate) use probe::dispatch;
pub use probe::{probe, GpuHit};
pub use render::{
    draw_frame, render, Frames, PairedBlocks, RenderResult, CLEAR, DEPTH_FORMAT, FORMAT, MAX_FRAMES_PER_BLOCK,
    SHADING_FORMULA,
};
pub(crate) use render::{paired_blocks, render_pipeline, timed_frames, Clock, Draw, Renderer, MIN_BLOCK_MS};
pub use resources::{map_upload_of, scene_uploads, upload_of_map, SceneTextures, SceneUploads, Upload, AMBIENT};
pub(crate) use resources::{params_for, resource_at};

use relief_dsl::compose::Compiled;

/// A pipeline compiled for the device: the WGSL the device loads, what each of its bindings
/// holds (the composer's table), and the bindings each entry point reads (from naga's
/// analysis of the same module).
pub struct Program {
    /// The composed module as WGSL text (naga's output): what the device loads.
    pub wgsl: String,
    /// What each binding of the module holds, as its stages declared it
    /// ([`relief_dsl::compose::Compiled::bindings`]): what the bind groups bind.
    pub bindings: relief_dsl::ir::Bindings,
    /// The binding numbers (group 0, [`relief_dsl::abi::binding`]) that `vs_main` and
    /// `fs_main` read, sorted.
    pub render_bindings: Vec<u32>,
    /// The binding numbers the `probe` entry reads, sorted.
    pub probe_bindings: Vec<u32>,
    /// The maps the pipeline reads, each with its parameters: the maps to build for it.
    pub maps: Vec<relief_dsl::spec::MapReq>,
    /// Whether the fragment entry writes the hit's depth (renders then get a depth buffer).
    pub writes_depth: bool,
    /// Whether the stages read their maps at levels other than 0 (a `lod` other than zero):
    /// the maps are then bound with their per-level chains ([`SceneTextures::add_maps_lod`]).
    pub map_levels: bool,
}

impl Program {
    /// Compiles `p` and records which bindings each entry point reads.
    pub fn new(p: &relief_dsl::Pipeline) -> Result<Program, relief_dsl::CompileError> {
        Self::new_with(p, &relief_dsl::compose::Options::default())
    }

    /// Compiles `p` with its safe marches gathering their cells' corners where they would
    /// read the patch map (`compose::Options::cell_patch_gather`): the form before the patch
    /// map, for the check that both give the same hits. Its [`Program::maps`] still name the
    /// patch map (built, not bound).
    pub fn with_patches_gathered(p: &relief_dsl::Pipeline) -> Result<Program, relief_dsl::CompileError> {
        Self::new_with(p, &relief_dsl::compose::Options { cell_patch_gather: true, ..Default::default() })
    }

    /// Compiles `p` with `options` (e.g. a fragment entry that writes depth).
    pub(crate) fn new_with(
        p: &relief_dsl::Pipeline,
        options: &relief_dsl::compose::Options,
    ) -> Result<Program, relief_dsl::CompileError> {
        if let Some(c) = p.curved {
            // The mesh module has other entry points and a vertex layout: `gpu::mesh` draws it.
            return Err(relief_dsl::CompileError {
                stage: "mesh".into(),
                message: format!(
                    "curved={c} composes a mesh module (docs/meshes-shaders.md), drawn on a mesh scene (`relief scene measure`), not on the flat tile"
                ),
            });
        }
        let maps = p.required_maps();
        for (i, a) in maps.iter().enumerate() {
            if let Some(b) = maps[..i].iter().find(|b| b.binding() == a.binding()) {
                return Err(relief_dsl::CompileError {
                    stage: "maps".into(),
                    message: format!(
                        "the pipeline reads two `{}` maps with different parameters ({b:?} and {a:?}), which share one binding; use one parameter for both stages",
                        a.name()
                    ),
                });
            }
        }
        let c = relief_dsl::compose::compile_with(p, options)?;
        let map_levels = p.lod != relief_dsl::spec::Lod::Zero;
        Ok(Program { maps, writes_depth: options.frag_depth, map_levels, ..Self::from_compiled(&c)? })
    }

    /// The WGSL loaded on `gpu`; a shader the device rejects is an error, not a panic.
    pub(crate) fn shader_module(&self, gpu: &Gpu) -> Result<wgpu::ShaderModule, GpuError> {
        gpu.checked(|| {
            gpu.device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("relief"),
                source: wgpu::ShaderSource::Wgsl(self.wgsl.as_str().into()),
            })
        })
    }

    /// From an already compiled module that reads no acceleration map (set [`Program::maps`]
    /// for one that does).
    pub(crate) fn from_compiled(c: &Compiled) -> Result<Program, relief_dsl::CompileError> {
        let wgsl = relief_dsl::emit::wgsl(c)?;
        let used = |names: &[&str]| used_bindings(c, names);
        Ok(Program {
            wgsl,
            bindings: c.bindings.clone(),
            render_bindings: used(&["vs_main", "fs_main"]),
            probe_bindings: used(&["probe"]),
            maps: vec![],
            writes_depth: false,
            map_levels: false,
        })
    }
}

/// The bindings the entry points `names` of a validated module use (naga's per-entry global
/// usage), sorted: what a bind group for those entries must hold.
pub(crate) fn used_bindings(c: &Compiled, names: &[&str]) -> Vec<u32> {
    let mut out = Vec::new();
    for (i, ep) in c.module.entry_points.iter().enumerate() {
        if !names.contains(&ep.name.as_str()) {
            continue;
        }
        let info = c.info.get_entry_point(i);
        for (h, g) in c.module.global_variables.iter() {
            if let Some(b) = g.binding {
                if !info[h].is_empty() && !out.contains(&b.binding) {
                    out.push(b.binding);
                }
            }
        }
    }
    out.sort();
    out
}
