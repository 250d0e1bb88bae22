//! # relief
//!
//! Relief-mapping search methods (parallax occlusion mapping and its relatives) composed
//! into shaders, rendered, measured against an exact reference and swept into tables.
//!
//! This facade re-exports the three crates:
//! - [`dsl`] (`relief-dsl`): pipeline specs and their text form, the typed naga IR builder,
//!   the stages, the composer and the WGSL / SPIR-V / GLSL emitters;
//! - `runtime` (`relief-runtime`, behind the default `runtime` feature): height maps,
//!   acceleration maps, scenes, the exact reference and the GPU runtime;
//! - `relief-macros`: declaring pipelines in Rust, checked at compile time: [`relief!`] (a
//!   [`Pipeline`]), [`relief_shader!`] (shaders emitted while compiling, as constants) and
//!   [`relief_grid!`] (a [`Grid`] of pipelines); see their docs for the syntax.
//!
//! A crate that only declares pipelines and emits shaders depends on
//! `relief = { version = "0.1", default-features = false }`: the macros and the DSL, without
//! the GPU runtime (wgpu, image, rayon) to compile.
//!
//! ```
//! let p: relief::Pipeline = "linear(10)+binary(5)".parse()?;
//! let shaders = relief::dsl::emit::emit(&p)?;
//! assert!(shaders.wgsl.contains("fn refine_binary("));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! ```
//! let p = relief::relief! { coarse: linear(10), refine: binary(5) };
//! assert_eq!(p, "linear(10)+binary(5)".parse().unwrap());
//! ```

#![warn(missing_docs)]

// The macros name their types `::relief::dsl::…`; this makes that path work inside this
// crate too.
extern crate self as relief;

pub use relief_dsl as dsl;
pub use relief_dsl::spec::Grid;
pub use relief_dsl::{compile, CompileError, Pipeline, Slot, StageSpec};
pub use relief_macros::{relief, relief_grid, relief_shader};
#[cfg(feature = "runtime")]
pub use relief_runtime as runtime;

/// The Rust examples of `README.md` and `docs/text-form.md`, compiled and run as doctests so
/// that the documentation stays true.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
#[doc = include_str!("../docs/text-form.md")]
pub struct DocExamples;
