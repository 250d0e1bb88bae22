//! File I/O in one place (a leaf: it imports nothing else of this crate): atomic writes,
//! shader files, and the image and array formats ([`npy`], [`png`], [`exr`]), and the GPU
//! texture containers ([`container`]: KTX2, DDS).

pub mod base64;
pub mod container;
pub mod exr;
pub mod npy;
pub mod png;

use std::path::{Path, PathBuf};

use relief_dsl::Pipeline;

/// A file or folder that could not be read, written, created or removed. Every variant
/// names the path and displays as one line: `cannot write PATH: REASON`.
#[derive(Debug, thiserror::Error)]
pub enum FileError {
    /// Opening or reading the file failed (a FIFO or folder in its place included).
    #[error("cannot read {}: {source}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// Creating, writing or renaming the file failed.
    #[error("cannot write {}: {source}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// The folder could not be created.
    #[error("cannot create folder {}: {source}", path.display())]
    CreateDir {
        /// The folder.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// The folder could not be removed (to be written afresh).
    #[error("cannot clear {}: {source}", path.display())]
    Clear {
        /// The folder.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// The contents could not be encoded in the file's format (an image whose pixels do not
    /// fill its size, a record the CSV writer refuses).
    #[error("cannot write {}: {message}", path.display())]
    Encode {
        /// The file.
        path: PathBuf,
        /// What the encoder said.
        message: String,
    },
}

impl FileError {
    /// A [`FileError::Read`] of `path`.
    pub fn read(path: &Path, source: std::io::Error) -> FileError {
        FileError::Read { path: path.to_path_buf(), source }
    }

    /// A [`FileError::Write`] of `path`.
    pub fn write(path: &Path, source: std::io::Error) -> FileError {
        FileError::Write { path: path.to_path_buf(), source }
    }

    /// The path the error names.
    pub fn path(&self) -> &Path {
        match self {
            FileError::Read { path, .. }
            | FileError::Write { path, .. }
            | FileError::CreateDir { path, .. }
            | FileError::Clear { path, .. }
            | FileError::Encode { path, .. } => path,
        }
    }
}

/// [`std::fs::create_dir_all`], the error naming the folder.
pub fn create_dir_all(path: &Path) -> Result<(), FileError> {
    std::fs::create_dir_all(path).map_err(|source| FileError::CreateDir { path: path.to_path_buf(), source })
}

/// Refuses a path that names anything but a regular file (a FIFO, a directory, a device, a
/// socket), before it is opened. Opening a FIFO for reading blocks until some writer opens
/// it, so a reader that simply opened every path it was given could hang forever; a
/// directory or a device would fail late or read without end. Symbolic links are followed.
/// The error is an [`std::io::Error`] of kind `InvalidInput` whose message names what the
/// path is, so callers format it as they do any other read error.
pub(crate) fn check_regular(path: &Path) -> std::io::Result<()> {
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
pub(crate) fn read_regular(path: &Path) -> std::io::Result<Vec<u8>> {
    check_regular(path)?;
    std::fs::read(path)
}

/// [`std::fs::read_to_string`] of a regular file only ([`check_regular`] first).
pub(crate) fn read_regular_to_string(path: &Path) -> std::io::Result<String> {
    check_regular(path)?;
    std::fs::read_to_string(path)
}

/// [`image::open`] of a regular file only ([`check_regular`] first); the error names the path.
pub(crate) fn open_image(path: &Path) -> Result<image::DynamicImage, String> {
    check_regular(path).map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    image::open(path).map_err(|e| format!("{}: {e}", path.display()))
}

/// Writes `bytes` to `path` through a temporary file and a rename, so that an interrupted
/// run never leaves a half-written file (`NAME.EXT.tmp` beside it, removed when the write
/// fails).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), FileError> {
    let tmp = path.with_extension(format!("{}.tmp", path.extension().and_then(|e| e.to_str()).unwrap_or("")));
    let result = std::fs::write(&tmp, bytes)
        .map_err(|e| FileError::write(&tmp, e))
        .and_then(|()| std::fs::rename(&tmp, path).map_err(|e| FileError::write(path, e)));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Writes the five shader files of `p` into `out` (`STEM.wgsl`, `STEM.spv` and one
/// `STEM.STAGE.glsl` per entry point); returns the file stem.
pub fn write_pipeline(p: &Pipeline, out: &Path) -> Result<String, WritePipelineError> {
    let shaders =
        relief_dsl::emit::emit(p).map_err(|source| WritePipelineError::Compile { pipeline: p.to_string(), source })?;
    let stem = p.file_stem();
    write_atomic(&out.join(format!("{stem}.wgsl")), shaders.wgsl.as_bytes())?;
    let spv: Vec<u8> = shaders.spirv.iter().flat_map(|w| w.to_le_bytes()).collect();
    write_atomic(&out.join(format!("{stem}.spv")), &spv)?;
    for (stage, src) in &shaders.glsl {
        write_atomic(&out.join(format!("{stem}.{stage}.glsl")), src.as_bytes())?;
    }
    Ok(stem)
}

/// Why [`write_pipeline`] failed.
#[derive(Debug, thiserror::Error)]
pub enum WritePipelineError {
    /// The pipeline did not compile.
    #[error("pipeline {pipeline}: {source}")]
    Compile {
        /// The pipeline's text form.
        pipeline: String,
        /// The compiler's error.
        #[source]
        source: relief_dsl::CompileError,
    },
    /// A shader file could not be written.
    #[error(transparent)]
    File(#[from] FileError),
}

/// `text` as one file-name component, injectively: ASCII letters, digits, `_`, `-` and `.`
/// stay as they are, every other byte (of the UTF-8 text; `/`, `:`, `~` itself, …) becomes
/// `~XX` (two upper-case hex digits), and so does a leading `.` (no `.`, `..` or hidden
/// names). Two different texts never give the same name, so `sc/trav.toml` and
/// `sc_trav.toml` get two folders. The empty text gives `~`. A name longer than 120 bytes is
/// cut to its first 80 and `~~` and the 16 hex digits of a 64-bit FNV-1a hash of the whole
/// text (`~~` never appears otherwise), so that it stays a valid file name.
pub(crate) fn path_component(text: &str) -> String {
    let mut s = String::with_capacity(text.len());
    for (i, b) in text.bytes().enumerate() {
        if b.is_ascii_alphanumeric() || b == b'_' || b == b'-' || (b == b'.' && i > 0) {
            s.push(b as char);
        } else {
            s.push_str(&format!("~{b:02X}"));
        }
    }
    if s.is_empty() {
        return "~".into();
    }
    if s.len() > 120 {
        let hash = text.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| (h ^ b as u64).wrapping_mul(0x0100_0000_01b3));
        let mut cut = 80;
        // Never cut inside an escape.
        while s.as_bytes()[cut - 1] == b'~' || s.as_bytes()[cut - 2] == b'~' {
            cut -= 1;
        }
        s = format!("{}~~{hash:016x}", &s[..cut]);
    }
    s
}

#[cfg(test)]
mod tests {
    use super::path_component;

    #[test]
    fn path_components_are_injective_and_plain() {
        // Hand-written expectations.
        assert_eq!(path_component("sc/trav.toml"), "sc~2Ftrav.toml");
        assert_eq!(path_component("sc_trav.toml"), "sc_trav.toml");
        assert_eq!(path_component("scene:rocks@angle=70"), "scene~3Arocks~40angle~3D70");
        assert_eq!(path_component(".."), "~2E.");
        assert_eq!(path_component("a~2F"), "a~7E2F");
        assert_eq!(path_component(""), "~");
        assert_eq!(path_component("é"), "~C3~A9");
        // Texts that a lossy mapping would merge stay apart.
        let texts = ["sc/trav.toml", "sc_trav.toml", "sc~2Ftrav.toml", "sc:trav.toml", ".x", "~2Ex", "", "~", "a b"];
        let names: std::collections::HashSet<String> = texts.iter().map(|t| path_component(t)).collect();
        assert_eq!(names.len(), texts.len());
        for n in &names {
            assert!(n.bytes().all(|b| b.is_ascii_alphanumeric() || b"_-.~".contains(&b)), "{n}");
            assert!(!n.starts_with('.'), "{n}");
        }
        // Long texts stay short enough for a file name and still differ.
        let long_a = "d/".repeat(100) + "a.toml";
        let long_b = "d/".repeat(100) + "b.toml";
        let (a, b) = (path_component(&long_a), path_component(&long_b));
        assert!(a.len() <= 100 && b.len() <= 100, "{a} {b}");
        assert_ne!(a, b);
    }
}
