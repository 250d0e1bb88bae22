//! File I/O in one place (a leaf: it imports nothing else of this crate): atomic writes,
//! shader files, and the image and array formats ([`npy`], [`png`], [`exr`]).

pub mod base64;
pub mod exr;
pub mod npy;
pub mod png;

use std::path::Path;

use anyhow::Context;
use relief_dsl::Pipeline;

/// Refuses a path that names anything but a regular file (a FIFO, a directory, a device, a
/// socket), before it is opened. Opening a FIFO for reading blocks until some writer opens
/// it, so a reader that simply opened every path it was given could hang forever; a
/// directory or a device would fail late or read without end. Symbolic links are followed.
/// The error is an [`std::io::Error`] of kind `InvalidInput` whose message names what the
/// path is, so callers format it as they do any other read error.
pub fn check_regular(path: &Path) -> std::io::Result<()> {
    let meta = std::fs::metadata(path)?;
    if meta.is_file() {
        return Ok(());
    }
    let what = if meta.is_dir() { "a directory" } else { special_kind(&meta) };
    Err(std::io::Error::new(std::io::ErrorKind::InvalidInput, format!("not a regular file ({what})")))
}

#[cfg(unix)]
fn special_kind(meta: &std::fs::Metadata) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    let t = meta.file_type();
    if t.is_fifo() {
        "a FIFO"
    } else if t.is_socket() {
        "a socket"
    } else if t.is_char_device() || t.is_block_device() {
        "a device"
    } else {
        "a special file"
    }
}

#[cfg(not(unix))]
fn special_kind(_: &std::fs::Metadata) -> &'static str {
    "a special file"
}

/// [`std::fs::read`] of a regular file only ([`check_regular`] first).
pub fn read_regular(path: &Path) -> std::io::Result<Vec<u8>> {
    check_regular(path)?;
    std::fs::read(path)
}

/// [`std::fs::read_to_string`] of a regular file only ([`check_regular`] first).
pub fn read_regular_to_string(path: &Path) -> std::io::Result<String> {
    check_regular(path)?;
    std::fs::read_to_string(path)
}

/// [`image::open`] of a regular file only ([`check_regular`] first); the error names the path.
pub fn open_image(path: &Path) -> Result<image::DynamicImage, String> {
    check_regular(path).map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    image::open(path).map_err(|e| format!("{}: {e}", path.display()))
}

/// Writes `bytes` to `path` through a temporary file and a rename, so that an interrupted
/// run never leaves a half-written file (`NAME.EXT.tmp` beside it, removed when the write
/// fails).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    let tmp = path.with_extension(format!("{}.tmp", path.extension().and_then(|e| e.to_str()).unwrap_or("")));
    let result = std::fs::write(&tmp, bytes)
        .with_context(|| format!("cannot write {}", tmp.display()))
        .and_then(|()| std::fs::rename(&tmp, path).with_context(|| format!("cannot write {}", path.display())));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Writes the five shader files of `p` into `out` (`STEM.wgsl`, `STEM.spv` and one
/// `STEM.STAGE.glsl` per entry point); returns the file stem.
pub fn write_pipeline(p: &Pipeline, out: &Path) -> anyhow::Result<String> {
    let shaders = relief_dsl::emit::emit(p).with_context(|| format!("pipeline {p}"))?;
    let stem = p.file_stem();
    write_atomic(&out.join(format!("{stem}.wgsl")), shaders.wgsl.as_bytes())?;
    let spv: Vec<u8> = shaders.spirv.iter().flat_map(|w| w.to_le_bytes()).collect();
    write_atomic(&out.join(format!("{stem}.spv")), &spv)?;
    for (stage, src) in &shaders.glsl {
        write_atomic(&out.join(format!("{stem}.{stage}.glsl")), src.as_bytes())?;
    }
    Ok(stem)
}
