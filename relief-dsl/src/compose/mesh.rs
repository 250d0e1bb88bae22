//! The mesh module: a pipeline with `curved=none|quadric|prism` on a triangle mesh (issue 38;
//! docs/meshes-shaders.md is the user's page).
//!
//! Built from the same pieces as relief's own module: the pipeline's stage functions
//! (`write_stage_fns`) and three entry points that share one trace, so that colour, depth
//! and shadows come from the same search:
//!
//! - `vs_mesh`: one [`MeshVertex`] per vertex (the layout the runtime uploads, by member
//!   name, at locations 0‥6 in member order) → clip position and the varyings;
//! - `fs_mesh`: the pipeline's coarse and refine stages on the fragment's ray in the tangent
//!   frame of the interpolated normal and tangent (N renormalized, T made orthogonal to it),
//!   then shadow and ao, shading as relief's own fragment; writes colour and the hit's depth
//!   (`frag_depth`, the NDC depth of the hit point under `params.view_proj`);
//! - `fs_mesh_depth`: the same trace and the same discards, writing only the depth: the
//!   depth pre-pass and the shadow caster (with the light's `view_proj` and `camera`);
//! - `fs_mesh_probe` (only with `compose::Options::mesh_probe`, for the runtime's
//!   measurement): the same trace and the same discards, writing the hit's depth and, to an
//!   `rgba32float` target, `(u, v, distance, 1)`: the hit's texture coordinates and its
//!   distance from the eye along the fragment's unit view ray, object units.
//!
//! `Params` for a mesh: `view_proj` object → clip, `camera.xyz` the eye in object space,
//! `camera.w` the relief's depth in object units, `light` toward the light in object space
//! and the ambient share, `quad.y` the edge mode; `quad.x`, `pixel_right` and `pixel_up`
//! are unused (`lod=auto` is refused: its footprint is the flat tile's).
//!
//! The three modes differ only in where the ray starts, which quadric the heights carry and
//! when a pixel is discarded (`covered`):
//!
//! - `none`: the flat tile's ray at every fragment (what engines ship); nothing discarded;
//! - `quadric`: every height read adds the vertex's quadric centred on the ray's entry
//!   (Oliveira & Policarpo 2005; the stage layer's `QUADRIC_COEFFS`); a ray that finds
//!   no hit has left the shell (or reached the floor) and is discarded: the silhouette;
//! - `prism`: the mesh is drawn as prisms (each triangle extruded along its vertex normals as
//!   deep as the relief, [`MeshVertex::position`]`.w` the layer); the ray enters where the
//!   prism face is rasterized, at texture point (u, v, w), and the search runs from there (over
//!   heights lifted by `1 − w`, `search`) to the ray's exit from the prism in texture space
//!   (`prism_exit`); a hit after the exit or none at all is discarded.
//!
//! Limitation of `prism`: the side walls are *planar in texture space* (vertical over the
//! triangle's uv edges), the prism mapped to texture space by the fragment's tangent frame;
//! the bilinear side walls of Hoetzlein 2025 are not built. Where the normals of a triangle
//! differ, the rasterized side faces (two triangles per wall) and those planes disagree by the
//! wall's bilinear twist.

use bytemuck::{Pod, Zeroable};
use naga::{Binding, BuiltIn, Module, ShaderStage, TypeInner};

use super::{entry_point, location, write_stage_fns, StageFns};
use crate::abi::{abi_record, Param};
use crate::ir::{Bindings, FnBuilder, Image, Mat4, ModuleCtx, Plain, Policy, Ty, Val, Vec2, Vec3, Vec4};
use crate::spec::{Curved, Lod, Pipeline, Silhouette};
use crate::stage::sampling::{PRISM_LIFT, QUADRIC_COEFFS, QUADRIC_ORIGIN};
use crate::stage::{Filter, Hit, Ray};
use crate::CompileError;

abi_record! {
/// One vertex of a mesh module (112 bytes, seven `vec4<f32>`): the vertex layout, the one
/// statement of it. The vertex entry reads member k at `@location(k)`, in this order; every
/// mode reads the same record, and a member a mode does not use is ignored (zero it).
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct MeshVertex {
    /// xyz: the point on the base surface, object space. w: the prism layer, 1 at the surface
    /// and 0 at the relief's floor (the vertex entry moves the point `(1 − w)·depth` along
    /// `−normal`); 1 for `none` and `quadric`.
    pub position: [f32; 4],
    /// xyz: the unit normal (object space); w: 0.
    pub normal: [f32; 4],
    /// xyz: the unit tangent along +u; w: the handedness ±1 (the bitangent along +v is
    /// `w · normal × tangent`), MikkTSpace's convention.
    pub tangent: [f32; 4],
    /// xy: the texture coordinates (u, v). zw: texture units per object unit along the
    /// tangent and the bitangent (`1 / |∂P/∂u|`, `1 / |∂P/∂v|`).
    pub uv: [f32; 4],
    /// `quadric`: xy the coefficients a, b of the base surface's quadric in the vertex's
    /// tangent frame (Oliveira & Policarpo 2005): the surface lies `a·Δu² + b·Δv²` object
    /// units above the tangent plane at texture offset (Δu, Δv) (negative where it curves
    /// away: a sphere of radius R with s texture units per object unit has
    /// `a = b = −1/(2R·s²)`); zw: 0.
    pub curvature: [f32; 4],
    /// `prism`: the texture coordinates of the prism's triangle, corners 0 (xy) and 1 (zw),
    /// the same at all six vertices of the prism.
    pub prism_a: [f32; 4],
    /// `prism`: xy the texture coordinates of corner 2; zw: 0.
    pub prism_b: [f32; 4],
}
}

/// The mesh module's policy: relief's plain one, with the quadric added to every height read
/// under `curved=quadric` and the prism's lift under `curved=prism`.
struct MeshPolicy {
    plain: Plain,
    quadric: bool,
    lift: bool,
}

impl Policy for MeshPolicy {
    fn lod(&self) -> Lod {
        self.plain.lod()
    }
    fn quadric_warp(&self) -> bool {
        self.quadric
    }
    fn prism_lift(&self) -> bool {
        self.lift
    }
}

/// The pipeline options a mesh module cannot honour, as the one-line error that names both:
/// `silhouette=clip` clips to the flat tile's square (a mesh's silhouette is `curved=`'s),
/// and `lod=auto` takes the pixel's footprint on the flat tile's plane.
fn check_mesh_options(p: &Pipeline, curved: Curved) -> Result<(), CompileError> {
    let refuse = |what: String, why: &str| {
        Err(CompileError { stage: "mesh".into(), message: format!("{what} cannot go with curved={curved}: {why}") })
    };
    if p.silhouette != Silhouette::None {
        return refuse(
            format!("silhouette={}", p.silhouette),
            "it clips to the flat tile's square; on a mesh the silhouette is curved=quadric's or curved=prism's",
        );
    }
    if p.lod == Lod::Auto {
        return refuse("lod=auto".into(), "its footprint is the flat tile's plane; use lod=zero or lod=level(k)");
    }
    Ok(())
}

/// The vertex varyings, members 1‥7 at locations 0‥6 (member 0 is the clip position): the
/// point (xyz, w the prism layer), the normal, the tangent, the uv with its scales, the
/// curvature and the prism's corners, each as the vertex gave it.
const VARYINGS: [&str; 7] = ["point", "normal", "tangent", "uv", "curvature", "prism_a", "prism_b"];

fn vertex_input(n: u32) -> Binding {
    Binding::Location { location: n, interpolation: None, sampling: None, blend_src: None, per_primitive: false }
}

/// `vs_mesh`: the vertex, moved to its prism layer, in clip space, and the varyings.
fn vertex_entry(m: &ModuleCtx, policy: &dyn Policy) -> naga::EntryPoint {
    let v4 = m.ty(Vec4::inner());
    let args: Vec<(&str, _, _)> =
        MeshVertex::MEMBERS.iter().enumerate().map(|(i, (n, _))| (*n, v4, Some(vertex_input(i as u32)))).collect();
    let s = m.function("vs_mesh", &args, policy);
    let position = s.arg::<Vec4>(0);
    let normal = s.arg::<Vec4>(1);
    let depth = s.param::<Vec4>(Param::Camera).w();
    // A prism's floor vertex lies the relief's depth below the surface along the normal.
    let point = position.xyz() - normal.xyz() * ((s.lit(1.0) - position.w()) * depth);
    let clip = s.param::<Mat4>(Param::ViewProj) * s.vec4(point, 1.0);
    let position_binding = Binding::BuiltIn(BuiltIn::Position { invariant: false });
    let mut members =
        vec![naga::StructMember { name: Some("clip".into()), ty: v4, binding: Some(position_binding), offset: 0 }];
    for (i, name) in VARYINGS.iter().enumerate() {
        members.push(naga::StructMember {
            name: Some((*name).into()),
            ty: v4,
            binding: Some(location(i as u32)),
            offset: 16 * (i as u32 + 1),
        });
    }
    let span = 16 * (VARYINGS.len() as u32 + 1);
    let out_ty = m.module.borrow_mut().types.insert(
        naga::Type { name: Some("MeshVarying".into()), inner: TypeInner::Struct { members, span } },
        naga::Span::UNDEFINED,
    );
    let mut values = vec![clip.handle(), s.vec4(point, position.w()).handle()];
    values.extend((1..MeshVertex::MEMBERS.len() as u32).map(|i| s.arg::<Vec4>(i).handle()));
    let out = s.make_struct(out_ty, &values);
    let f = s.finish(Some((out_ty, None, out)));
    entry_point("vs_mesh", ShaderStage::Vertex, f, [0; 3])
}

/// The fragment's tangent frame: the interpolated normal renormalized, the tangent made
/// orthogonal to it (Gram–Schmidt) and normalized, the bitangent `w · N × T`, and the texture
/// units per object unit along T and B.
pub(crate) struct Frame<'a> {
    t: Val<'a, Vec3>,
    b: Val<'a, Vec3>,
    n: Val<'a, Vec3>,
    scale: Val<'a, Vec2>,
}

pub(crate) fn frame<'a>(
    s: &'a FnBuilder<'a>,
    normal: Val<'a, Vec4>,
    tangent: Val<'a, Vec4>,
    uv: Val<'a, Vec4>,
) -> Frame<'a> {
    let n = normal.xyz().normalize();
    let t0 = tangent.xyz();
    let t = (t0 - n * n.dot(t0)).normalize();
    let b = n.cross(t) * tangent.w();
    Frame { t, b, n, scale: s.vec2(uv.z(), uv.w()) }
}

impl<'a> Frame<'a> {
    /// An object-space direction in texture units: (along u, along v, along the normal in
    /// object units).
    pub(crate) fn to_texture(&self, d: Val<'a, Vec3>) -> (Val<'a, Vec2>, Val<'a, f32>) {
        let s = d.builder();
        (s.vec2(d.dot(self.t) * self.scale.x(), d.dot(self.b) * self.scale.y()), d.dot(self.n))
    }
    /// A tangent-space direction (the normal map's) in object space.
    fn to_object(&self, d: Val<'a, Vec3>) -> Val<'a, Vec3> {
        self.t * d.x() + self.b * d.y() + self.n * d.z()
    }
}

/// The view ray's descent per unit length, `−v·N`, kept above zero: an interpolated normal
/// can face away from the eye on a front face near the silhouette, where the ray would not
/// descend at all (the room's walls keep the same floor).
fn descent<'a>(v_n: Val<'a, f32>) -> Val<'a, f32> {
    (-v_n).max(1e-6)
}

/// How far (in t) a hit may lie outside a prism's `[entry, exit]` and still count as inside:
/// the entry's w is interpolated across the face and the exit computed in f32, each good to a
/// few ulps of 1; 1e-4 covers that, and a hit on a shared wall is drawn by both prisms rather
/// than by neither (a goal, not measured yet).
const PRISM_SLACK: f32 = 1e-4;

/// The ray's exit from the prism over the texture triangle (`a`, `b`, `c`) in texture space:
/// the prism is the triangle × [0, 1] in (u, v, height), its side walls vertical (planar),
/// so the exit is the first of the floor (t = 1) and the walls the ray heads out of. Along
/// each edge with inward normal n (toward the third corner), the ray `origin + t·dir.xy`
/// leaves where `n·dir < 0`, at `t = n·(corner − origin) / n·dir`.
fn prism_exit<'a>(
    s: &'a FnBuilder<'a>,
    ray: &Ray<'a>,
    a: Val<'a, Vec2>,
    b: Val<'a, Vec2>,
    c: Val<'a, Vec2>,
) -> Val<'a, f32> {
    let mut exit = s.lit(1.0);
    for (p, q, r) in [(a, b, c), (b, c, a), (c, a, b)] {
        let e = q - p;
        let n0 = s.vec2(-e.y(), e.x());
        // Orient the normal toward the third corner.
        let n = n0 * s.select(n0.dot(r - p).lt(0.0), s.lit(-1.0), s.lit(1.0));
        let toward = n.dot(ray.dir.xy());
        let t = n.dot(p - ray.origin) / toward.min(-1e-12);
        exit = exit.min(s.select(toward.lt(0.0), t, s.lit(1.0)));
    }
    exit
}

/// What a mesh fragment traces: its ray, where the ray enters the relief volume in t (0 but
/// for a prism entered through a wall or the floor), and the view ray's data the depth needs.
pub(crate) struct MeshRay<'a> {
    /// The ray through the entry, started at height 1 (for `prism`, `1 − w` before the entry):
    /// the t of every hit, exit and depth is this ray's.
    pub(crate) ray: Ray<'a>,
    /// The ray the search runs on: `ray` for `none` and `quadric`; for `prism` the same
    /// direction started at the entry, searched over heights lifted by `1 − w` ([`search`]).
    search: Ray<'a>,
    pub(crate) t_entry: Val<'a, f32>,
    /// The unit view ray, object space.
    view: Val<'a, Vec3>,
    pub(crate) frame: Frame<'a>,
    /// The relief's depth along the unit normal at the fragment: `depth · |N|`, N the
    /// interpolated normal before renormalizing, as S = P − depth·(1 − h)·N descends
    /// (docs/meshes.md); t = 1 of the ray descends this far.
    pub(crate) depth: Val<'a, f32>,
}

/// What the fragment knows of its place on the mesh, from the vertex entry's varyings or a
/// library caller's arguments.
pub(crate) struct MeshInputs<'a> {
    /// The unit view ray from the eye to the fragment, object space.
    pub(crate) view: Val<'a, Vec3>,
    /// The interpolated normal, tangent (w: handedness) and uv (zw: texture units per object
    /// unit along T and B), as [`MeshVertex`] has them.
    pub(crate) normal: Val<'a, Vec4>,
    pub(crate) tangent: Val<'a, Vec4>,
    pub(crate) uv: Val<'a, Vec4>,
    /// The prism layer w at the fragment (1 on the surface; only `prism` reads it).
    pub(crate) layer: Val<'a, f32>,
    /// The quadric's coefficients a, b in object units (only `quadric` reads them).
    pub(crate) curvature: Val<'a, Vec2>,
    /// The relief's depth in object units.
    pub(crate) depth: Val<'a, f32>,
}

/// The fragment's ray, in the flat tile's convention (ARCHITECTURE.md, "Rays"): the view ray
/// in texture units, scaled so that t = 1 descends the relief's depth. For `prism` the ray
/// enters at the face's texture point (u, v, w), which is t = 1 − w on the ray through
/// `(u, v, 1)` started `1 − w` earlier. Under `quadric` it also centres the quadric on the
/// entry.
pub(crate) fn mesh_ray<'a>(s: &'a FnBuilder<'a>, curved: Curved, i: &MeshInputs<'a>) -> MeshRay<'a> {
    let frame = frame(s, i.normal, i.tangent, i.uv);
    // S's layers lie depth·|N| apart along the unit normal (N interpolated, not renormalized).
    let depth = i.depth * i.normal.xyz().length();
    let (v_uv, v_n) = frame.to_texture(i.view);
    let cos_view = descent(v_n);
    let dir = s.vec3(v_uv * (depth / cos_view), -1.0);
    let t_entry = match curved {
        Curved::Prism => s.lit(1.0) - i.layer,
        Curved::None | Curved::Quadric => s.lit(0.0),
    };
    let origin = i.uv.xy() - dir.xy() * t_entry;
    if curved == Curved::Quadric {
        set_quadric(s, i.curvature / depth, i.uv.xy());
    }
    let ray = Ray { origin, dir, cos_view };
    let search = match curved {
        Curved::Prism => Ray { origin: i.uv.xy(), dir, cos_view },
        Curved::None | Curved::Quadric => ray,
    };
    MeshRay { ray, search, t_entry, view: i.view, frame, depth }
}

/// The fragment entries' inputs: the varyings and the `Params` block.
fn varying_inputs<'a>(s: &'a FnBuilder<'a>) -> (MeshInputs<'a>, Val<'a, Vec3>) {
    let [point, normal, tangent, uv, curvature] = [0, 1, 2, 3, 4].map(|i| s.arg::<Vec4>(i));
    let camera = s.param::<Vec4>(Param::Camera);
    let depth = s.name("depth_scale", camera.w());
    let view = (point.xyz() - camera.xyz()).normalize();
    let inputs = MeshInputs { view, normal, tangent, uv, layer: point.w(), curvature: curvature.xy(), depth };
    (inputs, point.xyz())
}

/// Stores the quadric every height read adds under `curved=quadric` (in units of the
/// relief's depth) and the texture point it is centred on.
pub(crate) fn set_quadric<'a>(s: &'a FnBuilder<'a>, coeffs: Val<'a, Vec2>, origin: Val<'a, Vec2>) {
    let m = s.module();
    s.store(s.global_ptr(m.private::<Vec2>(QUADRIC_COEFFS)), coeffs.handle());
    s.store(s.global_ptr(m.private::<Vec2>(QUADRIC_ORIGIN)), origin.handle());
}

/// Moves the quadric's centre to `uv` (the hit, before the shadow and ao stages search from
/// it), keeping its coefficients.
pub(crate) fn recentre_quadric<'a>(s: &'a FnBuilder<'a>, uv: Val<'a, Vec2>) {
    s.store(s.global_ptr(s.module().private::<Vec2>(QUADRIC_ORIGIN)), uv.handle());
}

/// How far (in units of the relief's depth) the point a search returned may lie above the
/// warped surface and still count as a hit: a refined hit lies within its last bracket of the
/// surface, a few thousandths of the depth for the usual step counts; 1/32 (the default
/// linear search's step) keeps those and tells them from a search that ran out at the floor
/// plane with the surface still below it (a goal, checked by `relief scene measure`).
const QUADRIC_SLACK: f32 = 1.0 / 32.0;

/// Whether the search's point lies above the (quadric-warped) surface by more than
/// [`QUADRIC_SLACK`]: the search ended at the floor plane without meeting the surface (the
/// searches report `found` there too: the flat tile's floor is always met), so the ray has
/// left the shell.
fn above_surface<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>, traced: &Hit<'a>) -> Val<'a, bool> {
    let p = ray.at(traced.t);
    (p.z() - s.height(p.xy())).gt(QUADRIC_SLACK)
}

/// Whether the traced hit is drawn under `curved` (`none`: always): the rules of the mode
/// (the module's doc). `prism` is the prism's texture-space corners.
pub(crate) fn covered<'a>(
    s: &'a FnBuilder<'a>,
    curved: Curved,
    mr: &MeshRay<'a>,
    traced: &Hit<'a>,
    prism: [Val<'a, Vec2>; 3],
) -> Val<'a, bool> {
    match curved {
        Curved::None => s.lit_bool(true),
        // No hit: the ray left the shell above the curved surface or reached the floor
        // first (Oliveira & Policarpo 2005): the silhouette.
        Curved::Quadric => traced.found & !above_surface(s, &mr.ray, traced),
        Curved::Prism => {
            let exit = prism_exit(s, &mr.ray, prism[0], prism[1], prism[2]);
            // Entered through the floor (looking up from below the relief): nothing to see.
            let from_below = mr.frame.to_texture(mr.view).1.ge(0.0);
            let before = traced.t.lt(mr.t_entry - PRISM_SLACK);
            let after = traced.t.gt(exit + PRISM_SLACK);
            !(from_below | !traced.found | before | after)
        }
    }
}

/// The search of a mesh fragment, its hit on [`MeshRay::ray`]. For `prism` it runs from the
/// fragment's entry: on [`MeshRay::search`] with every height lifted by `1 − w`
/// ([`PRISM_LIFT`], set back to 0 after), so that relief in front of the entry (outside the
/// prism, where the fragment's frame extends the ray back to height 1) does not stop it; its t
/// is then `t_entry` more on `ray`.
pub(crate) fn search<'a>(s: &'a FnBuilder<'a>, fns: &StageFns, curved: Curved, mr: &MeshRay<'a>) -> Hit<'a> {
    match curved {
        Curved::Prism => {
            let lift = s.global_ptr(s.module().private::<f32>(PRISM_LIFT));
            s.store(lift, mr.t_entry.handle());
            let traced: Hit = s.unpack(s.call(fns.trace, &[s.pack(&mr.search)], true).unwrap());
            s.store(lift, s.lit(0.0).handle());
            Hit::at_found(&mr.ray, traced.t + mr.t_entry, traced.found)
        }
        Curved::None | Curved::Quadric => s.unpack(s.call(fns.trace, &[s.pack(&mr.ray)], true).unwrap()),
    }
}

/// The trace both fragment entries share: the search, then the discards of the mode; returns
/// the hit, kept inside the volume as relief's own fragment keeps it.
fn mesh_trace<'a>(s: &'a FnBuilder<'a>, fns: &StageFns, curved: Curved, mr: &MeshRay<'a>) -> Hit<'a> {
    let traced = search(s, fns, curved, mr);
    if curved != Curved::None {
        let prism = [s.arg::<Vec4>(5).xy(), s.arg::<Vec4>(5).zw(), s.arg::<Vec4>(6).xy()];
        s.if_(!covered(s, curved, mr, &traced, prism), |s| s.discard());
    }
    Hit::at_found(&mr.ray, traced.t.clamp(0.0, mr.ray.t_max()), traced.found)
}

/// The NDC depth of the hit: the point the unit view ray reaches after descending
/// `(t − t_entry)·depth` along the normal, `(t − t_entry)·depth / cos_view` along the ray.
fn hit_depth<'a>(s: &'a FnBuilder<'a>, mr: &MeshRay<'a>, point: Val<'a, Vec3>, hit: &Hit<'a>) -> Val<'a, f32> {
    let world = point + mr.view * depth_offset(mr, hit);
    let clip = s.param::<Mat4>(Param::ViewProj) * s.vec4(world, 1.0);
    clip.z() / clip.w()
}

/// How far the hit lies behind the fragment along the unit view ray: it is `(t − t_entry)·depth`
/// below the entry along the unit normal (`depth` the ray's, [`MeshRay::depth`]), and the view
/// ray descends `cos_view` per unit length.
pub(crate) fn depth_offset<'a>(mr: &MeshRay<'a>, hit: &Hit<'a>) -> Val<'a, f32> {
    (hit.t - mr.t_entry) * mr.depth / mr.ray.cos_view
}

fn fragment_args(m: &ModuleCtx) -> Vec<(&'static str, naga::Handle<naga::Type>, Option<Binding>)> {
    let v4 = m.ty(Vec4::inner());
    VARYINGS.iter().enumerate().map(|(i, n)| (*n, v4, Some(location(i as u32)))).collect()
}

/// `fs_mesh`: trace, shade (albedo, the normal map's normal in the fragment's frame, the
/// shadow stage's visibility, ambient × ao) and write colour and depth.
fn fragment_entry(m: &ModuleCtx, policy: &dyn Policy, fns: &StageFns, curved: Curved) -> naga::EntryPoint {
    let s = m.function("fs_mesh", &fragment_args(m), policy);
    let (inputs, point) = varying_inputs(&s);
    let mr = mesh_ray(&s, curved, &inputs);
    let hit = mesh_trace(&s, fns, curved, &mr);
    let depth_out = hit_depth(&s, &mr, point, &hit);
    if curved == Curved::Quadric {
        // The shadow and ao stages search from the hit: the quadric is centred there.
        recentre_quadric(&s, hit.uv);
    }
    let hv = s.pack(&hit);
    let light = s.param::<Vec4>(Param::Light);
    let depth = mr.depth;
    let (l_uv, l_n) = mr.frame.to_texture(light.xyz());
    let visibility = match fns.shadow {
        Some(f) => {
            let light_n = s.vec3(l_uv * (depth / l_n.max(1e-3)), 1.0);
            s.wrap::<f32>(s.call(f, &[hv, light_n.handle(), l_n.handle()], true).unwrap())
        }
        None => s.lit(1.0),
    };
    let occlusion = match fns.ao {
        Some(f) => s.wrap::<f32>(s.call(f, &[hv], true).unwrap()),
        None => s.lit(1.0),
    };
    let normal = mr.frame.to_object(s.normal(hit.uv));
    let albedo = s.sample(Image::Albedo, hit.uv, Filter::Linear).xyz();
    let ambient = light.w();
    let diffuse = normal.dot(light.xyz()).max(0.0);
    let color = albedo * (ambient * occlusion + (s.lit(1.0) - ambient) * diffuse * visibility);
    let out_ty = super::fragment_output_with_depth(m);
    let v = s.make_struct(out_ty, &[s.vec4(color, 1.0).handle(), depth_out.handle()]);
    let f = s.finish(Some((out_ty, None, v)));
    entry_point("fs_mesh", ShaderStage::Fragment, f, [0; 3])
}

/// `fs_mesh_depth`: the same trace and discards, only the depth written (the depth pre-pass
/// and the shadow caster).
fn depth_entry(m: &ModuleCtx, policy: &dyn Policy, fns: &StageFns, curved: Curved) -> naga::EntryPoint {
    let s = m.function(DEPTH_ENTRY, &fragment_args(m), policy);
    let (inputs, point) = varying_inputs(&s);
    let mr = mesh_ray(&s, curved, &inputs);
    let hit = mesh_trace(&s, fns, curved, &mr);
    let depth = hit_depth(&s, &mr, point, &hit);
    let f = s.finish(Some((m.ty(f32::inner()), Some(Binding::BuiltIn(BuiltIn::FragDepth)), depth.handle())));
    entry_point(DEPTH_ENTRY, ShaderStage::Fragment, f, [0; 3])
}

/// `fs_mesh_probe`: the same trace and discards as `fs_mesh`, writing `(u, v, distance, 1)`
/// and the hit's depth. The distance is the fragment's own distance from the eye plus
/// [`depth_offset`], the hit's place along the same unit view ray that `fs_mesh`'s depth
/// is taken at, so the probe's distance and the frame's depth are one point.
fn probe_entry(m: &ModuleCtx, policy: &dyn Policy, fns: &StageFns, curved: Curved) -> naga::EntryPoint {
    let s = m.function(PROBE_ENTRY, &fragment_args(m), policy);
    let (inputs, point) = varying_inputs(&s);
    let mr = mesh_ray(&s, curved, &inputs);
    let hit = mesh_trace(&s, fns, curved, &mr);
    let depth_out = hit_depth(&s, &mr, point, &hit);
    let camera = s.param::<Vec4>(Param::Camera);
    let distance = (point - camera.xyz()).length() + depth_offset(&mr, &hit);
    let out_ty = super::fragment_output_with_depth(m);
    let record = s.vec4(s.vec3(hit.uv, distance), 1.0);
    let v = s.make_struct(out_ty, &[record.handle(), depth_out.handle()]);
    let f = s.finish(Some((out_ty, None, v)));
    entry_point(PROBE_ENTRY, ShaderStage::Fragment, f, [0; 3])
}

/// Builds the mesh module of `p` (`p.curved` is `Some`), not yet validated, with its binding
/// table; `probe` adds the measurement entry `fs_mesh_probe`.
pub(crate) fn compose_mesh(p: &Pipeline, curved: Curved, probe: bool) -> Result<(Module, Bindings), CompileError> {
    check_mesh_options(p, curved)?;
    let m = ModuleCtx::new();
    let policy =
        MeshPolicy { plain: Plain { lod: p.lod }, quadric: curved == Curved::Quadric, lift: curved == Curved::Prism };
    let fns = write_stage_fns(&m, p, &policy, false)?;
    let vs = vertex_entry(&m, &policy);
    let fs = fragment_entry(&m, &policy, &fns, curved);
    let ds = depth_entry(&m, &policy, &fns, curved);
    // The probe shares the stage functions; the other entries are the same without it.
    let ps = probe.then(|| probe_entry(&m, &policy, &fns, curved));
    let (mut module, bindings) = super::finish(m)?;
    module.entry_points.extend([vs, fs, ds]);
    module.entry_points.extend(ps);
    Ok((module, bindings))
}

/// The fragment's ray on the host, as the fragment writes it for `none` and `quadric`: the
/// unit view ray `view` (object space) in the frame `t`, `b`, `n` (unit, orthogonal) with
/// `scale` texture units per object unit along t and b, for a relief `depth` object units
/// deep; returns the direction in normalized tangent space (t = 1 descends `depth`). The
/// runtime's reference and the tests state the shader's convention with it.
pub fn tangent_ray_dir(view: [f64; 3], t: [f64; 3], b: [f64; 3], n: [f64; 3], scale: [f64; 2], depth: f64) -> [f64; 3] {
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let descent = (-dot(view, n)).max(1e-6);
    let k = depth / descent;
    [dot(view, t) * scale[0] * k, dot(view, b) * scale[1] * k, -1.0]
}

/// The name of the depth-only entry.
pub const DEPTH_ENTRY: &str = "fs_mesh_depth";

/// The name of the measurement entry (`compose::Options::mesh_probe`).
pub const PROBE_ENTRY: &str = "fs_mesh_probe";

/// The quadric's height `a·Δu² + b·Δv²` (object units) at texture offset (Δu, Δv) from its
/// vertex: the host's statement of what the shader adds to every height read (divided by the
/// relief's depth), for a runtime's reference and the tests.
pub fn quadric_height(coeffs: [f64; 2], du: f64, dv: f64) -> f64 {
    coeffs[0] * du * du + coeffs[1] * dv * dv
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wgsl(text: &str) -> Result<String, CompileError> {
        let p: Pipeline = text.parse().unwrap();
        let c = crate::compose::compile(&p)?;
        crate::emit::wgsl(&c)
    }

    /// One pipeline of each coarse family (linear, one-shot, cone safe and textbook, max-mip,
    /// sphere tracing) with refine, shadow and ao stages, under each mode: the module
    /// validates, and WGSL, SPIR-V and GLSL come out of it.
    #[test]
    fn every_family_validates_in_each_mode() {
        for base in [
            "linear(32)+binary(5)+shadow=soft(16)",
            "parallax",
            "iterative_parallax(4)+binary(3)",
            "csm(15)+binary(5)+ao=cone_ratio",
            "rcs(15, form=textbook)+secant(3)",
            "maxmip(32)+interval(2)",
            "sphere(20)+shadow=hard(sphere(10))",
            "linear_dynamic(8, 32)+secant(4)+lod=level(1)",
        ] {
            for mode in ["none", "quadric", "prism"] {
                let text = format!("{base}+curved={mode}");
                let out = crate::emit::emit(&text.parse().unwrap()).unwrap_or_else(|e| panic!("{text}: {e}"));
                let stages: Vec<&str> = out.glsl.iter().map(|(s, _)| *s).collect();
                assert_eq!(stages, ["vert", "frag", "depth.frag"], "{text}");
                assert!(out.wgsl.contains("fn vs_mesh(") && out.wgsl.contains("fn fs_mesh_depth("), "{text}");
                assert!(out.wgsl.contains("@builtin(frag_depth)"), "{text}");
                // Only the quadric warps heights, and it warps the coarse stage's reads.
                assert_eq!(out.wgsl.contains("relief_quadric"), mode == "quadric", "{text}");
                let coarse = out.wgsl.split("\nfn coarse_").nth(1).and_then(|f| f.split("\nfn ").next()).unwrap();
                assert_eq!(coarse.contains("relief_quadric_origin"), mode == "quadric", "{text}");
                // Only quadric and prism discard; none draws every fragment as the flat tile does.
                assert_eq!(out.wgsl.contains("discard"), mode != "none", "{text}");
            }
        }
    }

    /// `curved=none` on a flat mesh (T = x, B = y, N = z, one texture unit per object unit)
    /// is the flat tile's ray: relief's own fragment sets `dir = (v.xy · d / −v.z, −1)`
    /// (`compose::fragment_entry`). On a tilted, scaled frame the ray walked to t lands where
    /// the straight object-space ray is, `t·d` below the surface along N (an independent
    /// statement: the object point mapped back through the frame).
    #[test]
    fn the_mesh_ray_is_the_flat_tiles_on_a_flat_mesh_and_follows_the_view_ray() {
        let norm = |v: [f64; 3]| {
            let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            [v[0] / l, v[1] / l, v[2] / l]
        };
        let views = [[0.3, -0.2, -0.9], [0.9, 0.1, -0.2], [-0.05, 0.6, -0.4], [0.0, 0.0, -1.0]].map(norm);
        for v in views {
            let d = 0.07;
            let dir = tangent_ray_dir(v, [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 1.0], d);
            let flat = [v[0] * d / -v[2], v[1] * d / -v[2], -1.0];
            for i in 0..3 {
                assert!((dir[i] - flat[i]).abs() <= 1e-12 * flat[i].abs().max(1.0), "{v:?}: {dir:?} vs {flat:?}");
            }
        }
        // A frame turned about x by 40° and scaled: T = x, B = (0, cos, sin), N = (0, −sin, cos).
        let (c, s) = (40f64.to_radians().cos(), 40f64.to_radians().sin());
        let (t, b, n, scale, depth) = ([1.0, 0.0, 0.0], [0.0, c, s], [0.0, -s, c], [3.0, 0.5], 0.2);
        for v in [[0.2, -0.5, -0.6], [0.7, 0.3, -0.7]].map(norm) {
            let dir = tangent_ray_dir(v, t, b, n, scale, depth);
            let along_n = v[0] * n[0] + v[1] * n[1] + v[2] * n[2];
            for tt in [0.25, 0.5, 1.0] {
                // The object-space point t·depth below the surface along the view ray.
                let len = tt * depth / -along_n;
                let p = [v[0] * len, v[1] * len, v[2] * len];
                let uv = [
                    (p[0] * t[0] + p[1] * t[1] + p[2] * t[2]) * scale[0],
                    (p[0] * b[0] + p[1] * b[1] + p[2] * b[2]) * scale[1],
                ];
                assert!((uv[0] - tt * dir[0]).abs() < 1e-12 && (uv[1] - tt * dir[1]).abs() < 1e-12, "{v:?} at {tt}");
            }
        }
    }

    /// The quadric against a sphere's exact geometry. On a sphere of radius R the tangent
    /// plane at the top (0, 0, R) and a point (x, y, R + z) below it (z < 0, r² = x² + y²):
    /// its exact depth below the sphere is `R − √(r² + (R+z)²)`, the quadric's
    /// `quadric_height − z` with `a = b = −1/(2R·s²)` at texture offset `s·(x, y)`. With
    /// `√(1+ε) = 1 + ε/2 − ε²/8 + …` (alternating, ε = r²/(R+z)² < 1) the two differ by at
    /// most `r²|z| / (2R(R+z)) + r⁴ / (8(R+z)³)`: the bound asserted. The flat tile's depth
    /// (`−z`, no quadric) misses by more than that bound on the same points.
    #[test]
    fn the_quadric_gives_a_rays_depth_below_a_sphere() {
        let (r_sphere, s) = (2.0f64, 4.0f64);
        let a = -1.0 / (2.0 * r_sphere * s * s);
        // Rays from the tangent point into the shell, points along them.
        for (dir, depth_max) in [([0.6, 0.0, -0.3], 0.1), ([0.3, 0.4, -0.2], 0.08), ([0.05, -0.9, -0.1], 0.05)] {
            for k in 1..=8 {
                let f = k as f64 / 8.0;
                let z = -depth_max * f;
                let scale = z / dir[2];
                let (x, y) = (dir[0] * scale, dir[1] * scale);
                let r2 = x * x + y * y;
                let exact = r_sphere - (r2 + (r_sphere + z) * (r_sphere + z)).sqrt();
                let quadric = quadric_height([a, a], s * x, s * y) - z;
                let bound = r2 * z.abs() / (2.0 * r_sphere * (r_sphere + z)) + r2 * r2 / (8.0 * (r_sphere + z).powi(3));
                assert!(
                    (quadric - exact).abs() <= bound,
                    "{dir:?} z={z}: quadric {quadric} exact {exact} bound {bound}"
                );
                assert!((-z - exact).abs() > bound, "{dir:?} z={z}: the flat depth is within the bound too");
            }
        }
    }

    /// The measurement entry is added only when asked for, and the shipped entries are the
    /// same text with or without it (naga writes each function from the same IR).
    #[test]
    fn the_probe_entry_leaves_the_shipped_entries_as_they_are() {
        for mode in ["none", "quadric", "prism"] {
            let p: Pipeline = format!("linear(32)+binary(5)+shadow=soft(8)+curved={mode}").parse().unwrap();
            let plain = crate::emit::wgsl(&crate::compose::compile(&p).unwrap()).unwrap();
            let options = crate::compose::Options { mesh_probe: true, ..Default::default() };
            let probed = crate::emit::wgsl(&crate::compose::compile_with(&p, &options).unwrap()).unwrap();
            assert!(!plain.contains(PROBE_ENTRY) && probed.contains(&format!("fn {PROBE_ENTRY}(")), "{mode}");
            let entry = |text: &str, name: &str| {
                let start = text.find(&format!("fn {name}(")).unwrap();
                let body = &text[start..];
                body[..body.find("\n}\n").unwrap()].to_string()
            };
            for name in ["vs_mesh", "fs_mesh", DEPTH_ENTRY] {
                assert_eq!(entry(&plain, name), entry(&probed, name), "{mode} {name}");
            }
            assert!(plain.len() < probed.len());
        }
    }

    #[test]
    fn options_of_the_flat_tile_are_refused_by_name() {
        for (text, names) in [
            ("linear(32)+silhouette=clip+curved=prism", ["silhouette=clip", "curved=prism"]),
            ("linear(32)+lod=auto+curved=quadric", ["lod=auto", "curved=quadric"]),
        ] {
            let e = wgsl(text).expect_err(text).to_string();
            assert!(names.iter().all(|n| e.contains(n)) && !e.contains('\n'), "{text}: {e}");
        }
    }
}
