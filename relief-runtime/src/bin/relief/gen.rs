//! `relief gen`: shader files for pipelines.

use std::path::PathBuf;

use anyhow::{bail, Context};
use relief_dsl::spec::{catalog, Pipeline, Slot};

/// Arguments of `relief gen`.
#[derive(clap::Args, Debug)]
pub struct GenArgs {
    /// Pipelines in the text form, e.g. `linear(10)+binary(5)`.
    pub pipelines: Vec<String>,
    /// Every combination of the stages at default parameters (coarse × refine × shadow).
    #[arg(long, conflicts_with = "pipelines")]
    pub all: bool,
    /// List the stages, their parameters and defaults.
    #[arg(long)]
    pub list: bool,
    /// Output folder (created when missing).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// The stage listing of `relief gen --list`.
pub fn listing() -> String {
    let mut s = String::new();
    for slot in Slot::ALL {
        s.push_str(&format!("{slot}:\n"));
        for m in catalog().iter().filter(|m| m.slot == slot) {
            let params: Vec<String> = m
                .params
                .iter()
                .map(|p| match &p.default {
                    Some(d) => format!("{}={d}", p.name),
                    None => p.name.to_string(),
                })
                .collect();
            let sig = if params.is_empty() { m.name.to_string() } else { format!("{}({})", m.name, params.join(", ")) };
            let state = if m.implemented { "" } else { " [not implemented yet]" };
            s.push_str(&format!("  {sig:<28} {}{state}\n", m.summary));
            for p in &m.params {
                s.push_str(&format!("  {:<28}   {}: {}\n", "", p.name, p.kind.describe()));
            }
        }
    }
    s
}

/// Runs `relief gen`.
pub fn run(args: &GenArgs) -> anyhow::Result<()> {
    if args.list {
        print!("{}", listing());
        return Ok(());
    }
    let pipelines: Vec<Pipeline> = if args.all {
        Pipeline::all_defaults()
    } else if args.pipelines.is_empty() {
        bail!("name at least one pipeline (e.g. `relief gen 'linear(10)+binary(5)' --out shaders`), or use --all or --list");
    } else {
        args.pipelines
            .iter()
            .map(|t| t.parse::<Pipeline>().map_err(|e| anyhow::anyhow!("pipeline `{t}`: {e}")))
            .collect::<Result<_, _>>()?
    };
    let Some(out) = &args.out else {
        bail!("--out DIR is required to write shader files");
    };
    std::fs::create_dir_all(out).with_context(|| format!("cannot create output folder {}", out.display()))?;
    for p in &pipelines {
        relief_runtime::io::write_pipeline(p, out)?;
    }
    println!(
        "wrote {} pipeline(s) × 5 files (.wgsl .spv .vert.glsl .frag.glsl .comp.glsl) to {}",
        pipelines.len(),
        out.display()
    );
    Ok(())
}
