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
    /// Browser results files (the live section's "measure on this GPU" button) to add to
    /// the one sweep folder first: their raw probe hits are scored as the sweep scores its
    /// own, and the rows go into its results.jsonl under the browser's adapter
    /// (docs/browser.md).
    #[arg(long, num_args = 1.., value_name = "FILE")]
    pub add: Vec<PathBuf>,
    /// With --add: replace the rows an earlier add recorded under the same adapter (without
    /// it, adding an adapter that already has rows is refused).
    #[arg(long, requires = "add")]
    pub replace: bool,
    /// When another relief process (a sweep) holds one of the folders' locks
    /// (`DIR/.relief.lock`), wait for it instead of refusing.
    #[arg(long)]
    pub wait: bool,
}

/// Runs `relief report`.
pub fn run(a: &ReportArgs) -> anyhow::Result<()> {
    let out = a.out.clone().unwrap_or_else(|| a.dirs[0].clone());
    // Every folder read and the one written, for as long as the report runs; a folder that
    // does not exist is left to the report to refuse.
    let mut locked: Vec<&std::path::Path> = a.dirs.iter().filter(|d| d.is_dir()).map(|d| d.as_path()).collect();
    if a.dirs.iter().all(|d| d.is_dir()) {
        locked.push(&out);
    }
    let _lock = crate::lock_folders(&locked, a.wait)?;
    if !a.add.is_empty() {
        if a.dirs.len() != 1 {
            anyhow::bail!("--add adds to one sweep folder; {} were given", a.dirs.len());
        }
        for added in report::add(&a.dirs[0], &a.add, a.replace)? {
            println!(
                "{}: {} rows added under `{}`{}{}",
                added.file,
                added.rows,
                added.adapter,
                if added.replaced > 0 { format!(" ({} earlier rows replaced)", added.replaced) } else { String::new() },
                if added.set_aside.is_empty() {
                    String::new()
                } else {
                    format!("; {} set aside", added.set_aside.len())
                }
            );
            for s in &added.set_aside {
                println!("  set aside: {s}");
            }
        }
    }
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
