//! The Unity form (`NAME.unity.hlsl`): a Custom Function file for Unity's Shader Graph (File
//! mode). Shader Graph hands a Custom Function its textures as `UnityTexture2D` /
//! `UnitySamplerState` arguments, so the file starts from the HLSL of the module with its
//! resources as arguments ([`super::hlsl::with_arguments`]) and adds `void P_float(...)` and
//! `void P_half(...)` (`P` the prefix in CamelCase, so the node's Name is `P`), taking the
//! uv, the view and light directions, the depth scale and one `UnityTexture2D` /
//! `UnitySamplerState` per resource, with `out` values for the hit uv, height and pixel depth
//! offset (and shadow and ao when the pipeline has them).

use std::fmt::Write as _;

use super::common::{include_guard, input_name, reads, Written};
use super::hlsl;
use crate::compose::library::{camel, Library, LibraryOptions, ResourceKind};
use crate::spec::Pipeline;
use crate::CompileError;

/// `NAME.unity.hlsl`.
pub(crate) fn write(p: &Pipeline, lib: &Library, opts: &LibraryOptions) -> Result<Vec<Written>, CompileError> {
    let text = text(p, lib, opts)?;
    Ok(vec![Written { name: format!("{}.unity.hlsl", p.file_stem()), code: Some(text.clone()), text }])
}

/// `NAME.unity.hlsl`: the Custom Function file for Unity's Shader Graph (File mode).
fn text(p: &Pipeline, lib: &Library, opts: &LibraryOptions) -> Result<String, CompileError> {
    let pre = &opts.prefix;
    let node = camel(pre);
    let body = hlsl::with_arguments(lib)?;
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
