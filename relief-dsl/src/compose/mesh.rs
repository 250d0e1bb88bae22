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
//!   deep as the relief, [`MeshVertex::position`]`.w` the layer), every vertex carrying the
//!   triangle's corners (points, normals, uvs). Each fragment intersects the view ray with the
//!   prism's exact volume, the map `X(b, w) = Σ bᵢ (Pᵢ − depth·(1 − w)·Nᵢ)` (N not
//!   renormalized, as S): its flat top and floor and its three bilinear side walls
//!   (`ray_bilinear_wall`); the first crossing is the entry, the last the exit, each with
//!   its exact (u, v, w), so every face of a prism computes the same answer (`prism_chord`).
//!   No crossing: discarded (a neighbour's prism owns the ray). An entry strictly below S
//!   through a sealed side wall or the floor: discarded before the search, exactly, a nearer
//!   fragment draws the pixel (`early_out`). The stages search the texture-space chord from
//!   the entry to the exit (over heights lifted by an affine function of uv so that their
//!   descending ray from height 1 is the chord), bent onto the quadratic through the view
//!   ray's exact point at its middle (`prism_bend`); a hit that is not on the lifted surface
//!   (the search met nothing) or after the exit is discarded; the hit is then polished onto S
//!   along the true view ray by Newton's method (`polish_on_s`), a hit the polish does not keep
//!   is discarded too, and colour, depth and the probe take the polished point.
//!
//! Limitation of `prism`: the view ray through the prism's map is a curve in texture space,
//! and the search follows the quadratic through three of its points (or, where the coarse
//! stage reads maps, the straight chord); a hit the path passes where the curve does not (or
//! the reverse) is lost or gained before the polish. The rasterized faces are flat (two triangles per
//! bilinear wall), so a ray through the exact prism may meet none of its drawn faces (and no
//! fragment runs) where a wall twists. Every face of a prism runs the same trace, so a runtime
//! may cull the back faces (the prisms are wound outward; relief's runtime culls them).

use bytemuck::{Pod, Zeroable};
use naga::{Binding, BuiltIn, Module, ShaderStage, TypeInner};

use super::{entry_point, location, write_stage_fns, StageFns};
use crate::abi::{abi_record, Param};
use crate::ir::{Bindings, FnBuilder, Image, Mat4, ModuleCtx, Plain, Policy, Ty, Val, Vec2, Vec3, Vec4};
use crate::spec::{Curved, Lod, Pipeline, Silhouette};
use crate::stage::sampling::{
    LAYER_SHARE, PRISM_BEND, PRISM_BEND_AXIS, PRISM_LIFT, PRISM_ORIGIN, PRISM_STOP, QUADRIC_COEFFS, QUADRIC_ORIGIN,
};
use crate::stage::{Filter, Hit, Ray};
use crate::CompileError;

abi_record! {
/// One vertex of a mesh module (208 bytes, thirteen `vec4<f32>`): the vertex layout, the one
/// statement of it. The vertex entry reads member k at `@location(k)`, in this order; every
/// mode reads the same record ([`vertex_members`] of its members), and a member a mode does
/// not use is ignored (zero it).
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
    /// `prism`: xy the texture coordinates of corner 2; z: which faces of the prism allow the
    /// early-out behind the hit (docs/meshes-shaders.md, "The modes"), a bitmask held
    /// as a float: bit k (k = 0, 1, 2) the side wall over the edge from corner k to corner
    /// k + 1 (mod 3) when that wall is *sealed* (shared with exactly one other triangle whose
    /// two ends carry bitwise the same point, normal and uv), bit 3 the floor. 0 (no face):
    /// no early-out, every fragment runs the whole trace (the behaviour before the early-out).
    /// w: 0.
    pub prism_b: [f32; 4],
    /// `prism`: xyz corner 0's point on the base surface (object space, as its `position`);
    /// w: 0. The same at all six vertices of the prism; read only under `curved=prism` (the
    /// other modes' vertex entries declare members 0‥6 only).
    pub prism_p0: [f32; 4],
    /// `prism`: corner 1's point, as `prism_p0`.
    pub prism_p1: [f32; 4],
    /// `prism`: corner 2's point, as `prism_p0`.
    pub prism_p2: [f32; 4],
    /// `prism`: xyz corner 0's normal (as its `normal`, the one S interpolates); w: 0.
    pub prism_n0: [f32; 4],
    /// `prism`: corner 1's normal, as `prism_n0`.
    pub prism_n1: [f32; 4],
    /// `prism`: corner 2's normal, as `prism_n0`.
    pub prism_n2: [f32; 4],
}
}

abi_record! {
/// One triangle of the prism walk (`compose::Options::prism_walk`; 208 bytes, thirteen
/// `vec4<f32>`): the prism's corners, as [`MeshVertex`]'s `prism_*` members carry them, the
/// triangles across its joined side walls, and its corners' tangents and scales. The runtime uploads one per triangle, in the
/// order the vertices' `prism_b.w` names them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PrismCell {
    /// xyz: corner 0's point on the base surface (object space). w: the triangle across the
    /// side wall over the edge from corner 0 to corner 1 when that wall is sealed (the index,
    /// a float, exact below 2²⁴), −1 where it is not ([`MeshVertex::prism_b`]'s sealed walls).
    pub p0: [f32; 4],
    /// Corner 1's point; w: the triangle across the wall from corner 1 to corner 2, as `p0`.
    pub p1: [f32; 4],
    /// Corner 2's point; w: the triangle across the wall from corner 2 to corner 0, as `p0`.
    pub p2: [f32; 4],
    /// xyz: corner 0's normal (as its vertex's, the one S interpolates); w: 0.
    pub n0: [f32; 4],
    /// Corner 1's normal, as `n0`.
    pub n1: [f32; 4],
    /// Corner 2's normal, as `n0`.
    pub n2: [f32; 4],
    /// xy: corner 0's texture coordinates, zw: corner 1's.
    pub uv01: [f32; 4],
    /// xy: corner 2's texture coordinates. z: the prism's headroom, 1 minus the largest
    /// height of the texels a bilinear read anywhere in the triangle's uv blends (level 0),
    /// for the walk's skip of prisms the ray crosses above the relief (`prism_walk`);
    /// 0 never skips. w: 0.
    pub uv2: [f32; 4],
    /// Corner 0's tangent, as its vertex's [`MeshVertex::tangent`] (w the handedness): with
    /// `t1`, `t2` and the scales, the shading frame at the hit (`walk_frame`).
    pub t0: [f32; 4],
    /// Corner 1's tangent, as `t0`.
    pub t1: [f32; 4],
    /// Corner 2's tangent, as `t0`.
    pub t2: [f32; 4],
    /// xy: corner 0's texture units per object unit along T and B (its vertex's `uv.zw`);
    /// zw: corner 1's.
    pub scale01: [f32; 4],
    /// xy: corner 2's texture units per object unit, as `scale01`; zw: 0.
    pub scale2: [f32; 4],
}
}

/// The global of the prism walk's triangles, `array<PrismCell>` at
/// [`crate::abi::binding::PRISM_CELLS`].
const PRISM_CELLS: &str = "prism_cells";

/// The most prisms one fragment's walk visits. A walk that reaches it without a hit or an
/// end is discarded (its pixel lost; the probe marks it, `WalkOut::at_limit`). The goal
/// cells' walks search 1.5–3.5 prisms per pixel on average and at most 56 (a ray along the
/// built-in sphere's pole, whose fan has 96 thin triangles; docs/notes/meshes.md, "One
/// fragment walks the prisms"), so 128 is a bound, not a setting: a pixel that reaches it is
/// counted, not hidden.
pub const PRISM_WALK_LIMIT: u32 = 128;

/// The most prisms the walk's second try visits, after a hit the polish does not keep: the
/// crossing Newton found outside the hit prism's triangle is in the next prism or the one
/// after, and a ray that entered a uv seam's crack may wander the pole's
/// fan below S. A second try that reaches it draws nothing: the pixel is lost (and counted in
/// the coverage), not marked as at [`PRISM_WALK_LIMIT`].
pub const PRISM_RETRY_LIMIT: u32 = 8;

/// The depth the probe writes for a pixel whose walk reached [`PRISM_WALK_LIMIT`]: the
/// farthest below the cleared 1.0, so that any fragment with a hit at the pixel wins the
/// depth test over the mark.
const PRISM_WALK_LIMIT_DEPTH: f32 = 1.0 - 1.0 / (1u32 << 24) as f32;

/// How far (in units of the relief's depth) the lower end of a prism's chord must lie above
/// the prism's highest texel ([`PrismCell::uv2`]'s headroom) for the walk to skip its search.
/// The search's hit is drawn only at t ≤ k + [`PRISM_SLACK`] and no more than
/// [`PRISM_ABOVE_SLACK`] (1/32) above S; on the chord from the entry to there the layer is at
/// least the chord's lower end less 1.1e-4 (its slope is at most 16/15 of the depth per unit
/// of t), and the device's heights exceed the host's by at most the R16Float rounding (5e-4).
/// 1/32 + 1/256 is more than all three, so a skipped prism's search could not have been drawn:
/// the skip changes no pixel.
const PRISM_SKIP_MARGIN: f32 = 1.0 / 32.0 + 1.0 / 256.0;

/// How many of [`MeshVertex`]'s members the vertex entry of `curved` reads (at locations
/// 0‥n−1): the first seven for `none` and `quadric`, all thirteen for `prism` (its triangle's
/// corners for the exact entry and exit).
pub fn vertex_members(curved: Curved) -> usize {
    match curved {
        Curved::None | Curved::Quadric => 7,
        Curved::Prism => MeshVertex::MEMBERS.len(),
    }
}

/// [`vertex_members`] of a `curved=prism` module that walks (`compose::Options::prism_walk`):
/// the first seven, as `none`'s (the walk reads the corners from its buffer; `prism_b.w`
/// names the triangle); `curved`'s own count otherwise.
pub fn vertex_members_for(curved: Curved, walk: bool) -> usize {
    if walk && curved == Curved::Prism {
        7
    } else {
        vertex_members(curved)
    }
}

/// The mesh module's policy: relief's plain one, with the quadric added to every height read
/// under `curved=quadric` and the prism's lift under `curved=prism`.
struct MeshPolicy {
    plain: Plain,
    quadric: bool,
    lift: bool,
    /// The coarse stage reads maps: the chord's straight pieces are searched, each untilted
    /// where it descends ([`piece_search`]).
    untilted: bool,
    /// The walk gives each chord its share of the linear searches' layers ([`chord_share`]).
    share: bool,
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
    fn prism_untilted(&self) -> bool {
        self.untilted
    }
    fn layer_share(&self) -> bool {
        self.share
    }
}

/// Whether `p`'s chord is searched as straight pieces, each untilted where it descends, under
/// `curved=prism` ([`piece_search`], `Policy::prism_untilted`): its coarse stage reads a
/// precomputed map, whose bounds hold for the unlifted field shifted by a constant, along
/// straight rays, but not under a tilt or along a curve.
pub(crate) fn coarse_reads_maps(p: &Pipeline) -> bool {
    !p.maps_of(crate::spec::Slot::Coarse).is_empty()
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

/// The vertex varyings, members 1‥ at locations 0‥ (member 0 is the clip position): the
/// point (xyz, w the prism layer), the normal, the tangent, the uv with its scales, the
/// curvature and the prism's corner uvs, each as the vertex gave it; under `prism` also the
/// corners' points and normals, flat (the same at every vertex of a prism).
const VARYINGS: [&str; 13] = [
    "point",
    "normal",
    "tangent",
    "uv",
    "curvature",
    "prism_a",
    "prism_b",
    "prism_p0",
    "prism_p1",
    "prism_p2",
    "prism_n0",
    "prism_n1",
    "prism_n2",
];

/// The binding of varying `n`: perspective-interpolated, but the prism's corners (7‥12) flat.
fn varying_binding(n: u32) -> Binding {
    if n < 7 {
        return location(n);
    }
    Binding::Location {
        location: n,
        interpolation: Some(naga::Interpolation::Flat),
        sampling: None,
        blend_src: None,
        per_primitive: false,
    }
}

fn vertex_input(n: u32) -> Binding {
    Binding::Location { location: n, interpolation: None, sampling: None, blend_src: None, per_primitive: false }
}

/// `vs_mesh`: the vertex, moved to its prism layer, in clip space, and the varyings.
fn vertex_entry(m: &ModuleCtx, policy: &dyn Policy, curved: Curved, walk: bool) -> naga::EntryPoint {
    let v4 = m.ty(Vec4::inner());
    let n = vertex_members_for(curved, walk);
    let args: Vec<(&str, _, _)> =
        MeshVertex::MEMBERS[..n].iter().enumerate().map(|(i, (n, _))| (*n, v4, Some(vertex_input(i as u32)))).collect();
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
    for (i, name) in VARYINGS[..n].iter().enumerate() {
        members.push(naga::StructMember {
            name: Some((*name).into()),
            ty: v4,
            binding: Some(varying_binding(i as u32)),
            offset: 16 * (i as u32 + 1),
        });
    }
    let span = 16 * (n as u32 + 1);
    let out_ty = m.module.borrow_mut().types.insert(
        naga::Type { name: Some("MeshVarying".into()), inner: TypeInner::Struct { members, span } },
        naga::Span::UNDEFINED,
    );
    let mut values = vec![clip.handle(), s.vec4(point, position.w()).handle()];
    values.extend((1..n as u32).map(|i| s.arg::<Vec4>(i).handle()));
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

/// How far (in the search's t) a hit may lie past the prism's exit and still count as
/// inside: the exit is computed in f32, good to a few ulps of 1; 1e-4 covers that, and a hit
/// on a shared wall is drawn by both prisms rather than by neither (a goal, not measured yet).
const PRISM_SLACK: f32 = 1e-4;

/// How far outside its face a crossing of the prism's boundary may lie (in barycentrics, a
/// wall's edge parameter and the layer) and still count: a ray through a shared edge or wall
/// is then a crossing of both prisms, not of neither; 1e-5 is a hundred f32 ulps of 1.
const PRISM_FACE_SLACK: f32 = 1e-5;

/// The texture-space length (`|Δuv|`) under which the chord is searched without the affine
/// lift's tilt (module doc of `stage::sampling`, `PRISM_LIFT`): the tilt's slope is
/// `(1 − r)/|Δuv|`, and with texture coordinates good to ~1e-6 a chord this short would carry
/// an error of `1e-6 / 1e-3 = 1e-3` depths; shorter chords descend (`r > 0`) or are discarded.
const PRISM_SHORT_CHORD: f32 = 1e-3;

/// The search's t at the exit of a chord searched whole: the stages search to t = 1 and
/// report a hit there even where they met nothing (the flat tile's floor is always met), so
/// the exit lies short of 1 and such a search ends past it, where it is discarded as after
/// the exit; 1/16 of the search's steps fall past the exit.
const PRISM_CHORD_END: f32 = 15.0 / 16.0;

/// Newton's steps of the inversion of the chord's middle ([`prism_bend`]), from the chord's
/// own middle: the chord is the curve's secant, so its middle lies off the curve by the
/// curve's sag (a few hundredths of a barycentric at most on the goal scenes), and Newton's
/// method squares that error each step: one step leaves an error of the order of the sag
/// squared, below the quadratic's own departure from the curve. (Two steps cost 5 % more
/// frame time on lavapipe; the emulation, with the same one step, gives the GPU's t on every
/// pixel of the tests' views.)
const PRISM_BEND_STEPS: usize = 1;

/// The largest bend kept, in barycentrics and in layers: a Newton's step that moves the middle
/// further has not met the curve (a ray grazing the prism's volume), and the chord is
/// searched straight, as before the bend.
const PRISM_BEND_MAX: f32 = 0.25;

/// The most straight pieces a chord searched untilted follows ([`piece_search`],
/// [`piece_count`]): the bent chord's quadratic through its points at `i/n`. A map's bounds
/// hold along straight rays only, so a coarse stage that reads maps cannot follow the
/// quadratic read by read as the linear family does. Four pieces put the runtime's emulation
/// (f64, a dense search) at or below the bent quadratic's figures on all twelve goal cells,
/// two pieces not (docs/notes/meshes.md, "Safe marches along the bent chord").
const PRISM_PIECES: u32 = 4;

/// How far (in units of the relief's depth) the pieces may depart from the bent chord's
/// quadratic ([`piece_count`]): 1e-3, issue 38's RMS t goal.
const PRISM_PIECE_TOLERANCE: f32 = 1e-3;

/// The texture-space length (`|Δuv|`) under which a chord is not bent: the bend reads each
/// point's fraction of the chord from its texture coordinates, `(uv − uv_in)·Δuv/|Δuv|²`,
/// good to ~1e-7/|Δuv| (texture coordinates of order 1 in f32); a chord shorter than 1e-5 is
/// nearly along the prism's normals, where the curve's sag is smaller than that rounding.
const PRISM_BEND_SHORT: f32 = 1e-5;

/// The prism's triangle as the fragment gets it (`curved=prism`): each corner's point on the
/// base surface relative to the fragment's point, its normal (N, not renormalized, as S
/// interpolates it) and its texture coordinates, object space.
pub(crate) struct PrismCorners<'a> {
    pub(crate) p: [Val<'a, Vec3>; 3],
    pub(crate) n: [Val<'a, Vec3>; 3],
    pub(crate) uv: [Val<'a, Vec2>; 3],
    /// The faces that allow the early-out behind the hit ([`MeshVertex::prism_b`]'s z, the
    /// bitmask as a float); `None`: no early-out code at all (the library form).
    pub(crate) early: Option<Val<'a, f32>>,
}

/// How far (in units of the relief's depth, the layer w's unit) the prism's entry must lie
/// below S (`h(uv_in) − w_in > ε`) for the early-out behind the hit ([`early_out`]). The
/// neighbouring prism computes the same wall point from its own fragment's point, in its own
/// ray frame: the two (uv, w) agree up to f32 rounding of object-space values of order 1
/// (a few ulps, ~1e-7 object units) divided by the relief's depth (0.01‥0.1 object units in
/// the scenes: ~1e-5 of the depth at worst), and h moves by its gradient times the uv's
/// rounding (~1e-7 texture units times a few hundred texels: ~1e-5); 1e-4 of the depth is ten
/// times both. Its only effect: a fragment whose entry lies within ε below S runs the whole
/// trace as before.
pub(crate) const PRISM_EARLY_EPSILON: f32 = 1e-4;

/// Whether bit `bit` of the float bitmask `mask` (an integer 0‥15 held exactly) is set.
fn mask_bit<'a>(mask: Val<'a, f32>, bit: u32) -> Val<'a, bool> {
    let shifted = (mask * (1.0 / (1u32 << bit) as f32)).floor() * 0.5;
    (shifted - shifted.floor()).gt(0.25)
}

/// The view ray inside the prism: where it enters and leaves the prism's exact volume
/// ([`prism_chord`]) and the texture-space chord between the two that the stages search.
pub(crate) struct Chord<'a> {
    /// Whether the ray crosses the prism's boundary twice (no crossing: a neighbour owns it).
    crosses: Val<'a, bool>,
    /// The entry's and the exit's distance from the fragment's point along the unit view ray.
    t_in: Val<'a, f32>,
    t_out: Val<'a, f32>,
    /// The search's t of the exit: [`PRISM_CHORD_END`], or `r` where a short chord is searched
    /// untilted.
    k: Val<'a, f32>,
    /// The barycentrics of corners 0 and 1 at the entry and at the exit.
    b_in: Val<'a, Vec2>,
    b_out: Val<'a, Vec2>,
    /// The layer at the entry and its drop to the exit (`r = w_in − w_out`).
    w_in: Val<'a, f32>,
    /// The entry's texture coordinates, and the chord's texture-space length to the exit.
    uv_in: Val<'a, Vec2>,
    duv: Val<'a, Vec2>,
    /// Whether the entry's face allows the early-out (a sealed wall or the floor,
    /// [`PrismCorners::early`]); `None` without the early-out.
    early_in: Option<Val<'a, bool>>,
    /// The walk's: the exit's face, 0, 1, 2 the side wall from corner k to k + 1, 3 the floor,
    /// 4 the top (a float holding the integer); `None` outside a walk.
    exit_face: Option<Val<'a, f32>>,
    /// The walk's: the barycentrics of corners 0 and 1 where the ray meets the top's plane,
    /// inside the top or not; `None` outside a walk.
    top_b: Option<Val<'a, Vec2>>,
    r: Val<'a, f32>,
    /// The chord's share of the linear searches' layers ([`chord_share`]); `None` outside a
    /// walk.
    share: Option<Val<'a, f32>>,
    /// The lift while the search runs: `(at the entry, slope along u, slope along v)`.
    lift: Val<'a, Vec3>,
    /// The chord's bend ([`prism_bend`]): the reads follow it where the chord is searched
    /// tilted, the pieces ([`piece_search`]) where the coarse stage reads maps
    /// (`Policy::prism_untilted`: the maps bound the field along straight rays only).
    bend: Bend<'a>,
    /// The stages' ray: from the entry's uv at height 1 toward the exit's (`dir.xy = Δuv / k`).
    search: Ray<'a>,
}

/// The view ray's curve through a prism's map against the chord ([`prism_bend`]).
struct Bend<'a> {
    /// [`crate::stage::sampling`]'s `PRISM_BEND`: xy the texture offset, z the layer offset of
    /// the curve's middle from the chord's, w 0.
    offset: Val<'a, Vec4>,
    /// `PRISM_BEND_AXIS`: `Δuv/|Δuv|²`, or 0 for a chord not bent.
    axis: Val<'a, Vec2>,
    /// The barycentrics' offset (b₀, b₁) of the curve's middle from the chord's.
    b: Val<'a, Vec2>,
}

/// The chord's bend: the view ray through the prism's map `X(b, w)` is a curve in (b, w), and
/// so in texture space, that meets the chord at the entry and the exit. Its point at the middle
/// of the ray's segment (t halfway between entry and exit) is found by Newton's method on
/// `X(b, w) = ray(t_mid)` from the chord's middle ([`PRISM_BEND_STEPS`], in the ray's frame,
/// [`RayFramed`]: `X`'s Jacobian columns are `∂X/∂b₀`, `∂X/∂b₁` and `depth·N(b)`, solved by
/// Cramer's rule); the search then follows the quadratic through entry, middle and exit
/// (`stage::sampling`'s `PRISM_BEND`). The quadratic is not the curve: what is left between
/// them is third order in the segment's length, measured against the exact curve by the
/// runtime's emulation (docs/notes/meshes.md, "The chord bent").
#[allow(clippy::too_many_arguments)]
fn prism_bend<'a>(
    s: &'a FnBuilder<'a>,
    top: [Val<'a, Vec3>; 3],
    d: [Val<'a, Vec3>; 3],
    (at_in, at_out): (Val<'a, Vec3>, Val<'a, Vec3>),
    (t_in, t_out): (Val<'a, f32>, Val<'a, f32>),
    uv: [Val<'a, Vec2>; 3],
    duv: Val<'a, Vec2>,
    len2: Val<'a, f32>,
) -> Bend<'a> {
    let zero3 = s.vec3(s.vec2(0.0, 0.0), 0.0);
    let mid = (at_in + at_out) * 0.5;
    let target = s.vec3(s.vec2(0.0, 0.0), (t_in + t_out) * 0.5);
    let mut x = mid;
    for _ in 0..PRISM_BEND_STEPS {
        let (b0, b1, sink) = (x.x(), x.y(), 1.0 - x.z());
        let b2 = 1.0 - b0 - b1;
        let at = |k: usize| top[k] - d[k] * sink;
        let f = at(0) * b0 + at(1) * b1 + at(2) * b2 - target;
        let c0 = (top[0] - top[2]) - (d[0] - d[2]) * sink;
        let c1 = (top[1] - top[2]) - (d[1] - d[2]) * sink;
        let c2 = d[0] * b0 + d[1] * b1 + d[2] * b2;
        let n = c1.cross(c2);
        let det = c0.dot(n);
        let usable = det.abs().gt(1e-30);
        let inv = 1.0 / s.select(usable, det, s.lit(1.0));
        let rhs = -f;
        let step = s.vec3(s.vec2(rhs.dot(n), c0.dot(rhs.cross(c2))), c0.dot(c1.cross(rhs))) * inv;
        x = x + s.select(usable, step, zero3);
    }
    let delta = x - mid;
    let tame =
        delta.x().abs().le(PRISM_BEND_MAX) & delta.y().abs().le(PRISM_BEND_MAX) & delta.z().abs().le(PRISM_BEND_MAX);
    let bends = tame & len2.ge(PRISM_BEND_SHORT * PRISM_BEND_SHORT);
    let delta = s.select(bends, delta, zero3);
    let duv_bend = (uv[0] - uv[2]) * delta.x() + (uv[1] - uv[2]) * delta.y();
    Bend {
        offset: s.vec4(s.vec3(duv_bend, delta.z()), 0.0),
        axis: s.select(bends, duv / len2.max(1e-30), s.vec2(0.0, 0.0)),
        b: delta.xy(),
    }
}

/// A point of the prism in the ray's frame: `xy` its components along `n1` and `n2` (two unit
/// vectors orthogonal to the view ray and to each other), `z` along the unit view ray `v`.
/// The ray from the fragment's point is the line `xy = 0` there, and a point on it is `z` away.
type RayFramed<'a> = (Val<'a, Vec2>, Val<'a, f32>);

/// The 2D cross product `a.x·b.y − a.y·b.x`.
fn cross2<'a>(a: Val<'a, Vec2>, b: Val<'a, Vec2>) -> Val<'a, f32> {
    a.x() * b.y() - a.y() * b.x()
}

/// The crossing of the ray with the triangle `q` (its corners in the ray's frame,
/// [`RayFramed`]): t, whether it lies in the triangle (within [`PRISM_FACE_SLACK`]) and the
/// barycentrics of corners 0 and 1 there. The ray is the line `xy = 0`, so the crossing's
/// barycentrics are the origin's in the projected triangle, `bₖ` the signed area of the
/// triangle the origin makes with the other two corners over the whole's (the same numbers as
/// Möller & Trumbore 1997's: their determinant is the whole's doubled signed area, the sum of
/// the three 2D cross products here), and t their blend of the corners' `z`.
fn ray_triangle<'a>(s: &'a FnBuilder<'a>, q: [RayFramed<'a>; 3]) -> (Val<'a, f32>, Val<'a, bool>, Val<'a, Vec2>) {
    let [(p0, z0), (p1, z1), (p2, z2)] = q;
    let (a0, a1, a2) = (cross2(p1, p2), cross2(p2, p0), cross2(p0, p1));
    let det = a0 + a1 + a2;
    let usable = det.abs().gt(1e-20);
    let inv = 1.0 / s.select(usable, det, s.lit(1.0));
    let (b0, b1, b2) = (a0 * inv, a1 * inv, a2 * inv);
    let t = b0 * z0 + b1 * z1 + b2 * z2;
    let ok = usable & b1.ge(-PRISM_FACE_SLACK) & b2.ge(-PRISM_FACE_SLACK) & (b1 + b2).le(1.0 + PRISM_FACE_SLACK);
    (t, ok, s.vec2(b0, b1))
}

/// A root of [`ray_bilinear_wall`]: the crossing's t along the ray, whether it lies on the
/// wall, its σ along the edge and its layer w.
type WallRoot<'a> = (Val<'a, f32>, Val<'a, bool>, Val<'a, f32>, Val<'a, f32>);

/// The crossings of the ray with a prism's side wall: the ruled surface
/// `W(σ, w) = F_i + σ(F_j − F_i) + w·D_i + σw·(D_j − D_i)`, σ along the edge from corner i
/// to j and w the layer, `F` the floor corners and `D = depth·N`, each given in the ray's
/// frame ([`RayFramed`]). This is the exact wall of the prism's map
/// `X(b, w) = Σ bₖ (Pₖ − depth·(1 − w)·Nₖ)` where the third corner's barycentric is 0:
/// bilinear in (σ, w), not planar where `N_i ≠ N_j` (Hoetzlein 2025's side walls), so the
/// rasterized wall (two flat triangles) is not where the prism ends, and the fragment's own
/// frame is not the prism's map. Why a quadratic: the ray is the meet of the two planes
/// `x = 0` and `y = 0` of its frame, each plane's equation in (σ, w) is bilinear,
/// `a + bσ + cw + fσw = 0`; eliminating w leaves a quadratic in σ (Ramsey, Potter & Hansen
/// 2004). Returns each root's t (the wall's `z` there), whether it lies on the wall, σ and w.
fn ray_bilinear_wall<'a>(
    s: &'a FnBuilder<'a>,
    fi: RayFramed<'a>,
    fj: RayFramed<'a>,
    di: RayFramed<'a>,
    dj: RayFramed<'a>,
) -> [WallRoot<'a>; 2] {
    let (a, c) = (fi.0, di.0);
    let (b, f) = (fj.0 - fi.0, dj.0 - di.0);
    let (za, zb, zc, zf) = (fi.1, fj.1 - fi.1, di.1, dj.1 - di.1);
    // (a₁ + b₁σ)(c₂ + f₂σ) − (a₂ + b₂σ)(c₁ + f₁σ) = qa·σ² + qb·σ + qc.
    let qa = b.x() * f.y() - b.y() * f.x();
    let qb = a.x() * f.y() + b.x() * c.y() - a.y() * f.x() - b.y() * c.x();
    let qc = a.x() * c.y() - a.y() * c.x();
    let disc = qb * qb - 4.0 * qa * qc;
    let root = disc.max(0.0).sqrt();
    // The two roots without cancellation: q = −(qb ± √disc)/2, σ = q/qa and qc/q (the
    // second is the linear root where qa is 0).
    let q = (qb + s.select(qb.ge(0.0), root, -root)) * -0.5;
    let sigma1 = q / s.select(qa.abs().gt(1e-30), qa, s.lit(1e-30));
    let sigma2 = qc / s.select(q.abs().gt(1e-30), q, s.lit(1e-30));
    [sigma1, sigma2].map(|sigma| {
        let den = c + f * sigma;
        let num = a + b * sigma;
        let first = den.x().abs().ge(den.y().abs());
        let d = s.select(first, den.x(), den.y());
        let usable = d.abs().gt(1e-20);
        let w = -s.select(first, num.x(), num.y()) / s.select(usable, d, s.lit(1.0));
        let t = za + zb * sigma + (zc + zf * sigma) * w;
        let inside = |x: Val<'a, f32>| x.ge(-PRISM_FACE_SLACK) & x.le(1.0 + PRISM_FACE_SLACK);
        (t, disc.ge(0.0) & usable & inside(sigma) & inside(w), sigma, w)
    })
}

/// The view ray (unit `view`, from the fragment's point) through the prism's exact volume:
/// the crossings of its top (layer 1) and floor (layer 0), which are flat triangles, and of its
/// three side walls ([`ray_bilinear_wall`]); the first crossing is the entry, the last the
/// exit, each with its exact (b₀, b₁, w) and so its (u, v, w). The corners are taken into the
/// ray's frame once ([`RayFramed`]: three dot products each for the three points and the
/// three depth-scaled normals), and the five crossings are solved there. The chord between
/// entry and exit in texture space is what the stages search: from the entry's uv at height 1,
/// over heights lifted by the affine function that makes the stages' descending ray meet the
/// lifted field where the chord meets the true one (`stage::sampling`'s `PRISM_LIFT`). The
/// chord is defined whatever the fragment's normal, so a ray level with or rising against the
/// fragment's tangent plane is traced like any other.
///
/// In a walk (`flat_drop` given: the flat tile's drop per texture unit,
/// [`flat_drop_per_texture_unit`]) the exit's face is kept ([`Chord::exit_face`]) and the
/// chord's share of the linear searches' layers computed ([`chord_share`]).
fn prism_chord<'a>(
    s: &'a FnBuilder<'a>,
    view: Val<'a, Vec3>,
    c: &PrismCorners<'a>,
    depth: Val<'a, f32>,
    cos_view: Val<'a, f32>,
    flat_drop: Option<Val<'a, f32>>,
) -> Chord<'a> {
    let walk = flat_drop.is_some();
    let zero3 = s.vec3(s.vec2(0.0, 0.0), 0.0);
    let t_in = s.var("prism_t_in", 1e30);
    let at_in = s.var("prism_at_in", zero3);
    let t_out = s.var("prism_t_out", -1e30);
    let at_out = s.var("prism_at_out", zero3);
    // The entry face's early-out flag (1: a sealed wall or the floor), with the early-out only.
    let early_in = c.early.map(|_| s.var("prism_early_in", 0.0f32));
    let exit_face = walk.then(|| s.var("prism_exit_face", -1.0f32));
    let consider = |t: Val<'a, f32>, ok: Val<'a, bool>, at: Val<'a, Vec3>, early: Option<Val<'a, bool>>, face: f32| {
        let first = ok & t.lt(t_in.get());
        t_in.set(s.select(first, t, t_in.get()));
        at_in.set(s.select(first, at, at_in.get()));
        if let (Some(var), Some(early)) = (&early_in, early) {
            var.set(s.select(first, s.select(early, 1.0f32, 0.0f32), var.get()));
        }
        let last = ok & t.gt(t_out.get());
        t_out.set(s.select(last, t, t_out.get()));
        at_out.set(s.select(last, at, at_out.get()));
        if let Some(var) = &exit_face {
            var.set(s.select(last, s.lit(face), var.get()));
        }
    };
    let axis = s.select(view.x().abs().lt(0.6), s.vec3(s.vec2(1.0, 0.0), 0.0), s.vec3(s.vec2(0.0, 1.0), 0.0));
    let n1 = view.cross(axis).normalize();
    let n2 = view.cross(n1);
    let framed = |x: Val<'a, Vec3>| -> RayFramed<'a> { (s.vec2(n1.dot(x), n2.dot(x)), view.dot(x)) };
    let top = [0, 1, 2].map(|k| framed(c.p[k]));
    let d = [0, 1, 2].map(|k| framed(c.n[k] * depth));
    let floor = [0, 1, 2].map(|k| (top[k].0 - d[k].0, top[k].1 - d[k].1));
    let mut top_b = None;
    for (q, layer, bit, face) in [(top, 1.0, None, 4.0), (floor, 0.0, Some(3), 3.0)] {
        let (t, ok, b) = ray_triangle(s, q);
        if walk && layer == 1.0 {
            top_b = Some(b);
        }
        // The top is never entered below S (w = 1 ≥ h): it carries no flag.
        let early = c.early.map(|m| bit.map_or(s.lit_bool(false), |bit| mask_bit(m, bit)));
        consider(t, ok, s.vec3(b, layer), early, face);
    }
    for (i, j) in [(0usize, 1usize), (1, 2), (2, 0)] {
        let early = c.early.map(|m| mask_bit(m, i as u32));
        for (t, ok, sigma, w) in ray_bilinear_wall(s, floor[i], floor[j], d[i], d[j]) {
            // Barycentrics on the wall: corner i has 1 − σ, corner j σ, the third 0.
            let bary = |k: usize| -> Val<'a, f32> {
                if k == i {
                    1.0 - sigma
                } else if k == j {
                    sigma
                } else {
                    s.lit(0.0)
                }
            };
            consider(t, ok, s.vec3(s.vec2(bary(0), bary(1)), w), early, i as f32);
        }
    }
    let (t_in, at_in, t_out, at_out) = (t_in.get(), at_in.get(), t_out.get(), at_out.get());
    let early_in = early_in.map(|var| var.get().gt(0.5));
    let exit_face = exit_face.map(|var| var.get());
    let uv_at = |at: Val<'a, Vec3>| c.uv[2] + (c.uv[0] - c.uv[2]) * at.x() + (c.uv[1] - c.uv[2]) * at.y();
    let (uv_in, uv_out) = (uv_at(at_in), uv_at(at_out));
    let duv = uv_out - uv_in;
    let (w_in, r) = (at_in.z(), at_in.z() - at_out.z());
    let len2 = duv.dot(duv);
    // A chord long enough in texture space is searched whole (the stages' t from 0 to
    // k = [`PRISM_CHORD_END`] spans entry to exit) over a tilted lift; a shorter one descends
    // untilted (k = r). Where the coarse stage reads maps (`Policy::prism_untilted`) the
    // chord's pieces are searched instead ([`piece_search`]), each untilted where it
    // descends; `k`, the lift and the search ray below are then not used.
    let long = if s.policy().prism_untilted() {
        r.le(1e-4)
    } else {
        len2.ge(PRISM_SHORT_CHORD * PRISM_SHORT_CHORD) | r.le(1e-4)
    };
    let k = s.select(long, s.lit(PRISM_CHORD_END), r);
    // The stages' ray at t is 1 − t high; the chord there is w_in − r·t/k high; the lift is
    // the difference, 1 − w_in − t·(1 − r/k), as a function of uv (uv − uv_in = Δuv·t/k).
    let slope = duv * (-(k - r) / len2.max(1e-12));
    let lift = s.vec3(s.vec2(1.0 - w_in, slope.x()), slope.y());
    let dir = s.vec3(duv / k, -1.0);
    let crosses = t_in.lt(t_out) & (long | r.gt(0.0));
    let share = flat_drop.map(|drop| s.select(long, chord_share(r, len2.sqrt() * drop, k), s.lit(1.0)));
    let v3 = |q: RayFramed<'a>| s.vec3(q.0, q.1);
    let bend = prism_bend(s, top.map(v3), d.map(v3), (at_in, at_out), (t_in, t_out), c.uv, duv, len2);
    let (b_in, b_out) = (at_in.xy(), at_out.xy());
    Chord {
        crosses,
        t_in,
        t_out,
        k,
        b_in,
        b_out,
        w_in,
        uv_in,
        duv,
        early_in,
        exit_face,
        top_b,
        r,
        share,
        lift,
        bend,
        search: Ray { origin: uv_in, dir, cos_view },
    }
}

/// What a mesh fragment traces: its ray, where the ray enters the relief volume in t (0 for
/// `none` and `quadric`), and the view ray's data the depth needs.
pub(crate) struct MeshRay<'a> {
    /// The ray the search runs on, started at height 1 (for `prism` the chord's,
    /// [`Chord::search`]): the t of every hit and depth is this ray's but for `prism`.
    pub(crate) ray: Ray<'a>,
    pub(crate) t_entry: Val<'a, f32>,
    /// The unit view ray, object space.
    view: Val<'a, Vec3>,
    pub(crate) frame: Frame<'a>,
    /// The relief's depth along the unit normal at the fragment: `depth · |N|`, N the
    /// interpolated normal before renormalizing, as S = P − depth·(1 − h)·N descends
    /// (docs/meshes.md); t = 1 of the ray descends this far.
    pub(crate) depth: Val<'a, f32>,
    /// `prism`: the view ray through the prism's exact volume.
    chord: Option<Chord<'a>>,
    /// `prism`: the triangle's corners and the relief's depth (object units), for the polish.
    corners: Option<(PrismCorners<'a>, Val<'a, f32>)>,
    /// `prism` walking: where the walk starts and the relief's depth (object units); the
    /// chord and the corners are then the walk's, one prism at a time ([`prism_walk`]).
    walk: Option<(WalkStart<'a>, Val<'a, f32>)>,
}

/// Where a fragment's prism walk starts: the walk's buffer, the fragment's triangle and its
/// point (the corners are taken relative to it, as the varyings' are).
pub(crate) struct WalkStart<'a> {
    cells: naga::Handle<naga::GlobalVariable>,
    first: Val<'a, u32>,
    point: Val<'a, Vec3>,
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
    /// The quadric's coefficients a, b in object units (only `quadric` reads them).
    pub(crate) curvature: Val<'a, Vec2>,
    /// The relief's depth in object units.
    pub(crate) depth: Val<'a, f32>,
    /// `prism`: the prism's triangle, relative to the fragment's point.
    pub(crate) prism: Option<PrismCorners<'a>>,
    /// `prism` walking (`compose::Options::prism_walk`): where the walk starts; `prism` is then
    /// `None`.
    pub(crate) walk: Option<WalkStart<'a>>,
}

/// The fragment's ray, in the flat tile's convention (ARCHITECTURE.md, "Rays"): the view ray
/// in texture units, scaled so that t = 1 descends the relief's depth. Under `quadric` it also
/// centres the quadric on the entry. For `prism` the ray is the chord through the prism's
/// exact volume ([`prism_chord`]).
pub(crate) fn mesh_ray<'a>(s: &'a FnBuilder<'a>, curved: Curved, i: MeshInputs<'a>) -> MeshRay<'a> {
    let frame = frame(s, i.normal, i.tangent, i.uv);
    // S's layers lie depth·|N| apart along the unit normal (N interpolated, not renormalized).
    let depth = i.depth * i.normal.xyz().length();
    let (v_uv, v_n) = frame.to_texture(i.view);
    let cos_view = descent(v_n);
    if let (Curved::Prism, Some(corners)) = (curved, i.prism) {
        let chord = prism_chord(s, i.view, &corners, i.depth, cos_view, None);
        let ray = chord.search;
        return MeshRay {
            ray,
            t_entry: s.lit(0.0),
            view: i.view,
            frame,
            depth,
            chord: Some(chord),
            corners: Some((corners, i.depth)),
            walk: None,
        };
    }
    if let (Curved::Prism, Some(start)) = (curved, i.walk) {
        // The walk makes its chords one prism at a time; `ray` is the flat tile's, unused.
        let dir = s.vec3(v_uv * (depth / cos_view), -1.0);
        let ray = Ray { origin: i.uv.xy(), dir, cos_view };
        let walk = Some((start, i.depth));
        return MeshRay { ray, t_entry: s.lit(0.0), view: i.view, frame, depth, chord: None, corners: None, walk };
    }
    let dir = s.vec3(v_uv * (depth / cos_view), -1.0);
    let t_entry = s.lit(0.0);
    let origin = i.uv.xy() - dir.xy() * t_entry;
    if curved == Curved::Quadric {
        set_quadric(s, i.curvature / depth, i.uv.xy());
    }
    let ray = Ray { origin, dir, cos_view };
    MeshRay { ray, t_entry, view: i.view, frame, depth, chord: None, corners: None, walk: None }
}

/// The fragment entries' inputs: the varyings and the `Params` block.
fn varying_inputs<'a>(
    s: &'a FnBuilder<'a>,
    curved: Curved,
    walk: Option<naga::Handle<naga::GlobalVariable>>,
) -> (MeshInputs<'a>, Val<'a, Vec3>) {
    let [point, normal, tangent, uv, curvature] = [0, 1, 2, 3, 4].map(|i| s.arg::<Vec4>(i));
    let camera = s.param::<Vec4>(Param::Camera);
    let depth = s.name("depth_scale", camera.w());
    let view = (point.xyz() - camera.xyz()).normalize();
    // The layer (`point.w`), which no mode reads since the prism's exact entry: its expression
    // is still made, so that the `none` and `quadric` modules keep their text to the byte
    // (naga numbers the temporaries by expression).
    let _ = point.w();
    let walking = curved == Curved::Prism && walk.is_some();
    // The fragment's triangle, `prism_b.w`: interpolated like any varying 0‥6, so rounded.
    let walk = walk.filter(|_| walking).map(|cells| WalkStart {
        cells,
        first: s.arg::<Vec4>(6).w().round().to_u32(),
        point: point.xyz(),
    });
    let prism = (curved == Curved::Prism && !walking).then(|| {
        let (a, b) = (s.arg::<Vec4>(5), s.arg::<Vec4>(6));
        PrismCorners {
            p: [7, 8, 9].map(|k| s.arg::<Vec4>(k).xyz() - point.xyz()),
            n: [10, 11, 12].map(|k| s.arg::<Vec4>(k).xyz()),
            uv: [a.xy(), a.zw(), b.xy()],
            early: Some(b.z()),
        }
    });
    let inputs = MeshInputs { view, normal, tangent, uv, curvature: curvature.xy(), depth, prism, walk };
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
/// (the module's doc); `prism`'s are [`prism_trace`]'s.
pub(crate) fn covered<'a>(s: &'a FnBuilder<'a>, curved: Curved, mr: &MeshRay<'a>, traced: &Hit<'a>) -> Val<'a, bool> {
    match curved {
        Curved::None | Curved::Prism => s.lit_bool(true),
        // No hit: the ray left the shell above the curved surface or reached the floor
        // first (Oliveira & Policarpo 2005): the silhouette.
        Curved::Quadric => traced.found & !above_surface(s, &mr.ray, traced),
    }
}

/// The search of a mesh fragment under `none` and `quadric`, its hit on [`MeshRay::ray`].
pub(crate) fn search<'a>(s: &'a FnBuilder<'a>, fns: &StageFns, mr: &MeshRay<'a>) -> Hit<'a> {
    s.unpack(s.call(fns.trace, &[s.pack(&mr.ray)], true).unwrap())
}

/// How far (in units of the relief's depth) the point `prism`'s search returned may lie above
/// the lifted surface and still count as a hit: as [`QUADRIC_SLACK`] (a refined hit lies
/// within its last bracket; a search that met nothing ends at the exit, above the surface).
const PRISM_ABOVE_SLACK: f32 = 1.0 / 32.0;

/// `prism`'s trace: the stages' search on the chord from the exact entry to the exact exit
/// ([`prism_chord`]) over the lifted heights (set for the search and back to 0 after), then
/// the polish of its hit onto S along the view ray ([`polish_on_s`]). Returns the hit (`t`:
/// its distance from the fragment's point along the unit view ray; `uv`, and `z` the layer of
/// the hit) and whether it is drawn: the ray crosses the prism, the search found the surface
/// (its point not above the lifted field by more than [`PRISM_ABOVE_SLACK`]), and not after the
/// exit.
pub(crate) fn prism_trace<'a>(
    s: &'a FnBuilder<'a>,
    fns: &StageFns,
    mr: &MeshRay<'a>,
) -> (Hit<'a>, Val<'a, bool>, Val<'a, Vec2>) {
    let ch = mr.chord.as_ref().expect("prism_trace needs the prism's chord");
    if let Some(early_in) = ch.early_in {
        s.if_(early_out(s, ch, early_in), |s| s.discard());
    }
    let (hit, drawn, b) = chord_search(s, fns, ch);
    let (corners, depth) = mr.corners.as_ref().expect("prism_trace needs the prism's corners");
    let (polished, newton_b, kept) = polish_on_s(s, mr.view, corners, *depth, hit, b);
    (polished, drawn & kept, newton_b)
}

/// The shading frame of a full draw's prism hit at its barycentrics `b` (b₀, b₁): the prism's
/// corner normals blended there, the fragment's interpolated tangent made orthogonal to that
/// normal with its handedness, and the fragment's texture units per object unit; and the
/// relief's depth along that normal (`depth · |N|`). Every face of the prism traces the same
/// hit, and the frame is the hit's whichever face was rasterized, as the walk's is
/// ([`walk_frame`]).
fn prism_hit_frame<'a>(s: &'a FnBuilder<'a>, mr: &MeshRay<'a>, b: Val<'a, Vec2>) -> (Frame<'a>, Val<'a, f32>) {
    let (corners, depth) = mr.corners.as_ref().expect("a prism hit's frame needs the prism's corners");
    let w = [b.x(), b.y(), 1.0 - b.x() - b.y()];
    let normal = corners.n[0] * w[0] + corners.n[1] * w[1] + corners.n[2] * w[2];
    let f = &mr.frame;
    let handedness = f.b.dot(f.n.cross(f.t));
    let frame = frame(
        s,
        s.vec4(normal, 0.0),
        s.vec4(f.t, handedness),
        s.vec4(s.vec3(s.vec2(0.0, 0.0), f.scale.x()), f.scale.y()),
    );
    (frame, *depth * normal.length())
}

/// The stages' search on one prism's chord ([`prism_trace`] without the polish): the hit on
/// the chord (`t` along the view ray from the fragment's point, `z` the layer), whether it is
/// drawn (the ray crosses the prism, the search met the lifted surface, not after the exit)
/// and the barycentrics of corners 0 and 1 there.
fn chord_search<'a>(s: &'a FnBuilder<'a>, fns: &StageFns, ch: &Chord<'a>) -> (Hit<'a>, Val<'a, bool>, Val<'a, Vec2>) {
    if s.policy().prism_untilted() {
        return piece_search(s, fns, ch);
    }
    let m = s.module();
    let lift = s.global_ptr(m.private::<Vec3>(PRISM_LIFT));
    s.store(lift, ch.lift.handle());
    s.store(s.global_ptr(m.private::<Vec2>(PRISM_ORIGIN)), ch.search.origin.handle());
    let bend = Some(&ch.bend).map(|b| {
        let (offset, axis) =
            (s.global_ptr(m.private::<Vec4>(PRISM_BEND)), s.global_ptr(m.private::<Vec2>(PRISM_BEND_AXIS)));
        s.store(offset, b.offset.handle());
        s.store(axis, b.axis.handle());
        (offset, axis, b)
    });
    let share = ch.share.filter(|_| s.policy().layer_share()).map(|v| (s.global_ptr(m.private::<f32>(LAYER_SHARE)), v));
    if let Some((share, v)) = share {
        s.store(share, v.handle());
    }
    let traced: Hit = s.unpack(s.call(fns.trace, &[s.pack(&ch.search)], true).unwrap());
    if let Some((share, _)) = share {
        s.store(share, s.lit(1.0f32).handle());
    }
    let p = ch.search.at(traced.t);
    let above = (p.z() - s.height(p.xy())).gt(PRISM_ABOVE_SLACK);
    s.store(lift, s.vec3(s.vec2(0.0, 0.0), 0.0).handle());
    if let Some((offset, axis, _)) = &bend {
        s.store(*offset, s.vec4(s.vec3(s.vec2(0.0, 0.0), 0.0), 0.0).handle());
        s.store(*axis, s.vec2(0.0, 0.0).handle());
    }
    let after = traced.t.gt(ch.k + PRISM_SLACK);
    let drawn = ch.crosses & traced.found & !above & !after;
    // Along the chord: τ = t/k from the entry (0) to the exit (1).
    let tau = (traced.t / ch.k).clamp(0.0, 1.0);
    let (mut uv, mut layer, mut b) = (p.xy(), ch.w_in - ch.r * tau, ch.b_in + (ch.b_out - ch.b_in) * tau);
    if let Some((_, _, bend)) = bend {
        // The point on the bent chord (the curve's quadratic), as the search's reads took it.
        let weight = crate::stage::sampling::bend_weight(tau);
        uv = uv + bend.offset.xy() * weight;
        layer = layer + bend.offset.z() * weight;
        b = b + bend.b * weight;
    }
    let dist = ch.t_in + (ch.t_out - ch.t_in) * tau;
    let hit = Hit { t: dist, uv, z: layer, found: traced.found };
    (hit, drawn, b)
}

/// Layers of the search of a piece of the bent chord that does not descend
/// ([`level_piece_search`]), and the bisections after it.
const PRISM_LEVEL_STEPS: u32 = 16;
const PRISM_LEVEL_BISECTIONS: u32 = 6;

/// The search of a piece of the bent chord that does not descend (its drop `r` ≤ 1e-4: level
/// or rising, near the silhouette), where the coarse stage reads maps ([`piece_search`]): a
/// map's bounds hold for descending rays only, so the piece is searched by a linear search of
/// its own ([`PRISM_LEVEL_STEPS`] points, the true heights at the piece's points against its
/// layers) and bisections ([`PRISM_LEVEL_BISECTIONS`]). Not exact: a crossing narrower than a
/// sixteenth of the piece can be stepped over. Returns the hit's fraction of the piece and
/// whether the piece met the surface.
fn level_piece_search<'a>(
    s: &'a FnBuilder<'a>,
    uv_a: Val<'a, Vec2>,
    duv: Val<'a, Vec2>,
    w_a: Val<'a, f32>,
    r: Val<'a, f32>,
) -> (Val<'a, f32>, Val<'a, bool>) {
    let below = |s: &'a FnBuilder<'a>, tau: Val<'a, f32>| s.height(uv_a + duv * tau).ge(w_a - r * tau);
    let step = 1.0 / PRISM_LEVEL_STEPS as f32;
    let (tau, met) = (s.var("level_tau", 0.0f32), s.var("level_met", s.lit_bool(false)));
    s.repeat(PRISM_LEVEL_STEPS, |l| {
        let s: &'a FnBuilder<'a> = l;
        tau.set(tau.get() + step);
        let hit = below(s, tau.get());
        met.set(hit);
        l.break_if(hit);
    });
    let half = s.var("level_half", step * 0.5);
    let at = s.var("level_at", tau.get() - step * 0.5);
    s.repeat(PRISM_LEVEL_BISECTIONS, |l| {
        let s: &'a FnBuilder<'a> = l;
        half.set(half.get() * 0.5);
        let b = below(s, at.get());
        at.set(at.get() + s.select(b, -half.get(), half.get()));
    });
    (s.select(met.get(), at.get(), s.lit(1.0f32)), met.get())
}

/// How many straight pieces the bent chord is searched as ([`piece_search`]): the fewest `n`
/// (at most [`PRISM_PIECES`]) whose pieces depart from the quadratic by at most
/// [`PRISM_PIECE_TOLERANCE`] in the height comparison. The pieces through the quadratic's
/// points at `i/n` depart from it by `|δ|/n²` at most (the bend's weight `4f(1 − f)` has second
/// derivative −8, and a straight piece 1/n long departs from such a curve by `8·(1/n)²/8`), δ
/// the middle's offset `(δuv, δw)`. A texture offset moves the height compared by at most its
/// texels along u plus its texels along v (h is bilinear in heights 0‥1, so it changes by at
/// most one depth per texel along each axis), so `|δ|` is taken as
/// `|δw| + |δu|·W + |δv|·H` (W × H the height map's texels): `n = ⌈√(|δ|/tolerance)⌉`,
/// clamped to 1‥[`PRISM_PIECES`].
fn piece_count<'a>(s: &'a FnBuilder<'a>, bend: &Bend<'a>) -> Val<'a, u32> {
    let texels = (bend.offset.xy() * s.height_map_size()).abs();
    let sag = bend.offset.z().abs() + texels.x() + texels.y();
    (sag * (1.0 / PRISM_PIECE_TOLERANCE)).sqrt().ceil().clamp(1.0, PRISM_PIECES as f32).to_u32()
}

/// [`chord_search`] where the coarse stage reads maps (`Policy::prism_untilted`): the bent
/// chord ([`prism_bend`]) followed as straight pieces through the quadratic's points at `i/n`
/// (n by [`piece_count`], at most [`PRISM_PIECES`]), searched in order until one meets the
/// surface before its end.
/// A map bounds the field along a straight descending ray, so a coarse stage that reads one
/// (a safe cone march) finds the first crossing of each descending piece exactly: the piece
/// is searched as its own untilted chord (the lift the constant that puts the piece's start
/// at the stages' height 1, [`FnBuilder::map_height`]), its march stopped at the piece's end
/// (`PRISM_STOP`) instead of going on to the floor. A piece that does not descend (r ≤ 1e-4:
/// level or rising, near the silhouette) has no such bound and is searched by
/// [`level_piece_search`]. The hit: the piece's point, its fraction of the chord carried to
/// the view ray and to the barycentrics as [`chord_search`] carries the bent chord's.
fn piece_search<'a>(s: &'a FnBuilder<'a>, fns: &StageFns, ch: &Chord<'a>) -> (Hit<'a>, Val<'a, bool>, Val<'a, Vec2>) {
    use crate::stage::sampling::bend_weight;
    let m = s.module();
    let (lift, origin, stop) = (
        s.global_ptr(m.private::<Vec3>(PRISM_LIFT)),
        s.global_ptr(m.private::<Vec2>(PRISM_ORIGIN)),
        s.global_ptr(m.private::<f32>(PRISM_STOP)),
    );
    let bend = &ch.bend;
    // The bent chord's point at the fraction f: its texture point and its layer.
    let point = |f: Val<'a, f32>| {
        let beta = bend_weight(f);
        (ch.uv_in + ch.duv * f + bend.offset.xy() * beta, ch.w_in - ch.r * f + bend.offset.z() * beta)
    };
    let zero2 = s.vec2(0.0, 0.0);
    let piece = s.var("piece", 0.0f32);
    let (found, hit_f, hit_uv, hit_w, hit_beta) = (
        s.var("piece_found", s.lit_bool(false)),
        s.var("piece_f", 0.0f32),
        s.var("piece_uv", zero2),
        s.var("piece_w", 0.0f32),
        s.var("piece_beta", 0.0f32),
    );
    let count = piece_count(s, bend);
    let step = 1.0 / count.to_f32();
    s.repeat_up_to(PRISM_PIECES, count, |l| {
        let s: &'a FnBuilder<'a> = l;
        let fa = piece.get() * step;
        let fb = fa + step;
        let ((uv_a, w_a), (uv_b, w_b)) = (point(fa), point(fb));
        let (duv, r) = (uv_b - uv_a, w_a - w_b);
        // The hit's fraction of the piece, and whether the piece met the surface.
        let (tau, here) = (s.var("piece_tau", 0.0f32), s.var("piece_here", s.lit_bool(false)));
        s.if_else(
            r.le(1e-4),
            |s| {
                let (t, met) = level_piece_search(s, uv_a, duv, w_a, r);
                tau.set(t);
                here.set(met);
            },
            |s| {
                s.store(lift, s.vec3(s.vec2(1.0 - w_a, 0.0), 0.0).handle());
                s.store(origin, uv_a.handle());
                s.store(stop, (r + PRISM_SLACK).handle());
                let ray = Ray { origin: uv_a, dir: s.vec3(duv / r, -1.0), cos_view: ch.search.cos_view };
                let traced: Hit = s.unpack(s.call(fns.trace, &[s.pack(&ray)], true).unwrap());
                let p = ray.at(traced.t);
                let above = (p.z() - s.height(p.xy())).gt(PRISM_ABOVE_SLACK);
                // A march stopped at the piece's end reports it as found: the end lies past r.
                here.set(traced.found & !above & traced.t.le(r));
                tau.set((traced.t / r).clamp(0.0, 1.0));
                s.store(lift, s.vec3(s.vec2(0.0, 0.0), 0.0).handle());
            },
        );
        let (tau, here) = (tau.get(), here.get());
        s.if_(here, |s| {
            found.set(s.lit_bool(true));
            hit_f.set(fa + tau * step);
            hit_uv.set(uv_a + duv * tau);
            hit_w.set(w_a - r * tau);
            hit_beta.set(bend_weight(fa) + (bend_weight(fb) - bend_weight(fa)) * tau);
        });
        l.break_if(here);
        piece.set(piece.get() + 1.0);
    });
    // The lift is back to 0 after every pass (a level piece reads the true heights).
    s.store(stop, s.lit(0.0f32).handle());
    let f = hit_f.get();
    let b = ch.b_in + (ch.b_out - ch.b_in) * f + bend.b * hit_beta.get();
    let found = found.get();
    let hit = Hit { t: ch.t_in + (ch.t_out - ch.t_in) * f, uv: hit_uv.get(), z: hit_w.get(), found };
    (hit, ch.crosses & found, b)
}

/// What a walk reports besides its hit: whether it stopped at [`PRISM_WALK_LIMIT`] still
/// walking, how many prisms it searched, and the shading frame at the hit with the relief's
/// depth along its normal ([`walk_frame`]).
pub(crate) struct WalkOut<'a> {
    pub(crate) drawn: Val<'a, bool>,
    pub(crate) at_limit: Val<'a, bool>,
    pub(crate) passes: Val<'a, u32>,
    pub(crate) frame: Frame<'a>,
    pub(crate) depth: Val<'a, f32>,
}

/// The shading frame at a walk's hit: the hit prism's corners' normals, tangents and scales
/// blended by the hit's barycentrics `b` (b₀, b₁; b₂ = 1 − b₀ − b₁), as a fragment of that
/// prism at the hit would get them interpolated, then [`frame`]; and the relief's depth
/// along its normal there (`depth · |N|`, as [`MeshRay::depth`]). The walk's fragment is the
/// entry prism's, often several prisms from the hit, and its own varyings would shade the
/// hit with the entry's frame, where the full draw shades it with the hit prism's.
fn walk_frame<'a>(
    s: &'a FnBuilder<'a>,
    get: impl Fn(&str) -> Val<'a, Vec4>,
    normals: [Val<'a, Vec3>; 3],
    uv: Val<'a, Vec2>,
    b: Val<'a, Vec2>,
    depth: Val<'a, f32>,
) -> (Frame<'a>, Val<'a, f32>) {
    let w = [b.x(), b.y(), 1.0 - b.x() - b.y()];
    let normal = normals[0] * w[0] + normals[1] * w[1] + normals[2] * w[2];
    let tangent = ["t0", "t1", "t2"].map(&get);
    let tangent = tangent[0] * w[0] + tangent[1] * w[1] + tangent[2] * w[2];
    let (s01, s2) = (get("scale01"), get("scale2"));
    let scale = s01.xy() * w[0] + s01.zw() * w[1] + s2.xy() * w[2];
    let frame = frame(s, s.vec4(normal, 0.0), tangent, s.vec4(s.vec3(uv, scale.x()), scale.y()));
    (frame, depth * normal.length())
}

/// Triangle `cell` of the walk's buffer: its corners relative to `point` (no early-out: a
/// walk enters its prisms only through drawn faces, the tops and unsealed walls, or from a
/// neighbour), its neighbours across walls 0, 1, 2 (−1: none) and its headroom.
fn walk_cell<'a>(
    s: &'a FnBuilder<'a>,
    cells: naga::Handle<naga::GlobalVariable>,
    cell: Val<'a, u32>,
    point: Val<'a, Vec3>,
) -> (PrismCorners<'a>, Val<'a, Vec3>, Val<'a, f32>) {
    let get = cell_member(s, cells, cell);
    let [p0, p1, p2] = ["p0", "p1", "p2"].map(&get);
    let [n0, n1, n2] = ["n0", "n1", "n2"].map(&get);
    let (uv01, uv2) = (get("uv01"), get("uv2"));
    let corners = PrismCorners {
        p: [p0, p1, p2].map(|p| p.xyz() - point),
        n: [n0, n1, n2].map(|n| n.xyz()),
        uv: [uv01.xy(), uv01.zw(), uv2.xy()],
        early: None,
    };
    (corners, s.vec3(s.vec2(p0.w(), p1.w()), p2.w()), uv2.z())
}

/// Where the ray does not cross the fragment's own prism (`missed`, the caller's): the
/// neighbour across the edge of the top that the ray passes outside of, the one opposite the
/// corner whose barycentric at the top's plane is the most negative; moves the walk's `cell`
/// there and says whether there was one (the walk then starts there). The rasterizer gives
/// a pixel whose centre lies on or near an edge two triangles share to one of them, deciding
/// with its own fixed-point snapping (a 256th of a pixel, much coarser than the crossings'
/// slack), so the drawn top can be the neighbour of the one the ray enters through. The
/// unwalked draw did not need this: the entered prism's walls were drawn too. (A pixel near a
/// vertex that several triangles share can still go to one that is no neighbour; its walk
/// finds no crossing and the pixel is lost, counted in the coverage.)
fn start_at_a_neighbour<'a>(
    s: &'a FnBuilder<'a>,
    missed: Val<'a, bool>,
    ch: &Chord<'a>,
    across: Val<'a, Vec3>,
    cell: crate::ir::Var<'a, u32>,
) -> Val<'a, bool> {
    let b = ch.top_b.expect("a walk's chord keeps the top's barycentrics");
    let (b0, b1) = (b.x(), b.y());
    let b2 = 1.0 - b0 - b1;
    // Corner k most negative: the edge from corner k + 1 to k + 2, wall (k + 1) mod 3.
    let next = s.select(b0.le(b1) & b0.le(b2), across.y(), s.select(b1.le(b2), across.z(), across.x()));
    let there = missed & next.ge(0.0);
    cell.set(s.select(there, next.max(0.0).round().to_u32(), cell.get()));
    there
}

/// A reader of triangle `cell`'s [`PrismCell`] in the walk's buffer, member by name.
fn cell_member<'a>(
    s: &'a FnBuilder<'a>,
    cells: naga::Handle<naga::GlobalVariable>,
    cell: Val<'a, u32>,
) -> impl Fn(&str) -> Val<'a, Vec4> {
    let record = s.element_ptr(s.global_ptr(cells), cell.handle());
    move |name| s.load::<Vec4>(s.member_ptr::<PrismCell>(record, name))
}

/// Whether the walk goes on into the prism of `ch`: the ray crosses it and leaves it beyond
/// `before`, the exit of the prism the walk came from (−10³⁰ for the fragment's own). Just
/// past that exit the ray is inside this prism, so with exact arithmetic this prism's last
/// crossing lies beyond it; where rounding says otherwise (a ray through an edge that
/// several prisms share) the walk stops there, and never goes back and forth between two
/// prisms.
fn advances<'a>(ch: &Chord<'a>, before: Val<'a, f32>) -> Val<'a, bool> {
    ch.crosses & ch.t_out.gt(before)
}

/// The flat tile's layer drop per unit of texture-space length for the walk's fragment: the
/// inverse length of its tangent-space ray's step per layer (`mr.ray`, the flat tile's ray
/// from the fragment's own frame, which the walk otherwise leaves unused). [`chord_share`]
/// measures each chord's texture-space length against it.
fn flat_drop_per_texture_unit<'a>(mr: &MeshRay<'a>) -> Val<'a, f32> {
    let along = mr.ray.dir.xy();
    1.0 / along.dot(along).sqrt().max(1e-12)
}

/// A walk's chord's share of the linear searches' layers ([`LAYER_SHARE`]), for a chord
/// searched over the stages' t from 0 to `k` (its exit) that drops `r` (in units of the
/// relief's depth) and whose texture-space length a flat tile would cover in a drop of
/// `flat`: `max(r, flat)/k`, at most 1. The unwalked draw searches every prism's chord with
/// all of the stage's layers, so a ray that crosses three prisms before its hit is sampled
/// three times as densely as the flat tile samples it, and pays three searches; with its
/// share, the walk samples a ray about as densely as the flat tile (one layer per
/// `1/steps` of the depth it descends). The flat drop is the floor for chords that hardly
/// descend (near the silhouette the ray runs level or rises through a prism), which the
/// flat tile would still sample along their length.
fn chord_share<'a>(r: Val<'a, f32>, flat: Val<'a, f32>, k: Val<'a, f32>) -> Val<'a, f32> {
    (r.max(flat) / k).clamp(0.0, 1.0)
}

/// Whether the walk may skip the search of the prism `ch` crosses (its headroom from the
/// walk's buffer): the chord's lower end lies more than [`PRISM_SKIP_MARGIN`] above every
/// height the search could read, so that search could not draw the pixel. The search follows
/// the bent chord ([`prism_bend`]), whose layer is the chord's plus the middle's layer offset
/// δw times a weight in 0‥1 (its pieces' too): the lower end is taken lower by δw where δw is
/// negative. Only where heights are read at level 0 (`lod=zero`), which the headroom bounds;
/// elsewhere never.
fn skip_search<'a>(s: &'a FnBuilder<'a>, ch: &Chord<'a>, headroom: Val<'a, f32>) -> Option<Val<'a, bool>> {
    if s.policy().lod() != Lod::Zero {
        return None;
    }
    let low = ch.w_in.min(ch.w_in - ch.r) + ch.bend.offset.z().min(0.0);
    Some((low - (1.0 - headroom)).gt(PRISM_SKIP_MARGIN))
}

/// `prism`'s trace as a walk (`compose::Options::prism_walk`): the fragment's own prism is
/// searched from its entry to its exit as [`prism_trace`] searches it; where the search
/// meets nothing and the ray leaves through a side wall joined to another triangle's, the
/// search goes on in that triangle's prism (from the walk's buffer, [`PrismCell`]), and so
/// on, until a prism's search meets S (then polished, [`polish_on_s`]), the ray leaves
/// through the top, the floor or a wall joined to nothing (the pixel is another fragment's,
/// or no one's), or [`PRISM_WALK_LIMIT`] prisms were searched. Each prism's chord (its first
/// to its last crossing) and search are those a fragment of that prism runs in the unwalked
/// draw, so the walk meets, in the ray's order, the prisms whose fragments that draw ran one
/// per prism crossed, with one fragment. Two rules the walk adds, each in a named helper: a
/// next prism must take the ray farther ([`advances`]), and a prism whose chord passes above
/// its highest texel is crossed without its search ([`skip_search`], which changes no pixel).
fn prism_walk<'a>(s: &'a FnBuilder<'a>, fns: &StageFns, mr: &MeshRay<'a>) -> (Hit<'a>, WalkOut<'a>) {
    let (start, depth) = mr.walk.as_ref().expect("prism_walk needs its start");
    let (view, cos_view, point, cells) = (mr.view, mr.ray.cos_view, start.point, start.cells);
    let zero2 = s.vec2(0.0, 0.0);
    let cell = s.var("walk_cell", start.first);
    let from = s.var("walk_from", -1e30f32);
    let drawn = s.var("walk_drawn", s.lit_bool(false));
    let going = s.var("walk_going", s.lit_bool(true));
    let passes = s.var("walk_passes", 0u32);
    let (hit_t, hit_uv, hit_z, hit_b) =
        (s.var("walk_t", 0.0f32), s.var("walk_uv", zero2), s.var("walk_z", 0.0f32), s.var("walk_b", zero2));
    let found = s.var("walk_found", s.lit_bool(false));
    let first = s.var("walk_first", s.lit_bool(true));
    let flat_drop = flat_drop_per_texture_unit(mr);
    // Every linear search takes all its layers but a chord's (the shadow's and ao's included):
    // the share is 1 until a chord's search sets it, and back to 1 after.
    if s.policy().layer_share() {
        s.store(s.global_ptr(s.module().private::<f32>(LAYER_SHARE)), s.lit(1.0f32).handle());
    }
    // Where the drawn prism's exit leads (the walk's next prism, whether there is one, and the
    // exit's distance): where the polish does not keep the hit, the walk goes on from there once.
    let (next_cell, next_on, next_from) =
        (s.var("walk_next", 0u32), s.var("walk_next_on", s.lit_bool(false)), s.var("walk_next_from", 0.0f32));
    // The walk, then the polish of its hit; where the polish does not keep it (a uv seam's
    // crack, or a crossing that is the neighbour's part of S), once more from the next prism.
    // The polish runs after each walk, not in its passes: lavapipe runs a block under `if` in
    // every pass whatever its lanes decide, and the polish is four gathers.
    let retried = s.var("walk_retried", s.lit_bool(false));
    s.repeat(2, |outer| {
        let s: &'a FnBuilder<'a> = outer;
        let limit = s.select(retried.get(), s.lit_u32(PRISM_RETRY_LIMIT), s.lit_u32(PRISM_WALK_LIMIT));
        s.repeat_up_to(PRISM_WALK_LIMIT, limit, |l| {
            let s: &'a FnBuilder<'a> = l;
            passes.set(passes.get() + 1u32);
            let (corners, across, headroom) = walk_cell(s, cells, cell.get(), point);
            let ch = prism_chord(s, view, &corners, *depth, cos_view, Some(flat_drop));
            let missed = first.get() & !ch.crosses;
            first.set(s.lit_bool(false));
            l.continue_if(start_at_a_neighbour(s, missed, &ch, across, cell));
            let onward = advances(&ch, from.get());
            going.set(onward);
            l.break_if(!onward);
            let search = |s: &'a FnBuilder<'a>| {
                let (hit, ok, b) = chord_search(s, fns, &ch);
                hit_t.set(hit.t);
                hit_uv.set(hit.uv);
                hit_z.set(hit.z);
                hit_b.set(b);
                found.set(hit.found);
                drawn.set(ok);
            };
            match skip_search(s, &ch, headroom) {
                Some(skip) => s.if_(!skip, search),
                None => search(s),
            }
            let face = ch.exit_face.expect("a walk's chord keeps its exit face");
            let next = s.select(face.lt(0.5), across.x(), s.select(face.lt(1.5), across.y(), across.z()));
            let on = ch.crosses & face.lt(2.5) & next.ge(0.0);
            next_cell.set(next.max(0.0).round().to_u32());
            next_on.set(on);
            next_from.set(ch.t_out);
            l.break_if(drawn.get());
            going.set(on);
            l.break_if(!on);
            cell.set(next_cell.get());
            from.set(ch.t_out);
        });
        let (corners, _, _) = walk_cell(s, cells, cell.get(), point);
        let hit = Hit { t: hit_t.get(), uv: hit_uv.get(), z: hit_z.get(), found: found.get() };
        let (polished, newton_b, kept) = polish_on_s(s, view, &corners, *depth, hit, hit_b.get());
        let searched = drawn.get();
        hit_t.set(polished.t);
        hit_uv.set(polished.uv);
        hit_z.set(polished.z);
        hit_b.set(newton_b);
        drawn.set(searched & kept);
        // A walk that ended at a search did not end at its limit, kept or not.
        going.set(going.get() & !searched);
        outer.break_if(!searched | kept | !next_on.get());
        cell.set(next_cell.get());
        from.set(next_from.get());
        going.set(s.lit_bool(true));
        retried.set(s.lit_bool(true));
    });
    let drawn = drawn.get();
    let at_limit = !drawn & going.get() & !retried.get();
    let (corners, _, _) = walk_cell(s, cells, cell.get(), point);
    let hit = Hit { t: hit_t.get(), uv: hit_uv.get(), z: hit_z.get(), found: found.get() };
    let get = cell_member(s, cells, cell.get());
    let (frame, along) = walk_frame(s, get, corners.n, hit.uv, hit_b.get(), *depth);
    (hit, WalkOut { drawn, at_limit, passes: passes.get(), frame, depth: along })
}

/// The exact early-out behind the hit: whether the prism's entry lies strictly inside the
/// relief solid (`h(uv_in) − w_in > ε`, [`PRISM_EARLY_EPSILON`], h bilinear as S takes it) on a
/// face that allows it (`early_in`: a sealed wall or the floor, [`MeshVertex::prism_b`]). Such
/// a fragment is discarded before the search and the polish, and the picture does not change:
///
/// - A sealed wall is shared with exactly one neighbouring triangle whose two ends carry the
///   same points, normals and uvs, so S (and the prism's map) is continuous across the wall
///   and both prisms give the wall point the same (uv, w), up to the rounding ε covers. Just
///   before the entry the ray was inside the neighbour's prism and below S there too; the eye
///   lies outside the solid, so the ray crossed S before it reached the wall. That crossing is
///   another fragment's hit, nearer along the same pixel's ray, and the depth test would have
///   thrown this fragment's (farther) hit away.
/// - A ray entering through the floor comes from behind the base surface: on a closed mesh
///   seen from outside it has already crossed S on the near side (again a nearer fragment);
///   on an open mesh it looks at the relief from its back, which relief does not draw
///   (docs/meshes-shaders.md).
///
/// Unsealed walls (uv seams, a sphere's poles, open boundaries) run the whole trace.
fn early_out<'a>(s: &'a FnBuilder<'a>, ch: &Chord<'a>, early_in: Val<'a, bool>) -> Val<'a, bool> {
    // The lift is 0 here (set only for the search, and back to 0 after it), so the gather
    // reads h itself.
    let (h, _) = height_and_gradient(s, ch.uv_in);
    early_in & ch.crosses & (h - ch.w_in).gt(PRISM_EARLY_EPSILON)
}

/// Newton steps of [`polish_on_s`]: the search's hit starts within its last bracket of S (a
/// few thousandths of the depth) and Newton doubles the correct digits per step where h is
/// smooth; 3 steps reach f32's resolution from there, and a fourth evaluation checks it.
const POLISH_STEPS: usize = 3;

/// How far from S (object units, in units of the relief's depth) the polished point may lie
/// and count as converged: 1e-4 depths, a tenth of issue 38's RMS t goal, and far above the
/// f32 rounding of points a tenth of a unit from the fragment (~1e-8).
const POLISH_TOLERANCE: f32 = 1e-4;

/// The height map bilinear at `uv` and its gradient in texture units, from the four texels a
/// bilinear sample blends (one gather, the scene's edge mode): S's `h` exactly as the
/// reference takes it, with the derivative Newton needs.
fn height_and_gradient<'a>(s: &'a FnBuilder<'a>, uv: Val<'a, Vec2>) -> (Val<'a, f32>, Val<'a, Vec2>) {
    let size = s.height_map_size();
    let g = uv * size - 0.5;
    let f = g - g.floor();
    // Gather order: (i, j+1), (i+1, j+1), (i+1, j), (i, j).
    let q = s.height_gather(uv);
    let (h01, h11, h10, h00) = (q.x(), q.y(), q.z(), q.w());
    let low = h00 + (h10 - h00) * f.x();
    let high = h01 + (h11 - h01) * f.x();
    let h = low + (high - low) * f.y();
    let du = ((h10 - h00) * (1.0 - f.y()) + (h11 - h01) * f.y()) * size.x();
    let dv = ((h01 - h00) * (1.0 - f.x()) + (h11 - h10) * f.x()) * size.y();
    (h, s.vec2(du, dv))
}

/// Polishes the search's hit onto S along the true view ray. The search ran on the bent
/// chord ([`prism_bend`]; the straight chord where the coarse stage reads maps), which is not
/// the view ray's curve through the prism's map, so its hit is off S by the search's last
/// bracket and the path's departure from the curve, and its distance along the ray is the
/// path's linear estimate. Newton's method on
/// `F(t, b₀, b₁) = t·v − Σ bᵢ (Pᵢ − depth·(1 − h(uv(b)))·Nᵢ)` (the view ray from the
/// fragment's point against S over this triangle; b₂ = 1 − b₀ − b₁, h bilinear with its
/// gradient from the four texels, [`height_and_gradient`]) from the search's (t, b) finds the
/// point of S on the ray near it; the 3 × 3 step by Cramer's rule. The search's hit is kept
/// where Newton leaves the prism (a barycentric below −[`PRISM_FACE_SLACK`]), moves more than
/// one depth along the ray (another crossing of S), or does not converge to
/// [`POLISH_TOLERANCE`]. Returns the hit, Newton's barycentrics (b₀, b₁) and whether Newton's
/// point was kept.
fn polish_on_s<'a>(
    s: &'a FnBuilder<'a>,
    v: Val<'a, Vec3>,
    c: &PrismCorners<'a>,
    depth: Val<'a, f32>,
    hit: Hit<'a>,
    b: Val<'a, Vec2>,
) -> (Hit<'a>, Val<'a, Vec2>, Val<'a, bool>) {
    let (duv0, duv1) = (c.uv[0] - c.uv[2], c.uv[1] - c.uv[2]);
    let uv_at = |b: Val<'a, Vec2>| c.uv[2] + duv0 * b.x() + duv1 * b.y();
    // F at (t, b), with what the step needs: the residual, h, and the columns ∂F/∂b₀, ∂F/∂b₁.
    let residual = |t: Val<'a, f32>, b: Val<'a, Vec2>| {
        let w = [b.x(), b.y(), 1.0 - b.x() - b.y()];
        let (h, grad) = height_and_gradient(s, uv_at(b));
        let p = c.p[0] * w[0] + c.p[1] * w[1] + c.p[2] * w[2];
        let n = c.n[0] * w[0] + c.n[1] * w[1] + c.n[2] * w[2];
        let sink = depth * (1.0 - h);
        let f = v * t - (p - n * sink);
        let column = |k: usize, duv: Val<'a, Vec2>| {
            -((c.p[k] - c.p[2]) - (c.n[k] - c.n[2]) * sink + n * (depth * grad.dot(duv)))
        };
        (f, h, column(0, duv0), column(1, duv1))
    };
    let (mut t, mut bb) = (hit.t, b);
    for _ in 0..POLISH_STEPS {
        let (f, _, c1, c2) = residual(t, bb);
        let cross = c1.cross(c2);
        let det = v.dot(cross);
        let usable = det.abs().gt(1e-30);
        let inv = 1.0 / s.select(usable, det, s.lit(1.0));
        let rhs = -f;
        let dt = rhs.dot(cross) * inv;
        let db = s.vec2(v.dot(rhs.cross(c2)), v.dot(c1.cross(rhs))) * inv;
        t = t + s.select(usable, dt, s.lit(0.0));
        bb = bb + s.select(usable, db, s.vec2(0.0, 0.0));
    }
    let (f, h, _, _) = residual(t, bb);
    let converged = f.length().le(depth * POLISH_TOLERANCE);
    let inside =
        bb.x().ge(-PRISM_FACE_SLACK) & bb.y().ge(-PRISM_FACE_SLACK) & (bb.x() + bb.y()).le(1.0 + PRISM_FACE_SLACK);
    let near = (t - hit.t).abs().le(depth);
    let keep = converged & inside & near;
    let polished = Hit {
        t: s.select(keep, t, hit.t),
        uv: s.select(keep, uv_at(bb), hit.uv),
        z: s.select(keep, h, hit.z),
        found: hit.found,
    };
    // Newton's barycentrics and whether they were kept, for a caller that needs the hit's b.
    (polished, bb, keep)
}

/// What [`mesh_trace`] knows of its hit besides the hit: a walk's report, a full draw's prism
/// hit's barycentrics (b₀, b₁; for its shading frame, [`prism_hit_frame`]), or nothing
/// (`none`, `quadric`: the fragment's own frame shades).
pub(crate) enum Traced<'a> {
    Walk(WalkOut<'a>),
    Prism(Val<'a, Vec2>),
    Flat,
}

impl<'a> Traced<'a> {
    /// The walk's report, where the trace walked.
    fn walk(&self) -> Option<&WalkOut<'a>> {
        match self {
            Traced::Walk(w) => Some(w),
            _ => None,
        }
    }
}

/// The trace both fragment entries share: the search, then the discards of the mode; returns
/// the hit, kept inside the volume as relief's own fragment keeps it (`prism`: its `t` the
/// distance along the view ray, [`prism_trace`]), and what else it knows ([`Traced`]).
///
/// A walk's fragment (`prism_walk`) is discarded where the walk found no hit; with
/// `keep_limit` (the probe) not where it stopped at [`PRISM_WALK_LIMIT`], which the caller
/// marks ([`WalkOut`]).
fn mesh_trace<'a>(
    s: &'a FnBuilder<'a>,
    fns: &StageFns,
    curved: Curved,
    mr: &MeshRay<'a>,
    keep_limit: bool,
) -> (Hit<'a>, Traced<'a>) {
    if curved == Curved::Prism && mr.walk.is_some() {
        let (hit, out) = prism_walk(s, fns, mr);
        let lost = if keep_limit { !out.drawn & !out.at_limit } else { !out.drawn };
        s.if_(lost, |s| s.discard());
        return (hit, Traced::Walk(out));
    }
    if curved == Curved::Prism {
        let (hit, drawn, b) = prism_trace(s, fns, mr);
        s.if_(!drawn, |s| s.discard());
        return (hit, Traced::Prism(b));
    }
    let traced = search(s, fns, mr);
    if curved != Curved::None {
        // The prism's corner uvs (varyings 5, 6), which `quadric` does not read: their
        // expressions are still made, so that its module keeps its text to the byte (naga
        // numbers the temporaries by expression).
        let _ = [s.arg::<Vec4>(5).xy(), s.arg::<Vec4>(5).zw(), s.arg::<Vec4>(6).xy()];
        s.if_(!covered(s, curved, mr, &traced), |s| s.discard());
    }
    (Hit::at_found(&mr.ray, traced.t.clamp(0.0, mr.ray.t_max()), traced.found), Traced::Flat)
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
/// ray descends `cos_view` per unit length; under `prism` the hit's `t` itself.
pub(crate) fn depth_offset<'a>(mr: &MeshRay<'a>, hit: &Hit<'a>) -> Val<'a, f32> {
    if mr.chord.is_some() || mr.walk.is_some() {
        return hit.t;
    }
    (hit.t - mr.t_entry) * mr.depth / mr.ray.cos_view
}

fn fragment_args(
    m: &ModuleCtx,
    curved: Curved,
    walk: bool,
) -> Vec<(&'static str, naga::Handle<naga::Type>, Option<Binding>)> {
    let v4 = m.ty(Vec4::inner());
    VARYINGS[..vertex_members_for(curved, walk)]
        .iter()
        .enumerate()
        .map(|(i, n)| (*n, v4, Some(varying_binding(i as u32))))
        .collect()
}

/// `fs_mesh`: trace, shade (albedo, the normal map's normal in the fragment's frame, the
/// shadow stage's visibility, ambient × ao) and write colour and depth.
fn fragment_entry(m: &ModuleCtx, policy: &dyn Policy, fns: &StageFns, curved: Curved, walk: Walk) -> naga::EntryPoint {
    let s = m.function("fs_mesh", &fragment_args(m, curved, walk.is_some()), policy);
    let (inputs, point) = varying_inputs(&s, curved, walk);
    let mr = mesh_ray(&s, curved, inputs);
    let (hit, walked) = mesh_trace(&s, fns, curved, &mr, false);
    let depth_out = hit_depth(&s, &mr, point, &hit);
    // The shading frame: the fragment's, or the hit prism's at the hit ([`walk_frame`],
    // [`prism_hit_frame`]).
    let (frame, depth) = match walked {
        Traced::Walk(w) => (w.frame, w.depth),
        Traced::Prism(b) => prism_hit_frame(&s, &mr, b),
        Traced::Flat => (mr.frame, mr.depth),
    };
    if curved == Curved::Quadric {
        // The shadow and ao stages search from the hit: the quadric is centred there.
        recentre_quadric(&s, hit.uv);
    }
    let hv = s.pack(&hit);
    let light = s.param::<Vec4>(Param::Light);
    let (l_uv, l_n) = frame.to_texture(light.xyz());
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
    let normal = frame.to_object(s.normal(hit.uv));
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
fn depth_entry(m: &ModuleCtx, policy: &dyn Policy, fns: &StageFns, curved: Curved, walk: Walk) -> naga::EntryPoint {
    let s = m.function(DEPTH_ENTRY, &fragment_args(m, curved, walk.is_some()), policy);
    let (inputs, point) = varying_inputs(&s, curved, walk);
    let mr = mesh_ray(&s, curved, inputs);
    let (hit, _) = mesh_trace(&s, fns, curved, &mr, false);
    let depth = hit_depth(&s, &mr, point, &hit);
    let f = s.finish(Some((m.ty(f32::inner()), Some(Binding::BuiltIn(BuiltIn::FragDepth)), depth.handle())));
    entry_point(DEPTH_ENTRY, ShaderStage::Fragment, f, [0; 3])
}

/// `fs_mesh_probe`: the same trace and discards as `fs_mesh`, writing `(u, v, distance, 1)`
/// and the hit's depth. The distance is the fragment's own distance from the eye plus
/// [`depth_offset`], the hit's place along the same unit view ray that `fs_mesh`'s depth
/// is taken at, so the probe's distance and the frame's depth are one point.
///
/// Walking (`prism_walk`), the record's w is the number of prisms the walk searched (≥ 1, so
/// still > 0.5 where the pixel is drawn), and a walk that stopped at [`PRISM_WALK_LIMIT`]
/// writes `(0, 0, 0, −1)` at the depth [`PRISM_WALK_LIMIT_DEPTH`]: not drawn, as the picture
/// discards it, but counted where no other fragment of the pixel has a hit.
fn probe_entry(m: &ModuleCtx, policy: &dyn Policy, fns: &StageFns, curved: Curved, walk: Walk) -> naga::EntryPoint {
    let s = m.function(PROBE_ENTRY, &fragment_args(m, curved, walk.is_some()), policy);
    let (inputs, point) = varying_inputs(&s, curved, walk);
    let mr = mesh_ray(&s, curved, inputs);
    let (hit, traced) = mesh_trace(&s, fns, curved, &mr, true);
    let out = traced.walk();
    let out_ty = super::fragment_output_with_depth(m);
    if let Some(out) = &out {
        s.if_(out.at_limit, |s| {
            let mark = s.vec4(s.vec3(s.vec2(0.0, 0.0), 0.0), -1.0);
            let v = s.make_struct(out_ty, &[mark.handle(), s.lit(PRISM_WALK_LIMIT_DEPTH).handle()]);
            s.ret_handle(Some(v));
        });
    }
    let depth_out = hit_depth(&s, &mr, point, &hit);
    let camera = s.param::<Vec4>(Param::Camera);
    let distance = (point - camera.xyz()).length() + depth_offset(&mr, &hit);
    let w = match &out {
        Some(out) => out.passes.to_f32(),
        None => s.lit(1.0),
    };
    let record = s.vec4(s.vec3(hit.uv, distance), w);
    let v = s.make_struct(out_ty, &[record.handle(), depth_out.handle()]);
    let f = s.finish(Some((out_ty, None, v)));
    entry_point(PROBE_ENTRY, ShaderStage::Fragment, f, [0; 3])
}

/// The prism walk's buffer, where a module walks (`compose::Options::prism_walk` under
/// `curved=prism`).
type Walk = Option<naga::Handle<naga::GlobalVariable>>;

/// Declares the prism walk's buffer, `array<PrismCell>` at [`crate::abi::binding::PRISM_CELLS`].
fn walk_buffer(m: &ModuleCtx) -> naga::Handle<naga::GlobalVariable> {
    let item = m.record_ty::<PrismCell>();
    let access = naga::StorageAccess::LOAD;
    let space = naga::AddressSpace::Storage { access };
    m.bound(PRISM_CELLS, space, crate::abi::binding::PRISM_CELLS, crate::ir::Resource::PrismCells, |m| {
        let stride = std::mem::size_of::<PrismCell>() as u32;
        m.ty(TypeInner::Array { base: item, size: naga::ArraySize::Dynamic, stride })
    })
}

/// Builds the mesh module of `p` (`p.curved` is `Some`), not yet validated, with its binding
/// table; `probe` adds the measurement entry `fs_mesh_probe`, `walk` makes `curved=prism`'s
/// fragments walk from prism to prism ([`prism_walk`]).
pub(crate) fn compose_mesh(
    p: &Pipeline,
    curved: Curved,
    probe: bool,
    walk: bool,
    share: bool,
) -> Result<(Module, Bindings), CompileError> {
    check_mesh_options(p, curved)?;
    let m = ModuleCtx::new();
    let policy = MeshPolicy {
        plain: Plain { lod: p.lod, gather_patches: false },
        quadric: curved == Curved::Quadric,
        lift: curved == Curved::Prism,
        untilted: curved == Curved::Prism && coarse_reads_maps(p),
        share: curved == Curved::Prism && walk && share,
    };
    let fns = write_stage_fns(&m, p, &policy, false)?;
    let walk = (walk && curved == Curved::Prism).then(|| walk_buffer(&m));
    let vs = vertex_entry(&m, &policy, curved, walk.is_some());
    let fs = fragment_entry(&m, &policy, &fns, curved, walk);
    let ds = depth_entry(&m, &policy, &fns, curved, walk);
    // The probe shares the stage functions; the other entries are the same without it.
    let ps = probe.then(|| probe_entry(&m, &policy, &fns, curved, walk));
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

    /// Only `prism` reads the triangle's corners (members 7‥12, passed flat): the other modes'
    /// vertex entries declare members 0‥6 as before, and their modules carry no corner.
    #[test]
    fn only_prism_reads_the_triangles_corners() {
        for mode in Curved::ALL {
            let text = wgsl(&format!("linear(32)+binary(5)+curved={mode}")).unwrap();
            let prism = mode == Curved::Prism;
            let vs = text.split("fn vs_mesh(").nth(1).and_then(|f| f.split(") ->").next()).unwrap();
            assert_eq!(vs.matches("@location(").count(), vertex_members(mode), "{mode}");
            assert_eq!(vertex_members(mode), if prism { 13 } else { 7 }, "{mode}");
            assert_eq!(text.contains("prism_n2") && text.contains("@interpolate(flat)"), prism, "{mode}");
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
