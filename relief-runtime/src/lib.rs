//! relief-runtime: maps, scenes, the GPU runtime, the exact reference, metrics and sweeps.

pub mod gpu;
pub mod heightmap;
pub mod cli_gen;
pub mod cli_maps;
pub mod cli_render;
pub mod cli_stability;
pub mod cli_sweep;
pub mod maps;
pub mod scene;
pub mod reference;
pub mod measure;
pub mod metrics;
pub mod stability;
pub mod sweep;
pub mod report;
pub mod cli_report;
