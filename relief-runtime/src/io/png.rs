//! PNG files: RGBA8 pictures (frames, error maps) and 1–4 channel unorm8/unorm16 maps.

use std::path::Path;

use super::FileError;

/// Writes an RGBA8 image as PNG, atomically ([`super::write_atomic`]). Pixels that do not
/// fill `w × h` exactly are a [`FileError::Encode`].
pub fn write_rgba8(path: &Path, w: u32, h: u32, rgba: Vec<u8>) -> Result<(), FileError> {
    let encode = |message: String| FileError::Encode { path: path.to_path_buf(), message };
    let len = rgba.len();
    let img = image::RgbaImage::from_raw(w, h, rgba)
        .ok_or_else(|| encode(format!("{len} bytes of RGBA8 pixels for a {w}x{h} image")))?;
    let mut bytes = Vec::new();
    img.write_to(&mut std::io::Cursor::new(&mut bytes), image::ImageFormat::Png).map_err(|e| encode(e.to_string()))?;
    super::write_atomic(path, &bytes)
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
