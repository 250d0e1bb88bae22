//! The built-in procedural room: bricks on the back wall, recessed panels on the side
//! walls, tiles on the floor, coffers in the ceiling. Every map is at height 1 on its
//! border, as Amaro & Gustafsson 2022 (§4) need for the walls to meet.

use glam::Vec3;

use super::{Room, RoomCamera, RoomLight, Wall};
use crate::heightmap::HeightMap;
use crate::scene::Rgba8Image;

/// Texels a side of the procedural maps by default.
pub(crate) const DEFAULT_MAP_SIZE: usize = 128;

/// The built-in rooms.
pub fn names() -> &'static [&'static str] {
    &["default", "deep", "window"]
}

/// Distance in texels from `(x, y)` to the map's nearest border texel.
fn border_distance(n: usize, x: usize, y: usize) -> f32 {
    x.min(y).min(n - 1 - x).min(n - 1 - y) as f32
}

/// `pattern` brought up to height 1 on the border: exactly 1 on the border texels, blended
/// back to the pattern over the next 4 texels.
fn with_border(n: usize, pattern: impl Fn(f32, f32) -> f32) -> HeightMap {
    HeightMap::from_fn(n, n, |x, y| {
        let (u, v) = ((x as f32 + 0.5) / n as f32, (y as f32 + 0.5) / n as f32);
        let b = (1.0 - (border_distance(n, x, y) - 1.0) / 4.0).clamp(0.0, 1.0);
        let h = pattern(u, v).clamp(0.0, 1.0);
        h + (1.0 - h) * b
    })
}

/// A ramp from `lo` at the edge of a cell to `hi` at `width` inside it: bevelled blocks.
fn bevel(dist: f32, width: f32, lo: f32, hi: f32) -> f32 {
    lo + (hi - lo) * (dist / width).clamp(0.0, 1.0)
}

/// Bricks: 8 rows, 4 bricks a row, every other row offset by half a brick; mortar at 0.45.
pub(crate) fn bricks(n: usize) -> HeightMap {
    with_border(n, |u, v| {
        let rows = 8.0;
        let row = (v * rows).floor();
        let fv = v * rows - row;
        let shift = if row as i32 % 2 == 0 { 0.0 } else { 0.5 };
        let fu = (u * 4.0 + shift).fract();
        let d = (fu.min(1.0 - fu) / 4.0).min(fv.min(1.0 - fv) / rows);
        bevel(d, 0.012, 0.45, 0.95)
    })
}

/// Panels: 2 × 3 recessed panels, floor at 0.35, bevels 45°-like.
pub(crate) fn panels(n: usize) -> HeightMap {
    with_border(n, |u, v| {
        let (cu, cv) = ((u * 2.0).fract(), (v * 3.0).fract());
        let d = ((cu.min(1.0 - cu)) / 2.0).min(cv.min(1.0 - cv) / 3.0);
        // The frame between panels is at 1; inside, the panel drops to 0.35.
        1.0 - bevel(d - 0.03, 0.03, 0.0, 0.65)
    })
}

/// Tiles: 6 × 6, grooves at 0.6.
pub fn tiles(n: usize) -> HeightMap {
    with_border(n, |u, v| {
        let (cu, cv) = ((u * 6.0).fract(), (v * 6.0).fract());
        let d = (cu.min(1.0 - cu).min(cv.min(1.0 - cv))) / 6.0;
        bevel(d, 0.01, 0.6, 1.0)
    })
}

/// Coffers: 3 × 3 recessed squares, down to 0.2.
pub(crate) fn coffers(n: usize) -> HeightMap {
    with_border(n, |u, v| {
        let (cu, cv) = ((u * 3.0).fract(), (v * 3.0).fract());
        let d = (cu.min(1.0 - cu).min(cv.min(1.0 - cv))) / 3.0;
        1.0 - bevel(d - 0.02, 0.06, 0.0, 0.8)
    })
}

/// A window's opacity: a frame and a cross of mullions (opaque), faintly frosted glass.
pub fn mullions(n: usize) -> HeightMap {
    HeightMap::from_fn(n, n, |x, y| {
        let (u, v) = ((x as f32 + 0.5) / n as f32, (y as f32 + 0.5) / n as f32);
        let bar = |c: f32, half: f32| (c - 0.5).abs() < half;
        let frame = !(0.03..=0.97).contains(&u) || !(0.03..=0.97).contains(&v);
        if frame || bar(u, 0.015) || bar(v, 0.015) {
            1.0
        } else {
            0.12
        }
    })
}

/// An albedo from a base colour, darker in the recesses.
fn tinted(m: &HeightMap, base: [f32; 3]) -> Rgba8Image {
    let rgba = m
        .data
        .iter()
        .flat_map(|&h| {
            let k = 0.55 + 0.45 * h;
            [base[0], base[1], base[2]]
                .map(|c| (c * k * 255.0).round().clamp(0.0, 255.0) as u8)
                .into_iter()
                .chain([255])
        })
        .collect();
    Rgba8Image { width: m.width, height: m.height, rgba }
}

/// The built-in room `name` ([`names`]) with maps of `map_size` texels a side
/// (`DEFAULT_MAP_SIZE` when `None`).
pub fn room(name: &str, map_size: Option<usize>) -> Result<Room, String> {
    let n = map_size.unwrap_or(DEFAULT_MAP_SIZE);
    if !(8..=4096).contains(&n) {
        return Err(format!("map size {n} is out of range: allowed 8..=4096"));
    }
    let depth = match name {
        "default" | "window" => 0.08,
        "deep" => 0.2,
        other => return Err(format!("unknown room `{other}`; built-in rooms: {}", names().join(", "))),
    };
    let maps = [
        (bricks(n), [0.72, 0.38, 0.28]),
        (panels(n), [0.55, 0.6, 0.52]),
        (panels(n), [0.52, 0.56, 0.62]),
        (tiles(n), [0.62, 0.58, 0.5]),
        (coffers(n), [0.85, 0.83, 0.78]),
    ];
    let walls = maps
        .into_iter()
        .map(|(height, base)| Wall { albedo: Some(tinted(&height, base)), height, normal: None, depth_scale: depth })
        .collect();
    Ok(Room {
        name: format!("room:{name}"),
        size: [2.0, 1.5, 2.0],
        walls,
        window: (name == "window").then(|| mullions(4 * n)),
        camera: RoomCamera { position: Vec3::new(1.35, 0.95, 2.6), target: Vec3::new(1.0, 0.72, -1.0), fov_deg: 42.0 },
        light: RoomLight::Point(Vec3::new(0.7, 1.3, -0.8)),
        ambient: 0.25,
        sun: Vec3::new(0.35, 0.55, 1.0).normalize(),
        sun_intensity: 0.35,
    })
}
