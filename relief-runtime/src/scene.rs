//! Scenes as plain data: a height map, optional albedo and normal map, depth scale, tiling,
//! edge mode, camera and light. No scene graph.
//!
//! # World and texture space
//!
//! World units are texture units. The relief quad is the square `[0, tiling]²` in the world
//! plane z = 0, with world x = u and world y = v (so the texture repeats `tiling` times across
//! it), and world z pointing up, out of the surface. The quad is the *top* of the relief
//! volume (height z = 1, see DESIGN.md "Conventions"); the relief hangs below it, down to world
//! z = -`depth_scale` at height 0. A point at height `z` in [0, 1] lies at world
//! z = (z - 1) · depth_scale.
//!
//! A world view direction `V` (pointing away from the eye, `V.z < 0`) becomes the normalized
//! tangent-space ray direction (Szirmay-Kalos & Umenhoffer, paper 002, eq. 11):
//!
//! ```text
//! d = (V.x · s / -V.z,  V.y · s / -V.z,  -1),   s = depth_scale
//! ```
//!
//! so that the ray `(u0, v0, 1) + t·d` reaches height 0 at t = 1.
//!
//! # Camera
//!
//! [`Camera`] orbits the centre of the quad: `angle_deg` is measured from the surface normal
//! (0 = straight down, 90 = grazing), `azimuth_deg` is the direction, around +z and from +x
//! towards +y, in which the eye sits as seen from the target. Projection follows wgpu: a
//! right-handed view, depth in [0, 1] ([`glam::Mat4::perspective_rh`]), NDC x to the right
//! and y up, pixel row 0 at the top of the image. The screen's up vector is the direction in
//! the vertical plane through the eye and the target that is perpendicular to the view, so it
//! stays defined at angle 0 (where it points away from the eye's azimuth).

use std::fmt;
use std::path::Path;

use glam::{Mat4, Vec3};

use crate::heightmap::{EdgeMode, HeightMap, HeightMapError, LoadOptions};

pub mod builtin;
pub mod file;

pub use builtin::{scene_kind, SceneKind, REAL_SCENES};
pub use file::{load_scene_file, Overrides, SceneFileError};

/// Side of the procedural height maps when no size is asked for.
pub const DEFAULT_SIZE: usize = 256;

/// An RGBA8 image, row-major, 4 bytes per texel (r, g, b, a), row 0 at v = 0.
#[derive(Clone, Debug, PartialEq)]
pub struct Rgba8Image {
    pub width: usize,
    pub height: usize,
    pub rgba: Vec<u8>,
}

/// A tangent-space normal map: unit vectors (x along u, y along v, z up), row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct NormalMap {
    pub width: usize,
    pub height: usize,
    pub data: Vec<[f32; 3]>,
}

/// A perspective camera that looks at a target point (the centre of the quad).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Angle between the view axis and the surface normal, degrees (0 = looking straight down).
    pub angle_deg: f32,
    /// Direction of the eye around the target, degrees from +x towards +y.
    pub azimuth_deg: f32,
    /// Distance from the eye to the target, world (= texture) units.
    pub distance: f32,
    /// Vertical field of view, degrees.
    pub fov_deg: f32,
    /// The point looked at (the centre of the quad, on z = 0).
    pub target: Vec3,
}

impl Camera {
    /// The default camera for a quad of side `tiling`: 45° from the normal, azimuth -90° (the
    /// eye on the -v side, so +u runs right and +v runs up the screen), 40° vertical field of
    /// view, at a distance where the quad fills most of a square frame.
    pub fn default_for(tiling: f32) -> Camera {
        Camera {
            angle_deg: 45.0,
            azimuth_deg: -90.0,
            distance: 1.3 * tiling,
            fov_deg: 40.0,
            target: Vec3::new(0.5 * tiling, 0.5 * tiling, 0.0),
        }
    }

    /// The eye's world position.
    pub fn camera_position(&self) -> Vec3 {
        let (a, az) = (self.angle_deg.to_radians(), self.azimuth_deg.to_radians());
        self.target + self.distance * Vec3::new(a.sin() * az.cos(), a.sin() * az.sin(), a.cos())
    }

    /// Unit vectors (forward, right, up) of the view.
    pub fn basis(&self) -> (Vec3, Vec3, Vec3) {
        let (a, az) = (self.angle_deg.to_radians(), self.azimuth_deg.to_radians());
        let forward = -Vec3::new(a.sin() * az.cos(), a.sin() * az.sin(), a.cos());
        let up = Vec3::new(-a.cos() * az.cos(), -a.cos() * az.sin(), a.sin());
        let right = forward.cross(up);
        (forward, right, up)
    }

    /// Near and far clip distances: `distance / 100` and `distance * 100`.
    pub fn near_far(&self) -> (f32, f32) {
        (self.distance * 0.01, self.distance * 100.0)
    }

    /// The view matrix (world → view, right-handed, looking down -z).
    pub fn view(&self) -> Mat4 {
        let (_, _, up) = self.basis();
        Mat4::look_at_rh(self.camera_position(), self.target, up)
    }

    /// Projection × view, wgpu clip conventions (depth 0..1). `aspect` = width / height.
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        let (near, far) = self.near_far();
        Mat4::perspective_rh(self.fov_deg.to_radians(), aspect, near, far) * self.view()
    }

    /// The world direction (unit) of the ray through NDC point `(ndc_x, ndc_y)`. Built from
    /// the camera basis directly (equal, up to rounding, to unprojecting with
    /// [`Camera::view_proj`], without its loss of precision).
    pub fn ray_dir(&self, ndc_x: f32, ndc_y: f32, aspect: f32) -> Vec3 {
        let (f, r, u) = self.basis();
        let ty = (0.5 * self.fov_deg.to_radians()).tan();
        (f + ndc_x * ty * aspect * r + ndc_y * ty * u).normalize()
    }
}

/// One probe ray: the shader ABI's record ([`relief_dsl::abi::ProbeRay`]), 32 bytes.
pub use relief_dsl::abi::ProbeRay;

/// A scene: everything a render, a probe or the reference needs, and no more.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// `scene:NAME` for procedural scenes, the file stem for loaded ones.
    pub name: String,
    /// Heights in [0, 1], 1 = top of the relief volume.
    pub height: HeightMap,
    /// Base colour; `None`: a neutral grey.
    pub albedo: Option<Rgba8Image>,
    /// Normal map; `None`: derived from the height map.
    pub normal: Option<NormalMap>,
    /// Depth of the relief volume in texture (= world) units.
    pub depth_scale: f32,
    /// Number of repeats of the texture across the quad (the quad is `[0, tiling]²`).
    pub tiling: f32,
    /// How maps are sampled past their edges.
    pub edge: EdgeMode,
    pub camera: Camera,
    /// Unit vector from the surface towards the light (world = tangent space).
    pub light_dir: Vec3,
}

impl Scene {
    /// A scene around a height map with the defaults: depth 0.1, tiling 1, repeat, the
    /// default camera, light from up-left-front.
    pub fn from_height_map(name: impl Into<String>, height: HeightMap) -> Scene {
        Scene {
            name: name.into(),
            height,
            albedo: None,
            normal: None,
            depth_scale: 0.1,
            tiling: 1.0,
            edge: EdgeMode::Repeat,
            camera: Camera::default_for(1.0),
            light_dir: Vec3::new(-0.4, -0.5, 0.75).normalize(),
        }
    }

    /// Sets the tiling and re-centres the camera target on the new quad (distance scaled).
    pub fn with_tiling(mut self, tiling: f32) -> Scene {
        let old = self.tiling;
        self.tiling = tiling;
        self.camera.target = Vec3::new(0.5 * tiling, 0.5 * tiling, 0.0);
        self.camera.distance *= tiling / old;
        self
    }

    /// The built-in scene `name` (see [`SCENES`]) with `size × size` texels: a procedural
    /// scene is generated at that size (default [`DEFAULT_SIZE`]); a real one
    /// ([`REAL_SCENES`]) is decoded at its native size and, for a smaller size that divides
    /// it, box-filtered down (see [`builtin`]).
    pub fn by_name(name: &str, size: Option<usize>) -> Result<Scene, SceneError> {
        if let Some(r) = builtin::find(name) {
            return builtin::real_scene(r, size);
        }
        let size = size.unwrap_or(DEFAULT_SIZE);
        if size == 0 {
            return Err(SceneError::ZeroSize);
        }
        let n = size;
        let mut s = match name {
            "lion" => Scene::from_height_map("", lion(n)).albedo_from(stone_palette),
            "self_shadow" => {
                let mut s = Scene::from_height_map("", self_shadow(n)).albedo_from(sand_palette);
                s.depth_scale = 0.15;
                s.light_dir = Vec3::new(0.8, 0.35, 0.35).normalize();
                s
            }
            "collage" => Scene::from_height_map("", collage(n)).albedo_from(sand_palette),
            "shapes" => {
                let mut s = Scene::from_height_map("", shapes(n)).albedo_from(stone_palette);
                s.depth_scale = 0.08;
                s
            }
            "rock_bump" => Scene::from_height_map("", rock_bump(n)).albedo_from(stone_palette),
            "spikes" => Scene::from_height_map("", spikes(n)),
            "walls" => Scene::from_height_map("", walls(n)),
            "flat0" => Scene::from_height_map("", HeightMap::from_fn(n, n, |_, _| 0.0)),
            "flat1" => Scene::from_height_map("", HeightMap::from_fn(n, n, |_, _| 1.0)),
            "step" => Scene::from_height_map("", step(n)),
            "checker" => Scene::from_height_map("", checker(n)),
            _ => return Err(SceneError::unknown(name)),
        };
        s.name = format!("scene:{name}");
        Ok(s)
    }

    fn albedo_from(mut self, palette: fn(f32, u32) -> [u8; 3]) -> Scene {
        let m = &self.height;
        let mut rgba = Vec::with_capacity(m.width * m.height * 4);
        for y in 0..m.height {
            for x in 0..m.width {
                let h = m.data[y * m.width + x];
                let [r, g, b] = palette(h, hash2(x as u32, y as u32, 77));
                rgba.extend_from_slice(&[r, g, b, 255]);
            }
        }
        self.albedo = Some(Rgba8Image { width: m.width, height: m.height, rgba });
        self
    }

    /// One probe ray per pixel of a `size × size` frame; see [`Scene::rays_wh`].
    pub fn rays(&self, size: u32) -> Vec<ProbeRay> {
        self.rays_wh(size, size)
    }

    /// One probe ray per pixel (through the pixel centre) whose camera ray meets the quad
    /// `[0, tiling]²` on z = 0 (boundary included), in row-major pixel order. Pixels that miss
    /// the quad get no ray. Pixel (x, y) has NDC `(2(x + ½)/w - 1, 1 - 2(y + ½)/h)`.
    pub fn rays_wh(&self, width: u32, height: u32) -> Vec<ProbeRay> {
        let aspect = width as f32 / height as f32;
        let eye = self.camera.camera_position();
        let mut out = Vec::new();
        for py in 0..height {
            for px in 0..width {
                let nx = 2.0 * (px as f32 + 0.5) / width as f32 - 1.0;
                let ny = 1.0 - 2.0 * (py as f32 + 0.5) / height as f32;
                let v = self.camera.ray_dir(nx, ny, aspect);
                if let Some(r) = self.tangent_ray(eye, v) {
                    out.push(ProbeRay { x: px, y: py, ..r });
                }
            }
        }
        out
    }

    /// The tangent-space probe ray for a world ray from `eye` along `v` (any length), if it
    /// meets the quad from above. Pixel fields are 0.
    pub fn tangent_ray(&self, eye: Vec3, v: Vec3) -> Option<ProbeRay> {
        let from_above = eye.z > 0.0 && v.z < 0.0; // false for NaN too
        if !from_above {
            return None;
        }
        let s = -eye.z / v.z;
        let p = eye + s * v;
        let inside = |c: f32| (0.0..=self.tiling).contains(&c);
        if !inside(p.x) || !inside(p.y) {
            return None;
        }
        let k = self.depth_scale / -v.z;
        Some(ProbeRay { origin: [p.x, p.y], dir: [v.x * k, v.y * k, -1.0], x: 0, y: 0, pad: 0 })
    }
}

/// The built-in scenes, with what each stresses: the real maps (see [`REAL_SCENES`]), the
/// procedural stand-ins for the dissertation's scenes, the stress scenes. `scene:NAME` on the
/// command line. The kind of each is [`scene_kind`].
pub const SCENES: &[(&str, &str)] = &[
    ("rocks", "real: rounded rocks (POM sample, 256², depth 0.1); the dissertation's Rock Bump"),
    ("stones", "real: flat paving stones (POM sample, 256², depth 0.02); a vertical seam"),
    ("wall", "real: brick wall (POM sample, 256², depth 0.06)"),
    ("four", "real: four simple shapes (POM sample, 256², depth 0.2); close to the dissertation's Shapes"),
    ("saint", "real: a carved saint (POM sample, 256², depth 0.08); does not tile"),
    ("bump", "real: bumps (POM sample, 128², depth 0.2); normals derived from the height"),
    ("dent", "real: dents (POM sample, 128², depth 0.2); normals derived from the height"),
    ("lion", "stand-in for Lion: a carved medallion, sharp one-texel edges and grooves at several depths"),
    ("self_shadow", "stand-in for Self-shadow: tall thin pillars on a low floor, long shadows, deep occlusion"),
    ("collage", "stand-in for Collage: sharp terraces, smooth waves, domes and rough noise in four quadrants"),
    ("shapes", "stand-in for Shapes: flat tops and gentle slopes (plateaus, a truncated pyramid, a ramp)"),
    ("rock_bump", "stand-in for Rock Bump: smooth rounded stones with soft grooves, small bumps"),
    ("spikes", "stress: isolated single-texel spikes on a flat floor (thin features a step skips)"),
    ("walls", "stress: one-texel-thick walls on a grid (thin occluders seen edge-on)"),
    ("flat0", "stress: everything at height 0 (every ray travels the full depth)"),
    ("flat1", "stress: everything at height 1 (every ray hits at t = 0)"),
    ("step", "stress: a vertical step from 0 to 1 (a discontinuity, cliffs hit from both sides)"),
    ("checker", "stress: a 0/1 checkerboard (many cliffs, corners, exact texel boundaries)"),
];

/// The names of [`SCENES`].
pub fn scene_names() -> Vec<&'static str> {
    SCENES.iter().map(|(n, _)| *n).collect()
}

/// A scene from a command-line argument: `scene:NAME` (built-in, default size), a TOML scene
/// file (`.toml`, see [`mod@file`]) or a path to an image file (edge mode repeat, loaded with
/// default [`LoadOptions`]).
pub fn scene_from_arg(arg: &str) -> Result<Scene, SceneError> {
    scene_from_arg_with(arg, None, &LoadOptions::default())
}

/// The canonical form of a scene argument: `scene:NAME` for a built-in name (a bare NAME is
/// one), the argument itself for anything with a `:`, a `.toml` ending or an existing path.
pub fn scene_spec(arg: &str) -> String {
    let is_file = Path::new(arg).extension().is_some_and(|e| e.eq_ignore_ascii_case("toml")) || Path::new(arg).exists();
    if arg.contains(':') || is_file {
        arg.to_string()
    } else {
        format!("scene:{arg}")
    }
}

/// [`scene_from_arg`] with a texel size for procedural scenes and load options for files.
pub fn scene_from_arg_with(arg: &str, size: Option<usize>, options: &LoadOptions) -> Result<Scene, SceneError> {
    if let Some(name) = arg.strip_prefix("scene:") {
        return Scene::by_name(name, size);
    }
    let path = Path::new(arg);
    if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("toml")) {
        return Ok(load_scene_file(path)?);
    }
    let map = HeightMap::load(path, options)?;
    let name = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| arg.to_string());
    Ok(Scene::from_height_map(name, map))
}

/// Why a scene could not be made.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// Not one of [`SCENES`].
    #[error("{}", unknown_message(name, suggestion))]
    Unknown { name: String, suggestion: Option<&'static str> },
    #[error("a scene needs at least one texel (size 0 asked for)")]
    ZeroSize,
    /// A real scene asked for at a size it cannot be box-filtered down to.
    #[error("scene `{name}` is a real {native}x{native} map: size {size} must divide {native} (it is box-filtered down by a whole factor, never up)")]
    BadRealSize { name: &'static str, native: usize, size: usize },
    /// A scene file could not be read.
    #[error(transparent)]
    File(#[from] SceneFileError),
    /// The height-map file could not be loaded.
    #[error(transparent)]
    Load(#[from] HeightMapError),
}

impl SceneError {
    fn unknown(name: &str) -> SceneError {
        let suggestion = relief_dsl::spec::suggest::nearest(name, SCENES.iter().map(|(n, _)| *n));
        SceneError::Unknown { name: name.to_string(), suggestion }
    }
}

fn unknown_message(name: &str, suggestion: &Option<&'static str>) -> String {
    let mut m = format!("unknown scene `{name}`");
    if let Some(s) = suggestion {
        m += &format!(" (did you mean `{s}`?)");
    }
    m += "; valid scenes: ";
    m += &scene_names().join(", ");
    m
}

impl fmt::Display for Scene {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} ({}x{}, depth {}, tiling {}, {:?})",
            self.name, self.height.width, self.height.height, self.depth_scale, self.tiling, self.edge
        )
    }
}

// ---------------------------------------------------------------------------------------------
// Procedural height maps. Pure functions of the size; all tile seamlessly (edge mode repeat).
// ---------------------------------------------------------------------------------------------

/// A 32-bit integer hash of a lattice point and a seed (lowbias32-style mixing).
fn hash2(x: u32, y: u32, seed: u32) -> u32 {
    let mut h = x.wrapping_mul(0x8da6_b343) ^ y.wrapping_mul(0xd816_3841) ^ seed.wrapping_mul(0xcb1a_b31f);
    h ^= h >> 16;
    h = h.wrapping_mul(0x7feb_352d);
    h ^= h >> 15;
    h = h.wrapping_mul(0x846c_a68b);
    h ^= h >> 16;
    h
}

/// Hash to [0, 1).
fn hash01(x: u32, y: u32, seed: u32) -> f32 {
    (hash2(x, y, seed) >> 8) as f32 / (1u32 << 24) as f32
}

fn smoothstep(a: f32, b: f32, x: f32) -> f32 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Periodic value noise with `period` lattice cells across [0, 1), smooth (quintic fade).
fn value_noise(u: f32, v: f32, period: u32, seed: u32) -> f32 {
    let (x, y) = (u * period as f32, v * period as f32);
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let fade = |t: f32| t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
    let (sx, sy) = (fade(fx), fade(fy));
    let wrap = |i: f32| (i as i64).rem_euclid(period as i64) as u32;
    let (xa, xb, ya, yb) = (wrap(x0), wrap(x0 + 1.0), wrap(y0), wrap(y0 + 1.0));
    let a = hash01(xa, ya, seed) + (hash01(xb, ya, seed) - hash01(xa, ya, seed)) * sx;
    let b = hash01(xa, yb, seed) + (hash01(xb, yb, seed) - hash01(xa, yb, seed)) * sx;
    a + (b - a) * sy
}

/// Periodic fractal noise in [0, 1].
fn fbm(u: f32, v: f32, period: u32, octaves: u32, seed: u32) -> f32 {
    let (mut sum, mut amp, mut norm, mut p) = (0.0, 1.0, 0.0, period);
    for o in 0..octaves {
        sum += amp * value_noise(u, v, p, seed + o);
        norm += amp;
        amp *= 0.5;
        p *= 2;
    }
    sum / norm
}

/// Texel centre in [0, 1)².
fn uv(x: usize, y: usize, n: usize) -> (f32, f32) {
    ((x as f32 + 0.5) / n as f32, (y as f32 + 0.5) / n as f32)
}

/// Lion: a carved medallion. A raised disc with a sharp rim, a mane of radial wedges cut to
/// alternating depths, a raised face with carved eyes and a mouth groove. Every feature edge
/// is a one-texel discontinuity: stresses sharp edges and grooves (methods that step over a
/// thin groove, or blur a cliff, show here), like the dissertation's carved Lion.
pub fn lion(n: usize) -> HeightMap {
    HeightMap::from_fn(n, n, |x, y| {
        let (u, v) = uv(x, y, n);
        let (dx, dy) = (u - 0.5, v - 0.5);
        let r = (dx * dx + dy * dy).sqrt();
        let a = dy.atan2(dx);
        if r > 0.44 {
            // Background: flat with a fine brick pattern carved in.
            let bu = (u * 16.0).fract();
            let bv = (v * 16.0 + if (u * 16.0) as i32 % 2 == 0 { 0.0 } else { 0.5 }).fract();
            return if bu < 0.06 || bv < 0.06 { 0.22 } else { 0.32 };
        }
        if r > 0.40 {
            return 0.96; // the rim
        }
        if r > 0.36 {
            return 0.62; // the channel inside the rim
        }
        if r > 0.17 {
            // Mane: 14 wedges, alternately high and carved, with a groove between them.
            let k = a / std::f32::consts::TAU * 14.0;
            let f = k - k.floor();
            if f < 0.08 {
                return 0.45;
            }
            return if (k.floor() as i32).rem_euclid(2) == 0 { 0.85 } else { 0.72 };
        }
        // Face, drawn with +v up so that it reads upright from the default camera.
        let dy = -dy;
        let eye = |ex: f32| ((dx - ex).powi(2) + (dy + 0.05).powi(2)).sqrt() < 0.03;
        if eye(-0.06) || eye(0.06) {
            return 0.55;
        }
        let mouth = dy > 0.03 && dy < 0.11 && ((dx * dx + (dy - 0.02).powi(2)).sqrt() - 0.08).abs() < 0.012;
        if mouth {
            return 0.6;
        }
        let nose = dx.abs() < 0.02 && dy > -0.04 && dy < 0.05;
        if nose {
            return 1.0;
        }
        0.9
    })
}

/// Self-shadow: square pillars of different heights (0.55 to 1) and widths (about 2 to 15 texels at
/// 256²) on a low, slightly rough floor. Stresses long shadows from tall occluders, deep
/// narrow gaps where rays travel far, and tall thin features a coarse step misses.
pub fn self_shadow(n: usize) -> HeightMap {
    let cells = 6u32;
    HeightMap::from_fn(n, n, |x, y| {
        let (u, v) = uv(x, y, n);
        let floor = 0.04 + 0.06 * fbm(u, v, 8, 3, 11);
        let (cu, cv) = ((u * cells as f32).floor() as u32, (v * cells as f32).floor() as u32);
        let mut h = floor;
        // Each cell holds one pillar; look at this cell only (pillars stay inside it).
        // Half-width in cell units (1 cell = n/6 texels); some pillars are thin.
        let half = if hash01(cu, cv, 2) < 0.3 { 0.025 } else { 0.03 + 0.15 * hash01(cu, cv, 1) };
        let (pu, pv) = (0.5 + 0.3 * (hash01(cu, cv, 3) - 0.5), 0.5 + 0.3 * (hash01(cu, cv, 4) - 0.5));
        let (lu, lv) = (u * cells as f32 - cu as f32, v * cells as f32 - cv as f32);
        if (lu - pu).abs() < half && (lv - pv).abs() < half {
            h = 0.55 + 0.45 * hash01(cu, cv, 5);
        }
        h
    })
}

/// Collage: four quadrants of different character. Terraced pyramid (sharp, flat steps),
/// smooth sine waves, hemispherical domes (smooth tops, sharp base contours), rough fractal
/// noise. Stresses a method's consistency across sharp and smooth content in one frame.
pub fn collage(n: usize) -> HeightMap {
    use std::f32::consts::TAU;
    HeightMap::from_fn(n, n, |x, y| {
        let (u, v) = uv(x, y, n);
        let (qu, qv) = ((u * 2.0).fract(), (v * 2.0).fract());
        match (u < 0.5, v < 0.5) {
            (true, true) => {
                // Terraces: 6 square steps towards the centre.
                let d = (qu - 0.5).abs().max((qv - 0.5).abs());
                0.15 + 0.8 * ((1.0 - d / 0.5) * 6.0).floor().clamp(0.0, 5.0) / 5.0
            }
            (false, true) => 0.5 + 0.4 * (TAU * 2.0 * qu).sin() * (TAU * 2.0 * qv).sin(),
            (true, false) => {
                // 3x3 domes.
                let (cu, cv) = ((qu * 3.0).fract() - 0.5, (qv * 3.0).fract() - 0.5);
                let r2 = (cu * cu + cv * cv) / (0.42 * 0.42);
                0.1 + if r2 < 1.0 { 0.85 * (1.0 - r2).sqrt() } else { 0.0 }
            }
            (false, false) => fbm(u, v, 8, 5, 21),
        }
    })
}

/// Shapes: flat plateaus joined by gentle slopes: a truncated pyramid, a round mesa with a
/// smooth shoulder, a long ramp, on a flat base. Stresses flat regions (where secant and
/// interval refinements are exact) against gentle slopes seen at grazing angles.
pub fn shapes(n: usize) -> HeightMap {
    HeightMap::from_fn(n, n, |x, y| {
        let (u, v) = uv(x, y, n);
        let mut h: f32 = 0.2;
        // Truncated pyramid centred at (0.28, 0.3): top 0.12 wide, slope 0.12 wide.
        let d = (u - 0.28).abs().max((v - 0.3).abs());
        h = h.max(0.2 + 0.6 * (1.0 - ((d - 0.06) / 0.12).clamp(0.0, 1.0)));
        // Round mesa at (0.72, 0.32), radius 0.12, smooth shoulder 0.08.
        let r = ((u - 0.72).powi(2) + (v - 0.32).powi(2)).sqrt();
        h = h.max(0.2 + 0.5 * (1.0 - smoothstep(0.12, 0.2, r)));
        // A ramp along u in the band v in [0.62, 0.88], rising from 0.2 to 0.7, with a flat top.
        if (0.62..0.88).contains(&v) {
            h = h.max(0.2 + 0.5 * ((u - 0.1) / 0.6).clamp(0.0, 1.0));
        }
        h
    })
}

/// Rock bump: rounded stones (a periodic Worley pattern: high in the middle of each cell, soft
/// grooves where cells meet) with small smooth bumps on top. Everything is smooth; stresses
/// curved surfaces where linear search's staircase and binary refinement are easy to see.
pub fn rock_bump(n: usize) -> HeightMap {
    let g = 5u32;
    HeightMap::from_fn(n, n, |x, y| {
        let (u, v) = uv(x, y, n);
        let (px, py) = (u * g as f32, v * g as f32);
        let (cx, cy) = (px.floor() as i64, py.floor() as i64);
        let (mut f1, mut f2) = (f32::MAX, f32::MAX);
        for j in -2..=2 {
            for i in -2..=2 {
                let (qx, qy) = (cx + i, cy + j);
                let (wx, wy) = (qx.rem_euclid(g as i64) as u32, qy.rem_euclid(g as i64) as u32);
                let fx = qx as f32 + 0.3 + 0.4 * hash01(wx, wy, 31);
                let fy = qy as f32 + 0.3 + 0.4 * hash01(wx, wy, 32);
                let d = ((px - fx).powi(2) + (py - fy).powi(2)).sqrt();
                if d < f1 {
                    f2 = f1;
                    f1 = d;
                } else if d < f2 {
                    f2 = d;
                }
            }
        }
        // (f2 - f1) / 2 is the distance to the border between two stones: a smooth shoulder
        // up from the groove, then a gently domed top.
        let shoulder = smoothstep(0.0, 0.3, 0.5 * (f2 - f1));
        let dome = 1.0 - 0.35 * (f1 / 0.6).min(1.0).powi(2);
        (0.12 + 0.7 * shoulder * dome + 0.08 * fbm(u, v, 16, 3, 41)).clamp(0.0, 1.0)
    })
}

/// Spikes: a flat floor at 0 with isolated single-texel spikes at height 1 (about one texel
/// in 64, never adjacent). Under bilinear sampling each is a one-texel-wide pyramid: the
/// thinnest feature there is; any method that steps more than a texel may miss it.
pub fn spikes(n: usize) -> HeightMap {
    HeightMap::from_fn(n, n, |x, y| {
        let (x, y) = (x as u32, y as u32);
        // One candidate per 8x8 block, at a hashed position inside the block's inner 6x6.
        let (bx, by) = (x / 8, y / 8);
        let sx = bx * 8 + 1 + hash2(bx, by, 51) % 6;
        let sy = by * 8 + 1 + hash2(bx, by, 52) % 6;
        if x == sx && y == sy && (sx as usize) < n && (sy as usize) < n {
            1.0
        } else {
            0.0
        }
    })
}

/// Walls: one-texel-thick walls of height 1 on a square grid (spacing n/16 texels, at least
/// 4) over a floor at 0. Stresses thin occluders seen at grazing angles.
pub fn walls(n: usize) -> HeightMap {
    let k = (n / 16).max(4);
    HeightMap::from_fn(n, n, |x, y| if x % k == 0 || y % k == 0 { 1.0 } else { 0.0 })
}

/// Step: 0 for u < 1/2, 1 for u >= 1/2 (with repeat, a second cliff at u = 0).
pub fn step(n: usize) -> HeightMap {
    HeightMap::from_fn(n, n, |x, _| if 2 * x < n { 0.0 } else { 1.0 })
}

/// Checker: 0/1 squares of side n/8 texels (at least 1).
pub fn checker(n: usize) -> HeightMap {
    let k = (n / 8).max(1);
    HeightMap::from_fn(n, n, |x, y| if (x / k + y / k).is_multiple_of(2) { 0.0 } else { 1.0 })
}

fn stone_palette(h: f32, noise: u32) -> [u8; 3] {
    let j = (noise % 16) as f32 - 8.0;
    let c = |base: f32, k: f32| (base + k * h + j).clamp(0.0, 255.0) as u8;
    [c(110.0, 110.0), c(100.0, 105.0), c(90.0, 95.0)]
}

fn sand_palette(h: f32, noise: u32) -> [u8; 3] {
    let j = (noise % 12) as f32 - 6.0;
    let c = |base: f32, k: f32| (base + k * h + j).clamp(0.0, 255.0) as u8;
    [c(150.0, 90.0), c(120.0, 90.0), c(80.0, 80.0)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_named_scene_builds_in_range_and_deterministically() {
        for (name, doc) in SCENES {
            assert!(!doc.is_empty());
            let a = Scene::by_name(name, Some(64)).unwrap();
            let b = Scene::by_name(name, Some(64)).unwrap();
            assert_eq!(a, b, "{name} is not deterministic");
            assert_eq!(a.name, format!("scene:{name}"));
            assert_eq!((a.height.width, a.height.height), (64, 64));
            assert!(a.height.data.iter().all(|h| (0.0..=1.0).contains(h)), "{name} out of [0, 1]");
            if let Some(img) = &a.albedo {
                assert_eq!(img.rgba.len(), 64 * 64 * 4);
            }
            assert!((a.light_dir.length() - 1.0).abs() < 1e-5);
        }
        let d = Scene::by_name("lion", None).unwrap();
        assert_eq!(d.height.width, DEFAULT_SIZE);
    }

    #[test]
    fn scenes_have_the_features_they_promise() {
        let n = 256;
        let count = |m: &HeightMap, f: &dyn Fn(f32) -> bool| m.data.iter().filter(|h| f(**h)).count();
        let sp = spikes(n);
        assert!(count(&sp, &|h| h == 1.0) >= (n / 8) * (n / 8) - 1);
        // Spikes are single texels: no 4-neighbour of a spike is a spike.
        for y in 0..n as i64 {
            for x in 0..n as i64 {
                if sp.texel(x, y, EdgeMode::Repeat) == 1.0 {
                    for (dx, dy) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
                        assert_eq!(sp.texel(x + dx, y + dy, EdgeMode::Repeat), 0.0);
                    }
                }
            }
        }
        let ss = self_shadow(n);
        assert!(count(&ss, &|h| h > 0.9) > 0 && count(&ss, &|h| h < 0.15) > n * n / 2);
        assert!(count(&lion(n), &|h| h > 0.9) > 0);
        // Rock bump is smooth: no cliffs, neighbouring texels never differ by much (lion and
        // checker jump by 0.3 to 1).
        let rb = rock_bump(n);
        for y in 0..n as i64 {
            for x in 0..n as i64 {
                let d = (rb.texel(x + 1, y, EdgeMode::Repeat) - rb.texel(x, y, EdgeMode::Repeat)).abs();
                assert!(d < 0.08, "rock_bump jumps by {d} at ({x}, {y})");
            }
        }
        assert_eq!(count(&step(n), &|h| h == 1.0), n * n / 2);
        assert_eq!(count(&checker(n), &|h| h == 1.0), n * n / 2);
    }

    #[test]
    fn unknown_names_list_the_valid_ones_and_suggest_the_nearest() {
        let e = Scene::by_name("rockbump", None).unwrap_err().to_string();
        assert!(e.contains("did you mean `rock_bump`"), "{e}");
        for (n, _) in SCENES {
            assert!(e.contains(n), "{e}");
        }
        let e = Scene::by_name("xyzzy-nothing-like-it", None).unwrap_err().to_string();
        assert!(!e.contains("did you mean"), "{e}");
        assert!(scene_from_arg("scene:lino").unwrap_err().to_string().contains("`lion`"));
        assert_eq!(scene_from_arg("scene:step").unwrap().name, "scene:step");
        assert!(scene_from_arg("/nonexistent/relief/height.png").is_err());
    }

    #[test]
    fn camera_looks_at_the_target_from_the_given_angle() {
        let s = Scene::by_name("flat0", Some(8)).unwrap();
        let c = s.camera;
        let eye = c.camera_position();
        assert!((eye.distance(c.target) - c.distance).abs() < 1e-5);
        let to = (c.target - eye).normalize();
        assert!((to.dot(-Vec3::Z).acos().to_degrees() - c.angle_deg).abs() < 1e-3);
        // The target projects to the centre of the frame, in front of the eye.
        let p = c.view_proj(1.0).project_point3(c.target);
        assert!(p.x.abs() < 1e-5 && p.y.abs() < 1e-5 && p.z > 0.0 && p.z < 1.0, "{p}");
        // The basis is orthonormal and right-handed at every angle, including 0 and 90.
        for a in [0.0, 10.0, 45.0, 89.0, 90.0] {
            let c = Camera { angle_deg: a, azimuth_deg: 33.0, ..c };
            let (f, r, u) = c.basis();
            assert!(f.dot(r).abs() < 1e-6 && f.dot(u).abs() < 1e-6 && r.dot(u).abs() < 1e-6);
            assert!((r.cross(u) - -f).length() < 1e-5);
            assert!((c.view_proj(1.0).project_point3(c.target)).truncate().length() < 1e-4);
        }
    }

    #[test]
    fn rays_go_through_pixel_centres_and_enter_the_quad() {
        let mut s = Scene::by_name("flat0", Some(16)).unwrap().with_tiling(2.0);
        s.depth_scale = 0.2;
        s.camera.azimuth_deg = 20.0;
        let (w, h) = (48u32, 32u32);
        let rays = s.rays_wh(w, h);
        assert!(rays.len() > (w * h / 3) as usize);
        let vp = s.camera.view_proj(w as f32 / h as f32);
        let eye = s.camera.camera_position();
        for r in &rays {
            assert!((0.0..=2.0).contains(&r.origin[0]) && (0.0..=2.0).contains(&r.origin[1]));
            assert_eq!(r.dir[2], -1.0);
            assert_eq!(r.pad, 0);
            // The entry point projects to the pixel's centre (wgpu NDC, row 0 at the top).
            let p = vp.project_point3(Vec3::new(r.origin[0], r.origin[1], 0.0));
            let px = (p.x + 1.0) * 0.5 * w as f32;
            let py = (1.0 - p.y) * 0.5 * h as f32;
            assert!((px - (r.x as f32 + 0.5)).abs() < 1e-2 && (py - (r.y as f32 + 0.5)).abs() < 1e-2);
            assert!(p.z > 0.0 && p.z < 1.0);
            // The tangent direction continues the world ray: at t = 1 (height 0, world z =
            // -depth) the point lies on the line from the eye through the entry point.
            let bottom = Vec3::new(r.origin[0] + r.dir[0], r.origin[1] + r.dir[1], -s.depth_scale);
            let entry = Vec3::new(r.origin[0], r.origin[1], 0.0);
            let along = (entry - eye).normalize().cross((bottom - eye).normalize()).length();
            assert!(along < 1e-5, "tangent ray leaves the world ray: {along}");
        }
        // Row-major order, one ray per pixel.
        for pair in rays.windows(2) {
            assert!((pair[0].y, pair[0].x) < (pair[1].y, pair[1].x));
        }
        assert_eq!(bytemuck::cast_slice::<ProbeRay, u8>(&rays).len(), rays.len() * 32);
    }

    #[test]
    fn the_default_camera_fills_most_of_the_frame() {
        let s = Scene::by_name("flat0", Some(8)).unwrap();
        let n = 64u32;
        let covered = s.rays(n).len() as f32 / (n * n) as f32;
        assert!(covered > 0.6 && covered < 0.95, "quad covers {covered} of the frame");
    }
}
