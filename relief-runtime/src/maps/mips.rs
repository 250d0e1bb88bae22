//! Mip chains: the one filter behind every level relief uploads (height map, normal map,
//! albedo), so that the levels the shaders sample under `lod=level(k)` and `lod=auto` and the
//! levels the exact reference intersects are the same texels.
//!
//! **Filter.** A 2×2 box: texel (x, y) of level k + 1 is the mean of texels (2x, 2y),
//! (2x + 1, 2y), (2x, 2y + 1), (2x + 1, 2y + 1) of level k, each channel on its own, in the
//! values as stored (heights; normal vectors before encoding, not renormalized: the shaders
//! normalize after decoding; albedo in its sRGB-encoded bytes). A side of 1 stays 1 and
//! averages over the other side only (a 4×1 map has levels 4×1, 2×1, 1×1).
//!
//! **Sizes.** A level is made only while every side is even or 1, so that each texel of the
//! next level covers exactly a 2×2 (or 2×1) block and the level's texel centres stay where a
//! sampler puts them (texel x of a level of width w at u = (x + ½)/w). Power-of-two maps get
//! the full chain down to 1×1; a map with an odd side stops early: a 96×96 map has levels 96,
//! 48, 24, 12, 6, 3 (six levels), a 100×100 map 100, 50, 25. The number of levels is the
//! chain's length on the device too, so `lod=auto` clamps to the same last level on both.

/// One level: `width × height` texels of `channels` values each, row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct Level {
    /// Texels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// `width * height * channels` values, channels interleaved, row y = v.
    pub data: Vec<f32>,
}

/// The number of levels of a `width × height` map under the rule above (level 0 included).
pub(crate) fn level_count(width: usize, height: usize) -> usize {
    let (mut w, mut h, mut n) = (width, height, 1);
    while (w > 1 || h > 1) && (w == 1 || w % 2 == 0) && (h == 1 || h % 2 == 0) {
        w = (w / 2).max(1);
        h = (h / 2).max(1);
        n += 1;
    }
    n
}

/// The chain of a map, level 0 (a copy of `data`) first; see the module docs.
pub(crate) fn box_chain(width: usize, height: usize, channels: usize, data: &[f32]) -> Vec<Level> {
    assert_eq!(data.len(), width * height * channels, "map data has the wrong length");
    let mut out = vec![Level { width, height, data: data.to_vec() }];
    for _ in 1..level_count(width, height) {
        let prev = out.last().expect("level 0 is there");
        let (w, h) = ((prev.width / 2).max(1), (prev.height / 2).max(1));
        let (sx, sy) = (if prev.width > 1 { 2 } else { 1 }, if prev.height > 1 { 2 } else { 1 });
        let weight = 1.0 / (sx * sy) as f32;
        let mut next = vec![0.0f32; w * h * channels];
        for y in 0..h {
            for x in 0..w {
                for c in 0..channels {
                    let mut sum = 0.0f32;
                    for j in 0..sy {
                        for i in 0..sx {
                            sum += prev.data[((sy * y + j) * prev.width + sx * x + i) * channels + c];
                        }
                    }
                    next[(y * w + x) * channels + c] = sum * weight;
                }
            }
        }
        out.push(Level { width: w, height: h, data: next });
    }
    out
}

/// The mip chain of a height map, level 0 (a copy) first, by `box_chain` (2×2 box; the
/// chain stops before a level with an odd side).
pub fn height_chain(map: &crate::heightmap::HeightMap) -> Vec<crate::heightmap::HeightMap> {
    box_chain(map.width, map.height, 1, &map.data)
        .into_iter()
        .map(|l| crate::heightmap::HeightMap::new(l.width, l.height, l.data))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_average_blocks_and_stop_at_odd_sides() {
        assert_eq!(level_count(256, 256), 9);
        assert_eq!(level_count(256, 64), 9);
        assert_eq!(level_count(96, 96), 6);
        assert_eq!(level_count(100, 100), 3);
        assert_eq!(level_count(1, 1), 1);
        assert_eq!(level_count(7, 8), 1);
        // A 4×2 map of two channels: each texel of level 1 is the mean of its 2×2 block.
        let data: Vec<f32> = (0..16).map(|i| i as f32).collect();
        let chain = box_chain(4, 2, 2, &data);
        assert_eq!(chain.len(), 3);
        let at = |x: usize, y: usize, c: usize| data[(y * 4 + x) * 2 + c];
        for c in 0..2 {
            for x in 0..2 {
                let mean = (at(2 * x, 0, c) + at(2 * x + 1, 0, c) + at(2 * x, 1, c) + at(2 * x + 1, 1, c)) / 4.0;
                assert_eq!(chain[1].data[x * 2 + c], mean);
            }
            // The 2×1 level averages its pair: the mean of all eight texels.
            let all: f32 =
                (0..4).flat_map(|x| (0..2).map(move |y| (x, y))).map(|(x, y)| at(x, y, c)).sum::<f32>() / 8.0;
            assert_eq!(chain[2].data[c], all);
        }
        assert_eq!((chain[2].width, chain[2].height), (1, 1));
    }
}
