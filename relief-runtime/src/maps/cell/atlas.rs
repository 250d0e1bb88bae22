//! The cell maps of every level of a mip chain in one texture.

use crate::heightmap::{EdgeMode, HeightMap};

/// The cell map `kind` of every level of the height map's mip chain `chain` in one 2D
/// texture, for stages that sample at a level (`lod` other than zero): the levels stacked by
/// rows from level 0 down, each at the left edge, as relief-dsl's `FnBuilder::cell_map_texel`
/// addresses them (the rows above level k are `Σ_{j<k}` of the levels' cell rows). Texels
/// right of a narrower level are 0 and never read. A map of 2 × 2 texels a cell (the quad
/// cone map) stacks its levels the same way in its own texels. An error if a level's cell grid is not
/// the one that addressing assumes (`h_k` rows, `h_k + 1` under clamp).
pub fn level_atlas(
    chain: &[HeightMap],
    kind: crate::maps::MapKind,
    params: &crate::maps::MapParams,
    edge: EdgeMode,
) -> Result<crate::maps::Map, crate::maps::MapError> {
    let levels = chain.iter().map(|h| crate::maps::build(h, kind, params, edge)).collect::<Result<Vec<_>, _>>()?;
    let border = (edge == EdgeMode::Clamp) as usize;
    let k = kind.request_with(params).cell_texels();
    for (h, m) in chain.iter().zip(&levels) {
        if m.height != (h.height + border) * k || m.width != (h.width + border) * k {
            return Err(crate::maps::MapError::Params {
                kind,
                message: format!("a {}×{} level has a {}×{} cell map; the atlas assumes {k}×{k} texels a cell (plus a border under clamp)", h.width, h.height, m.width, m.height),
            });
        }
    }
    let (w, c) = (levels[0].width, levels[0].channels);
    let rows: usize = levels.iter().map(|m| m.height).sum();
    let mut data = vec![0.0f32; w * rows * c];
    let mut row = 0;
    for m in &levels {
        for y in 0..m.height {
            let dst = (row + y) * w * c;
            data[dst..dst + m.width * c].copy_from_slice(&m.data[y * m.width * c..(y + 1) * m.width * c]);
        }
        row += m.height;
    }
    Ok(crate::maps::Map::new_2d(w, rows, c, data))
}
