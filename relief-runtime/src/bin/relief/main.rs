//! The `relief` command line.

use clap::{Parser, Subcommand};
use relief_runtime::Overrides;
mod adapters;
mod compare;
mod cost;
mod export;
mod export_mesh;
mod gen;
mod maps;
mod render;
mod report;
mod room;
mod scene;
mod serve;
mod stability;
mod sweep;
mod tune;

/// relief: relief-mapping search methods composed into shaders, measured and swept.
#[derive(Parser)]
#[command(name = "relief", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// The GPU adapter to use: a substring of its name, any case (`relief adapters` lists
    /// them; default: the RELIEF_ADAPTER variable, else a hardware GPU before a software one).
    #[arg(long, global = true, value_name = "SUBSTRING")]
    adapter: Option<String>,
}

#[derive(Subcommand)]
enum Command {
    /// The GPU adapters wgpu sees (name, backend, device type) and the one relief uses.
    Adapters,
    /// Write WGSL, SPIR-V and GLSL for pipelines (`relief gen 'linear(10)+binary(5)' --out DIR`).
    Gen(gen::GenArgs),
    /// Build an acceleration map from a height map.
    Maps(maps::MapsArgs),
    /// One pipeline's library for an engine target, every texture it reads (KTX2 or DDS) and
    /// relief.json saying how to bind them (`relief export 'csm(64)' --scene rocks --target glsl-es --out DIR`).
    Export(export::ExportArgs),
    /// Render and probe one pipeline on one scene: frame time, accuracy against the exact
    /// reference, frame.png, error.png, metrics.json (and hits.csv).
    Render(render::RenderArgs),
    /// Two pipelines timed in alternating blocks on one scene: the ratio of their mean frame
    /// times with its 95 % interval, and the SIMD cost model.
    Compare(compare::CompareArgs),
    /// The GPU's own compiler prices pipelines: registers, instructions and loop bodies of the
    /// fragment shader and the probe, per AMD GPU family (Mesa's RADV, no GPU needed).
    Cost(cost::CostArgs),
    /// (internal) Compile jobs on stdin for this process's RADV family.
    #[command(name = "__radv-child", hide = true)]
    RadvChild,
    /// The fastest frontier pipeline reaching an RMS t error with no skipped geometry at
    /// every view, timed against Bevy's default (`relief tune rocks --error 1e-2`); with
    /// `--target --out`, its export bundle.
    Tune(tune::TuneArgs),
    /// Measure a whole grid (the dissertation's tables and figures, or a grid file), resumable.
    Sweep(sweep::SweepArgs),
    /// Every coarse × refine method on stress scenes and grazing angles: where each fails.
    Stability(stability::StabilityArgs),
    /// Tables, conclusions, charts, picture strips and Pareto fronts from a sweep folder.
    Report(report::ReportArgs),
    /// A room behind a window, interior mapping with relief on every wall (Amaro & Gustafsson 2022), against
    /// the same room as real geometry: frame.png, baseline.png, diff.png, metrics.json.
    Room(room::RoomArgs),
    /// Scene files: `relief scene check FILE` loads one (and its mesh) and says what it holds.
    Scene(scene::SceneArgs),
    /// Serve a report folder on this machine over HTTP (127.0.0.1 unless `--bind` says
    /// otherwise): files inside the folder only; prints the URL.
    Serve(serve::ServeArgs),
}

/// The scene overrides `relief render` and `relief sweep` take (a sweep applies them to
/// every scene).
#[derive(clap::Args, Debug)]
pub struct OverrideArgs {
    /// A named view, applied before the other overrides: `dissertation` (the Steep Parallax
    /// demo's: depth scale 0.05, 20° from the normal, 25° field of view, lod=auto).
    #[arg(long, value_parser = |s: &str| relief_runtime::View::parse(s))]
    pub view: Option<relief_runtime::View>,
    /// View angle from the surface normal, in degrees (overrides the scene's camera).
    #[arg(long)]
    pub angle: Option<f32>,
    /// The eye's azimuth around the normal, degrees from +u towards +v (overrides the scene's camera).
    #[arg(long)]
    pub azimuth: Option<f32>,
    /// Relief depth in texture units (overrides the scene's depth scale).
    #[arg(long)]
    pub depth_scale: Option<f32>,
    /// Repeats of the texture across the quad (overrides the scene's tiling).
    #[arg(long)]
    pub tiling: Option<f32>,
}

impl OverrideArgs {
    /// The overrides, checked ([`Overrides::check`]).
    pub fn checked(&self) -> anyhow::Result<Overrides> {
        let o = Overrides {
            view: self.view,
            depth_scale: self.depth_scale,
            tiling: self.tiling,
            angle: self.angle,
            azimuth: self.azimuth,
        };
        o.check().map_err(anyhow::Error::msg)?;
        Ok(o)
    }
}

/// Takes the lock of every results folder in `dirs` ([`relief_runtime::lock`]) for a command
/// that reads or writes them; with `wait` a held folder is waited for (said once on stderr).
pub fn lock_folders(dirs: &[&std::path::Path], wait: bool) -> anyhow::Result<Vec<relief_runtime::lock::FolderLock>> {
    Ok(relief_runtime::lock::take_all(dirs, wait, &mut |holder| {
        eprintln!("relief: waiting for the results folder's lock, held by {holder}");
    })?)
}

fn main() {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            use clap::error::ErrorKind;
            if matches!(
                e.kind(),
                ErrorKind::DisplayHelp
                    | ErrorKind::DisplayVersion
                    | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
            ) {
                e.exit();
            }
            // One line: clap's first line of the error, without the usage that follows.
            let text = e.render().to_string();
            let message: Vec<&str> = text
                .lines()
                .take_while(|l| !l.trim().is_empty() && !l.starts_with("Usage:"))
                .map(|l| l.trim())
                .collect();
            let message = message.join(" ");
            eprintln!(
                "relief: error: {} (relief --help lists the commands)",
                relief_dsl::spec::one_line(message.trim_start_matches("error: "))
            );
            std::process::exit(2);
        }
    };
    if let Some(a) = &cli.adapter {
        // Read by every command that opens a device (`Gpu::new`); set before any thread starts.
        std::env::set_var(relief_runtime::gpu::ADAPTER_VAR, a);
    }
    let result = match &cli.command {
        Command::Adapters => adapters::run(),
        Command::Gen(a) => gen::run(a),
        Command::Maps(a) => maps::run(a),
        Command::Export(a) => export::run(a),
        Command::Render(a) => render::run(a),
        Command::Compare(a) => compare::run(a),
        Command::Cost(a) => cost::run(a),
        Command::RadvChild => cost::child(),
        Command::Sweep(a) => sweep::run(a),
        Command::Tune(a) => tune::run(a),
        Command::Stability(a) => stability::run(a),
        Command::Report(a) => report::run(a),
        Command::Room(a) => room::run(a),
        Command::Serve(a) => serve::run(a),
        Command::Scene(a) => scene::run(a),
    };
    if let Err(e) = result {
        // One line: the error and its causes (a cause its error already quotes is not
        // repeated), control characters escaped and the length bounded.
        let mut line = String::new();
        for cause in e.chain().map(|c| c.to_string()) {
            if !line.contains(&cause) {
                if !line.is_empty() {
                    line.push_str(": ");
                }
                line.push_str(&cause);
            }
        }
        eprintln!("relief: error: {}", relief_dsl::spec::one_line(&line));
        std::process::exit(1);
    }
}
