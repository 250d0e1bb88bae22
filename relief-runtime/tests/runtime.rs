//! relief-runtime's integration tests, one module per file beside this one, linked into one
//! test binary (linking wgpu and naga once instead of once per file). Run one file's tests with
//! `cargo test --release --test runtime cones::`. Every file here is one of them (the facade's
//! `every_test_file_is_a_module` checks).

mod cell_maps;
mod cli;
mod cli_library;
mod cones;
mod containers;
mod cost;
mod gpu;
mod heightmap;
mod lod;
mod maps;
mod mesh_early;
mod mesh_fragments;
mod mesh_grid;
mod mesh_walk;
mod meshes;
mod meshes_gpu;
mod reference;
mod report;
mod report_add;
mod results;
mod robust;
mod room;
mod scenes;
mod silhouette;
mod stability;
mod sweep;
mod tune;
