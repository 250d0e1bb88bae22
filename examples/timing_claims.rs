//! The timing figures behind the dissertation's two contested timing claims (Burger 2018,
//! Table 4.5: an interval step costs more than a binary step; Table 4.11: cone normal
//! stepping is slower than CSM), measured twice with paired timing: once on the machine as
//! it is and once beside CPU hogs (`yes > /dev/null`, one per core); and the SIMD-32 cost
//! model of every pipeline of Table 4.7 on the real map `rocks`.
//!
//! ```sh
//! LP_NUM_THREADS=1 cargo run --release --example timing_claims -- [--out out/timing_claims] [--size 256] [--frames 50] [--no-hog]
//! ```
//!
//! Writes `OUT/idle`, `OUT/hog` and `OUT/t4.7_rocks` (sweep folders with their reports) and
//! prints the figures, also written to `OUT/timing_claims.md`. Takes a few minutes.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

use relief::runtime::report::{self, Verdict};
use relief::runtime::results::{self, Row};
use relief::runtime::sweep::{self, grids, NamedGrid};
use relief::runtime::Ratio;
use relief::Pipeline;

type Error = Box<dyn std::error::Error>;

/// CPU hogs, one per core, killed (by their own handles) when dropped.
struct Hogs(Vec<Child>);

impl Hogs {
    fn start() -> Result<Hogs, Error> {
        let n = std::thread::available_parallelism().map(|n| n.get()).unwrap_or(2);
        let hogs = (0..n).map(|_| Command::new("yes").stdout(Stdio::null()).spawn()).collect::<Result<Vec<_>, _>>()?;
        Ok(Hogs(hogs))
    }
}

impl Drop for Hogs {
    fn drop(&mut self) {
        for c in &mut self.0 {
            let _ = c.kill();
            let _ = c.wait();
        }
    }
}

struct Args {
    out: PathBuf,
    size: u32,
    frames: u32,
    hog: bool,
}

fn args() -> Result<Args, Error> {
    let mut a = Args { out: "out/timing_claims".into(), size: 256, frames: 50, hog: true };
    let mut it = std::env::args().skip(1);
    while let Some(k) = it.next() {
        let mut value = || it.next().ok_or_else(|| format!("{k} needs a value"));
        match k.as_str() {
            "--out" => a.out = value()?.into(),
            "--size" => a.size = value()?.parse()?,
            "--frames" => a.frames = value()?.parse()?,
            "--no-hog" => a.hog = false,
            other => {
                return Err(
                    format!("unknown argument `{other}` (expected --out DIR, --size N, --frames N, --no-hog)").into()
                )
            }
        }
    }
    Ok(a)
}

/// The built-in grids `names`, as one grid.
fn union(names: &[&str], scenes: Option<&[String]>) -> NamedGrid {
    let mut cells = Vec::new();
    for g in grids::builtin(scenes).into_iter().filter(|g| names.contains(&g.name.as_str())) {
        for c in g.cells {
            if !cells.contains(&c) {
                cells.push(c);
            }
        }
    }
    NamedGrid { name: names.join("+"), description: format!("Burger 2018 {}", names.join(", ")), cells }
}

fn sweep_into(grid: NamedGrid, out: &Path, size: u32, frames: u32) -> Result<Vec<Row>, Error> {
    sweep::run(&sweep::Options {
        grid,
        size,
        frames,
        warmup: 3,
        out: out.to_path_buf(),
        progress: true,
        overrides: Default::default(),
        shard: None,
        gpu_cost: None,
    })?;
    Ok(results::read(out)?.rows.into_iter().filter(|r| r.status.is_ok()).collect())
}

fn ratio(r: &Row) -> Ratio {
    Ratio::to_baseline(&r.metrics).unwrap_or(Ratio::point(f64::NAN))
}

/// `a` ÷ `b` from their ratios to the baseline, with the verdict "a slower".
fn quotient_line(rows: &[Row], a: &str, b: &str) -> String {
    let find = |p: &str| {
        let p = p.parse::<Pipeline>().ok()?;
        rows.iter().find(|r| r.metrics.pipeline == p)
    };
    match (find(a), find(b)) {
        (Some(x), Some(y)) => {
            let q = ratio(x).over(&ratio(y));
            let says = match q.above(1.0) {
                Some(true) => "slower",
                Some(false) => "not slower",
                None => "not decided",
            };
            let model = x.metrics.simd32_fetches / y.metrics.simd32_fetches;
            format!("| `{a}` ÷ `{b}` | {q} | {says} | {model:.3} |")
        }
        _ => format!("| `{a}` ÷ `{b}` | not measured | | |"),
    }
}

fn claims(md: &mut String, label: &str, out: &Path, rows: &[Row]) -> Result<(), Error> {
    let _ = writeln!(md, "\n## {label}\n\n| cells | frame-time quotient (95 %) | A is | model (simd32_fetches) A ÷ B |\n| --- | --- | --- | --- |");
    for k in 1..=6 {
        md.push_str(&quotient_line(rows, &format!("linear(10)+interval({k})"), &format!("linear(10)+binary({k})")));
        md.push('\n');
    }
    for form in ["safe", "textbook"] {
        for n in [5, 8, 10, 15, 20, 30] {
            let cns = format!("cns({n}, form={form})+binary(5)");
            // The report's reading: the safe form reads every cone map unfiltered (its default
            // sampling), the textbook CSM with nearest filtering like CNS.
            let csm = if form == "safe" {
                format!("csm({n})+binary(5)")
            } else {
                format!("csm({n}, form=textbook, sample=nearest)+binary(5)")
            };
            md.push_str(&quotient_line(rows, &cns, &csm));
            md.push('\n');
        }
    }
    let s = report::write(out)?;
    let _ = writeln!(md, "\nThe report's verdicts (on the paired ratios, and on the model):\n");
    for c in s.conclusions.iter().filter(|c| c.reads_time && (c.table == "4.5" || c.table == "4.11")) {
        let form = if c.form.is_empty() { String::new() } else { format!(" [form={}]", c.form) };
        let model = c.model.unwrap_or(Verdict::NotMeasured);
        let _ = writeln!(
            md,
            "- {} {}{form}: **{}** ({}); model: **{}** ({})",
            c.table, c.claim, c.ours_mse, c.evidence_mse, model, c.evidence_model
        );
    }
    Ok(())
}

fn main() -> Result<(), Error> {
    let a = args()?;
    std::fs::create_dir_all(&a.out)?;
    let mut md = String::from("# Timing claims of Tables 4.5 and 4.11, and the SIMD-32 cost of Table 4.7 on rocks\n");
    let g = relief::runtime::gpu::Gpu::new()?;
    let _ = writeln!(
        md,
        "\nAdapter: {} ({}); frames {}², {} timed blocks per cell against `{}`; {} cores.",
        g.adapter,
        g.driver,
        a.size,
        a.frames,
        relief::runtime::measure::BASELINE,
        std::thread::available_parallelism().map(|n| n.get()).unwrap_or(0)
    );
    drop(g);
    let grid = || union(&["t4.5", "t4.11"], None);
    let idle = a.out.join("idle");
    let rows = sweep_into(grid(), &idle, a.size, a.frames)?;
    claims(&mut md, "Run 1: the machine as it is", &idle, &rows)?;
    if a.hog {
        let hog = a.out.join("hog");
        let rows = {
            let _hogs = Hogs::start()?;
            sweep_into(grid(), &hog, a.size, a.frames)?
        };
        claims(&mut md, "Run 2: beside CPU hogs (`yes > /dev/null`, one per core)", &hog, &rows)?;
    }
    let rocks = a.out.join("t4.7_rocks");
    let rows = sweep_into(union(&["t4.7"], Some(&["scene:rocks".to_string()])), &rocks, a.size, 4)?;
    let _ = writeln!(
        md,
        "\n## Table 4.7 on rocks: the SIMD cost model\n\n| pipeline | simd32_steps | simd64_steps | simd32_fetches | simd32_divergence | avg_fetches | mse_dissertation_mean |\n| --- | --- | --- | --- | --- | --- | --- |"
    );
    for r in &rows {
        let m = &r.metrics;
        let _ = writeln!(
            md,
            "| `{}` | {:.2} | {:.2} | {:.2} | {:.3} | {:.2} | {:.3e} |",
            m.pipeline,
            m.simd32_steps,
            m.simd64_steps,
            m.simd32_fetches,
            m.simd32_divergence,
            m.avg_fetches,
            m.mse_dissertation_mean
        );
    }
    std::fs::write(a.out.join("timing_claims.md"), &md)?;
    println!("{md}");
    Ok(())
}
