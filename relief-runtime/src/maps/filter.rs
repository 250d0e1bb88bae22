//! 3×3 neighbourhood filters over maps.
//!
//! A shader that samples a cone map bilinearly at `x` gets a blend of the four texels around
//! `x`, which can be wider than the narrowest of them (Burger 2018 §4.3.1, Fig. 4.6). After
//! [`min3x3`] every texel holds the minimum of its 3×3 neighbourhood, and each of the four
//! texels around `x` has all four in its neighbourhood, so the blend is at most the smallest
//! of the four original values: linear filtering then never widens a cone beyond the
//! narrowest cone of the cell.
//!

use super::Map;
use crate::heightmap::EdgeMode;

/// Every texel (each channel, each slice) replaced by the minimum over its 3×3 neighbourhood,
/// neighbours resolved with `edge`. See the module docs for why.
pub fn min3x3(map: &Map, edge: EdgeMode) -> Map {
    filter3x3(map, edge, f32::min)
}

/// Every texel replaced by the maximum over its 3×3 neighbourhood (for maps that round up).
pub fn max3x3(map: &Map, edge: EdgeMode) -> Map {
    filter3x3(map, edge, f32::max)
}

fn filter3x3(map: &Map, edge: EdgeMode, f: fn(f32, f32) -> f32) -> Map {
    let (w, h, c) = (map.width, map.height, map.channels);
    let mut data = map.data.clone();
    for k in 0..map.depth {
        let base = k * w * h * c;
        for y in 0..h as i64 {
            for x in 0..w as i64 {
                for ch in 0..c {
                    let mut v = map.data[base + ((y as usize) * w + x as usize) * c + ch];
                    for dy in -1..=1 {
                        for dx in -1..=1 {
                            let xi = edge.index(x + dx, w);
                            let yi = edge.index(y + dy, h);
                            v = f(v, map.data[base + (yi * w + xi) * c + ch]);
                        }
                    }
                    data[base + ((y as usize) * w + x as usize) * c + ch] = v;
                }
            }
        }
    }
    Map { data, mips: Vec::new(), ..map.clone_shape() }
}
