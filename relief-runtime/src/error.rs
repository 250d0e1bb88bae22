//! The crate's error, [`Error`]: what measuring, sweeping, the stability grid, rooms and
//! reports fail with. It wraps the error of each area below it (files, the folder lock,
//! results files, height maps, scenes, maps, the exact reference, the device, the shader
//! compiler), so `?` converts them, and adds the failures of its own callers. Every variant
//! displays as one line naming the problem; a wrapped error's text is part of it, so printing
//! `{}` says everything (its [`source`](std::error::Error::source) is there to match on).

use std::path::PathBuf;

use crate::cost::CostError;
use crate::gpu::GpuError;
use crate::heightmap::HeightMapError;
use crate::io::FileError;
use crate::lock::LockError;
use crate::maps::MapError;
use crate::reference::ReferenceError;
use crate::results::ResultsError;
use crate::scene::{file::SceneFileError, SceneError};

/// Why a measurement, sweep, stability grid, room run or report failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A file or folder could not be read, written or created.
    #[error(transparent)]
    File(#[from] FileError),
    /// A results folder is locked by another relief process.
    #[error(transparent)]
    Lock(#[from] LockError),
    /// A results file could not be read or written.
    #[error(transparent)]
    Results(#[from] ResultsError),
    /// A height map could not be loaded.
    #[error(transparent)]
    HeightMap(#[from] HeightMapError),
    /// A scene could not be made.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// A scene file could not be read.
    #[error(transparent)]
    SceneFile(#[from] SceneFileError),
    /// A precomputed map could not be built.
    #[error(transparent)]
    Map(#[from] MapError),
    /// The exact reference did not finish a ray.
    #[error(transparent)]
    Reference(#[from] ReferenceError),
    /// No device, or work on it failed.
    #[error(transparent)]
    Gpu(#[from] GpuError),
    /// A mesh scene's mesh could not be made, or its reference built.
    #[error(transparent)]
    Mesh(#[from] crate::mesh::MeshError),
    /// The GPU compiler's statistics could not be read (`cost`).
    #[error(transparent)]
    Cost(#[from] CostError),
    /// A pipeline did not compile.
    #[error(transparent)]
    Compile(#[from] relief_dsl::CompileError),
    /// A pipeline's text form did not parse.
    #[error(transparent)]
    Parse(Box<relief_dsl::spec::ParseError>),
    /// An error met on one scene, or on one pipeline on it: `scene LABEL: …`.
    #[error("scene {scene}: {source}")]
    InScene {
        /// The scene, as named (with the condition, such as an angle, when there is one).
        scene: String,
        /// What failed there.
        #[source]
        source: Box<Error>,
    },
    /// An error met on one pipeline: `pipeline TEXT: …`.
    #[error("pipeline {pipeline}: {source}")]
    InPipeline {
        /// The pipeline's text form (quoted where it came from a file).
        pipeline: String,
        /// What failed there.
        #[source]
        source: Box<Error>,
    },
    /// Inputs that cannot be used, or not together: a view flag that conflicts with a grid's
    /// own view, `silhouette=clip` on a scene that repeats, a grid that is too large, a
    /// pipeline a grid cannot build, hits and rays of different counts. The message names
    /// the inputs.
    #[error("{0}")]
    Input(String),
    /// A folder given as a sweep folder is not one.
    #[error("no sweep folder {}: it does not exist or is not a folder", .0.display())]
    NoSweepFolder(PathBuf),
    /// A report was asked for with no sweep folder.
    #[error("no sweep folder given")]
    NoSweepFolders,
    /// A sweep folder (or the merged folders) hold no rows to report.
    #[error(
        "{} holds no results: {} is missing or has no rows (run `relief sweep --out {}` first){}",
        dir.display(),
        dir.join(crate::results::JSONL).display(),
        dir.display(),
        if bad_lines.is_empty() { String::new() } else { format!("; unreadable lines: {}", bad_lines.join("; ")) }
    )]
    NoResults {
        /// The folder.
        dir: PathBuf,
        /// The lines that could not be read.
        bad_lines: Vec<String>,
    },
    /// A file is not a browser results file relief can add, or cannot be added to this sweep.
    #[error("{message}")]
    BrowserFile {
        /// The file.
        path: PathBuf,
        /// What is wrong with it, the file named.
        message: String,
    },
    /// A room (built-in or file) could not be made.
    #[error("{0}")]
    Room(String),
}

impl Error {
    /// `self` as met on scene `scene` ([`Error::InScene`]).
    pub fn in_scene(self, scene: impl Into<String>) -> Error {
        Error::InScene { scene: scene.into(), source: Box::new(self) }
    }

    /// `self` as met on pipeline `pipeline` ([`Error::InPipeline`]).
    pub fn in_pipeline(self, pipeline: impl Into<String>) -> Error {
        Error::InPipeline { pipeline: pipeline.into(), source: Box::new(self) }
    }
}

impl From<relief_dsl::spec::ParseError> for Error {
    fn from(e: relief_dsl::spec::ParseError) -> Error {
        Error::Parse(Box::new(e))
    }
}

/// The crate's result: `T` or an [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;
