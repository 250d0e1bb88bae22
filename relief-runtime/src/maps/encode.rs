//! Storage encodings for maps, conservative quantisation, the 3×3-min pass and map files.
//!
//! # Encodings
//!
//! | [`Format`] | stored | decoded value |
//! | --- | --- | --- |
//! | `F32` | `s` (f32) | `s`, or `s²` with `sqrt` |
//! | `F16` | `s` (IEEE half) | `s`, or `s²` with `sqrt` |
//! | `Unorm8` / `Unorm16` | integer `q` in `0..=M` (`M` = 255 / 65535) | `t · max_value`, or `t² · max_value` with `sqrt`, where `t = q / M` |
//!
//! `sqrt` is Dummer's square-root encoding of cone ratios (Burger 2018 §2.4: "the cone map
//! stores √r to increase precision of smaller values"), which spends the codes on the narrow
//! cones that matter. Unorm formats clamp to `[0, max_value]` (the GPU Gems 3 cone maps use
//! `max_value = 1`); this is the only place where a map is clamped: the f32 maps keep `+inf`.
//! F16 keeps `+inf` and rounds finite values above 65504 to 65504.
//!
//! # Conservative rounding
//!
//! Every encoding rounds in the *safe* direction of its map kind ([`Rounding`]): cone ratios,
//! cone normals and distances round **down** (a narrower cone, a smaller sphere never
//! overshoots), maximum heights round **up**. The code is chosen, then checked by decoding in
//! f32 exactly as the table says, and moved one step if the decoded value crossed the input.
//!
//! # The 3×3-min pass
//!
//! A shader that samples a cone map bilinearly at `x` gets a blend of the four texels around
//! `x`, which can be wider than the narrowest of them (Burger 2018 §4.3.1, Fig. 4.6). After
//! [`min3x3`] every texel holds the minimum of its 3×3 neighbourhood, and each of the four
//! texels around `x` has all four in its neighbourhood, so the blend is at most the smallest
//! of the four original values: linear filtering then never widens a cone beyond the
//! narrowest cone of the cell.
//!
//! # Files
//!
//! - `.png`: unorm8 or unorm16, 1 channel (gray), 2 (gray+alpha), 3 (RGB) or 4 (RGBA); 2D only.
//! - `.exr`: f32 or f16 (decoded to f32), written as RGB (1 channel replicated; 2 channels with
//!   B = 0) or RGBA; 2D only.
//! - `.npy`: NumPy format version 1.0, little-endian `float32` (`<f4`), C order, the decoded
//!   values (what a shader reads); shape `[h, w]`, `[h, w, c]` (c > 1), and `[d, h, w]` /
//!   `[d, h, w, c]` for 3D maps. Row 0 is v = 0. The same format is the raw float *input*
//!   for height maps ([`crate::heightmap::HeightMap::from_npy_bytes`]).

use super::{Map, MapError};
use crate::heightmap::EdgeMode;
use std::path::Path;

/// Rounds an f64 to the largest f32 not above it (`+inf` stays `+inf`).
pub fn f32_down(v: f64) -> f32 {
    let f = v as f32;
    if (f as f64) > v {
        next_down(f)
    } else {
        f
    }
}

/// Rounds an f64 to the smallest f32 not below it.
pub fn f32_up(v: f64) -> f32 {
    let f = v as f32;
    if (f as f64) < v {
        next_up(f)
    } else {
        f
    }
}

fn next_down(f: f32) -> f32 {
    if f.is_nan() || f == f32::NEG_INFINITY {
        return f;
    }
    if f == 0.0 {
        return -f32::from_bits(1);
    }
    let b = f.to_bits();
    f32::from_bits(if f > 0.0 { b - 1 } else { b + 1 })
}

fn next_up(f: f32) -> f32 {
    -next_down(-f)
}

/// How values are stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Format {
    #[default]
    F32,
    F16,
    Unorm8,
    Unorm16,
}

impl std::str::FromStr for Format {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "f32" | "float" => Ok(Format::F32),
            "f16" | "half" => Ok(Format::F16),
            "unorm8" | "u8" => Ok(Format::Unorm8),
            "unorm16" | "u16" => Ok(Format::Unorm16),
            o => Err(format!("unknown encoding `{o}` (expected f32, f16, unorm8 or unorm16)")),
        }
    }
}

impl Format {
    /// Bytes per stored value.
    pub fn bytes(self) -> usize {
        match self {
            Format::F32 => 4,
            Format::F16 | Format::Unorm16 => 2,
            Format::Unorm8 => 1,
        }
    }
}

/// Which way quantisation may move a value without breaking the map's guarantee.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Rounding {
    /// Never above the input (cone ratios, cone normals, distances, min-mips).
    Down,
    /// Never below the input (maximum heights).
    Up,
}

/// An encoding: format, optional square-root encoding, and the unorm range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Encoding {
    pub format: Format,
    /// Store `sqrt(value / max_value)` (unorm) or `sqrt(value)` (float).
    pub sqrt: bool,
    /// The value that the largest unorm code stands for (ignored by float formats).
    pub max_value: f32,
}

impl Default for Encoding {
    fn default() -> Self {
        Encoding { format: Format::F32, sqrt: false, max_value: 1.0 }
    }
}

impl Eq for Encoding {}

impl std::hash::Hash for Encoding {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.format.hash(state);
        self.sqrt.hash(state);
        self.max_value.to_bits().hash(state);
    }
}

impl Encoding {
    /// Plain f32, no transformation.
    pub const F32: Encoding = Encoding { format: Format::F32, sqrt: false, max_value: 1.0 };

    /// The value a stored code stands for (how a shader must decode it).
    pub fn decode_code(&self, code: u32) -> f32 {
        match self.format {
            Format::F32 => {
                let s = f32::from_bits(code);
                if self.sqrt {
                    s * s
                } else {
                    s
                }
            }
            Format::F16 => {
                let s = half::f16::from_bits(code as u16).to_f32();
                if self.sqrt {
                    s * s
                } else {
                    s
                }
            }
            Format::Unorm8 | Format::Unorm16 => {
                let m = if self.format == Format::Unorm8 { 255.0 } else { 65535.0 };
                let t = code as f32 / m;
                if self.sqrt {
                    t * t * self.max_value
                } else {
                    t * self.max_value
                }
            }
        }
    }

    /// The code for `v`, rounded in direction `r` (see the module docs).
    pub fn encode_value(&self, v: f32, r: Rounding) -> u32 {
        let v = if v.is_nan() { 0.0 } else { v };
        match self.format {
            Format::F32 | Format::F16 => self.encode_float(v, r),
            Format::Unorm8 | Format::Unorm16 => {
                let m: u32 = if self.format == Format::Unorm8 { 255 } else { 65535 };
                let x = (v.max(0.0) as f64 / self.max_value as f64).min(1.0);
                let x = if self.sqrt { x.sqrt() } else { x };
                let y = x * m as f64;
                let mut q = match r {
                    Rounding::Down => y.floor(),
                    Rounding::Up => y.ceil(),
                }
                .clamp(0.0, m as f64) as u32;
                match r {
                    Rounding::Down => {
                        while q > 0 && self.decode_code(q) > v {
                            q -= 1;
                        }
                        while q < m && self.decode_code(q + 1) <= v {
                            q += 1;
                        }
                    }
                    Rounding::Up => {
                        while q < m && self.decode_code(q) < v {
                            q += 1;
                        }
                        while q > 0 && self.decode_code(q - 1) >= v {
                            q -= 1;
                        }
                    }
                }
                q
            }
        }
    }

    fn encode_float(&self, v: f32, r: Rounding) -> u32 {
        let target = if self.sqrt { v.max(0.0).sqrt() } else { v };
        let to_code = |s: f32| -> u32 {
            if self.format == Format::F32 {
                s.to_bits()
            } else {
                half::f16::from_f32(s).to_bits() as u32
            }
        };
        let mut code = to_code(target);
        // Step through representable codes until the decoded value is on the safe side.
        for _ in 0..4 {
            let d = self.decode_code(code);
            let ok = match r {
                Rounding::Down => d <= v || (d.is_infinite() && v.is_infinite()),
                Rounding::Up => d >= v,
            };
            if ok {
                break;
            }
            code = step_code(self.format, code, r);
        }
        code
    }
}

/// One representable step down (or up) from a float code.
fn step_code(format: Format, code: u32, r: Rounding) -> u32 {
    match format {
        Format::F32 => {
            let f = f32::from_bits(code);
            match r {
                Rounding::Down => next_down(f).to_bits(),
                Rounding::Up => next_up(f).to_bits(),
            }
        }
        _ => {
            let f = half::f16::from_bits(code as u16);
            let b = code as u16;
            let positive = !f.is_sign_negative();
            let nb = match (r, positive) {
                (Rounding::Down, true) if b == 0 => 0x8001,
                (Rounding::Down, true) => b - 1,
                (Rounding::Down, false) => b + 1,
                (Rounding::Up, true) => b + 1,
                (Rounding::Up, false) if b == 0x8000 => 0x0001,
                (Rounding::Up, false) => b - 1,
            };
            nb as u32
        }
    }
}

/// A map in its stored form: little-endian codes, ready to upload.
#[derive(Clone, Debug, PartialEq)]
pub struct EncodedMap {
    pub width: usize,
    pub height: usize,
    pub depth: usize,
    pub channels: usize,
    pub encoding: Encoding,
    /// `width * height * depth * channels * encoding.format.bytes()` bytes, channels
    /// interleaved, row-major, slice-major.
    pub bytes: Vec<u8>,
}

impl EncodedMap {
    /// The stored code of value `i` (in `0..width*height*depth*channels`).
    pub fn code(&self, i: usize) -> u32 {
        let n = self.encoding.format.bytes();
        let b = &self.bytes[i * n..(i + 1) * n];
        match n {
            1 => b[0] as u32,
            2 => u16::from_le_bytes([b[0], b[1]]) as u32,
            _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        }
    }

    /// The values a shader reads back.
    pub fn decode(&self) -> Map {
        let n = self.width * self.height * self.depth * self.channels;
        Map {
            width: self.width,
            height: self.height,
            depth: self.depth,
            channels: self.channels,
            data: (0..n).map(|i| self.encoding.decode_code(self.code(i))).collect(),
            mips: Vec::new(),
        }
    }
}

/// Encodes every value of `map` with `enc`, rounding toward `rounding`.
pub fn encode(map: &Map, enc: &Encoding, rounding: Rounding) -> EncodedMap {
    let n = enc.format.bytes();
    let mut bytes = Vec::with_capacity(map.data.len() * n);
    for &v in &map.data {
        let c = enc.encode_value(v, rounding);
        match n {
            1 => bytes.push(c as u8),
            2 => bytes.extend_from_slice(&(c as u16).to_le_bytes()),
            _ => bytes.extend_from_slice(&c.to_le_bytes()),
        }
    }
    EncodedMap {
        width: map.width,
        height: map.height,
        depth: map.depth,
        channels: map.channels,
        encoding: *enc,
        bytes,
    }
}

/// Encodes every value of `map` with `enc`, channel `c` rounding toward `rounding[c]` (the
/// cell kinds round their ratios down and their apex up).
pub fn encode_channels(map: &Map, enc: &Encoding, rounding: &[Rounding]) -> EncodedMap {
    assert_eq!(rounding.len(), map.channels, "one rounding per channel");
    let n = enc.format.bytes();
    let mut bytes = Vec::with_capacity(map.data.len() * n);
    for (i, &v) in map.data.iter().enumerate() {
        let c = enc.encode_value(v, rounding[i % map.channels]);
        match n {
            1 => bytes.push(c as u8),
            2 => bytes.extend_from_slice(&(c as u16).to_le_bytes()),
            _ => bytes.extend_from_slice(&c.to_le_bytes()),
        }
    }
    EncodedMap { width: map.width, height: map.height, depth: map.depth, channels: map.channels, encoding: *enc, bytes }
}

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

/// Writes `values` as a NumPy v1.0 `<f4` array of the given shape.
pub fn npy_bytes(shape: &[usize], values: &[f32]) -> Vec<u8> {
    let dims: Vec<String> = shape.iter().map(|d| d.to_string()).collect();
    let shape_txt = if dims.len() == 1 { format!("({},)", dims[0]) } else { format!("({})", dims.join(", ")) };
    let mut header = format!("{{'descr': '<f4', 'fortran_order': False, 'shape': {shape_txt}, }}");
    // magic (6) + version (2) + length (2) + header + '\n' must be a multiple of 64.
    let total = 10 + header.len() + 1;
    header.push_str(&" ".repeat((64 - total % 64) % 64));
    header.push('\n');
    let mut out = Vec::with_capacity(10 + header.len() + values.len() * 4);
    out.extend_from_slice(b"\x93NUMPY\x01\x00");
    out.extend_from_slice(&(header.len() as u16).to_le_bytes());
    out.extend_from_slice(header.as_bytes());
    for v in values {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out
}

/// A parsed `.npy` header.
#[derive(Debug, Clone, PartialEq)]
pub struct NpyHeader {
    pub shape: Vec<usize>,
    /// 4 (`<f4`) or 8 (`<f8`).
    pub item_size: usize,
    /// Where the data start.
    pub data_offset: usize,
}

/// Parses the header of a `.npy` file holding little-endian `<f4` or `<f8` in C order.
pub fn parse_npy_header(bytes: &[u8]) -> Result<NpyHeader, String> {
    if bytes.len() < 10 || &bytes[..6] != b"\x93NUMPY" {
        return Err("not a .npy file (bad magic)".into());
    }
    let (len, start): (usize, usize) = match bytes[6] {
        1 => (u16::from_le_bytes([bytes[8], bytes[9]]) as usize, 10),
        2 | 3 => {
            if bytes.len() < 12 {
                return Err("truncated .npy header".into());
            }
            (u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]) as usize, 12)
        }
        v => return Err(format!("unsupported .npy version {v}")),
    };
    let end = start.checked_add(len).filter(|&e| e <= bytes.len()).ok_or("truncated .npy header")?;
    let text = std::str::from_utf8(&bytes[start..end]).map_err(|_| "the .npy header is not text")?;
    let field = |name: &str| -> Result<&str, String> {
        let key = format!("'{name}'");
        let i = text.find(&key).ok_or(format!("the .npy header lacks {key}"))?;
        let rest = text[i + key.len()..].trim_start();
        let rest = rest.strip_prefix(':').ok_or("malformed .npy header")?;
        Ok(rest.trim_start())
    };
    let descr = field("descr")?;
    let item_size = if descr.starts_with("'<f4'") {
        4
    } else if descr.starts_with("'<f8'") {
        8
    } else {
        return Err(format!(
            "unsupported .npy dtype {} (expected '<f4' or '<f8')",
            descr.split(',').next().unwrap_or("")
        ));
    };
    if field("fortran_order")?.starts_with("True") {
        return Err("Fortran-order .npy arrays are not supported".into());
    }
    let shape = field("shape")?;
    let close = shape.find(')').ok_or("malformed .npy shape")?;
    let inner = shape.strip_prefix('(').ok_or("malformed .npy shape")?;
    let inner = &inner[..close - 1];
    let mut dims = Vec::new();
    for part in inner.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        dims.push(part.parse::<usize>().map_err(|_| format!("bad .npy dimension `{part}`"))?);
    }
    Ok(NpyHeader { shape: dims, item_size, data_offset: end })
}

/// Writes an encoded map to `path`, format chosen by extension (see the module docs).
pub fn write_map(path: &Path, map: &EncodedMap) -> Result<(), MapError> {
    let ext = path.extension().and_then(|e| e.to_str()).map(|e| e.to_ascii_lowercase()).unwrap_or_default();
    let io = |source: std::io::Error| MapError::Io { path: path.to_path_buf(), source };
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
            std::fs::write(path, npy_bytes(&shape, &dec.data)).map_err(io)
        }
        "png" => {
            if map.depth > 1 {
                return Err(bad("a 3D map cannot be written as .png; use .npy".into()));
            }
            let color = match (map.encoding.format, c) {
                (Format::Unorm8, 1) => image::ExtendedColorType::L8,
                (Format::Unorm8, 2) => image::ExtendedColorType::La8,
                (Format::Unorm8, 3) => image::ExtendedColorType::Rgb8,
                (Format::Unorm8, 4) => image::ExtendedColorType::Rgba8,
                (Format::Unorm16, 1) => image::ExtendedColorType::L16,
                (Format::Unorm16, 2) => image::ExtendedColorType::La16,
                (Format::Unorm16, 3) => image::ExtendedColorType::Rgb16,
                (Format::Unorm16, 4) => image::ExtendedColorType::Rgba16,
                (Format::Unorm8 | Format::Unorm16, c) => {
                    return Err(bad(format!("{c} channels do not fit a .png (1 to 4); use .npy")))
                }
                (f, _) => {
                    return Err(bad(format!("{f:?} cannot be written as .png; use --encoding unorm8 or unorm16, or .exr/.npy")))
                }
            };
            // PNG stores 16-bit samples big-endian; the image crate takes native-endian u16.
            let bytes: Vec<u8> = if map.encoding.format == Format::Unorm16 {
                map.bytes
                    .chunks_exact(2)
                    .flat_map(|b| u16::from_le_bytes([b[0], b[1]]).to_ne_bytes())
                    .collect()
            } else {
                map.bytes.clone()
            };
            image::save_buffer_with_format(path, &bytes, w as u32, h as u32, color, image::ImageFormat::Png)
                .map_err(|e| bad(e.to_string()))
        }
        "exr" => {
            if map.depth > 1 {
                return Err(bad("a 3D map cannot be written as .exr; use .npy".into()));
            }
            if !matches!(map.encoding.format, Format::F32 | Format::F16) {
                return Err(bad("unorm encodings cannot be written as .exr; use .png".into()));
            }
            let dec = map.decode();
            let out_c = match c {
                1..=3 => 3,
                4 => 4,
                _ => return Err(bad(format!("{c} channels do not fit an .exr (1 to 4); use .npy"))),
            };
            let mut px = Vec::with_capacity(w * h * out_c);
            for t in 0..w * h {
                let s = &dec.data[t * c..(t + 1) * c];
                match c {
                    1 => px.extend([s[0], s[0], s[0]]),
                    2 => px.extend([s[0], s[1], 0.0]),
                    _ => px.extend_from_slice(s),
                }
            }
            let img = if out_c == 3 {
                image::DynamicImage::ImageRgb32F(
                    image::ImageBuffer::from_raw(w as u32, h as u32, px).ok_or_else(|| bad("buffer size".into()))?,
                )
            } else {
                image::DynamicImage::ImageRgba32F(
                    image::ImageBuffer::from_raw(w as u32, h as u32, px).ok_or_else(|| bad("buffer size".into()))?,
                )
            };
            img.save_with_format(path, image::ImageFormat::OpenExr).map_err(|e| bad(e.to_string()))
        }
        _ => Err(bad("unknown output extension (expected .png, .exr or .npy)".into())),
    }
}
