//! The Unreal form: an include file (`NAME.ush`, for a Custom material expression's Include
//! File Paths) and the node's code (`NAME.custom.hlsl`). Unreal hands a Custom node its
//! texture objects as `Texture2D` inputs, so the include file is the HLSL of the module with
//! its resources as arguments ([`super::hlsl::with_arguments`]); the node's code passes the
//! textures it gets as inputs named after the resources, and for samplers the view's shared
//! samplers (`View.SharedBilinearWrappedSampler`, …) chosen by the edge mode.

use std::fmt::Write as _;

use super::common::{header_lines, include_guard, input_name, reads, Written};
use super::hlsl;
use crate::compose::library::{camel, Library, LibraryOptions, ResourceKind};
use crate::spec::Pipeline;
use crate::CompileError;

/// `NAME.ush` and `NAME.custom.hlsl`.
pub(crate) fn write(p: &Pipeline, lib: &Library, opts: &LibraryOptions) -> Result<Vec<Written>, CompileError> {
    let stem = p.file_stem();
    let (include, node) = files(p, lib, opts)?;
    Ok(vec![
        Written { name: format!("{stem}.ush"), code: Some(include.clone()), text: include },
        Written { name: format!("{stem}.custom.hlsl"), text: node, code: None },
    ])
}

/// Unreal's two files: the include file (`NAME.ush`) and the Custom node's code
/// (`NAME.custom.hlsl`).
fn files(p: &Pipeline, lib: &Library, opts: &LibraryOptions) -> Result<(String, String), CompileError> {
    let pre = &opts.prefix;
    let stem = p.file_stem();
    let guard = include_guard(pre, &stem, "ush");
    let mut inc = String::new();
    let _ = writeln!(inc, "// relief library for the pipeline `{p}`: an include file for Unreal's Custom material");
    let _ = writeln!(inc, "// expression, written by `relief gen --library --target unreal` (the node's code is");
    let _ = writeln!(inc, "// `{stem}.custom.hlsl`). Each function takes, after its own arguments, the textures and");
    let _ = writeln!(inc, "// samplers it reads:");
    for line in header_lines(p, lib, opts, &hlsl::HEADER).lines().skip(2) {
        let _ = writeln!(inc, "{line}");
    }
    let _ = writeln!(inc, "#pragma once\n#ifndef {guard}\n#define {guard}\n");
    inc.push_str(&hlsl::with_arguments(lib)?);
    let _ = writeln!(inc, "\n#endif // {guard}");

    let wrap = if opts.edge_clamp { "Clamped" } else { "Wrapped" };
    let mut node = String::new();
    let _ =
        writeln!(node, "// Code of an Unreal Custom material expression for the pipeline `{p}` (relief gen --library");
    let _ =
        writeln!(node, "// --target unreal). Include File Paths: the virtual path of `{stem}.ush` in your project.");
    let _ = writeln!(node, "// Output Type: Float 4 = (hit uv, hit height, pixel depth offset in texture units).");
    let _ =
        writeln!(node, "// Inputs: UV (float2), ViewTS (float3: normalized tangent-space direction from the camera,");
    let _ = write!(node, "// z < 0), DepthScale (float: the relief's depth in texture units)");
    if lib.has_shadow {
        let _ = write!(node, ", LightTS (float3: toward the light)");
    }
    let textures: Vec<&crate::compose::library::LibraryBinding> =
        lib.bindings.iter().filter(|b| b.kind != ResourceKind::Sampler).collect();
    for b in &textures {
        let _ = write!(node, ",\n//   {} (Texture Object: {})", input_name(pre, &b.name), b.what);
    }
    let _ = writeln!(node, ".");
    match (lib.has_shadow, lib.has_ao) {
        (false, false) => {}
        (shadow, ao) => {
            let names: Vec<&str> =
                [("Shadow", shadow), ("AO", ao)].into_iter().filter(|(_, on)| *on).map(|(n, _)| n).collect();
            let _ = writeln!(node, "// Additional Outputs (Float 1): {}.", names.join(", "));
        }
    }
    let _ = writeln!(
        node,
        "// Samplers: the view's shared {} samplers (edge mode {}).",
        wrap.to_lowercase(),
        if opts.edge_clamp { "clamp" } else { "repeat" }
    );
    let call = |f: &str, own: &str| -> String {
        let mut args = vec![own.to_string()];
        for i in reads(lib, &format!("{pre}_{f}")) {
            let b = &lib.bindings[i];
            args.push(match b.kind {
                ResourceKind::Sampler if b.name.ends_with("_nearest") => format!("View.SharedPoint{wrap}Sampler"),
                ResourceKind::Sampler => format!("View.SharedBilinear{wrap}Sampler"),
                _ => input_name(pre, &b.name),
            });
        }
        format!("{pre}_{f}({})", args.join(", "))
    };
    let _ = writeln!(node, "{}Hit hit = {};", camel(pre), call("trace", "UV, ViewTS, DepthScale"));
    if lib.has_shadow {
        let _ = writeln!(node, "Shadow = {};", call("shadow", "hit, LightTS, DepthScale"));
    }
    if lib.has_ao {
        let _ = writeln!(node, "AO = {};", call("ao", "hit"));
    }
    let _ = writeln!(node, "return float4(hit.uv, hit.height, hit.depth_offset);");
    Ok((inc, node))
}
