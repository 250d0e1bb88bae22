//! The mesh forms (`curved=none|quadric|prism`, docs/meshes-shaders.md): the mesh module's
//! SPIR-V passes `spirv-val` and its GLSL (vertex, fragment, depth-only) `glslangValidator`;
//! the library's WGSL (naga), GLSL ES (glslang's ES profile) and HLSL (glslang's HLSL front
//! end, then spirv-val) compile inside a user shader that feeds the per-vertex inputs the
//! header lists and discards where `covered` is 0.

use std::process::Command;

use crate::common::{run, tool};

use relief::dsl::emit::{self, LibraryForm, LibraryOptions};
use relief::Pipeline;

/// One pipeline per coarse family with refine, shadow and ao stages, under each mode.
fn pipelines() -> Vec<Pipeline> {
    let bases = [
        "linear(32)+binary(5)+shadow=soft(16)",
        "parallax",
        "csm(15)+binary(5)+ao=cone_ratio",
        "rcs(15, form=textbook)+secant(3)+shadow=hard(16)",
        "maxmip(32)+interval(2)",
        "sphere(20)",
    ];
    let mut all = Vec::new();
    for base in bases {
        for mode in ["none", "quadric", "prism"] {
            let text = format!("{base}+curved={mode}");
            all.push(text.parse().unwrap_or_else(|e| panic!("{text}: {e}")));
        }
    }
    all
}

#[test]
fn mesh_modules_pass_spirv_val_and_glslang() {
    let spirv_val = tool("spirv-val");
    let glslang = tool("glslangValidator");
    let dir = std::env::temp_dir().join(format!("relief-mesh-khronos-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for p in pipelines() {
        let out = emit::emit(&p).unwrap_or_else(|e| panic!("{p}: {e}"));
        let stem = p.file_stem();
        let spv = dir.join(format!("{stem}.spv"));
        std::fs::write(&spv, out.spirv.iter().flat_map(|w| w.to_le_bytes()).collect::<Vec<u8>>()).unwrap();
        run(Command::new(spirv_val).args(["--target-env", "vulkan1.1"]).arg(&spv), &format!("spirv-val on {p}"));
        let suffixes: Vec<&str> = out.glsl.iter().map(|(s, _)| *s).collect();
        assert_eq!(suffixes, ["vert", "frag", "depth.frag"], "{p}");
        for (suffix, src) in &out.glsl {
            let file = dir.join(format!("{stem}.{suffix}.glsl"));
            std::fs::write(&file, src).unwrap();
            let stage = suffix.rsplit('.').next().unwrap();
            let gl = file.with_extension("glsl.spv");
            run(
                Command::new(glslang).args(["-G", "-S", stage, "-o"]).arg(&gl).arg(&file),
                &format!("glslangValidator on {p} ({suffix})"),
            );
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// The arguments of `relief_trace` after the first, in a language whose 2-, 3- and
/// 4-vectors are `v2`, `v3`, `v4`, from the user shader's inputs `n`, `t`, `s` (uv scale) and
/// `view`, and constants for the mode's own (the curvature, or the prism's corner uvs, points
/// and normals).
fn trace_call(p: &Pipeline, [v2, v3, v4]: [&str; 3], first: &str) -> String {
    let curved = p.curved.expect("a mesh pipeline").to_string();
    let own = match curved.as_str() {
        "none" => String::new(),
        "quadric" => format!("{v2}(-0.2, -0.1), "),
        // The corner uvs, the fragment's point, the corners' points and normals.
        _ => format!(
            "{v4}(0.0, 0.0, 1.0, 0.0), {v2}(0.0, 1.0), view, {v3}(0.0, 0.0, 0.0), {v3}(1.0, 0.0, 0.0), \
             {v3}(0.0, 1.0, 0.0), n, n, {v3}(0.0, 0.0, 1.0), "
        ),
    };
    format!("relief_trace({first}, normalize(view), normalize(n), t, s, {own}0.08)")
}

fn shadow_call(v3: &str) -> String {
    format!("relief_shadow(hit, normalize({v3}(0.3, 0.2, 0.9)), normalize(n), t, s, 0.08)")
}

#[test]
fn mesh_libraries_compile_in_wgsl_glsl_es_and_hlsl() {
    let glslang = tool("glslangValidator");
    let spirv_val = tool("spirv-val");
    let dir = std::env::temp_dir().join(format!("relief-mesh-library-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let forms = [LibraryForm::Wgsl, LibraryForm::GlslEs, LibraryForm::Hlsl];
    for p in pipelines() {
        let lib = emit::library_forms(&p, &LibraryOptions::default(), &forms).unwrap_or_else(|e| panic!("{p}: {e}"));
        let text = |suffix: &str| lib.files.iter().find(|f| f.name.ends_with(suffix)).map(|f| f.text.as_str()).unwrap();
        let prism = p.curved.unwrap().to_string() == "prism";
        for suffix in [".lib.wgsl", ".lib.es.glsl", ".lib.hlsl"] {
            let t = text(suffix);
            assert!(t.contains("covered: f32") && t.contains("uv_scale = texture units per object unit"), "{p}");
            assert_eq!(t.contains("prism_a = the triangle's"), prism, "{p}");
        }
        let stem = p.file_stem();
        // WGSL.
        let first = if prism { "vec3<f32>(uv, 0.5)" } else { "uv" };
        let mut s = text(".lib.wgsl").to_string();
        s += "@fragment fn user_main(@location(0) uv: vec2<f32>, @location(1) view: vec3<f32>, @location(2) n: vec3<f32>, @location(3) t: vec4<f32>, @location(4) s: vec2<f32>) -> @location(0) vec4<f32> {\n";
        s += &format!(
            "    let hit = {};\n    if hit.covered == 0.0 {{ discard; }}\n    var shade = 1.0;\n",
            trace_call(&p, ["vec2<f32>", "vec3<f32>", "vec4<f32>"], first)
        );
        if lib.has_shadow {
            s += &format!("    shade *= {};\n", shadow_call("vec3<f32>"));
        }
        if lib.has_ao {
            s += "    shade *= relief_ao(hit);\n";
        }
        s += "    return vec4(hit.uv, hit.height + hit.t + hit.depth_offset, shade);\n}\n";
        let module = naga::front::wgsl::parse_str(&s).unwrap_or_else(|e| panic!("{p}: {}", e.emit_to_string(&s)));
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::default())
            .validate(&module)
            .unwrap_or_else(|e| panic!("{p}: {e:?}"));
        // GLSL ES 3.00.
        let first = if prism { "vec3(uv, 0.5)" } else { "uv" };
        let mut s =
            String::from("#version 300 es\nprecision highp float;\nprecision highp int;\n#define RELIEF_EDGE_REPEAT\n");
        s += text(".lib.es.glsl");
        s += "in vec2 uv;\nin vec3 view;\nin vec3 n;\nin vec4 t;\nin vec2 s;\nout vec4 o_color;\n";
        s += &format!(
            "void main() {{\n    ReliefHit hit = {};\n    if (hit.covered == 0.0) discard;\n    float shade = 1.0;\n",
            trace_call(&p, ["vec2", "vec3", "vec4"], first)
        );
        if lib.has_shadow {
            s += &format!("    shade *= {};\n", shadow_call("vec3"));
        }
        if lib.has_ao {
            s += "    shade *= relief_ao(hit);\n";
        }
        s += "    o_color = vec4(hit.uv, hit.height + hit.t + hit.depth_offset, shade);\n}\n";
        let frag = dir.join(format!("{stem}.es.frag"));
        std::fs::write(&frag, s).unwrap();
        run(Command::new(glslang).args(["-S", "frag"]).arg(&frag), &format!("glslangValidator (ES) on {p}"));
        // HLSL.
        let first = if prism { "float3(i.uv, 0.5)" } else { "i.uv" };
        let mut s = text(".lib.hlsl").to_string();
        s += "struct UserIn { float4 pos : SV_Position; float2 uv : TEXCOORD0; float3 view : TEXCOORD1; float3 n : TEXCOORD2; float4 t : TEXCOORD3; float2 s : TEXCOORD4; };\n";
        s += "float4 user_main(UserIn i) : SV_Target {\n    float3 view = i.view; float3 n = i.n; float4 t = i.t; float2 s = i.s;\n";
        s += &format!(
            "    ReliefHit hit = {};\n    if (hit.covered == 0.0) discard;\n    float shade = 1.0;\n",
            trace_call(&p, ["float2", "float3", "float4"], first)
        );
        if lib.has_shadow {
            s += &format!("    shade *= {};\n", shadow_call("float3"));
        }
        if lib.has_ao {
            s += "    shade *= relief_ao(hit);\n";
        }
        s += "    return float4(hit.uv, hit.height + hit.t + hit.depth_offset, shade);\n}\n";
        let file = dir.join(format!("{stem}.hlsl"));
        std::fs::write(&file, s).unwrap();
        let spv = dir.join(format!("{stem}.hlsl.spv"));
        run(
            Command::new(glslang).args(["-D", "-V", "-S", "frag", "-e", "user_main", "-o"]).arg(&spv).arg(&file),
            &format!("glslangValidator -D on the HLSL library of {p}"),
        );
        run(
            Command::new(spirv_val).args(["--target-env", "vulkan1.0"]).arg(&spv),
            &format!("spirv-val on the HLSL of {p}"),
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn mesh_libraries_refuse_the_node_forms_in_one_line() {
    let p: Pipeline = "linear(16)+curved=prism".parse().unwrap();
    for form in [LibraryForm::Tsl, LibraryForm::Unity, LibraryForm::Unreal] {
        let e = emit::library_forms(&p, &LibraryOptions::default(), &[form]).err().unwrap().to_string();
        assert!(e.contains("curved=prism") && e.contains(form.name()) && !e.contains('\n'), "{e}");
        assert!(emit::inexpressible_in(&p, form).is_some());
    }
}
