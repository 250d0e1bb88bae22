//! The GLSL ES 3.00 form for WebGL2 (`NAME.lib.es.glsl`): the GLSL writer's ES text, with
//! the resources as sampler uniforms bound by name and `textureGather`, which ES 3.00 lacks,
//! written with `texelFetch` (see [`LibraryForm::GlslEs`](super::LibraryForm::GlslEs)).

use std::fmt::Write as _;

use super::common::{has_word, header_lines, Header, ResourceArguments, Written};
use super::glsl;
use crate::compose::library::{Library, LibraryOptions};
use crate::spec::Pipeline;
use crate::CompileError;

const HEADER: Header = Header {
    arguments: ResourceArguments::Global,
    intro:
        "// GLSL ES 3.00 (WebGL2): put after the ES 3.00 version line (three.js and Babylon.js add it). Resources:\n\
            // sampler uniforms, bound by name (ES 3.00 has no binding qualifiers); a texture takes the\n\
            // sampler's filtering from the application; the samplers below have no uniform in GLSL ES:\n",
    resource_type: glsl::glsl_type,
    by_name: true,
    no_nearest_sampler: false,
};

/// `NAME.lib.es.glsl`.
pub(crate) fn write(p: &Pipeline, lib: &Library, opts: &LibraryOptions) -> Result<Vec<Written>, CompileError> {
    let body = body(lib, opts)?;
    let text = header_lines(p, lib, opts, &HEADER) + &body;
    Ok(vec![Written { name: format!("{}.lib.es.glsl", p.file_stem()), text, code: Some(body) }])
}

/// The GLSL ES 3.00 form's body: naga's ES writer's text with each `textureGather` (which
/// ES 3.00 lacks: OpenGL ES 3.1 added it) replaced by `PREFIX_gather`, four `texelFetch`
/// reads at level 0 that apply the library's edge mode to the integer texel coordinates, and
/// an `#error` guard that makes the user state the samplers' edge mode where the library
/// addresses texels itself.
pub(crate) fn body(lib: &Library, opts: &LibraryOptions) -> Result<String, CompileError> {
    let pre = &opts.prefix;
    let refuse = |why: String| CompileError { stage: "library GLSL ES".into(), message: why };
    let body = glsl::body(lib, opts, true)?;
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
