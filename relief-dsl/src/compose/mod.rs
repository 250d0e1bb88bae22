//! Pipeline → one validated `naga::Module`.
//!
//! The module holds, for a pipeline `C + R + shadow=S + ao=A`:
//! - one function per stage (`coarse_linear`, `refine_binary`, `shadow_soft`, …) and
//!   `trace(ray) -> Hit`, which calls the coarse then the refine stage;
//! - the same functions again with a `_counted` suffix, which count loop passes and texture
//!   fetches in two private counters, for the probe;
//! - the render entry pair `vs_main` (a quad in tangent space) and `fs_main` (trace, then
//!   shade with albedo and normal at the hit, visibility from the shadow stage, ambient × ao);
//! - the probe entry `probe` (compute, 64 rays per workgroup: [`ProbeRay`] in, [`ProbeHit`]
//!   out).
//!
//! Resources are declared when a stage first reads them (see [`binding`]), so the module
//! declares only what its stages read.

pub mod interior;
pub mod library;

use naga::{Binding, BuiltIn, Handle, Module, ShaderStage, TypeInner};

use crate::abi::{binding, Param, ProbeHit, ProbeRay, PROBE_WORKGROUP};
use crate::ir::{ModuleCtx, Stage, Ty, UVec3, Val, Vec2, Vec3, Vec4};
use crate::CompileError;
use crate::spec::{Pipeline, Slot, StageSpec};
use crate::stage::{self, Bracket, Filter, Hit, Ray};

/// A compiled pipeline: the module and its validation info.
pub struct Compiled {
    /// The module.
    pub module: Module,
    /// What naga's validator found out about it (the backends need it).
    pub info: naga::valid::ModuleInfo,
}

/// Struct types shared by the stage functions.
pub(crate) struct Types {
    pub(crate) ray: Handle<naga::Type>,
    pub(crate) bracket: Handle<naga::Type>,
    pub(crate) hit: Handle<naga::Type>,
}

fn f32_ty() -> TypeInner {
    f32::inner()
}

impl Types {
    pub(crate) fn new(m: &ModuleCtx) -> Self {
        Types {
            ray: m.struct_ty("Ray", &[("origin", Vec2::inner()), ("dir", Vec3::inner()), ("cos_view", f32_ty())]),
            bracket: m.struct_ty("Bracket", &[("above", f32_ty()), ("below", f32_ty()), ("found", bool::inner())]),
            hit: m.struct_ty("Hit", &[("t", f32_ty()), ("uv", Vec2::inner()), ("z", f32_ty()), ("found", bool::inner())]),
        }
    }
}

fn ray_from<'a>(s: &'a Stage<'a>, h: Handle<naga::Expression>) -> Ray<'a> {
    Ray { origin: s.field(h, 0), dir: s.field(h, 1), cos_view: s.field(h, 2) }
}
pub(crate) fn ray_value<'a>(s: &'a Stage<'a>, ty: &Types, r: &Ray<'a>) -> Handle<naga::Expression> {
    s.make_struct(ty.ray, &[r.origin.handle(), r.dir.handle(), r.cos_view.handle()])
}
pub(crate) fn hit_from<'a>(s: &'a Stage<'a>, h: Handle<naga::Expression>) -> Hit<'a> {
    Hit { t: s.field(h, 0), uv: s.field(h, 1), z: s.field(h, 2), found: s.field(h, 3) }
}
pub(crate) fn hit_value<'a>(s: &'a Stage<'a>, ty: &Types, h: &Hit<'a>) -> Handle<naga::Expression> {
    s.make_struct(ty.hit, &[h.t.handle(), h.uv.handle(), h.z.handle(), h.found.handle()])
}

/// The stage functions of one variant (plain or counted).
pub(crate) struct StageFns {
    pub(crate) trace: Handle<naga::Function>,
    pub(crate) shadow: Option<Handle<naga::Function>>,
    pub(crate) ao: Option<Handle<naga::Function>>,
}

fn fn_name(slot: Slot, spec: &StageSpec, counted: bool) -> String {
    let base = format!("{}_{}", slot.name(), spec.name);
    if counted {
        format!("{base}_counted")
    } else {
        base
    }
}

fn wrap_err(slot: Slot, spec: &StageSpec) -> impl Fn(CompileError) -> CompileError + '_ {
    move |mut e| {
        if !e.stage.starts_with(slot.name()) {
            e.stage = format!("{} {} ({})", slot.name(), spec.name, e.stage);
        }
        e
    }
}

pub(crate) fn build_stage_fns(m: &ModuleCtx, ty: &Types, p: &Pipeline, counted: bool) -> Result<StageFns, CompileError> {
    m.counting.set(counted);
    // coarse(ray) -> Bracket
    m.step_counter.set(crate::ir::counter::COARSE_STEPS);
    let coarse = {
        let s = m.function(&fn_name(Slot::Coarse, &p.coarse, counted), &[("ray", ty.ray, None)]);
        let arg = s.arg::<Vec4>(0).handle();
        let ray = ray_from(&s, arg);
        let b = stage::coarse::build(&s, &ray, &p.coarse).map_err(wrap_err(Slot::Coarse, &p.coarse))?;
        let v = s.make_struct(ty.bracket, &[b.above.handle(), b.below.handle(), b.found.handle()]);
        let f = s.finish(Some((ty.bracket, None, v)));
        m.add_function(f)
    };
    // refine(ray, bracket) -> Hit
    m.step_counter.set(crate::ir::counter::REFINE_STEPS);
    let refine = {
        let s = m.function(
            &fn_name(Slot::Refine, &p.refine, counted),
            &[("ray", ty.ray, None), ("bracket", ty.bracket, None)],
        );
        let ray = ray_from(&s, s.arg::<Vec4>(0).handle());
        let bh = s.arg::<Vec4>(1).handle();
        let b = Bracket::searched(s.field(bh, 0), s.field(bh, 1), s.field(bh, 2));
        let hit = stage::refine::build(&s, &ray, b, &p.refine).map_err(wrap_err(Slot::Refine, &p.refine))?;
        let v = hit_value(&s, ty, &hit);
        let f = s.finish(Some((ty.hit, None, v)));
        m.add_function(f)
    };
    // trace(ray) -> Hit: the refinement runs on a bracket that holds a crossing; a search
    // that found none ends at the last point it knew to be above the surface.
    let trace = {
        let name = if counted { "trace_counted" } else { "trace" };
        let s = m.function(name, &[("ray", ty.ray, None)]);
        let ray_h = s.arg::<Vec4>(0).handle();
        let b = s.call(coarse, &[ray_h], true).unwrap();
        let found: Val<bool> = s.field(b, 2);
        s.if_(!found, |s| {
            let ray = ray_from(s, ray_h);
            let above = Hit::at_found(&ray, s.field(b, 0), found);
            s.ret_handle(Some(hit_value(s, ty, &above)));
        });
        let h = s.call(refine, &[ray_h, b], true).unwrap();
        let f = s.finish(Some((ty.hit, None, h)));
        m.add_function(f)
    };
    m.counting.set(false);
    if counted {
        // The probe traces only: shadow and ao have no counted variant.
        return Ok(StageFns { trace, shadow: None, ao: None });
    }
    let shadow = if p.shadow.is_none() {
        None
    } else {
        let s = m.function(
            &fn_name(Slot::Shadow, &p.shadow, counted),
            &[("hit", ty.hit, None), ("light", m.ty(Vec3::inner()), None), ("light_cos", m.ty(f32::inner()), None)],
        );
        let hit = hit_from(&s, s.arg::<Vec4>(0).handle());
        let light = stage::Light { dir: s.arg::<Vec3>(1), cos: s.arg::<f32>(2) };
        let v = stage::shadow::build(&s, &hit, &light, &p.shadow).map_err(wrap_err(Slot::Shadow, &p.shadow))?;
        let f = s.finish(Some((m.ty(f32::inner()), None, v.handle())));
        Some(m.add_function(f))
    };
    let ao = if p.ao.is_none() {
        None
    } else {
        let s = m.function(&fn_name(Slot::Ao, &p.ao, counted), &[("hit", ty.hit, None)]);
        let hit = hit_from(&s, s.arg::<Vec4>(0).handle());
        let v = stage::ao::build(&s, &hit, &p.ao).map_err(wrap_err(Slot::Ao, &p.ao))?;
        let f = s.finish(Some((m.ty(f32::inner()), None, v.handle())));
        Some(m.add_function(f))
    };
    Ok(StageFns { trace, shadow, ao })
}

pub(crate) fn location(n: u32) -> Binding {
    Binding::Location {
        location: n,
        interpolation: Some(naga::Interpolation::Perspective),
        sampling: Some(naga::Sampling::Center),
        blend_src: None,
        per_primitive: false,
    }
}

/// An entry point of `stage` running `function` (`workgroup` is `[0; 3]` for render stages).
pub(crate) fn entry_point(name: &str, stage: ShaderStage, function: naga::Function, workgroup: [u32; 3]) -> naga::EntryPoint {
    naga::EntryPoint {
        name: name.into(),
        stage,
        early_depth_test: None,
        workgroup_size: workgroup,
        workgroup_size_overrides: None,
        function,
        mesh_info: None,
        task_payload: None,
        incoming_ray_payload: None,
    }
}

fn vertex_entry(m: &ModuleCtx) -> naga::EntryPoint {
    let out_ty = {
        let v4 = m.ty(Vec4::inner());
        let v2 = m.ty(Vec2::inner());
        let loc = location(0);
        m.module.borrow_mut().types.insert(
            naga::Type {
                name: Some("VertexOutput".into()),
                inner: TypeInner::Struct {
                    members: vec![
                        naga::StructMember {
                            name: Some("clip".into()),
                            ty: v4,
                            binding: Some(Binding::BuiltIn(BuiltIn::Position { invariant: false })),
                            offset: 0,
                        },
                        naga::StructMember { name: Some("world".into()), ty: v2, binding: Some(loc), offset: 16 },
                    ],
                    span: 32,
                },
            },
            naga::Span::UNDEFINED,
        )
    };
    let s = m.function(
        "vs_main",
        &[("vertex", m.ty(u32::inner()), Some(Binding::BuiltIn(BuiltIn::VertexIndex)))],
    );
    // Four vertices as a triangle strip: (0,0) (1,0) (0,1) (1,1), scaled to the quad's size.
    let i = s.arg::<u32>(0);
    let size = s.param::<Vec4>(Param::Quad).x();
    let corner = s.vec2(i.and(1).to_f32(), i.shift_right(1).to_f32()) * size;
    let clip = s.param::<crate::ir::Mat4>(Param::ViewProj) * s.vec4(s.vec3(corner, 0.0), 1.0);
    let out = s.make_struct(out_ty, &[clip.handle(), corner.handle()]);
    let f = s.finish(Some((out_ty, None, out)));
    entry_point("vs_main", ShaderStage::Vertex, f, [0; 3])
}

/// What a module is built with besides its pipeline.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Options {
    /// The fragment entry also writes the depth of the hit (a pixel depth offset): the NDC
    /// depth of the hit point `(uv, (z - 1)·depth_scale)` under `params.view_proj`, so that
    /// a depth buffer holds the relief's surface, not the quad's.
    pub frag_depth: bool,
}

/// The fragment output with a depth: `color @location(0)`, `depth @builtin(frag_depth)`.
fn fragment_output_with_depth(m: &ModuleCtx) -> Handle<naga::Type> {
    let v4 = m.ty(Vec4::inner());
    let f = m.ty(f32::inner());
    m.module.borrow_mut().types.insert(
        naga::Type {
            name: Some("FragmentOutput".into()),
            inner: TypeInner::Struct {
                members: vec![
                    naga::StructMember { name: Some("color".into()), ty: v4, binding: Some(location(0)), offset: 0 },
                    naga::StructMember { name: Some("depth".into()), ty: f, binding: Some(Binding::BuiltIn(BuiltIn::FragDepth)), offset: 16 },
                ],
                span: 32,
            },
        },
        naga::Span::UNDEFINED,
    )
}

fn fragment_entry(m: &ModuleCtx, ty: &Types, fns: &StageFns, options: &Options) -> naga::EntryPoint {
    let loc = location(0);
    let s = m.function("fs_main", &[("world", m.ty(Vec2::inner()), Some(loc))]);
    let world = s.arg::<Vec2>(0);
    let camera = s.param::<Vec4>(Param::Camera);
    let depth_scale = s.name("depth_scale", camera.w());
    // The view ray in tangent space, then scaled so that t = 1 reaches the bottom.
    let view = (s.vec3(world, 0.0) - camera.xyz()).normalize();
    let dir = s.vec3(view.xy() * (depth_scale / -view.z()), -1.0);
    let ray = Ray { origin: world, dir, cos_view: -view.z() };
    interior::store_view_distance(&s, (s.vec3(world, 0.0) - camera.xyz()).length());
    let rv = ray_value(&s, ty, &ray);
    let traced = hit_from(&s, s.call(fns.trace, &[rv], true).unwrap());
    // The pixel is drawn inside the volume whatever the search returned (the probe, not
    // this entry, measures the raw result).
    let hit = Hit::at_found(&ray, traced.t.clamp(0.0, ray.t_max()), traced.found);
    let hv = hit_value(&s, ty, &hit);

    let light = s.param::<Vec4>(Param::Light);
    let to_light = light.xyz();
    let ambient = light.w();
    let visibility = match fns.shadow {
        Some(f) => {
            let light_n = s.vec3(to_light.xy() * (depth_scale / to_light.z().max(1e-3)), 1.0);
            s.wrap::<f32>(s.call(f, &[hv, light_n.handle(), to_light.z().handle()], true).unwrap())
        }
        None => s.lit(1.0),
    };
    let occlusion = match fns.ao {
        Some(f) => s.wrap::<f32>(s.call(f, &[hv], true).unwrap()),
        None => s.lit(1.0),
    };
    let normal = s.normal(hit.uv);
    let albedo = s.sample("albedo_map", binding::ALBEDO, hit.uv, Filter::Linear).xyz();
    let diffuse = normal.dot(to_light).max(0.0);
    let color = albedo * (ambient * occlusion + (1.0 - ambient) * diffuse * visibility);
    let out = s.vec4(color, 1.0);
    let f = if options.frag_depth {
        let world_hit = s.vec3(hit.uv, (hit.z - 1.0) * depth_scale);
        let clip = s.param::<crate::ir::Mat4>(Param::ViewProj) * s.vec4(world_hit, 1.0);
        let depth = clip.z() / clip.w();
        let out_ty = fragment_output_with_depth(m);
        let v = s.make_struct(out_ty, &[out.handle(), depth.handle()]);
        s.finish(Some((out_ty, None, v)))
    } else {
        s.finish(Some((m.ty(Vec4::inner()), Some(location(0)), out.handle())))
    };
    entry_point("fs_main", ShaderStage::Fragment, f, [0; 3])
}

pub(crate) fn storage_array(m: &ModuleCtx, name: &str, item: Handle<naga::Type>, binding: u32, write: bool) -> Handle<naga::GlobalVariable> {
    m.global(name, |m| {
        let (stride, _) = match &m.module.borrow().types[item].inner {
            TypeInner::Struct { span, .. } => (*span, 0),
            _ => unreachable!("probe records are structs"),
        };
        let arr = m.ty(TypeInner::Array { base: item, size: naga::ArraySize::Dynamic, stride });
        let access = if write {
            naga::StorageAccess::LOAD | naga::StorageAccess::STORE
        } else {
            naga::StorageAccess::LOAD
        };
        naga::GlobalVariable {
            name: Some(name.to_string()),
            space: naga::AddressSpace::Storage { access },
            binding: Some(naga::ResourceBinding { group: 0, binding }),
            ty: arr,
            init: None,
            memory_decorations: Default::default(),
        }
    })
}

fn probe_entry(m: &ModuleCtx, ty: &Types, fns: &StageFns) -> naga::EntryPoint {
    let ray_rec = m.record_ty("ProbeRay", &ProbeRay::MEMBERS);
    let hit_rec = m.record_ty("ProbeHit", &ProbeHit::MEMBERS);
    let rays = storage_array(m, "rays", ray_rec, binding::RAYS, false);
    let hits = storage_array(m, "hits", hit_rec, binding::HITS, true);
    use crate::ir::counter;
    let counters = [counter::COARSE_STEPS, counter::REFINE_STEPS, counter::FETCHES].map(|name| {
        m.global(name, |m| naga::GlobalVariable {
            name: Some(name.into()),
            space: naga::AddressSpace::Private,
            binding: None,
            ty: m.ty(u32::inner()),
            init: None,
            memory_decorations: Default::default(),
        })
    });

    let s = m.function(
        "probe",
        &[("id", m.ty(UVec3::inner()), Some(Binding::BuiltIn(BuiltIn::GlobalInvocationId)))],
    );
    let index = s.arg::<UVec3>(0).x();
    let rays_ptr = s.global_ptr(rays);
    s.if_(index.ge(s.array_length(rays_ptr)), |s| s.ret());
    let rec = s.element_ptr(rays_ptr, index.handle());
    let origin = s.load::<Vec2>(s.member_ptr(rec, 0));
    let dir_xy = s.load::<Vec2>(s.member_ptr(rec, 1));
    let dir_z = s.load::<f32>(s.member_ptr(rec, 2));
    let depth_scale = s.param::<Vec4>(Param::Camera).w();
    // The same cosine the render entry gets from the camera: the unscaled view ray is
    // (dir.xy, dir.z · depth_scale).
    let vz = dir_z * depth_scale;
    let cos_view = -vz / (dir_xy.dot(dir_xy) + vz * vz).sqrt();
    let ray = Ray { origin, dir: s.vec3(dir_xy, dir_z), cos_view };
    for c in counters {
        let zero = s.lit_u32(0);
        s.store(s.global_ptr(c), zero.handle());
    }
    // The camera distance for stages that read it: from the camera to the ray's entry.
    let camera = s.param::<Vec4>(Param::Camera).xyz();
    interior::store_view_distance(&s, (s.vec3(origin, 0.0) - camera).length());
    let rv = ray_value(&s, ty, &ray);
    let hit = hit_from(&s, s.call(fns.trace, &[rv], true).unwrap());
    let out = s.element_ptr(s.global_ptr(hits), index.handle());
    let [coarse_steps, refine_steps, fetches] = counters.map(|c| s.load::<u32>(s.global_ptr(c)));
    let converged = s.select(hit.found, 1u32, 0u32);
    let values = [
        hit.t.handle(),
        hit.uv.x().handle(),
        hit.uv.y().handle(),
        hit.z.handle(),
        coarse_steps.handle(),
        refine_steps.handle(),
        fetches.handle(),
        converged.handle(),
    ];
    for (i, v) in values.into_iter().enumerate() {
        s.store(s.member_ptr(out, i as u32), v);
    }
    let f = s.finish(None);
    entry_point("probe", ShaderStage::Compute, f, [PROBE_WORKGROUP, 1, 1])
}

/// Builds the module for `p` (not yet validated).
pub fn build_module(p: &Pipeline) -> Result<Module, CompileError> {
    build_module_with(p, &Options::default())
}

/// Builds the module for `p` with `options` (not yet validated).
pub fn build_module_with(p: &Pipeline, options: &Options) -> Result<Module, CompileError> {
    let m = ModuleCtx::new();
    let ty = Types::new(&m);
    let plain = build_stage_fns(&m, &ty, p, false)?;
    let counted = build_stage_fns(&m, &ty, p, true)?;
    let vs = vertex_entry(&m);
    let fs = fragment_entry(&m, &ty, &plain, options);
    let cs = probe_entry(&m, &ty, &counted);
    let mut module = m.finish();
    module.entry_points.extend([vs, fs, cs]);
    Ok(module)
}

/// Builds and validates the module for `p`.
pub fn compile(p: &Pipeline) -> Result<Compiled, CompileError> {
    compile_with(p, &Options::default())
}

/// Builds and validates the module for `p` with `options`.
pub fn compile_with(p: &Pipeline, options: &Options) -> Result<Compiled, CompileError> {
    let module = build_module_with(p, options)?;
    let info = validate(&module)?;
    Ok(Compiled { module, info })
}

/// Runs naga's validator, the single authority on what a module may be.
pub fn validate(module: &Module) -> Result<naga::valid::ModuleInfo, CompileError> {
    naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::default())
        .validate(module)
        .map_err(|e| CompileError { stage: "validation".into(), message: format!("{:?}", e.into_inner()) })
}

/// Names of the resources the module declares (for tests and `required_maps` checks).
pub fn declared_resources(module: &Module) -> Vec<String> {
    module
        .global_variables
        .iter()
        .filter(|(_, g)| g.binding.is_some())
        .filter_map(|(_, g)| g.name.clone())
        .collect()
}
