//! `relief gen`: shader files for pipelines.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context};
use relief_dsl::emit::LibraryForm;
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
    /// Write the stages as functions for your own shader instead of whole modules:
    /// `NAME.lib.wgsl`, `NAME.lib.glsl`, `NAME.lib.hlsl`, `NAME.lib.metal` (or the forms
    /// --target names).
    #[arg(long)]
    pub library: bool,
    /// With --library: the forms to write, comma-separated or repeated: wgsl, wesl, glsl,
    /// glsl-es (WebGL2), tsl (three.js WebGPU: WGSL with resources as arguments), hlsl, msl, unity (Shader Graph Custom Function), unreal (include +
    /// Custom node code), or all (default: wgsl,glsl,hlsl,msl).
    #[arg(long, value_delimiter = ',', requires = "library")]
    pub target: Vec<String>,
    /// With --library: the bind group (descriptor set, register space) of the resources.
    #[arg(long, default_value_t = 0, requires = "library")]
    pub group: u32,
    /// With --library: the first binding; the resources take consecutive bindings from it.
    #[arg(long, default_value_t = 0, requires = "library")]
    pub binding: u32,
    /// With --library: the name every global, function and type starts with.
    #[arg(long, default_value = "relief", requires = "library")]
    pub prefix: String,
    /// With --library: start the WGSL file with `#define_import_path PATH` (naga_oil / WESL);
    /// `NAME` in PATH becomes the pipeline's file name (`-` → `_`), e.g. `relief::NAME`.
    #[arg(long, requires = "library")]
    pub import_path: Option<String>,
    /// With --library: the edge mode the stages that address texels themselves assume
    /// (maxmip, the cell cone reads, glsl-es's gathers); it must match your samplers' address
    /// mode (glsl-es: define RELIEF_EDGE_REPEAT or RELIEF_EDGE_CLAMP to say so).
    #[arg(long, value_parser = ["repeat", "clamp"], default_value = "repeat", requires = "library")]
    pub edge: String,
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
            s.push_str(&format!("  {sig:<28} {}\n", m.summary));
            for p in &m.params {
                s.push_str(&format!("  {:<28}   {}: {}\n", "", p.name, p.kind.describe()));
            }
        }
    }
    s
}

/// The forms `--target` names (every form for `all`, the default four when none).
pub fn forms(args: &GenArgs) -> anyhow::Result<Vec<LibraryForm>> {
    if args.target.is_empty() {
        return Ok(LibraryForm::DEFAULT.to_vec());
    }
    let mut forms = Vec::new();
    for name in &args.target {
        let named = if name == "all" {
            LibraryForm::ALL.to_vec()
        } else {
            vec![LibraryForm::from_name(name.trim()).map_err(|e| anyhow::anyhow!("--target: {}", e.message))?]
        };
        for f in named {
            if !forms.contains(&f) {
                forms.push(f);
            }
        }
    }
    Ok(forms)
}

/// The import path `--import-path TEMPLATE` gives `p`'s library (`relief gen` and `relief
/// export`): `NAME` becomes the pipeline's file name with `-` as `_` (an identifier).
pub fn import_path_of(template: &str, p: &Pipeline) -> String {
    template.replace("NAME", &p.file_stem().replace('-', "_"))
}

/// Writes the library files of `p` in `forms` into `out`; returns their names.
pub fn write_library(p: &Pipeline, args: &GenArgs, forms: &[LibraryForm], out: &Path) -> anyhow::Result<Vec<String>> {
    let opts = relief_dsl::emit::LibraryOptions {
        prefix: args.prefix.clone(),
        group: args.group,
        binding: args.binding,
        edge_clamp: args.edge == "clamp",
        import_path: args.import_path.as_deref().map(|t| import_path_of(t, p)),
    };
    let lib = relief_dsl::emit::library_forms(p, &opts, forms).with_context(|| format!("pipeline {p}"))?;
    for f in &lib.files {
        relief_runtime::io::write_atomic(&out.join(&f.name), f.text.as_bytes())?;
    }
    Ok(lib.files.into_iter().map(|f| f.name).collect())
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
            .map(|t| {
                t.parse::<Pipeline>().map_err(|e| anyhow::anyhow!("pipeline `{}`: {e}", relief_dsl::spec::echo(t)))
            })
            .collect::<Result<_, _>>()?
    };
    let Some(out) = &args.out else {
        bail!("--out DIR is required to write shader files");
    };
    std::fs::create_dir_all(out).with_context(|| format!("cannot create output folder {}", out.display()))?;
    if args.library {
        let forms = forms(args)?;
        let mut written = 0;
        let mut files = 0;
        let mut skipped = Vec::new();
        for p in &pipelines {
            // With --all, a pipeline no library can express is skipped and listed; a named one
            // is an error.
            if let Some(why) = relief_dsl::compose::library::inexpressible(p).filter(|_| args.all) {
                skipped.push(format!("{p}: {why}"));
                continue;
            }
            let mut here = forms.clone();
            if args.all {
                here.retain(|f| match relief_dsl::emit::inexpressible_in(p, *f) {
                    Some(why) => {
                        skipped.push(format!("{p} as {}: {why}", f.name()));
                        false
                    }
                    None => true,
                });
            }
            files += write_library(p, args, &here, out)?.len();
            written += 1;
        }
        let names: Vec<&str> = forms.iter().map(|f| f.name()).collect();
        println!("wrote {written} pipeline(s) as libraries ({}): {files} files to {}", names.join(", "), out.display());
        if !skipped.is_empty() {
            println!("skipped {} pipeline(s) or form(s) that a library cannot express:", skipped.len());
            for s in &skipped {
                println!("  {s}");
            }
        }
        return Ok(());
    }
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
