//! The engine forms of a library: Unity Shader Graph's Custom Function file and Unreal's
//! include file with the body of a Custom expression node.
//!
//! Neither engine lets a material function read global textures that the library declares:
//! Shader Graph hands a Custom Function its textures as `UnityTexture2D` /
//! `UnitySamplerState` arguments, and Unreal hands a Custom node its texture objects as
//! `Texture2D` arguments. Both forms therefore start from `resources_as_arguments`: the
//! library module with every texture and sampler turned into a function argument (the
//! convention naga's MSL backend follows), written by naga's HLSL backend. Each public
//! function takes, after its own arguments, the resources it reads in binding order.
//!
//! - Unity (File mode of the Custom Function node): `void P_float(...)` and `void P_half(...)`
//!   (`P` the prefix in CamelCase, so the node's Name is `P`), taking the uv, the view and
//!   light directions, the depth scale and one `UnityTexture2D` / `UnitySamplerState` per
//!   resource, with `out` values for the hit uv, height and pixel depth offset (and shadow
//!   and ao when the pipeline has them).
//! - Unreal: the include file (`NAME.ush`, for the node's Include File Paths) and the node's
//!   code: texture objects come in as inputs named after the resources; samplers are the
//!   view's shared samplers (`View.SharedBilinearWrappedSampler`, …) chosen by the edge mode.

use std::fmt::Write as _;

use naga::back::hlsl;
use naga::{Expression, Handle, Module, Statement};

use super::library::{err, header_lines, sample_level_zero, Lang};
use crate::compose::library::{camel, Library, LibraryOptions, ResourceKind};
use crate::spec::Pipeline;
use crate::CompileError;

/// The library module with every global (all of them are textures and samplers) turned into
/// trailing arguments of the functions that read it, in binding order; callers pass theirs on.
pub(crate) fn resources_as_arguments(lib: &Library) -> Result<(Module, naga::valid::ModuleInfo), CompileError> {
    let mut module = lib.module.clone();
    let by_name =
        |name: &str| module.global_variables.iter().find(|(_, g)| g.name.as_deref() == Some(name)).map(|(h, _)| h);
    let order: Vec<Handle<naga::GlobalVariable>> = lib.bindings.iter().filter_map(|b| by_name(&b.name)).collect();
    if order.len() != module.global_variables.len() {
        return Err(err("hlsl arguments", "a global of the library is no listed resource"));
    }
    // For each function, the resources it (or a function it calls) reads, in binding order.
    let uses: Vec<(Handle<naga::Function>, Vec<Handle<naga::GlobalVariable>>)> = module
        .functions
        .iter()
        .map(|(fh, _)| (fh, order.iter().copied().filter(|g| !lib.info[fh][*g].is_empty()).collect()))
        .collect();
    let used =
        |fh: Handle<naga::Function>| uses.iter().find(|(h, _)| *h == fh).map(|(_, u)| u.clone()).unwrap_or_default();
    for (fh, f) in module.functions.iter_mut() {
        let mine = used(fh);
        let base = f.arguments.len() as u32;
        for g in &mine {
            let gv = &lib.module.global_variables[*g];
            f.arguments.push(naga::FunctionArgument { name: gv.name.clone(), ty: gv.ty, binding: None });
        }
        let index = |g: Handle<naga::GlobalVariable>| mine.iter().position(|m| *m == g).map(|i| base + i as u32);
        for (_, e) in f.expressions.iter_mut() {
            if let Expression::GlobalVariable(g) = *e {
                *e = Expression::FunctionArgument(
                    index(g).ok_or_else(|| err("hlsl arguments", "a resource read outside its function's uses"))?,
                );
            }
        }
        // The arguments callers pass on: one expression per resource, appended once.
        let mut arg_exprs = Vec::new();
        for (i, _) in mine.iter().enumerate() {
            arg_exprs.push(f.expressions.append(Expression::FunctionArgument(base + i as u32), naga::Span::UNDEFINED));
        }
        let pass = |callee: Handle<naga::Function>| -> Vec<Handle<Expression>> {
            used(callee).iter().filter_map(|g| mine.iter().position(|m| m == g).map(|i| arg_exprs[i])).collect()
        };
        add_call_arguments(&mut f.body, &pass);
    }
    module.global_variables = naga::Arena::new();
    let info = crate::compose::validate(&module)?;
    Ok((module, info))
}

/// Appends `pass(callee)` to the arguments of every call in `block`, nested blocks included.
fn add_call_arguments(block: &mut naga::Block, pass: &dyn Fn(Handle<naga::Function>) -> Vec<Handle<Expression>>) {
    for s in block.iter_mut() {
        match s {
            Statement::Call { function, arguments, .. } => arguments.extend(pass(*function)),
            Statement::Block(b) => add_call_arguments(b, pass),
            Statement::If { accept, reject, .. } => {
                add_call_arguments(accept, pass);
                add_call_arguments(reject, pass);
            }
            Statement::Switch { cases, .. } => cases.iter_mut().for_each(|c| add_call_arguments(&mut c.body, pass)),
            Statement::Loop { body, continuing, .. } => {
                add_call_arguments(body, pass);
                add_call_arguments(continuing, pass);
            }
            _ => {}
        }
    }
}

/// The HLSL of the library with resources as arguments (shader model 5.1, level-0 samples
/// written as `SampleLevel(s, uv, 0.0)` as in the plain HLSL library).
pub(crate) fn argument_hlsl(lib: &Library) -> Result<String, CompileError> {
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

/// The resources' names without the prefix, in CamelCase (`relief_cone_nearest` →
/// `ConeNearest`): the engine-side input names.
fn input_name(prefix: &str, resource: &str) -> String {
    camel(resource.strip_prefix(&format!("{prefix}_")).unwrap_or(resource))
}

/// Which resources each public function reads, in its argument order.
fn reads(lib: &Library, function: &str) -> Vec<usize> {
    let Some((fh, _)) = lib.module.functions.iter().find(|(_, f)| f.name.as_deref() == Some(function)) else {
        return Vec::new();
    };
    lib.bindings
        .iter()
        .enumerate()
        .filter(|(_, b)| {
            lib.module
                .global_variables
                .iter()
                .any(|(g, gv)| gv.name.as_deref() == Some(b.name.as_str()) && !lib.info[fh][g].is_empty())
        })
        .map(|(i, _)| i)
        .collect()
}

fn include_guard(prefix: &str, stem: &str, what: &str) -> String {
    format!("{prefix}_{stem}_{what}")
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c.to_ascii_uppercase() } else { '_' })
        .collect()
}

/// `NAME.unity.hlsl`: the Custom Function file for Unity's Shader Graph (File mode).
pub fn unity(p: &Pipeline, lib: &Library, opts: &LibraryOptions) -> Result<String, CompileError> {
    let pre = &opts.prefix;
    let node = camel(pre);
    let body = argument_hlsl(lib)?;
    let guard = include_guard(pre, &p.file_stem(), "unity");
    let mut s = String::new();
    let _ = writeln!(s, "// relief library for the pipeline `{p}`: a Custom Function file for Unity's Shader Graph,");
    let _ = writeln!(s, "// written by `relief gen --library --target unity`.");
    let _ = writeln!(s, "//");
    let _ = writeln!(s, "// Custom Function node: Type File, this file as Source, Name `{node}` (Shader Graph calls");
    let _ = writeln!(s, "// `{node}_float` or `{node}_half` by the node's precision). Inputs, in order:");
    let _ = writeln!(s, "//   UV (Vector 2): the texture coordinate; ViewTS (Vector 3): the normalized tangent-space");
    let _ =
        writeln!(s, "//   direction from the camera to the fragment (z < 0); DepthScale (Float): the relief's depth");
    let _ = writeln!(s, "//   in texture units;");
    if lib.has_shadow {
        let _ = writeln!(s, "//   LightTS (Vector 3): the normalized tangent-space direction toward the light;");
    }
    for b in &lib.bindings {
        let (ty, sg) = unity_type(b.kind);
        let _ = writeln!(s, "//   {} ({sg}, {ty}): {}", input_name(pre, &b.name), b.what);
    }
    let _ = writeln!(s, "// Outputs: HitUV (Vector 2): where to shade; HitHeight (Float): the height there (1 at the");
    let _ = writeln!(s, "//   polygon); DepthOffset (Float): the distance behind the polygon along the view ray, in");
    let _ = writeln!(
        s,
        "//   texture units (pixel depth offset){}.",
        match (lib.has_shadow, lib.has_ao) {
            (true, true) => "; Shadow (Float): the light's visibility; AO (Float): ambient occlusion",
            (true, false) => "; Shadow (Float): the light's visibility",
            (false, true) => "; AO (Float): ambient occlusion",
            (false, false) => "",
        }
    );
    let _ = writeln!(
        s,
        "// Edge mode assumed by stages that address texels themselves: {}; set the textures' wrap mode to match.",
        if opts.edge_clamp { "clamp" } else { "repeat" }
    );
    let _ = writeln!(s, "\n#ifndef {guard}\n#define {guard}\n");
    s.push_str(&body);
    for (suffix, scalar) in [("float", "float"), ("half", "half")] {
        let _ = writeln!(s, "\nvoid {node}_{suffix}({}) {{", unity_params(lib, pre, scalar).join(", "));
        let call = |f: &str, own: &str| -> String {
            let mut args = vec![own.to_string()];
            for i in reads(lib, &format!("{pre}_{f}")) {
                let b = &lib.bindings[i];
                let field = if b.kind == ResourceKind::Sampler { "samplerstate" } else { "tex" };
                args.push(format!("{}.{field}", input_name(pre, &b.name)));
            }
            format!("{pre}_{f}({})", args.join(", "))
        };
        let _ = writeln!(s, "    {node}Hit hit = {};", call("trace", "(float2)UV, (float3)ViewTS, (float)DepthScale"));
        let _ = writeln!(s, "    HitUV = ({scalar}2)hit.uv;\n    HitHeight = ({scalar})hit.height;\n    DepthOffset = ({scalar})hit.depth_offset;");
        if lib.has_shadow {
            let _ =
                writeln!(s, "    Shadow = ({scalar}){};", call("shadow", "hit, (float3)LightTS, (float)DepthScale"));
        }
        if lib.has_ao {
            let _ = writeln!(s, "    AO = ({scalar}){};", call("ao", "hit"));
        }
        s.push_str("}\n");
    }
    let _ = writeln!(s, "\n#endif // {guard}");
    Ok(s)
}

fn unity_type(kind: ResourceKind) -> (&'static str, &'static str) {
    match kind {
        ResourceKind::Texture2d => ("UnityTexture2D", "Texture 2D"),
        ResourceKind::Texture3d => ("UnityTexture3D", "Texture 3D"),
        ResourceKind::Sampler => ("UnitySamplerState", "Sampler State"),
    }
}

fn unity_params(lib: &Library, pre: &str, scalar: &str) -> Vec<String> {
    let mut params = vec![format!("{scalar}2 UV"), format!("{scalar}3 ViewTS"), format!("{scalar} DepthScale")];
    if lib.has_shadow {
        params.push(format!("{scalar}3 LightTS"));
    }
    for b in &lib.bindings {
        params.push(format!("{} {}", unity_type(b.kind).0, input_name(pre, &b.name)));
    }
    params.extend([
        format!("out {scalar}2 HitUV"),
        format!("out {scalar} HitHeight"),
        format!("out {scalar} DepthOffset"),
    ]);
    if lib.has_shadow {
        params.push(format!("out {scalar} Shadow"));
    }
    if lib.has_ao {
        params.push(format!("out {scalar} AO"));
    }
    params
}

/// Unreal's two files: the include file (`NAME.ush`) and the Custom node's code
/// (`NAME.custom.hlsl`).
pub fn unreal(p: &Pipeline, lib: &Library, opts: &LibraryOptions) -> Result<(String, String), CompileError> {
    let pre = &opts.prefix;
    let stem = p.file_stem();
    let guard = include_guard(pre, &stem, "ush");
    let mut inc = String::new();
    let _ = writeln!(inc, "// relief library for the pipeline `{p}`: an include file for Unreal's Custom material");
    let _ = writeln!(inc, "// expression, written by `relief gen --library --target unreal` (the node's code is");
    let _ = writeln!(inc, "// `{stem}.custom.hlsl`). Each function takes, after its own arguments, the textures and");
    let _ = writeln!(inc, "// samplers it reads:");
    for line in header_lines(p, lib, opts, Lang::Hlsl).lines().skip(2) {
        let _ = writeln!(inc, "{line}");
    }
    let _ = writeln!(inc, "#pragma once\n#ifndef {guard}\n#define {guard}\n");
    inc.push_str(&argument_hlsl(lib)?);
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
