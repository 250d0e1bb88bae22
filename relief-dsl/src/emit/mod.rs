//! Emitters: WGSL, SPIR-V and GLSL 450 from a compiled pipeline (this module); [`library()`]
//! and [`library_forms()`]: the stages as functions for a user's own shader, in each
//! [`LibraryForm`], one module per form.
//!
//! The library modules import downward only: `library` (the driver) calls each form's
//! module; a form's module uses `common` (the header, the resources as arguments) and at
//! most the one form it builds on (`wesl` on `wgsl`, `glsl_es` on `glsl`, `unity` and
//! `unreal` on `hlsl`); `limits` imports only `form`, and `form` no emit module.

use naga::back::spv;
use naga::ShaderStage;

use crate::compose::Compiled;
use crate::CompileError;

/// The shader files for one pipeline.
#[derive(Clone, Debug)]
pub struct Outputs {
    /// The whole module (render and probe entries) as WGSL.
    pub wgsl: String,
    /// The whole module as SPIR-V words.
    pub spirv: Vec<u32>,
    /// GLSL 450, one source per entry point: `(file suffix, source)` with suffixes `vert`,
    /// `frag` and `comp` (a mesh module: `vert`, `frag` and `depth.frag`, its depth-only
    /// entry).
    pub glsl: Vec<(&'static str, String)>,
}

fn err(target: &str, e: impl std::fmt::Debug) -> CompileError {
    CompileError { stage: format!("emit {target}"), message: format!("{e:?}") }
}

/// WGSL text of the module.
pub fn wgsl(c: &Compiled) -> Result<String, CompileError> {
    naga::back::wgsl::write_string(&c.module, &c.info, naga::back::wgsl::WriterFlags::empty())
        .map_err(|e| err("wgsl", e))
}

/// SPIR-V words of the module (Vulkan 1.1 target environment). Loops are statically
/// bounded, so naga's forced loop bounding is off.
pub fn spirv(c: &Compiled) -> Result<Vec<u32>, CompileError> {
    let options = spv::Options { lang_version: (1, 3), force_loop_bounding: false, ..spv::Options::default() };
    spv::write_vec(&c.module, &c.info, &options, None).map_err(|e| err("spir-v", e))
}

/// The GLSL binding map: every `(group 0, binding n)` resource at binding n.
pub(crate) fn glsl_binding_map(c: &Compiled) -> naga::back::glsl::BindingMap {
    c.module.global_variables.iter().filter_map(|(_, g)| g.binding).map(|rb| (rb, rb.binding as u8)).collect()
}

/// GLSL 450 of one entry point.
pub(crate) fn glsl_entry(c: &Compiled, stage: ShaderStage, entry: &str) -> Result<String, CompileError> {
    use naga::back::glsl as back;
    let options = back::Options {
        version: back::Version::Desktop(450),
        binding_map: glsl_binding_map(c),
        ..back::Options::default()
    };
    let pipeline = back::PipelineOptions { shader_stage: stage, entry_point: entry.to_string(), multiview: None };
    let mut out = String::new();
    let mut w = back::Writer::new(&mut out, &c.module, &c.info, &options, &pipeline, Default::default())
        .map_err(|e| err("glsl", e))?;
    w.write().map_err(|e| err("glsl", e))?;
    Ok(out)
}

/// All three targets.
pub fn all(c: &Compiled) -> Result<Outputs, CompileError> {
    let mut glsl = Vec::new();
    for ep in &c.module.entry_points {
        let suffix = match ep.stage {
            ShaderStage::Vertex => "vert",
            ShaderStage::Fragment if ep.name == crate::compose::mesh::DEPTH_ENTRY => "depth.frag",
            ShaderStage::Fragment => "frag",
            ShaderStage::Compute => "comp",
            _ => continue,
        };
        glsl.push((suffix, glsl_entry(c, ep.stage, &ep.name)?));
    }
    Ok(Outputs { wgsl: wgsl(c)?, spirv: spirv(c)?, glsl })
}

/// Compiles a pipeline and emits every target.
pub fn emit(p: &crate::spec::Pipeline) -> Result<Outputs, CompileError> {
    all(&crate::compose::compile(p)?)
}

mod common;
mod form;
mod glsl;
mod glsl_es;
mod hlsl;
pub mod library;
pub mod limits;
mod msl;
mod tsl;
mod unity;
mod unreal;
mod wesl;
mod wgsl;

pub use crate::compose::library::{LibraryBinding, LibraryOptions, ResourceKind};
pub use form::LibraryForm;
pub use library::{inexpressible_in, library, library_forms, LibraryFile, LibraryFiles, LibraryForms};
pub use wesl::wesl_module_name;
