//! OpenEXR files: f32 pixels, written as RGB (1 channel replicated, 2 channels with B = 0)
//! or RGBA.

use std::path::Path;

/// Writes `w × h` pixels of `channels` (1 to 4) interleaved f32 values as `.exr`.
pub fn write(path: &Path, w: usize, h: usize, channels: usize, values: &[f32]) -> Result<(), String> {
    let c = channels;
    let out_c = match c {
        1..=3 => 3,
        4 => 4,
        _ => return Err(format!("{c} channels do not fit an .exr (1 to 4); use .npy")),
    };
    let mut px = Vec::with_capacity(w * h * out_c);
    for t in 0..w * h {
        let s = &values[t * c..(t + 1) * c];
        match c {
            1 => px.extend([s[0], s[0], s[0]]),
            2 => px.extend([s[0], s[1], 0.0]),
            _ => px.extend_from_slice(s),
        }
    }
    let size = || "buffer size".to_string();
    let img = if out_c == 3 {
        image::DynamicImage::ImageRgb32F(image::ImageBuffer::from_raw(w as u32, h as u32, px).ok_or_else(size)?)
    } else {
        image::DynamicImage::ImageRgba32F(image::ImageBuffer::from_raw(w as u32, h as u32, px).ok_or_else(size)?)
    };
    img.save_with_format(path, image::ImageFormat::OpenExr).map_err(|e| e.to_string())
}
