//! Map files, format chosen by extension; the formats themselves are in [`crate::io`].
//!
//! - `.png`: unorm8 or unorm16, 1 channel (gray), 2 (gray+alpha), 3 (RGB) or 4 (RGBA); 2D only.
//! - `.exr`: f32 or f16 (decoded to f32), written as RGB (1 channel replicated; 2 channels with
//!   B = 0) or RGBA; 2D only.
//! - `.npy`: NumPy format version 1.0, little-endian `float32` (`<f4`), C order, the decoded
//!   values (what a shader reads); shape `[h, w]`, `[h, w, c]` (c > 1), and `[d, h, w]` /
//!   `[d, h, w, c]` for 3D maps. Row 0 is v = 0. The same format is the raw float *input*
//!   for height maps (`crate::heightmap::HeightMap::from_npy_bytes`).

use std::path::Path;

use super::encode::{EncodedMap, Format};
use super::MapError;
use crate::io;

/// Writes an encoded map to `path`, format chosen by extension (see the module docs).
pub fn write_map(path: &Path, map: &EncodedMap) -> Result<(), MapError> {
    let ext = path.extension().and_then(|e| e.to_str()).map(|e| e.to_ascii_lowercase()).unwrap_or_default();
    let bad = |message: String| MapError::Output { path: path.to_path_buf(), message };
    let (w, h, c) = (map.width, map.height, map.channels);
    match ext.as_str() {
        "npy" => {
            let dec = map.decode();
            let mut shape = Vec::new();
            if map.depth > 1 {
                shape.push(map.depth);
            }
            shape.extend([h, w]);
            if c > 1 {
                shape.push(c);
            }
            std::fs::write(path, io::npy::npy_bytes(&shape, &dec.data))
                .map_err(|source| MapError::Io { path: path.to_path_buf(), source })
        }
        "png" => {
            if map.depth > 1 {
                return Err(bad("a 3D map cannot be written as .png; use .npy".into()));
            }
            let sixteen_bit = match map.encoding.format {
                Format::Unorm8 => false,
                Format::Unorm16 => true,
                f => {
                    return Err(bad(format!(
                        "{f:?} cannot be written as .png; use --encoding unorm8 or unorm16, or .exr/.npy"
                    )))
                }
            };
            io::png::write_unorm(path, w, h, c, sixteen_bit, &map.bytes).map_err(bad)
        }
        "exr" => {
            if map.depth > 1 {
                return Err(bad("a 3D map cannot be written as .exr; use .npy".into()));
            }
            if !matches!(map.encoding.format, Format::F32 | Format::F16) {
                return Err(bad("unorm encodings cannot be written as .exr; use .png".into()));
            }
            io::exr::write(path, w, h, c, &map.decode().data).map_err(bad)
        }
        _ => Err(bad("unknown output extension (expected .png, .exr or .npy)".into())),
    }
}
