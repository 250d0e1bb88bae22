//! Scenes as plain data: a height map, optional albedo and normal map, depth scale, tiling,
//! edge mode, camera and light. No scene graph.
//!
//! # World and texture space
//!
//! World units are texture units. The relief quad is the square `[0, tiling]²` in the world
//! plane z = 0, with world x = u and world y = v (so the texture repeats `tiling` times across
//! it), and world z pointing up, out of the surface. The quad is the *top* of the relief
//! volume (height z = 1, see ARCHITECTURE.md "Conventions"); the relief hangs below it, down to world
//! z = -`depth_scale` at height 0. A point at height `z` in [0, 1] lies at world
//! z = (z - 1) · depth_scale.
//!
//! A world view direction `V` (pointing away from the eye, `V.z < 0`) becomes the normalized
//! tangent-space ray direction (Szirmay-Kalos & Umenhoffer 2008, eq. 11):
//!
//! ```text
//! d = (V.x · s / -V.z,  V.y · s / -V.z,  -1),   s = depth_scale
//! ```
//!
//! so that the ray `(u0, v0, 1) + t·d` reaches height 0 at t = 1.
//!
//! # Modules
//!
//! This module holds the [`Scene`] record and the registry of built-in scenes ([`SCENES`],
//! [`Scene::by_name`], [`scene_from_arg`]); [`camera`] the camera, [`procedural`] the
//! procedural height maps and scenes, [`builtin`] the real scenes, [`mod@file`] scene files.

use std::fmt;
use std::path::Path;

use glam::Vec3;

use crate::heightmap::{EdgeMode, HeightMap, HeightMapError, LoadOptions};

pub(crate) mod builtin;
pub(crate) mod camera;
pub(crate) mod file;
pub(crate) mod procedural;
pub(crate) mod view;

pub(crate) use builtin::scene_kind;
pub use builtin::{RealScene, REAL_SCENES};
pub use camera::Camera;
pub use file::{camera_json, load_scene_file, Overrides, SceneFileError};
pub use view::View;

/// Side of the procedural height maps when no size is asked for.
pub(crate) const DEFAULT_SIZE: usize = 256;

/// An RGBA8 image, row-major, 4 bytes per texel (r, g, b, a), row 0 at v = 0.
#[derive(Clone, Debug, PartialEq)]
pub struct Rgba8Image {
    /// Texels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// `width * height * 4` bytes; colour is sRGB-encoded (uploaded as `Rgba8UnormSrgb`).
    pub rgba: Vec<u8>,
}

/// A tangent-space normal map: unit vectors (x along u, y along v, z up), row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct NormalMap {
    /// Texels per row (may differ from the height map's).
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// `width * height` normals, texel (x, y) at `data[y * width + x]`.
    pub data: Vec<[f32; 3]>,
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
    /// The eye that renders use and that [`Scene::rays`] casts the probe rays from.
    pub camera: Camera,
    /// Unit vector from the surface towards the light (world = tangent space).
    pub light_dir: Vec3,
    /// The scene's sampling level policy (a scene file's `lod`): the `lod` of every pipeline
    /// measured on it that names none ([`Scene::pipeline_for`]). `None`: the pipeline's own.
    pub lod: Option<relief_dsl::spec::Lod>,
    /// The mesh the relief covers (a scene file's `[mesh]`, docs/meshes.md); `None`: the
    /// flat quad. Loaded by `crate::mesh`.
    pub mesh: Option<MeshSource>,
}

/// The mesh a scene names (docs/meshes.md).
#[derive(Clone, Debug, PartialEq)]
pub enum MeshSource {
    /// A built-in mesh: `sphere`, `cylinder` or `torus`.
    Builtin(String),
    /// A glTF 2.0 (`.gltf`, `.glb`) or OBJ file, resolved against the scene file's folder;
    /// `name` picks one of its meshes (all of them when `None`).
    File {
        /// The mesh file.
        path: std::path::PathBuf,
        /// The one mesh to draw, by name.
        name: Option<String>,
    },
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
            lod: None,
            mesh: None,
        }
    }

    /// `p` as measured on this scene: with the scene's `lod` policy where `p` leaves `lod`
    /// at its default (`zero`, not written). A pipeline keeps mip 0 on such a scene with
    /// `lod=level(0)`, the same surface. The result is what rows record, so results say
    /// which level policy was measured.
    pub fn pipeline_for(&self, p: &relief_dsl::Pipeline) -> relief_dsl::Pipeline {
        match self.lod {
            Some(l) if p.lod == relief_dsl::spec::Lod::Zero => p.clone().with_lod(l),
            _ => p.clone(),
        }
    }

    /// Sets the tiling and re-centres the camera target on the new quad (distance scaled).
    pub(crate) fn with_tiling(mut self, tiling: f32) -> Scene {
        let old = self.tiling;
        self.tiling = tiling;
        self.camera.target = Vec3::new(0.5 * tiling, 0.5 * tiling, 0.0);
        self.camera.distance *= tiling / old;
        self
    }

    /// The built-in scene `name` (see `SCENES`) with `size × size` texels: a procedural
    /// scene is generated at that size (default `DEFAULT_SIZE`); a real one
    /// ([`REAL_SCENES`]) is decoded at its native size and, for a smaller size that divides
    /// it, box-filtered down (see `builtin`).
    pub fn by_name(name: &str, size: Option<usize>) -> Result<Scene, SceneError> {
        if let Some(r) = builtin::find(name) {
            return builtin::real_scene(r, size);
        }
        let size = size.unwrap_or(DEFAULT_SIZE);
        if size == 0 {
            return Err(SceneError::ZeroSize);
        }
        let mut s = procedural::scene(name, size).ok_or_else(|| SceneError::unknown(name))?;
        s.name = format!("scene:{name}");
        Ok(s)
    }

    /// One probe ray per pixel of a `size × size` frame; see `Scene::rays_wh`.
    pub fn rays(&self, size: u32) -> Vec<ProbeRay> {
        self.rays_wh(size, size)
    }

    /// One probe ray per pixel (through the pixel centre) whose camera ray meets the quad
    /// `[0, tiling]²` on z = 0 (boundary included), in row-major pixel order. Pixels that miss
    /// the quad get no ray. Pixel (x, y) has NDC `(2(x + ½)/w - 1, 1 - 2(y + ½)/h)`; every ray
    /// carries the frame's [`Camera::pixel_size`].
    pub(crate) fn rays_wh(&self, width: u32, height: u32) -> Vec<ProbeRay> {
        let aspect = width as f32 / height as f32;
        let eye = self.camera.camera_position();
        let pixel_size = self.camera.pixel_size(height);
        let mut out = Vec::new();
        for py in 0..height {
            for px in 0..width {
                let nx = 2.0 * (px as f32 + 0.5) / width as f32 - 1.0;
                let ny = 1.0 - 2.0 * (py as f32 + 0.5) / height as f32;
                let v = self.camera.ray_dir(nx, ny, aspect);
                if let Some(r) = self.tangent_ray(eye, v) {
                    out.push(ProbeRay { x: px, y: py, pixel_size, ..r });
                }
            }
        }
        out
    }

    /// The tangent-space probe ray for a world ray from `eye` along `v` (any length), if it
    /// meets the quad from above. Pixel fields are 0.
    pub(crate) fn tangent_ray(&self, eye: Vec3, v: Vec3) -> Option<ProbeRay> {
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
        Some(ProbeRay { origin: [p.x, p.y], dir: [v.x * k, v.y * k, -1.0], x: 0, y: 0, pixel_size: 0.0 })
    }
}

/// The built-in scenes, with what each stresses: the real maps (see [`REAL_SCENES`]), the
/// procedural stand-ins for the dissertation's scenes, the stress scenes. `scene:NAME` on the
/// command line. The kind of each is [`scene_kind`].
pub(crate) const SCENES: &[(&str, &str)] = &[
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
pub(crate) fn scene_names() -> Vec<&'static str> {
    SCENES.iter().map(|(n, _)| *n).collect()
}

/// A scene from a command-line argument: `scene:NAME` (built-in, default size), a TOML scene
/// file (`.toml`, see `mod@file`) or a path to an image file (edge mode repeat, loaded with
/// default [`LoadOptions`]), each optionally followed by a view as results name it
/// (`scene:rocks@angle=70` is `scene:rocks` with `--angle 70`; see `file::split_view`).
pub fn scene_from_arg(arg: &str) -> Result<Scene, SceneError> {
    scene_from_arg_with(arg, None, &LoadOptions::default())
}

/// The canonical form of a scene argument: `scene:NAME` for a built-in name (a bare NAME is
/// one), the argument itself for anything with a `:`, a `.toml` ending or an existing path;
/// a view suffix (`@angle=70`) is kept after the canonical base.
pub fn scene_spec(arg: &str) -> String {
    if let Some((base, _)) = file::split_view(arg) {
        return format!("{}{}", scene_spec(base), &arg[base.len()..]);
    }
    let is_file = Path::new(arg).extension().is_some_and(|e| e.eq_ignore_ascii_case("toml")) || Path::new(arg).exists();
    if arg.contains(':') || is_file {
        arg.to_string()
    } else {
        format!("scene:{arg}")
    }
}

/// [`scene_from_arg`] with a texel size for procedural scenes and load options for files.
pub(crate) fn scene_from_arg_with(arg: &str, size: Option<usize>, options: &LoadOptions) -> Result<Scene, SceneError> {
    // `rocks@angle=70`: the scene with that view, named as `--angle 70` names it.
    if let Some((base, view)) = file::split_view(arg) {
        let view = view.map_err(|e| SceneError::View { arg: arg.to_string(), message: e })?;
        return Ok(view.apply(scene_from_arg_with(base, size, options)?));
    }
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
    /// Not one of `SCENES`.
    #[error("{}", unknown_message(name, suggestion))]
    Unknown {
        /// The name asked for, without `scene:`.
        name: String,
        /// The nearest built-in name, when one is close enough to be a likely typo.
        suggestion: Option<&'static str>,
    },
    /// A built-in scene asked for at size 0.
    #[error("a scene needs at least one texel (size 0 asked for)")]
    ZeroSize,
    /// A real scene asked for at a size it cannot be box-filtered down to.
    #[error("scene `{name}` is a real {native}x{native} map: size {size} must divide {native} (it is box-filtered down by a whole factor, never up)")]
    BadRealSize {
        /// The real scene's name.
        name: &'static str,
        /// Its side in texels as stored.
        native: usize,
        /// The side asked for: it must divide `native` (so it is at most `native`).
        size: usize,
    },
    /// The view after the `@` of `NAME@angle=70` does not read or is out of range.
    #[error("scene `{arg}`: {message}")]
    View {
        /// The scene argument as given.
        arg: String,
        /// What is wrong with its view.
        message: String,
    },
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

#[cfg(test)]
mod tests {
    use super::procedural::{checker, lion, rock_bump, self_shadow, spikes, step};
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
            assert_eq!(r.pixel_size, s.camera.pixel_size(h));
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
