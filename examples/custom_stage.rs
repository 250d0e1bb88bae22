//! A coarse search defined outside relief, registered, and swept against a built-in one like
//! any other stage.
//!
//! `geometric(steps, growth)` is a linear search whose step grows by `growth` percent each
//! time: short steps near the top of the volume, where a grazing ray meets the first bump,
//! longer ones deeper down. The `steps` steps still reach the bottom of the volume (t = 1):
//! with `r = 1 + growth/100`, the first step is `(r - 1) / (r^steps - 1)` (`1/steps` at
//! growth 0, which is `linear(steps)`).
//!
//! The sweep measures `geometric(16, 10)` and `geometric(16, 0)` against `linear(16)`
//! (frame time, accuracy against the exact reference) on the procedural `rock_bump` scene,
//! into the folder given as the first argument, or `relief-custom-stage-example` in the
//! system's temporary folder, and prints its rows.
//!
//! `LP_NUM_THREADS=1 cargo run --release --example custom_stage -- out/custom-stage`

use std::path::{Path, PathBuf};

use relief::dsl::ir::{FnBuilder, Var};
use relief::dsl::spec::{register, Args, MethodDef, ParamDef};
use relief::dsl::stage::{Bracket, Ray, StageFn};
use relief::dsl::CompileError;
use relief::runtime::results::{self, Row};
use relief::runtime::sweep::{self, NamedGrid};
use relief::Pipeline;

type Error = Box<dyn std::error::Error + Send + Sync>;

/// The first step of `steps` steps growing by the ratio `r` that add up to 1.
fn first_step(steps: u32, r: f64) -> f64 {
    if r == 1.0 {
        1.0 / steps as f64
    } else {
        (r - 1.0) / (r.powi(steps as i32) - 1.0)
    }
}

/// The search: stop at the first point at or below the surface; the bracket runs from the
/// point before it (never before the entry) to it.
fn geometric<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>, a: &Args) -> Result<Bracket<'a>, CompileError> {
    let steps = a.int("steps")?;
    let r = 1.0 + a.int("growth")? as f64 / 100.0;
    let t: Var<f32> = s.var("t", 0.0);
    let step: Var<f32> = s.var("step", first_step(steps, r) as f32);
    let last: Var<f32> = s.var("last", 0.0);
    s.repeat(steps, |s| {
        let p = ray.at(t.get());
        s.break_if(s.height(p.xy()).ge(p.z()));
        last.set(step.get());
        t.set(t.get() + step.get());
        step.set(step.get() * r as f32);
    });
    Ok(Bracket::new((t.get() - last.get()).max(0.0), t.get()))
}

/// The stage function of `geometric`: a coarse stage.
pub fn stage_fn() -> StageFn {
    StageFn::Coarse(geometric)
}

/// Adds `geometric(steps, growth)` to the catalogue, declared the way relief declares its
/// own methods (once per process; a second call finds it there).
pub fn register_geometric() -> Result<(), Error> {
    let def = MethodDef::new(
        "geometric",
        "linear search whose step grows by growth% each step (an example stage, examples/custom_stage.rs)",
        stage_fn(),
    )
    .param(ParamDef::steps("steps", 16))
    .param(ParamDef::count("growth", 0, 100, 10));
    match register(def) {
        Ok(()) => Ok(()),
        Err(_) if relief::dsl::spec::method(relief::Slot::Coarse, "geometric").is_some() => Ok(()),
        Err(e) => Err(e.into()),
    }
}

/// Registers the stage, sweeps it against `linear(16)` into `out` and returns the rows.
pub fn run(out: &Path) -> Result<Vec<Row>, Error> {
    register_geometric()?;
    let pipelines =
        ["linear(16)", "geometric(16)", "geometric(16, 0)", "geometric(16, 25)+binary(5)", "linear(16)+binary(5)"];
    let cells = pipelines
        .iter()
        .map(|p| Ok((p.parse::<Pipeline>()?, "rock_bump".to_string())))
        .collect::<Result<Vec<_>, Error>>()?;
    let options = sweep::Options {
        grid: NamedGrid { name: "custom-stage".into(), description: "geometric against linear".into(), cells },
        size: 64,
        frames: 3,
        warmup: 1,
        out: out.to_path_buf(),
        progress: false,
        overrides: Default::default(),
        shard: None,
        gpu_cost: None,
    };
    sweep::run(&options).map_err(|e| e.to_string())?;
    Ok(results::read(out).map_err(|e| e.to_string())?.rows)
}

#[allow(dead_code)]
fn main() -> Result<(), Error> {
    let out = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| std::env::temp_dir().join("relief-custom-stage-example"));
    let rows = run(&out)?;
    println!("{:<32} {:>9} {:>14} {:>12}", "pipeline", "frame ms", "ref t rms", "coarse steps");
    for r in &rows {
        let m = &r.metrics;
        println!(
            "{:<32} {:>9.3} {:>14.6} {:>12.2}  {}",
            m.pipeline, m.frame_ms_median, m.ref_err_t_rms, m.avg_coarse_steps, r.status
        );
    }
    Ok(())
}
