//! OpenEXR files: f32 pixels, written as RGB (1 channel replicated, 2 channels with B = 0)
//! or RGBA, as one part of *scanline* blocks (ZIP, 16 lines a block, increasing line order),
//! not tiles: Babylon.js's and three.js's EXR loaders read scanline images only (image 0.25's
//! writer, used before, wrote 64×64 tiles).
//!
//! Row order: file row 0 (the first scanline, the top of the image as viewers show it) is
//! the map's row 0, texture coordinate v = 0 (relief's texture space; a WebGL upload without
//! `UNPACK_FLIP_Y` puts it at v = 0, an engine that flips images on load, as Babylon.js does,
//! must not flip this one).
//!
//! ```no_run
//! use relief_runtime::io::exr;
//! // A 2×1 two-channel map: (ratio, apex) per texel; B is written as 0.
//! exr::write(std::path::Path::new("cells.exr"), 2, 1, 2, &[0.5, 1.0, 0.25, 0.75]).unwrap();
//! ```

use std::path::Path;

use ::exr::prelude::{Encoding, Image, Layer, LayerAttributes, SpecificChannels, Vec2, WritableImage};

/// Writes `w × h` pixels of `channels` (1 to 4) interleaved f32 values as `.exr` (scanlines).
pub fn write(path: &Path, w: usize, h: usize, channels: usize, values: &[f32]) -> Result<(), String> {
    let c = channels;
    if !(1..=4).contains(&c) {
        return Err(format!("{c} channels do not fit an .exr (1 to 4); use .npy"));
    }
    if values.len() != w * h * c {
        return Err(format!("{} values for {w}×{h}×{c}: buffer size", values.len()));
    }
    let at = move |Vec2(x, y): Vec2<usize>| -> [f32; 4] {
        let s = &values[(y * w + x) * c..(y * w + x + 1) * c];
        match c {
            1 => [s[0], s[0], s[0], 1.0],
            2 => [s[0], s[1], 0.0, 1.0],
            3 => [s[0], s[1], s[2], 1.0],
            _ => [s[0], s[1], s[2], s[3]],
        }
    };
    let encoding = Encoding::SMALL_LOSSLESS;
    let result = if c == 4 {
        let layer = Layer::new(
            (w, h),
            LayerAttributes::default(),
            encoding,
            SpecificChannels::rgba(|p: Vec2<usize>| {
                let v = at(p);
                (v[0], v[1], v[2], v[3])
            }),
        );
        Image::from_layer(layer).write().to_file(path)
    } else {
        let layer = Layer::new(
            (w, h),
            LayerAttributes::default(),
            encoding,
            SpecificChannels::rgb(|p: Vec2<usize>| {
                let v = at(p);
                (v[0], v[1], v[2])
            }),
        );
        Image::from_layer(layer).write().to_file(path)
    };
    result.map_err(|e| e.to_string())
}
