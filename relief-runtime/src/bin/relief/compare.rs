//! `relief compare A B`: two pipelines timed in alternating blocks on one scene; the ratio
//! of their mean frame times with its 95 % interval, and the SIMD cost model beside it.

use relief_runtime::gpu::Gpu;
use relief_runtime::measure::compare;
use relief_runtime::{scene_from_arg, scene_spec};

/// Arguments of `relief compare`.
#[derive(clap::Args, Debug)]
pub struct CompareArgs {
    /// Pipeline A in the text form, e.g. `linear(10)+interval(3)`.
    pub a: String,
    /// Pipeline B, e.g. `linear(10)+binary(3)`.
    pub b: String,
    /// The scene (`scene:NAME`, a bare NAME, a TOML scene file or a height-map file).
    #[arg(long, default_value = "scene:lion")]
    pub scene: String,
    #[command(flatten)]
    pub overrides: crate::OverrideArgs,
    /// Frame size in pixels (square).
    #[arg(long, default_value_t = 256)]
    pub size: u32,
    /// Pairs of blocks (A B, then B A, …); each block lasts at least 2 ms of device time.
    #[arg(long, default_value_t = 30)]
    pub pairs: u32,
}

/// Runs `relief compare`.
pub fn run(a: &CompareArgs) -> anyhow::Result<()> {
    let parse = |t: &str| {
        t.parse::<relief_dsl::Pipeline>().map_err(|e| anyhow::anyhow!("pipeline `{}`: {e}", relief_dsl::spec::echo(t)))
    };
    let (pa, pb) = (parse(&a.a)?, parse(&a.b)?);
    if a.size == 0 || a.size > 8192 {
        anyhow::bail!("--size {} is out of range: allowed 1..=8192", a.size);
    }
    if a.pairs < 2 || a.pairs > 100_000 {
        anyhow::bail!("--pairs {} is out of range: allowed 2..=100000 (an interval needs two pairs)", a.pairs);
    }
    let overrides = a.overrides.checked()?;
    let scene = overrides.apply(scene_from_arg(&scene_spec(&a.scene))?);
    let g = Gpu::new()?;
    let c = compare(&g, &scene, a.size, &pa, &pb, 3, a.pairs)?;
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    println!(
        "scene {}, {}², adapter {} ({}), timer tick {} ns",
        scene.name, a.size, g.adapter, g.driver, c.blocks.timestamp_period_ns
    );
    for (i, name) in ["A", "B"].iter().enumerate() {
        let (ms, k) = (if i == 0 { &c.blocks.a_ms } else { &c.blocks.b_ms }, c.blocks.frames_per_block[i]);
        let s = &c.cost[i];
        println!(
            "{name} {}: mean frame {:.4} ms ({} blocks of {k} frames); model: simd32_fetches {:.2}, simd32_steps {:.2}, simd64_steps {:.2}, simd32_divergence {:.3}",
            c.pipelines[i],
            mean(ms),
            ms.len(),
            s.simd32_fetches,
            s.simd32_steps,
            s.simd64_steps,
            s.simd32_divergence
        );
    }
    println!("frame time A / B: {}", c.ratio);
    println!("model (simd32_fetches) A / B: {:.3}", c.cost[0].simd32_fetches / c.cost[1].simd32_fetches);
    Ok(())
}
