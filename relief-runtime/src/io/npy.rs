//! NumPy `.npy` arrays: format version 1.0 written as little-endian `float32` (`<f4`) in C
//! order; versions 1–3 of `<f4` or `<f8` read.

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
    /// The array's dimensions, outermost first (C order); `[]` for a scalar.
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
