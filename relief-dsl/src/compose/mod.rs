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
//! A pipeline with `curved=…` is a *mesh module* instead ([`mesh`]): a vertex entry taking
//! [`mesh::MeshVertex`], a fragment entry writing colour and depth, and a depth-only entry.
//!
//! Resources are declared when a stage first reads them (see [`binding`]), so the module
//! declares only what its stages read.

pub mod interior;
pub mod library;
pub mod mesh;

use naga::{Binding, BuiltIn, Handle, Module, ShaderStage, TypeInner};

use crate::abi::{binding, Param, ProbeHit, ProbeRay, PROBE_WORKGROUP};
use crate::ir::{
    Bindings, Counting, FnBuilder, Image, ModuleCtx, Plain, Policy, Resource, Ty, UVec3, Val, Vec2, Vec3, Vec4,
};
use crate::spec::{Pipeline, Silhouette, Slot, StageSpec};
use crate::stage::{self, Bracket, Filter, Hit, Ray};
use crate::CompileError;

/// A compiled pipeline: the module, its validation info and what each binding holds.
pub struct Compiled {
    /// The module.
    pub module: Module,
    /// What naga's validator found out about it (the backends need it).
    pub info: naga::valid::ModuleInfo,
    /// What each binding of the module holds, as the stages declared it: the table a
    /// runtime binds by.
    pub bindings: Bindings,
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

/// The error for a stage that read something with no level under `lod` other than zero
/// (what the sampling methods of its function noted, [`FnBuilder::take_no_level`]): never a
/// silent level 0.
fn check_lod(s: &FnBuilder<'_>, slot: Slot, spec: &StageSpec) -> Result<(), CompileError> {
    let what = s.take_no_level();
    if what.is_empty() {
        return Ok(());
    }
    Err(CompileError {
        stage: format!("{} {}", slot.name(), spec.name),
        message: format!(
            "`{}` does not support lod={} yet: it reads {}, which has no mip chain of the level's own surface (built over level 0 of the height map)",
            spec.name,
            s.policy().lod(),
            what.join(", ")
        ),
    })
}

/// Writes the stage functions of `p` and `trace` under `base` (relief's own [`Plain`], a
/// library's constant edge, a room's wall), or, `counted`, the probe's copies, which count
/// under [`Counting`] around `base`: the coarse stage's passes apart from the refine stage's.
pub(crate) fn write_stage_fns(
    m: &ModuleCtx,
    p: &Pipeline,
    base: &dyn Policy,
    counted: bool,
) -> Result<StageFns, CompileError> {
    let coarse_policy = Counting { inner: base, steps: crate::ir::counter::COARSE_STEPS };
    let refine_policy = Counting { inner: base, steps: crate::ir::counter::REFINE_STEPS };
    let (coarse_policy, refine_policy): (&dyn Policy, &dyn Policy) =
        if counted { (&coarse_policy, &refine_policy) } else { (base, base) };
    let ray_ty = m.record_type::<Ray>();
    let hit_ty = m.record_type::<Hit>();
    // coarse(ray) -> Bracket
    let coarse = {
        let s = m.function(&fn_name(Slot::Coarse, &p.coarse, counted), &[("ray", ray_ty, None)], coarse_policy);
        let ray: Ray = s.arg_record(0);
        let b = stage::coarse(&s, &ray, &p.coarse).map_err(wrap_err(Slot::Coarse, &p.coarse))?;
        check_lod(&s, Slot::Coarse, &p.coarse)?;
        m.add_function(s.finish_record(&b))
    };
    // refine(ray, bracket) -> Hit
    let refine = {
        let s = m.function(
            &fn_name(Slot::Refine, &p.refine, counted),
            &[("ray", ray_ty, None), ("bracket", m.record_type::<Bracket>(), None)],
            refine_policy,
        );
        let ray: Ray = s.arg_record(0);
        let b: Bracket = s.arg_record(1);
        let hit = stage::refine(&s, &ray, b, &p.refine).map_err(wrap_err(Slot::Refine, &p.refine))?;
        check_lod(&s, Slot::Refine, &p.refine)?;
        m.add_function(s.finish_record(&hit))
    };
    // trace(ray) -> Hit: the refinement runs on a bracket that holds a crossing; a search
    // that found none ends at the last point it knew to be above the surface.
    let trace = {
        let name = if counted { "trace_counted" } else { "trace" };
        let s = m.function(name, &[("ray", ray_ty, None)], base);
        let ray_h = s.arg::<Vec4>(0).handle();
        let b_h = s.call(coarse, &[ray_h], true).unwrap();
        let b: Bracket = s.unpack(b_h);
        s.if_(!b.found, |s| {
            let ray: Ray = s.unpack(ray_h);
            let above = Hit::at_found(&ray, b.above, b.found);
            s.ret_handle(Some(s.pack(&above)));
        });
        let h = s.call(refine, &[ray_h, b_h], true).unwrap();
        let f = s.finish(Some((m.record_type::<Hit>(), None, h)));
        m.add_function(f)
    };
    if counted {
        // The probe traces only: shadow and ao have no counted variant.
        return Ok(StageFns { trace, shadow: None, ao: None });
    }
    let shadow = if p.shadow.is_none() {
        None
    } else {
        let s = m.function(
            &fn_name(Slot::Shadow, &p.shadow, counted),
            &[("hit", hit_ty, None), ("light", m.ty(Vec3::inner()), None), ("light_cos", m.ty(f32::inner()), None)],
            base,
        );
        let hit: Hit = s.arg_record(0);
        let light = stage::Light { dir: s.arg::<Vec3>(1), cos: s.arg::<f32>(2) };
        let v = stage::shadow(&s, &hit, &light, &p.shadow).map_err(wrap_err(Slot::Shadow, &p.shadow))?;
        check_lod(&s, Slot::Shadow, &p.shadow)?;
        let f = s.finish(Some((m.ty(f32::inner()), None, v.handle())));
        Some(m.add_function(f))
    };
    let ao = if p.ao.is_none() {
        None
    } else {
        let s = m.function(&fn_name(Slot::Ao, &p.ao, counted), &[("hit", hit_ty, None)], base);
        let hit: Hit = s.arg_record(0);
        let v = stage::ao(&s, &hit, &p.ao).map_err(wrap_err(Slot::Ao, &p.ao))?;
        check_lod(&s, Slot::Ao, &p.ao)?;
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
pub(crate) fn entry_point(
    name: &str,
    stage: ShaderStage,
    function: naga::Function,
    workgroup: [u32; 3],
) -> naga::EntryPoint {
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

/// A vertex entry `name`'s function: one argument, the vertex index. Both render pairs (this
/// module's quad, a room's window) draw one quad as a triangle strip of four vertices.
pub(crate) fn vertex_function<'a>(m: &'a ModuleCtx, name: &str, policy: &'a dyn Policy) -> FnBuilder<'a> {
    m.function(name, &[("vertex", m.ty(u32::inner()), Some(Binding::BuiltIn(BuiltIn::VertexIndex)))], policy)
}

/// Ends the vertex entry `name` built in `s`: it returns the struct `out_name` of the clip
/// position `clip` and the point `world` (at location 0), which the fragment entry reads.
pub(crate) fn finish_vertex<'a, T: Ty>(
    s: &'a FnBuilder<'a>,
    name: &str,
    out_name: &str,
    clip: Val<'a, Vec4>,
    world: Val<'a, T>,
) -> naga::EntryPoint {
    let m = s.module();
    let (v4, world_ty) = (m.ty(Vec4::inner()), m.ty(T::inner()));
    let position = Binding::BuiltIn(BuiltIn::Position { invariant: false });
    let members = vec![
        naga::StructMember { name: Some("clip".into()), ty: v4, binding: Some(position), offset: 0 },
        naga::StructMember { name: Some("world".into()), ty: world_ty, binding: Some(location(0)), offset: 16 },
    ];
    let out_ty = m.module.borrow_mut().types.insert(
        naga::Type { name: Some(out_name.into()), inner: TypeInner::Struct { members, span: 32 } },
        naga::Span::UNDEFINED,
    );
    let out = s.make_struct(out_ty, &[clip.handle(), world.handle()]);
    let f = s.finish(Some((out_ty, None, out)));
    entry_point(name, ShaderStage::Vertex, f, [0; 3])
}

fn vertex_entry(m: &ModuleCtx, policy: &dyn Policy) -> naga::EntryPoint {
    let s = vertex_function(m, "vs_main", policy);
    // Four vertices as a triangle strip: (0,0) (1,0) (0,1) (1,1), scaled to the quad's size.
    let i = s.arg::<u32>(0);
    let size = s.param::<Vec4>(Param::Quad).x();
    let corner = s.vec2(i.and(1).to_f32(), i.shift_right(1).to_f32()) * size;
    let clip = s.param::<crate::ir::Mat4>(Param::ViewProj) * s.vec4(s.vec3(corner, 0.0), 1.0);
    finish_vertex(&s, "vs_main", "VertexOutput", clip, corner)
}

/// The footprint level: `relief_lod_level(entry, pixel_size) -> f32`, the mip level every
/// sample of a pixel is taken at, from the point `entry` where the pixel's ray enters the
/// volume (on the polygon, z = 0 in world = tangent space) and the pixel's size δ (the
/// render entry's from `Params::pixel_right.w`, the probe's from its ray record,
/// `ProbeRay::pixel_size`). `None` under `lod=zero`. Both entry points
/// call this one function and store its result in the stage-wide level
/// ([`stage::sampling::SAMPLE_LEVEL`]) before they trace; the probe's rays are the render's pixels, so
/// the probe finds the level of the pixel the ray belongs to.
///
/// `lod=level(k)` is `min(k, levels − 1)`. For `lod=auto` the level is derived from the
/// camera (`relief-runtime`'s `scene::camera`: a pinhole at E with unit basis forward f,
/// right r, up u in `Params::pixel_right`/`pixel_up`, square pixels of size δ =
/// 2·tan(fov_y/2)/H on the image plane at unit distance), not from screen-space derivatives, which a
/// compute entry lacks:
///
/// - the ray through image-plane point (a, b) is E + s·q with q = f + a·r + b·u, and meets
///   the plane z = 0 at P(a, b) = E + s·q, s = −E.z / q.z;
/// - differentiating, ∂P/∂a = s·(r − q·r.z/q.z), and with D = P − E = s·q (so s = D·f, since
///   q·f = 1) this is ∂P/∂a = (D·f)·(r − D·r.z/D.z); likewise ∂P/∂b with u. Both lie in the
///   plane (their z is 0);
/// - one pixel moves a and b by δ, so the pixel's footprint in texels is spanned by
///   δ·∂P/∂a and δ·∂P/∂b scaled by the map's size (w, h) (uv is in texture units);
/// - as a GPU's trilinear filter does, λ = log2 of the longer of the two, and the level is
///   `clamp(round(λ), 0, levels − 1)` (round half to even): one whole level, so the surface
///   the stages sample is that level's bilinear surface.
///
/// The CPU twin is `Camera::footprint_lambda` in relief-runtime (the reference traces each
/// ray on the level it gives).
fn lod_level_fn(m: &ModuleCtx, policy: &dyn Policy) -> Option<Handle<naga::Function>> {
    use crate::spec::Lod;
    let lod = policy.lod();
    if lod == Lod::Zero {
        return None;
    }
    let s = m.function(
        "relief_lod_level",
        &[("entry", m.ty(Vec2::inner()), None), ("pixel_size", m.ty(f32::inner()), None)],
        policy,
    );
    let entry = s.arg::<Vec2>(0);
    let delta = s.arg::<f32>(1);
    let last = s.height_map_levels() - 1.0;
    let level = match lod {
        Lod::Zero => unreachable!("handled above"),
        Lod::Level(k) => s.lit(f32::from(k)).min(last),
        Lod::Auto => {
            let eye = s.param::<Vec4>(Param::Camera).xyz();
            let right = s.param::<Vec4>(Param::PixelRight).xyz();
            let up = s.param::<Vec4>(Param::PixelUp).xyz();
            let d = s.vec3(entry, 0.0) - eye;
            let dist = d.dot(up.cross(right));
            let size = s.height_map_size();
            let dx = (right - d * (right.z() / d.z())) * (dist * delta);
            let dy = (up - d * (up.z() / d.z())) * (dist * delta);
            let extent = (dx.xy() * size).length().max((dy.xy() * size).length());
            s.name("lod_lambda", extent.log2()).round().clamp(s.lit(0.0), last)
        }
    };
    let f = s.finish(Some((m.ty(f32::inner()), None, level.handle())));
    Some(m.add_function(f))
}

/// Stores the pixel's level ([`lod_level_fn`]) in the stage-wide level, before tracing.
fn set_sample_level<'a>(
    s: &'a FnBuilder<'a>,
    lod: Option<Handle<naga::Function>>,
    entry: Val<'a, Vec2>,
    pixel_size: impl FnOnce() -> Val<'a, f32>,
) {
    if let Some(f) = lod {
        let level = s.call(f, &[entry.handle(), pixel_size().handle()], true).unwrap();
        s.store(s.global_ptr(stage::sample_level_global(s.module())), level);
    }
}

/// What a module is built with besides its pipeline.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Options {
    /// The fragment entry also writes the depth of the hit (a pixel depth offset): the NDC
    /// depth of the hit point `(uv, (z - 1)·depth_scale)` under `params.view_proj`, so that
    /// a depth buffer holds the relief's surface, not the quad's.
    pub frag_depth: bool,
    /// A mesh module (`curved=`) also gets the measurement entry
    /// [`mesh::PROBE_ENTRY`] (`fs_mesh_probe`, docs/meshes-shaders.md); the other entries are
    /// the same with or without it. Ignored for a flat-tile module.
    pub mesh_probe: bool,
    /// A `curved=prism` module walks from prism to prism along the ray (the runtime's form,
    /// `compose::mesh`'s "The prism walk"): it reads the triangles' corners and neighbours from
    /// a storage buffer ([`crate::abi::binding::PRISM_CELLS`], [`mesh::PrismCell`]), and the
    /// runtime draws only the prisms' tops and unsealed walls. Off: every face of every
    /// prism is drawn and runs its own trace (the library form). Ignored for other modules.
    pub prism_walk: bool,
    /// A walking module searches every prism's chord with all of its linear search's layers,
    /// as the unwalked draw does, instead of the chord's share of them (`compose::mesh`'s
    /// `chord_share`): the check that the walk meets what the unwalked draw meets. Ignored
    /// where the module does not walk.
    pub prism_walk_all_layers: bool,
    /// The safe marches that read the patch map (`cell_patch`, `MapReq::patches_read_with`)
    /// gather their cells' corners instead, as they did before the patch map: the check that
    /// both give the same hits bit for bit (relief-runtime's `cones` tests). The pipeline's
    /// `required_maps` still name the patch map; this module does not read it. Ignored for a
    /// mesh module.
    pub cell_patch_gather: bool,
}

/// Whether the hit's (u, v) lies outside the quad's square `[0, tiling]²` (`params.quad.x`
/// is the tiling): the test of `silhouette=clip`, the same in the fragment and the probe.
///
/// Under `silhouette=clip` a hit outside the square is no hit: the fragment entry discards
/// the pixel, so the relief's outline shows at the edge of the quad, and the probe reports
/// the raw hit with `clipped = 1`. Meant for scenes with clamp edges (the runtime refuses
/// repeat edges).
fn outside_square<'a>(s: &'a FnBuilder<'a>, uv: Val<'a, Vec2>) -> Val<'a, bool> {
    let tiling = s.param::<Vec4>(Param::Quad).x();
    uv.x().lt(0.0) | uv.y().lt(0.0) | uv.x().gt(tiling) | uv.y().gt(tiling)
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
                    naga::StructMember {
                        name: Some("depth".into()),
                        ty: f,
                        binding: Some(Binding::BuiltIn(BuiltIn::FragDepth)),
                        offset: 16,
                    },
                ],
                span: 32,
            },
        },
        naga::Span::UNDEFINED,
    )
}

fn fragment_entry(
    m: &ModuleCtx,
    policy: &dyn Policy,
    fns: &StageFns,
    options: &Options,
    clip: bool,
    lod: Option<Handle<naga::Function>>,
) -> naga::EntryPoint {
    let loc = location(0);
    let s = m.function("fs_main", &[("world", m.ty(Vec2::inner()), Some(loc))], policy);
    let world = s.arg::<Vec2>(0);
    let camera = s.param::<Vec4>(Param::Camera);
    let depth_scale = s.name("depth_scale", camera.w());
    // The view ray in tangent space, then scaled so that t = 1 reaches the bottom.
    let view = (s.vec3(world, 0.0) - camera.xyz()).normalize();
    let dir = s.vec3(view.xy() * (depth_scale / -view.z()), -1.0);
    let ray = Ray { origin: world, dir, cos_view: -view.z() };
    set_sample_level(&s, lod, world, || s.param::<Vec4>(Param::PixelRight).w());
    interior::store_view_distance(&s, (s.vec3(world, 0.0) - camera.xyz()).length());
    let traced: Hit = s.unpack(s.call(fns.trace, &[s.pack(&ray)], true).unwrap());
    if clip {
        s.if_(outside_square(&s, traced.uv), |s| s.discard());
    }
    // The pixel is drawn inside the volume whatever the search returned (the probe, not
    // this entry, measures the raw result).
    let hit = Hit::at_found(&ray, traced.t.clamp(0.0, ray.t_max()), traced.found);
    let hv = s.pack(&hit);

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
    let albedo = s.sample(Image::Albedo, hit.uv, Filter::Linear).xyz();
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

/// The probe's array `name` of `R` records: its rays (read, at [`binding::RAYS`]) or, `hits`,
/// its hits (written, at [`binding::HITS`]).
fn storage_array<R: crate::abi::AbiRecord>(m: &ModuleCtx, name: &str, hits: bool) -> Handle<naga::GlobalVariable> {
    let item = m.record_ty::<R>();
    let (binding, resource, access) = if hits {
        (binding::HITS, Resource::Hits, naga::StorageAccess::LOAD | naga::StorageAccess::STORE)
    } else {
        (binding::RAYS, Resource::Rays, naga::StorageAccess::LOAD)
    };
    m.bound(name, naga::AddressSpace::Storage { access }, binding, resource, |m| {
        let (stride, _) = match &m.module.borrow().types[item].inner {
            TypeInner::Struct { span, .. } => (*span, 0),
            _ => unreachable!("probe records are structs"),
        };
        m.ty(TypeInner::Array { base: item, size: naga::ArraySize::Dynamic, stride })
    })
}

/// The probe's private counters (coarse steps, refine steps, fetches), which the counted
/// stage functions increment; an entry zeroes them per ray and stores them in its hit.
fn probe_counters(m: &ModuleCtx) -> [Handle<naga::GlobalVariable>; 3] {
    use crate::ir::counter;
    [counter::COARSE_STEPS, counter::REFINE_STEPS, counter::FETCHES].map(|name| m.private::<u32>(name))
}

/// The buffers and counters a probe entry reads and writes: its array of ray records, its
/// array of hit records and the counters.
pub(crate) struct ProbeIo {
    rays: Handle<naga::GlobalVariable>,
    hits: Handle<naga::GlobalVariable>,
    counters: [Handle<naga::GlobalVariable>; 3],
}

impl ProbeIo {
    /// The probe's array `rays` of `R` records at [`binding::RAYS`], its array `hits` of `H`
    /// records at [`binding::HITS`], and the counters.
    pub(crate) fn new<R: crate::abi::AbiRecord, H: crate::abi::AbiRecord>(
        m: &ModuleCtx,
        rays: &str,
        hits: &str,
    ) -> ProbeIo {
        ProbeIo {
            rays: storage_array::<R>(m, rays, false),
            hits: storage_array::<H>(m, hits, true),
            counters: probe_counters(m),
        }
    }
}

/// Where a probe invocation reads and writes: pointers to its ray record and its hit record,
/// and the counters, zeroed.
pub(crate) struct ProbeSlot {
    /// The ray record (a pointer).
    pub(crate) ray: Handle<naga::Expression>,
    /// The hit record (a pointer).
    pub(crate) hit: Handle<naga::Expression>,
    /// Coarse steps, refine steps, fetches.
    pub(crate) counters: [Handle<naga::GlobalVariable>; 3],
}

/// A probe entry `name`'s function: one argument, the invocation id, one ray per invocation.
pub(crate) fn probe_function<'a>(m: &'a ModuleCtx, name: &str, policy: &'a dyn Policy) -> FnBuilder<'a> {
    m.function(name, &[("id", m.ty(UVec3::inner()), Some(Binding::BuiltIn(BuiltIn::GlobalInvocationId)))], policy)
}

/// The start every probe entry shares: an invocation past the last ray returns; the others
/// get their ray and hit records, with the counters zeroed for the ray.
pub(crate) fn probe_start<'a>(s: &'a FnBuilder<'a>, io: &ProbeIo) -> ProbeSlot {
    let index = s.arg::<UVec3>(0).x();
    let rays_ptr = s.global_ptr(io.rays);
    s.if_(index.ge(s.array_length(rays_ptr)), |s| s.ret());
    for c in io.counters {
        let zero = s.lit_u32(0);
        s.store(s.global_ptr(c), zero.handle());
    }
    ProbeSlot {
        ray: s.element_ptr(rays_ptr, index.handle()),
        hit: s.element_ptr(s.global_ptr(io.hits), index.handle()),
        counters: io.counters,
    }
}

/// What a probe reports of one ray: the counted trace's hit, its counters and whether its
/// coarse search converged (1) or not (0).
pub(crate) struct ProbeTrace<'a> {
    pub(crate) hit: Hit<'a>,
    pub(crate) coarse_steps: Val<'a, u32>,
    pub(crate) refine_steps: Val<'a, u32>,
    pub(crate) fetches: Val<'a, u32>,
    pub(crate) converged: Val<'a, u32>,
}

/// Traces `ray` with the counted `trace` and reads the counters after it.
pub(crate) fn probe_trace<'a>(
    s: &'a FnBuilder<'a>,
    trace: Handle<naga::Function>,
    ray: &Ray<'a>,
    counters: [Handle<naga::GlobalVariable>; 3],
) -> ProbeTrace<'a> {
    let hit: Hit = s.unpack(s.call(trace, &[s.pack(ray)], true).unwrap());
    let [coarse_steps, refine_steps, fetches] = counters.map(|c| s.load::<u32>(s.global_ptr(c)));
    let converged = s.select(hit.found, 1u32, 0u32);
    ProbeTrace { hit, coarse_steps, refine_steps, fetches, converged }
}

/// Ends the probe entry `name` built in `s`.
pub(crate) fn finish_probe(s: &FnBuilder<'_>, name: &str) -> naga::EntryPoint {
    let f = s.finish(None);
    entry_point(name, ShaderStage::Compute, f, [PROBE_WORKGROUP, 1, 1])
}

fn probe_entry(
    m: &ModuleCtx,
    policy: &dyn Policy,
    fns: &StageFns,
    clip: bool,
    lod: Option<Handle<naga::Function>>,
) -> naga::EntryPoint {
    let io = ProbeIo::new::<ProbeRay, ProbeHit>(m, "rays", "hits");
    let s = probe_function(m, "probe", policy);
    let ProbeSlot { ray: rec, hit: out, counters } = probe_start(&s, &io);
    let origin = s.load::<Vec2>(s.member_ptr::<ProbeRay>(rec, "origin"));
    let dir_xy = s.load::<Vec2>(s.member_ptr::<ProbeRay>(rec, "dir_xy"));
    let dir_z = s.load::<f32>(s.member_ptr::<ProbeRay>(rec, "dir_z"));
    let depth_scale = s.param::<Vec4>(Param::Camera).w();
    // The same cosine the render entry gets from the camera: the unscaled view ray is
    // (dir.xy, dir.z · depth_scale).
    let vz = dir_z * depth_scale;
    let cos_view = -vz / (dir_xy.dot(dir_xy) + vz * vz).sqrt();
    let ray = Ray { origin, dir: s.vec3(dir_xy, dir_z), cos_view };
    set_sample_level(&s, lod, origin, || s.load::<f32>(s.member_ptr::<ProbeRay>(rec, "pixel_size")));
    // The camera distance for stages that read it: from the camera to the ray's entry.
    let camera = s.param::<Vec4>(Param::Camera).xyz();
    interior::store_view_distance(&s, (s.vec3(origin, 0.0) - camera).length());
    let ProbeTrace { hit, coarse_steps, refine_steps, fetches, converged } = probe_trace(&s, fns.trace, &ray, counters);
    let clipped = if clip { s.select(outside_square(&s, hit.uv), 1u32, 0u32) } else { s.lit_u32(0) };
    let values = [
        ("t", hit.t.handle()),
        ("u", hit.uv.x().handle()),
        ("v", hit.uv.y().handle()),
        ("z", hit.z.handle()),
        ("coarse_steps", coarse_steps.handle()),
        ("refine_steps", refine_steps.handle()),
        ("fetches", fetches.handle()),
        ("converged", converged.handle()),
        ("clipped", clipped.handle()),
    ];
    s.store_record::<ProbeHit>(out, &values);
    finish_probe(&s, "probe")
}

/// Builds the module for `p` (not yet validated).
pub fn compose_module(p: &Pipeline) -> Result<Module, CompileError> {
    Ok(compose_module_with(p, &Options::default())?.0)
}

/// The module's bindings declared twice, as the composer's error.
pub(crate) fn finish(m: ModuleCtx) -> Result<(Module, Bindings), CompileError> {
    m.finish().map_err(|message| CompileError { stage: "bindings".into(), message })
}

/// Builds the module for `p` with `options` (not yet validated), with its binding table.
pub(crate) fn compose_module_with(p: &Pipeline, options: &Options) -> Result<(Module, Bindings), CompileError> {
    if let Some(curved) = p.curved {
        return mesh::compose_mesh(p, curved, options.mesh_probe, options.prism_walk, !options.prism_walk_all_layers);
    }
    let m = ModuleCtx::new();
    let policy = Plain { lod: p.lod, gather_patches: options.cell_patch_gather };
    let plain = write_stage_fns(&m, p, &policy, false)?;
    let counted = write_stage_fns(&m, p, &policy, true)?;
    let lod = lod_level_fn(&m, &policy);
    let clip = p.silhouette == Silhouette::Clip;
    let vs = vertex_entry(&m, &policy);
    let fs = fragment_entry(&m, &policy, &plain, options, clip, lod);
    let cs = probe_entry(&m, &policy, &counted, clip, lod);
    let (mut module, bindings) = finish(m)?;
    module.entry_points.extend([vs, fs, cs]);
    Ok((module, bindings))
}

/// Builds and validates the module for `p`.
pub fn compile(p: &Pipeline) -> Result<Compiled, CompileError> {
    compile_with(p, &Options::default())
}

/// Builds and validates the module for `p` with `options`.
pub fn compile_with(p: &Pipeline, options: &Options) -> Result<Compiled, CompileError> {
    let (module, bindings) = compose_module_with(p, options)?;
    let info = validate(&module)?;
    Ok(Compiled { module, info, bindings })
}

/// Runs naga's validator, the single authority on what a module may be.
pub fn validate(module: &Module) -> Result<naga::valid::ModuleInfo, CompileError> {
    naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::default())
        .validate(module)
        .map_err(|e| CompileError { stage: "validation".into(), message: format!("{:?}", e.into_inner()) })
}

/// Names of the resources the module declares (for tests and `required_maps` checks).
pub fn declared_resources(module: &Module) -> Vec<String> {
    module.global_variables.iter().filter(|(_, g)| g.binding.is_some()).filter_map(|(_, g)| g.name.clone()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wgsl(text: &str) -> Result<String, CompileError> {
        let p: Pipeline = text.parse().unwrap();
        let c = compile(&p)?;
        Ok(naga::back::wgsl::write_string(&c.module, &c.info, naga::back::wgsl::WriterFlags::empty()).unwrap())
    }

    #[test]
    fn sampling_at_a_level_validates_for_the_methods_that_support_it() {
        for text in [
            "linear(32)+binary(5)+lod=auto",
            "linear(400)+interval(8)+lod=level(2)",
            "linear_dynamic(8, 32)+secant(4)+lod=auto",
            "parallax+lod=auto",
            "offset_limited+lod=level(1)",
            "slope_parallax+lod=auto",
            "iterative_parallax(4)+binary(3)+lod=auto",
            "linear(16)+binary(3)+shadow=hard(16)+lod=auto",
            "linear(16)+binary(3)+shadow=soft(16)+lod=level(3)",
            "csm(15, form=textbook)+binary(5)+lod=auto",
            "csm(15, form=textbook, sample=min4)+lod=level(1)",
            "rcs(15, form=textbook)+lod=auto",
            "linear(16)+shadow=soft_cone(8)+lod=auto",
        ] {
            let src = wgsl(text).unwrap_or_else(|e| panic!("{text}: {e}"));
            // Every sample reads the stage-wide level; no sample is left at level 0.
            assert!(src.contains("relief_sample_level"), "{text}");
            assert!(src.contains("fn relief_lod_level("), "{text}");
            assert!(!src.contains("textureSampleLevel(height_map, linear_sampler, ray.origin, 0f)"), "{text}");
            assert!(!src.contains("textureGather("), "{text}: a gather reads level 0 only");
        }
        // Every backend takes the level: SPIR-V and GLSL of the whole module.
        for text in [
            "linear(32)+binary(5)+lod=auto",
            "csm(15, form=textbook, sample=min4)+lod=level(1)",
            "csm(15)+binary(5)+lod=auto",
            "rcs(15)+lod=auto",
            "maxmip(32)+lod=auto",
        ] {
            let out = crate::emit::emit(&text.parse().unwrap()).unwrap_or_else(|e| panic!("{text}: {e}"));
            assert!(!out.spirv.is_empty() && out.glsl.len() == 3, "{text}");
        }
        // lod=zero is today's module, with no level in it.
        let src = wgsl("linear(32)+binary(5)").unwrap();
        assert!(!src.contains("relief_sample_level") && !src.contains("relief_lod_level"));
    }

    #[test]
    fn methods_without_a_level_are_refused_by_name() {
        for (text, stage) in
            [("sphere(32)+lod=level(1)", "sphere"), ("linear(8)+shadow=hard(sphere(8))+lod=auto", "hard")]
        {
            let e = wgsl(text).err().unwrap_or_else(|| panic!("{text} compiled"));
            let msg = e.to_string();
            assert!(msg.contains(&format!("`{stage}` does not support lod=")), "{text}: {msg}");
        }
    }
}
