//! The GPU's own compiler prices a pipeline: AMD's shader compiler (Mesa's RADV with ACO),
//! run without a GPU on RADV's null device, and a modeled cost per pixel from its counts.
//!
//! **What is compiled.** Exactly the SPIR-V the runtime hands a Vulkan driver: the
//! pipeline's WGSL ([`Program::wgsl`], what wgpu loads) parsed and validated by naga, then
//! written per entry point with the options wgpu 30's Vulkan backend uses on a Vulkan 1.3
//! device with `robustBufferAccess2` and `robustImageAccess` (SPIR-V 1.6, forced loop
//! bounding, index bounds clamped, varyings labelled, the point size written; see
//! [`wgpu_spirv_options`]). The render entry pair (`vs_main`, `fs_main`) is compiled as a
//! graphics pipeline drawing into relief's colour format, the `probe` entry as a compute
//! pipeline.
//!
//! **Where.** One child process per GPU family ([`Compiler`]): the driver reads its family
//! (`RADV_FORCE_FAMILY`) once per process. The child is relief's own command line (a hidden
//! subcommand) with `VK_ICD_FILENAMES` naming RADV's manifest and Mesa's shader cache off
//! (a cache hit returns no statistics). Every figure carries the family and the Mesa version
//! that compiled it.
//!
//! **What is counted.** Per shader: the compiler's statistics (VGPRs, SGPRs, spills,
//! scratch, instructions, code size, waves per SIMD) and, from the disassembly
//! ([`isa`]), each loop's body and nesting. The loops are attributed to the pipeline's
//! stages by compiling it again with the later stages removed ([`StageLoops`]).
//!
//! **The model** ([`modeled`]) is a model, not a clock: a lane's instructions are the
//! shader's instructions outside its loops, plus each coarse loop's body times the ray's
//! coarse passes and each refine loop's body times its refine passes (the probe's
//! counters). A SIMD group runs in lock step, so the group issues, per loop, as many passes
//! as its slowest lane; the group's figure is the same for each of its lanes, and the model
//! averages it over the launched groups, as [`crate::SimdCost`] does for steps. Shadow and
//! ambient-occlusion loops, which the probe does not count, enter at one pass each; a loop
//! nested in a stage's loop enters once per pass of the outer loop. What it leaves out:
//! latency (a fetch costs one instruction here, hundreds of cycles on a GPU), occupancy
//! beyond the reported waves per SIMD, and branches not taken inside a loop body.

pub mod isa;
mod model;
pub(crate) mod radv;

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use relief_dsl::spec::{Pipeline, StageSpec};
use serde::{Deserialize, Serialize};

use crate::gpu::Program;
pub use isa::{IsaLoop, IsaShape};
pub use model::{modeled, set_columns, set_mesh_columns, GpuModel};

/// The families `relief cost` and the sweep compile for when none is asked: one RDNA2
/// (`navi21`, a Radeon RX 6800/6900) and one RDNA3 (`gfx1100`, a Radeon RX 7900).
pub const DEFAULT_FAMILIES: [&str; 2] = ["navi21", "gfx1100"];

/// The family names Mesa 22.3's RADV accepts in `RADV_FORCE_FAMILY` (its chip names,
/// any case), GCN 1 to RDNA3, each checked to compile there. Names of later Mesas (`navi31`,
/// `gfx1030`) are refused by it; `navi24`, `rembrandt` and `gfx1036` are accepted by the
/// driver but crash its null device (SIGFPE), so they are left out.
pub const KNOWN_FAMILIES: &[&str] = &[
    "tahiti",
    "pitcairn",
    "verde",
    "oland",
    "hainan",
    "bonaire",
    "kaveri",
    "kabini",
    "hawaii",
    "tonga",
    "iceland",
    "carrizo",
    "fiji",
    "stoney",
    "polaris10",
    "polaris11",
    "polaris12",
    "vegam",
    "vega10",
    "vega12",
    "vega20",
    "raven",
    "raven2",
    "renoir",
    "arcturus",
    "aldebaran",
    "navi10",
    "navi12",
    "navi14",
    "navi21",
    "navi22",
    "navi23",
    "vangogh",
    "gfx1100",
    "gfx1101",
    "gfx1102",
    "gfx1103_r1",
    "gfx1103_r2",
];

/// Where RADV's Vulkan manifest lies on Debian (`mesa-vulkan-drivers`).
pub const RADV_ICD: &str = "/usr/share/vulkan/icd.d/radeon_icd.x86_64.json";

/// Why a pipeline could not be priced.
#[derive(Debug, thiserror::Error)]
pub enum CostError {
    /// The family is not one Mesa 22.3 knows.
    #[error("unknown GPU family `{0}`; known: {known}", known = KNOWN_FAMILIES.join(", "))]
    UnknownFamily(String),
    /// RADV's manifest is missing: nothing can compile.
    #[error("RADV is not installed ({RADV_ICD} missing; Debian's mesa-vulkan-drivers provides it)")]
    NoRadv,
    /// The pipeline does not compile to SPIR-V.
    #[error("pipeline `{pipeline}`: {message}")]
    Spirv {
        /// The pipeline's text form.
        pipeline: String,
        /// naga's error.
        message: String,
    },
    /// The child process failed, or the driver refused a pipeline.
    #[error("{family}: {message}")]
    Driver {
        /// The family the child compiled for.
        family: String,
        /// What failed, one line.
        message: String,
    },
    /// A file of recorded costs (`relief cost --json`) cannot be read.
    #[error("{file}: {message}")]
    RecordedFile {
        /// The file.
        file: String,
        /// Why, one line.
        message: String,
    },
    /// A file of recorded costs has no entry for this pipeline and family.
    #[error("pipeline `{pipeline}` on {family} is not in {file} (price it there with `relief cost`)")]
    NotRecorded {
        /// The pipeline's text form.
        pipeline: String,
        /// The family asked for.
        family: String,
        /// The file.
        file: String,
    },
}

/// A shader's figures as the compiler reports them.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ShaderCost {
    /// The driver's name of the executable ("Fragment Shader", "Compute Shader").
    pub executable: String,
    /// Lanes per SIMD group the shader was compiled for (wave32 or wave64).
    pub subgroup_size: u32,
    /// Vector registers per lane.
    pub vgprs: u32,
    /// Scalar registers.
    pub sgprs: u32,
    /// Vector registers spilled.
    pub spilled_vgprs: u32,
    /// Scalar registers spilled.
    pub spilled_sgprs: u32,
    /// Scratch memory per lane, bytes.
    pub scratch_bytes: u32,
    /// Instructions (the compiler's count).
    pub instructions: u32,
    /// Code size, bytes.
    pub code_bytes: u32,
    /// Waves the registers allow per SIMD (the compiler's "Subgroups per SIMD").
    pub waves_per_simd: u32,
    /// The disassembly's shape: instructions and loops.
    pub shape: IsaShape,
    /// The disassembly, when asked for.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub isa: Option<String>,
}

impl ShaderCost {
    fn from_executable(e: &radv::Executable, keep_isa: bool) -> ShaderCost {
        let stat = |names: &[&str]| -> u32 {
            e.stats.iter().find(|(n, _)| names.contains(&n.as_str())).map(|(_, v)| *v as u32).unwrap_or(0)
        };
        ShaderCost {
            executable: e.name.clone(),
            subgroup_size: e.subgroup_size,
            vgprs: stat(&["VGPRs"]),
            sgprs: stat(&["SGPRs"]),
            spilled_vgprs: stat(&["Spilled VGPRs"]),
            spilled_sgprs: stat(&["Spilled SGPRs"]),
            scratch_bytes: stat(&["Scratch size", "PrivMem VGPRs"]),
            instructions: stat(&["Instructions"]),
            code_bytes: stat(&["Code size"]),
            waves_per_simd: stat(&["Subgroups per SIMD"]),
            shape: isa::shape(&e.isa),
            isa: keep_isa.then(|| e.isa.clone()),
        }
    }

    /// Instructions outside every loop.
    pub fn straight_line(&self) -> u32 {
        self.shape.instructions - self.shape.top_level().map(|l| l.body).sum::<u32>()
    }
}

/// Which of a fragment shader's top-level loops (in program order) belong to which stage:
/// the first `coarse` loops are the coarse search's, the next `refine` the refinement's,
/// the rest the shadow's and ambient occlusion's. Found by compiling the pipeline with the
/// later stages set to `none` and counting the top-level loops each prefix adds.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct StageLoops {
    /// Top-level loops with no stage (the pipeline with every stage `none`).
    pub base: u32,
    /// The coarse search's top-level loops.
    pub coarse: u32,
    /// The refinement's.
    pub refine: u32,
    /// The shadow's and ambient occlusion's.
    pub lighting: u32,
}

/// One pipeline compiled for one family.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PipelineCost {
    /// The pipeline's text form.
    pub pipeline: String,
    /// The family (`RADV_FORCE_FAMILY`).
    pub family: String,
    /// The device name RADV gave (e.g. `AMD RADV NAVI21`).
    pub device: String,
    /// The driver and its version (e.g. `radv Mesa 22.3.6`).
    pub driver: String,
    /// The render entry's fragment shader.
    pub fragment: ShaderCost,
    /// The probe's compute shader (with its counters).
    pub probe: ShaderCost,
    /// The fragment shader's loops by stage.
    pub stage_loops: StageLoops,
}

impl PipelineCost {
    /// The body of the fragment shader's coarse loops (summed over the stage's top-level
    /// loops), 0 when the compiler unrolled them.
    pub fn coarse_body(&self) -> u32 {
        self.stage_bodies().0
    }

    /// (coarse, refine, lighting) top-level loop bodies of the fragment shader.
    pub fn stage_bodies(&self) -> (u32, u32, u32) {
        let top: Vec<u32> = self.fragment.shape.top_level().map(|l| l.body).collect();
        let s = self.stage_loops;
        let take = |from: u32, n: u32| top.iter().skip(from as usize).take(n as usize).sum::<u32>();
        (take(s.base, s.coarse), take(s.base + s.coarse, s.refine), take(s.base + s.coarse + s.refine, s.lighting))
    }
}

/// A family name checked against [`KNOWN_FAMILIES`] (lower-cased).
pub fn family(name: &str) -> Result<String, CostError> {
    let f = name.trim().to_ascii_lowercase();
    if KNOWN_FAMILIES.contains(&f.as_str()) {
        Ok(f)
    } else {
        Err(CostError::UnknownFamily(relief_dsl::spec::echo(name)))
    }
}

/// The SPIR-V options of wgpu 30's Vulkan backend (`wgpu-hal`'s `Adapter::open`) on a
/// Vulkan 1.3 device with `robustBufferAccess2` and `robustImageAccess` and no optional
/// shader feature, which is what RADV offers: SPIR-V 1.6, labelled varyings, a written
/// point size, index accesses clamped (`Restrict`) and buffer and image accesses left to the
/// hardware's robustness, forced loop bounding, no debug information.
pub fn wgpu_spirv_options() -> naga::back::spv::Options<'static> {
    use naga::back::spv;
    use naga::proc::{BoundsCheckPolicies, BoundsCheckPolicy};
    spv::Options {
        lang_version: (1, 6),
        flags: spv::WriterFlags::LABEL_VARYINGS | spv::WriterFlags::FORCE_POINT_SIZE,
        bounds_check_policies: BoundsCheckPolicies {
            index: BoundsCheckPolicy::Restrict,
            buffer: BoundsCheckPolicy::Unchecked,
            image_load: BoundsCheckPolicy::Unchecked,
            binding_array: BoundsCheckPolicy::Unchecked,
        },
        zero_initialize_workgroup_memory: spv::ZeroInitializeWorkgroupMemoryMode::Native,
        force_loop_bounding: true,
        ..spv::Options::default()
    }
}

/// A WGSL module the runtime loads, parsed and validated, whose entry points are written as
/// SPIR-V the way wgpu writes them ([`wgpu_spirv_options`]); errors name `pipeline`.
struct Spirv {
    pipeline: String,
    module: naga::Module,
    info: naga::valid::ModuleInfo,
}

impl Spirv {
    fn of(pipeline: &str, wgsl: &str) -> Result<Spirv, CostError> {
        let pipeline = pipeline.to_string();
        let err = |e: String| CostError::Spirv { pipeline: pipeline.clone(), message: relief_dsl::spec::one_line(&e) };
        let module = naga::front::wgsl::parse_str(wgsl).map_err(|e| err(e.to_string()))?;
        let info =
            naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::default())
                .validate(&module)
                .map_err(|e| err(e.to_string()))?;
        Ok(Spirv { pipeline, module, info })
    }

    /// The entry point `name` of `stage`, its overrides processed, as SPIR-V words.
    fn entry(&self, stage: naga::ShaderStage, name: &str) -> Result<Vec<u32>, CostError> {
        let err =
            |e: String| CostError::Spirv { pipeline: self.pipeline.clone(), message: relief_dsl::spec::one_line(&e) };
        let (m, i) = naga::back::pipeline_constants::process_overrides(
            &self.module,
            &self.info,
            Some((stage, name)),
            &Default::default(),
        )
        .map_err(|e| err(e.to_string()))?;
        let po = naga::back::spv::PipelineOptions { shader_stage: stage, entry_point: name.to_string() };
        naga::back::spv::write_vec(&m, &i, &wgpu_spirv_options(), Some(&po)).map_err(|e| err(e.to_string()))
    }
}

/// The compile jobs of one pipeline: its render pair and its probe, from the WGSL the
/// runtime loads.
fn jobs_of(text: &str, program: &Program) -> Result<(radv::Job, radv::Job), CostError> {
    let spirv = Spirv::of(text, &program.wgsl)?;
    let entry = |stage, name: &str| spirv.entry(stage, name);
    let bindings = descriptors(&spirv.module);
    let render = radv::Job {
        name: format!("{text} (render)"),
        shaders: radv::Shaders::Graphics {
            vert: entry(naga::ShaderStage::Vertex, "vs_main")?,
            frag: entry(naga::ShaderStage::Fragment, "fs_main")?,
            depth: program.writes_depth,
            entries: ["vs_main".into(), "fs_main".into()],
            vertex_attributes: 0,
        },
        bindings: bindings.clone(),
    };
    let probe = radv::Job {
        name: format!("{text} (probe)"),
        shaders: radv::Shaders::Compute { comp: entry(naga::ShaderStage::Compute, "probe")? },
        bindings,
    };
    Ok((render, probe))
}

/// The pipeline with the stages after `keep` set to `none` (0: every stage none, 1: coarse
/// only, 2: coarse and refine).
fn prefix(p: &Pipeline, keep: usize) -> Pipeline {
    let mut q = p.clone();
    let none = StageSpec::none();
    if keep < 1 {
        q.coarse = none.clone();
    }
    if keep < 2 {
        q.refine = none.clone();
    }
    q.shadow = none.clone();
    q.ao = none;
    q
}

/// How the child process is started: relief's command line and the arguments of its
/// hidden child subcommand.
#[derive(Clone, Debug)]
pub struct Compiler {
    /// The program to run (relief's command line: `std::env::current_exe()` from the
    /// command line itself, `env!("CARGO_BIN_EXE_relief")` from a test).
    pub program: PathBuf,
    /// Its arguments that make it a child ([`CHILD_ARGS`]).
    pub args: Vec<String>,
    /// Costs recorded earlier (`relief cost --json`), answered instead of compiling: for a
    /// machine without RADV (a GPU machine measuring the clock the model is set beside). The
    /// compiler's figures depend on the SPIR-V and Mesa's version only, never on the machine.
    pub recorded: Option<Recorded>,
}

/// Costs read from a file that `relief cost --json` wrote ([`Compiler::from_recorded`]).
#[derive(Clone, Debug)]
pub struct Recorded {
    /// The file, for messages.
    pub file: PathBuf,
    /// Its costs, any order.
    pub costs: Vec<PipelineCost>,
}

/// The hidden subcommand that makes relief's command line a compiling child: it reads jobs
/// as JSON on stdin and writes the answer on stdout ([`serve_child`]).
pub const CHILD_ARGS: [&str; 1] = ["__radv-child"];

impl Compiler {
    /// The child is `program` with [`CHILD_ARGS`].
    pub fn new(program: impl AsRef<Path>) -> Compiler {
        Compiler {
            program: program.as_ref().to_path_buf(),
            args: CHILD_ARGS.iter().map(|s| s.to_string()).collect(),
            recorded: None,
        }
    }

    /// A compiler that answers from `file` (what `relief cost --json` wrote) and compiles
    /// nothing: a pipeline or family missing from it is [`CostError::NotRecorded`].
    pub fn from_recorded(file: impl AsRef<Path>) -> Result<Compiler, CostError> {
        let file = file.as_ref();
        let fail = |m: String| CostError::RecordedFile {
            file: file.display().to_string(),
            message: relief_dsl::spec::one_line(&m),
        };
        let bytes = crate::io::read_regular(file).map_err(|e| fail(e.to_string()))?;
        let costs: Vec<PipelineCost> =
            serde_json::from_slice(&bytes).map_err(|e| fail(format!("not a `relief cost --json` file: {e}")))?;
        for c in &costs {
            family(&c.family).map_err(|e| fail(e.to_string()))?;
        }
        Ok(Compiler {
            program: PathBuf::new(),
            args: vec![],
            recorded: Some(Recorded { file: file.to_path_buf(), costs }),
        })
    }

    /// Whether RADV's manifest is installed (the sweep writes no GPU columns without it).
    pub fn radv_present() -> bool {
        Path::new(RADV_ICD).exists()
    }

    /// Runs one child for `family` on `jobs`.
    fn run(&self, family: &str, jobs: &[radv::Job]) -> Result<radv::Answer, CostError> {
        let fail =
            |m: String| CostError::Driver { family: family.to_string(), message: relief_dsl::spec::one_line(&m) };
        let mut child = Command::new(&self.program)
            .args(&self.args)
            .env("RADV_FORCE_FAMILY", family)
            .env("VK_ICD_FILENAMES", RADV_ICD)
            .env("MESA_SHADER_CACHE_DISABLE", "true")
            .env_remove("RADV_DEBUG")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| fail(format!("cannot start {}: {e}", self.program.display())))?;
        let input = serde_json::to_vec(jobs).map_err(|e| fail(e.to_string()))?;
        let mut stdin = child.stdin.take().expect("piped stdin");
        let writer = std::thread::spawn(move || stdin.write_all(&input));
        let out = child.wait_with_output().map_err(|e| fail(e.to_string()))?;
        let _ = writer.join();
        let stderr = String::from_utf8_lossy(&out.stderr);
        if !out.status.success() {
            let last = stderr.lines().rev().find(|l| !l.trim().is_empty()).unwrap_or("no message");
            return Err(fail(format!("the compiling child failed ({}): {last}", out.status)));
        }
        let answer: Result<radv::Answer, String> =
            serde_json::from_slice(&out.stdout).map_err(|e| fail(format!("the child's answer: {e}")))?;
        answer.map_err(fail)
    }

    /// Prices `pipelines` on each of `families`: one child per family, all pipelines (and
    /// their stage prefixes) in it; `keep_isa` keeps each shader's disassembly. Any pipeline
    /// that fails is an error ([`Compiler::cost_each`] keeps the others).
    pub fn cost(
        &self,
        pipelines: &[Pipeline],
        families: &[String],
        keep_isa: bool,
    ) -> Result<Vec<PipelineCost>, CostError> {
        let each = self.cost_each(pipelines, families, keep_isa)?;
        // Family by family, as the children answered.
        let mut out = vec![];
        for f in 0..families.len() {
            for costs in &each {
                out.push(costs.as_ref().map_err(|e| e.clone_error())?[f].clone());
            }
        }
        Ok(out)
    }

    /// Prices each of `pipelines` on every family: per pipeline, its costs in the order of
    /// `families`, or why it could not be priced. A missing driver, an unknown family or a
    /// child that fails as a whole is the outer error.
    pub fn cost_each(
        &self,
        pipelines: &[Pipeline],
        families: &[String],
        keep_isa: bool,
    ) -> Result<Vec<Result<Vec<PipelineCost>, CostError>>, CostError> {
        for f in families {
            family(f)?;
        }
        if let Some(r) = &self.recorded {
            return Ok(pipelines.iter().map(|p| r.lookup(p, families)).collect());
        }
        if !Compiler::radv_present() {
            return Err(CostError::NoRadv);
        }
        // Jobs, each once (pipelines share their stage prefixes): per pipeline, the indices of
        // its render, probe and prefix 0, 1, 2 render jobs.
        let mut jobs: Vec<radv::Job> = vec![];
        let mut index: std::collections::HashMap<String, usize> = Default::default();
        let mut plan: Vec<Result<[usize; 5], CostError>> = vec![];
        for p in pipelines {
            let mut add = |q: &Pipeline, probe: bool| -> Result<(usize, Option<usize>), CostError> {
                let text = q.to_string();
                if let Some(&i) = index.get(&text) {
                    if !probe || index.contains_key(&format!("{text} (probe)")) {
                        return Ok((i, index.get(&format!("{text} (probe)")).copied()));
                    }
                }
                let program = Program::new(q).map_err(|e| CostError::Spirv {
                    pipeline: text.clone(),
                    message: relief_dsl::spec::one_line(&e.to_string()),
                })?;
                let (render, probe_job) = jobs_of(&text, &program)?;
                let r = *index.entry(text.clone()).or_insert_with(|| {
                    jobs.push(render);
                    jobs.len() - 1
                });
                let pr = probe.then(|| {
                    jobs.push(probe_job);
                    index.insert(format!("{text} (probe)"), jobs.len() - 1);
                    jobs.len() - 1
                });
                Ok((r, pr))
            };
            let entry = (|| {
                let (render, probe) = add(p, true)?;
                let p0 = add(&prefix(p, 0), false)?.0;
                let p1 = add(&prefix(p, 1), false)?.0;
                let p2 = add(&prefix(p, 2), false)?.0;
                Ok([render, probe.expect("probe job"), p0, p1, p2])
            })();
            plan.push(entry);
        }
        let answers: Vec<Result<radv::Answer, CostError>> = std::thread::scope(|s| {
            let handles: Vec<_> = families.iter().map(|f| s.spawn(|| self.run(f, &jobs))).collect();
            handles.into_iter().map(|h| h.join().expect("compiling thread")).collect()
        });
        let answers: Vec<radv::Answer> = answers.into_iter().collect::<Result<_, _>>()?;
        let mut out = vec![];
        for (p, plan) in pipelines.iter().zip(plan) {
            let one = |plan: [usize; 5]| -> Result<Vec<PipelineCost>, CostError> {
                let mut costs = vec![];
                for (family, answer) in families.iter().zip(&answers) {
                    costs.push(price(p, family, answer, plan, keep_isa)?);
                }
                Ok(costs)
            };
            out.push(plan.and_then(one));
        }
        Ok(out)
    }
}

impl Recorded {
    /// `p`'s costs on each of `families`, in that order.
    fn lookup(&self, p: &Pipeline, families: &[String]) -> Result<Vec<PipelineCost>, CostError> {
        let text = p.to_string();
        families
            .iter()
            .map(|f| {
                self.costs.iter().find(|c| c.pipeline == text && &c.family == f).cloned().ok_or_else(|| {
                    CostError::NotRecorded {
                        pipeline: text.clone(),
                        family: f.clone(),
                        file: self.file.display().to_string(),
                    }
                })
            })
            .collect()
    }
}

impl CostError {
    /// A copy (the variants hold text only).
    fn clone_error(&self) -> CostError {
        match self {
            CostError::UnknownFamily(f) => CostError::UnknownFamily(f.clone()),
            CostError::NoRadv => CostError::NoRadv,
            CostError::Spirv { pipeline, message } => {
                CostError::Spirv { pipeline: pipeline.clone(), message: message.clone() }
            }
            CostError::Driver { family, message } => {
                CostError::Driver { family: family.clone(), message: message.clone() }
            }
            CostError::RecordedFile { file, message } => {
                CostError::RecordedFile { file: file.clone(), message: message.clone() }
            }
            CostError::NotRecorded { pipeline, family, file } => {
                CostError::NotRecorded { pipeline: pipeline.clone(), family: family.clone(), file: file.clone() }
            }
        }
    }
}

/// One pipeline's cost on one family from the child's answer: `plan` holds the indices of
/// its render, probe and prefix 0, 1, 2 render jobs.
fn price(
    p: &Pipeline,
    family: &str,
    answer: &radv::Answer,
    plan: [usize; 5],
    keep_isa: bool,
) -> Result<PipelineCost, CostError> {
    let fail = |m: &str| CostError::Driver { family: family.to_string(), message: relief_dsl::spec::one_line(m) };
    let get = |i: usize| answer.results[plan[i]].as_ref().map_err(|e| fail(e));
    let exe = |xs: &[radv::Executable], what: &str| -> Result<radv::Executable, CostError> {
        xs.iter().find(|e| e.name.contains(what)).cloned().ok_or_else(|| fail(&format!("no {what} shader")))
    };
    let fragment = ShaderCost::from_executable(&exe(get(0)?, "Fragment")?, keep_isa);
    let probe = ShaderCost::from_executable(&exe(get(1)?, "Compute")?, keep_isa);
    let tops = |i: usize| -> Result<u32, CostError> {
        Ok(isa::shape(&exe(get(i)?, "Fragment")?.isa).top_level().count() as u32)
    };
    let (l0, l1, l2) = (tops(2)?, tops(3)?, tops(4)?);
    let all = fragment.shape.top_level().count() as u32;
    let stage_loops = StageLoops {
        base: l0,
        coarse: l1.saturating_sub(l0),
        refine: l2.saturating_sub(l1),
        lighting: all.saturating_sub(l2),
    };
    Ok(PipelineCost {
        pipeline: p.to_string(),
        family: family.to_string(),
        device: answer.device.clone(),
        driver: answer.driver.clone(),
        fragment,
        probe,
        stage_loops,
    })
}

impl Compiler {
    /// Prices a compute shader given as WGSL, whose entry point is named `probe`, on
    /// `family`: the same SPIR-V options and driver path as a pipeline's probe. For checking
    /// what the counts mean on shaders whose work is known.
    pub fn cost_compute_wgsl(&self, wgsl: &str, family_name: &str, keep_isa: bool) -> Result<ShaderCost, CostError> {
        if !Compiler::radv_present() {
            return Err(CostError::NoRadv);
        }
        let family = family(family_name)?;
        let err =
            |m: String| CostError::Spirv { pipeline: "compute shader".into(), message: relief_dsl::spec::one_line(&m) };
        let module = naga::front::wgsl::parse_str(wgsl).map_err(|e| err(e.emit_to_string(wgsl)))?;
        let info =
            naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::default())
                .validate(&module)
                .map_err(|e| err(e.to_string()))?;
        let po =
            naga::back::spv::PipelineOptions { shader_stage: naga::ShaderStage::Compute, entry_point: "probe".into() };
        let comp = naga::back::spv::write_vec(&module, &info, &wgpu_spirv_options(), Some(&po))
            .map_err(|e| err(e.to_string()))?;
        let job = radv::Job {
            name: "compute shader".into(),
            shaders: radv::Shaders::Compute { comp },
            bindings: descriptors(&module),
        };
        let answer = self.run(&family, &[job])?;
        let fail = |m: &str| CostError::Driver { family: family.clone(), message: relief_dsl::spec::one_line(m) };
        let exes = answer.results[0].as_ref().map_err(|e| fail(e))?;
        let exe = exes.iter().find(|e| e.name.contains("Compute")).ok_or_else(|| fail("no compute shader"))?;
        Ok(ShaderCost::from_executable(exe, keep_isa))
    }
}

/// A `curved=` pipeline's mesh module (relief-dsl's `compose/mesh.rs`) compiled for one
/// family: the compiler's figures for its three render entries. Like [`PipelineCost`], these
/// are the compiler's counts, a model of the cost and not a clock.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MeshCost {
    /// The pipeline's text form (with its `curved=` option).
    pub pipeline: String,
    /// The family (`RADV_FORCE_FAMILY`).
    pub family: String,
    /// The device name RADV gave.
    pub device: String,
    /// The driver and its version.
    pub driver: String,
    /// `vs_mesh`, the vertex shader (compiled beside `fs_mesh`).
    pub vertex: ShaderCost,
    /// `fs_mesh`, the colour entry's fragment shader.
    pub fragment: ShaderCost,
    /// `fs_mesh_depth`, the depth-only / shadow-caster entry's fragment shader.
    pub depth: ShaderCost,
}

impl MeshCost {
    /// The body of `fs_mesh`'s top-level loops, summed (0 when the compiler unrolled them):
    /// the instructions one pass of every search loop takes.
    pub fn fragment_loop_body(&self) -> u32 {
        self.fragment.shape.top_level().map(|l| l.body).sum()
    }
}

/// The mesh module's two graphics jobs, from the WGSL the runtime loads
/// ([`crate::gpu::mesh::MeshProgram`]; `curved=prism` as the walk): `vs_mesh` + `fs_mesh`, and
/// `vs_mesh` + `fs_mesh_depth`, the vertex shader reading
/// [`relief_dsl::compose::mesh::MeshVertex`]'s `vec4` members (as many as the mode reads,
/// `vertex_members_for`).
fn mesh_jobs(p: &Pipeline) -> Result<[radv::Job; 2], CostError> {
    use relief_dsl::compose::mesh::{vertex_members_for, DEPTH_ENTRY};
    let text = p.to_string();
    let err = |m: String| CostError::Spirv { pipeline: text.clone(), message: relief_dsl::spec::one_line(&m) };
    let mesh = crate::gpu::mesh::MeshProgram::new(p).map_err(|e| err(e.to_string()))?;
    let spirv = Spirv::of(&text, &mesh.program.wgsl)?;
    let entry = |stage, name: &str| spirv.entry(stage, name);
    // The members `vs_mesh` reads (the unwalked `prism` reads its triangle's corners too; the
    // runtime's walk reads them from its buffer).
    let attributes = vertex_members_for(mesh.curved, mesh.walk) as u32;
    let vert = entry(naga::ShaderStage::Vertex, "vs_mesh")?;
    let bindings = descriptors(&spirv.module);
    let job = |frag: &str| -> Result<radv::Job, CostError> {
        Ok(radv::Job {
            name: format!("{text} ({frag})"),
            shaders: radv::Shaders::Graphics {
                vert: vert.clone(),
                frag: entry(naga::ShaderStage::Fragment, frag)?,
                depth: true,
                entries: ["vs_mesh".into(), frag.into()],
                vertex_attributes: attributes,
            },
            bindings: bindings.clone(),
        })
    };
    Ok([job("fs_mesh")?, job(DEPTH_ENTRY)?])
}

impl Compiler {
    /// Prices the mesh modules of `pipelines` (each with a `curved=` option) on each of
    /// `families`: per pipeline, its costs in the order of `families`, or why it could not be
    /// priced. A recorded compiler ([`Compiler::from_recorded`]) holds flat pipelines only
    /// and refuses.
    pub fn cost_mesh_each(
        &self,
        pipelines: &[Pipeline],
        families: &[String],
        keep_isa: bool,
    ) -> Result<Vec<Result<Vec<MeshCost>, CostError>>, CostError> {
        for f in families {
            family(f)?;
        }
        if let Some(r) = &self.recorded {
            return Err(CostError::RecordedFile {
                file: r.file.display().to_string(),
                message: "recorded costs are not implemented for mesh modules (curved=); price them with RADV".into(),
            });
        }
        if !Compiler::radv_present() {
            return Err(CostError::NoRadv);
        }
        let mut jobs = vec![];
        let plan: Vec<Result<usize, CostError>> = pipelines
            .iter()
            .map(|p| {
                let [colour, depth] = mesh_jobs(p)?;
                jobs.push(colour);
                jobs.push(depth);
                Ok(jobs.len() - 2)
            })
            .collect();
        if jobs.is_empty() {
            return Ok(plan.into_iter().map(|r| r.map(|_| vec![])).collect());
        }
        let answers: Vec<Result<radv::Answer, CostError>> = std::thread::scope(|s| {
            let handles: Vec<_> = families.iter().map(|f| s.spawn(|| self.run(f, &jobs))).collect();
            handles.into_iter().map(|h| h.join().expect("compiling thread")).collect()
        });
        let answers: Vec<radv::Answer> = answers.into_iter().collect::<Result<_, _>>()?;
        let one = |p: &Pipeline, first: usize| -> Result<Vec<MeshCost>, CostError> {
            let mut costs = vec![];
            for (family, answer) in families.iter().zip(&answers) {
                let fail =
                    |m: &str| CostError::Driver { family: family.clone(), message: relief_dsl::spec::one_line(m) };
                let get = |i: usize| answer.results[i].as_ref().map_err(|e| fail(e));
                let exe = |xs: &[radv::Executable], what: &str| -> Result<ShaderCost, CostError> {
                    let e =
                        xs.iter().find(|e| e.name.contains(what)).ok_or_else(|| fail(&format!("no {what} shader")))?;
                    Ok(ShaderCost::from_executable(e, keep_isa))
                };
                costs.push(MeshCost {
                    pipeline: p.to_string(),
                    family: family.clone(),
                    device: answer.device.clone(),
                    driver: answer.driver.clone(),
                    vertex: exe(get(first)?, "Vertex")?,
                    fragment: exe(get(first)?, "Fragment")?,
                    depth: exe(get(first + 1)?, "Fragment")?,
                });
            }
            Ok(costs)
        };
        Ok(pipelines.iter().zip(plan).map(|(p, first)| first.and_then(|i| one(p, i))).collect())
    }
}

/// Set 0's descriptors, from the module's bound globals.
fn descriptors(module: &naga::Module) -> Vec<(u32, radv::Descriptor)> {
    module
        .global_variables
        .iter()
        .filter_map(|(_, g)| {
            let b = g.binding.as_ref()?;
            let kind = match (g.space, &module.types[g.ty].inner) {
                (naga::AddressSpace::Uniform, _) => radv::Descriptor::Uniform,
                (naga::AddressSpace::Storage { .. }, _) => radv::Descriptor::Storage,
                (_, naga::TypeInner::Sampler { .. }) => radv::Descriptor::Sampler,
                (_, naga::TypeInner::Image { class: naga::ImageClass::Storage { .. }, .. }) => {
                    radv::Descriptor::StorageImage
                }
                _ => radv::Descriptor::SampledImage,
            };
            Some((b.binding, kind))
        })
        .collect()
}

/// The child's side: reads the jobs (JSON) from `input`, compiles them on the RADV device
/// this process sees, and writes the answer (JSON) to `output`. An error opening the driver
/// is written as the answer's error; the caller exits 0 either way once it is written.
pub fn serve_child(input: impl std::io::Read, output: impl std::io::Write) -> std::io::Result<()> {
    let jobs: Result<Vec<radv::Job>, String> = serde_json::from_reader(input).map_err(|e| format!("the jobs: {e}"));
    let answer = jobs.and_then(|j| radv::compile_jobs(&j));
    serde_json::to_writer(output, &answer).map_err(std::io::Error::other)
}
