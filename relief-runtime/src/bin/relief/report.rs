//! `relief report DIR`: tables, conclusions, charts, strips and Pareto fronts from a sweep.

use std::path::PathBuf;

use relief_runtime::report;

/// Arguments of `relief report`.
#[derive(clap::Args, Debug)]
pub struct ReportArgs {
    /// The sweep folder (the `--out` of `relief sweep`, holding results.jsonl).
    pub dir: PathBuf,
}

/// Runs `relief report`.
pub fn run(a: &ReportArgs) -> anyhow::Result<()> {
    let s = report::write(&a.dir)?;
    let (holds, fails, unmeasured) = s.verdict_counts();
    println!(
        "{} rows ({} ok, {} failed); conclusions by mse_dissertation_mean: {holds} hold, {fails} do not hold, {unmeasured} not measured",
        s.rows,
        s.ok,
        s.failed.len()
    );
    for w in &s.warnings {
        eprintln!("warning: {w}");
    }
    for l in &s.bad_lines {
        eprintln!("warning: skipped results line {l}");
    }
    println!("{} files → {}", s.files.len(), a.dir.join("index.html").display());
    Ok(())
}
