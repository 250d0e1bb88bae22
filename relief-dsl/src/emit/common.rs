//! What the library writers share: the error shape, the header comment every file starts
//! with (each writer describes its dialect in a [`Header`]), the module with its resources as
//! function arguments (MSL's convention, taken by the TSL and engine forms), and the names
//! the engine forms give the resources.

use std::fmt::Write as _;

use naga::{Expression, Handle, Module, Statement};

use crate::compose::library::{camel, Library, LibraryBinding, LibraryOptions, ResourceKind};
use crate::ir::{Filter, Resource};
use crate::spec::{Curved, Pipeline};
use crate::CompileError;

/// An error of the library writer for `target`.
pub(crate) fn err(target: &str, e: impl std::fmt::Debug) -> CompileError {
    CompileError { stage: format!("emit library {target}"), message: format!("{e:?}") }
}

/// One file a form writes.
pub(crate) struct Written {
    /// Its file name (`NAME.lib.wgsl`).
    pub name: String,
    /// Its text.
    pub text: String,
    /// The library's code in it as the writer produced it, whose public names the driver
    /// checks came out as asked; `None` for a file that only calls the library (Unreal's
    /// node code).
    pub code: Option<String>,
}

/// How a function's header line lists the resources it takes as arguments.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum ResourceArguments {
    /// None: the resources are globals.
    Global,
    /// Every global the function reads, in the module's order (naga's MSL convention); the
    /// line is there even when the list is empty.
    ModuleOrder,
    /// The resources the function reads in binding order ([`resources_as_arguments`]), the
    /// line only when there are any.
    BindingOrder,
}

/// What a form's header comment says about its dialect.
pub(crate) struct Header {
    /// How the functions take their resources.
    pub arguments: ResourceArguments,
    /// The lines (each ending in a newline) before the resource list.
    pub intro: &'static str,
    /// The declared type of a resource of each kind.
    pub resource_type: fn(ResourceKind) -> &'static str,
    /// Whether the resources are bound by name (GLSL ES: no group or binding to list).
    pub by_name: bool,
    /// Whether the form reads nearest-filtered textures with texel loads and so takes no
    /// nearest sampler (TSL: three.js binds no sampler for a texture whose filters are both
    /// nearest); the sampler is then left out of the header's lists.
    pub no_nearest_sampler: bool,
}

/// Whether a form whose header is `header` lists the resource `b`.
pub(crate) fn listed(header: &Header, b: &LibraryBinding) -> bool {
    !(header.no_nearest_sampler && b.resource == Resource::Sampler(Filter::Nearest))
}

/// WGSL's resource types.
pub(crate) fn wgsl_type(kind: ResourceKind) -> &'static str {
    match kind {
        ResourceKind::Sampler => "sampler",
        ResourceKind::Texture2d => "texture_2d<f32>",
        ResourceKind::Texture3d => "texture_3d<f32>",
    }
}

/// The header's interface of a mesh library (`curved=…`): the functions and the per-vertex
/// inputs the caller interpolates for them (docs/meshes-shaders.md).
fn mesh_interface(h: &mut String, curved: Curved, pre: &str, hit: &str, lib: &Library, extra: &dyn Fn(&str) -> String) {
    let (first, own) = match curved {
        Curved::None => ("uv: vec2<f32>", ""),
        Curved::Quadric => ("uv: vec2<f32>", " curvature: vec2<f32>,"),
        Curved::Prism => (
            "uvw: vec3<f32>",
            " prism_a: vec4<f32>, prism_b: vec2<f32>, position: vec3<f32>, prism_p0: vec3<f32>, prism_p1: vec3<f32>, prism_p2: vec3<f32>, prism_n0: vec3<f32>, prism_n1: vec3<f32>, prism_n2: vec3<f32>,",
        ),
    };
    let _ = writeln!(
        h,
        "// fn {pre}_trace({first}, view: vec3<f32>, normal: vec3<f32>, tangent: vec4<f32>, uv_scale: vec2<f32>,{own} depth_scale: f32) -> {hit}{}",
        extra(&format!("{pre}_trace"))
    );
    if lib.has_shadow {
        let _ = writeln!(
            h,
            "// fn {pre}_shadow(hit: {hit}, light: vec3<f32>, normal: vec3<f32>, tangent: vec4<f32>, uv_scale: vec2<f32>, depth_scale: f32) -> f32{}",
            extra(&format!("{pre}_shadow"))
        );
    }
    if lib.has_ao {
        let _ = writeln!(h, "// fn {pre}_ao(hit: {hit}) -> f32{}", extra(&format!("{pre}_ao")));
    }
    let _ =
        writeln!(h, "// Mesh form, curved={curved}. Per-vertex inputs, interpolated to the fragment (object space):");
    let _ = writeln!(
        h,
        "//   position; normal (unit); tangent (xyz unit along +u, w the handedness: B = w * cross(N, T));"
    );
    let _ = writeln!(h, "//   uv; uv_scale = texture units per object unit along T and B.");
    match curved {
        Curved::None => {}
        Curved::Quadric => {
            let _ = writeln!(
                h,
                "//   curvature = (a, b): the base surface lies a*du^2 + b*dv^2 object units above the tangent"
            );
            let _ = writeln!(
                h,
                "//   plane at texture offset (du, dv) (Oliveira & Policarpo 2005; a sphere: -1/(2 R uv_scale^2))."
            );
        }
        Curved::Prism => {
            let _ = writeln!(
                h,
                "//   draw each triangle as a prism: 6 vertices, the floor ones moved depth_scale along -normal;"
            );
            let _ = writeln!(
                h,
                "//   uvw = (uv, layer) with layer 1 on the surface and 0 on the floor; prism_a = the triangle's"
            );
            let _ = writeln!(
                h,
                "//   uv0 (xy) and uv1 (zw), prism_b = its uv2, the same at all six vertices; position = the"
            );
            let _ = writeln!(
                h,
                "//   fragment's point; prism_p0..2, prism_n0..2 = the triangle's corner points and normals (flat)."
            );
            let _ = writeln!(
                h,
                "//   The ray is traced through the prism's exact volume (bilinear side walls); layer is unused."
            );
        }
    }
    let _ = writeln!(
        h,
        "//   view: from the eye to the fragment; light: toward the light; depth_scale: the relief's depth"
    );
    let _ = writeln!(h, "//   in object units. hit.covered = 0: discard the fragment (no hit in the shell or prism);");
    let _ = writeln!(
        h,
        "//   hit.depth_offset: the distance from the fragment to the hit along the view ray (object units)."
    );
}

/// The header comment of a library file: the interface, the edge mode and the resources, in
/// the dialect `header` describes.
pub(crate) fn header_lines(p: &Pipeline, lib: &Library, opts: &LibraryOptions, header: &Header) -> String {
    let pre = &opts.prefix;
    let hit = format!("{}Hit", camel(pre));
    let mut h = String::new();
    let _ = writeln!(h, "// relief library for the pipeline `{p}`, written by `relief gen --library`.");
    let _ = writeln!(h, "//");
    let covered = if lib.curved.is_some() { ", covered: f32" } else { "" };
    let _ = writeln!(h, "// struct {hit} {{ uv: vec2<f32>, height: f32, t: f32, depth_offset: f32{covered} }}");
    let extra = |name: &str| -> String {
        if header.arguments == ResourceArguments::Global {
            return String::new();
        }
        let Some((fh, _)) = lib.module.functions.iter().find(|(_, f)| f.name.as_deref() == Some(name)) else {
            return String::new();
        };
        let reads = |g: &str| {
            lib.module
                .global_variables
                .iter()
                .any(|(h, gv)| gv.name.as_deref() == Some(g) && !lib.info[fh][h].is_empty())
        };
        let args: Vec<String> = if header.arguments == ResourceArguments::BindingOrder {
            lib.bindings.iter().filter(|b| listed(header, b) && reads(&b.name)).map(|b| b.name.clone()).collect()
        } else {
            lib.module
                .global_variables
                .iter()
                .filter(|(g, _)| !lib.info[fh][*g].is_empty())
                .filter_map(|(_, g)| g.name.clone())
                .collect()
        };
        if args.is_empty() && header.arguments == ResourceArguments::BindingOrder {
            return String::new();
        }
        format!("\n//     + resource arguments: {}", args.join(", "))
    };
    if let Some(curved) = lib.curved {
        mesh_interface(&mut h, curved, pre, &hit, lib, &extra);
    } else {
        let _ = writeln!(
            h,
            "// fn {pre}_trace(uv: vec2<f32>, view_ts: vec3<f32>, depth_scale: f32) -> {hit}{}",
            extra(&format!("{pre}_trace"))
        );
        if lib.has_shadow {
            let _ = writeln!(
                h,
                "// fn {pre}_shadow(hit: {hit}, light_ts: vec3<f32>, depth_scale: f32) -> f32{}",
                extra(&format!("{pre}_shadow"))
            );
        }
        if lib.has_ao {
            let _ = writeln!(h, "// fn {pre}_ao(hit: {hit}) -> f32{}", extra(&format!("{pre}_ao")));
        }
        let _ =
            writeln!(h, "//   uv: the fragment's texture coordinate; view_ts: the normalized tangent-space direction");
        let _ =
            writeln!(h, "//   from the eye to the fragment (z < 0); light_ts: the normalized tangent-space direction");
        let _ = writeln!(h, "//   toward the light; depth_scale: the relief's depth in texture units.");
        let _ =
            writeln!(h, "//   hit.uv: where to shade; hit.height in [0, 1] (1 at the polygon); hit.t in [0, 1] along");
        let _ = writeln!(
            h,
            "//   the ray from the polygon (0) to the floor (1); hit.depth_offset = t * depth_scale / -view_ts.z:"
        );
        let _ = writeln!(
            h,
            "//   the distance behind the polygon along the view ray, in texture units (pixel depth offset)."
        );
    }
    let _ = writeln!(
        h,
        "// Edge mode assumed by stages that address texels themselves: {} ({pre}_edge_clamp = {}).",
        if opts.edge_clamp { "clamp to edge" } else { "repeat" },
        opts.edge_clamp
    );
    let _ = writeln!(h, "//");
    h.push_str(header.intro);
    for b in lib.bindings.iter().filter(|b| listed(header, b)) {
        let ty = (header.resource_type)(b.kind);
        if header.by_name {
            let _ = writeln!(h, "//   uniform {} {ty} — {}", b.name, b.what);
        } else {
            let _ = writeln!(h, "//   group {} binding {}: {} {ty} — {}", b.group, b.binding, b.name, b.what);
        }
    }
    h.push('\n');
    h
}

/// Whether `name` occurs in `text` as a whole identifier.
pub(crate) fn has_word(text: &str, name: &str) -> bool {
    let ident = |c: char| c.is_ascii_alphanumeric() || c == '_';
    text.match_indices(name).any(|(i, _)| {
        let before = text[..i].chars().next_back();
        let after = text[i + name.len()..].chars().next();
        !before.is_some_and(ident) && !after.is_some_and(ident)
    })
}

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

/// The resources' names without the prefix, in CamelCase (`relief_cone_nearest` →
/// `ConeNearest`): the engine-side input names.
pub(crate) fn input_name(prefix: &str, resource: &str) -> String {
    camel(resource.strip_prefix(&format!("{prefix}_")).unwrap_or(resource))
}

/// Which resources (indices into the bindings) the public function `function` reads, in its
/// argument order.
pub(crate) fn reads(lib: &Library, function: &str) -> Vec<usize> {
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

/// An engine file's include guard: `PREFIX_STEM_WHAT` in capitals, anything else as `_`.
pub(crate) fn include_guard(prefix: &str, stem: &str, what: &str) -> String {
    format!("{prefix}_{stem}_{what}")
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c.to_ascii_uppercase() } else { '_' })
        .collect()
}
