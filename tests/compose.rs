//! The composed module: entry points, the resources each entry reads, and the WGSL of a few
//! pipelines (snapshots, reviewed by eye: they should read like the algorithm boxes).

use relief::dsl::abi::binding;
use relief::dsl::compose;
use relief::dsl::emit;
use relief::dsl::spec::MapReq;
use relief::Pipeline;

fn p(s: &str) -> Pipeline {
    s.parse().unwrap_or_else(|e| panic!("{s}: {e}"))
}

/// Names of the bound resources an entry point reads.
fn used_by(c: &relief::dsl::Compiled, entry: &str) -> Vec<String> {
    let (i, _) = c.module.entry_points.iter().enumerate().find(|(_, e)| e.name == entry).unwrap();
    let info = c.info.get_entry_point(i);
    let mut out: Vec<String> = c
        .module
        .global_variables
        .iter()
        .filter(|(h, g)| g.binding.is_some() && !info[*h].is_empty())
        .map(|(_, g)| g.name.clone().unwrap())
        .collect();
    out.sort();
    out
}

/// The module's entry points, in order, each with its stage.
fn entry_points(c: &relief::dsl::Compiled) -> Vec<(&str, naga::ShaderStage)> {
    c.module.entry_points.iter().map(|e| (e.name.as_str(), e.stage)).collect()
}

#[test]
fn module_has_the_render_pair_and_the_probe() {
    use naga::ShaderStage::{Compute, Fragment, Vertex};
    let c = relief::compile(&p("linear(10)+binary(5)")).unwrap();
    assert_eq!(entry_points(&c), [("vs_main", Vertex), ("fs_main", Fragment), ("probe", Compute)]);
}

#[test]
fn the_probe_reads_only_what_its_stages_read() {
    let c = relief::compile(&p("linear(10)+binary(5)")).unwrap();
    assert_eq!(used_by(&c, "probe"), ["height_map", "hits", "linear_sampler", "params", "rays"]);
    // Slope parallax reads the normal map as well.
    let c = relief::compile(&p("slope_parallax")).unwrap();
    assert!(used_by(&c, "probe").contains(&"normal_map".to_string()));
    // The render pass shades with albedo and normal; it never touches the probe's buffers.
    let c = relief::compile(&p("linear(10)")).unwrap();
    let fs = used_by(&c, "fs_main");
    assert!(fs.contains(&"albedo_map".into()) && fs.contains(&"normal_map".into()));
    assert!(!fs.contains(&"rays".into()) && !fs.contains(&"hits".into()));
}

#[test]
fn nothing_unread_is_declared() {
    for pipe in Pipeline::all_defaults() {
        let c = relief::compile(&pipe).unwrap();
        let declared = compose::declared_resources(&c.module);
        // Only a map read with nearest filtering brings the nearest sampler.
        let nearest = declared.iter().any(|d| d.ends_with("_nearest"));
        assert_eq!(declared.contains(&"nearest_sampler".to_string()), nearest, "{pipe}");
        let bindings: Vec<u32> =
            c.module.global_variables.iter().filter_map(|(_, g)| g.binding).map(|b| b.binding).collect();
        // Plain texture mapping with no refinement and no shadow samples no height at all.
        let samples_height = !(pipe.coarse.is_none() && pipe.refine.is_none() && pipe.shadow.is_none());
        assert_eq!(bindings.contains(&binding::HEIGHT), samples_height, "{pipe}");
        // Each map the pipeline needs is declared, and no other.
        for m in [
            MapReq::Cone,
            MapReq::QuadCone,
            MapReq::RelaxedCone,
            MapReq::ConeNormal,
            MapReq::DistanceField,
            MapReq::CellCone,
            MapReq::CellQuadCone,
            MapReq::CellRelaxedCone,
            MapReq::CellConeNormal,
            MapReq::CellPatch,
        ] {
            let declared_map = declared.iter().any(|d| d.starts_with(&m.texture_name()));
            assert_eq!(declared_map, pipe.required_maps().contains(&m), "{pipe}: {}", m.name());
        }
    }
    let plain = relief::compile(&p("linear(10)+binary(5)")).unwrap();
    assert!(!compose::declared_resources(&plain.module).contains(&"nearest_sampler".to_string()));
    let cone = relief::compile(&p("csm(10, form=textbook, sample=nearest)")).unwrap();
    let declared = compose::declared_resources(&cone.module);
    assert!(declared.contains(&"cone_map_nearest".to_string()) && declared.contains(&"nearest_sampler".to_string()));
}

#[test]
fn required_maps_match_what_the_probe_and_shading_read() {
    let mut pipes = Pipeline::all_defaults();
    pipes.push(p("rcs(15)+binary(5)+ao=cone_normal"));
    pipes.push(p("mcns(15, 3)+shadow=hard(pcns(5, 2))+ao=cone_ratio"));
    for pipe in pipes {
        let c = relief::compile(&pipe).unwrap();
        let read: Vec<String> = [used_by(&c, "probe"), used_by(&c, "fs_main")].concat();
        let reads = |m: MapReq| read.iter().any(|r| r.starts_with(&m.texture_name()));
        assert_eq!(
            pipe.required_maps().contains(&MapReq::Normal),
            used_by(&c, "probe").contains(&"normal_map".to_string()),
            "{pipe}"
        );
        for m in pipe.required_maps() {
            assert!(reads(m), "{pipe}: requires {} but reads {read:?}", m.name());
        }
        for m in [
            MapReq::Cone,
            MapReq::QuadCone,
            MapReq::RelaxedCone,
            MapReq::ConeNormal,
            MapReq::RelaxedConeNormal,
            MapReq::DistanceField,
            MapReq::CellCone,
            MapReq::CellQuadCone,
            MapReq::CellRelaxedCone,
            MapReq::CellConeNormal,
            MapReq::CellPatch,
        ] {
            assert_eq!(reads(m), pipe.required_maps().contains(&m), "{pipe}: {}", m.name());
        }
    }
    // The example: relaxed stepping with cone-normal AO needs both maps (the safe
    // form's cell map, and the texel map the AO reads).
    assert_eq!(p("rcs(15)+binary(5)+ao=cone_normal").required_maps(), [MapReq::ConeNormal, MapReq::CellRelaxedCone]);
    assert_eq!(
        p("rcs(15, form=textbook)+binary(5)+ao=cone_normal").required_maps(),
        [MapReq::RelaxedCone, MapReq::ConeNormal]
    );
    // A sampling choice of the textbook form is an error on the safe one, not ignored.
    let e = relief::compile(&p("csm(10, sample=min4)")).err().expect("sample=min4 with form=safe");
    assert!(e.to_string().contains("form=textbook"), "{e}");
}

/// The binding table the composer returns agrees with the module it returns it with: one
/// entry per bound global (its binding and name), each of the kind the global's type says,
/// every texture named for its image and filter at its plain binding, every map one the
/// pipeline's `required_maps` (declared apart from the stage code) asks for, with the same
/// parameters.
#[test]
fn the_binding_table_names_every_bound_global() {
    use relief::dsl::ir::{Filter, Image, Resource};
    let mut pipes = Pipeline::all_defaults();
    pipes.push(p("mcns(15, 3)+shadow=hard(pcns(5, 2))+ao=cone_ratio"));
    pipes.push(p("csm(10, form=textbook, sample=nearest)+binary(3)"));
    pipes.push(p("maxmip(32)+lod=auto"));
    for pipe in pipes {
        let c = relief::compile(&pipe).unwrap();
        let globals: Vec<(u32, String, &naga::GlobalVariable)> = c
            .module
            .global_variables
            .iter()
            .filter_map(|(_, g)| Some((g.binding?.binding, g.name.clone()?, g)))
            .collect();
        assert_eq!(c.bindings.len(), globals.len(), "{pipe}: {:?}", c.bindings);
        for (b, name, g) in globals {
            let e = c.bindings.get(b).unwrap_or_else(|| panic!("{pipe}: binding {b} (`{name}`) not in the table"));
            assert_eq!(e.name, name, "{pipe}: binding {b}");
            let ty = &c.module.types[g.ty].inner;
            match e.resource {
                Resource::Params => assert_eq!((b, g.space), (binding::PARAMS, naga::AddressSpace::Uniform), "{pipe}"),
                Resource::Sampler(f) => {
                    assert!(matches!(ty, naga::TypeInner::Sampler { .. }), "{pipe}: {name}");
                    let want = if f == Filter::Linear { "linear_sampler" } else { "nearest_sampler" };
                    assert_eq!(name, want, "{pipe}");
                }
                Resource::Texture { image, filter, wall } => {
                    assert!(matches!(ty, naga::TypeInner::Image { .. }), "{pipe}: {name}");
                    assert_eq!(wall, None, "{pipe}: a plain module has no walls");
                    let (base, plain) = match image {
                        Image::Height => ("height_map".to_string(), binding::HEIGHT),
                        Image::Normal => ("normal_map".to_string(), binding::NORMAL),
                        Image::Albedo => ("albedo_map".to_string(), binding::ALBEDO),
                        Image::Window => panic!("{pipe}: a window outside a room"),
                        Image::Map(req) => {
                            assert!(
                                pipe.required_maps().contains(&req),
                                "{pipe}: reads {req:?}, requires {:?}",
                                pipe.required_maps()
                            );
                            (req.texture_name(), req.binding())
                        }
                    };
                    match filter {
                        Filter::Linear => assert_eq!((name.as_str(), b), (base.as_str(), plain), "{pipe}"),
                        Filter::Nearest => {
                            assert_eq!(
                                (name, b),
                                (format!("{base}_nearest"), plain + binding::NEAREST_OFFSET),
                                "{pipe}"
                            )
                        }
                    }
                }
                Resource::Rays | Resource::Hits => {
                    assert!(matches!(g.space, naga::AddressSpace::Storage { .. }), "{pipe}: {name}");
                    let want = if e.resource == Resource::Rays { binding::RAYS } else { binding::HITS };
                    assert_eq!(b, want, "{pipe}");
                }
                Resource::PrismCells => panic!("{pipe}: the prism walk's buffer in a flat-tile module"),
                Resource::RoomParams => panic!("{pipe}: a room block outside a room"),
            }
        }
    }
}

#[test]
fn counters_exist_only_in_the_probe_variant() {
    let c = relief::compile(&p("linear(10)+interval(3)+shadow=hard(8)")).unwrap();
    let wgsl = emit::wgsl(&c).unwrap();
    let plain = function_body(&wgsl, "fn coarse_linear(");
    assert!(!plain.contains("relief_fetches") && !plain.contains("relief_coarse_steps"));
    let counted = function_body(&wgsl, "fn coarse_linear_counted(");
    assert!(
        counted.contains("relief_fetches")
            && counted.contains("relief_coarse_steps")
            && !counted.contains("relief_refine_steps")
    );
    // The refine stage's passes go to their own counter.
    let refine = function_body(&wgsl, "fn refine_interval_counted(");
    assert!(refine.contains("relief_refine_steps") && !refine.contains("relief_coarse_steps"));
    // The shadow is not traced by the probe, so it has no counted variant.
    assert!(function_body(&wgsl, "fn probe(").contains("trace_counted("));
    assert!(!wgsl.contains("fn shadow_hard_counted("));
}

#[test]
fn all_sampling_uses_an_explicit_level() {
    for pipe in Pipeline::all_defaults() {
        let wgsl = emit::emit(&pipe).unwrap().wgsl;
        assert!(!wgsl.contains("textureSample("), "{pipe}: implicit-level sampling");
        assert!(wgsl.contains("textureSampleLevel("));
    }
}

fn function_body<'a>(wgsl: &'a str, header: &str) -> &'a str {
    let start = wgsl.find(header).unwrap_or_else(|| panic!("no `{header}` in\n{wgsl}"));
    let rest = &wgsl[start..];
    let end = rest.find("\n}\n").unwrap_or(rest.len());
    &rest[..end]
}

fn stage_functions(wgsl: &str) -> String {
    // The stage functions only (entry points and declarations are shared boilerplate).
    let mut out = String::new();
    for header in ["fn coarse_", "fn refine_", "fn shadow_"] {
        let mut from = 0;
        while let Some(i) = wgsl[from..].find(header) {
            let body = function_body(&wgsl[from + i..], header);
            if !body.contains("_counted(") {
                out.push_str(body);
                out.push_str("\n}\n\n");
            }
            from += i + header.len();
        }
    }
    out
}

#[test]
fn wgsl_snapshots() {
    for text in [
        "linear(10)+binary(5)",
        "linear(16)+interval(4)",
        "linear(16)+secant(4)",
        "iterative_parallax(3)",
        "linear_dynamic(8, 32)+shadow=soft(24)",
        "parallax+shadow=hard(16)",
        "csm(15)+binary(5)",
        "cns(15)+shadow=soft_cone(16)+ao=cone_normal",
    ] {
        let wgsl = emit::emit(&p(text)).unwrap().wgsl;
        insta::assert_snapshot!(relief::dsl::spec::file_safe(text), stage_functions(&wgsl), text);
    }
}

/// The mesh modules of `curved=none`, `curved=quadric` and `curved=prism` (issue 38), whole as the runtime
/// loads them: the declarations, the stage functions (quadric's height reads carry the
/// vertex's quadric), the vertex entry `vs_mesh`, the render entry `fs_mesh` and the depth
/// entry `fs_mesh_depth`, which is also the shadow caster. Reviewed by eye like the flat
/// snapshots; the first two also pin that a change to `curved=prism` leaves the other modes'
/// modules alone. `curved=prism`'s module carries the exact entry and exit through the
/// prism's walls, the chord's lift and the polish onto S (docs/meshes-shaders.md).
#[test]
fn mesh_wgsl_snapshots() {
    for mode in ["none", "quadric", "prism"] {
        let text = format!("linear(32)+binary(5)+curved={mode}");
        let c = relief::compile(&p(&text)).unwrap();
        let (vertex, fragment) = (naga::ShaderStage::Vertex, naga::ShaderStage::Fragment);
        assert_eq!(
            entry_points(&c),
            [("vs_mesh", vertex), ("fs_mesh", fragment), ("fs_mesh_depth", fragment)],
            "{text}"
        );
        let wgsl = emit::wgsl(&c).unwrap();
        insta::assert_snapshot!(relief::dsl::spec::file_safe(&text), wgsl, &text);
    }
}

/// The ABI's records are laid out by naga exactly as the Rust structs the runtime uploads
/// and reads: same size, and each member at the offset the `#[repr(C)]` struct gives it.
#[test]
fn abi_records_match_their_rust_structs() {
    use relief::dsl::abi::{Params, ProbeHit, ProbeRay};
    let c = relief::compile(&p("linear(4)")).unwrap();
    let span_of = |name: &str| -> (u32, Vec<u32>) {
        let ty = c
            .module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("no type {name}"))
            .1;
        match &ty.inner {
            naga::TypeInner::Struct { members, span } => (*span, members.iter().map(|m| m.offset).collect()),
            other => panic!("{name} is {other:?}"),
        }
    };
    assert_eq!(span_of("Params"), (std::mem::size_of::<Params>() as u32, vec![0, 64, 80, 96, 112, 128]));
    assert_eq!(span_of("ProbeRay"), (std::mem::size_of::<ProbeRay>() as u32, vec![0, 8, 16, 20, 24, 28]));
    assert_eq!(span_of("ProbeHit"), (std::mem::size_of::<ProbeHit>() as u32, (0..9).map(|i| 4 * i).collect()));
    assert_eq!(std::mem::offset_of!(Params, quad), 96);
    assert_eq!(std::mem::offset_of!(ProbeHit, converged), 28);
    assert_eq!(std::mem::offset_of!(ProbeHit, clipped), 32);
}
