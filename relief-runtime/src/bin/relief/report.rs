//! `relief report DIR…`: tables, conclusions, charts, strips and Pareto fronts from one sweep
//! folder, or from several merged (shards, machines), adapters kept apart.

use std::path::PathBuf;

use relief_runtime::report;

/// Arguments of `relief report`.
#[derive(clap::Args, Debug)]
pub struct ReportArgs {
    /// The sweep folders (the `--out` of `relief sweep`, each holding results.jsonl); several
    /// are merged into one report, each adapter's rows kept apart.
    #[arg(required = true)]
    pub dirs: Vec<PathBuf>,
    /// Where the report goes (default: the first folder).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Runs `relief report`.
pub fn run(a: &ReportArgs) -> anyhow::Result<()> {
    let out = a.out.clone().unwrap_or_else(|| a.dirs[0].clone());
    let s = report::write_many(&a.dirs, &out)?;
    let (holds, fails, unmeasured, open) = s.verdict_counts();
    println!(
        "{} rows ({} ok, {} failed){}; conclusions by mse_dissertation_mean: {holds} hold, {fails} do not hold, {open} not decided, {unmeasured} not measured",
        s.rows,
        s.ok,
        s.failed.len(),
        if s.adapters.len() > 1 { format!(" from {} adapters", s.adapters.len()) } else { String::new() }
    );
    for w in &s.warnings {
        eprintln!("warning: {w}");
    }
    for l in &s.bad_lines {
        eprintln!("warning: skipped results line {l}");
    }
    println!("{} files → {}", s.files.len(), out.join("index.html").display());
    Ok(())
}
