//! The shader ABI: what a generated module and the runtime that drives it agree on — binding
//! numbers, the `Params` uniform block, the probe's ray and hit records, the probe's workgroup
//! size, and the constants both sides build maps with.
//!
//! A leaf: every layer of relief-dsl and relief-runtime may read it, and it reads nothing of
//! theirs. Each record is one `#[repr(C)]` Rust struct; the shader's struct type is built from
//! the same member list ([`Params::MEMBERS`], [`ProbeRay::MEMBERS`], [`ProbeHit::MEMBERS`]),
//! and a test checks that naga lays it out at the Rust struct's size.

use bytemuck::{Pod, Zeroable};

/// Binding numbers (all in group 0). Stable: the runtime binds by these numbers.
pub mod binding {
    /// `Params` uniform block: see [`super::Params`].
    pub const PARAMS: u32 = 0;
    /// Height map, `texture_2d<f32>`, height in the red channel.
    pub const HEIGHT: u32 = 1;
    /// Sampler with linear filtering (the scene's edge mode as address mode).
    pub const LINEAR_SAMPLER: u32 = 2;
    /// Sampler with nearest filtering.
    pub const NEAREST_SAMPLER: u32 = 3;
    /// Normal map, `texture_2d<f32>`, `n * 0.5 + 0.5` in rgb.
    pub const NORMAL: u32 = 4;
    /// Albedo, `texture_2d<f32>`, rgb.
    pub const ALBEDO: u32 = 5;
    /// Cone ratio map (`texture_2d<f32>`, r).
    pub const CONE: u32 = 6;
    /// Quad cone ratio map (rgba).
    pub const QUAD_CONE: u32 = 7;
    /// Relaxed cone ratio map (r).
    pub const RELAXED_CONE: u32 = 8;
    /// Cone normal map, `n_z` (r).
    pub const CONE_NORMAL: u32 = 9;
    /// Relaxed cone normal map, `n_z` (r).
    pub const RELAXED_CONE_NORMAL: u32 = 10;
    /// Stacked cones, `n_z` per cone (rgba, K ≤ 4 channels used).
    pub const MULTI_CONE: u32 = 11;
    /// Piecewise cone slopes as `n_z` (rgba, K ≤ 4 channels used).
    pub const PIECEWISE_CONE: u32 = 12;
    /// Maximum mipmap of the height map's bilinear cells (r, full mip chain).
    pub const MAX_MIP: u32 = 13;
    /// Distance field, `texture_3d<f32>` (r), z slices from the bottom (0) to the top (1).
    pub const DISTANCE_FIELD: u32 = 14;
    /// Cell cone ratio and apex (rg), one texel per bilinear cell, read with `textureLoad`
    /// (the cell maps carry their apex after the cones where it fits:
    /// [`super::cell_apex_on_device`]).
    pub const CELL_CONE: u32 = 15;
    /// Cell quad cone ratios (rgba; the apex does not fit).
    pub const CELL_QUAD_CONE: u32 = 16;
    /// Cell relaxed cone ratio and apex (rg).
    pub const CELL_RELAXED_CONE: u32 = 17;
    /// Cell cone normal, `n_z`, and apex (rg).
    pub const CELL_CONE_NORMAL: u32 = 18;
    /// Cell stacked cones, `n_z` per cone, then the apex where K ≤ 3 (rgba).
    pub const CELL_MULTI_CONE: u32 = 19;
    /// Cell piecewise cone slopes as `n_z`, then the apex where K ≤ 3 (rgba).
    pub const CELL_PIECEWISE_CONE: u32 = 20;
    /// Cell patch coefficients (rgba: `h00`, `h10 − h00`, `h01 − h00`, `(h11 − h10) − (h01 −
    /// h00)`), one texel per bilinear cell, on the cell maps' grid.
    pub const CELL_PATCH: u32 = 21;
    /// A 2D map read with nearest filtering is bound a second time at its binding plus this
    /// offset (`cone_map_nearest` at 38 for `cone_map` at 6): GLSL combines a texture with one
    /// sampler.
    pub const NEAREST_OFFSET: u32 = 32;
    /// A room module's window opacity map (`texture_2d<f32>`, r). A room binds its walls'
    /// images from 6 on, so it reuses the plain modules' numbers 4 and 5.
    pub const ROOM_WINDOW: u32 = 4;
    /// A room module's `RoomParams` uniform block.
    pub const ROOM_PARAMS: u32 = 5;
    /// Probe input, `array<ProbeRay>` (storage, read).
    pub const RAYS: u32 = 64;
    /// Probe output, `array<ProbeHit>` (storage, read_write).
    pub const HITS: u32 = 65;
    /// A mesh module's prism walk, `array<PrismCell>` (storage, read): one record per
    /// triangle (`compose::Options::prism_walk`).
    pub const PRISM_CELLS: u32 = 66;
}

/// Workgroup size of the probe entry.
pub const PROBE_WORKGROUP: u32 = 64;

/// The z resolution of the distance field `sphere` reads, as the runtime builds it (the
/// field is a lower bound of the distance to the surface at any resolution; this one is the
/// default of `relief maps` and of every pipeline).
pub const DISTANCE_FIELD_Z: u32 = 64;

/// The scalar type of a record member, for building the shader's struct type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Member {
    /// `f32`.
    F32,
    /// `u32`.
    U32,
    /// `vec2<f32>`.
    Vec2,
    /// `vec3<f32>`.
    Vec3,
    /// `vec4<f32>`.
    Vec4,
    /// `mat4x4<f32>`.
    Mat4,
}

/// The shader type of a record field, from its Rust type (what the records' `MEMBERS` list).
pub trait AbiType {
    /// The member type.
    const MEMBER: Member;
}
impl AbiType for f32 {
    const MEMBER: Member = Member::F32;
}
impl AbiType for u32 {
    const MEMBER: Member = Member::U32;
}
impl AbiType for [f32; 2] {
    const MEMBER: Member = Member::Vec2;
}
impl AbiType for [f32; 3] {
    const MEMBER: Member = Member::Vec3;
}
impl AbiType for [f32; 4] {
    const MEMBER: Member = Member::Vec4;
}
impl AbiType for [f32; 16] {
    const MEMBER: Member = Member::Mat4;
}

/// A record the shader and the host share: the shader's struct is named [`AbiRecord::NAME`]
/// (the Rust struct's name) and has [`AbiRecord::MEMBERS`].
pub trait AbiRecord {
    /// The struct's name, in Rust and in the shader.
    const NAME: &'static str;
    /// The members as the shader declares them, in order: the one statement of the order.
    const MEMBERS: &'static [(&'static str, Member)];

    /// The position of the member `name` in [`AbiRecord::MEMBERS`], for code that reads or
    /// writes a member by its name.
    ///
    /// # Panics
    ///
    /// When the record declares no member `name` (a composer bug: the message names the record
    /// and its members).
    fn member_index(name: &str) -> u32 {
        let Some(i) = Self::MEMBERS.iter().position(|(n, _)| *n == name) else {
            let names: Vec<&str> = Self::MEMBERS.iter().map(|(n, _)| *n).collect();
            panic!("the ABI record {} has no member `{name}` (its members: {names:?})", Self::NAME);
        };
        i as u32
    }
}

/// Declares a `#[repr(C)]` record and, from the same field list, its `MEMBERS` as the shader
/// declares them (each field's [`AbiType`]), so that the two cannot drift apart.
macro_rules! abi_record {
    ($(#[$meta:meta])* pub struct $name:ident { $($(#[$fmeta:meta])* pub $field:ident: $ty:ty,)* }) => {
        $(#[$meta])*
        #[repr(C)]
        pub struct $name {
            $($(#[$fmeta])* pub $field: $ty,)*
        }
        impl $name {
            /// The members as the shader declares them, in order.
            pub const MEMBERS: &'static [(&'static str, $crate::abi::Member)] =
                &[$((stringify!($field), <$ty as $crate::abi::AbiType>::MEMBER)),*];
        }
        impl $crate::abi::AbiRecord for $name {
            const NAME: &'static str = stringify!($name);
            const MEMBERS: &'static [(&'static str, $crate::abi::Member)] = $name::MEMBERS;
        }
    };
}
pub(crate) use abi_record;

abi_record! {
/// The `Params` uniform block (144 bytes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Params {
    /// Tangent space → clip space, column-major.
    pub view_proj: [f32; 16],
    /// xyz: the camera's position in tangent space; w: the depth scale (the relief's depth
    /// in texture units).
    pub camera: [f32; 4],
    /// xyz: unit vector toward the light; w: the ambient share.
    pub light: [f32; 4],
    /// x: the quad's size in texture units (the tiling); y: 1 when the scene's edge mode is
    /// clamp, 0 for repeat; z, w: 0.
    pub quad: [f32; 4],
    /// xyz: the camera's unit right vector (world = tangent space); w: one pixel's size on
    /// the image plane at unit distance, `2·tan(fov_y / 2) / frame height` (square pixels).
    /// With [`Params::pixel_up`], what `lod=auto` needs to project a pixel onto the plane
    /// (see `relief_dsl::compose`, "The footprint level").
    pub pixel_right: [f32; 4],
    /// xyz: the camera's unit up vector; w: 0.
    pub pixel_up: [f32; 4],
}
}

/// A member of [`Params`], for the stages that read the block: the shader addresses it by
/// [`Param::name`], so the order stays [`Params`]'s alone.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Param {
    /// [`Params::view_proj`].
    ViewProj,
    /// [`Params::camera`].
    Camera,
    /// [`Params::light`].
    Light,
    /// [`Params::quad`].
    Quad,
    /// [`Params::pixel_right`].
    PixelRight,
    /// [`Params::pixel_up`].
    PixelUp,
}

impl Param {
    /// The member's name in [`Params::MEMBERS`].
    pub fn name(self) -> &'static str {
        match self {
            Param::ViewProj => "view_proj",
            Param::Camera => "camera",
            Param::Light => "light",
            Param::Quad => "quad",
            Param::PixelRight => "pixel_right",
            Param::PixelUp => "pixel_up",
        }
    }
}

/// One probe ray, 32 bytes, as the probe's storage buffer holds it.
///
/// `pixel_size` is the size δ of the ray's pixel on the image plane at unit distance,
/// `2·tan(fov_y / 2) / frame height`, for rays that are a frame's pixels (what `lod=auto`
/// needs to find the pixel's footprint, as the render entry finds it from
/// [`Params::pixel_right`]); 0 for rays that are not (they sample level 0 under `lod=auto`).
///
/// The ray's point at t is `(origin.x + t·dir.x, origin.y + t·dir.y, 1 + t·dir.z)`: it enters
/// the relief volume at height 1, and `dir` is normalized so that t = 1 reaches height 0
/// (`dir.z = -1`). `x`, `y` are the pixel (column, row; row 0 at the top).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct ProbeRay {
    /// Where the ray enters the volume, in texture coordinates.
    pub origin: [f32; 2],
    /// The direction, `dir[2] = -1`.
    pub dir: [f32; 3],
    /// The pixel's column.
    pub x: u32,
    /// The pixel's row (0 at the top).
    pub y: u32,
    /// The pixel's size on the image plane at unit distance (0: not a frame's pixel).
    pub pixel_size: f32,
}

impl ProbeRay {
    /// The members as the shader declares them (`dir` split into `dir_xy` and `dir_z`, so
    /// that no member needs 16-byte alignment).
    pub const MEMBERS: &'static [(&'static str, Member)] = &[
        ("origin", Member::Vec2),
        ("dir_xy", Member::Vec2),
        ("dir_z", Member::F32),
        ("pixel_x", Member::U32),
        ("pixel_y", Member::U32),
        ("pixel_size", Member::F32),
    ];

    /// The ray's point (u, v, height) at parameter t.
    pub fn at(&self, t: f32) -> [f32; 3] {
        [self.origin[0] + t * self.dir[0], self.origin[1] + t * self.dir[1], 1.0 + t * self.dir[2]]
    }
}

impl AbiRecord for ProbeRay {
    const NAME: &'static str = "ProbeRay";
    const MEMBERS: &'static [(&'static str, Member)] = ProbeRay::MEMBERS;
}

abi_record! {
/// One probe hit, 36 bytes: the search's raw result, never clamped into the volume.
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct ProbeHit {
    /// The ray parameter of the hit.
    pub t: f32,
    /// The hit's u in texture coordinates.
    pub u: f32,
    /// The hit's v in texture coordinates.
    pub v: f32,
    /// The hit's height.
    pub z: f32,
    /// Loop passes of the coarse stage.
    pub coarse_steps: u32,
    /// Loop passes of the refine stage.
    pub refine_steps: u32,
    /// Texture samples over both stages.
    pub fetches: u32,
    /// 1 when the coarse search found the surface; 0 when it ran out of steps (the hit is
    /// then the last point it knew to be above the surface, and nothing refined it).
    pub converged: u32,
    /// 1 when the pipeline clips the silhouette (`silhouette=clip`) and the hit's (u, v)
    /// lies outside the quad's square `[0, tiling]²`: the render discards that pixel and
    /// the ray counts as "no hit". The raw hit above is still reported. 0 otherwise.
    pub clipped: u32,
}
}

impl ProbeHit {
    /// Loop passes over both stages.
    pub fn iterations(&self) -> u32 {
        self.coarse_steps + self.refine_steps
    }

    /// Whether every coordinate of the hit is finite.
    pub fn is_finite(&self) -> bool {
        [self.t, self.u, self.v, self.z].iter().all(|x| x.is_finite())
    }

    /// Whether the raw hit lies outside the volume of `ray`: the ray's height at the hit's t,
    /// `1 + t·dir.z`, above the polygon (t < 0) or below the floor, by more than
    /// [`OUTSIDE_TOLERANCE`]. A NaN t is not outside (it is counted as NaN).
    pub fn outside(&self, ray: &ProbeRay) -> bool {
        let z = 1.0 + self.t as f64 * ray.dir[2] as f64;
        !(-OUTSIDE_TOLERANCE..=1.0 + OUTSIDE_TOLERANCE).contains(&z)
    }
}

/// How far (in height) a hit may lie outside the volume and still count as inside: the
/// rounding of a t summed in f32 over up to 128 steps of at most the volume's depth is below
/// 128 · 2⁻²⁴ ≈ 7.6e-6, so 1e-5 separates rounding from a search that left the volume.
pub const OUTSIDE_TOLERANCE: f64 = 1e-5;

/// The channels of one map texel on the device (an `Rgba32Float` texel).
pub const TEXEL_CHANNELS: usize = 4;

/// Whether a cell map of `channels` channels (its cones, then the apex `A_C`, the highest
/// corner of the cell) is uploaded with its apex: where the apex fits in the texel beside the
/// cones. A safe cone step then reads the apex with the cone in one load and gathers the
/// cell's corners only where it meets the cell's patch; a map without it (the quad cone, K = 4
/// stacked or piecewise cones) has its apex taken from the gathered corners.
pub fn cell_apex_on_device(channels: usize) -> bool {
    channels <= TEXEL_CHANNELS
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each member is found at its place in the record's declaration, and every [`Param`] names
    /// a distinct member of [`Params`].
    #[test]
    fn members_are_found_by_name() {
        for (i, (name, _)) in ProbeHit::MEMBERS.iter().enumerate() {
            assert_eq!(ProbeHit::member_index(name), i as u32);
        }
        assert_eq!(ProbeRay::member_index("pixel_size"), 5);
        let params = [Param::ViewProj, Param::Camera, Param::Light, Param::Quad, Param::PixelRight, Param::PixelUp];
        let mut found: Vec<u32> = params.iter().map(|p| Params::member_index(p.name())).collect();
        found.sort();
        found.dedup();
        assert_eq!(found.len(), Params::MEMBERS.len());
    }

    /// A name the record lacks is a panic that names the record.
    #[test]
    #[should_panic(expected = "the ABI record ProbeRay has no member `dir`")]
    fn a_missing_member_is_named() {
        ProbeRay::member_index("dir");
    }
}
