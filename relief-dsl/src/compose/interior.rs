//! Interior mapping with relief on every wall (Amaro & Gustafsson 2022, §2.2, §2.4).
//!
//! A window quad (the rectangle `[0, W] × [0, H]` at world `z = 0`) shows a box room behind
//! it, `z ∈ [−D, 0]`, with five walls ([`WALL_NAMES`]). The fragment entry `fs_room`:
//!
//! 1. finds the wall the view ray from the camera through the fragment meets (§2.2.1,
//!    eq. 1–4): per axis, the plane the ray heads for, `t = (plane − camera) / (frag −
//!    camera)`, and the nearest of the three;
//! 2. takes the hit point into that wall's tangent space ([`wall_frame`]: u, v along the
//!    wall's edges in `[0, 1]`, height z with the wall's plane at z = 1 and the deepest point
//!    `depth_scale` world units behind it, the relief convention of ARCHITECTURE.md), and scales the
//!    ray so that t = 1 reaches z = 0;
//! 3. runs the pipeline's coarse + refine (+ shadow, + ao) on that wall's maps (§2.4: one
//!    relief function per wall, in the wall's space) and shades with the wall's albedo and
//!    normal maps and the room's light, a point or a directional light.
//!
//! **Maps: five bindings per map.** Each wall has its own textures: the stage functions are
//! built five times, once per wall, with every texture the stages (and the shading) declare
//! renamed `NAME_wallK` and bound at the next free binding from [`WALL_BASE`] (the module's
//! binding table, [`Compiled::bindings`], names the wall and the image of each); samplers,
//! the `Params` block and the [`RoomParams`] block are shared. The stages are unchanged: they sample
//! `height_map` as always and get the wall's. Precomputed maps (cone maps, …) are per wall in
//! the same way. Walls are sampled with clamp-to-edge (`params.quad.y = 1`).
//!
//! The probe entry `probe_room` (compute, [`RoomRay`] in, [`RoomHit`] out) runs the same
//! selection and the counted trace, and reports per ray the wall and the hit in the wall's
//! tangent space.

use bytemuck::{Pod, Zeroable};
use naga::{Module, ShaderStage};

use super::{
    entry_point, finish_probe, finish_vertex, location, probe_function, probe_start, probe_trace, vertex_function,
    write_stage_fns, Compiled, ProbeIo, ProbeSlot, ProbeTrace, StageFns,
};
use crate::abi::{abi_record, binding, Param};
use crate::ir::{
    Bindings, FnBuilder, Image, Mat4, ModuleCtx, Plain, Policy, Resource, TextureSite, Ty, Val, Vec2, Vec3, Vec4,
};
use crate::spec::Pipeline;
use crate::stage::{Filter, Hit, Ray};
use crate::CompileError;

/// The walls, in index order.
pub const WALL_NAMES: [&str; 5] = ["back", "left", "right", "floor", "ceiling"];
/// Number of walls.
pub const WALLS: usize = 5;

/// Binding of the window's opacity map (read when [`RoomParams::size`]`[3]` is 1).
pub const WINDOW_MAP: u32 = binding::ROOM_WINDOW;
/// Binding of the [`RoomParams`] uniform block.
pub const ROOM_PARAMS: u32 = binding::ROOM_PARAMS;
/// The first binding of the walls' textures: each texture a wall reads gets the next free
/// binding from here, in the order the module declares them (the module's binding table,
/// [`Compiled::bindings`], says which is which). Bindings stay small: GLSL limits sampler
/// bindings (80 in glslang).
pub const WALL_BASE: u32 = 6;
/// Binding of the [`RoomRay`] storage buffer of `probe_room`.
pub const ROOM_RAYS: u32 = binding::RAYS;
/// Binding of the [`RoomHit`] storage buffer of `probe_room`.
pub const ROOM_HITS: u32 = binding::HITS;

abi_record! {
/// The room block (64 bytes) at binding [`ROOM_PARAMS`]. The `Params` block is shared
/// with plain modules and holds, for a room: `view_proj` world → clip, `camera.xyz` the
/// camera in world units, `light.xyz` the unit vector toward a directional light or the
/// position of a point light, `light.w` the ambient share, `quad.y = 1` (walls clamp).
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct RoomParams {
    /// Width W, height H, depth D of the room (world units); w: 1 when the window has an
    /// opacity map.
    pub size: [f32; 4],
    /// Depth scale (world units from a wall's plane to its height 0) of walls 0–3.
    pub depth_a: [f32; 4],
    /// x: depth scale of wall 4; y: 1 for a point light, 0 for a directional one; z, w: 0.
    pub depth_b: [f32; 4],
    /// For light scattering ([`RoomOptions::scatter`]): xyz the unit vector toward the sun
    /// outside the window (`z > 0`), w its intensity.
    pub sun: [f32; 4],
}
}

abi_record! {
/// One ray of `probe_room` (32 bytes): from `origin` (world, the camera) along `dir` (world,
/// any length); the fourth components are padding.
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct RoomRay {
    /// The ray's origin in world units (w: 0).
    pub origin: [f32; 4],
    /// The ray's direction (w: 0).
    pub dir: [f32; 4],
}
}

abi_record! {
/// What `probe_room` reports per ray (32 bytes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct RoomHit {
    /// The wall the ray meets ([`WALL_NAMES`]).
    pub wall: u32,
    /// The search's raw t in the wall's normalized tangent space (t = 1 at height 0).
    pub t: f32,
    /// Where the hit lands on the wall, u.
    pub u: f32,
    /// Where the hit lands on the wall, v.
    pub v: f32,
    /// The hit's height.
    pub z: f32,
    /// Coarse loop passes.
    pub coarse_steps: u32,
    /// Refine loop passes.
    pub refine_steps: u32,
    /// 1 when the coarse search found the surface.
    pub converged: u32,
}
}

/// A wall's frame in world units: the point at `(u, v, z) = (0, 0, 1)`, the edges along
/// which u and v go from 0 to 1, and the unit normal into the room. A point `(u, v, z)` of
/// the wall's relief is `origin + u·u_edge + v·v_edge + (z − 1)·depth_scale·normal`;
/// `û × v̂ = normal` for every wall.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallFrame {
    /// The corner at u = v = 0.
    pub origin: [f64; 3],
    /// The edge along u (length: the wall's extent in u).
    pub u_edge: [f64; 3],
    /// The edge along v.
    pub v_edge: [f64; 3],
    /// The unit normal, pointing into the room.
    pub normal: [f64; 3],
}

/// Coefficients of W, H, D per component of origin, u edge, v edge, and the normal, per wall.
const FRAMES: [[[f64; 3]; 4]; WALLS] = [
    // back: z = −D, u along +x, v along +y
    [[0.0, 0.0, -1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
    // left: x = 0, u from the window to the back, v up
    [[0.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]],
    // right: x = W, u from the back to the window, v up
    [[1.0, 0.0, -1.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]],
    // floor: y = 0, u along +x, v from the window to the back
    [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]],
    // ceiling: y = H, u along +x, v from the back to the window
    [[0.0, 1.0, -1.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]],
];

/// Wall `k`'s frame in a room of `size = [W, H, D]` (the host side of what the shader
/// computes).
pub fn wall_frame(k: usize, size: [f64; 3]) -> WallFrame {
    let f = FRAMES[k];
    let scale = |c: [f64; 3]| [c[0] * size[0], c[1] * size[1], c[2] * size[2]];
    WallFrame { origin: scale(f[0]), u_edge: scale(f[1]), v_edge: scale(f[2]), normal: f[3] }
}

/// Options of the room module.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RoomOptions {
    /// Light scattering through the window (Amaro & Gustafsson 2022, §2.3) with this many samples along the
    /// view ray; `None` (the default): off. The sun is [`RoomParams::sun`]; each sample adds
    /// `SCATTER_WEIGHT`, decaying by `SCATTER_DECAY`, where the sun passes the window.
    pub scatter: Option<u32>,
}

/// Share of the in-scattered light each sample adds, before decay.
pub(crate) const SCATTER_WEIGHT: f32 = 0.6;
/// Decay of each further sample's contribution (Amaro & Gustafsson 2022, §2.3: "a diminished intensity each
/// step of the way").
pub(crate) const SCATTER_DECAY: f32 = 0.97;

/// The walls' frames in the shader, from the room's size.
struct Frame<'a> {
    origin: Val<'a, Vec3>,
    u_edge: Val<'a, Vec3>,
    v_edge: Val<'a, Vec3>,
    normal: Val<'a, Vec3>,
}

fn frame<'a>(s: &'a FnBuilder<'a>, k: usize, size: Val<'a, Vec3>) -> Frame<'a> {
    let f = FRAMES[k];
    let v = |c: [f64; 3]| s.vec3(s.vec2(size.x() * c[0] as f32, size.y() * c[1] as f32), size.z() * c[2] as f32);
    let n = f[3];
    Frame {
        origin: v(f[0]),
        u_edge: v(f[1]),
        v_edge: v(f[2]),
        normal: s.vec3(s.vec2(n[0] as f32, n[1] as f32), n[2] as f32),
    }
}

/// The member `name` of the [`RoomParams`] block.
fn room_param<'a>(s: &'a FnBuilder<'a>, name: &str) -> Val<'a, Vec4> {
    let g = s
        .module()
        .bound("room", naga::AddressSpace::Uniform, ROOM_PARAMS, Resource::RoomParams, |m| m.record_ty::<RoomParams>());
    s.load(s.member_ptr::<RoomParams>(s.global_ptr(g), name))
}

fn depth_scale<'a>(s: &'a FnBuilder<'a>, k: usize) -> Val<'a, f32> {
    let (a, b) = (room_param(s, "depth_a"), room_param(s, "depth_b"));
    match k {
        0 => a.x(),
        1 => a.y(),
        2 => a.z(),
        3 => a.w(),
        _ => b.x(),
    }
}

/// Amaro & Gustafsson 2022, eq. 1–4: per axis the plane the ray `cam + t·w` heads for, its t, and the
/// nearest. Returns (wall index, t).
fn select_wall<'a>(
    s: &'a FnBuilder<'a>,
    cam: Val<'a, Vec3>,
    w: Val<'a, Vec3>,
    size: Val<'a, Vec3>,
) -> (Val<'a, u32>, Val<'a, f32>) {
    let zero = s.lit(0.0);
    let left = w.x().lt(0.0);
    let tx = s.select(left, zero - cam.x(), size.x() - cam.x()) / w.x();
    let down = w.y().lt(0.0);
    let ty = s.select(down, zero - cam.y(), size.y() - cam.y()) / w.y();
    let tz = (zero - size.z() - cam.z()) / w.z();
    let wall = s.var::<u32>("wall", 0u32);
    let t = s.var::<f32>("t_wall", tz);
    s.if_(tx.lt(t.get()), |s| {
        t.set(tx);
        wall.set(s.select(left, 1u32, 2u32));
    });
    s.if_(ty.lt(t.get()), |s| {
        t.set(ty);
        wall.set(s.select(down, 3u32, 4u32));
    });
    (wall.get(), t.get())
}

/// The world ray `cam + t·w`, met at `t_wall` on wall `k`, in the wall's normalized tangent
/// space (Amaro & Gustafsson 2022, §2.4: "a view matrix transform … into each wall's space").
fn wall_ray<'a>(
    s: &'a FnBuilder<'a>,
    f: &Frame<'a>,
    scale: Val<'a, f32>,
    cam: Val<'a, Vec3>,
    w: Val<'a, Vec3>,
    t_wall: Val<'a, f32>,
) -> Ray<'a> {
    let x = cam + w * t_wall;
    let rel = x - f.origin;
    let uu = f.u_edge.dot(f.u_edge);
    let vv = f.v_edge.dot(f.v_edge);
    let origin = s.vec2(rel.dot(f.u_edge) / uu, rel.dot(f.v_edge) / vv);
    let view = w.normalize();
    let into = view.dot(f.normal); // < 0: toward the wall
    let k = scale / (-into).max(1e-6);
    let dir = s.vec3(s.vec2(view.dot(f.u_edge) / uu, view.dot(f.v_edge) / vv) * k, -1.0);
    Ray { origin, dir, cos_view: -into }
}

/// The world point of a wall's relief at `(uv, z)`.
fn wall_point<'a>(f: &Frame<'a>, scale: Val<'a, f32>, uv: Val<'a, Vec2>, z: Val<'a, f32>) -> Val<'a, Vec3> {
    f.origin + f.u_edge * uv.x() + f.v_edge * uv.y() + f.normal * ((z - 1.0) * scale)
}

/// Stores the camera distance for [`crate::stage::coarse::linear::linear_distance`] when
/// a stage of the module reads it.
pub(crate) fn store_view_distance<'a>(s: &'a FnBuilder<'a>, d: Val<'a, f32>) {
    if let Some(g) = s.module().find_global(crate::stage::coarse::linear::VIEW_DISTANCE) {
        s.store(s.global_ptr(g), d.handle());
    }
}

/// A wall's policy: every texture the stages (and the shading) read is wall `k`'s own,
/// named `NAME_wallK` and bound, the first time the wall reads it, at the next binding from
/// [`WALL_BASE`] after the walls' textures the module's binding table already holds;
/// samplers, uniforms and private globals stay shared. Walls are sampled at level 0, with the
/// edge mode of `Params` (clamp).
struct Wall<'t> {
    k: u32,
    module: &'t ModuleCtx,
}

impl Policy for Wall<'_> {
    fn texture(&self, name: &str, _plain: u32) -> TextureSite {
        let name = format!("{name}_wall{}", self.k);
        let table = self.module.bindings();
        let binding = match table.iter().find(|e| e.name == name) {
            Some(e) => e.binding,
            None => table
                .iter()
                .filter(|e| matches!(e.resource, Resource::Texture { wall: Some(_), .. }))
                .map(|e| e.binding + 1)
                .max()
                .unwrap_or(WALL_BASE),
        };
        TextureSite { name, binding, wall: Some(self.k) }
    }
}

/// The stage functions for each wall (`counted`: the probe's variant), each under its
/// wall's policy.
fn wall_fns(m: &ModuleCtx, p: &Pipeline, walls: &[Wall<'_>], counted: bool) -> Result<Vec<StageFns>, CompileError> {
    let mut out = Vec::new();
    for wall in walls {
        let before = m.module.borrow().functions.len();
        let fns = write_stage_fns(m, p, wall, counted)?;
        for (i, (_, f)) in m.module.borrow_mut().functions.iter_mut().enumerate() {
            if i >= before {
                f.name = f.name.take().map(|n| format!("{n}_wall{}", wall.k));
            }
        }
        out.push(fns);
    }
    Ok(out)
}

fn vertex_entry(m: &ModuleCtx, policy: &dyn Policy) -> naga::EntryPoint {
    let s = vertex_function(m, "vs_room", policy);
    // The window: (0,0) (W,0) (0,H) (W,H) as a triangle strip, at z = 0.
    let i = s.arg::<u32>(0);
    let size = room_param(&s, "size");
    let world = s.vec3(s.vec2(i.and(1).to_f32() * size.x(), i.shift_right(1).to_f32() * size.y()), 0.0);
    let clip = s.param::<Mat4>(Param::ViewProj) * s.vec4(world, 1.0);
    finish_vertex(&s, "vs_room", "RoomVertex", clip, world)
}

/// The glass colour the window's opacity blends toward.
const GLASS: [f32; 3] = [0.72, 0.78, 0.84];

/// Light scattering through the window (Amaro & Gustafsson §2.3): the window's inverted
/// opacity says which rays of the sun pass the glass. From the window point along the view
/// ray to the wall's plane, `samples` points at equal intervals; at each, the ray toward the
/// sun is followed back to the window's plane, and where it passes the window's clear part
/// the sample adds `weight · decay^i · (1 − opacity)`; the sum, times the sun's intensity
/// over the samples, is added to the colour. Our reading of the paper's "paint the hit plane
/// again and again at a known interval with a diminished intensity": a march along the view
/// ray through the room's air, lit only where the window lets the sun in.
fn scattering<'a>(
    s: &'a FnBuilder<'a>,
    samples: u32,
    world: Val<'a, Vec3>,
    far: Val<'a, Vec3>,
    size: Val<'a, Vec3>,
    window_on: Val<'a, bool>,
) -> Val<'a, f32> {
    let sun = room_param(s, "sun");
    let to_sun = sun.xyz();
    let sum = s.var::<f32>("scatter", 0.0);
    let k = s.var::<f32>("scatter_k", 0.0);
    let w = s.var::<f32>("scatter_w", SCATTER_WEIGHT);
    let n = samples.max(1);
    s.repeat(n, |s| {
        let p = world + (far - world) * ((k.get() + 0.5) / n as f32);
        let q = p + to_sun * ((-p.z()) / to_sun.z().max(1e-4));
        let inside = q.x().ge(0.0) & q.x().le(size.x()) & q.y().ge(0.0) & q.y().le(size.y()) & to_sun.z().gt(1e-4);
        let uv = s.vec2(q.x() / size.x(), 1.0 - q.y() / size.y());
        let opacity = s.sample(Image::Window, uv, Filter::Linear).x();
        let clear = s.select(window_on, 1.0 - opacity, s.lit(1.0));
        sum.set(sum.get() + s.select(inside, w.get() * clear, s.lit(0.0)));
        w.set(w.get() * SCATTER_DECAY);
        k.set(k.get() + 1.0);
    });
    sum.get() * sun.w() / n as f32
}

fn fragment_entry(
    m: &ModuleCtx,
    policy: &dyn Policy,
    walls: &[Wall<'_>],
    fns: &[StageFns],
    options: &RoomOptions,
) -> naga::EntryPoint {
    let s = m.function("fs_room", &[("world", m.ty(Vec3::inner()), Some(location(0)))], policy);
    let world = s.arg::<Vec3>(0);
    let cam = s.param::<Vec4>(Param::Camera).xyz();
    let size = room_param(&s, "size").xyz();
    let w = world - cam;
    let (wall, t_wall) = select_wall(&s, cam, w, size);
    let light = s.param::<Vec4>(Param::Light);
    let ambient = light.w();
    let point_light = room_param(&s, "depth_b").y().gt(0.5);
    let color = s.var::<Vec3>("color", s.vec3(s.vec2(0.0, 0.0), 0.0));
    let far = s.var::<Vec3>("far", world);
    for (k, (wall_policy, fns)) in walls.iter().zip(fns).enumerate() {
        s.if_(wall.ge(k as u32) & wall.le(k as u32), |s| {
            s.with_policy(wall_policy, || {
                let f = frame(s, k, size);
                let scale = depth_scale(s, k);
                let ray = wall_ray(s, &f, scale, cam, w, t_wall);
                store_view_distance(s, (w * t_wall).length());
                let traced: Hit = s.unpack(s.call(fns.trace, &[s.pack(&ray)], true).unwrap());
                let hit = Hit::at_found(&ray, traced.t.clamp(0.0, ray.t_max()), traced.found);
                let hv = s.pack(&hit);
                let p = wall_point(&f, scale, hit.uv, hit.z);
                let to_point = (light.xyz() - p).normalize();
                let to_light = s.select(point_light, to_point, light.xyz().normalize());
                let ln = to_light.dot(f.normal);
                let uu = f.u_edge.dot(f.u_edge);
                let vv = f.v_edge.dot(f.v_edge);
                let visibility = match fns.shadow {
                    Some(sh) => {
                        let lk = scale / ln.max(1e-3);
                        let light_n =
                            s.vec3(s.vec2(to_light.dot(f.u_edge) / uu, to_light.dot(f.v_edge) / vv) * lk, 1.0);
                        let v = s.wrap::<f32>(s.call(sh, &[hv, light_n.handle(), ln.handle()], true).unwrap());
                        s.select(ln.gt(0.0), v, s.lit(0.0))
                    }
                    None => s.lit(1.0),
                };
                let occlusion = match fns.ao {
                    Some(a) => s.wrap::<f32>(s.call(a, &[hv], true).unwrap()),
                    None => s.lit(1.0),
                };
                let n = s.normal(hit.uv);
                let n_world =
                    (f.u_edge * (n.x() / uu.sqrt()) + f.v_edge * (n.y() / vv.sqrt()) + f.normal * n.z()).normalize();
                let albedo = s.sample(Image::Albedo, hit.uv, Filter::Linear).xyz();
                let diffuse = n_world.dot(to_light).max(0.0);
                color.set(albedo * (ambient * occlusion + (1.0 - ambient) * diffuse * visibility));
                far.set(cam + w * t_wall);
            })
        });
    }
    // The window's opacity map (optional): opaque parts show glass, not the room.
    let window_on = room_param(&s, "size").w().gt(0.5);
    if let Some(n) = options.scatter {
        let i = scattering(&s, n, world, far.get(), size, window_on);
        color.set(color.get() + s.vec3(s.vec2(i, i), i) * s.vec3(s.vec2(1.0, 0.95), 0.85));
    }
    let out = s.var::<Vec3>("out", color.get());
    s.if_(window_on, |s| {
        let uv = s.vec2(world.x() / size.x(), 1.0 - world.y() / size.y());
        let opacity = s.sample(Image::Window, uv, Filter::Linear).x();
        let glass = s.vec3(s.vec2(GLASS[0], GLASS[1]), GLASS[2]);
        out.set(color.get().mix(glass, s.vec3(s.vec2(opacity, opacity), opacity)));
    });
    let f = s.finish(Some((m.ty(Vec4::inner()), Some(location(0)), s.vec4(out.get(), 1.0).handle())));
    entry_point("fs_room", ShaderStage::Fragment, f, [0; 3])
}

fn probe_entry(m: &ModuleCtx, policy: &dyn Policy, walls: &[StageFns]) -> naga::EntryPoint {
    let io = ProbeIo::new::<RoomRay, RoomHit>(m, "room_rays", "room_hits");
    let s = probe_function(m, "probe_room", policy);
    let ProbeSlot { ray: rec, hit: out, counters } = probe_start(&s, &io);
    let cam = s.load::<Vec4>(s.member_ptr::<RoomRay>(rec, "origin")).xyz();
    let w = s.load::<Vec4>(s.member_ptr::<RoomRay>(rec, "dir")).xyz();
    let size = room_param(&s, "size").xyz();
    let (wall, t_wall) = select_wall(&s, cam, w, size);
    for (k, fns) in walls.iter().enumerate() {
        s.if_(wall.ge(k as u32) & wall.le(k as u32), |s| {
            let f = frame(s, k, size);
            let scale = depth_scale(s, k);
            let ray = wall_ray(s, &f, scale, cam, w, t_wall);
            store_view_distance(s, (w * t_wall).length());
            let ProbeTrace { hit, coarse_steps, refine_steps, converged, .. } =
                probe_trace(s, fns.trace, &ray, counters);
            let values = [
                ("wall", wall.handle()),
                ("t", hit.t.handle()),
                ("u", hit.uv.x().handle()),
                ("v", hit.uv.y().handle()),
                ("z", hit.z.handle()),
                ("coarse_steps", coarse_steps.handle()),
                ("refine_steps", refine_steps.handle()),
                ("converged", converged.handle()),
            ];
            s.store_record::<RoomHit>(out, &values);
        });
    }
    finish_probe(&s, "probe_room")
}

/// The pipeline options the room entries do not implement, as errors: the room's entries set
/// no sample level (`lod`), a window has no quad square to clip to (`silhouette`), and a
/// room's walls are flat (`curved`).
fn refuse_render_options(p: &Pipeline) -> Result<(), CompileError> {
    let refuse = |what: String| {
        Err(CompileError { stage: "room".into(), message: format!("{what} is not implemented for rooms yet") })
    };
    if p.lod != crate::spec::Lod::Zero {
        return refuse(format!("lod={}", p.lod));
    }
    if p.silhouette != crate::spec::Silhouette::None {
        return refuse(format!("silhouette={}", p.silhouette));
    }
    if let Some(c) = p.curved {
        return refuse(format!("curved={c}"));
    }
    Ok(())
}

fn compose_room(p: &Pipeline, options: &RoomOptions) -> Result<(Module, Bindings), CompileError> {
    refuse_render_options(p)?;
    let m = ModuleCtx::new();
    let walls: Vec<Wall> = (0..WALLS as u32).map(|k| Wall { k, module: &m }).collect();
    let shared = Plain::default();
    let plain = wall_fns(&m, p, &walls, false)?;
    let counted = wall_fns(&m, p, &walls, true)?;
    let vs = vertex_entry(&m, &shared);
    let fs = fragment_entry(&m, &shared, &walls, &plain, options);
    let cs = probe_entry(&m, &shared, &counted);
    drop(walls);
    let (mut module, bindings) = super::finish(m)?;
    module.entry_points.extend([vs, fs, cs]);
    Ok((module, bindings))
}

/// Builds and validates the room module for `p`; its binding table names each wall's
/// textures ([`Resource::Texture`] with `wall`).
pub fn compile_room(p: &Pipeline, options: &RoomOptions) -> Result<Compiled, CompileError> {
    if options.scatter.is_some_and(|n| !(1..=4096).contains(&n)) {
        return Err(CompileError {
            stage: "scatter".into(),
            message: format!("{} scattering samples: allowed 1..=4096", options.scatter.unwrap_or(0)),
        });
    }
    let (module, bindings) = compose_room(p, options)?;
    let info = super::validate(&module)?;
    Ok(Compiled { module, info, bindings })
}
