//! relief-runtime: maps, scenes, the GPU runtime, the exact reference, metrics and sweeps.
//!
//! Modules in import order (a module imports only modules listed before it): the leaves
//! [`io`], [`picture`], [`results`] and [`timing`]; then [`heightmap`], [`scene`], [`maps`],
//! [`reference`](mod@reference); [`gpu`]; [`metrics`] and [`simd`]; [`measure`]; [`sweep`], [`stability`], [`room`]; [`report`].
//! The `relief` command line lives in `src/bin/relief/` and the library never calls it.

#![warn(missing_docs)]

pub mod gpu;
pub mod heightmap;
pub mod io;
pub mod lock;
pub mod maps;
pub mod measure;
pub mod metrics;
pub mod picture;
pub mod reference;
pub mod report;
pub mod results;
pub mod room;
pub mod scene;
pub mod simd;
pub mod stability;
pub mod sweep;
pub mod timing;
