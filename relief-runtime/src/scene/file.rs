//! Scene files: a scene as TOML, and the command-line overrides of a scene.
//!
//! ```toml
//! name = "my_rocks"              # optional; default: the file's stem
//! depth_scale = 0.1              # relief depth in texture units (fraction of the width)
//! tiling = 1.0                   # repeats across the quad
//! edge = "repeat"                # repeat | clamp
//! light = [-0.4, -0.5, 0.75]     # towards the light (normalised)
//! albedo = "rocks_diffuse.png"   # optional, relative to this file
//! normal_map = "rocks_NM_height.tga"  # optional, RGB = tangent-space normal (2·rgb/255 − 1)
//! normal_green = "up"            # up: green points to the image's top, −v (default); down: +v
//! lod = "auto"                   # sampling level policy: zero | auto | level(k), for pipelines that name none
//! view = "dissertation"          # a named view (crate::scene::view): its depth scale, camera angle and fov, lod; keys given win
//!
//! [height_map]
//! path = "tatarchuk/rocks_NM_height.tga"   # relative to this file
//! channel = "a"                  # r | g | b | a | luma (default: gray, or luma of colour)
//! white = "height"               # height: white is the top (default); depth: white is deep
//!
//! [camera]
//! angle = 45.0                   # degrees from the surface normal, 0 <= angle < 90
//! azimuth = -90.0                # degrees, the eye's direction around +z from +x to +y
//! distance = 1.3                 # eye to the quad's centre, texture units (default 1.3 × tiling)
//! fov = 40.0                     # vertical field of view, degrees
//! ```
//!
//! Every key but `height_map.path` is optional; left out, a key takes the value of
//! [`Scene::from_height_map`] and [`Camera::default_for`]. The camera keys map one to one onto
//! [`Camera`]'s fields (`angle_deg`, `azimuth_deg`, `distance`, `fov_deg`); `tiling` is applied
//! first ([`Scene::with_tiling`] re-centres the camera and scales the default distance), then
//! the named `view`, then `depth_scale`, `lod` and the camera keys.
//!
//! Errors are one line naming the file and the key: an unknown key (with the nearest known
//! one), a value of the wrong type, a bad value, a missing file. Unknown keys and types are
//! checked against [`KEYS`] before serde (with `deny_unknown_fields`) reads the file.

use std::path::{Path, PathBuf};

use glam::Vec3;
use serde::Deserialize;

use crate::heightmap::{Channel, EdgeMode, HeightMap, LoadOptions};
use crate::scene::{Camera, MeshSource, NormalMap, Rgba8Image, Scene, View};

/// The keys of a scene file with the type each holds: `number`, `string`, `table` or
/// `array of 3 numbers`.
pub(crate) const KEYS: &[(&str, &str)] = &[
    ("name", "string"),
    ("height_map", "table"),
    ("height_map.path", "string"),
    ("height_map.channel", "string"),
    ("height_map.white", "string"),
    ("depth_scale", "number"),
    ("tiling", "number"),
    ("edge", "string"),
    ("camera", "table"),
    ("camera.angle", "number"),
    ("camera.azimuth", "number"),
    ("camera.distance", "number"),
    ("camera.fov", "number"),
    ("camera.target", "array of 3 numbers"),
    ("light", "array of 3 numbers"),
    ("albedo", "string"),
    ("normal_map", "string"),
    ("normal_green", "string"),
    ("lod", "string"),
    ("view", "string"),
    ("mesh", "table"),
    ("mesh.builtin", "string"),
    ("mesh.path", "string"),
    ("mesh.name", "string"),
];

/// Why a scene file could not be read. Displays as one line: `FILE: key `KEY`: MESSAGE`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}: {}{message}", path.display(), key.as_ref().map(|k| format!("key `{k}`: ")).unwrap_or_default())]
pub struct SceneFileError {
    /// The scene file (`.toml`), also when the fault is in a file it names.
    pub path: PathBuf,
    /// The dotted key at fault (`camera.angle`), if the error is about one.
    pub key: Option<String>,
    /// What is wrong; the display puts the path and key in front of it.
    pub message: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileSpec {
    name: Option<String>,
    height_map: HeightSpec,
    depth_scale: Option<f32>,
    tiling: Option<f32>,
    edge: Option<String>,
    camera: Option<CameraSpec>,
    light: Option<[f32; 3]>,
    albedo: Option<String>,
    normal_map: Option<String>,
    normal_green: Option<String>,
    lod: Option<String>,
    view: Option<String>,
    mesh: Option<MeshSpec>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MeshSpec {
    builtin: Option<String>,
    path: Option<String>,
    name: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct HeightSpec {
    path: String,
    channel: Option<String>,
    white: Option<String>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct CameraSpec {
    angle: Option<f32>,
    azimuth: Option<f32>,
    distance: Option<f32>,
    fov: Option<f32>,
    target: Option<[f32; 3]>,
}

/// The TOML table of the file at `path` (a scene or a room file): a missing or unreadable file
/// and TOML that does not parse (with the line it fails at) are errors naming the file.
pub(crate) fn read_toml_table(path: &Path) -> Result<toml::Table, SceneFileError> {
    let err = |message: String| SceneFileError { path: path.to_path_buf(), key: None, message };
    if !path.exists() {
        return Err(err("file not found".into()));
    }
    let text = crate::io::read_regular_to_string(path).map_err(|e| err(format!("cannot read: {e}")))?;
    text.parse().map_err(|e: toml::de::Error| {
        let line = e.span().map(|s| text[..s.start.min(text.len())].lines().count().max(1));
        let at = line.map(|l| format!(" at line {l}")).unwrap_or_default();
        err(format!("not valid TOML{at}: {}", e.message().trim().replace('\n', " ")))
    })
}

/// Reads a scene file (see the module docs).
pub fn load_scene_file(path: &Path) -> Result<Scene, SceneFileError> {
    let err = |key: Option<&str>, message: String| SceneFileError {
        path: path.to_path_buf(),
        key: key.map(str::to_string),
        message,
    };
    let table = read_toml_table(path)?;
    check_keys(&table).map_err(|(k, m)| err(Some(&k), m))?;
    let spec: FileSpec = FileSpec::deserialize(toml::Value::Table(table))
        .map_err(|e| err(None, e.message().trim().replace('\n', " ")))?;
    build(path, spec).map_err(|(k, m)| err(Some(k), m))
}

/// Checks the scene file's keys ([`KEYS`], [`check_toml_keys`]) and the two it requires.
fn check_keys(t: &toml::Table) -> Result<(), (String, String)> {
    match t.get("height_map") {
        None => {
            return Err((
                "height_map".into(),
                "missing (a scene file needs `[height_map]` with `path = \"...\"`)".into(),
            ))
        }
        Some(toml::Value::Table(h)) if !h.contains_key("path") => {
            return Err((
                "height_map.path".into(),
                "missing (the height map's file, relative to the scene file)".into(),
            ))
        }
        _ => {}
    }
    check_toml_keys(t, "", KEYS, &|k| k.to_string())
}

/// Checks every key of the TOML table `t` (under the dotted `prefix`, "" at the top) against
/// `keys` (dotted names and the type each holds; `pattern` maps a key to its entry there, as
/// a room file maps a wall's name to `*`): an unknown key is named with the nearest known one
/// beside it, a wrong type with what it found. Recurses into tables. Scene and room files
/// share it.
pub(crate) fn check_toml_keys(
    t: &toml::Table,
    prefix: &str,
    keys: &[(&str, &str)],
    pattern: &dyn Fn(&str) -> String,
) -> Result<(), (String, String)> {
    for (k, v) in t {
        let full = if prefix.is_empty() { k.clone() } else { format!("{prefix}.{k}") };
        let Some((_, ty)) = keys.iter().find(|(n, _)| *n == pattern(&full)) else {
            // The known keys beside this one, named under the actual prefix.
            let here = pattern(prefix);
            let siblings: Vec<String> = keys
                .iter()
                .filter_map(|(n, _)| {
                    let (parent, last) = n.rsplit_once('.').unwrap_or(("", n));
                    (parent == here)
                        .then(|| if prefix.is_empty() { last.to_string() } else { format!("{prefix}.{last}") })
                })
                .collect();
            let near = relief_dsl::spec::suggest::nearest(&full, siblings.iter().map(|s| s.as_str()))
                .map(|n| format!(" (did you mean `{n}`?)"))
                .unwrap_or_default();
            return Err((full, format!("unknown key{near}; known keys here: {}", siblings.join(", "))));
        };
        let ok = match *ty {
            "number" => v.is_integer() || v.is_float(),
            "string" => v.is_str(),
            "table" => v.is_table(),
            _ => v.as_array().is_some_and(|a| a.len() == 3 && a.iter().all(|x| x.is_integer() || x.is_float())),
        };
        if !ok {
            return Err((full, format!("expected {ty}, found {}", describe(v))));
        }
        if let Some(sub) = v.as_table() {
            check_toml_keys(sub, &full, keys, pattern)?;
        }
    }
    Ok(())
}

fn describe(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) => format!("the string \"{s}\""),
        toml::Value::Integer(i) => format!("the integer {i}"),
        toml::Value::Float(f) => format!("the number {f}"),
        toml::Value::Boolean(b) => format!("the boolean {b}"),
        toml::Value::Datetime(d) => format!("the date {d}"),
        toml::Value::Array(a) => format!("an array of {} values", a.len()),
        toml::Value::Table(_) => "a table".into(),
    }
}

type KeyError = (&'static str, String);

fn build(path: &Path, f: FileSpec) -> Result<Scene, KeyError> {
    let dir = path.parent().unwrap_or(Path::new("."));
    let channel = match f.height_map.channel.as_deref() {
        None | Some("luma") => None,
        Some(c) => Some(
            c.parse::<Channel>()
                .map_err(|_| ("height_map.channel", format!("`{c}` is not a channel (expected r, g, b, a or luma)")))?,
        ),
    };
    let depth = match f.height_map.white.as_deref() {
        None | Some("height") => false,
        Some("depth") => true,
        Some(o) => {
            return Err((
                "height_map.white",
                format!("`{o}`: expected `height` (white is the top) or `depth` (white is deep)"),
            ))
        }
    };
    let lod = match f.lod.as_deref() {
        None => None,
        // The pipeline parser reads the word, so a scene and a pipeline accept the same.
        Some(l) => Some(
            format!("none+lod={l}")
                .parse::<relief_dsl::Pipeline>()
                .map_err(|e| ("lod", format!("`{l}`: expected zero, auto or level(k) ({})", e.message)))?
                .lod,
        ),
    };
    let hpath = dir.join(&f.height_map.path);
    let hm =
        HeightMap::load(&hpath, &LoadOptions { channel, depth }).map_err(|e| ("height_map.path", e.to_string()))?;
    let name = f
        .name
        .clone()
        .unwrap_or_else(|| path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default());
    let mut s = Scene::from_height_map(name, hm);
    s.lod = lod;
    if let Some(t) = f.tiling {
        check_tiling(t).map_err(|m| ("tiling", m))?;
        s = s.with_tiling(t);
    }
    if let Some(v) = &f.view {
        View::parse(v).map_err(|m| ("view", m))?.apply(&mut s);
        if lod.is_some() {
            s.lod = lod;
        }
    }
    if let Some(d) = f.depth_scale {
        check_depth_scale(d).map_err(|m| ("depth_scale", m))?;
        s.depth_scale = d;
    }
    s.edge = match f.edge.as_deref() {
        None | Some("repeat") => EdgeMode::Repeat,
        Some("clamp") => EdgeMode::Clamp,
        Some(o) => return Err(("edge", format!("`{o}`: expected `repeat` or `clamp`"))),
    };
    if let Some(m) = &f.mesh {
        s.mesh = Some(mesh_source(dir, m)?);
        // A mesh scene looks at the origin from 3 units away unless its camera keys say
        // otherwise (docs/meshes.md: built-in meshes are about one unit across, at the origin).
        s.camera.target = Vec3::ZERO;
        s.camera.distance = 3.0;
    }
    let c = f.camera.unwrap_or_default();
    if let Some(t) = c.target {
        let v = Vec3::from(t);
        if !v.is_finite() {
            return Err(("camera.target", format!("{t:?}: must be a finite point")));
        }
        s.camera.target = v;
    }
    if let Some(a) = c.angle {
        check_angle(a).map_err(|m| ("camera.angle", m))?;
        s.camera.angle_deg = a;
    }
    if let Some(a) = c.azimuth {
        check_azimuth(a).map_err(|m| ("camera.azimuth", m))?;
        s.camera.azimuth_deg = a;
    }
    if let Some(d) = c.distance {
        if !(d.is_finite() && d > 0.0) {
            return Err(("camera.distance", format!("{d}: must be a positive number")));
        }
        s.camera.distance = d;
    }
    if let Some(v) = c.fov {
        if !(v.is_finite() && v > 0.0 && v < 180.0) {
            return Err(("camera.fov", format!("{v}: must lie in (0, 180) degrees")));
        }
        s.camera.fov_deg = v;
    }
    if let Some(l) = f.light {
        let v = Vec3::from(l);
        if !(v.is_finite() && v.length() > 1e-6) {
            return Err(("light", format!("{l:?}: must be a finite, non-zero direction")));
        }
        s.light_dir = v.normalize();
    }
    if let Some(a) = &f.albedo {
        s.albedo = Some(load_albedo(&dir.join(a)).map_err(|m| ("albedo", m))?);
    }
    let green_up = match f.normal_green.as_deref() {
        None | Some("up") => true,
        Some("down") => false,
        Some(o) => {
            return Err((
                "normal_green",
                format!("`{o}`: expected `up` (green towards the image's top, −v) or `down` (+v)"),
            ))
        }
    };
    if let Some(n) = &f.normal_map {
        s.normal = Some(load_normal_map(&dir.join(n), green_up).map_err(|m| ("normal_map", m))?);
    }
    Ok(s)
}

/// The built-in meshes a scene's `mesh.builtin` may name (built by `crate::mesh::builtin`).
pub(crate) const BUILTIN_MESHES: &[&str] = &["sphere", "cylinder", "torus"];

/// The `[mesh]` table as a [`MeshSource`]: exactly one of `builtin` and `path`; `name` only
/// with a file (it picks one of the file's meshes).
fn mesh_source(dir: &Path, m: &MeshSpec) -> Result<MeshSource, KeyError> {
    match (&m.builtin, &m.path) {
        (Some(b), None) => {
            if m.name.is_some() {
                return Err(("mesh.name", "names one mesh of a file: it needs `mesh.path`, not `mesh.builtin`".into()));
            }
            if !BUILTIN_MESHES.contains(&b.as_str()) {
                return Err(("mesh.builtin", format!("`{b}`: expected one of {}", BUILTIN_MESHES.join(", "))));
            }
            Ok(MeshSource::Builtin(b.clone()))
        }
        (None, Some(p)) => Ok(MeshSource::File { path: dir.join(p), name: m.name.clone() }),
        _ => Err(("mesh", "needs exactly one of `builtin = \"sphere\"` and `path = \"mesh.glb\"`".into())),
    }
}

/// The largest depth scale accepted: a relief MAX_DEPTH_SCALE times as deep as its texture
/// is wide. Papers use 0.02 to 0.3; far deeper, a ray crosses so many texels that the exact
/// reference cannot end its traversal (1e30 did not, after seconds), so such a value is
/// refused before any work.
pub(crate) const MAX_DEPTH_SCALE: f32 = 10.0;

/// The largest tiling accepted (repeats across the quad), for the same reason.
pub(crate) const MAX_TILING: f32 = 1000.0;

/// A depth scale in (0, [`MAX_DEPTH_SCALE`]], or the message naming the range.
pub(crate) fn check_depth_scale(d: f32) -> Result<(), String> {
    if d.is_finite() && d > 0.0 && d <= MAX_DEPTH_SCALE {
        Ok(())
    } else {
        Err(format!(
            "{d}: must be a positive number at most {MAX_DEPTH_SCALE} (allowed 0 < depth scale <= {MAX_DEPTH_SCALE})"
        ))
    }
}

/// A tiling in (0, [`MAX_TILING`]], or the message naming the range.
pub(crate) fn check_tiling(t: f32) -> Result<(), String> {
    if t.is_finite() && t > 0.0 && t <= MAX_TILING {
        Ok(())
    } else {
        Err(format!("{t}: must be a positive number at most {MAX_TILING} (allowed 0 < tiling <= {MAX_TILING})"))
    }
}

fn check_angle(a: f32) -> Result<(), String> {
    if (0.0..90.0).contains(&a) {
        Ok(())
    } else {
        Err(format!("{a} is out of range: allowed 0 <= angle < 90 degrees from the normal"))
    }
}

fn check_azimuth(a: f32) -> Result<(), String> {
    if a.is_finite() {
        Ok(())
    } else {
        Err(format!("{a}: must be a finite number of degrees"))
    }
}

fn open_rgba(path: &Path) -> Result<image::RgbaImage, String> {
    if !path.exists() {
        return Err(format!("{}: file not found", path.display()));
    }
    let img = crate::io::open_image(path)?;
    Ok(img.to_rgba8())
}

fn load_albedo(path: &Path) -> Result<Rgba8Image, String> {
    let img = open_rgba(path)?;
    Ok(Rgba8Image { width: img.width() as usize, height: img.height() as usize, rgba: img.into_raw() })
}

/// Tangent-space normals from RGBA8 texels: c = 2·rgb/255 − 1, red along +u, blue up, green
/// towards the top of the image (−v, `green_up`, the POM sample's maps and most tools') or
/// towards the bottom (+v); renormalised (a zero vector becomes +z).
pub(crate) fn rgb_to_normals(rgba: &[u8], green_up: bool) -> Vec<[f32; 3]> {
    let gy = if green_up { -1.0 } else { 1.0 };
    rgba.chunks_exact(4)
        .map(|p| {
            let c = |v: u8| 2.0 * v as f32 / 255.0 - 1.0;
            Vec3::new(c(p[0]), gy * c(p[1]), c(p[2])).normalize_or(Vec3::Z).to_array()
        })
        .collect()
}

/// A tangent-space normal map from an image's RGB, see [`rgb_to_normals`].
pub(crate) fn load_normal_map(path: &Path, green_up: bool) -> Result<NormalMap, String> {
    let img = open_rgba(path)?;
    let (width, height) = (img.width() as usize, img.height() as usize);
    Ok(NormalMap { width, height, data: rgb_to_normals(img.as_raw(), green_up) })
}

/// Command-line overrides of a scene (`--view`, `--depth-scale`, `--tiling`, `--angle`,
/// `--azimuth`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Overrides {
    /// `--view`: a named view ([`View`]), applied before the other overrides (which win).
    /// `None`: the scene's own.
    pub view: Option<View>,
    /// `--depth-scale`: the relief depth in texture units, > 0. `None`: keep the scene's.
    pub depth_scale: Option<f32>,
    /// `--tiling`: repeats across the quad, > 0; re-centres the camera. `None`: keep it.
    pub tiling: Option<f32>,
    /// `--angle`: the camera's angle from the surface normal, degrees, in [0, 90).
    /// `None`: keep it.
    pub angle: Option<f32>,
    /// `--azimuth`: the camera's azimuth, degrees, any finite value. `None`: keep it.
    pub azimuth: Option<f32>,
}

impl Overrides {
    /// Whether no override is set.
    pub fn is_empty(&self) -> bool {
        *self == Overrides::default()
    }

    /// Checks the values: 0 < depth scale <= `MAX_DEPTH_SCALE`, 0 < tiling <= `MAX_TILING`,
    /// 0 <= angle < 90, azimuth finite.
    /// Errors name the flag.
    pub fn check(&self) -> Result<(), String> {
        if let Some(d) = self.depth_scale {
            check_depth_scale(d).map_err(|m| format!("--depth-scale {m}"))?;
        }
        if let Some(t) = self.tiling {
            check_tiling(t).map_err(|m| format!("--tiling {m}"))?;
        }
        if let Some(a) = self.angle {
            check_angle(a).map_err(|m| format!("--angle {m}"))?;
        }
        if let Some(a) = self.azimuth {
            check_azimuth(a).map_err(|m| format!("--azimuth {m}"))?;
        }
        Ok(())
    }

    /// The suffix a scene's name gets when overridden, e.g. `@depth_scale=0.05,angle=60`
    /// (empty without overrides), so that results on an overridden scene keep their own name.
    pub fn suffix(&self) -> String {
        let view = self.view.map(|v| format!("view={}", v.name()));
        let parts: Vec<String> = view
            .into_iter()
            .chain(
                [
                    ("depth_scale", self.depth_scale),
                    ("tiling", self.tiling),
                    ("angle", self.angle),
                    ("azimuth", self.azimuth),
                ]
                .iter()
                .filter_map(|(k, v)| v.map(|v| format!("{k}={v}"))),
            )
            .collect();
        if parts.is_empty() {
            String::new()
        } else {
            format!("@{}", parts.join(","))
        }
    }

    /// Reads an override list as [`Overrides::suffix`] writes it, without the `@`
    /// (`angle=70`, `depth_scale=0.05,angle=60`): its inverse. Values are not range-checked
    /// here ([`Overrides::check`] does that). Errors name the bad part.
    pub(crate) fn parse_suffix(text: &str) -> Result<Overrides, String> {
        let mut o = Overrides::default();
        for part in text.split(',') {
            let (k, v) = part.split_once('=').ok_or_else(|| format!("`{part}` is not KEY=VALUE"))?;
            if k.trim() == "view" {
                if o.view.replace(View::parse(v.trim())?).is_some() {
                    return Err("`view` is given twice".into());
                }
                continue;
            }
            let v: f32 = v.trim().parse().map_err(|_| format!("`{part}`: `{v}` is not a number"))?;
            let slot = match k.trim() {
                "depth_scale" => &mut o.depth_scale,
                "tiling" => &mut o.tiling,
                "angle" => &mut o.angle,
                "azimuth" => &mut o.azimuth,
                other => {
                    return Err(format!("`{other}` is not a view key (view, depth_scale, tiling, angle, azimuth)"))
                }
            };
            if slot.replace(v).is_some() {
                return Err(format!("`{}` is given twice", k.trim()));
            }
        }
        Ok(o)
    }

    /// The keys both `self` and `other` set (`angle`, …; a named view sets `depth_scale` and
    /// `angle`), for refusing one that would silently replace the other.
    pub(crate) fn shared_keys(&self, other: &Overrides) -> Vec<&'static str> {
        // A named view sets the depth scale and the angle too.
        let depth = |o: &Overrides| o.depth_scale.is_some() || o.view.is_some();
        let angle = |o: &Overrides| o.angle.is_some() || o.view.is_some();
        let pairs = [
            ("view", self.view.is_some() && other.view.is_some()),
            ("depth_scale", depth(self) && depth(other)),
            ("tiling", self.tiling.is_some() && other.tiling.is_some()),
            ("angle", angle(self) && angle(other)),
            ("azimuth", self.azimuth.is_some() && other.azimuth.is_some()),
        ];
        pairs.iter().filter(|(_, both)| *both).map(|(k, _)| *k).collect()
    }

    /// Applies the overrides: tiling first (with `Scene::with_tiling`), then the named view,
    /// then depth scale, angle and azimuth; appends [`Overrides::suffix`] to the name. Call
    /// [`Overrides::check`] first.
    pub fn apply(&self, mut s: Scene) -> Scene {
        if let Some(t) = self.tiling {
            s = s.with_tiling(t);
        }
        if let Some(v) = self.view {
            v.apply(&mut s);
        }
        if let Some(d) = self.depth_scale {
            s.depth_scale = d;
        }
        if let Some(a) = self.angle {
            s.camera.angle_deg = a;
        }
        if let Some(a) = self.azimuth {
            s.camera.azimuth_deg = a;
        }
        s.name += &self.suffix();
        s
    }
}

/// A scene argument with a view (`rocks@angle=70`, the name results give a scene measured
/// with `--angle 70`): the argument before the last `@` and the override list after it.
/// `None` when there is no `@` or what follows does not read as an override list (a file
/// name with an `@` in it is then a file name); an override list with a bad value is `Some`
/// with the error.
pub(crate) fn split_view(arg: &str) -> Option<(&str, Result<Overrides, String>)> {
    let (base, view) = arg.rsplit_once('@')?;
    let keys = ["view=", "depth_scale=", "tiling=", "angle=", "azimuth="];
    if base.is_empty() || !view.split(',').all(|p| keys.iter().any(|k| p.trim_start().starts_with(k))) {
        return None;
    }
    Some((base, Overrides::parse_suffix(view).and_then(|o| o.check().map(|()| o))))
}

/// The camera's fields as written into `metrics.json` by `relief render`.
pub fn camera_json(c: &Camera) -> serde_json::Value {
    serde_json::json!({
        "angle_deg": c.angle_deg,
        "azimuth_deg": c.azimuth_deg,
        "distance": c.distance,
        "fov_deg": c.fov_deg,
    })
}
