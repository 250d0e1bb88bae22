//! `relief stability`: every coarse × refine method on every stress condition.

use std::path::PathBuf;

use relief_runtime::gpu::Gpu;
use relief_runtime::stability;

/// Arguments of `relief stability`.
#[derive(clap::Args, Debug)]
pub struct StabilityArgs {
    /// Rays per side (size² rays per method and condition).
    #[arg(long, default_value_t = 128)]
    pub size: u32,
    /// Output folder.
    #[arg(long, default_value = "out/stability")]
    pub out: PathBuf,
    /// Scenes to probe (a built-in NAME, `scene:NAME`, `seam`, a TOML scene file or a
    /// height-map file); repeatable. Default: the whole stability matrix.
    #[arg(long)]
    pub scene: Vec<String>,
    /// Mesh conditions to probe (`sphere`, `torus`: the built-in mesh with each of the real
    /// maps `rocks` and `four` at 75°, 85° and 89°, each method under curved=none, quadric and
    /// prism; at --size 64 both take about 26 s on a loaded two-core machine); repeatable.
    /// Default: both when no --scene is given, none otherwise.
    #[arg(long)]
    pub mesh: Vec<String>,
    /// Leave the mesh conditions out.
    #[arg(long, conflicts_with = "mesh")]
    pub no_meshes: bool,
    /// When another relief process holds the output folder's lock (`OUT/.relief.lock`),
    /// wait for it instead of refusing.
    #[arg(long)]
    pub wait: bool,
}

/// Runs `relief stability`.
pub fn run(a: &StabilityArgs) -> anyhow::Result<()> {
    if a.size == 0 || a.size > 1024 {
        anyhow::bail!("--size {} is out of range: allowed 1..=1024", a.size);
    }
    std::fs::create_dir_all(&a.out)
        .map_err(|e| anyhow::anyhow!("cannot create output folder {}: {e}", a.out.display()))?;
    let _lock = crate::lock_folders(&[&a.out], a.wait)?;
    let methods = stability::methods();
    let scenes: Vec<&str> =
        if a.scene.is_empty() { stability::SCENES.to_vec() } else { a.scene.iter().map(String::as_str).collect() };
    let meshes: Vec<&str> = if a.no_meshes {
        vec![]
    } else if a.mesh.is_empty() && a.scene.is_empty() {
        stability::MESH_SCENES.iter().map(|(m, _)| *m).collect()
    } else {
        a.mesh.iter().map(String::as_str).collect()
    };
    for m in &meshes {
        if !stability::MESH_SCENES.iter().any(|(n, _)| n == m) {
            anyhow::bail!("--mesh {}: no such mesh condition (sphere, torus)", relief_dsl::spec::echo(m));
        }
    }
    // The device is opened once the arguments are known good: a refusal waits on no GPU.
    let gpu = Gpu::new()?;
    let flat_conditions = scenes.len() * stability::ANGLES.len();
    let mesh_conditions = meshes.len() * stability::MESH_MAPS.len() * stability::MESH_ANGLES.len();
    let total = (flat_conditions + mesh_conditions) as u64;
    let bar = if std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        indicatif::ProgressBar::new(total)
    } else {
        indicatif::ProgressBar::hidden()
    };
    let tick = |scene: &str, angle: f32| {
        bar.set_message(format!("{scene} at {angle}°"));
        bar.inc(1);
    };
    let mut cells = stability::run(&gpu, a.size, &methods, &scenes, &stability::ANGLES, tick)?;
    let mesh_methods = stability::mesh_methods();
    if !meshes.is_empty() {
        let modes = relief_dsl::spec::Curved::ALL;
        cells.extend(stability::run_meshes(
            &gpu,
            a.size,
            &mesh_methods,
            &modes,
            &meshes,
            &stability::MESH_MAPS,
            &stability::MESH_ANGLES,
            tick,
        )?);
    }
    bar.finish_and_clear();
    stability::write(&a.out, &cells)?;
    let nan: usize = cells.iter().map(|c| c.nan_count).sum();
    let outside: usize = cells.iter().map(|c| c.outside_count).sum();
    let mesh_part = if meshes.is_empty() {
        String::new()
    } else {
        format!(", {} methods × 3 curved= modes × {mesh_conditions} mesh conditions", mesh_methods.len())
    };
    println!(
        "{} methods × {flat_conditions} conditions{mesh_part}: {nan} NaN hits, {outside} hits outside the volume → {}",
        methods.len(),
        a.out.join("stability.csv").display()
    );
    Ok(())
}
