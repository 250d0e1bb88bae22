//! The library output (`relief gen --library`): each file, wrapped in a small user shader
//! whose own entry point calls `relief_trace` (and shadow, ao), passes the real validators:
//! GLSL through `glslangValidator` (Vulkan and OpenGL SPIR-V), HLSL through glslang's HLSL
//! front end (`glslangValidator -D`), the SPIR-V of both through `spirv-val`; the WGSL is
//! included textually into a user module that naga parses and validates. MSL has no
//! validator on this machine: the module is validated by naga before it is written.

use std::path::Path;
use std::process::Command;

use crate::common::{run, tool};

use relief::dsl::emit::{self, LibraryFiles, LibraryOptions, ResourceKind};
use relief::Pipeline;

fn camel(prefix: &str) -> String {
    prefix.split('_').map(|w| w[..1].to_uppercase() + &w[1..]).collect()
}

const DEPTH: &str = "0.08";

/// The body of a user's fragment shader: trace, then shadow and ao when present, and use
/// every field of the hit.
fn wgsl_user(lib: &LibraryFiles, prefix: &str, entry: &str) -> String {
    let hit = format!("{}Hit", camel(prefix));
    let mut s = format!(
        "@fragment fn {entry}(@location(0) uv: vec2<f32>, @location(1) view: vec3<f32>) -> @location(0) vec4<f32> {{\n\
         let hit: {hit} = {prefix}_trace(uv, normalize(view), {DEPTH});\n    var shade = 1.0;\n"
    );
    if lib.has_shadow {
        s += &format!("    shade *= {prefix}_shadow(hit, normalize(vec3(0.3, 0.2, 0.9)), {DEPTH});\n");
    }
    if lib.has_ao {
        s += &format!("    shade *= {prefix}_ao(hit);\n");
    }
    s += "    return vec4(hit.uv, hit.height + hit.t + hit.depth_offset, shade);\n}\n";
    s
}

fn glsl_user(lib: &LibraryFiles) -> String {
    let mut s = String::from("#version 450\n");
    s += &lib.glsl;
    s += "layout(location = 0) in vec2 v_uv;\nlayout(location = 1) in vec3 v_view;\nlayout(location = 0) out vec4 o_color;\n";
    s += &format!(
        "void main() {{\n    ReliefHit hit = relief_trace(v_uv, normalize(v_view), {DEPTH});\n    float shade = 1.0;\n"
    );
    if lib.has_shadow {
        s += &format!("    shade *= relief_shadow(hit, normalize(vec3(0.3, 0.2, 0.9)), {DEPTH});\n");
    }
    if lib.has_ao {
        s += "    shade *= relief_ao(hit);\n";
    }
    s += "    o_color = vec4(hit.uv, hit.height + hit.t + hit.depth_offset, shade);\n}\n";
    s
}

fn hlsl_user(lib: &LibraryFiles) -> String {
    let mut s = lib.hlsl.clone();
    s += "struct UserIn { float4 pos : SV_Position; float2 uv : TEXCOORD0; float3 view : TEXCOORD1; };\n";
    s += &format!(
        "float4 user_main(UserIn i) : SV_Target {{\n    ReliefHit hit = relief_trace(i.uv, normalize(i.view), {DEPTH});\n    float shade = 1.0;\n"
    );
    if lib.has_shadow {
        s += &format!("    shade *= relief_shadow(hit, normalize(float3(0.3, 0.2, 0.9)), {DEPTH});\n");
    }
    if lib.has_ao {
        s += "    shade *= relief_ao(hit);\n";
    }
    s += "    return float4(hit.uv, hit.height + hit.t + hit.depth_offset, shade);\n}\n";
    s
}

/// Parses and validates a WGSL user module with naga.
fn naga_wgsl(src: &str, what: &str) -> naga::Module {
    let module =
        naga::front::wgsl::parse_str(src).unwrap_or_else(|e| panic!("{what}: {}\n{src}", e.emit_to_string(src)));
    naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::default())
        .validate(&module)
        .unwrap_or_else(|e| panic!("{what}: {e:?}"));
    module
}

fn pipelines() -> Vec<Pipeline> {
    // Every fifth default combination (every coarse stage at least once) and the stages the
    // defaults leave out: each ao stage, nested shadow searches, the 3D distance field,
    // nearest and gathered cone reads.
    // `linear_distance` needs the camera distance, which the library interface does not take
    // (its library is an error: `linear_distance_has_no_library`).
    let mut all: Vec<Pipeline> =
        Pipeline::all_defaults().into_iter().filter(|p| p.coarse.name != "linear_distance").step_by(5).collect();
    for extra in [
        "rcs(15)+binary(5)+ao=cone_normal",
        "csm(15)+binary(4)+ao=cone_ratio",
        "linear(16)+shadow=hard(csm(15, form=textbook, sample=min4))",
        "cns(10)+shadow=hard(rcs(8, start=bracket))+ao=cone_ratio",
        "mcns(10, 2)+interval(2)+shadow=hard(pcns(6, 3))",
        "sphere(20)+secant(3)+shadow=hard(sphere(10))",
        "qcsm(12)+shadow=hard(qcsm(12))",
        "maxmip(32)+binary(4)+shadow=soft_cone(10)",
    ] {
        all.push(extra.parse().unwrap_or_else(|e| panic!("{extra}: {e}")));
    }
    all
}

#[test]
fn every_library_validates_in_wgsl_glsl_hlsl_and_spirv_val() {
    let glslang = tool("glslangValidator");
    let spirv_val = tool("spirv-val");
    let dir = std::env::temp_dir().join(format!("relief-library-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let all = pipelines();
    let chunks: Vec<&[Pipeline]> = all.chunks(all.len().div_ceil(2)).collect();
    std::thread::scope(|scope| {
        for chunk in chunks {
            let dir = &dir;
            scope.spawn(move || {
                for p in chunk {
                    check_one(p, dir, glslang, spirv_val);
                }
            });
        }
    });
    std::fs::remove_dir_all(&dir).ok();
}

fn check_one(p: &Pipeline, dir: &Path, glslang: &str, spirv_val: &str) {
    let opts = LibraryOptions { group: 2, binding: 5, ..LibraryOptions::default() };
    let lib = emit::library(p, &opts).unwrap_or_else(|e| panic!("{p}: {e}"));
    let stem = p.file_stem();

    // WGSL: included into a user module, parsed and validated by naga.
    let src = format!("{}\n{}", lib.wgsl, wgsl_user(&lib, "relief", "user_main"));
    let module = naga_wgsl(&src, &format!("WGSL library of {p}"));
    // The resources are the header's list: group 2, consecutive bindings from 5, each once.
    let mut found: Vec<(u32, String)> = module
        .global_variables
        .iter()
        .filter_map(|(_, g)| {
            g.binding.map(|rb| {
                assert_eq!(rb.group, 2, "{p}: {:?} in group {}", g.name, rb.group);
                (rb.binding, g.name.clone().unwrap())
            })
        })
        .collect();
    found.sort();
    let expect: Vec<(u32, String)> = (5..).zip(lib.bindings.iter().map(|b| b.name.clone())).collect();
    assert_eq!(found, expect, "{p}: bindings consecutive from 5 in the header's order");
    for b in &lib.bindings {
        assert!(
            lib.wgsl.contains(&format!("//   group 2 binding {}: {} ", b.binding, b.name)),
            "{p}: header lists {}",
            b.name
        );
    }
    // Nothing of relief's own module is left: no entry points, Params, probe buffers.
    for gone in ["params", "rays", "hits", "@vertex", "@compute", "fs_main", "_counted"] {
        assert!(!lib.wgsl.contains(gone), "{p}: the library still holds `{gone}`");
    }

    // GLSL: after a #version, compiled for Vulkan (set + binding) and for OpenGL.
    let file = dir.join(format!("{stem}.frag"));
    std::fs::write(&file, glsl_user(&lib)).unwrap();
    let spv = dir.join(format!("{stem}.glsl.spv"));
    run(
        Command::new(glslang).args(["-V", "-S", "frag", "-o"]).arg(&spv).arg(&file),
        &format!("glslangValidator -V on the GLSL library of {p}"),
    );
    run(
        Command::new(spirv_val).args(["--target-env", "vulkan1.0"]).arg(&spv),
        &format!("spirv-val on the GLSL library of {p}"),
    );
    let gl = dir.join(format!("{stem}.gl.spv"));
    run(
        Command::new(glslang).args(["-G", "-S", "frag", "-o"]).arg(&gl).arg(&file),
        &format!("glslangValidator -G on the GLSL library of {p}"),
    );

    // HLSL: glslang's HLSL front end, then spirv-val.
    let file = dir.join(format!("{stem}.hlsl"));
    std::fs::write(&file, hlsl_user(&lib)).unwrap();
    let spv = dir.join(format!("{stem}.hlsl.spv"));
    run(
        Command::new(glslang).args(["-D", "-V", "-S", "frag", "-e", "user_main", "-o"]).arg(&spv).arg(&file),
        &format!("glslangValidator -D on the HLSL library of {p}"),
    );
    run(
        Command::new(spirv_val).args(["--target-env", "vulkan1.0"]).arg(&spv),
        &format!("spirv-val on the HLSL library of {p}"),
    );

    // MSL: written (naga validated the module first) with the public functions.
    assert!(lib.msl.contains("#include <metal_stdlib>"), "{p}");
    assert!(lib.msl.contains("ReliefHit relief_trace("), "{p}");
    assert_eq!(lib.msl.contains("float relief_shadow("), lib.has_shadow, "{p}");
    assert_eq!(lib.msl.contains("float relief_ao("), lib.has_ao, "{p}");
}

#[test]
fn the_resources_are_what_the_stages_read() {
    // linear and binary read the height map through the linear sampler, nothing else.
    let p: Pipeline = "linear(10)+binary(5)".parse().unwrap();
    let lib = emit::library(&p, &LibraryOptions::default()).unwrap();
    let got: Vec<(&str, u32, ResourceKind)> =
        lib.bindings.iter().map(|b| (b.name.as_str(), b.binding, b.kind)).collect();
    assert_eq!(got, [("relief_height", 0, ResourceKind::Texture2d), ("relief_sampler", 1, ResourceKind::Sampler)]);
    assert!(!lib.has_shadow && !lib.has_ao);
    // sphere tracing reads the 3D distance field.
    let p: Pipeline = "sphere(20)".parse().unwrap();
    let lib = emit::library(&p, &LibraryOptions::default()).unwrap();
    assert!(
        lib.bindings.iter().any(|b| b.name == "relief_distance_field" && b.kind == ResourceKind::Texture3d),
        "{:?}",
        lib.bindings
    );
    // an ao stage adds its map and relief_ao.
    let p: Pipeline = "linear(10)+ao=cone_normal".parse().unwrap();
    let lib = emit::library(&p, &LibraryOptions::default()).unwrap();
    assert!(lib.has_ao && lib.bindings.iter().any(|b| b.name.starts_with("relief_cone_normal")), "{:?}", lib.bindings);
}

#[test]
fn two_prefixed_libraries_compose_in_one_module() {
    let a: Pipeline = "linear(16)+binary(4)+shadow=soft(10)".parse().unwrap();
    let b: Pipeline = "rcs(15)+binary(5)+ao=cone_normal".parse().unwrap();
    let la =
        emit::library(&a, &LibraryOptions { prefix: "rock".into(), binding: 0, ..LibraryOptions::default() }).unwrap();
    let next = la.bindings.len() as u32;
    let lb =
        emit::library(&b, &LibraryOptions { prefix: "brick_wall".into(), binding: next, ..LibraryOptions::default() })
            .unwrap();
    let src = format!(
        "{}\n{}\n{}\n{}",
        la.wgsl,
        lb.wgsl,
        wgsl_user(&la, "rock", "rock_main"),
        wgsl_user(&lb, "brick_wall", "brick_main")
    );
    let module = naga_wgsl(&src, "two libraries in one module");
    let owned = |n: &str| n.starts_with("rock") || n.starts_with("brick_wall");
    for (_, g) in module.global_variables.iter() {
        assert!(owned(g.name.as_deref().unwrap()), "global {:?} not under a prefix", g.name);
    }
    for (_, f) in module.functions.iter() {
        assert!(owned(f.name.as_deref().unwrap()), "function {:?} not under a prefix", f.name);
    }
    for (_, t) in module.types.iter() {
        if let Some(n) = &t.name {
            assert!(n.starts_with("Rock") || n.starts_with("BrickWall"), "type {n} not under a prefix");
        }
    }
    for (_, c) in module.constants.iter() {
        assert!(owned(c.name.as_deref().unwrap()), "constant {:?} not under a prefix", c.name);
    }
    let mut bindings: Vec<u32> =
        module.global_variables.iter().filter_map(|(_, g)| g.binding.map(|b| b.binding)).collect();
    bindings.sort();
    assert_eq!(bindings, (0..bindings.len() as u32).collect::<Vec<_>>(), "one binding range, no overlap");
}

#[test]
fn options_are_checked_and_written() {
    let p: Pipeline = "maxmip(32)+binary(4)".parse().unwrap();
    for bad in ["", "1abc", "relief_", "a__b", "a-b"] {
        let e = emit::library(&p, &LibraryOptions { prefix: bad.into(), ..LibraryOptions::default() });
        assert!(e.is_err(), "prefix `{bad}` accepted");
    }
    let e = emit::library(&p, &LibraryOptions { import_path: Some("relief::a-b".into()), ..LibraryOptions::default() });
    assert!(e.is_err(), "an import path with `-` accepted");
    let lib = emit::library(
        &p,
        &LibraryOptions { import_path: Some("relief::maxmip".into()), edge_clamp: true, ..LibraryOptions::default() },
    )
    .unwrap();
    assert!(lib.wgsl.starts_with("#define_import_path relief::maxmip\n"));
    // The edge mode is the constant the stages read: maxmip's texel walk uses it.
    let src = lib.wgsl.replacen("#define_import_path relief::maxmip", "", 1);
    let module = naga_wgsl(&src, "maxmip library");
    let (_, c) =
        module.constants.iter().find(|(_, c)| c.name.as_deref() == Some("relief_edge_clamp")).expect("edge constant");
    assert!(matches!(module.global_expressions[c.init], naga::Expression::Literal(naga::Literal::Bool(true))));
    let uses = module.functions.iter().any(|(_, f)| {
        f.expressions.iter().any(|(_, e)| matches!(e, naga::Expression::Constant(h) if module.constants[*h].name.as_deref() == Some("relief_edge_clamp")))
    });
    assert!(uses, "maxmip reads relief_edge_clamp");
}

/// Render options a library cannot honour are errors that say so, never dropped.
#[test]
fn a_library_refuses_the_render_options_it_cannot_honour() {
    for (text, says) in [
        ("linear(8)+binary(3)+silhouette=clip", "silhouette=clip is an option of relief's own render entry"),
        ("linear(8)+binary(3)+lod=auto", "does not support lod=auto"),
    ] {
        let p: Pipeline = text.parse().unwrap();
        let e = emit::library(&p, &LibraryOptions::default()).err().unwrap_or_else(|| panic!("{text} made a library"));
        assert!(e.to_string().contains(says), "{text}: {e}");
    }
}

#[test]
fn linear_distance_has_no_library() {
    let p: Pipeline = "linear_distance+binary(5)".parse().unwrap();
    let Err(e) = emit::library(&p, &LibraryOptions::default()) else { panic!("no library for linear_distance") };
    let e = e.to_string();
    assert!(e.contains("linear_distance") && e.contains("not implemented for libraries"), "{e}");
}

/// A library at the largest options every language accepts (the longest prefix, the highest
/// group, the last binding at the highest binding) compiles with the real validators, and one
/// past each limit is refused with a one-line error that names the option and the limit
/// (`relief_dsl::emit::limits`).
#[test]
fn the_largest_accepted_options_compile_and_one_past_is_refused() {
    use relief::dsl::emit::{limits, LibraryForm};
    let glslang = tool("glslangValidator");
    let spirv_val = tool("spirv-val");
    let dir = std::env::temp_dir().join(format!("relief-library-limits-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // The longest names: nested stages in the shadow slot, an ao stage.
    let p: Pipeline = "cns(10)+shadow=hard(rcs(8, start=bracket))+ao=cone_ratio".parse().unwrap();
    let count = emit::library(&p, &LibraryOptions::default()).unwrap().bindings.len() as u32;
    let max_name = |t| limits::limits(t).max_name.map_or(usize::MAX, |(n, _)| n);
    let max_group = |t| limits::limits(t).max_group.map_or(u32::MAX, |(n, _)| n);
    let max_binding = |t| limits::limits(t).max_binding.map_or(u32::MAX, |(n, _)| n);
    let longest = LibraryForm::DEFAULT.iter().map(|t| max_name(*t)).min().unwrap() - limits::LONGEST_SUFFIX;
    let group = LibraryForm::DEFAULT.iter().map(|t| max_group(*t)).min().unwrap();
    let last = LibraryForm::DEFAULT.iter().map(|t| max_binding(*t)).min().unwrap();
    let prefix = format!("r{}", "e".repeat(longest - 1));
    let opts = LibraryOptions { prefix: prefix.clone(), group, binding: last + 1 - count, ..LibraryOptions::default() };
    let lib = emit::library(&p, &opts).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(lib.bindings.last().map(|b| (b.group, b.binding)), Some((group, last)));
    let hit = format!("{}Hit", camel(&prefix));

    let wgsl = format!("{}\n{}", lib.wgsl, wgsl_user(&lib, &prefix, "user_main"));
    naga_wgsl(&wgsl, "WGSL library at the limits");

    let frag = dir.join("limits.frag");
    let call = |lang_vec3: &str| {
        let mut s = format!("    {hit} hit = {prefix}_trace(UV, normalize(VIEW), {DEPTH});\n    float shade = {prefix}_shadow(hit, normalize({lang_vec3}(0.3, 0.2, 0.9)), {DEPTH}) * {prefix}_ao(hit);\n");
        s += "    return_value(hit.uv, hit.height + hit.t + hit.depth_offset, shade);\n";
        s
    };
    let glsl_body =
        call("vec3").replace("UV", "v_uv").replace("VIEW", "v_view").replace("return_value", "o_color = vec4");
    std::fs::write(
        &frag,
        format!("#version 450\n{}layout(location = 0) in vec2 v_uv;\nlayout(location = 1) in vec3 v_view;\nlayout(location = 0) out vec4 o_color;\nvoid main() {{\n{glsl_body}}}\n", lib.glsl),
    )
    .unwrap();
    let spv = dir.join("limits.glsl.spv");
    run(
        Command::new(glslang).args(["-V", "-S", "frag", "-o"]).arg(&spv).arg(&frag),
        "glslangValidator -V at the limits",
    );
    run(
        Command::new(spirv_val).args(["--target-env", "vulkan1.0"]).arg(&spv),
        "spirv-val on the GLSL library at the limits",
    );
    run(
        Command::new(glslang).args(["-G", "-S", "frag", "-o"]).arg(dir.join("limits.gl.spv")).arg(&frag),
        "glslangValidator -G at the limits",
    );

    let hlsl_body =
        call("float3").replace("UV", "i.uv").replace("VIEW", "i.view").replace("return_value", "return float4");
    let hlsl = dir.join("limits.hlsl");
    std::fs::write(
        &hlsl,
        format!("{}struct UserIn {{ float4 pos : SV_Position; float2 uv : TEXCOORD0; float3 view : TEXCOORD1; }};\nfloat4 user_main(UserIn i) : SV_Target {{\n{hlsl_body}}}\n", lib.hlsl),
    )
    .unwrap();
    let spv = dir.join("limits.hlsl.spv");
    run(
        Command::new(glslang).args(["-D", "-V", "-S", "frag", "-e", "user_main", "-o"]).arg(&spv).arg(&hlsl),
        "glslangValidator -D at the limits",
    );
    run(
        Command::new(spirv_val).args(["--target-env", "vulkan1.0"]).arg(&spv),
        "spirv-val on the HLSL library at the limits",
    );
    std::fs::remove_dir_all(&dir).ok();

    // One past each limit: refused, in one line, naming the option and the limit.
    let past = [
        (LibraryOptions { prefix: format!("{prefix}e"), ..LibraryOptions::default() }, "prefix of"),
        (LibraryOptions { group: group + 1, ..LibraryOptions::default() }, "group"),
        (LibraryOptions { binding: last + 2 - count, ..LibraryOptions::default() }, "binding"),
        (LibraryOptions { prefix: "gl".into(), ..LibraryOptions::default() }, "prefix `gl`"),
        (LibraryOptions { group: 1000, ..LibraryOptions::default() }, "group 1000"),
        (LibraryOptions { group: u32::MAX, binding: u32::MAX, ..LibraryOptions::default() }, "group"),
        (LibraryOptions { binding: u32::MAX, ..LibraryOptions::default() }, "binding"),
    ];
    for (o, says) in past {
        let e = emit::library(&p, &o).err().unwrap_or_else(|| panic!("{o:?} accepted")).to_string();
        assert!(e.contains(says), "{o:?}: {e}");
        assert!(!e.contains('\n'), "{e}");
    }
}

// ---- The engine forms (`relief gen --library --target …`) ----

use emit::{LibraryForm, LibraryForms};

fn forms(p: &Pipeline, opts: &LibraryOptions, forms: &[LibraryForm]) -> LibraryForms {
    emit::library_forms(p, opts, forms).unwrap_or_else(|e| panic!("{p}: {e}"))
}

fn file<'a>(lib: &'a LibraryForms, suffix: &str) -> &'a str {
    lib.files
        .iter()
        .find(|f| f.name.ends_with(suffix))
        .map(|f| f.text.as_str())
        .unwrap_or_else(|| panic!("no `{suffix}` file"))
}

/// The pipelines the engine forms are checked on: every coarse stage family at least once,
/// shadow and ao stages, the 3D distance field, maxmip's texel walk.
fn engine_pipelines() -> Vec<Pipeline> {
    let mut all: Vec<Pipeline> =
        Pipeline::all_defaults().into_iter().filter(|p| p.coarse.name != "linear_distance").step_by(9).collect();
    for extra in [
        "linear(16)+binary(5)+shadow=soft(10)",
        "rcs(15)+binary(5)+ao=cone_normal",
        "cns(10)+shadow=hard(rcs(8, start=bracket))+ao=cone_ratio",
        "sphere(20)+secant(3)+shadow=hard(sphere(10))",
        "maxmip(32)+binary(4)+shadow=soft_cone(10)",
    ] {
        all.push(extra.parse().unwrap_or_else(|e| panic!("{extra}: {e}")));
    }
    all
}

/// The WGSL library with `--import-path` is a `naga_oil` composable module: a user material
/// that `#import`s it composes through naga_oil's Composer (what Bevy used up to 0.16) into a
/// module naga validates, with the library's resources at the group and bindings asked for.
#[test]
fn wgsl_import_path_composes_with_naga_oil() {
    use naga_oil::compose::{ComposableModuleDescriptor, Composer, NagaModuleDescriptor};
    for p in engine_pipelines() {
        let path = format!("relief::{}", p.file_stem().replace('-', "_"));
        let opts =
            LibraryOptions { group: 2, binding: 3, import_path: Some(path.clone()), ..LibraryOptions::default() };
        let lib = forms(&p, &opts, &[LibraryForm::Wgsl]);
        let text = file(&lib, ".lib.wgsl");
        let mut composer = Composer::default();
        let added = composer.add_composable_module(ComposableModuleDescriptor {
            source: text,
            file_path: "relief.lib.wgsl",
            ..Default::default()
        });
        if let Err(e) = added {
            panic!("{p}: naga_oil refused the library: {}", e.emit_to_string(&composer));
        }
        let mut user = format!(
            "#import {path} as relief\n\
             @fragment fn user_main(@location(0) uv: vec2<f32>, @location(1) view: vec3<f32>) -> @location(0) vec4<f32> {{\n\
             let hit = relief::relief_trace(uv, normalize(view), {DEPTH});\n    var shade = 1.0;\n"
        );
        if lib.has_shadow {
            user += &format!("    shade *= relief::relief_shadow(hit, normalize(vec3(0.3, 0.2, 0.9)), {DEPTH});\n");
        }
        if lib.has_ao {
            user += "    shade *= relief::relief_ao(hit);\n";
        }
        user += "    return vec4(hit.uv, hit.height + hit.t + hit.depth_offset, shade);\n}\n";
        let module = match composer.make_naga_module(NagaModuleDescriptor {
            source: &user,
            file_path: "user.wgsl",
            ..Default::default()
        }) {
            Ok(m) => m,
            Err(e) => panic!(
                "{p}: naga_oil could not compose a user module with the library: {}",
                e.emit_to_string(&composer)
            ),
        };
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::default())
            .validate(&module)
            .unwrap_or_else(|e| panic!("{p}: the composed module does not validate: {e:?}"));
        let mut bound: Vec<(u32, u32)> =
            module.global_variables.iter().filter_map(|(_, g)| g.binding.map(|b| (b.group, b.binding))).collect();
        bound.sort();
        let expect: Vec<(u32, u32)> = (3..3 + lib.bindings.len() as u32).map(|b| (2, b)).collect();
        assert_eq!(bound, expect, "{p}: the composed module's resources");
    }
}

/// The WESL form is a module a user module `import`s; the `wesl` crate compiles the pair to
/// WGSL that naga validates.
#[test]
fn wesl_module_is_imported_by_a_user_module() {
    use wesl::{VirtualResolver, Wesl};
    for p in engine_pipelines() {
        let lib = forms(&p, &LibraryOptions::default(), &[LibraryForm::Wesl]);
        let f = &lib.files[0];
        let module = f.name.strip_suffix(".wesl").expect("a .wesl file");
        assert_eq!(module, emit::wesl_module_name(&p.file_stem()));
        let mut names = vec!["relief_trace".to_string()];
        if lib.has_shadow {
            names.push("relief_shadow".into());
        }
        if lib.has_ao {
            names.push("relief_ao".into());
        }
        let mut user = format!(
            "import package::{module}::{{{}}};\n\
             @fragment fn user_main(@location(0) uv: vec2<f32>, @location(1) view: vec3<f32>) -> @location(0) vec4<f32> {{\n\
             let hit = relief_trace(uv, normalize(view), {DEPTH});\n    var shade = 1.0;\n",
            names.join(", ")
        );
        if lib.has_shadow {
            user += &format!("    shade *= relief_shadow(hit, normalize(vec3(0.3, 0.2, 0.9)), {DEPTH});\n");
        }
        if lib.has_ao {
            user += "    shade *= relief_ao(hit);\n";
        }
        user += "    return vec4(hit.uv, hit.height + hit.t + hit.depth_offset, shade);\n}\n";
        let mut resolver = VirtualResolver::new();
        resolver.add_module(format!("package::{module}").parse().unwrap(), f.text.clone().into());
        resolver.add_module("package::user".parse().unwrap(), user.into());
        let compiler = Wesl::new("").set_custom_resolver(resolver);
        let wgsl = compiler
            .compile(&"package::user".parse().unwrap())
            .unwrap_or_else(|e| panic!("{p}: the wesl crate could not compile a module importing the library: {e}"))
            .to_string();
        let m = naga_wgsl(&wgsl, &format!("WGSL that wesl made from the WESL library of {p}"));
        assert_eq!(m.entry_points.len(), 1, "{p}");
        assert_eq!(
            m.global_variables.len(),
            lib.bindings.len(),
            "{p}: every resource of the library is in the compiled module"
        );
    }
}

/// GLSL ES 3.00 (WebGL2): a fragment shader as three.js's `ShaderMaterial` with GLSL3 makes
/// it (`#version 300 es`, precision lines, the library, the user's main) passes glslang's ES
/// profile; the uniforms carry no binding (WebGL binds by name).
#[test]
fn glsl_es_libraries_pass_the_es_profile() {
    let glslang = tool("glslangValidator");
    let dir = std::env::temp_dir().join(format!("relief-library-es-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (mut refused, mut gathered, mut guarded_count) = (0, 0, 0);
    for p in pipelines() {
        if let Some(why) = emit::inexpressible_in(&p, LibraryForm::GlslEs) {
            // Refused with a one-line error, never written.
            let e =
                emit::library_forms(&p, &LibraryOptions::default(), &[LibraryForm::GlslEs]).unwrap_err().to_string();
            assert!(e.contains(&why) && e.contains("GLSL ES") && !e.contains('\n'), "{p}: {e}");
            refused += 1;
            continue;
        }
        let lib = forms(&p, &LibraryOptions::default(), &[LibraryForm::GlslEs]);
        let text = file(&lib, ".lib.es.glsl");
        let code: String = text.lines().filter(|l| !l.starts_with("//")).collect();
        assert!(
            !code.contains("#version") && !code.contains("layout("),
            "{p}: an ES 3.00 include has no #version and no binding"
        );
        for b in lib.bindings.iter().filter(|b| b.kind != ResourceKind::Sampler) {
            assert!(text.contains(&format!(" {};", b.name)), "{p}: uniform {}", b.name);
        }
        // The user states the samplers' edge mode (the library's guard wants it where it
        // addresses texels itself); without it such a library must not compile.
        let guarded = text.contains("#error");
        let head = "#version 300 es\nprecision highp float;\nprecision highp int;\n";
        let mut s = format!("{head}#define RELIEF_EDGE_REPEAT\n");
        s += text;
        s += "in vec2 v_uv;\nin vec3 v_view;\nout vec4 o_color;\n";
        s += &format!("void main() {{\n    ReliefHit hit = relief_trace(v_uv, normalize(v_view), {DEPTH});\n    float shade = 1.0;\n");
        if lib.has_shadow {
            s += &format!("    shade *= relief_shadow(hit, normalize(vec3(0.3, 0.2, 0.9)), {DEPTH});\n");
        }
        if lib.has_ao {
            s += "    shade *= relief_ao(hit);\n";
        }
        s += "    o_color = vec4(hit.uv, hit.height + hit.t + hit.depth_offset, shade);\n}\n";
        let frag = dir.join(format!("{}.es.frag", p.file_stem()));
        std::fs::write(&frag, s).unwrap();
        run(
            Command::new(glslang).args(["-S", "frag"]).arg(&frag),
            &format!("glslangValidator (ES 3.00 profile) on the GLSL ES library of {p}"),
        );
        if guarded {
            // The same shader without the define, or with the other edge mode's, fails.
            let src = std::fs::read_to_string(&frag).unwrap();
            for wrong in ["", "#define RELIEF_EDGE_REPEAT\n#define RELIEF_EDGE_CLAMP\n"] {
                let bad = dir.join(format!("{}.noedge.es.frag", p.file_stem()));
                std::fs::write(&bad, src.replacen("#define RELIEF_EDGE_REPEAT\n", wrong, 1)).unwrap();
                let out = Command::new(glslang).args(["-S", "frag"]).arg(&bad).output().unwrap();
                assert!(!out.status.success(), "{p}: the GLSL ES library compiles without stating its edge mode");
            }
            guarded_count += 1;
        }
        if text.contains("relief_gather(") {
            gathered += 1;
        }
    }
    assert!(refused < pipelines().len(), "every pipeline refused");
    // The safe cone marches, maxmip and the min4 reads gather: all written in ES now.
    assert!(gathered > 0 && guarded_count >= gathered, "{gathered} gathering, {guarded_count} guarded");
    std::fs::remove_dir_all(&dir).ok();
}

/// The Unity form: a shader as Shader Graph generates one around a Custom Function node
/// (texture properties `_Name` with `sampler_Name`, built into `UnityTexture2D`s; samplers
/// from sampler states) calls `Relief_float` and `Relief_half`; glslang's HLSL front end
/// compiles it against the repository's stub of Unity's declarations
/// (`tests/stubs/unity_shader_graph.hlsl`, a stub), and spirv-val accepts the result.
#[test]
fn unity_custom_function_compiles_against_the_unity_stub() {
    let glslang = tool("glslangValidator");
    let spirv_val = tool("spirv-val");
    let stub = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/stubs/unity_shader_graph.hlsl");
    let dir = std::env::temp_dir().join(format!("relief-library-unity-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for p in engine_pipelines() {
        let lib = forms(&p, &LibraryOptions::default(), &[LibraryForm::Unity]);
        let text = file(&lib, ".unity.hlsl");
        let mut s = format!("{}\n{text}\n", std::fs::read_to_string(&stub).unwrap());
        let mut args = vec!["uv".to_string(), "view".into(), DEPTH.into()];
        if lib.has_shadow {
            args.push("normalize(float3(0.3, 0.2, 0.9))".into());
        }
        for b in &lib.bindings {
            let base = camel(b.name.strip_prefix("relief_").unwrap());
            match b.kind {
                ResourceKind::Texture2d => {
                    s += &format!("TEXTURE2D(_{base}); SAMPLER(sampler_{base}); float4 _{base}_TexelSize;\n");
                    args.push(format!("UnityBuildTexture2DStructNoScale(_{base})"));
                }
                ResourceKind::Texture3d => {
                    s += &format!("TEXTURE3D(_{base}); SAMPLER(sampler_{base});\n");
                    args.push(format!("UnityBuildTexture3DStruct(_{base})"));
                }
                ResourceKind::Sampler => {
                    s += &format!("SAMPLER(SamplerState_{base});\n");
                    args.push(format!("UnityBuildSamplerStateStruct(SamplerState_{base})"));
                }
            }
        }
        let outs = 3 + usize::from(lib.has_shadow) + usize::from(lib.has_ao);
        s += "float4 frag(float2 uv : TEXCOORD0, float3 view : TEXCOORD1) : SV_Target {\n    float o[5]; half h[5];\n";
        let f_out: Vec<String> = (0..outs).map(|i| format!("o[{i}]")).collect();
        let h_out: Vec<String> = (0..outs).map(|i| format!("h[{i}]")).collect();
        // HitUV is a 2-vector: give it a variable of its own.
        s += "    float2 uv_f; half2 uv_h;\n";
        let call = |name: &str, uvv: &str, rest: &[String], cast: &str| {
            let a: Vec<String> = args
                .iter()
                .map(|a| if cast.is_empty() || a.starts_with("Unity") { a.clone() } else { format!("({cast})({a})") })
                .collect();
            format!("    {name}({}, {uvv}, {});\n", a.join(", "), rest[1..].join(", "))
        };
        s += &call("Relief_float", "uv_f", &f_out, "");
        s += &call("Relief_half", "uv_h", &h_out, "");
        s += "    return float4(uv_f + (float2)uv_h, o[1] + o[2] + (float)h[1] + (float)h[2], 1.0);\n}\n";
        let src = dir.join(format!("{}.unity.frag.hlsl", p.file_stem()));
        std::fs::write(&src, s).unwrap();
        let spv = dir.join(format!("{}.unity.spv", p.file_stem()));
        run(
            Command::new(glslang).args(["-D", "-V", "-S", "frag", "-e", "frag", "-o"]).arg(&spv).arg(&src),
            &format!("glslangValidator -D (Unity stub) on the Unity library of {p}"),
        );
        run(
            Command::new(spirv_val).args(["--target-env", "vulkan1.0"]).arg(&spv),
            &format!("spirv-val on the Unity library of {p}"),
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// The Unreal form: the Custom node's code, pasted into a function whose parameters are the
/// node's inputs as Unreal's material translator declares them (a Texture Object `Name` as
/// `Texture2D Name, SamplerState NameSampler`, additional outputs `inout`), after the include
/// file and the repository's stub of the view's shared samplers
/// (`tests/stubs/unreal_material.hlsl`, a stub), compiles with glslang's HLSL front end and
/// passes spirv-val.
#[test]
fn unreal_custom_node_compiles_against_the_unreal_stub() {
    let glslang = tool("glslangValidator");
    let spirv_val = tool("spirv-val");
    let stub = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/stubs/unreal_material.hlsl");
    let dir = std::env::temp_dir().join(format!("relief-library-unreal-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for edge_clamp in [false, true] {
        for p in engine_pipelines() {
            let lib = forms(&p, &LibraryOptions { edge_clamp, ..LibraryOptions::default() }, &[LibraryForm::Unreal]);
            let include = file(&lib, ".ush");
            let node = file(&lib, ".custom.hlsl");
            let sampler = if edge_clamp { "Clamped" } else { "Wrapped" };
            if lib.bindings.iter().any(|b| b.kind == ResourceKind::Sampler) {
                assert!(
                    node.contains("View.Shared") && node.contains(&format!("{sampler}Sampler")),
                    "{p}: the node's samplers follow the edge mode"
                );
            }
            let mut params = vec![
                "FMaterialPixelParameters Parameters".to_string(),
                "float2 UV".into(),
                "float3 ViewTS".into(),
                "float DepthScale".into(),
            ];
            let mut args = vec!["Parameters".to_string(), "uv".into(), "view".into(), DEPTH.into()];
            let mut globals = String::new();
            if lib.has_shadow {
                params.push("float3 LightTS".into());
                args.push("normalize(float3(0.3, 0.2, 0.9))".into());
            }
            for b in lib.bindings.iter().filter(|b| b.kind != ResourceKind::Sampler) {
                let name = camel(b.name.strip_prefix("relief_").unwrap());
                let ty = if b.kind == ResourceKind::Texture3d { "Texture3D" } else { "Texture2D" };
                params.push(format!("{ty} {name}"));
                params.push(format!("SamplerState {name}Sampler"));
                globals += &format!("{ty} Material_{name}; SamplerState Material_{name}Sampler;\n");
                args.push(format!("Material_{name}"));
                args.push(format!("Material_{name}Sampler"));
            }
            let mut outs = Vec::new();
            if lib.has_shadow {
                outs.push("Shadow");
            }
            if lib.has_ao {
                outs.push("AO");
            }
            for o in &outs {
                params.push(format!("inout float {o}"));
                args.push(format!("extra_{o}"));
            }
            let mut s = format!(
                "{}\nstruct FMaterialPixelParameters {{ float4 SvPosition; }};\n{include}\n{globals}",
                std::fs::read_to_string(&stub).unwrap()
            );
            s += &format!("float4 CustomExpression0({})\n{{\n{node}}}\n", params.join(", "));
            s +=
                "float4 frag(float4 pos : SV_Position, float2 uv : TEXCOORD0, float3 view : TEXCOORD1) : SV_Target {\n";
            s += "    FMaterialPixelParameters Parameters; Parameters.SvPosition = pos;\n";
            for o in &outs {
                s += &format!("    float extra_{o} = 0.0;\n");
            }
            s += &format!("    float4 r = CustomExpression0({});\n", args.join(", "));
            s += &format!("    return r{};\n}}\n", outs.iter().map(|o| format!(" * extra_{o}")).collect::<String>());
            let src = dir.join(format!("{}.{edge_clamp}.unreal.hlsl", p.file_stem()));
            std::fs::write(&src, s).unwrap();
            let spv = dir.join(format!("{}.{edge_clamp}.unreal.spv", p.file_stem()));
            run(
                Command::new(glslang).args(["-D", "-V", "-S", "frag", "-e", "frag", "-o"]).arg(&spv).arg(&src),
                &format!("glslangValidator -D (Unreal stub) on the Unreal library of {p}"),
            );
            run(
                Command::new(spirv_val).args(["--target-env", "vulkan1.0"]).arg(&spv),
                &format!("spirv-val on the Unreal library of {p}"),
            );
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// Bad input is a one-line error naming it: an unknown target (with the nearest name), a
/// prefix that WebGL reserves in the GLSL ES form only.
#[test]
fn engine_forms_refuse_bad_input_in_one_line() {
    let e = LibraryForm::from_name("glsles").unwrap_err().to_string();
    assert!(e.contains("unknown target `glsles`") && e.contains("did you mean `glsl-es`?") && !e.contains('\n'), "{e}");
    let p: Pipeline = "linear(8)+binary(3)".parse().unwrap();
    let opts = LibraryOptions { prefix: "webgl".into(), ..LibraryOptions::default() };
    let e = emit::library_forms(&p, &opts, &[LibraryForm::GlslEs]).unwrap_err().to_string();
    assert!(e.contains("prefix `webgl`") && e.contains("WebGL") && !e.contains('\n'), "{e}");
    assert!(
        emit::library_forms(&p, &opts, &[LibraryForm::Wgsl, LibraryForm::Glsl, LibraryForm::Unity]).is_ok(),
        "`webgl` is a fine prefix outside WebGL"
    );
    let q: Pipeline = "linear_distance+binary(5)".parse().unwrap();
    for form in LibraryForm::ALL {
        let e = emit::library_forms(&q, &LibraryOptions::default(), &[form]).unwrap_err().to_string();
        assert!(e.contains("linear_distance") && !e.contains('\n'), "{form:?}: {e}");
    }
}

// ---- Issue 39, item 4: what an engine's shader processor reads in the header ----

/// The comment text of each line of `src` (`//` to the end of the line, and every line
/// inside `/* … */`).
fn comments(src: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut in_block = false;
    for line in src.lines() {
        let mut rest = line;
        loop {
            if in_block {
                match rest.find("*/") {
                    Some(i) => {
                        out.push(rest[..i].to_string());
                        rest = &rest[i + 2..];
                        in_block = false;
                    }
                    None => {
                        out.push(rest.to_string());
                        break;
                    }
                }
            } else {
                let line_c = rest.find("//");
                let block = rest.find("/*");
                match (line_c, block) {
                    (Some(l), Some(b)) if b < l => {
                        rest = &rest[b + 2..];
                        in_block = true;
                    }
                    (Some(l), _) => {
                        out.push(rest[l + 2..].to_string());
                        break;
                    }
                    (None, Some(b)) => {
                        rest = &rest[b + 2..];
                        in_block = true;
                    }
                    (None, None) => break,
                }
            }
        }
    }
    out
}

/// Babylon.js's shader processor takes a shader holding `#version 3…` anywhere as already
/// converted (issue 39): no comment of any form of any expressible default pipeline holds a
/// `#version` or `#extension` (line-leading or not), and no line of these include files
/// starts with one.
#[test]
fn no_library_form_has_a_version_or_extension_directive_in_its_comments() {
    let mut all: Vec<Pipeline> = Pipeline::all_defaults()
        .into_iter()
        .filter(|p| relief::dsl::compose::library::inexpressible(p).is_none())
        .collect();
    all.extend(engine_pipelines());
    let mut checked = 0;
    for p in &all {
        let lib = forms(p, &LibraryOptions::default(), &LibraryForm::ALL);
        for f in &lib.files {
            for c in comments(&f.text) {
                for d in ["#version", "#extension"] {
                    assert!(!c.contains(d), "{p}: {}: a comment holds `{d}`: {c}", f.name);
                }
            }
            for line in f.text.lines() {
                let t = line.trim_start();
                assert!(
                    !t.starts_with("#version") && !t.starts_with("#extension"),
                    "{p}: {}: a line starts with a directive the user's shader owns: {line}",
                    f.name
                );
            }
            checked += 1;
        }
    }
    assert!(checked >= 9 * 20, "only {checked} files checked");
    // The helper finds a directive where one is.
    assert_eq!(
        comments("x; // put after `#version 300 es`\n/* a\n#extension b */ y"),
        [" put after `#version 300 es`", " a", "#extension b "]
    );
}

/// The arguments of the call that starts at `s` (just after its `(`), split at top-level
/// commas.
fn call_args(s: &str) -> Vec<String> {
    let (mut depth, mut cur, mut out) = (0i32, String::new(), Vec::new());
    for ch in s.chars() {
        match ch {
            '(' => depth += 1,
            ')' if depth == 0 => {
                out.push(cur.trim().to_string());
                return out;
            }
            ')' => depth -= 1,
            ',' if depth == 0 => {
                out.push(cur.trim().to_string());
                cur.clear();
                continue;
            }
            _ => {}
        }
        cur.push(ch);
    }
    panic!("unclosed call: {s}")
}

/// Whether the WGSL library `src` reads texture `name` at some level other than 0, from its
/// text: `textureLoad` and `textureSampleLevel` name the level last (a literal zero is level
/// 0), `textureGather` reads level 0, `textureSample` lets the hardware choose.
fn wgsl_reads_other_levels(src: &str, name: &str) -> Option<bool> {
    let mut seen = false;
    let mut other = false;
    for (fun, at_zero) in [("textureLoad(", None), ("textureSampleLevel(", None), ("textureSample(", Some(false))] {
        for (i, _) in src.match_indices(fun) {
            let args = call_args(&src[i + fun.len()..]);
            if args[0] != name {
                continue;
            }
            seen = true;
            let zero = at_zero.unwrap_or_else(|| {
                let last = args.last().map(String::as_str).unwrap_or("");
                matches!(last, "0" | "0i" | "0u" | "0f" | "0.0" | "0.0f" | "i32(0)" | "u32(0)" | "f32(0)")
            });
            other |= !zero;
        }
    }
    for (i, _) in src.match_indices("textureGather(") {
        let args = call_args(&src[i + "textureGather(".len()..]);
        if args.iter().any(|a| a == name) {
            seen = true;
        }
    }
    seen.then_some(other)
}

/// Each texture's line in the header says at which levels the library reads it, and that is
/// what the module's text reads: `csm(64)` reads its cell cone map at level 0 only, maxmip
/// walks the max-mip chain (issue 39: the header said "over its mip chain" for both).
#[test]
fn the_header_says_at_which_levels_each_texture_is_read() {
    let mut all = pipelines();
    all.extend(["csm(64)", "maxmip(96)", "linear(32)+binary(5)+shadow=soft(16)"].map(|s| s.parse().unwrap()));
    let (mut zero, mut chain, mut sized) = (0, 0, 0);
    for p in &all {
        let lib = forms(p, &LibraryOptions::default(), &[LibraryForm::Wgsl]);
        let src = file(&lib, ".lib.wgsl");
        for line in src.lines().filter(|l| l.starts_with("//   group ") && l.contains("texture_")) {
            let name = line.split(": ").nth(1).and_then(|r| r.split(' ').next()).unwrap_or_else(|| panic!("{line}"));
            if line.contains(relief::dsl::compose::library::SIZE_ONLY) {
                // Only its size: queried, and no texel of it read.
                assert!(wgsl_reads_other_levels(src, name).is_none(), "{p}: {line}, yet `{name}` is read");
                assert!(src.contains(&format!("textureDimensions({name}")), "{p}: {line}, yet no size is asked");
                sized += 1;
                continue;
            }
            let other = wgsl_reads_other_levels(src, name).unwrap_or_else(|| panic!("{p}: `{name}` is never read"));
            if other {
                chain += 1;
                assert!(line.contains("at every level of its mip chain"), "{p}: {line}");
                assert!(!line.contains("level 0 only"), "{p}: {line}");
            } else {
                zero += 1;
                assert!(line.contains("at level 0 only"), "{p}: {line}");
                assert!(!line.contains("mip chain"), "{p}: {line}");
            }
        }
        if p.to_string() == "csm(64)" {
            assert!(
                src.lines().any(|l| l.contains("relief_cell_cone_nearest texture_2d") && l.contains("at level 0 only")),
                "{src}"
            );
            // Its cells' patches come from the patch map: no texel of the height map is read.
            assert!(
                src.lines()
                    .any(|l| l.contains("relief_height texture_2d")
                        && l.contains(relief::dsl::compose::library::SIZE_ONLY)),
                "{src}"
            );
        }
        if p.to_string() == "maxmip(96)" {
            assert!(src.lines().any(|l| l.contains("relief_max_mip texture_2d") && l.contains("mip chain")), "{src}");
        }
    }
    assert!(zero > 10 && chain >= 2 && sized >= 1, "level 0: {zero}, chain: {chain}, size only: {sized}");
}

/// Runs `relief ARGS… DIR` and returns its output (status and stderr unchecked).
fn relief_out(args: &[&str], dir: &Path) -> std::process::Output {
    Command::new(crate::common::exe::relief_exe()).args(args).arg(dir).output().unwrap()
}

/// `relief export --target wgsl --group 2 --import-path relief::bundle` (issue 39, Bevy): the
/// exported library is a naga_oil module `relief::bundle` that a user module `#import`s into
/// a module naga validates, with every global in group 2; `relief.json`'s group and each
/// binding's (name, group, binding) are the library file's as naga itself parses it. Without
/// the options the library is byte for byte `relief gen --library --target wgsl`'s (what
/// export wrote before them) and relief.json names no group; with them it is `relief gen
/// --library --group 2 --import-path relief::bundle`'s. `--group` for a target without groups
/// and `--import-path` for one other than wgsl are refused in one line naming the target.
#[test]
fn export_group_and_import_path_make_a_library_naga_oil_composes() {
    use naga_oil::compose::{ComposableModuleDescriptor, Composer, NagaModuleDescriptor};
    let dir = std::env::temp_dir().join(format!("relief-library-export-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    for pipe in ["linear(32)+binary(5)+shadow=soft(16)", "csm(64)", "maxmip(96)"] {
        let p: Pipeline = pipe.parse().unwrap();
        let lib_name = format!("{}.lib.wgsl", p.file_stem());
        let read_json = |d: &Path| -> serde_json::Value {
            serde_json::from_slice(&std::fs::read(d.join("relief.json")).unwrap()).unwrap()
        };
        let ok =
            |o: std::process::Output| assert!(o.status.success(), "{pipe}: {}", String::from_utf8_lossy(&o.stderr));
        let export = ["export", pipe, "--scene", "scene:step", "--target", "wgsl"];
        // Without the options: gen's library, no group recorded.
        let (plain, gen_plain) = (dir.join("plain"), dir.join("gen-plain"));
        ok(relief_out(&[&export[..], &["--out"]].concat(), &plain));
        ok(relief_out(&["gen", pipe, "--library", "--target", "wgsl", "--edge", "repeat", "--out"], &gen_plain));
        let plain_lib = std::fs::read(plain.join(&lib_name)).unwrap();
        assert_eq!(plain_lib, std::fs::read(gen_plain.join(&lib_name)).unwrap(), "{pipe}: the default library");
        let j = read_json(&plain);
        assert!(j.get("group").is_none() && j.get("import_path").is_none(), "{pipe}: {j}");
        // With them.
        let (bevy, gen_bevy) = (dir.join("bevy"), dir.join("gen-bevy"));
        let opts = ["--group", "2", "--import-path", "relief::bundle"];
        ok(relief_out(&[&export[..], &opts, &["--out"]].concat(), &bevy));
        ok(relief_out(
            &[&["gen", pipe, "--library", "--target", "wgsl", "--edge", "repeat"][..], &opts, &["--out"]].concat(),
            &gen_bevy,
        ));
        let text = std::fs::read_to_string(bevy.join(&lib_name)).unwrap();
        assert_eq!(text, std::fs::read_to_string(gen_bevy.join(&lib_name)).unwrap(), "{pipe}: gen's library");
        let j = read_json(&bevy);
        assert_eq!((j["group"].as_u64(), j["import_path"].as_str()), (Some(2), Some("relief::bundle")), "{pipe}");
        // naga's own reading of the file (the import line is naga_oil's, not WGSL).
        let body = text.strip_prefix("#define_import_path relief::bundle\n").expect("the import line first");
        let parsed = naga_wgsl(body, pipe);
        let mut declared: Vec<(String, u32, u32)> = parsed
            .global_variables
            .iter()
            .filter_map(|(_, g)| g.binding.map(|b| (g.name.clone().unwrap_or_default(), b.group, b.binding)))
            .collect();
        let mut listed: Vec<(String, u32, u32)> = j["bindings"]
            .as_array()
            .unwrap()
            .iter()
            .map(|b| {
                let n = |k: &str| b[k].as_u64().unwrap_or_else(|| panic!("{pipe}: {k} of {b}")) as u32;
                (b["name"].as_str().unwrap().to_string(), n("group"), n("binding"))
            })
            .collect();
        declared.sort();
        listed.sort();
        assert!(!declared.is_empty(), "{pipe}: no globals");
        assert_eq!(listed, declared, "{pipe}: relief.json against the library");
        // naga_oil composes a user module that imports it; every global lands in group 2.
        let mut composer = Composer::default();
        if let Err(e) = composer.add_composable_module(ComposableModuleDescriptor {
            source: &text,
            file_path: &lib_name,
            ..Default::default()
        }) {
            panic!("{pipe}: naga_oil refused the library: {}", e.emit_to_string(&composer));
        }
        let mut user = format!(
            "#import relief::bundle::{{relief_trace{}}}\n\
             @fragment fn user_main(@location(0) uv: vec2<f32>, @location(1) view: vec3<f32>) -> @location(0) vec4<f32> {{\n\
             let hit = relief_trace(uv, normalize(view), {DEPTH});\n    var shade = 1.0;\n",
            if j["has_shadow"] == true { ", relief_shadow" } else { "" }
        );
        if j["has_shadow"] == true {
            user += &format!("    shade *= relief_shadow(hit, normalize(vec3(0.3, 0.2, 0.9)), {DEPTH});\n");
        }
        user += "    return vec4(hit.uv, hit.height + hit.t, shade);\n}\n";
        let module = composer
            .make_naga_module(NagaModuleDescriptor { source: &user, file_path: "user.wgsl", ..Default::default() })
            .unwrap_or_else(|e| panic!("{pipe}: naga_oil could not compose: {}", e.emit_to_string(&composer)));
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::default())
            .validate(&module)
            .unwrap_or_else(|e| panic!("{pipe}: the composed module does not validate: {e:?}"));
        let groups: Vec<u32> = module.global_variables.iter().filter_map(|(_, g)| g.binding.map(|b| b.group)).collect();
        assert_eq!(groups.len(), declared.len(), "{pipe}: the composed module's globals");
        assert!(groups.iter().all(|g| *g == 2), "{pipe}: groups {groups:?}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
    // Refusals, one line each, naming the target.
    for (target, opt, val, says) in [
        ("msl", "--group", "1", "--target msl has no groups"),
        ("glsl-es", "--group", "0", "--target glsl-es has no groups"),
        ("tsl", "--group", "2", "--target tsl has no groups"),
        ("wesl", "--import-path", "relief::bundle", "(wesl names its module otherwise)"),
        ("hlsl", "--import-path", "relief::bundle", "(hlsl names its module otherwise)"),
    ] {
        let o =
            relief_out(&["export", "csm(64)", "--scene", "scene:step", "--target", target, opt, val, "--out"], &dir);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains(says) && err.trim().lines().count() == 1, "{target} {opt}: {err}");
        assert!(!dir.exists(), "{target} {opt}: refused after writing");
    }
}
