//! File I/O in one place (a leaf: it imports nothing else of this crate): atomic writes,
//! shader files, and the image and array formats ([`npy`], [`png`], [`exr`]).

pub mod exr;
pub mod npy;
pub mod png;

use std::path::Path;

use anyhow::Context;
use relief_dsl::Pipeline;

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
