//! `relief cost PIPELINE…`: the GPU's own compiler prices each pipeline (AMD's, through
//! Mesa's RADV on its null device; no GPU needed): registers, spills, instructions, code
//! size, waves per SIMD and each loop's body, for the render entry's fragment shader and the
//! probe, per GPU family.

use std::path::PathBuf;

use anyhow::Context;
use relief_dsl::Pipeline;
use relief_runtime::cost::{self, Compiler, PipelineCost, ShaderCost};

/// Arguments of `relief cost`.
#[derive(clap::Args, Debug)]
pub struct CostArgs {
    /// Pipelines in the text form, e.g. `csm(64)` `linear_dynamic(1, 16)+binary(5)`.
    #[arg(required_unless_present_any = ["all", "grid"])]
    pub pipelines: Vec<String>,
    /// Every method at its default parameters (`relief gen --all`'s list).
    #[arg(long)]
    pub all: bool,
    /// Every pipeline a sweep of this grid measures (a built-in grid or a grid file, as
    /// `relief sweep --grid` takes it, with `--scene` and the view overrides), each as
    /// measured on its scene; repeatable. With `--json`, the file `relief sweep --gpu-costs`
    /// reads on a machine without RADV.
    #[arg(long, value_name = "GRID")]
    pub grid: Vec<String>,
    /// The scenes of `--grid` (as `relief sweep --scene`).
    #[arg(long, requires = "grid")]
    pub scene: Vec<String>,
    #[command(flatten)]
    pub overrides: crate::OverrideArgs,
    /// GPU families, comma-separated (Mesa's chip names: navi21 is RDNA2, gfx1100 RDNA3;
    /// default: navi21,gfx1100).
    #[arg(long, value_delimiter = ',', value_name = "FAMILY,…")]
    pub gpu: Vec<String>,
    /// Write each shader's disassembly into this folder (`STEM.FAMILY.fs.s`,
    /// `STEM.FAMILY.probe.s`).
    #[arg(long, value_name = "DIR")]
    pub isa: Option<PathBuf>,
    /// Write every figure as JSON to this file as well.
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
}

fn loops(s: &ShaderCost) -> String {
    if s.shape.loops.is_empty() {
        return "none".into();
    }
    s.shape
        .loops
        .iter()
        .map(
            |l| if l.depth == 0 { l.body.to_string() } else { format!("{}({})", l.body, "^".repeat(l.depth as usize)) },
        )
        .collect::<Vec<_>>()
        .join(" ")
}

fn line(what: &str, s: &ShaderCost) -> String {
    format!(
        "  {what:<5} wave{:<2} vgprs {:>3}  sgprs {:>3}  spills {}/{}  scratch {:>4}  instr {:>4}  code {:>5} B  waves/SIMD {:>2}  loops {}",
        s.subgroup_size,
        s.vgprs,
        s.sgprs,
        s.spilled_vgprs,
        s.spilled_sgprs,
        s.scratch_bytes,
        s.instructions,
        s.code_bytes,
        s.waves_per_simd,
        loops(s)
    )
}

/// Runs `relief cost`.
pub fn run(a: &CostArgs) -> anyhow::Result<()> {
    let mut pipelines: Vec<Pipeline> = if a.all { Pipeline::all_defaults() } else { vec![] };
    let overrides = a.overrides.checked()?;
    if a.grid.is_empty() && overrides != Default::default() {
        anyhow::bail!(
            "--view, --angle, --azimuth, --depth-scale and --tiling apply to --grid's scenes; no --grid given"
        );
    }
    for g in &a.grid {
        let scenes = if a.scene.is_empty() { None } else { Some(a.scene.as_slice()) };
        // What `relief sweep --grid` would measure: a grid of cells, the room comparison or the mesh grid.
        let grid = match relief_runtime::sweep::Plan::load(g, scenes)? {
            relief_runtime::sweep::Plan::Cells(grid) => grid,
            relief_runtime::sweep::Plan::Rooms(_) => anyhow::bail!(
                "--grid {g}: the room grid's pipelines are not priced (its walls are not relief pipelines)"
            ),
            relief_runtime::sweep::Plan::Meshes(scenes) => {
                // Each mode's pipeline once: the mesh modules are priced, not the scenes.
                pipelines.extend(relief_runtime::sweep::meshes::cells(&scenes).into_iter().map(|(p, _)| p));
                continue;
            }
        };
        pipelines.extend(relief_runtime::sweep::measured_pipelines(&grid, &overrides));
    }
    if !a.pipelines.is_empty() {
        let listed: Vec<Pipeline> = a
            .pipelines
            .iter()
            .map(|t| {
                t.parse::<Pipeline>().map_err(|e| anyhow::anyhow!("pipeline `{}`: {e}", relief_dsl::spec::echo(t)))
            })
            .collect::<Result<_, _>>()?;
        pipelines.extend(listed);
    }
    let mut seen = std::collections::HashSet::new();
    pipelines.retain(|p| seen.insert(p.to_string()));
    let families: Vec<String> = if a.gpu.is_empty() {
        cost::DEFAULT_FAMILIES.iter().map(|s| s.to_string()).collect()
    } else {
        a.gpu.iter().map(|f| cost::family(f)).collect::<Result<_, _>>()?
    };
    let exe = std::env::current_exe().context("cannot find relief's own program to run the compiler in")?;
    let compiler = Compiler::new(exe);
    let (mesh, pipelines): (Vec<Pipeline>, Vec<Pipeline>) = pipelines.into_iter().partition(|p| p.curved.is_some());
    if !mesh.is_empty() && a.json.is_some() {
        anyhow::bail!("--json is not implemented for curved= pipelines (their mesh modules); leave it out or price flat pipelines only");
    }
    if !mesh.is_empty() {
        mesh_costs(&compiler, &mesh, &families, a.isa.as_deref())?;
    }
    if pipelines.is_empty() {
        return Ok(());
    }
    let costs: Vec<PipelineCost> = compiler.cost(&pipelines, &families, a.isa.is_some())?;
    let mut last_family = String::new();
    for c in &costs {
        if c.family != last_family {
            println!("{} ({}, {}); loops: body in instructions, (^) nested", c.family, c.device, c.driver);
            last_family = c.family.clone();
        }
        let (bc, br, bl) = c.stage_bodies();
        println!("{}  [loop bodies: coarse {bc}, refine {br}, shadow+ao {bl}]", c.pipeline);
        println!("{}", line("fs", &c.fragment));
        println!("{}", line("probe", &c.probe));
    }
    if let Some(dir) = &a.isa {
        relief_runtime::io::create_dir_all(dir)?;
        for (c, p) in costs.iter().zip(pipelines.iter().cycle()) {
            let stem = p.file_stem();
            for (what, s) in [("fs", &c.fragment), ("probe", &c.probe)] {
                let path = dir.join(format!("{stem}.{}.{what}.s", c.family));
                relief_runtime::io::write_atomic(&path, s.isa.as_deref().unwrap_or("").as_bytes())?;
            }
        }
        println!("wrote the disassembly to {}", dir.display());
    }
    if let Some(path) = &a.json {
        let text = serde_json::to_string_pretty(&costs)?;
        relief_runtime::io::write_atomic(path, text.as_bytes())?;
    }
    Ok(())
}

/// Prices and prints the mesh modules of `mesh` (`curved=` pipelines): `vs_mesh`, `fs_mesh`
/// and `fs_mesh_depth` per family, and their disassembly into `isa` when given.
fn mesh_costs(
    compiler: &Compiler,
    mesh: &[Pipeline],
    families: &[String],
    isa: Option<&std::path::Path>,
) -> anyhow::Result<()> {
    let each = compiler.cost_mesh_each(mesh, families, isa.is_some())?;
    let each: Vec<Vec<cost::MeshCost>> = each.into_iter().collect::<Result<_, _>>()?;
    println!("mesh modules (the compiler's counts: a model, not a clock); loops: body in instructions, (^) nested");
    for (f, family) in families.iter().enumerate() {
        let mut first = true;
        for costs in &each {
            let c = &costs[f];
            if first {
                println!("{family} ({}, {})", c.device, c.driver);
                first = false;
            }
            println!("{}  [fs_mesh loop bodies: {}]", c.pipeline, c.fragment_loop_body());
            println!("{}", line("vs", &c.vertex));
            println!("{}", line("fs", &c.fragment));
            println!("{}", line("depth", &c.depth));
        }
    }
    if let Some(dir) = isa {
        relief_runtime::io::create_dir_all(dir)?;
        for (costs, p) in each.iter().zip(mesh) {
            let stem = p.file_stem();
            for c in costs {
                for (what, s) in [("vs_mesh", &c.vertex), ("fs_mesh", &c.fragment), ("fs_mesh_depth", &c.depth)] {
                    let path = dir.join(format!("{stem}.{}.{what}.s", c.family));
                    relief_runtime::io::write_atomic(&path, s.isa.as_deref().unwrap_or("").as_bytes())?;
                }
            }
        }
        println!("wrote the mesh modules' disassembly to {}", dir.display());
    }
    Ok(())
}

/// The hidden child: compiles the jobs on stdin for this process's RADV family.
pub fn child() -> anyhow::Result<()> {
    cost::serve_child(std::io::stdin().lock(), std::io::stdout().lock())?;
    Ok(())
}
