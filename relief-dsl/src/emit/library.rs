//! The library output: a pipeline's stages as functions for a user's own shader, in WGSL,
//! GLSL 450, HLSL and MSL (the interface: [`crate::compose::library`]).
//!
//! Every file starts with a header comment that lists the interface and the resources with
//! their bindings. What differs between languages:
//! - WGSL: the module as naga writes it; with [`LibraryOptions::import_path`] its first line
//!   is `#define_import_path PATH` (a `naga_oil` / WESL import).
//! - GLSL 450: an include file (no `#version`): GLSL combines a texture with its sampler, so
//!   each texture is a `sampler2D` (`sampler3D`) at the texture's binding, to be bound with
//!   the filtering the header names, and the samplers' bindings stay unused. Each declaration
//!   carries `set = G` when compiled for Vulkan (`#ifdef VULKAN`) and `binding = B` only
//!   otherwise.
//! - HLSL (shader model 5.1): textures at `register(tB, spaceG)`, samplers at
//!   `register(sB, spaceG)`. naga writes samplers through a sampler heap and an index
//!   buffer (its D3D12 binding model); the library declares them as plain `SamplerState`s at
//!   their registers instead.
//! - MSL: Metal has no global resources, so every function that reads one takes it as an
//!   extra argument (naga's convention): `relief_trace(uv, view_ts, depth_scale,
//!   relief_height, relief_sampler, …)`, in the order the header lists for each function.
//!   The module is validated by naga before it is written.

use std::fmt::Write as _;

use naga::back::{glsl, hlsl, msl, wgsl};
use naga::{Expression, Handle, Module, ShaderStage, Span, Statement};

pub use crate::compose::library::{Library, LibraryBinding, LibraryOptions, ResourceKind};
use crate::spec::Pipeline;
use crate::CompileError;

/// The four library files of one pipeline.
#[derive(Clone, Debug)]
pub struct LibraryFiles {
    /// `NAME.lib.wgsl`.
    pub wgsl: String,
    /// `NAME.lib.glsl` (an include file, GLSL 450).
    pub glsl: String,
    /// `NAME.lib.hlsl`.
    pub hlsl: String,
    /// `NAME.lib.metal`.
    pub msl: String,
    /// The resources, in binding order.
    pub bindings: Vec<LibraryBinding>,
    /// Whether `P_shadow` exists.
    pub has_shadow: bool,
    /// Whether `P_ao` exists.
    pub has_ao: bool,
}

pub(crate) fn err(target: &str, e: impl std::fmt::Debug) -> CompileError {
    CompileError { stage: format!("emit library {target}"), message: format!("{e:?}") }
}

#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum Lang {
    Wgsl,
    /// WGSL with the resources as trailing arguments (three.js TSL's `wgslFn`).
    WgslArgs,
    Glsl,
    GlslEs,
    Hlsl,
    Msl,
}

/// The header comment of a library file in `lang`.
pub(crate) fn header_lines(p: &Pipeline, lib: &Library, opts: &LibraryOptions, lang: Lang) -> String {
    let pre = &opts.prefix;
    let hit = format!("{}Hit", crate::compose::library::camel(pre));
    let mut h = String::new();
    let _ = writeln!(h, "// relief library for the pipeline `{p}`, written by `relief gen --library`.");
    let _ = writeln!(h, "//");
    let _ = writeln!(h, "// struct {hit} {{ uv: vec2<f32>, height: f32, t: f32, depth_offset: f32 }}");
    // Metal takes each resource a function reads as an extra argument, in the order of the
    // module's globals (naga's MSL convention).
    // The TSL form takes them in binding order ([`super::engines::resources_as_arguments`]).
    let extra = |name: &str| -> String {
        if lang != Lang::Msl && lang != Lang::WgslArgs {
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
        let args: Vec<String> = if lang == Lang::WgslArgs {
            lib.bindings.iter().filter(|b| reads(&b.name)).map(|b| b.name.clone()).collect()
        } else {
            lib.module
                .global_variables
                .iter()
                .filter(|(g, _)| !lib.info[fh][*g].is_empty())
                .filter_map(|(_, g)| g.name.clone())
                .collect()
        };
        if args.is_empty() && lang == Lang::WgslArgs {
            return String::new();
        }
        format!("\n//     + resource arguments: {}", args.join(", "))
    };
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
    let _ = writeln!(h, "//   uv: the fragment's texture coordinate; view_ts: the normalized tangent-space direction");
    let _ = writeln!(h, "//   from the eye to the fragment (z < 0); light_ts: the normalized tangent-space direction");
    let _ = writeln!(h, "//   toward the light; depth_scale: the relief's depth in texture units.");
    let _ = writeln!(h, "//   hit.uv: where to shade; hit.height in [0, 1] (1 at the polygon); hit.t in [0, 1] along");
    let _ = writeln!(
        h,
        "//   the ray from the polygon (0) to the floor (1); hit.depth_offset = t * depth_scale / -view_ts.z:"
    );
    let _ =
        writeln!(h, "//   the distance behind the polygon along the view ray, in texture units (pixel depth offset).");
    let _ = writeln!(
        h,
        "// Edge mode assumed by stages that address texels themselves: {} ({pre}_edge_clamp = {}).",
        if opts.edge_clamp { "clamp to edge" } else { "repeat" },
        opts.edge_clamp
    );
    let _ = writeln!(h, "//");
    match lang {
        Lang::Glsl => {
            let _ = writeln!(
                h,
                "// Include after the GLSL 450 version line. Resources (combined image samplers; a texture takes the"
            );
            let _ = writeln!(
                h,
                "// sampler's filtering from the application; the sampler bindings below are unused in GLSL):"
            );
        }
        Lang::GlslEs => {
            let _ = writeln!(
                h,
                "// GLSL ES 3.00 (WebGL2): put after the ES 3.00 version line (three.js and Babylon.js add it). Resources:"
            );
            let _ = writeln!(
                h,
                "// sampler uniforms, bound by name (ES 3.00 has no binding qualifiers); a texture takes the"
            );
            let _ = writeln!(
                h,
                "// sampler's filtering from the application; the samplers below have no uniform in GLSL ES:"
            );
        }
        Lang::WgslArgs => {
            let _ = writeln!(
                h,
                "// three.js TSL (`wgsl(this)` as an include of your `wgslFn`): no resource is global; each function"
            );
            let _ = writeln!(
                h,
                "// above takes those it reads as extra arguments after its own, in the order listed (the group and"
            );
            let _ = writeln!(h, "// binding numbers are for the other forms; TSL binds what you pass):");
        }
        Lang::Msl => {
            let _ =
                writeln!(h, "// Resources (Metal has none global: each function above takes those it reads as extra");
            let _ = writeln!(
                h,
                "// arguments after its own, in the order listed; the bindings are for the other languages):"
            );
        }
        _ => {
            let _ = writeln!(h, "// Resources:");
        }
    }
    for b in &lib.bindings {
        let ty = match (lang, b.kind) {
            (Lang::Glsl | Lang::GlslEs, ResourceKind::Sampler) => "(none in GLSL)",
            (Lang::Glsl | Lang::GlslEs, ResourceKind::Texture2d) => "sampler2D",
            (Lang::Glsl | Lang::GlslEs, ResourceKind::Texture3d) => "sampler3D",
            (Lang::Hlsl, ResourceKind::Sampler) => "SamplerState",
            (Lang::Hlsl, ResourceKind::Texture2d) => "Texture2D<float4>",
            (Lang::Hlsl, ResourceKind::Texture3d) => "Texture3D<float4>",
            (Lang::Msl, ResourceKind::Sampler) => "metal::sampler",
            (Lang::Msl, ResourceKind::Texture2d) => "metal::texture2d<float, metal::access::sample>",
            (Lang::Msl, ResourceKind::Texture3d) => "metal::texture3d<float, metal::access::sample>",
            (_, ResourceKind::Sampler) => "sampler",
            (_, ResourceKind::Texture2d) => "texture_2d<f32>",
            (_, ResourceKind::Texture3d) => "texture_3d<f32>",
        };
        if lang == Lang::GlslEs {
            let _ = writeln!(h, "//   uniform {} {ty} — {}", b.name, b.what);
        } else {
            let _ = writeln!(h, "//   group {} binding {}: {} {ty} — {}", b.group, b.binding, b.name, b.what);
        }
    }
    h.push('\n');
    h
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

fn wgsl_text(lib: &Library) -> Result<String, CompileError> {
    wgsl::write_string(&lib.module, &lib.info, wgsl::WriterFlags::empty()).map_err(|e| err("wgsl", e))
}

/// WGSL of the library with every texture and sampler a trailing argument of the functions
/// that read it, in binding order: three.js's node system declares the bindings itself, so a
/// `wgslFn` can only hand the library the textures it was given as arguments.
fn wgsl_args_text(lib: &Library) -> Result<String, CompileError> {
    let (module, info) = super::engines::resources_as_arguments(lib)?;
    wgsl::write_string(&module, &info, wgsl::WriterFlags::empty()).map_err(|e| err("tsl", e))
}

/// GLSL of the library: an include file for GLSL 450 (`es == false`) or GLSL ES 3.00 for
/// WebGL2 (`es == true`, whose uniforms carry no binding: WebGL binds them by name).
fn glsl_text(lib: &Library, opts: &LibraryOptions, es: bool) -> Result<String, CompileError> {
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

fn hlsl_text(lib: &Library) -> Result<String, CompileError> {
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
pub(crate) fn sample_level_zero(line: &str) -> String {
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

fn msl_text(lib: &Library) -> Result<String, CompileError> {
    let options = msl::Options { lang_version: (2, 0), force_loop_bounding: false, ..msl::Options::default() };
    let (text, _) = msl::write_string(&lib.module, &lib.info, &options, &msl::PipelineOptions::default())
        .map_err(|e| err("msl", e))?;
    Ok(text)
}

/// One form of a library: what `relief gen --library --target NAME` writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LibraryForm {
    /// `NAME.lib.wgsl`: WGSL to concatenate, or to import through `naga_oil` with
    /// [`LibraryOptions::import_path`].
    Wgsl,
    /// `NAME_ident.wesl` (the stem with `-` as `_`, a WESL module name): the same module as a
    /// WESL module to `import`.
    Wesl,
    /// `NAME.lib.glsl`: a GLSL 450 include file.
    Glsl,
    /// `NAME.lib.es.glsl`: GLSL ES 3.00 for WebGL2 (three.js, Babylon.js `ShaderMaterial`).
    /// ES 3.00 has no `textureGather`: each gather (the `form=safe` cone marches, maxmip's
    /// and the `sample=min4` reads) is four `texelFetch` reads at level 0 that apply
    /// [`LibraryOptions::edge_clamp`] to the texel coordinates themselves, since GLSL ES
    /// cannot see the sampler's address mode. Where the library addresses texels itself the
    /// file refuses to compile (`#error`) unless the user defines `PREFIX_EDGE_REPEAT` or
    /// `PREFIX_EDGE_CLAMP` (the prefix in capitals) to match the edge mode it was generated
    /// for.
    GlslEs,
    /// `NAME.tsl.wgsl`: WGSL with the resources as function arguments, for three.js's
    /// WebGPU renderer (TSL `wgsl` / `wgslFn`).
    Tsl,
    /// `NAME.lib.hlsl`: HLSL, shader model 5.1, resources at registers.
    Hlsl,
    /// `NAME.lib.metal`: MSL, resources as arguments.
    Msl,
    /// `NAME.unity.hlsl`: a Custom Function file for Unity's Shader Graph.
    Unity,
    /// `NAME.ush` and `NAME.custom.hlsl`: an include file and a Custom node's code for Unreal.
    Unreal,
}

impl LibraryForm {
    /// Every form, in the order of `--target`'s list.
    pub const ALL: [LibraryForm; 9] = [
        LibraryForm::Wgsl,
        LibraryForm::Wesl,
        LibraryForm::Glsl,
        LibraryForm::GlslEs,
        LibraryForm::Tsl,
        LibraryForm::Hlsl,
        LibraryForm::Msl,
        LibraryForm::Unity,
        LibraryForm::Unreal,
    ];
    /// The forms written when no `--target` is named.
    pub const DEFAULT: [LibraryForm; 4] = [LibraryForm::Wgsl, LibraryForm::Glsl, LibraryForm::Hlsl, LibraryForm::Msl];

    /// The name `--target` takes.
    pub fn name(self) -> &'static str {
        match self {
            LibraryForm::Wgsl => "wgsl",
            LibraryForm::Wesl => "wesl",
            LibraryForm::Glsl => "glsl",
            LibraryForm::GlslEs => "glsl-es",
            LibraryForm::Tsl => "tsl",
            LibraryForm::Hlsl => "hlsl",
            LibraryForm::Msl => "msl",
            LibraryForm::Unity => "unity",
            LibraryForm::Unreal => "unreal",
        }
    }

    /// The form named `name`; an unknown name is a one-line error with the valid names and the
    /// nearest one.
    pub fn from_name(name: &str) -> Result<LibraryForm, CompileError> {
        if let Some(f) = LibraryForm::ALL.into_iter().find(|f| f.name() == name) {
            return Ok(f);
        }
        let names: Vec<&str> = LibraryForm::ALL.iter().map(|f| f.name()).collect();
        let near = names
            .iter()
            .copied()
            .min_by_key(|n| strsim::levenshtein(n, name))
            .filter(|n| strsim::levenshtein(n, name) <= 2);
        Err(CompileError {
            stage: "library".into(),
            message: format!(
                "unknown target `{name}`; expected one of: {}{}",
                names.join(", "),
                near.map(|n| format!("; did you mean `{n}`?")).unwrap_or_default()
            ),
        })
    }

    /// The language whose limits the form is held to.
    pub fn target(self) -> super::limits::Target {
        use super::limits::Target;
        match self {
            LibraryForm::Wgsl | LibraryForm::Wesl | LibraryForm::Tsl => Target::Wgsl,
            LibraryForm::Glsl => Target::Glsl,
            LibraryForm::GlslEs => Target::GlslEs,
            LibraryForm::Hlsl | LibraryForm::Unity | LibraryForm::Unreal => Target::Hlsl,
            LibraryForm::Msl => Target::Msl,
        }
    }
}

/// One file of a library.
#[derive(Clone, Debug)]
pub struct LibraryFile {
    /// The form it belongs to.
    pub form: LibraryForm,
    /// Its file name (`NAME.lib.wgsl`).
    pub name: String,
    /// Its text.
    pub text: String,
}

/// The files of one pipeline's library in the forms asked for.
#[derive(Clone, Debug)]
pub struct LibraryForms {
    /// The files, in the order of the forms asked for.
    pub files: Vec<LibraryFile>,
    /// The resources, in binding order.
    pub bindings: Vec<LibraryBinding>,
    /// Whether `P_shadow` exists.
    pub has_shadow: bool,
    /// Whether `P_ao` exists.
    pub has_ao: bool,
}

impl LibraryForms {
    /// The text of the file `name`.
    pub fn text(&self, name: &str) -> Option<&str> {
        self.files.iter().find(|f| f.name == name).map(|f| f.text.as_str())
    }
}

/// Builds the library of `p` and writes it in the four default languages
/// ([`library_forms`] with [`LibraryForm::DEFAULT`]).
pub fn library(p: &Pipeline, opts: &LibraryOptions) -> Result<LibraryFiles, CompileError> {
    let forms = library_forms(p, opts, &LibraryForm::DEFAULT)?;
    let mut texts = forms.files.into_iter().map(|f| f.text);
    let mut next = || texts.next().unwrap_or_default();
    let (wgsl, glsl, hlsl, msl) = (next(), next(), next(), next());
    Ok(LibraryFiles {
        wgsl,
        glsl,
        hlsl,
        msl,
        bindings: forms.bindings,
        has_shadow: forms.has_shadow,
        has_ao: forms.has_ao,
    })
}

/// Builds the library of `p` and writes it in each of `forms`. The options are checked
/// against every form's language limits first ([`super::limits`]), and the names as written
/// against what was asked for, so a file that would not compile, or whose functions a writer
/// renamed, is an error instead.
pub fn library_forms(p: &Pipeline, opts: &LibraryOptions, forms: &[LibraryForm]) -> Result<LibraryForms, CompileError> {
    use super::limits::{self, Target};
    let targets: Vec<Target> = forms.iter().map(|f| f.target()).collect();
    limits::check_all(&targets, &opts.prefix, opts.group, opts.binding)?;
    let lib = crate::compose::library::compose_library(p, opts)?;
    let last = lib.bindings.last().map_or(opts.binding, |b| b.binding);
    limits::check_all(&targets, &opts.prefix, opts.group, last)?;
    check_name_lengths(&lib, &opts.prefix)?;
    let stem = p.file_stem();
    let mut files = Vec::new();
    for &form in forms {
        let mut add = |name: String, body: &str, text: String| -> Result<(), CompileError> {
            check_names_kept(&lib, &opts.prefix, form.target(), body)?;
            files.push(LibraryFile { form, name, text });
            Ok(())
        };
        match form {
            LibraryForm::Wgsl => {
                let body = wgsl_text(&lib)?;
                let mut text = String::new();
                if let Some(path) = &opts.import_path {
                    check_import_path(path)?;
                    let _ = writeln!(text, "#define_import_path {path}\n");
                }
                text += &header_lines(p, &lib, opts, Lang::Wgsl);
                text += &body;
                add(format!("{stem}.lib.wgsl"), &body, text)?;
            }
            LibraryForm::Wesl => {
                let body = wgsl_text(&lib)?;
                let module = wesl_module_name(&stem);
                let mut text = header_lines(p, &lib, opts, Lang::Wgsl);
                let _ = writeln!(text, "// As a WESL module: `import package::{module}::{{{pre}_trace, {camel}Hit}};` with this file at the\n// package's root.\n", pre = opts.prefix, camel = crate::compose::library::camel(&opts.prefix));
                text += &body;
                add(format!("{module}.wesl"), &body, text)?;
            }
            LibraryForm::Glsl => {
                let body = glsl_text(&lib, opts, false)?;
                add(format!("{stem}.lib.glsl"), &body, header_lines(p, &lib, opts, Lang::Glsl) + &body)?;
            }
            LibraryForm::GlslEs => {
                let body = glsl_es_text(&lib, opts)?;
                add(format!("{stem}.lib.es.glsl"), &body, header_lines(p, &lib, opts, Lang::GlslEs) + &body)?;
            }
            LibraryForm::Tsl => {
                let body = wgsl_args_text(&lib)?;
                add(format!("{stem}.tsl.wgsl"), &body, header_lines(p, &lib, opts, Lang::WgslArgs) + &body)?;
            }
            LibraryForm::Hlsl => {
                let body = hlsl_text(&lib)?;
                add(format!("{stem}.lib.hlsl"), &body, header_lines(p, &lib, opts, Lang::Hlsl) + &body)?;
            }
            LibraryForm::Msl => {
                let body = msl_text(&lib)?;
                add(format!("{stem}.lib.metal"), &body, header_lines(p, &lib, opts, Lang::Msl) + &body)?;
            }
            LibraryForm::Unity => {
                let text = super::engines::unity(p, &lib, opts)?;
                add(format!("{stem}.unity.hlsl"), &text, text.clone())?;
            }
            LibraryForm::Unreal => {
                let (include, node) = super::engines::unreal(p, &lib, opts)?;
                add(format!("{stem}.ush"), &include, include.clone())?;
                files.push(LibraryFile { form, name: format!("{stem}.custom.hlsl"), text: node });
            }
        }
    }
    Ok(LibraryForms { files, bindings: lib.bindings, has_shadow: lib.has_shadow, has_ao: lib.has_ao })
}

/// Why `p`'s library cannot be written in `form`, if it cannot (besides what no library can
/// express, [`crate::compose::library::inexpressible`]): the one-line error writing it gives.
/// Every form can write every such pipeline today (GLSL ES 3.00's missing `textureGather`
/// is lowered to `texelFetch`, see [`LibraryForm::GlslEs`]); a pipeline whose GLSL ES text still
/// needs what ES 3.00 lacks is refused here with the reason. `relief gen --all --library`
/// skips such a pipeline in that form.
pub fn inexpressible_in(p: &Pipeline, form: LibraryForm) -> Option<String> {
    if form != LibraryForm::GlslEs {
        return None;
    }
    let opts = LibraryOptions::default();
    let lib = crate::compose::library::compose_library(p, &opts).ok()?;
    glsl_es_text(&lib, &opts).err().map(|e| e.message)
}

/// The GLSL ES 3.00 form's body: naga's ES writer's text with each `textureGather` (which
/// ES 3.00 lacks: OpenGL ES 3.1 added it) replaced by `PREFIX_gather`, four `texelFetch`
/// reads at level 0 that apply the library's edge mode to the integer texel coordinates, and
/// an `#error` guard that makes the user state the samplers' edge mode where the library
/// addresses texels itself.
fn glsl_es_text(lib: &Library, opts: &LibraryOptions) -> Result<String, CompileError> {
    let pre = &opts.prefix;
    let refuse = |why: String| CompileError { stage: "library GLSL ES".into(), message: why };
    let body = glsl_text(lib, opts, true)?;
    let gathers = body.contains("textureGather(");
    let helper = format!("{pre}_gather");
    let edge_fn = format!("{pre}_texel_edge");
    if gathers && (has_word(&body, &helper) || has_word(&body, &edge_fn)) {
        return Err(refuse(format!(
            "the library already has a function `{helper}` or `{edge_fn}`, the names the GLSL ES form gives its gather"
        )));
    }
    let body = body.replace("textureGather(", &format!("{helper}("));
    for missing in ["textureGather", "textureQueryLevels", "textureQueryLod"] {
        if has_word(&body, missing) || body.contains(&format!("{missing}Offset")) {
            return Err(refuse(format!(
                "GLSL ES 3.00 (WebGL2) has no {missing}, which a stage of this pipeline uses: not expressible as glsl-es"
            )));
        }
    }
    let edge_const = format!("{pre}_edge_clamp");
    let decl = format!("const bool {edge_const} = ");
    // The edge mode matters where the text reads the constant, not only declares it.
    let edge_matters = gathers || body.matches(edge_const.as_str()).count() > 1;
    let mut text = String::new();
    if edge_matters {
        let up = pre.to_ascii_uppercase();
        let (mine, other, wrap, flag) = if opts.edge_clamp {
            ("CLAMP", "REPEAT", "CLAMP_TO_EDGE (three.js ClampToEdgeWrapping)", "--edge repeat")
        } else {
            ("REPEAT", "CLAMP", "REPEAT (three.js RepeatWrapping)", "--edge clamp")
        };
        let _ = writeln!(
            text,
            "// This library addresses texels itself assuming samplers that wrap with {wrap}.\n\
             // Say that yours do: `#define {up}_EDGE_{mine}` before this file (three.js: `defines`).\n\
             #if !defined({up}_EDGE_{mine}) || defined({up}_EDGE_{other})\n\
             #error relief library: generated for {mine} edges; define {up}_EDGE_{mine} and bind {mine} samplers, or generate with {flag}\n\
             #endif"
        );
    }
    let mut placed = !gathers;
    for line in body.lines() {
        text.push_str(line);
        text.push('\n');
        if !placed && line.starts_with(&decl) {
            text += &gather_helpers(pre);
            placed = true;
        }
    }
    if !placed {
        return Err(refuse(format!("no `{decl}…` line to put the gather after in naga's GLSL ES text")));
    }
    Ok(text)
}

/// GLSL ES 3.00 functions standing in for `textureGather(s, uv, comp)`: the four texels a
/// bilinear sample at `uv` blends, at level 0, with `(i0, j0) = floor(uv · size − ½)` and
/// `(i1, j1) = (i0, j0) + 1`, in gather order `(i0, j1), (i1, j1), (i1, j0), (i0, j0)`
/// (the GLSL and WGSL specifications' order), each coordinate wrapped (repeat: Euclidean
/// modulo) or clamped to `[0, size − 1]` by the library's edge constant, as a sampler
/// applies its address mode to a gather's texel coordinates. Euclidean modulo without `%`,
/// which ES 3.00 leaves undefined for negative operands.
fn gather_helpers(pre: &str) -> String {
    format!(
        "// GLSL ES 3.00 has no textureGather: {pre}_gather reads its four texels with texelFetch.
ivec2 {pre}_texel_edge(ivec2 i, ivec2 size) {{
    if ({pre}_edge_clamp) {{
        return clamp(i, ivec2(0), size - 1);
    }}
    ivec2 r = i - size * ivec2(floor(vec2(i) / vec2(size)));
    r += size * ivec2(lessThan(r, ivec2(0)));
    r -= size * ivec2(greaterThanEqual(r, size));
    return r;
}}
float {pre}_gather_pick(vec4 t, int comp) {{
    return comp == 0 ? t.x : (comp == 1 ? t.y : (comp == 2 ? t.z : t.w));
}}
vec4 {pre}_gather(highp sampler2D s, vec2 uv, int comp) {{
    ivec2 size = textureSize(s, 0);
    ivec2 lo = ivec2(floor(uv * vec2(size) - 0.5));
    ivec2 i0 = {pre}_texel_edge(lo, size);
    ivec2 i1 = {pre}_texel_edge(lo + 1, size);
    return vec4(
        {pre}_gather_pick(texelFetch(s, ivec2(i0.x, i1.y), 0), comp),
        {pre}_gather_pick(texelFetch(s, ivec2(i1.x, i1.y), 0), comp),
        {pre}_gather_pick(texelFetch(s, ivec2(i1.x, i0.y), 0), comp),
        {pre}_gather_pick(texelFetch(s, ivec2(i0.x, i0.y), 0), comp));
}}
vec4 {pre}_gather(highp sampler2D s, vec2 uv) {{
    return {pre}_gather(s, uv, 0);
}}
"
    )
}

/// The WESL module name of a pipeline's file stem: WESL names modules by identifiers, so
/// `-` becomes `_` (`linear_10__binary_5__shadow-soft_30` → `linear_10__binary_5__shadow_soft_30`).
pub fn wesl_module_name(stem: &str) -> String {
    stem.replace('-', "_")
}

fn check_import_path(path: &str) -> Result<(), CompileError> {
    let ok = path.split("::").all(|seg| {
        seg.chars().next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
            && seg.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
    });
    if ok {
        Ok(())
    } else {
        Err(err("wgsl", format!("import path `{path}` is not `::`-separated identifiers")))
    }
}

/// The module's names may add at most [`super::limits::LONGEST_SUFFIX`] characters to the
/// prefix (what the limits assumed when they checked the prefix's length).
fn check_name_lengths(lib: &Library, prefix: &str) -> Result<(), CompileError> {
    let m = &lib.module;
    let names = m
        .functions
        .iter()
        .filter_map(|(_, f)| f.name.as_deref())
        .chain(m.global_variables.iter().filter_map(|(_, g)| g.name.as_deref()))
        .chain(m.types.iter().filter_map(|(_, t)| t.name.as_deref()))
        .chain(m.constants.iter().filter_map(|(_, c)| c.name.as_deref()));
    let longest = names.max_by_key(|n| n.chars().count()).unwrap_or("");
    let extra = longest.chars().count().saturating_sub(prefix.chars().count());
    if extra > super::limits::LONGEST_SUFFIX {
        return Err(CompileError {
            stage: "library".into(),
            message: format!(
                "the name `{longest}` adds {extra} characters to the prefix, more than the {} the languages' name limits allow for",
                super::limits::LONGEST_SUFFIX
            ),
        });
    }
    Ok(())
}

/// Whether `name` occurs in `text` as a whole identifier.
fn has_word(text: &str, name: &str) -> bool {
    let ident = |c: char| c.is_ascii_alphanumeric() || c == '_';
    text.match_indices(name).any(|(i, _)| {
        let before = text[..i].chars().next_back();
        let after = text[i + name.len()..].chars().next();
        !before.is_some_and(ident) && !after.is_some_and(ident)
    })
}

/// The public functions, the hit type and the resources came out of `target`'s writer with
/// the names asked for: a writer renames a name its language reserves (naga prepends `gen_`
/// or appends `_`), which would leave the user calling a function that does not exist.
fn check_names_kept(
    lib: &Library,
    prefix: &str,
    target: super::limits::Target,
    body: &str,
) -> Result<(), CompileError> {
    let mut names = vec![format!("{prefix}_trace"), format!("{}Hit", crate::compose::library::camel(prefix))];
    if lib.has_shadow {
        names.push(format!("{prefix}_shadow"));
    }
    if lib.has_ao {
        names.push(format!("{prefix}_ao"));
    }
    // GLSL keeps no sampler (a texture is combined with its sampler).
    let glsl = matches!(target, super::limits::Target::Glsl | super::limits::Target::GlslEs);
    names.extend(lib.bindings.iter().filter(|b| !(glsl && b.kind == ResourceKind::Sampler)).map(|b| b.name.clone()));
    match names.iter().find(|n| !has_word(body, n)) {
        None => Ok(()),
        Some(n) => Err(CompileError {
            stage: format!("library {}", target.name()),
            message: format!(
                "prefix `{prefix}`: the {} writer renamed `{n}` (a name the language reserves); choose another prefix",
                target.name()
            ),
        }),
    }
}
