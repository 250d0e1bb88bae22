//! `relief scene check FILE`: a scene file loaded, with its mesh if it names one, and what was
//! found printed, or one error line. With `--reference N`, the mesh's exact reference of an
//! N × N frame is traced and timed (docs/meshes.md).

use std::path::PathBuf;
use std::time::Instant;

use anyhow::Context;
use relief_runtime::mesh::MeshScene;

/// Arguments of `relief scene`.
#[derive(clap::Args, Debug)]
pub struct SceneArgs {
    #[command(subcommand)]
    pub command: SceneCommand,
}

/// What `relief scene` does.
#[derive(clap::Subcommand, Debug)]
pub enum SceneCommand {
    /// Load a scene file (and its mesh) and say what it holds.
    Check {
        /// The scene file (`.toml`).
        file: PathBuf,
        /// Also trace the mesh's exact reference for an N × N frame and print its time and
        /// coverage.
        #[arg(long, value_name = "N")]
        reference: Option<u32>,
    },
}

pub fn run(a: &SceneArgs) -> anyhow::Result<()> {
    let SceneCommand::Check { file, reference } = &a.command;
    let scene = relief_runtime::load_scene_file(file)?;
    println!("{scene}");
    if scene.mesh.is_none() {
        return Ok(());
    }
    let ms = MeshScene::from_scene(scene)?;
    if let Some(w) = ms.notes.warning() {
        eprintln!("{w}");
    }
    println!("mesh {}: {} vertices, {} triangles", ms.mesh.name, ms.mesh.positions.len(), ms.mesh.triangles.len());
    if let Some(n) = *reference {
        anyhow::ensure!((1..=4096).contains(&n), "--reference {n}: expected a frame side from 1 to 4096");
        let start = Instant::now();
        let r = ms.reference().context("the exact reference")?;
        let built = start.elapsed().as_secs_f64();
        let hits = r.trace_all(&ms.rays(n, n));
        let total = start.elapsed().as_secs_f64();
        let covered = hits.iter().filter(|h| h.is_some()).count();
        println!(
            "reference {n}x{n}: {} patches, built in {built:.2} s, traced in {:.2} s; {covered} of {} pixels covered",
            r.patch_count(),
            total - built,
            hits.len()
        );
    }
    Ok(())
}
