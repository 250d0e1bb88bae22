//! Rooms behind a window: interior mapping with relief on every wall (Amaro &
//! Gustafsson 2022, §2.2–2.4), and the same room as real geometry.
//!
//! A [`Room`] is a box `[0, W] × [0, H] × [−D, 0]` in world units behind a window quad at
//! `z = 0`, five walls ([`WALL_NAMES`]: back, left, right, floor, ceiling), each with a
//! height map, an optional albedo and normal map and a depth scale (world units from the
//! wall's plane to height 0: the relief goes *into* the wall, Amaro & Gustafsson 2022, §4), an optional
//! window opacity map, a camera in front of the window and a point or directional light
//! inside the room. Every wall's frame (where u, v and the height point) is
//! [`relief_dsl::compose::interior::wall_frame`].
//!
//! - [`builtin`]: the procedural room (a fresh clone needs nothing);
//! - [`mod@file`]: room files (TOML), errors in the scene files' one-line style;
//! - [`gpu`]: the room module on the device: timed interior frames and the room probe;
//! - [`mesh`]: the real-geometry baseline (each wall's height map displaced into a grid);
//! - [`accuracy`]: per-wall accuracy of the probe's hits against the exact reference;
//! - [`measure`]: one room measured (both renders timed, the accuracy);
//! - [`sweep`]: the room grid (pipelines × rooms) of `relief sweep --grid rooms`.
//!
//! Amaro & Gustafsson 2022 (§4) need wall height maps at height 1 on their borders, so that the walls
//! meet at the room's edges: the procedural maps are made so, and [`border_warnings`] says
//! which given map is not.

pub mod accuracy;
pub mod builtin;
pub mod file;
pub mod gpu;
pub mod measure;
pub mod mesh;
pub mod sweep;
pub use crate::gpu::Frames;

/// The clear colour of the room's two renders (outside the window), alpha 0: no wall there.
pub(crate) const CLEAR: wgpu::Color = wgpu::Color { r: 0.02, g: 0.02, b: 0.03, a: 0.0 };

use glam::{DVec3, DVec4, Mat4, Vec3};

use crate::heightmap::{EdgeMode, HeightMap};
use crate::scene::{NormalMap, Rgba8Image, Scene};

pub use relief_dsl::compose::interior::{wall_frame, RoomHit, RoomRay, WallFrame, WALLS, WALL_NAMES};

/// One wall: its maps and its depth.
#[derive(Clone, Debug, PartialEq)]
pub struct Wall {
    /// Heights in [0, 1]; 1 is the wall's plane.
    pub height: HeightMap,
    /// Base colour; `None`: neutral grey.
    pub albedo: Option<Rgba8Image>,
    /// Tangent-space normal map; `None`: derived from the height map.
    pub normal: Option<NormalMap>,
    /// World units from the wall's plane to height 0.
    pub depth_scale: f32,
}

/// The room's light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RoomLight {
    /// A point light at this world position (inside the room).
    Point(Vec3),
    /// A directional light: the unit vector toward it.
    Directional(Vec3),
}

/// The camera in front of the window, looking at `target`, up = +y.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoomCamera {
    /// The eye, world units (`z > 0`: in front of the window).
    pub position: Vec3,
    /// The point looked at.
    pub target: Vec3,
    /// Vertical field of view, degrees.
    pub fov_deg: f32,
}

/// Near and far planes of the room camera.
pub const NEAR_FAR: (f32, f32) = (0.01, 100.0);

impl RoomCamera {
    /// Unit (forward, right, up) of the view.
    pub fn basis(&self) -> (Vec3, Vec3, Vec3) {
        let f = (self.target - self.position).normalize();
        let r = f.cross(Vec3::Y).normalize();
        (f, r, r.cross(f))
    }
    /// Projection × view, wgpu clip conventions; `aspect` = width / height.
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        Mat4::perspective_rh(self.fov_deg.to_radians(), aspect, NEAR_FAR.0, NEAR_FAR.1)
            * Mat4::look_at_rh(self.position, self.target, Vec3::Y)
    }
    /// The world direction (unit) through pixel `(x, y)` of a `size²` frame (row 0 at the
    /// top), through the pixel's centre.
    pub(crate) fn pixel_dir(&self, x: u32, y: u32, size: u32) -> Vec3 {
        let ndc_x = (x as f32 + 0.5) / size as f32 * 2.0 - 1.0;
        let ndc_y = 1.0 - (y as f32 + 0.5) / size as f32 * 2.0;
        let (f, r, u) = self.basis();
        let ty = (0.5 * self.fov_deg.to_radians()).tan();
        (f + ndc_x * ty * r + ndc_y * ty * u).normalize()
    }
}

/// A room behind a window.
#[derive(Clone, Debug, PartialEq)]
pub struct Room {
    /// `room:NAME` for the built-in room, the file stem for loaded ones.
    pub name: String,
    /// Width W, height H, depth D behind the window, world units.
    pub size: [f32; 3],
    /// The walls in [`WALL_NAMES`] order.
    pub walls: Vec<Wall>,
    /// The window's opacity (1 = opaque glass, 0 = clear), `None`: no glass.
    pub window: Option<HeightMap>,
    /// The eye in front of the window that both renders and the probe use.
    pub camera: RoomCamera,
    /// The room's one light: a point inside the room, or a direction.
    pub light: RoomLight,
    /// The ambient share of the shading.
    pub ambient: f32,
    /// Unit vector toward the sun outside the window (`z > 0`), for light scattering
    /// (Amaro & Gustafsson 2022, §2.3; off unless asked for).
    pub sun: Vec3,
    /// The sun's scattering intensity.
    pub sun_intensity: f32,
}

/// One ray of a frame that passes through the window: its pixel and the probe ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelRay {
    /// Column.
    pub x: u32,
    /// Row (0 at the top).
    pub y: u32,
    /// From the camera, through the pixel's centre.
    pub ray: RoomRay,
}

/// A ray in one wall's normalized tangent space (f64): enters at `(origin, 1)`, `dir.z = −1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallRay {
    /// The wall.
    pub wall: usize,
    /// Where it enters the wall's relief (u, v).
    pub origin: [f64; 2],
    /// The direction, scaled so that t = 1 reaches height 0.
    pub dir: [f64; 3],
    /// The world ray's parameter at the wall's plane (world point = `o + t_plane·d`).
    pub t_plane: f64,
}

/// A wall's frame ([`WallFrame`], which the shader ABI states in arrays) as glam vectors.
struct Frame {
    origin: DVec3,
    u_edge: DVec3,
    v_edge: DVec3,
    normal: DVec3,
}

impl Frame {
    fn of(f: WallFrame) -> Frame {
        let v = DVec3::from_array;
        Frame { origin: v(f.origin), u_edge: v(f.u_edge), v_edge: v(f.v_edge), normal: v(f.normal) }
    }
}

impl Room {
    /// The room's size in f64.
    pub fn size64(&self) -> [f64; 3] {
        self.size.map(|x| x as f64)
    }

    /// The rays of a `size²` frame that pass through the window (the only pixels the
    /// interior entry draws), in row order.
    pub fn rays(&self, size: u32) -> Vec<PixelRay> {
        let c = self.camera.position;
        let mut out = Vec::new();
        for y in 0..size {
            for x in 0..size {
                let d = self.camera.pixel_dir(x, y, size);
                if d.z >= 0.0 {
                    continue;
                }
                let t = -c.z / d.z;
                let p = c + d * t;
                if p.x < 0.0 || p.x > self.size[0] || p.y < 0.0 || p.y > self.size[1] {
                    continue;
                }
                out.push(PixelRay { x, y, ray: RoomRay { origin: [c.x, c.y, c.z, 0.0], dir: [d.x, d.y, d.z, 0.0] } });
            }
        }
        out
    }

    /// The wall a world ray meets and the ray in that wall's tangent space: Amaro & Gustafsson 2022, eq. 1–4
    /// on the host (what `fs_room` and `probe_room` compute), in f64.
    pub fn wall_ray(&self, ray: &RoomRay) -> WallRay {
        let o = DVec4::from_array(ray.origin.map(f64::from)).truncate();
        let w = DVec4::from_array(ray.dir.map(f64::from)).truncate();
        let s = DVec3::from_array(self.size64());
        let tx = (if w.x < 0.0 { -o.x } else { s.x - o.x }) / w.x;
        let ty = (if w.y < 0.0 { -o.y } else { s.y - o.y }) / w.y;
        let tz = (-s.z - o.z) / w.z;
        let (mut wall, mut t) = (0, tz);
        if tx < t {
            (wall, t) = (if w.x < 0.0 { 1 } else { 2 }, tx);
        }
        if ty < t {
            (wall, t) = (if w.y < 0.0 { 3 } else { 4 }, ty);
        }
        let f = Frame::of(wall_frame(wall, s.to_array()));
        let rel = o + t * w - f.origin;
        let (uu, vv) = (f.u_edge.length_squared(), f.v_edge.length_squared());
        let view = w.normalize();
        let k = self.walls[wall].depth_scale as f64 / (-view.dot(f.normal)).max(1e-6);
        WallRay {
            wall,
            origin: [rel.dot(f.u_edge) / uu, rel.dot(f.v_edge) / vv],
            dir: [view.dot(f.u_edge) / uu * k, view.dot(f.v_edge) / vv * k, -1.0],
            t_plane: t,
        }
    }

    /// The world point of wall `k`'s relief at `(u, v, z)`.
    pub fn wall_point(&self, k: usize, u: f64, v: f64, z: f64) -> DVec3 {
        let f = Frame::of(wall_frame(k, self.size64()));
        f.origin + u * f.u_edge + v * f.v_edge + self.walls[k].depth_scale as f64 * (z - 1.0) * f.normal
    }

    /// Wall `k` as a scene (its maps, edge mode clamp), for uploading and the reference.
    /// The scene's `depth_scale` is the wall's depth over its mean extent (texture units),
    /// which the derived normal map uses.
    pub(crate) fn wall_scene(&self, k: usize) -> Scene {
        let w = &self.walls[k];
        let f = Frame::of(wall_frame(k, self.size64()));
        let extent = (f.u_edge.length() * f.v_edge.length()).sqrt() as f32;
        let mut s = Scene::from_height_map(format!("{}/{}", self.name, WALL_NAMES[k]), w.height.clone());
        s.albedo = w.albedo.clone();
        s.normal = w.normal.clone();
        s.depth_scale = w.depth_scale / extent.max(1e-6);
        s.edge = EdgeMode::Clamp;
        s
    }

    /// Checks the room's values: positive size, depth scales in range
    /// (`crate::scene::file::check_depth_scale`), the camera in front of the window and a
    /// finite target, a point light inside the room. Errors name the key.
    pub fn check(&self) -> Result<(), (String, String)> {
        if !self.size.iter().all(|x| x.is_finite() && *x > 0.0) {
            return Err(("size".into(), format!("{:?}: width, height and depth must be positive", self.size)));
        }
        if self.walls.len() != WALLS {
            return Err(("walls".into(), format!("{} walls, expected {WALLS}", self.walls.len())));
        }
        for (k, w) in self.walls.iter().enumerate() {
            crate::scene::file::check_depth_scale(w.depth_scale)
                .map_err(|m| (format!("walls.{}.depth_scale", WALL_NAMES[k]), m))?;
        }
        if !(self.camera.position.is_finite() && self.camera.position.z > 0.0) {
            return Err((
                "camera.position".into(),
                format!("{:?}: the camera must be in front of the window (z > 0)", self.camera.position.to_array()),
            ));
        }
        if !self.camera.target.is_finite() {
            return Err((
                "camera.target".into(),
                format!("{:?}: must be three finite numbers", self.camera.target.to_array()),
            ));
        }
        if !(self.camera.fov_deg > 0.0 && self.camera.fov_deg < 180.0) {
            return Err(("camera.fov".into(), format!("{}: must lie in (0, 180) degrees", self.camera.fov_deg)));
        }
        if let RoomLight::Point(p) = self.light {
            let inside =
                p.x > 0.0 && p.x < self.size[0] && p.y > 0.0 && p.y < self.size[1] && p.z < 0.0 && p.z > -self.size[2];
            if !inside {
                return Err((
                    "light.point".into(),
                    format!("{:?}: a point light must lie inside the room", p.to_array()),
                ));
            }
        }
        if !(self.sun.is_finite() && self.sun.z > 0.0) {
            return Err((
                "sun".into(),
                format!("{:?}: the sun must lie in front of the window (z > 0)", self.sun.to_array()),
            ));
        }
        if !(self.sun_intensity.is_finite() && self.sun_intensity >= 0.0) {
            return Err(("sun_intensity".into(), format!("{}: must be a number >= 0", self.sun_intensity)));
        }
        if !(0.0..=1.0).contains(&self.ambient) {
            return Err(("ambient".into(), format!("{}: must lie in [0, 1]", self.ambient)));
        }
        Ok(())
    }
}

/// Texels on a map's border lower than this below 1 make [`border_warnings`] warn.
pub(crate) const BORDER_TOLERANCE: f32 = 1e-3;

/// One warning per wall whose height map is not at height 1 on its whole border (Amaro & Gustafsson 2022
/// §4: the walls would not meet at the room's edges). Empty when every border is at 1.
pub fn border_warnings(room: &Room) -> Vec<String> {
    let mut out = Vec::new();
    for (k, w) in room.walls.iter().enumerate() {
        let m = &w.height;
        let (nw, nh) = (m.width, m.height);
        let mut low = 0usize;
        let mut min = f32::INFINITY;
        let mut total = 0usize;
        for y in 0..nh {
            for x in 0..nw {
                if x == 0 || y == 0 || x == nw - 1 || y == nh - 1 {
                    let h = m.data[y * nw + x];
                    total += 1;
                    min = min.min(h);
                    if h < 1.0 - BORDER_TOLERANCE {
                        low += 1;
                    }
                }
            }
        }
        if low > 0 {
            out.push(format!(
                "room {}: the {} wall's height map is below 1 on {low} of its {total} border texels (lowest {min:.3}); interior mapping (Amaro & Gustafsson 2022) needs height 1 at the borders so that the walls meet",
                room.name, WALL_NAMES[k]
            ));
        }
    }
    out
}

/// The room named by `arg`: `room:NAME` (built-in, [`builtin::names`]), or a TOML file; the
/// border warnings with it.
pub fn room_from_arg(arg: Option<&str>, map_size: Option<usize>) -> Result<(Room, Vec<String>), String> {
    let room = match arg {
        None => builtin::room("default", map_size)?,
        Some(a) if a.starts_with("room:") => builtin::room(&a["room:".len()..], map_size)?,
        Some(a) if a.ends_with(".toml") => {
            file::load_room_file(std::path::Path::new(a), map_size).map_err(|e| e.to_string())?
        }
        Some(a) => builtin::room(a, map_size).map_err(|e| format!("{e}; or give a room file (`.toml`)"))?,
    };
    let warnings = border_warnings(&room);
    Ok((room, warnings))
}
