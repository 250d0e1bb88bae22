//! `relief tune`: the fastest `frontier` pipeline reaching an RMS t error and skipping no
//! geometry at every view asked, timed on this machine's adapter against Bevy's default
//! (`relief_runtime::tune`); with `--target` and `--out`, `relief export`'s bundle for it.
//!
//! ```text
//! relief tune MAP --error E [--view A]... [--size 256] [--frames 20] [--target T --out DIR [--force]]
//! relief tune rocks --error 1e-2 --view 45 --view 70 --target glsl-es --out bundle/
//! ```

use std::io::IsTerminal;
use std::path::PathBuf;

use anyhow::bail;
use relief_runtime::tune::{self, Checked, Tuned};
use relief_runtime::{scene_from_arg, scene_spec};

/// Arguments of `relief tune`.
#[derive(clap::Args, Debug)]
pub struct TuneArgs {
    /// The map: `scene:NAME` (a bare NAME works too), a TOML scene file or a height-map file,
    /// as `relief render --scene` takes it.
    pub map: String,
    /// The goal: RMS t error (`ref_err_t_rms`) at most this, with no ray that skipped geometry.
    #[arg(long, allow_negative_numbers = true)]
    pub error: f64,
    /// A view, degrees from the surface normal (repeatable, or a list `30,60,80`; default 30,
    /// 60 and 80), at the map's depth scale.
    #[arg(long = "view", visible_alias = "angle", value_delimiter = ',', allow_negative_numbers = true)]
    pub views: Vec<f32>,
    /// Frame size in pixels (square).
    #[arg(long, default_value_t = 256)]
    pub size: u32,
    /// Timed blocks per timed cell, the cell's and Bevy's default's together.
    #[arg(long, default_value_t = 20)]
    pub frames: u32,
    /// Write `relief export`'s bundle of the pick for this library form (with `--out`).
    #[arg(long, requires = "out")]
    pub target: Option<String>,
    /// The bundle's folder (with `--target`).
    #[arg(long, requires = "target")]
    pub out: Option<PathBuf>,
    /// The bundle's texture container: ktx2 or dds.
    #[arg(long, default_value = "ktx2")]
    pub container: String,
    /// Write the bundle into a folder that already holds files.
    #[arg(long)]
    pub force: bool,
    /// Leave out the GPU compiler's modeled cost (RADV).
    #[arg(long)]
    pub no_gpu_cost: bool,
}

/// `0.82× [0.79, 0.85]`.
fn times(r: &relief_runtime::Ratio) -> String {
    if r.lo.is_finite() && r.hi.is_finite() {
        format!("{:.2}× [{:.2}, {:.2}]", r.ratio, r.lo, r.hi)
    } else {
        format!("{:.2}×", r.ratio)
    }
}

fn degrees(angles: &[f32]) -> String {
    angles.iter().map(|a| format!("{a}°")).collect::<Vec<_>>().join(", ")
}

/// Runs `relief tune`.
pub fn run(a: &TuneArgs) -> anyhow::Result<()> {
    let angles = if a.views.is_empty() { tune::DEFAULT_ANGLES.to_vec() } else { a.views.clone() };
    let opts = tune::Options {
        error: a.error,
        angles,
        size: a.size,
        frames: a.frames,
        warmup: 3,
        progress: std::io::stderr().is_terminal(),
        gpu_cost: if a.no_gpu_cost {
            None
        } else {
            std::env::current_exe().ok().map(relief_runtime::cost::Compiler::new)
        },
    };
    opts.check()?;
    if a.frames == 0 || a.frames > 100_000 {
        bail!("--frames {} is out of range: allowed 1..=100000", a.frames);
    }
    // The bundle's arguments are checked before any measurement.
    if let (Some(target), Some(out)) = (&a.target, &a.out) {
        relief_dsl::emit::LibraryForm::from_name(target)?;
        crate::export::check_container(&a.container)?;
        crate::export::check_out(out, a.force)?;
    }
    let scene = scene_from_arg(&scene_spec(&a.map))?;
    let t = tune::run(&scene, &opts)?;
    print(&t);
    let Some(pick) = &t.pick else {
        let closest = match t.closest() {
            Some(c) => format!(
                "; the closest measured: {} (t error {:.3e}, skipped_rate {:.4} at {}°)",
                c.pipeline, c.err, c.skipped, c.angle
            ),
            None => String::new(),
        };
        let why = if t.open.is_empty() {
            "no frontier pipeline reaches".to_string()
        } else {
            format!("within {} measurements no frontier pipeline was found reaching", t.budget)
        };
        bail!(
            "{why} t error ≤ {:e} with no skipped geometry at {} on {}{closest}",
            t.error,
            degrees(&t.angles),
            t.scene
        );
    };
    if let (Some(target), Some(out)) = (&a.target, &a.out) {
        crate::export::run(&crate::export::ExportArgs {
            pipeline: pick.to_string(),
            scene: a.map.clone(),
            target: target.clone(),
            container: a.container.clone(),
            out: out.clone(),
            force: a.force,
            group: None,
            import_path: None,
        })?;
    }
    Ok(())
}

/// The answer on stdout: the pick, the axis that decided, the runners-up, the count.
fn print(t: &Tuned) {
    println!(
        "goal: t error ≤ {:e} and skipped_rate = 0 at {} on {}, {}²; timed at {}° against Bevy's default {} on {}",
        t.error,
        degrees(&t.angles),
        t.scene,
        t.size,
        t.angles[0],
        tune::BEVY_DEFAULT,
        t.adapter
    );
    let model =
        |m: Option<f64>| m.map(|v| format!(", model (RDNA2, not a clock): {v:.0} instr/px")).unwrap_or_default();
    if let Some(p) = t.pick() {
        println!(
            "pick: {}  frame ÷ Bevy's {}, t error ≤ {:.3e} at every view{}",
            p.pipeline,
            times(&p.speed),
            p.err,
            model(p.model_navi21)
        );
        let (n, fastest) = t.faster_missing();
        let mut decided = Vec::new();
        if let Some(c) = fastest {
            decided.push(format!(
                "accuracy: {n} faster pipeline(s) missed the goal, the fastest {} ({}, t error {:.3e}, skipped_rate {:.4} at {}°)",
                c.pipeline,
                c.speed.map(|s| times(&s)).unwrap_or_default(),
                c.err,
                c.skipped,
                c.angle
            ));
        }
        if let Some(r) = t.candidates.iter().find(|c| c.pipeline != p.pipeline) {
            let q = p.speed.over(&r.speed);
            let verdict = if q.lo.is_finite() && q.hi.is_finite() && q.lo <= 1.0 && 1.0 <= q.hi {
                "not decided: a tie within the interval"
            } else {
                "decided"
            };
            decided.push(format!("clock: {} over the runner-up {}, {verdict}", times(&q), r.pipeline));
        }
        if decided.is_empty() {
            decided.push("the only pipeline measured that reaches the goal".into());
        }
        println!("decided by {}", decided.join("; "));
        println!("runners-up (reaching the goal at {}°, fastest first):", t.angles[0]);
        let mut shown = 0;
        for c in t.candidates.iter().filter(|c| c.pipeline != p.pipeline).take(tune::RUNNERS_UP) {
            let standing = match &c.checked {
                Checked::Every => "reaches it at every view".to_string(),
                Checked::Misses(v) => format!("misses it at {v}°"),
                Checked::Slower => "other views not probed (slower)".to_string(),
            };
            println!(
                "  {}  frame ÷ Bevy's {}, ÷ pick {}, t error {:.3e}, {standing}{}",
                c.pipeline,
                times(&c.speed),
                times(&c.speed.over(&p.speed)),
                c.err,
                model(c.model_navi21)
            );
            shown += 1;
        }
        if shown == 0 {
            println!("  none");
        }
    }
    if !t.open.is_empty() {
        println!("the budget ran out with these families open: {}", t.open.join(", "));
    }
    println!(
        "measured {} of the frontier grid's {} cells at these views (budget {}: a quarter)",
        t.cells.len(),
        t.grid_cells,
        t.budget
    );
}
