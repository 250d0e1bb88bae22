//! The `relief` command line.

use clap::{Parser, Subcommand};
use relief_runtime::{cli_gen, cli_maps};

/// relief: relief-mapping search methods composed into shaders, measured and swept.
#[derive(Parser)]
#[command(name = "relief", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Write WGSL, SPIR-V and GLSL for pipelines (`relief gen 'linear(10)+binary(5)' --out DIR`).
    Gen(cli_gen::GenArgs),
    /// Build an acceleration map from a height map.
    Maps(cli_maps::MapsArgs),
}

fn main() {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Gen(a) => cli_gen::run(a),
        Command::Maps(a) => cli_maps::run(a),
    };
    if let Err(e) = result {
        // One line: the error and its causes.
        let chain: Vec<String> = e.chain().map(|c| c.to_string()).collect();
        eprintln!("relief: error: {}", chain.join(": "));
        std::process::exit(1);
    }
}
