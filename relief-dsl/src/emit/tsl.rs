//! The three.js TSL form (`NAME.tsl.wgsl`): WGSL with every texture and sampler a trailing
//! argument of the functions that read it, in binding order. three.js's node system declares
//! the bindings itself, so a `wgslFn` can only hand the library the textures it was given as
//! arguments.
//!
//! three.js's `WebGPURenderer` binds no sampler for a texture whose min and mag filters are
//! both nearest (it declares the texture unfilterable), so this form reads the
//! nearest-filtered textures (`*_nearest`) with `textureLoad` at the nearest texel and takes
//! no nearest sampler: the user binds a plain `NearestFilter` texture.

use std::fmt::Write as _;

use naga::back::wgsl;

use super::common::{
    err, has_word, header_lines, resources_as_arguments, wgsl_type, Header, ResourceArguments, Written,
};
use crate::compose::library::{Library, LibraryOptions};
use crate::ir::{Filter, Resource};
use crate::spec::Pipeline;
use crate::CompileError;

const HEADER: Header = Header {
    arguments: ResourceArguments::BindingOrder,
    intro: "// three.js TSL (`wgsl(this)` as an include of your `wgslFn`): no resource is global; each function\n\
            // above takes those it reads as extra arguments after its own, in the order listed (the group and\n\
            // binding numbers are for the other forms; TSL binds what you pass). The `_nearest` textures are\n\
            // read texel by texel (`textureLoad`): give them NearestFilter; no nearest sampler is taken:\n",
    resource_type: wgsl_type,
    by_name: false,
    no_nearest_sampler: true,
};

/// `NAME.tsl.wgsl`.
pub(crate) fn write(p: &Pipeline, lib: &Library, opts: &LibraryOptions) -> Result<Vec<Written>, CompileError> {
    let (module, info) = resources_as_arguments(lib)?;
    let body = wgsl::write_string(&module, &info, wgsl::WriterFlags::empty()).map_err(|e| err("tsl", e))?;
    let body = nearest_reads_as_loads(lib, opts, body)?;
    let text = header_lines(p, lib, opts, &HEADER) + &body;
    Ok(vec![Written { name: format!("{}.tsl.wgsl", p.file_stem()), text, code: Some(body) }])
}

/// The WGSL writer's text with every read through the nearest sampler,
/// `textureSampleLevel(T, S, uv, level)`, written `P_texel_nearest(T, uv, level)` (one
/// `textureLoad` of the texel a nearest sample takes, [`texel_nearest`]), and the nearest
/// sampler `S` dropped from the functions' parameters and calls. naga names it
/// `P_sampler_nearest` or, in later functions, `P_sampler_nearest_N`; it is a trailing
/// argument after a function's own ([`resources_as_arguments`]), so it always follows `, `.
/// Any use left over is an error rather than a library that asks for a sampler three.js
/// cannot give.
fn nearest_reads_as_loads(lib: &Library, opts: &LibraryOptions, body: String) -> Result<String, CompileError> {
    let Some(smp) = lib.bindings.iter().find(|b| b.resource == Resource::Sampler(Filter::Nearest)).map(|b| &b.name)
    else {
        return Ok(body);
    };
    let helper = format!("{}_texel_nearest", opts.prefix);
    if has_word(&body, &helper) {
        return Err(err("tsl", format!("the library already has a function `{helper}`, the name of its texel read")));
    }
    let ours = |id: &str| {
        id.strip_prefix(smp.as_str()).is_some_and(|rest| {
            rest.is_empty()
                || rest.strip_prefix('_').is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
        })
    };
    let ident_len = |t: &str| t.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(t.len());
    // The reads: `textureSampleLevel(T, S, ` → `P_texel_nearest(T, `.
    let mut out = String::with_capacity(body.len());
    let mut rest = body.as_str();
    const SAMPLE: &str = "textureSampleLevel(";
    while let Some(i) = rest.find(SAMPLE) {
        out.push_str(&rest[..i]);
        let args = &rest[i + SAMPLE.len()..];
        let t = ident_len(args);
        let s = args[t..].strip_prefix(", ").map(ident_len).unwrap_or(0);
        if s > 0 && ours(&args[t + 2..t + 2 + s]) && args[t + 2 + s..].starts_with(", ") {
            let _ = write!(out, "{helper}({}", &args[..t]);
            rest = &args[t + 2 + s..];
        } else {
            out.push_str(SAMPLE);
            rest = args;
        }
    }
    out.push_str(rest);
    // The parameters `, S: sampler` and the arguments `, S` passed on.
    let text = out;
    let mut out = String::with_capacity(text.len());
    let mut rest = text.as_str();
    while let Some(i) = rest.find(", ") {
        let after = &rest[i + 2..];
        let n = ident_len(after);
        if n > 0 && ours(&after[..n]) {
            out.push_str(&rest[..i]);
            let tail = &after[n..];
            rest = tail.strip_prefix(": sampler").unwrap_or(tail);
        } else {
            out.push_str(&rest[..i + 2]);
            rest = after;
        }
    }
    out.push_str(rest);
    if out.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).any(ours) {
        return Err(err("tsl", format!("`{smp}` is used other than by a nearest read: no texel-load form")));
    }
    Ok(out + &texel_nearest(&helper, opts.edge_clamp))
}

/// `NAME(t, uv, level)`: the texel a nearest sample of `t` at `uv` on `level` takes, read
/// with `textureLoad`. Its coordinates are `floor(uv · size)`, addressed as the sampler
/// would: clamped to `[0, size − 1]` or wrapped (Euclidean modulo, exact in integers:
/// WGSL's `%` keeps the dividend's sign), by the library's edge mode, since a texel load
/// ignores the address mode.
fn texel_nearest(name: &str, clamp: bool) -> String {
    let edge = if clamp { "clamp(i, vec2<i32>(0), size - vec2<i32>(1))" } else { "((i % size) + size) % size" };
    format!(
        "
// The texel a nearest sample of `t` at `uv` on `level` reads, addressed with the library's
// edge mode ({mode}): three.js binds no sampler for a NearestFilter texture.
fn {name}(t: texture_2d<f32>, uv: vec2<f32>, level: f32) -> vec4<f32> {{
    let l = i32(level);
    let size = vec2<i32>(textureDimensions(t, l));
    let i = vec2<i32>(floor(uv * vec2<f32>(size)));
    return textureLoad(t, {edge}, l);
}}
",
        mode = if clamp { "clamp to edge" } else { "repeat" }
    )
}
