//! PNG files: RGBA8 pictures (frames, error maps) and 1–4 channel unorm8/unorm16 maps.

use std::path::Path;

use super::FileError;

/// Writes an RGBA8 image as PNG, atomically ([`super::write_atomic`]): as an indexed image
/// (a palette of at most 256 colours, one byte a pixel) when every pixel is opaque and it has
/// at most 256 colours (the error maps, whose heat scale has `picture::HEAT_LEVELS`
/// steps), else as RGB when every pixel is opaque (frames; the alpha channel would add bytes
/// and nothing else), else RGBA, with adaptive row filters (RGB and the filters were a measured
/// 26 % off the main job's `cells/`, not a tested figure). Read back as RGBA8 it gives the
/// same pixels. Pixels that do not fill `w × h` exactly are a [`FileError::Encode`].
pub fn write_rgba8(path: &Path, w: u32, h: u32, rgba: Vec<u8>) -> Result<(), FileError> {
    use image::codecs::png::{CompressionType, FilterType, PngEncoder};
    use image::ImageEncoder as _;
    let encode = |message: String| FileError::Encode { path: path.to_path_buf(), message };
    if rgba.len() as u64 != u64::from(w) * u64::from(h) * 4 {
        return Err(encode(format!("{} bytes of RGBA8 pixels for a {w}x{h} image", rgba.len())));
    }
    let opaque = rgba.chunks_exact(4).all(|p| p[3] == u8::MAX);
    if opaque {
        if let Some((palette, indices)) = palette_of(&rgba) {
            let bytes = indexed_png(w, h, &palette, &indices).map_err(|e| encode(e.to_string()))?;
            return super::write_atomic(path, &bytes);
        }
    }
    let (pixels, color) = if opaque {
        (rgba.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect(), image::ExtendedColorType::Rgb8)
    } else {
        (rgba, image::ExtendedColorType::Rgba8)
    };
    let mut bytes = Vec::new();
    PngEncoder::new_with_quality(&mut bytes, CompressionType::Default, FilterType::Adaptive)
        .write_image(&pixels, w, h, color)
        .map_err(|e| encode(e.to_string()))?;
    super::write_atomic(path, &bytes)
}

/// The colours of opaque RGBA8 pixels as a PNG palette (RGB triples, in order of first
/// appearance) and one index a pixel, or `None` when there are more than 256.
fn palette_of(rgba: &[u8]) -> Option<(Vec<u8>, Vec<u8>)> {
    let mut index = std::collections::HashMap::<[u8; 3], u8>::new();
    let mut palette = Vec::new();
    let mut indices = Vec::with_capacity(rgba.len() / 4);
    for p in rgba.chunks_exact(4) {
        let c = [p[0], p[1], p[2]];
        let i = match index.get(&c) {
            Some(&i) => i,
            None => {
                let i = u8::try_from(index.len()).ok()?;
                index.insert(c, i);
                palette.extend_from_slice(&c);
                i
            }
        };
        indices.push(i);
    }
    Some((palette, indices))
}

/// An 8-bit indexed PNG of `w × h` palette indices, through the `png` crate (the image
/// crate's encoder writes no palettes). No row filter: a palette's indices are labels, not
/// intensities, so differences between neighbours predict nothing.
fn indexed_png(w: u32, h: u32, palette: &[u8], indices: &[u8]) -> Result<Vec<u8>, png::EncodingError> {
    let mut bytes = Vec::new();
    let mut enc = png::Encoder::new(&mut bytes, w, h);
    enc.set_color(png::ColorType::Indexed);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_palette(palette);
    enc.set_compression(png::Compression::Balanced);
    enc.set_filter(png::Filter::NoFilter);
    let mut writer = enc.write_header()?;
    writer.write_image_data(indices)?;
    writer.finish()?;
    Ok(bytes)
}

/// Writes `w × h` pixels of `channels` (1 gray, 2 gray+alpha, 3 RGB, 4 RGBA) unsigned
/// samples as PNG; `samples` holds little-endian `u16` when `sixteen_bit`, bytes otherwise.
pub(crate) fn write_unorm(
    path: &Path,
    w: usize,
    h: usize,
    channels: usize,
    sixteen_bit: bool,
    samples: &[u8],
) -> Result<(), String> {
    use image::ExtendedColorType as C;
    let color = match (sixteen_bit, channels) {
        (false, 1) => C::L8,
        (false, 2) => C::La8,
        (false, 3) => C::Rgb8,
        (false, 4) => C::Rgba8,
        (true, 1) => C::L16,
        (true, 2) => C::La16,
        (true, 3) => C::Rgb16,
        (true, 4) => C::Rgba16,
        (_, c) => return Err(format!("{c} channels do not fit a .png (1 to 4); use .npy")),
    };
    // PNG stores 16-bit samples big-endian; the image crate takes native-endian u16.
    let bytes: Vec<u8> = if sixteen_bit {
        samples.chunks_exact(2).flat_map(|b| u16::from_le_bytes([b[0], b[1]]).to_ne_bytes()).collect()
    } else {
        samples.to_vec()
    };
    image::save_buffer_with_format(path, &bytes, w as u32, h as u32, color, image::ImageFormat::Png)
        .map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An opaque picture is stored as RGB and a translucent one as RGBA, and both read back
    /// as the RGBA8 pixels written, byte for byte (a gradient and noise, so every row filter
    /// has work to do).
    #[test]
    fn rgba8_pictures_read_back_as_written_and_opaque_ones_are_stored_as_rgb() {
        let dir = std::env::temp_dir().join(format!("relief-png-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (w, h) = (37u32, 23u32);
        let px = |i: u32, alpha: bool| {
            let n = i.wrapping_mul(2_654_435_761) >> 24;
            [(i % w * 7) as u8, (i / w * 11) as u8, n as u8, if alpha { (i % 3 * 100) as u8 } else { 255 }]
        };
        for (alpha, want_color) in [(false, image::ColorType::Rgb8), (true, image::ColorType::Rgba8)] {
            let rgba: Vec<u8> = (0..w * h).flat_map(|i| px(i, alpha)).collect();
            let path = dir.join(format!("alpha_{alpha}.png"));
            write_rgba8(&path, w, h, rgba.clone()).unwrap();
            let back = image::open(&path).unwrap();
            assert_eq!(back.color(), want_color, "alpha {alpha}");
            assert_eq!(back.to_rgba8().into_raw(), rgba, "alpha {alpha}");
        }
        // At most 256 colours, opaque: an indexed image, the same pixels read back.
        let few: Vec<u8> = (0..w * h)
            .flat_map(|i| {
                let k = (i * 7 % 200) as u8;
                [k, 255 - k, k / 3, 255]
            })
            .collect();
        let path = dir.join("few.png");
        write_rgba8(&path, w, h, few.clone()).unwrap();
        let raw = std::fs::read(&path).unwrap();
        // IHDR's colour type byte (offset 8 + 4 + 4 + 9 = 25): 3 is indexed colour.
        assert_eq!(raw[25], 3, "colour type");
        assert_eq!(image::open(&path).unwrap().to_rgba8().into_raw(), few);
        // 257 colours: not indexed (RGB), the same pixels.
        let many: Vec<u8> = (0..w * h)
            .flat_map(|i| {
                let k = i % 257;
                [(k % 256) as u8, (k / 256) as u8, 0, 255]
            })
            .collect();
        write_rgba8(&path, w, h, many.clone()).unwrap();
        assert_eq!(std::fs::read(&path).unwrap()[25], 2, "colour type");
        assert_eq!(image::open(&path).unwrap().to_rgba8().into_raw(), many);
        let short = write_rgba8(&dir.join("short.png"), w, h, vec![0; 5]).unwrap_err().to_string();
        assert!(short.contains("5 bytes of RGBA8 pixels for a 37x23 image") && !short.contains('\n'), "{short}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
