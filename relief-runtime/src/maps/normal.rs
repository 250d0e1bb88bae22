//! The normal map of a height map, for scenes that bring none.

use crate::heightmap::{EdgeMode, HeightMap};

/// Unit normals of the surface z = `depth_scale` · h(u, v) (texture units) by central
/// differences, one per texel, row-major; neighbours resolved with `edge`.
pub(crate) fn derived_normals(m: &HeightMap, depth_scale: f32, edge: EdgeMode) -> Vec<[f32; 3]> {
    let (w, h) = (m.width as i64, m.height as i64);
    let mut out = Vec::with_capacity(m.data.len());
    for y in 0..h {
        for x in 0..w {
            let dx = (m.texel(x + 1, y, edge) - m.texel(x - 1, y, edge)) * depth_scale * w as f32 / 2.0;
            let dy = (m.texel(x, y + 1, edge) - m.texel(x, y - 1, edge)) * depth_scale * h as f32 / 2.0;
            let n = glam::Vec3::new(-dx, -dy, 1.0).normalize();
            out.push(n.to_array());
        }
    }
    out
}
