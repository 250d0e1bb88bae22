//! Room files (TOML). Every key is optional; left out, a key takes the built-in room's
//! value (`room:default`, [`super::builtin`]), so a file names only what it changes:
//!
//! ```toml
//! name = "my_room"                 # default: the file's stem
//! size = [2.0, 1.5, 2.0]           # width, height, depth behind the window (world units)
//! ambient = 0.25
//! map_size = 128                   # texels a side of the procedural maps
//! window = "window_opacity.png"    # optional: white = opaque glass, black = clear
//! sun = [0.35, 0.55, 1.0]          # toward the sun outside the window, for `--scatter`
//! sun_intensity = 0.35
//!
//! [camera]
//! position = [1.35, 0.95, 2.6]     # in front of the window (z > 0)
//! target = [1.0, 0.72, -1.0]
//! fov = 42.0                       # vertical, degrees
//!
//! [light]
//! point = [0.7, 1.3, -0.8]         # inside the room; or
//! # direction = [0.2, 1.0, 0.5]    # toward a directional light (not both)
//!
//! [walls.back]                     # back, left, right, floor, ceiling
//! height_map = "bricks.png"        # relative to this file; default: procedural
//! white = "height"                 # height (default) | depth
//! albedo = "bricks_albedo.png"
//! normal_map = "bricks_normal.png" # RGB tangent-space normal, green towards the image's top
//! depth_scale = 0.08               # world units from the wall's plane to height 0
//! ```
//!
//! Errors are one line naming the file and the key (`FILE: key `KEY`: MESSAGE`), as scene
//! files' are ([`crate::scene::file::SceneFileError`], reused).

use std::path::Path;

use glam::Vec3;

use super::{builtin, Room, RoomLight, WALL_NAMES};
use crate::heightmap::{HeightMap, LoadOptions};
use crate::scene::file::{check_toml_keys, load_normal_map, SceneFileError};
use crate::scene::Rgba8Image;

/// The keys of a room file and the type each holds (`*` stands for a wall's name).
pub(crate) const KEYS: &[(&str, &str)] = &[
    ("name", "string"),
    ("size", "array of 3 numbers"),
    ("ambient", "number"),
    ("map_size", "number"),
    ("window", "string"),
    ("sun", "array of 3 numbers"),
    ("sun_intensity", "number"),
    ("camera", "table"),
    ("camera.position", "array of 3 numbers"),
    ("camera.target", "array of 3 numbers"),
    ("camera.fov", "number"),
    ("light", "table"),
    ("light.point", "array of 3 numbers"),
    ("light.direction", "array of 3 numbers"),
    ("walls", "table"),
    ("walls.*", "table"),
    ("walls.*.height_map", "string"),
    ("walls.*.white", "string"),
    ("walls.*.albedo", "string"),
    ("walls.*.normal_map", "string"),
    ("walls.*.depth_scale", "number"),
];

fn pattern_of(full: &str) -> String {
    let parts: Vec<&str> = full.split('.').collect();
    if parts.len() >= 2 && parts[0] == "walls" {
        let mut p = parts.clone();
        p[1] = "*";
        return p.join(".");
    }
    full.to_string()
}

/// Checks the room file's keys ([`KEYS`]); a wall table must be one of [`WALL_NAMES`].
fn check_keys(t: &toml::Table) -> Result<(), (String, String)> {
    if let Some(toml::Value::Table(walls)) = t.get("walls") {
        for k in walls.keys() {
            if !WALL_NAMES.contains(&k.as_str()) {
                let near = relief_dsl::spec::suggest::nearest(k, WALL_NAMES.iter().copied())
                    .map(|n| format!(" (did you mean `{n}`?)"))
                    .unwrap_or_default();
                return Err((format!("walls.{k}"), format!("unknown wall{near}; walls: {}", WALL_NAMES.join(", "))));
            }
        }
    }
    check_toml_keys(t, "", KEYS, &pattern_of)
}

fn num(v: &toml::Value) -> f32 {
    v.as_float().unwrap_or_else(|| v.as_integer().unwrap_or(0) as f64) as f32
}
fn vec3(v: &toml::Value) -> Vec3 {
    let a = v.as_array().expect("checked: an array of 3 numbers");
    Vec3::new(num(&a[0]), num(&a[1]), num(&a[2]))
}

/// Reads a room file (see the module docs); `map_size` overrides the file's `map_size`.
pub fn load_room_file(path: &Path, map_size: Option<usize>) -> Result<Room, SceneFileError> {
    let err = |key: Option<&str>, message: String| SceneFileError {
        path: path.to_path_buf(),
        key: key.map(str::to_string),
        message,
    };
    let t = crate::scene::file::read_toml_table(path)?;
    check_keys(&t).map_err(|(k, m)| err(Some(&k), m))?;
    build(path, &t, map_size).map_err(|(k, m)| err(Some(&k), m))
}

fn build(path: &Path, t: &toml::Table, map_size: Option<usize>) -> Result<Room, (String, String)> {
    let dir = path.parent().unwrap_or(Path::new("."));
    let n = match (map_size, t.get("map_size")) {
        (Some(n), _) => Some(n),
        (None, Some(v)) => {
            let x = num(v);
            if !(x.fract() == 0.0 && (8.0..=4096.0).contains(&x)) {
                return Err(("map_size".into(), format!("{x}: must be a whole number in 8..=4096")));
            }
            Some(x as usize)
        }
        (None, None) => None,
    };
    let mut room = builtin::room("default", n).map_err(|m| ("map_size".to_string(), m))?;
    room.name = match t.get("name") {
        Some(v) => v.as_str().unwrap_or_default().to_string(),
        None => path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default(),
    };
    if let Some(v) = t.get("size") {
        let s = vec3(v);
        room.size = s.to_array();
    }
    if let Some(v) = t.get("ambient") {
        room.ambient = num(v);
    }
    if let Some(v) = t.get("sun") {
        let d = vec3(v);
        if !(d.is_finite() && d.length() > 1e-6) {
            return Err(("sun".into(), format!("{:?}: must be a finite, non-zero direction", d.to_array())));
        }
        room.sun = d.normalize();
    }
    if let Some(v) = t.get("sun_intensity") {
        room.sun_intensity = num(v);
    }
    if let Some(v) = t.get("window") {
        let p = dir.join(v.as_str().unwrap_or_default());
        room.window =
            Some(HeightMap::load(&p, &LoadOptions::default()).map_err(|e| ("window".to_string(), e.to_string()))?);
    }
    if let Some(c) = t.get("camera").and_then(|v| v.as_table()) {
        if let Some(v) = c.get("position") {
            room.camera.position = vec3(v);
        }
        if let Some(v) = c.get("target") {
            room.camera.target = vec3(v);
        }
        if let Some(v) = c.get("fov") {
            room.camera.fov_deg = num(v);
        }
        if (room.camera.target - room.camera.position).length() < 1e-6 {
            return Err(("camera.target".into(), "must differ from camera.position".into()));
        }
    }
    if let Some(l) = t.get("light").and_then(|v| v.as_table()) {
        match (l.get("point"), l.get("direction")) {
            (Some(_), Some(_)) => return Err(("light".into(), "give `point` or `direction`, not both".into())),
            (Some(p), None) => room.light = RoomLight::Point(vec3(p)),
            (None, Some(d)) => {
                let d = vec3(d);
                if !(d.is_finite() && d.length() > 1e-6) {
                    return Err((
                        "light.direction".into(),
                        format!("{:?}: must be a finite, non-zero direction", d.to_array()),
                    ));
                }
                room.light = RoomLight::Directional(d.normalize());
            }
            (None, None) => {
                return Err(("light".into(), "needs `point = [x, y, z]` or `direction = [x, y, z]`".into()))
            }
        }
    }
    if let Some(ws) = t.get("walls").and_then(|v| v.as_table()) {
        for (name, spec) in ws {
            let k = WALL_NAMES.iter().position(|n| n == name).expect("checked: a wall's name");
            let spec = spec.as_table().expect("checked: a table");
            let key = |s: &str| format!("walls.{name}.{s}");
            let wall = &mut room.walls[k];
            let depth = match spec.get("white").and_then(|v| v.as_str()) {
                None | Some("height") => false,
                Some("depth") => true,
                Some(o) => {
                    return Err((
                        key("white"),
                        format!("`{o}`: expected `height` (white is the top) or `depth` (white is deep)"),
                    ))
                }
            };
            if let Some(v) = spec.get("height_map") {
                let p = dir.join(v.as_str().unwrap_or_default());
                wall.height = HeightMap::load(&p, &LoadOptions { channel: None, depth })
                    .map_err(|e| (key("height_map"), e.to_string()))?;
                // A given height map does not match the procedural albedo: neutral grey unless given.
                wall.albedo = None;
            } else if spec.contains_key("white") {
                return Err((key("white"), "given without `height_map`".into()));
            }
            if let Some(v) = spec.get("albedo") {
                let p = dir.join(v.as_str().unwrap_or_default());
                wall.albedo = Some(load_albedo(&p).map_err(|m| (key("albedo"), m))?);
            }
            if let Some(v) = spec.get("normal_map") {
                let p = dir.join(v.as_str().unwrap_or_default());
                wall.normal = Some(load_normal_map(&p, true).map_err(|m| (key("normal_map"), m))?);
            }
            if let Some(v) = spec.get("depth_scale") {
                wall.depth_scale = num(v);
            }
        }
    }
    room.check()?;
    Ok(room)
}

fn load_albedo(path: &Path) -> Result<Rgba8Image, String> {
    if !path.exists() {
        return Err(format!("{}: file not found", path.display()));
    }
    let img = crate::io::open_image(path)?.to_rgba8();
    Ok(Rgba8Image { width: img.width() as usize, height: img.height() as usize, rgba: img.into_raw() })
}
