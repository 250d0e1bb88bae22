//! Procedural height maps (pure functions of the size; all tile seamlessly, edge mode
//! repeat) and the procedural built-in scenes made from them.

use glam::Vec3;

use super::{Rgba8Image, Scene};
use crate::heightmap::HeightMap;

/// The procedural built-in scene `name` at `n × n` texels (its name left empty), or `None`
/// when `name` is not one.
pub(crate) fn scene(name: &str, n: usize) -> Option<Scene> {
    let s = match name {
        "lion" => with_albedo(Scene::from_height_map("", lion(n)), stone_palette),
        "self_shadow" => {
            let mut s = with_albedo(Scene::from_height_map("", self_shadow(n)), sand_palette);
            s.depth_scale = 0.15;
            s.light_dir = Vec3::new(0.8, 0.35, 0.35).normalize();
            s
        }
        "collage" => with_albedo(Scene::from_height_map("", collage(n)), sand_palette),
        "shapes" => {
            let mut s = with_albedo(Scene::from_height_map("", shapes(n)), stone_palette);
            s.depth_scale = 0.08;
            s
        }
        "rock_bump" => with_albedo(Scene::from_height_map("", rock_bump(n)), stone_palette),
        "spikes" => Scene::from_height_map("", spikes(n)),
        "walls" => Scene::from_height_map("", walls(n)),
        "flat0" => Scene::from_height_map("", HeightMap::from_fn(n, n, |_, _| 0.0)),
        "flat1" => Scene::from_height_map("", HeightMap::from_fn(n, n, |_, _| 1.0)),
        "step" => Scene::from_height_map("", step(n)),
        "checker" => Scene::from_height_map("", checker(n)),
        _ => return None,
    };
    Some(s)
}

/// `s` with an albedo coloured by `palette(height, noise)`.
fn with_albedo(mut s: Scene, palette: fn(f32, u32) -> [u8; 3]) -> Scene {
    let m = &s.height;
    let mut rgba = Vec::with_capacity(m.width * m.height * 4);
    for y in 0..m.height {
        for x in 0..m.width {
            let h = m.data[y * m.width + x];
            let [r, g, b] = palette(h, hash2(x as u32, y as u32, 77));
            rgba.extend_from_slice(&[r, g, b, 255]);
        }
    }
    s.albedo = Some(Rgba8Image { width: m.width, height: m.height, rgba });
    s
}

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
pub(crate) fn lion(n: usize) -> HeightMap {
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
pub(crate) fn self_shadow(n: usize) -> HeightMap {
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
pub(crate) fn collage(n: usize) -> HeightMap {
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
pub(crate) fn shapes(n: usize) -> HeightMap {
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
pub(crate) fn rock_bump(n: usize) -> HeightMap {
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
pub(crate) fn spikes(n: usize) -> HeightMap {
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
pub(crate) fn walls(n: usize) -> HeightMap {
    let k = (n / 16).max(4);
    HeightMap::from_fn(n, n, |x, y| if x % k == 0 || y % k == 0 { 1.0 } else { 0.0 })
}

/// Step: 0 for u < 1/2, 1 for u >= 1/2 (with repeat, a second cliff at u = 0).
pub(crate) fn step(n: usize) -> HeightMap {
    HeightMap::from_fn(n, n, |x, _| if 2 * x < n { 0.0 } else { 1.0 })
}

/// Checker: 0/1 squares of side n/8 texels (at least 1).
pub(crate) fn checker(n: usize) -> HeightMap {
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
