//! Storage encodings for maps and conservative quantisation (the 3×3 filters are in
//! [`super::filter`], map files in [`super::file`] over [`crate::io`]).
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
//! F16 keeps `+inf`; a finite value above 65504 becomes 65504 when rounded down and `+inf` when
//! rounded up (the safe side either way; heights and apexes, the values rounded up, are at most 1).
//!
//! # Conservative rounding
//!
//! Every encoding rounds in the *safe* direction of its map kind ([`Rounding`]): cone ratios,
//! cone normals and distances round **down** (a narrower cone, a smaller sphere never
//! overshoots), maximum heights round **up**. The code is chosen, then checked by decoding in
//! f32 exactly as the table says, and moved one step if the decoded value crossed the input.

use super::Map;

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
pub(crate) fn f32_up(v: f64) -> f32 {
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
    /// 32-bit IEEE float, 4 bytes; keeps `+inf`.
    #[default]
    F32,
    /// 16-bit IEEE half float, 2 bytes; keeps `+inf`.
    F16,
    /// 8-bit code `q` in `0..=255` for `q / 255` of [`Encoding::max_value`]; clamps.
    Unorm8,
    /// 16-bit code `q` in `0..=65535` for `q / 65535` of [`Encoding::max_value`]; clamps.
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
    /// How each value is stored.
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
    /// Entries per row, as in the [`Map`] it was encoded from.
    pub width: usize,
    /// Rows, as in the source [`Map`].
    pub height: usize,
    /// Slices: 1 for 2D maps, the z resolution for `distance_field`.
    pub depth: usize,
    /// Values per entry.
    pub channels: usize,
    /// How the codes in `bytes` were made and must be decoded.
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
    encode_channels(map, enc, &vec![rounding; map.channels])
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
