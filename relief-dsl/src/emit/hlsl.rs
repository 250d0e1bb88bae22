//! The HLSL form (`NAME.lib.hlsl`, shader model 5.1): textures at `register(tB, spaceG)`,
//! samplers at `register(sB, spaceG)`. naga writes samplers through a sampler heap and an
//! index buffer (its D3D12 binding model); the library declares them as plain
//! `SamplerState`s at their registers instead. The engine forms ([`super::unity`],
//! [`super::unreal`]) take [`with_arguments`], the HLSL of the module with its resources as
//! arguments.

use std::fmt::Write as _;

use naga::back::hlsl;

use super::common::{err, header_lines, resources_as_arguments, Header, ResourceArguments, Written};
use crate::compose::library::{Library, LibraryOptions, ResourceKind};
use crate::spec::Pipeline;
use crate::CompileError;

/// The HLSL header: resources at registers (Unreal's include file shares it).
pub(crate) const HEADER: Header = Header {
    arguments: ResourceArguments::Global,
    intro: "// Resources:\n",
    resource_type: hlsl_type,
    by_name: false,
    no_nearest_sampler: false,
};

fn hlsl_type(kind: ResourceKind) -> &'static str {
    match kind {
        ResourceKind::Sampler => "SamplerState",
        ResourceKind::Texture2d => "Texture2D<float4>",
        ResourceKind::Texture3d => "Texture3D<float4>",
    }
}

/// `NAME.lib.hlsl`.
pub(crate) fn write(p: &Pipeline, lib: &Library, opts: &LibraryOptions) -> Result<Vec<Written>, CompileError> {
    let body = body(lib)?;
    let text = header_lines(p, lib, opts, &HEADER) + &body;
    Ok(vec![Written { name: format!("{}.lib.hlsl", p.file_stem()), text, code: Some(body) }])
}

fn body(lib: &Library) -> Result<String, CompileError> {
    let options = hlsl::Options { force_loop_bounding: false, ..hlsl::Options::default() };
    let pipeline = hlsl::PipelineOptions { entry_point: None };
    let mut out = String::new();
    hlsl::Writer::new(&mut out, &options, &pipeline).write(&lib.module, &lib.info, None).map_err(|e| err("hlsl", e))?;
    // Samplers as plain registers instead of naga's sampler heap.
    let mut text = String::new();
    for line in out.lines() {
        let t = line.trim_start();
        if t.starts_with("SamplerState nagaSamplerHeap")
            || t.starts_with("SamplerComparisonState nagaComparisonSamplerHeap")
            || (t.starts_with("StructuredBuffer<uint> nagaGroup") && t.contains("SamplerIndexArray"))
        {
            continue;
        }
        if let Some(rest) = t.strip_prefix("static const SamplerState ") {
            let name = rest.split_whitespace().next().unwrap_or("");
            let b = lib
                .bindings
                .iter()
                .find(|b| b.name == name)
                .ok_or_else(|| err("hlsl", format!("sampler `{name}` is not a library resource")))?;
            let _ = writeln!(text, "SamplerState {name} : register(s{}, space{});", b.binding, b.group);
            continue;
        }
        if t.contains("nagaSamplerHeap") || t.contains("SamplerIndexArray") {
            return Err(err("hlsl", format!("sampler heap access left in `{line}`")));
        }
        text.push_str(&sample_level_zero(line));
        text.push('\n');
    }
    Ok(text)
}

/// naga 30's HLSL backend writes a level-0 sample as `t.SampleLevelZero(s, uv)`, which
/// glslang's HLSL front end rejects (no matching overloaded function): the library writes
/// the classic `t.SampleLevel(s, uv, 0.0)`, which every HLSL compiler takes.
fn sample_level_zero(line: &str) -> String {
    const BAD: &str = ".SampleLevelZero(";
    let mut out = String::new();
    let mut rest = line;
    while let Some(i) = rest.find(BAD) {
        out.push_str(&rest[..i]);
        out.push_str(".SampleLevel(");
        rest = &rest[i + BAD.len()..];
        let mut depth = 1;
        let mut end = rest.len();
        for (j, c) in rest.char_indices() {
            match c {
                '(' => depth += 1,
                ')' => {
                    depth -= 1;
                    if depth == 0 {
                        end = j;
                        break;
                    }
                }
                _ => {}
            }
        }
        out.push_str(&sample_level_zero(&rest[..end]));
        out.push_str(", 0.0");
        rest = &rest[end..];
    }
    out.push_str(rest);
    out
}

/// The HLSL of the library with resources as arguments (shader model 5.1, level-0 samples
/// written as `SampleLevel(s, uv, 0.0)` as in the plain HLSL library).
pub(crate) fn with_arguments(lib: &Library) -> Result<String, CompileError> {
    let (module, info) = resources_as_arguments(lib)?;
    let options = hlsl::Options { force_loop_bounding: false, ..hlsl::Options::default() };
    let pipeline = hlsl::PipelineOptions { entry_point: None };
    let mut out = String::new();
    hlsl::Writer::new(&mut out, &options, &pipeline).write(&module, &info, None).map_err(|e| err("hlsl", e))?;
    let mut text = String::new();
    for line in out.lines() {
        if line.contains("nagaSamplerHeap") || line.contains("SamplerIndexArray") {
            return Err(err("hlsl", format!("sampler heap access left in `{line}`")));
        }
        text.push_str(&sample_level_zero(line));
        text.push('\n');
    }
    Ok(text)
}
