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
    let gpu = Gpu::new()?;
    let methods = stability::methods();
    let scenes: Vec<&str> =
        if a.scene.is_empty() { stability::SCENES.to_vec() } else { a.scene.iter().map(String::as_str).collect() };
    let total = (scenes.len() * stability::ANGLES.len()) as u64;
    let bar = if std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        indicatif::ProgressBar::new(total)
    } else {
        indicatif::ProgressBar::hidden()
    };
    let cells = stability::run(&gpu, a.size, &methods, &scenes, &stability::ANGLES, |scene, angle| {
        bar.set_message(format!("{scene} at {angle}°"));
        bar.inc(1);
    })?;
    bar.finish_and_clear();
    stability::write(&a.out, &cells)?;
    let nan: usize = cells.iter().map(|c| c.nan_count).sum();
    let outside: usize = cells.iter().map(|c| c.outside_count).sum();
    println!(
        "{} methods × {} conditions: {nan} NaN hits, {outside} hits outside the volume → {}",
        methods.len(),
        total,
        a.out.join("stability.csv").display()
    );
    Ok(())
}
