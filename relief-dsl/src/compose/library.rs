//! Pipeline → a validated *library* module: the stages as functions for a user's own
//! material shader, with no entry points, no `Params` block and no probe buffers.
//!
//! The interface (the same in every language [`crate::emit::library()`] writes), for the
//! default prefix `relief`:
//! - `struct ReliefHit { uv: vec2<f32>, height: f32, t: f32, depth_offset: f32 }`;
//! - `fn relief_trace(uv: vec2<f32>, view_ts: vec3<f32>, depth_scale: f32) -> ReliefHit`;
//! - `fn relief_shadow(hit: ReliefHit, light_ts: vec3<f32>, depth_scale: f32) -> f32` when the
//!   pipeline has a shadow stage, `fn relief_ao(hit: ReliefHit) -> f32` when it has an ao stage;
//! - the textures and samplers the stages read, as globals `relief_height`, `relief_sampler`,
//!   `relief_cone`, … at the user's group, at consecutive bindings from the user's first
//!   binding ([`LibraryBinding`]);
//! - `const relief_edge_clamp: bool`, the edge mode the stages that address texels
//!   themselves assume (maxmip's texel walk): fixed when the library is generated.
//!
//! `relief_trace` turns the view ray into the normalized ray the stages search (the
//! conversion of the render entry, ARCHITECTURE.md "Conventions"): with `v` the normalized view
//! direction (`v.z < 0`) and `d` the depth scale, the ray enters at `(uv, 1)` with direction
//! `(v.xy · d / −v.z, −1)`, so that t = 1 reaches the floor. The hit's t is clamped into
//! `[0, 1]` as the render entry clamps it.
//!
//! `depth_offset` is the distance from the polygon to the hit along the unit view ray, in
//! texture units (the units of the depth scale): the hit lies `t · d` below the polygon, and
//! the unit view ray descends `−v.z` per unit length, so `depth_offset = t · d / −v.z`.
//!
//! Everything the stages build is renamed under the prefix `P` so that several libraries
//! compose in one shader: the public functions `P_trace`, `P_shadow`, `P_ao`, the globals
//! `P_height`, …, the stage functions `P_impl_coarse_linear`, …, and the struct types
//! `PHit` (the public hit, `P` in CamelCase), `PRay`, `PBracket`, `PHit`.

use naga::{Handle, Module, TypeInner};

use crate::compose::mesh::{self, MeshInputs};
use crate::compose::write_stage_fns;
use crate::ir::{Filter, ModuleCtx, Plain, Policy, Resource, Ty, Vec2, Vec3, Vec4};
use crate::spec::{Curved, Pipeline};
use crate::stage::{Hit, Ray};
use crate::CompileError;

/// The library's policy: relief's plain one, but the edge mode from the module constant
/// `P_edge_clamp` (a library has no `Params` block).
struct LibraryPolicy {
    edge: Handle<naga::Constant>,
    /// Heights carry the quadric (`curved=quadric`).
    quadric: bool,
    /// Heights carry the prism's lift (`curved=prism`).
    lift: bool,
    /// Under the lift, the coarse stage reads maps (`Policy::prism_untilted`).
    untilted: bool,
}

impl Policy for LibraryPolicy {
    fn edge_clamp_constant(&self) -> Option<Handle<naga::Constant>> {
        Some(self.edge)
    }
    fn quadric_warp(&self) -> bool {
        self.quadric
    }
    fn prism_lift(&self) -> bool {
        self.lift
    }
    fn prism_untilted(&self) -> bool {
        self.untilted
    }
}

/// How a library is named and bound.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LibraryOptions {
    /// The name every global and function starts with (`relief` → `relief_trace`); an
    /// identifier of ASCII letters, digits and `_`, starting with a letter, not ending in `_`.
    pub prefix: String,
    /// The bind group (descriptor set, register space) of every resource.
    pub group: u32,
    /// The first binding; the resources take consecutive bindings from it.
    pub binding: u32,
    /// The edge mode the stages that address texels themselves assume (`true`: clamp to the
    /// edge, `false`: repeat). It must match the user's samplers.
    pub edge_clamp: bool,
    /// When set, the WGSL file starts with `#define_import_path PATH` (for `naga_oil` / WESL).
    pub import_path: Option<String>,
}

impl Default for LibraryOptions {
    fn default() -> Self {
        LibraryOptions { prefix: "relief".into(), group: 0, binding: 0, edge_clamp: false, import_path: None }
    }
}

/// What a library resource is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ResourceKind {
    /// `texture_2d<f32>`.
    Texture2d,
    /// `texture_3d<f32>`.
    Texture3d,
    /// `sampler` (non-comparison).
    Sampler,
}

/// One resource of a library, at its binding.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LibraryBinding {
    /// The global's name (`relief_height`).
    pub name: String,
    /// The bind group (descriptor set, register space) it is declared in.
    pub group: u32,
    /// Its binding in that group.
    pub binding: u32,
    /// Texture or sampler.
    pub kind: ResourceKind,
    /// What to bind there (`the height map, linear filtering`).
    pub what: String,
    /// What the module's binding table says the global holds (the map and its filter, or a
    /// sampler): what an exporter writes for it.
    pub resource: Resource,
    /// Whether some read is at a level other than 0 (then every level of the map's mip
    /// chain is needed; else level 0 suffices).
    pub all_levels: bool,
}

/// A built library module and its resources, in binding order.
pub struct Library {
    /// The validated module: the stage functions and the public `P_trace` (…), no entry points.
    pub module: Module,
    /// naga's validation info of `module`.
    pub info: naga::valid::ModuleInfo,
    /// The resources, in binding order.
    pub bindings: Vec<LibraryBinding>,
    /// Whether the pipeline has a shadow stage (`P_shadow` exists).
    pub has_shadow: bool,
    /// Whether the pipeline has an ao stage (`P_ao` exists).
    pub has_ao: bool,
    /// The pipeline's `curved=` (`Some`: the mesh forms of the functions, docs/meshes-shaders.md).
    pub curved: Option<Curved>,
}

fn check_prefix(prefix: &str) -> Result<(), CompileError> {
    let ok = prefix.chars().next().is_some_and(|c| c.is_ascii_alphabetic())
        && prefix.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        && !prefix.ends_with('_')
        && !prefix.contains("__");
    if ok {
        Ok(())
    } else {
        Err(CompileError {
            stage: "library".into(),
            message: format!(
                "prefix `{prefix}` is not an identifier of ASCII letters, digits and single `_`s that starts with a letter and does not end in `_`"
            ),
        })
    }
}

/// `rock_a` → `RockA`.
pub(crate) fn camel(prefix: &str) -> String {
    prefix
        .split('_')
        .map(|w| {
            let mut c = w.chars();
            match c.next() {
                Some(f) => f.to_ascii_uppercase().to_string() + c.as_str(),
                None => String::new(),
            }
        })
        .collect()
}

/// The library name of a resource the stages declare (the height map → `height`, the cone
/// map read with nearest filtering → `cone_nearest`, the linear sampler → `sampler`), and
/// what it holds; `None` for what a library has no place for.
fn library_name(resource: Resource) -> Option<(String, String)> {
    let filter_name = |f: Filter| if f == Filter::Nearest { "nearest" } else { "linear" };
    match resource {
        Resource::Sampler(Filter::Linear) => Some(("sampler".into(), "a sampler with linear filtering".into())),
        Resource::Sampler(Filter::Nearest) => {
            Some(("sampler_nearest".into(), "a sampler with nearest filtering".into()))
        }
        Resource::Texture { image, filter, wall: None } => {
            let texture = image.texture_name();
            let base = texture.strip_suffix("_map").unwrap_or(&texture);
            let what = format!("the {} map, read with {} filtering", base.replace('_', " "), filter_name(filter));
            Some((if filter == Filter::Nearest { format!("{base}_nearest") } else { base.to_string() }, what))
        }
        _ => None,
    }
}

/// The end of a texture's description when every read of it is at mip level 0.
pub const LEVEL_ZERO: &str = " at level 0 only (one level suffices)";
/// The end of a texture's description when some read of it is at a level other than 0.
pub const LEVELS_CHAIN: &str = " at every level of its mip chain (upload all levels)";

/// The description of a texture the library's functions only ask the size of (no texel is
/// read: the height map of the safe `csm`, `cns`, `csm_relax` and `qcsm`, whose cells' patches come
/// from the patch map): its size sets the cell grid.
pub const SIZE_ONLY: &str = ", only its size read (textureDimensions at level 0; no texel)";

/// How a library's functions read one texture.
#[derive(Default)]
struct Reads {
    /// Its size is queried.
    sized: bool,
    /// Some read is a texel load.
    loaded: bool,
    /// Some read goes through a sampler.
    sampled: bool,
    /// Some read is at a level that is not the constant 0 (a computed level or the
    /// hardware's choice).
    other_levels: bool,
}

/// Whether expression `h` is the constant 0 (a literal, a zero value, a module constant
/// or a conversion of one).
fn is_const_zero(module: &Module, exprs: &naga::Arena<naga::Expression>, h: Handle<naga::Expression>) -> bool {
    fn literal_zero(l: naga::Literal) -> bool {
        match l {
            naga::Literal::U32(v) => v == 0,
            naga::Literal::I32(v) => v == 0,
            naga::Literal::U64(v) => v == 0,
            naga::Literal::I64(v) => v == 0,
            naga::Literal::F32(v) => v == 0.0,
            naga::Literal::F64(v) => v == 0.0,
            naga::Literal::AbstractInt(v) => v == 0,
            naga::Literal::AbstractFloat(v) => v == 0.0,
            _ => false,
        }
    }
    fn global_zero(module: &Module, h: Handle<naga::Expression>) -> bool {
        match module.global_expressions[h] {
            naga::Expression::Literal(l) => literal_zero(l),
            naga::Expression::ZeroValue(_) => true,
            naga::Expression::Constant(c) => global_zero(module, module.constants[c].init),
            _ => false,
        }
    }
    match exprs[h] {
        naga::Expression::Literal(l) => literal_zero(l),
        naga::Expression::ZeroValue(_) => true,
        naga::Expression::Constant(c) => global_zero(module, module.constants[c].init),
        naga::Expression::As { expr, .. } => is_const_zero(module, exprs, expr),
        _ => false,
    }
}

/// Why a library cannot express `p`, if it cannot: the render options a library has no
/// place for (`lod`, `silhouette`) and stages that read what the library interface does not
/// take (`linear_distance`'s camera distance). `relief gen --all --library` skips these.
pub fn inexpressible(p: &Pipeline) -> Option<String> {
    if p.lod != crate::spec::Lod::Zero {
        // The stages would read a level that only relief's own entry points set.
        return Some(format!("the library output does not support lod={} yet (its functions sample level 0)", p.lod));
    }
    if p.silhouette != crate::spec::Silhouette::None {
        // A library has no fragment to discard; the caller knows its quad's square.
        return Some(format!(
            "silhouette={} is an option of relief's own render entry; in a library, discard where `hit.uv` leaves your quad's texture square yourself",
            p.silhouette
        ));
    }
    let m = ModuleCtx::new();
    if write_stage_fns(&m, p, &Plain::default(), false).is_ok() {
        let module = m.module.borrow();
        if module
            .global_variables
            .iter()
            .any(|(_, g)| g.name.as_deref() == Some(crate::stage::coarse::linear::VIEW_DISTANCE))
        {
            return Some("`linear_distance` reads the distance from the camera to the fragment (Amaro & Gustafsson 2022, §2.1.3), which the library interface (`P_trace(uv, view_ts, depth_scale)`) does not take: not implemented for libraries (`linear_dynamic` needs no distance)".into());
        }
    }
    None
}

/// Builds and validates the library module of `p`.
pub(crate) fn compose_library(p: &Pipeline, opts: &LibraryOptions) -> Result<Library, CompileError> {
    if let Some(why) = inexpressible(p) {
        return Err(CompileError { stage: "library".into(), message: why });
    }
    check_prefix(&opts.prefix)?;
    let prefix = opts.prefix.as_str();
    let m = ModuleCtx::new();
    let edge = {
        let ty = m.ty(bool::inner());
        let mut module = m.module.borrow_mut();
        let init = module
            .global_expressions
            .append(naga::Expression::Literal(naga::Literal::Bool(opts.edge_clamp)), naga::Span::UNDEFINED);
        module
            .constants
            .append(naga::Constant { name: Some(format!("{prefix}_edge_clamp")), ty, init }, naga::Span::UNDEFINED)
    };
    let lift = p.curved == Some(Curved::Prism);
    let policy = LibraryPolicy {
        edge,
        quadric: p.curved == Some(Curved::Quadric),
        lift,
        untilted: lift && super::mesh::coarse_reads_maps(p),
    };
    let fns = write_stage_fns(&m, p, &policy, false)?;
    let f32_ty = m.ty(f32::inner());
    let vec2_ty = m.ty(Vec2::inner());
    let vec3_ty = m.ty(Vec3::inner());
    let camel = camel(prefix);
    let mut hit_members =
        vec![("uv", Vec2::inner()), ("height", f32::inner()), ("t", f32::inner()), ("depth_offset", f32::inner())];
    if p.curved.is_some() {
        hit_members.push(("covered", f32::inner()));
    }
    let public_hit = m.struct_ty(&format!("{camel}Hit"), &hit_members);
    let mut public = Vec::new();

    if let Some(curved) = p.curved {
        public.push(mesh_trace_fn(&m, &policy, &fns, curved, public_hit));
    } else {
        // relief_trace(uv, view_ts, depth_scale) -> ReliefHit
        let s = m.function(
            "trace",
            &[("uv", vec2_ty, None), ("view_ts", vec3_ty, None), ("depth_scale", f32_ty, None)],
            &policy,
        );
        let uv = s.arg::<Vec2>(0);
        let view = s.arg::<Vec3>(1).normalize();
        let depth_scale = s.arg::<f32>(2);
        let cos_view = s.name("cos_view", -view.z());
        let dir = s.vec3(view.xy() * (depth_scale / cos_view), -1.0);
        let ray = Ray { origin: uv, dir, cos_view };
        let traced: Hit = s.unpack(s.call(fns.trace, &[s.pack(&ray)], true).unwrap());
        let t = traced.t.clamp(0.0, ray.t_max());
        let hit = Hit::at_found(&ray, t, traced.found);
        let depth_offset = t * depth_scale / cos_view;
        let out = s.make_struct(public_hit, &[hit.uv.handle(), hit.z.handle(), t.handle(), depth_offset.handle()]);
        let f = s.finish(Some((public_hit, None, out)));
        public.push(m.add_function(f));
    }
    // The stages' hit from the public one (`found`: the public hit is always drawn).
    fn stage_hit<'a>(s: &'a crate::ir::FnBuilder<'a>, h: Handle<naga::Expression>) -> Handle<naga::Expression> {
        let uv = s.field::<Vec2>(h, 0);
        let z = s.field::<f32>(h, 1);
        let t = s.field::<f32>(h, 2);
        s.pack(&Hit { t, uv, z, found: s.lit_bool(true) })
    }
    // relief_shadow(hit, light_ts, depth_scale) -> f32: the light ray in the stages'
    // normalized space, as the render entry builds it.
    if let (Some(shadow), Some(curved)) = (fns.shadow, p.curved) {
        public.push(mesh_shadow_fn(&m, &policy, shadow, curved, public_hit));
    } else if let Some(shadow) = fns.shadow {
        let s = m.function(
            "shadow",
            &[("hit", public_hit, None), ("light_ts", vec3_ty, None), ("depth_scale", f32_ty, None)],
            &policy,
        );
        let hv = stage_hit(&s, s.arg::<Vec4>(0).handle());
        let light = s.arg::<Vec3>(1).normalize();
        let depth_scale = s.arg::<f32>(2);
        let light_n = s.vec3(light.xy() * (depth_scale / light.z().max(1e-3)), 1.0);
        let v = s.call(shadow, &[hv, light_n.handle(), light.z().handle()], true).unwrap();
        let f = s.finish(Some((f32_ty, None, v)));
        public.push(m.add_function(f));
    }
    // relief_ao(hit) -> f32
    if let Some(ao) = fns.ao {
        let s = m.function("ao", &[("hit", public_hit, None)], &policy);
        let hv = stage_hit(&s, s.arg::<Vec4>(0).handle());
        if p.curved == Some(Curved::Quadric) {
            mesh::recentre_quadric(&s, s.field::<Vec2>(s.arg::<Vec4>(0).handle(), 0));
        }
        let v = s.call(ao, &[hv], true).unwrap();
        let f = s.finish(Some((f32_ty, None, v)));
        public.push(m.add_function(f));
    }
    let (mut module, table) = super::finish(m)?;

    // Functions: the public ones `P_NAME`, the stages' `P_impl_NAME`.
    for (h, f) in module.functions.iter_mut() {
        let name = f.name.take().unwrap_or_default();
        f.name = Some(if public.contains(&h) { format!("{prefix}_{name}") } else { format!("{prefix}_impl_{name}") });
    }
    // Struct types: the public hit `PHit`, the stages' `PNAME`.
    let renamed: Vec<(Handle<naga::Type>, naga::Type)> = module
        .types
        .iter()
        .filter(|(h, t)| matches!(t.inner, TypeInner::Struct { .. }) && t.name.is_some() && *h != public_hit)
        .map(|(h, t)| {
            let old = t.name.as_deref().unwrap();
            let new = if old == "Hit" { format!("{camel}StageHit") } else { format!("{camel}{old}") };
            (h, naga::Type { name: Some(new), inner: t.inner.clone() })
        })
        .collect();
    for (h, t) in renamed {
        module.types.replace(h, t);
    }
    // Globals: every one is a texture or sampler the stages read; renamed, and rebound in the
    // order of their fixed bindings.
    let mut order: Vec<(u32, Handle<naga::GlobalVariable>)> = Vec::new();
    for (h, g) in module.global_variables.iter_mut() {
        let name = g.name.as_deref().unwrap_or("");
        if let Some(rest) = quadric_global(g) {
            // The quadric's private state (`curved=quadric`) or the prism's lift
            // (`curved=prism`), set by `P_trace`.
            g.name = Some(format!("{prefix}_{rest}"));
            continue;
        }
        let Some(rb) = g.binding else {
            return Err(CompileError {
                stage: "library".into(),
                message: format!("the stages declare `{name}`, which is no resource: a library has no place for it"),
            });
        };
        if !matches!(g.space, naga::AddressSpace::Handle) {
            return Err(CompileError {
                stage: "library".into(),
                message: format!(
                    "the stages read `{name}` (not a texture or sampler), which a library has no value for"
                ),
            });
        }
        order.push((rb.binding, h));
    }
    order.sort();
    // How each texture is read (texel loads or samples) and at which levels: the header
    // says so, from the module's own reads.
    let mut reads: std::collections::HashMap<Handle<naga::GlobalVariable>, Reads> = Default::default();
    for (_, f) in module.functions.iter() {
        for (_, e) in f.expressions.iter() {
            let gv = |h: Handle<naga::Expression>| match f.expressions[h] {
                naga::Expression::GlobalVariable(g) => Some(g),
                _ => None,
            };
            let zero = |h: Handle<naga::Expression>| is_const_zero(&module, &f.expressions, h);
            match *e {
                naga::Expression::ImageLoad { image, level, .. } => {
                    if let Some(g) = gv(image) {
                        let r = reads.entry(g).or_default();
                        r.loaded = true;
                        r.other_levels |= level.is_some_and(|l| !zero(l));
                    }
                }
                naga::Expression::ImageSample { image, level, .. } => {
                    if let Some(g) = gv(image) {
                        let r = reads.entry(g).or_default();
                        r.sampled = true;
                        r.other_levels |= match level {
                            naga::SampleLevel::Zero => false,
                            naga::SampleLevel::Exact(l) => !zero(l),
                            _ => true,
                        };
                    }
                }
                naga::Expression::ImageQuery { image, .. } => {
                    if let Some(g) = gv(image) {
                        reads.entry(g).or_default().sized = true;
                    }
                }
                _ => {}
            }
        }
    }
    let mut bindings = Vec::new();
    for (i, (_, h)) in order.into_iter().enumerate() {
        let g = &mut module.global_variables[h];
        let old = g.name.clone().unwrap_or_default();
        let resource = g.binding.and_then(|rb| table.resource(rb.binding));
        let Some((resource, (base, mut what))) = resource.and_then(|r| Some((r, library_name(r)?))) else {
            return Err(CompileError {
                stage: "library".into(),
                message: format!("no library name for the resource `{old}`"),
            });
        };
        let all_levels = reads.get(&h).is_some_and(|r| r.other_levels);
        if let Some(r) = reads.get(&h) {
            if !r.loaded && !r.sampled {
                what = format!("{}{SIZE_ONLY}", what.split(", read").next().unwrap_or(""));
            } else {
                if r.loaded && !r.sampled {
                    what = format!("{}, read texel by texel (textureLoad)", what.split(", read").next().unwrap_or(""));
                }
                what.push_str(if r.other_levels { LEVELS_CHAIN } else { LEVEL_ZERO });
            }
        }
        let name = format!("{prefix}_{base}");
        let binding = u32::try_from(i).ok().and_then(|i| opts.binding.checked_add(i)).ok_or_else(|| CompileError {
            stage: "library".into(),
            message: format!("binding {} + {i}: the resources' bindings would pass {}", opts.binding, u32::MAX),
        })?;
        g.name = Some(name.clone());
        g.binding = Some(naga::ResourceBinding { group: opts.group, binding });
        let kind = match &module.types[g.ty].inner {
            TypeInner::Image { dim: naga::ImageDimension::D2, .. } => ResourceKind::Texture2d,
            TypeInner::Image { dim: naga::ImageDimension::D3, .. } => ResourceKind::Texture3d,
            TypeInner::Sampler { comparison: false } => ResourceKind::Sampler,
            other => {
                return Err(CompileError {
                    stage: "library".into(),
                    message: format!("resource `{old}` of unexpected type {other:?}"),
                })
            }
        };
        bindings.push(LibraryBinding { name, group: opts.group, binding, kind, what, resource, all_levels });
    }
    let info = crate::compose::validate(&module)?;
    Ok(Library { module, info, bindings, has_shadow: fns.shadow.is_some(), has_ao: fns.ao.is_some(), curved: p.curved })
}

/// The name of a quadric or prism-lift global after `relief_` (`quadric`, `quadric_origin`,
/// `prism_lift`, `prism_stop`), if `g` is one.
fn quadric_global(g: &naga::GlobalVariable) -> Option<String> {
    use crate::stage::sampling::{
        PRISM_BEND, PRISM_BEND_AXIS, PRISM_LIFT, PRISM_ORIGIN, PRISM_STOP, QUADRIC_COEFFS, QUADRIC_ORIGIN,
    };
    let name = g.name.as_deref()?;
    let private = matches!(g.space, naga::AddressSpace::Private);
    let ours = [QUADRIC_COEFFS, QUADRIC_ORIGIN, PRISM_LIFT, PRISM_ORIGIN, PRISM_BEND, PRISM_BEND_AXIS, PRISM_STOP];
    (private && ours.contains(&name)).then(|| name.trim_start_matches("relief_").to_string())
}

/// The mesh form's arguments of `P_trace` under `curved`, after the first (`uv: vec2` or, for
/// a prism, `uvw: vec3`): the view ray and the frame, the mode's own inputs, the depth.
fn mesh_trace_args(m: &ModuleCtx, curved: Curved) -> Vec<(&'static str, Handle<naga::Type>, Option<naga::Binding>)> {
    let (v2, v3, v4, f) = (m.ty(Vec2::inner()), m.ty(Vec3::inner()), m.ty(Vec4::inner()), m.ty(f32::inner()));
    let first = match curved {
        Curved::Prism => ("uvw", v3, None),
        Curved::None | Curved::Quadric => ("uv", v2, None),
    };
    let mut args = vec![first, ("view", v3, None), ("normal", v3, None), ("tangent", v4, None), ("uv_scale", v2, None)];
    match curved {
        Curved::None => {}
        Curved::Quadric => args.push(("curvature", v2, None)),
        Curved::Prism => args.extend([
            ("prism_a", v4, None),
            ("prism_b", v2, None),
            ("position", v3, None),
            ("prism_p0", v3, None),
            ("prism_p1", v3, None),
            ("prism_p2", v3, None),
            ("prism_n0", v3, None),
            ("prism_n1", v3, None),
            ("prism_n2", v3, None),
        ]),
    }
    args.push(("depth_scale", f, None));
    args
}

/// `P_trace` of a mesh library (docs/meshes-shaders.md): the mesh module's ray, trace and
/// coverage on the caller's interpolated inputs; `covered` is 0 where the mesh module would
/// discard.
fn mesh_trace_fn(
    m: &ModuleCtx,
    policy: &dyn Policy,
    fns: &crate::compose::StageFns,
    curved: Curved,
    public_hit: Handle<naga::Type>,
) -> Handle<naga::Function> {
    let args = mesh_trace_args(m, curved);
    let s = m.function("trace", &args, policy);
    let uv = match curved {
        Curved::Prism => s.arg::<Vec3>(0).xy(),
        Curved::None | Curved::Quadric => {
            // The layer the prism no longer reads: its literal is still made, so that the
            // `none` and `quadric` forms keep their text to the byte (naga numbers the
            // temporaries by expression).
            let _ = s.lit(1.0);
            s.arg::<Vec2>(0)
        }
    };
    let last = args.len() as u32 - 1;
    let depth = s.arg::<f32>(last);
    let scale = s.arg::<Vec2>(4);
    let prism = (curved == Curved::Prism).then(|| {
        let (a, point) = (s.arg::<Vec4>(5), s.arg::<Vec3>(7));
        mesh::PrismCorners {
            p: [8, 9, 10].map(|k| s.arg::<Vec3>(k) - point),
            n: [11, 12, 13].map(|k| s.arg::<Vec3>(k)),
            uv: [a.xy(), a.zw(), s.arg::<Vec2>(6)],
            // The library form passes no sealed walls: no early-out (docs/meshes-shaders.md).
            early: None,
        }
    });
    let inputs = MeshInputs {
        view: s.arg::<Vec3>(1).normalize(),
        normal: s.vec4(s.arg::<Vec3>(2), 0.0),
        tangent: s.arg::<Vec4>(3),
        uv: s.vec4(s.vec3(uv, scale.x()), scale.y()),
        curvature: if curved == Curved::Quadric { s.arg::<Vec2>(5) } else { s.vec2(0.0, 0.0) },
        depth,
        prism,
        walk: None,
    };
    let mr = mesh::mesh_ray(&s, curved, inputs);
    let (hit, covered) = if curved == Curved::Prism {
        let (hit, drawn, _) = mesh::prism_trace(&s, fns, &mr);
        (hit, s.select(drawn, 1.0f32, 0.0f32))
    } else {
        let traced = mesh::search(&s, fns, &mr);
        let covered = s.select(mesh::covered(&s, curved, &mr, &traced), 1.0f32, 0.0f32);
        let t = traced.t.clamp(0.0, mr.ray.t_max());
        (Hit::at_found(&mr.ray, t, traced.found), covered)
    };
    let t = hit.t;
    let offset = mesh::depth_offset(&mr, &hit);
    let values = [hit.uv.handle(), hit.z.handle(), t.handle(), offset.handle(), covered.handle()];
    let out = s.make_struct(public_hit, &values);
    let f = s.finish(Some((public_hit, None, out)));
    m.add_function(f)
}

/// `P_shadow(hit, light, normal, tangent, uv_scale, depth_scale)` of a mesh library: the
/// light (object space, toward the light) in the frame of the fragment, as the mesh module's
/// fragment builds it; under `quadric` the quadric centred on the hit.
fn mesh_shadow_fn(
    m: &ModuleCtx,
    policy: &dyn Policy,
    shadow: Handle<naga::Function>,
    curved: Curved,
    public_hit: Handle<naga::Type>,
) -> Handle<naga::Function> {
    let (v2, v3, v4, f) = (m.ty(Vec2::inner()), m.ty(Vec3::inner()), m.ty(Vec4::inner()), m.ty(f32::inner()));
    let s = m.function(
        "shadow",
        &[
            ("hit", public_hit, None),
            ("light", v3, None),
            ("normal", v3, None),
            ("tangent", v4, None),
            ("uv_scale", v2, None),
            ("depth_scale", f, None),
        ],
        policy,
    );
    let h = s.arg::<Vec4>(0).handle();
    let (uv, z, t) = (s.field::<Vec2>(h, 0), s.field::<f32>(h, 1), s.field::<f32>(h, 2));
    let hv = s.pack(&Hit { t, uv, z, found: s.lit_bool(true) });
    if curved == Curved::Quadric {
        mesh::recentre_quadric(&s, uv);
    }
    let scale = s.arg::<Vec2>(4);
    let frame =
        mesh::frame(&s, s.vec4(s.arg::<Vec3>(2), 0.0), s.arg::<Vec4>(3), s.vec4(s.vec3(uv, scale.x()), scale.y()));
    let (l_uv, l_n) = frame.to_texture(s.arg::<Vec3>(1).normalize());
    // The relief's depth along the unit normal, as the trace takes it (`MeshRay::depth`).
    let depth = s.arg::<f32>(5) * s.arg::<Vec3>(2).length();
    let light_n = s.vec3(l_uv * (depth / l_n.max(1e-3)), 1.0);
    let v = s.call(shadow, &[hv, light_n.handle(), l_n.handle()], true).unwrap();
    let f = s.finish(Some((m.ty(f32::inner()), None, v)));
    m.add_function(f)
}
