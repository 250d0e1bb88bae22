//! Height maps: a grid of heights in [0, 1] (1 = top of the relief volume), row-major,
//! texel (x, y) at texture coordinates ((x + 0.5) / width, (y + 0.5) / height).

/// What happens past the edge of a map: wrap around (tiling) or repeat the border texel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum EdgeMode {
    /// Tiling: texel coordinates wrap, distances are measured the shorter way round.
    #[default]
    Repeat,
    /// The border texel extends outward.
    Clamp,
}

impl EdgeMode {
    /// Resolves a possibly out-of-range texel index into `0..n`.
    pub fn index(self, i: i64, n: usize) -> usize {
        let n = n as i64;
        match self {
            EdgeMode::Repeat => i.rem_euclid(n) as usize,
            EdgeMode::Clamp => i.clamp(0, n - 1) as usize,
        }
    }
}

/// A height map: `width * height` heights in [0, 1], row-major (row y = v).
#[derive(Clone, Debug, PartialEq)]
pub struct HeightMap {
    /// Texels per row: the count along x (u).
    pub width: usize,
    /// Rows: the count along y (v).
    pub height: usize,
    /// The heights, row by row: texel (x, y) is `data[y * width + x]`. Each is in [0, 1],
    /// 1 being the top of the relief volume.
    pub data: Vec<f32>,
}

impl HeightMap {
    /// A map from row-major data; `data.len()` must be `width * height`.
    pub fn new(width: usize, height: usize, data: Vec<f32>) -> Self {
        assert_eq!(data.len(), width * height, "height map data has the wrong length");
        HeightMap { width, height, data }
    }

    /// A map whose heights come from `f(x, y)` per texel.
    pub fn from_fn(width: usize, height: usize, mut f: impl FnMut(usize, usize) -> f32) -> Self {
        let mut data = Vec::with_capacity(width * height);
        for y in 0..height {
            for x in 0..width {
                data.push(f(x, y));
            }
        }
        HeightMap { width, height, data }
    }

    /// The texel at integer coordinates, resolved with `edge`.
    pub fn texel(&self, x: i64, y: i64, edge: EdgeMode) -> f32 {
        let xi = edge.index(x, self.width);
        let yi = edge.index(y, self.height);
        self.data[yi * self.width + xi]
    }

    /// The surface the shaders sample: bilinear interpolation between texel centres.
    pub fn bilinear(&self, u: f64, v: f64, edge: EdgeMode) -> f64 {
        let x = u * self.width as f64 - 0.5;
        let y = v * self.height as f64 - 0.5;
        let x0 = x.floor();
        let y0 = y.floor();
        let fx = x - x0;
        let fy = y - y0;
        let (x0, y0) = (x0 as i64, y0 as i64);
        let h00 = self.texel(x0, y0, edge) as f64;
        let h10 = self.texel(x0 + 1, y0, edge) as f64;
        let h01 = self.texel(x0, y0 + 1, edge) as f64;
        let h11 = self.texel(x0 + 1, y0 + 1, edge) as f64;
        let a = h00 + (h10 - h00) * fx;
        let b = h01 + (h11 - h01) * fx;
        a + (b - a) * fy
    }

    /// Nearest-texel sampling, for stages that ask for it.
    pub fn nearest(&self, u: f64, v: f64, edge: EdgeMode) -> f64 {
        let x = (u * self.width as f64).floor() as i64;
        let y = (v * self.height as f64).floor() as i64;
        self.texel(x, y, edge) as f64
    }
}

// ---------------------------------------------------------------------------------------------
// Loading
// ---------------------------------------------------------------------------------------------

use std::path::{Path, PathBuf};

/// Largest accepted side of a height map, in texels. Checked against the file's header
/// *before* any texel storage is allocated, so a hostile header cannot exhaust memory.
pub(crate) const MAX_SIDE: usize = 16384;

/// Largest accepted texel count (`MAX_SIDE²`, 1 GiB of `f32`).
pub(crate) const MAX_TEXELS: usize = MAX_SIDE * MAX_SIDE;

/// A channel of a colour image to read heights from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Channel {
    /// Red: sample 0 of a pixel.
    R,
    /// Green: sample 1 of a pixel.
    G,
    /// Blue: sample 2 of a pixel.
    B,
    /// Alpha: the last sample of a gray+alpha or colour+alpha pixel (sample 3 in a
    /// `[h, w, c]` `.npy` array).
    A,
}

impl Channel {
    /// The lower-case letter used on the command line (`r`, `g`, `b`, `a`).
    pub(crate) fn letter(self) -> char {
        match self {
            Channel::R => 'r',
            Channel::G => 'g',
            Channel::B => 'b',
            Channel::A => 'a',
        }
    }
}

impl std::str::FromStr for Channel {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "r" | "red" => Ok(Channel::R),
            "g" | "green" => Ok(Channel::G),
            "b" | "blue" => Ok(Channel::B),
            "a" | "alpha" => Ok(Channel::A),
            other => Err(format!("unknown channel `{other}` (expected r, g, b or a)")),
        }
    }
}

/// How to turn a file into heights.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct LoadOptions {
    /// Which channel holds the heights. `None`: the gray value of a gray image, or the
    /// Rec. 709 luma (0.2126 R + 0.7152 G + 0.0722 B) of a colour image. `R`/`G`/`B` need a
    /// colour image, `A` an image with alpha; otherwise [`HeightMapError::MissingChannel`].
    pub channel: Option<Channel>,
    /// The file is a depth map (white = deep, as in GPU Gems 3): height = 1 - value.
    pub depth: bool,
}

/// Why a height map could not be loaded. Every variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum HeightMapError {
    /// Nothing exists at the path.
    #[error("{path}: file not found")]
    Missing {
        /// The file asked for.
        path: PathBuf,
    },
    /// The file exists but opening or reading it failed.
    #[error("{path}: cannot read: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// The extension is none of `.png`, `.tga`, `.bmp`, `.jpg`/`.jpeg`, `.tif`/`.tiff`,
    /// `.webp`, `.exr`, `.npy` (case is ignored).
    #[error(
        "{path}: unsupported file type (expected .png, .tga, .bmp, .jpg, .jpeg, .tif, .tiff, .webp, .exr or .npy)"
    )]
    Unsupported {
        /// The file.
        path: PathBuf,
    },
    /// The image decoder failed, or the `.npy` header, shape or data length is invalid.
    #[error("{path}: corrupt or unreadable image: {message}")]
    Corrupt {
        /// The file.
        path: PathBuf,
        /// What is wrong, from the decoder or the `.npy` parser.
        message: String,
    },
    /// The width or the height is 0 (for `.npy`, also a channel count of 0).
    #[error("{path}: the image has zero size ({width} x {height})")]
    ZeroSize {
        /// The file.
        path: PathBuf,
        /// Width in texels, as the header states it.
        width: usize,
        /// Height in texels, as the header states it.
        height: usize,
    },
    /// A side is larger than `MAX_SIDE`; found from the header, before decoding.
    #[error("{path}: {width} x {height} texels exceeds the limit of {max} x {max}", max = MAX_SIDE)]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// Width in texels, as the header states it.
        width: usize,
        /// Height in texels, as the header states it.
        height: usize,
    },
    /// [`LoadOptions::channel`] names a channel the file does not have (a colour channel
    /// of a gray image, alpha of an image without alpha, or past the last `.npy` channel).
    #[error("{path}: channel `{channel}` does not exist in this {layout} image", channel = channel.letter())]
    MissingChannel {
        /// The file.
        path: PathBuf,
        /// The channel asked for.
        channel: Channel,
        /// What the file holds, for the message: the decoder's colour type (e.g. `L8`) or
        /// `"N-channel npy"`.
        layout: String,
    },
    /// A height is NaN or infinite (only float files can hold one).
    #[error("{path}: texel ({x}, {y}) is not a finite number ({value})")]
    NotFinite {
        /// The file.
        path: PathBuf,
        /// Column of the first bad texel.
        x: usize,
        /// Row of the first bad texel.
        y: usize,
        /// Its value.
        value: f32,
    },
    /// A height is below 0 or above 1 (only float files can hold one).
    #[error("{path}: texel ({x}, {y}) = {value} lies outside [0, 1]")]
    OutOfRange {
        /// The file.
        path: PathBuf,
        /// Column of the first bad texel.
        x: usize,
        /// Row of the first bad texel.
        y: usize,
        /// Its value.
        value: f32,
    },
}

impl HeightMap {
    /// Loads a height map from a file, chosen by extension:
    ///
    /// - `.png` and `.tif`/`.tiff` (8 or 16 bit, gray, gray+alpha, RGB or RGBA), `.tga`,
    ///   `.bmp`, `.jpg`/`.jpeg` (8 bit, gray or RGB), `.webp` (8 bit, lossy or lossless, RGB or
    ///   RGBA): integer samples are normalised to [0, 1] (`v / 255` or `v / 65535`), through the
    ///   `image` crate's decoders.
    /// - `.exr`: float samples, used as they are.
    /// - `.npy`: the raw float format, see `HeightMap::from_npy_bytes`.
    ///
    /// Then `options.depth` flips depth to height (`1 - v`). Float values must be finite and in
    /// [0, 1]. Sizes are checked against `MAX_SIDE` before the texels are decoded. Never panics.
    pub fn load(path: impl AsRef<Path>, options: &LoadOptions) -> Result<HeightMap, HeightMapError> {
        let path = path.as_ref();
        let p = || path.to_path_buf();
        if !path.exists() {
            return Err(HeightMapError::Missing { path: p() });
        }
        crate::io::check_regular(path).map_err(|source| HeightMapError::Io { path: p(), source })?;
        let ext = path.extension().and_then(|e| e.to_str()).map(|e| e.to_ascii_lowercase()).unwrap_or_default();
        let mut map = match ext.as_str() {
            "npy" => {
                let bytes = std::fs::read(path).map_err(|source| HeightMapError::Io { path: p(), source })?;
                HeightMap::from_npy_bytes(&bytes, options.channel, path)?
            }
            "png" | "tga" | "bmp" | "jpg" | "jpeg" | "tif" | "tiff" | "webp" | "exr" => {
                load_image(path, options.channel)?
            }
            _ => return Err(HeightMapError::Unsupported { path: p() }),
        };
        if options.depth {
            for v in &mut map.data {
                *v = 1.0 - *v;
            }
        }
        Ok(map)
    }

    /// Parses the raw float format: a NumPy `.npy` file (format version 1, 2 or 3) holding
    /// little-endian `float32` (`<f4`) or `float64` (`<f8`) in C order, shape `[h, w]` or
    /// `[h, w, c]` (then `channel` picks `c` = 0..3 as r, g, b, a; without a channel, `c` must
    /// be 1). Row 0 is v = 0, like image rows. Values must be finite and in [0, 1]; `depth`
    /// conversion is applied by [`HeightMap::load`], not here. `path` only names errors.
    pub(crate) fn from_npy_bytes(
        bytes: &[u8],
        channel: Option<Channel>,
        path: &Path,
    ) -> Result<HeightMap, HeightMapError> {
        let corrupt = |m: &str| HeightMapError::Corrupt { path: path.to_path_buf(), message: m.to_string() };
        let header = crate::io::npy::parse_npy_header(bytes).map_err(|m| corrupt(&m))?;
        let (h, w, c) = match header.shape.as_slice() {
            [h, w] => (*h, *w, 1),
            [h, w, c] => (*h, *w, *c),
            _ => return Err(corrupt("shape must be [h, w] or [h, w, c]")),
        };
        if w == 0 || h == 0 || c == 0 {
            return Err(HeightMapError::ZeroSize { path: path.to_path_buf(), width: w, height: h });
        }
        if w > MAX_SIDE || h > MAX_SIDE {
            return Err(HeightMapError::TooLarge { path: path.to_path_buf(), width: w, height: h });
        }
        let ci = match channel {
            None if c == 1 => 0,
            None => return Err(corrupt("a [h, w, c] array with c > 1 needs a channel (r, g, b or a)")),
            Some(ch) => {
                let i = ch as usize;
                if i >= c {
                    return Err(HeightMapError::MissingChannel {
                        path: path.to_path_buf(),
                        channel: ch,
                        layout: format!("{c}-channel npy"),
                    });
                }
                i
            }
        };
        let size = header.item_size;
        let need = w
            .checked_mul(h)
            .and_then(|n| n.checked_mul(c))
            .and_then(|n| n.checked_mul(size))
            .ok_or_else(|| corrupt("shape overflows"))?;
        let body = &bytes[header.data_offset..];
        if body.len() < need {
            return Err(corrupt(&format!("data too short: {} bytes for {} needed", body.len(), need)));
        }
        let mut data = Vec::with_capacity(w * h);
        for i in 0..w * h {
            let off = (i * c + ci) * size;
            let v = if size == 4 {
                f32::from_le_bytes(body[off..off + 4].try_into().unwrap())
            } else {
                f64::from_le_bytes(body[off..off + 8].try_into().unwrap()) as f32
            };
            data.push(v);
        }
        check_values(&data, w, path)?;
        Ok(HeightMap { width: w, height: h, data })
    }

    /// A stable 64-bit content hash (FNV-1a over the size and the bit patterns of the heights),
    /// the same on every machine and run; used as the map cache key.
    pub fn content_hash(&self) -> u64 {
        let mut h = Fnv::new();
        h.write(&(self.width as u64).to_le_bytes());
        h.write(&(self.height as u64).to_le_bytes());
        for v in &self.data {
            h.write(&v.to_bits().to_le_bytes());
        }
        h.finish()
    }
}

/// FNV-1a, 64 bit: tiny, stable across platforms and Rust versions.
pub(crate) struct Fnv(u64);

impl Fnv {
    pub(crate) fn new() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
    pub(crate) fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= b as u64;
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    pub(crate) fn finish(&self) -> u64 {
        self.0
    }
}

fn check_values(data: &[f32], width: usize, path: &Path) -> Result<(), HeightMapError> {
    for (i, &v) in data.iter().enumerate() {
        let (x, y) = (i % width, i / width);
        if !v.is_finite() {
            return Err(HeightMapError::NotFinite { path: path.to_path_buf(), x, y, value: v });
        }
        if !(0.0..=1.0).contains(&v) {
            return Err(HeightMapError::OutOfRange { path: path.to_path_buf(), x, y, value: v });
        }
    }
    Ok(())
}

fn load_image(path: &Path, channel: Option<Channel>) -> Result<HeightMap, HeightMapError> {
    use image::DynamicImage as D;
    let p = || path.to_path_buf();
    let corrupt = |e: &dyn std::fmt::Display| HeightMapError::Corrupt { path: p(), message: e.to_string() };
    let open = || {
        image::ImageReader::open(path)
            .map_err(|source| HeightMapError::Io { path: p(), source })?
            .with_guessed_format()
            .map_err(|source| HeightMapError::Io { path: p(), source })
    };
    // Header first: size checks before any texel storage exists.
    let (w, h) = open()?.into_dimensions().map_err(|e| corrupt(&e))?;
    let (w, h) = (w as usize, h as usize);
    if w == 0 || h == 0 {
        return Err(HeightMapError::ZeroSize { path: p(), width: w, height: h });
    }
    if w > MAX_SIDE || h > MAX_SIDE {
        return Err(HeightMapError::TooLarge { path: p(), width: w, height: h });
    }
    let mut reader = open()?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_SIDE as u32);
    limits.max_image_height = Some(MAX_SIDE as u32);
    limits.max_alloc = Some((MAX_TEXELS as u64) * 16 + (1 << 20));
    reader.limits(limits);
    let img = reader.decode().map_err(|e| corrupt(&e))?;
    if img.width() as usize != w || img.height() as usize != h {
        return Err(corrupt(&"header and decoded size differ"));
    }
    let (colour, alpha) = (img.color().has_color(), img.color().has_alpha());
    let layout = format!("{:?}", img.color());
    // Which sample of a pixel to read: Some(i) = channel i, None = luma of channels 0..3.
    let pick: Option<usize> = match channel {
        None => {
            if colour {
                None
            } else {
                Some(0)
            }
        }
        Some(Channel::A) if alpha => Some(if colour { 3 } else { 1 }),
        Some(ch @ (Channel::R | Channel::G | Channel::B)) if colour => Some(ch as usize),
        Some(ch) => return Err(HeightMapError::MissingChannel { path: p(), channel: ch, layout }),
    };
    fn extract<T: Copy>(raw: &[T], n: usize, pick: Option<usize>, f: impl Fn(T) -> f32) -> Vec<f32> {
        raw.chunks_exact(n)
            .map(|px| match pick {
                Some(i) => f(px[i]),
                None => 0.2126 * f(px[0]) + 0.7152 * f(px[1]) + 0.0722 * f(px[2]),
            })
            .collect()
    }
    let u8f = |v: u8| v as f32 / 255.0;
    let u16f = |v: u16| v as f32 / 65535.0;
    let f32f = |v: f32| v;
    let data = match &img {
        D::ImageLuma8(b) => extract(b.as_raw(), 1, pick, u8f),
        D::ImageLumaA8(b) => extract(b.as_raw(), 2, pick, u8f),
        D::ImageRgb8(b) => extract(b.as_raw(), 3, pick, u8f),
        D::ImageRgba8(b) => extract(b.as_raw(), 4, pick, u8f),
        D::ImageLuma16(b) => extract(b.as_raw(), 1, pick, u16f),
        D::ImageLumaA16(b) => extract(b.as_raw(), 2, pick, u16f),
        D::ImageRgb16(b) => extract(b.as_raw(), 3, pick, u16f),
        D::ImageRgba16(b) => extract(b.as_raw(), 4, pick, u16f),
        D::ImageRgb32F(b) => extract(b.as_raw(), 3, pick, f32f),
        D::ImageRgba32F(b) => extract(b.as_raw(), 4, pick, f32f),
        other => {
            // Future layouts: go through 32-bit float RGBA.
            let b = other.to_rgba32f();
            let pick = match channel {
                None | Some(Channel::R) => Some(0),
                Some(ch) => Some(ch as usize),
            };
            extract(b.as_raw(), 4, pick, f32f)
        }
    };
    // Luma of 8/16-bit data can round a hair above 1.
    let data = if pick.is_none() && !matches!(img, D::ImageRgb32F(_) | D::ImageRgba32F(_)) {
        data.into_iter().map(|v| v.clamp(0.0, 1.0)).collect()
    } else {
        data
    };
    check_values(&data, w, path)?;
    Ok(HeightMap { width: w, height: h, data })
}
