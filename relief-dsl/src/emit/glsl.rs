//! The GLSL 450 form (`NAME.lib.glsl`): an include file (no `#version`). GLSL combines a
//! texture with its sampler, so each texture is a `sampler2D` (`sampler3D`) at the texture's
//! binding, to be bound with the filtering the header names, and the samplers' bindings stay
//! unused. Each declaration carries `set = G` when compiled for Vulkan (`#ifdef VULKAN`) and
//! `binding = B` only otherwise. The GLSL ES form ([`super::glsl_es`]) starts from the same
//! writer.

use naga::back::glsl;
use naga::{Expression, Handle, Module, ShaderStage, Span, Statement};

use super::common::{err, header_lines, Header, ResourceArguments, Written};
use crate::compose::library::{Library, LibraryOptions, ResourceKind};
use crate::spec::Pipeline;
use crate::CompileError;

/// The GLSL types of the resources (GLSL ES shares them).
pub(crate) fn glsl_type(kind: ResourceKind) -> &'static str {
    match kind {
        ResourceKind::Sampler => "(none in GLSL)",
        ResourceKind::Texture2d => "sampler2D",
        ResourceKind::Texture3d => "sampler3D",
    }
}

const HEADER: Header = Header {
    arguments: ResourceArguments::Global,
    intro: "// Include after the GLSL 450 version line. Resources (combined image samplers; a texture takes the\n\
            // sampler's filtering from the application; the sampler bindings below are unused in GLSL):\n",
    resource_type: glsl_type,
    by_name: false,
    no_nearest_sampler: false,
};

/// `NAME.lib.glsl`.
pub(crate) fn write(p: &Pipeline, lib: &Library, opts: &LibraryOptions) -> Result<Vec<Written>, CompileError> {
    let body = body(lib, opts, false)?;
    let text = header_lines(p, lib, opts, &HEADER) + &body;
    Ok(vec![Written { name: format!("{}.lib.glsl", p.file_stem()), text, code: Some(body) }])
}

/// A copy of `module` with a fragment entry `main` that calls every public function, for
/// the backends that write only what an entry point reaches (GLSL).
fn with_caller(lib: &Library, prefix: &str) -> Result<(Module, naga::valid::ModuleInfo), CompileError> {
    let mut module = lib.module.clone();
    let find = |name: &str| -> Option<Handle<naga::Function>> {
        module.functions.iter().find(|(_, f)| f.name.as_deref() == Some(name)).map(|(h, _)| h)
    };
    let trace = find(&format!("{prefix}_trace")).ok_or_else(|| err("glsl", "no trace function"))?;
    let shadow = find(&format!("{prefix}_shadow"));
    let ao = find(&format!("{prefix}_ao"));
    let vec2 = module.types.insert(
        naga::Type {
            name: None,
            inner: naga::TypeInner::Vector { size: naga::VectorSize::Bi, scalar: naga::Scalar::F32 },
        },
        Span::UNDEFINED,
    );
    let vec3 = module.types.insert(
        naga::Type {
            name: None,
            inner: naga::TypeInner::Vector { size: naga::VectorSize::Tri, scalar: naga::Scalar::F32 },
        },
        Span::UNDEFINED,
    );
    let loc = |location| naga::Binding::Location {
        location,
        interpolation: Some(naga::Interpolation::Perspective),
        sampling: Some(naga::Sampling::Center),
        blend_src: None,
        per_primitive: false,
    };
    let mut f = naga::Function {
        name: Some("main".into()),
        arguments: vec![
            naga::FunctionArgument { name: Some("uv".into()), ty: vec2, binding: Some(loc(0)) },
            naga::FunctionArgument { name: Some("view".into()), ty: vec3, binding: Some(loc(1)) },
        ],
        ..Default::default()
    };
    let uv = f.expressions.append(Expression::FunctionArgument(0), Span::UNDEFINED);
    let view = f.expressions.append(Expression::FunctionArgument(1), Span::UNDEFINED);
    let scale = f.expressions.append(Expression::Literal(naga::Literal::F32(0.1)), Span::UNDEFINED);
    let hit = f.expressions.append(Expression::CallResult(trace), Span::UNDEFINED);
    if lib.curved.is_some() {
        // A mesh library's functions take more inputs: zeros of their types (only that
        // every public function is reached matters here), the hit where one is taken.
        let hit_ty = module.functions[trace].result.as_ref().map(|r| r.ty);
        let call = |f: &mut naga::Function, function: Handle<naga::Function>, result: Handle<Expression>| {
            let tys: Vec<Handle<naga::Type>> = module.functions[function].arguments.iter().map(|a| a.ty).collect();
            let arguments = tys
                .into_iter()
                .map(|ty| match Some(ty) == hit_ty && function != trace {
                    true => hit,
                    false => f.expressions.append(Expression::ZeroValue(ty), Span::UNDEFINED),
                })
                .collect();
            f.body.push(Statement::Call { function, arguments, result: Some(result) }, Span::UNDEFINED);
        };
        call(&mut f, trace, hit);
        for g in [shadow, ao].into_iter().flatten() {
            let r = f.expressions.append(Expression::CallResult(g), Span::UNDEFINED);
            call(&mut f, g, r);
        }
        f.body.push(Statement::Return { value: None }, Span::UNDEFINED);
        module.entry_points.push(crate::compose::entry_point("main", ShaderStage::Fragment, f, [0; 3]));
        let info = crate::compose::validate(&module)?;
        return Ok((module, info));
    }
    f.body.push(
        Statement::Call { function: trace, arguments: vec![uv, view, scale], result: Some(hit) },
        Span::UNDEFINED,
    );
    if let Some(s) = shadow {
        let r = f.expressions.append(Expression::CallResult(s), Span::UNDEFINED);
        f.body
            .push(Statement::Call { function: s, arguments: vec![hit, view, scale], result: Some(r) }, Span::UNDEFINED);
    }
    if let Some(a) = ao {
        let r = f.expressions.append(Expression::CallResult(a), Span::UNDEFINED);
        f.body.push(Statement::Call { function: a, arguments: vec![hit], result: Some(r) }, Span::UNDEFINED);
    }
    f.body.push(Statement::Return { value: None }, Span::UNDEFINED);
    module.entry_points.push(crate::compose::entry_point("main", ShaderStage::Fragment, f, [0; 3]));
    let info = crate::compose::validate(&module)?;
    Ok((module, info))
}

/// GLSL of the library: an include file for GLSL 450 (`es == false`) or GLSL ES 3.00 for
/// WebGL2 (`es == true`, whose uniforms carry no binding: WebGL binds them by name).
pub(crate) fn body(lib: &Library, opts: &LibraryOptions, es: bool) -> Result<String, CompileError> {
    let (module, info) = with_caller(lib, &opts.prefix)?;
    let mut binding_map = glsl::BindingMap::default();
    for b in &lib.bindings {
        let n = u8::try_from(b.binding).map_err(|_| {
            err("glsl", format!("binding {} of `{}` does not fit GLSL's binding map (< 256)", b.binding, b.name))
        })?;
        binding_map.insert(naga::ResourceBinding { group: b.group, binding: b.binding }, n);
    }
    let version =
        if es { glsl::Version::Embedded { version: 300, is_webgl: true } } else { glsl::Version::Desktop(450) };
    let options = glsl::Options { version, binding_map, ..glsl::Options::default() };
    let pipeline =
        glsl::PipelineOptions { shader_stage: ShaderStage::Fragment, entry_point: "main".into(), multiview: None };
    let mut out = String::new();
    glsl::Writer::new(&mut out, &module, &info, &options, &pipeline, Default::default())
        .map_err(|e| err("glsl", e))?
        .write()
        .map_err(|e| err("glsl", e))?;
    // Keep everything but the version line, the caller's inputs and the caller itself.
    let body = out.split("\nvoid main()").next().unwrap_or(&out);
    let mut text = String::new();
    for line in body.lines() {
        if line.starts_with("#version") || line.contains("_vs2fs_location") {
            continue;
        }
        let mut line = line.to_string();
        for b in &lib.bindings {
            let naga_name = format!("_group_{}_binding_{}_fs", b.group, b.binding);
            if line.contains(&naga_name) && line.trim_start().starts_with("layout(") && line.contains(" uniform ") {
                let decl =
                    line.split_once(" uniform ").map(|(_, d)| d.replace(&naga_name, &b.name)).unwrap_or_default();
                line = format!(
                    "#ifdef VULKAN\nlayout(set = {g}, binding = {n}) uniform {decl}\n#else\nlayout(binding = {n}) uniform {decl}\n#endif",
                    g = b.group,
                    n = b.binding
                );
            } else {
                line = line.replace(&naga_name, &b.name);
            }
        }
        if line.contains("_group_") {
            return Err(err("glsl", format!("unexpected resource name left in `{line}`")));
        }
        text.push_str(&line);
        text.push('\n');
    }
    Ok(text)
}
