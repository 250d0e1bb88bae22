//! relief-runtime: maps, scenes, the GPU runtime, the exact reference, metrics and sweeps.
//!
//! The types a user meets are re-exported here, in the groups below; the work of each area
//! is reached through its module ([`gpu`], [`cost`], [`maps`], [`metrics`], [`measure`], [`results`],
//! [`sweep`], [`tune`], [`stability`], [`room`], [`report`], [`io`], [`lock`]). Everything else is
//! private to the crate. ARCHITECTURE.md ("Layers", "Public API") gives the import order
//! of the modules; the `relief` command line lives in `src/bin/relief/` and the library
//! never calls it.
//!
//! Errors are typed: each area has its own ([`io::FileError`], [`lock::LockError`],
//! [`results::ResultsError`], [`SceneError`], [`gpu::GpuError`], …), and the modules above
//! them return [`Error`], which wraps them all.

#![warn(missing_docs)]
#![warn(unreachable_pub)]
#![warn(unnameable_types)]

pub mod cost;
pub mod error;
pub mod gpu;
mod heightmap;
pub mod io;
pub mod lock;
pub mod maps;
pub mod measure;
pub mod mesh;
pub mod mesh_measure;
pub mod metrics;
mod picture;
mod reference;
pub mod report;
pub mod results;
pub mod room;
mod scene;
mod simd;
pub mod stability;
pub mod sweep;
mod timing;
pub mod tune;

// The crate's error, which wraps every area's (each area's own is in its module).
pub use error::{Error, Result};

// Height maps and scenes: a height map loaded or made, the scene around it (camera, depth
// scale, edge mode, maps), named views and scene-file overrides.
pub use heightmap::{Channel, EdgeMode, HeightMap, HeightMapError, LoadOptions};
pub use scene::{
    camera_json, load_scene_file, scene_from_arg, scene_spec, Camera, MeshSource, NormalMap, Overrides, ProbeRay,
    RealScene, Rgba8Image, Scene, SceneError, SceneFileError, View, REAL_SCENES,
};

// Maps: the kinds a pipeline reads and their parameters (built by `maps::build`).
pub use maps::{Map, MapCache, MapKey, MapKind, MapParams};

// The device: a pipeline compiled for it, the scene's textures on it, the probe's hits.
pub use gpu::{Gpu, GpuHit, Program, SceneTextures};

// The exact reference on the CPU and the accuracy it gives.
pub use metrics::{Accuracy, Metrics};
pub use reference::{reference_hits, RefHit, Reference, ReferenceError, Sampling};

// Measurement, results and sweeps: one pipeline on one prepared scene, the paired-timing
// ratio, a results row, a named grid of cells, a report's verdict.
pub use measure::{Prepared, BASELINE};
pub use report::Verdict;
pub use results::Row;
pub use simd::SimdCost;
pub use sweep::NamedGrid;
pub use timing::Ratio;
