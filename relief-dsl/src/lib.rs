//! relief-dsl: relief-mapping search methods as stages, composed into one naga module.
//!
//! - [`abi`]: what a generated module and the runtime agree on (bindings, `Params`, probe
//!   records);
//! - [`spec`]: the pipeline as data and its text form (`linear(10)+binary(5)`);
//! - [`ir`]: a typed builder over naga IR in which stages are written;
//! - [`stage`]: the stages, one file per method family;
//! - [`compose`]: pipeline → validated module with render and probe entry points;
//! - [`emit`]: WGSL, SPIR-V and GLSL 450; the library output (WGSL, GLSL, HLSL, MSL).
//!
//! ```
//! use relief_dsl::{compose, emit, spec::Pipeline};
//! let p: Pipeline = "linear(10)+binary(5)".parse()?;
//! let shaders = emit::emit(&p)?;
//! assert!(shaders.wgsl.contains("fn coarse_linear("));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]
#![warn(unreachable_pub)]
#![warn(unnameable_types)]

pub mod abi;
pub mod compose;
pub mod emit;
pub mod ir;
pub mod spec;
pub mod stage;

pub use compose::{compile, Compiled};

/// Why a pipeline could not be compiled: which stage, and what went wrong.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{stage}: {message}")]
pub struct CompileError {
    /// The stage (or phase) that failed, e.g. `coarse linear` or `validation`.
    pub stage: String,
    /// What went wrong.
    pub message: String,
}

pub use spec::{register, Pipeline, Slot, StageSpec};

/// What relief-macros calls: the pattern types and parser pieces the macros build from Rust
/// tokens. Not part of the API.
#[doc(hidden)]
pub mod __private {
    pub use crate::spec::grid::{ArgPattern, GridPattern, OptionPattern, SlotPattern, StagePattern, ValuePattern};
    pub use crate::spec::options::{key_named, Key};
    pub use crate::spec::{slot_named, ParseError, TextForm, MAX_DEPTH};
}
