//! The GPU compiler's counts (`relief_runtime::cost`), on shaders whose work is known, and
//! its columns in a sweep and the report. Needs Mesa's RADV (`mesa-vulkan-drivers`, which
//! `.ci/run` installs); no GPU.

use std::process::Command;

use relief_runtime::cost::{Compiler, ShaderCost};

fn compiler() -> Compiler {
    Compiler::new(env!("CARGO_BIN_EXE_relief"))
}

/// A compute shader whose loop runs a count read from memory (so the compiler cannot unroll
/// it) and holds `n` dependent multiply-adds on one value: `x = x * x + c_k`.
fn chain(n: usize) -> String {
    let body: String = (0..n).map(|k| format!("        x = x * x + {}.25;\n", k + 1)).collect();
    format!(
        "@group(0) @binding(0) var<storage, read_write> data: array<f32>;\n\
         @compute @workgroup_size(64) fn probe(@builtin(global_invocation_id) id: vec3<u32>) {{\n\
         \x20   var x = data[id.x];\n\
         \x20   let n = u32(data[0]);\n\
         \x20   for (var i = 0u; i < n; i++) {{\n{body}    }}\n\
         \x20   data[id.x] = x;\n}}\n"
    )
}

fn cost(wgsl: &str, family: &str) -> ShaderCost {
    compiler().cost_compute_wgsl(wgsl, family, true).unwrap_or_else(|e| panic!("{e}"))
}

/// Each dependent multiply-add is one vector instruction (`v_fma_f32`/`v_fmac_f32`: the
/// chain cannot be merged or reordered, and both families issue an FMA in one instruction),
/// and the loop's own work (the counter's increment and compare, naga's forced loop bound,
/// the branch back and the lane mask's bookkeeping) does not depend on `n`. So the body is
/// at least `n`, at most `n` plus a fixed overhead, and the body of `2n` is the body of `n`
/// plus exactly `n`. The overhead bound, 24: the counter (add, compare: 2), naga's 64-bit
/// loop bound as two 32-bit words (decrement, borrow, two compares, a select: ≤ 8), the
/// exits' conditional branches and mask saves (≤ 3 exits × 3 = 9), the branch back (1),
/// with room for a few moves (4).
#[test]
fn a_loop_of_n_dependent_multiply_adds_has_a_body_of_n_plus_a_fixed_overhead() {
    for family in ["navi21", "gfx1100"] {
        let c16 = cost(&chain(16), family);
        let c32 = cost(&chain(32), family);
        for (n, c) in [(16u32, &c16), (32, &c32)] {
            assert_eq!(c.shape.loops.len(), 1, "{family}, n = {n}: {:?}\n{}", c.shape, c.isa.as_deref().unwrap_or(""));
            let body = c.shape.loops[0].body;
            assert!((n..=n + 24).contains(&body), "{family}, n = {n}: body {body}\n{}", c.isa.as_deref().unwrap_or(""));
            // The disassembly's instruction count is the compiler's own.
            assert_eq!(c.shape.instructions, c.instructions, "{family}, n = {n}");
        }
        assert_eq!(c32.shape.loops[0].body - c16.shape.loops[0].body, 16, "{family}");
        assert_eq!(c16.subgroup_size, 64, "{family}: RADV 22.3 compiles compute shaders for wave64");
    }
}

#[test]
fn two_nested_loops_are_found_as_two_one_inside_the_other() {
    let wgsl = "@group(0) @binding(0) var<storage, read_write> data: array<f32>;\n\
        @compute @workgroup_size(64) fn probe(@builtin(global_invocation_id) id: vec3<u32>) {\n\
            var x = data[id.x];\n\
            let n = u32(data[0]);\n\
            let m = u32(data[1]);\n\
            for (var i = 0u; i < n; i++) {\n\
                x = x * 1.5 + 0.25;\n\
                for (var j = 0u; j < m; j++) {\n\
                    x = x * x + 2.0;\n\
                }\n\
            }\n\
            data[id.x] = x;\n\
        }\n";
    let c = cost(wgsl, "navi21");
    let loops = &c.shape.loops;
    assert_eq!(loops.len(), 2, "{:?}\n{}", c.shape, c.isa.as_deref().unwrap_or(""));
    assert_eq!((loops[0].depth, loops[1].depth), (0, 1));
    // The inner loop lies inside the outer one.
    assert!(loops[1].start > loops[0].start && loops[1].start + loops[1].body <= loops[0].start + loops[0].body);
    assert_eq!(c.shape.top_level().count(), 1);
}

#[test]
fn bad_families_and_shaders_are_one_line_errors() {
    let e = compiler().cost_compute_wgsl(&chain(1), "navi31", false).unwrap_err().to_string();
    assert!(e.contains("unknown GPU family `navi31`") && e.contains("navi21") && !e.contains('\n'), "{e}");
    let e = compiler().cost_compute_wgsl("fn probe( {", "navi21", false).unwrap_err().to_string();
    assert!(!e.contains('\n'), "{e}");
    // A child that cannot start fails the whole run, in one line.
    let p: relief_dsl::Pipeline = "linear(8)".parse().unwrap();
    let e = Compiler::new("/nonexistent/relief").cost(&[p], &["navi21".into()], false).unwrap_err().to_string();
    assert!(e.starts_with("navi21: cannot start /nonexistent/relief") && !e.contains('\n'), "{e}");
    // The command line: an unknown family exits non-zero with one line.
    let o = Command::new(env!("CARGO_BIN_EXE_relief")).args(["cost", "csm(8)", "--gpu", "navi31"]).output().unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("known: "), "{err}");
}

/// A small sweep writes the GPU columns in every row (and the CSV), and the report shows
/// the model's section with its chart; without the compiler, no row has them and the run
/// says why once.
#[test]
fn a_sweep_writes_the_gpu_columns_and_the_report_shows_the_model() {
    use relief_runtime::sweep::{self, grids, NamedGrid};
    let dir = std::env::temp_dir().join(format!("relief-cost-sweep-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    let pipelines =
        grids::parse_grid_file("coarse: linear_dynamic(1, [8, 16])\nrefine: binary(5)\n---\ncoarse: csm(16)\n")
            .unwrap();
    let cells: Vec<_> = pipelines.into_iter().map(|p| (p, "rocks".to_string())).collect();
    let run = |out: &std::path::Path, compiler: Option<Compiler>| {
        let grid = NamedGrid { name: "cost".into(), description: "the GPU model test".into(), cells: cells.clone() };
        sweep::run(&sweep::Options {
            grid,
            size: 48,
            frames: 2,
            warmup: 1,
            out: out.to_path_buf(),
            progress: false,
            overrides: Default::default(),
            shard: None,
            gpu_cost: compiler,
        })
        .expect("sweep")
    };
    let with = dir.join("with");
    let s = run(&with, Some(compiler()));
    assert_eq!((s.measured, s.failed), (3, 0));
    assert!(s.gpu_note.is_none(), "{:?}", s.gpu_note);
    let rows = relief_runtime::results::read(&with).unwrap().rows;
    for r in &rows {
        let m = &r.metrics;
        assert_eq!(m.gpu_driver.as_deref().map(|d| d.contains("Mesa")), Some(true), "{m:?}");
        for (px, vgprs, instructions, body) in [
            (m.gpu_navi21_instr_px, m.gpu_navi21_vgprs, m.gpu_navi21_instructions, m.gpu_navi21_loop_body),
            (m.gpu_gfx1100_instr_px, m.gpu_gfx1100_vgprs, m.gpu_gfx1100_instructions, m.gpu_gfx1100_loop_body),
        ] {
            let (px, vgprs, instructions, body) = (px.unwrap(), vgprs.unwrap(), instructions.unwrap(), body.unwrap());
            assert!(vgprs > 0 && instructions > 0, "{m:?}");
            // Every pipeline here loops: the compiler cannot unroll a search whose passes
            // depend on the height map.
            assert!(body > 0, "{}: {m:?}", m.pipeline);
            // A group runs the code outside the loops once and each loop at least as often
            // as its slowest lane, which takes at least one coarse pass.
            assert!(px >= instructions as f64, "{}: {px} {m:?}", m.pipeline);
        }
    }
    let csv = std::fs::read_to_string(with.join("results.csv")).unwrap();
    assert!(csv.lines().next().unwrap().ends_with("gpu_gfx1100_loop_body"), "{csv}");
    relief_runtime::report::write(&with).expect("report");
    let md = std::fs::read_to_string(with.join("tables.md")).unwrap();
    assert!(md.contains("## The GPU compiler's model beside the clock"), "{md}");
    assert!(md.contains("A **model**, not a clock"));
    let chart = md.split("](report/gpu_").nth(1).and_then(|s| s.split(')').next()).expect("a chart link");
    let svg = std::fs::read_to_string(with.join("report").join(format!("gpu_{chart}"))).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("modeled instructions per pixel"), "{svg}");
    let html = std::fs::read_to_string(with.join("index.html")).unwrap();
    assert!(html.contains("id=\"gpu-model\""));
    // The model's order against the clock: Spearman's ρ over the three rows, computed here
    // from the rows (three distinct values each: ρ = 1 − 6Σd²/(n(n²−1))).
    let rank = |v: Vec<f64>| -> Vec<f64> { v.iter().map(|x| v.iter().filter(|y| *y < x).count() as f64).collect() };
    let clock = rank(rows.iter().map(|r| r.metrics.frame_ratio_to_baseline.unwrap()).collect());
    let model = rank(rows.iter().map(|r| r.metrics.gpu_navi21_instr_px.unwrap()).collect());
    let d2: f64 = clock.iter().zip(&model).map(|(a, b)| (a - b) * (a - b)).sum();
    let rho = 1.0 - 6.0 * d2 / (3.0 * 8.0);
    let line = md
        .lines()
        .find(|l| l.starts_with("| rocks") && l.contains("| lavapipe | 3 |"))
        .unwrap_or_else(|| panic!("the ρ table's row: {md}"));
    let cells: Vec<&str> = line.split('|').map(str::trim).collect();
    assert!(md.contains("### How the model orders the pipelines"), "{md}");
    assert_eq!(cells[4].parse::<f64>().unwrap(), rho, "{line}");

    // Recorded costs (what `relief cost --grid G --json F` writes, for a GPU machine
    // without RADV) give every row the same columns as compiling; a pipeline missing from
    // the file leaves its rows without them, and the run says how many.
    let grid_file = dir.join("grid.txt");
    std::fs::write(&grid_file, "coarse: linear_dynamic(1, [8, 16])\nrefine: binary(5)\n---\ncoarse: csm(16)\n")
        .unwrap();
    let json = dir.join("costs.json");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(["cost", "--grid"])
        .arg(&grid_file)
        .args(["--scene", "rocks", "--json"])
        .arg(&json)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let recorded = dir.join("recorded");
    let s = run(&recorded, Some(Compiler::from_recorded(&json).unwrap()));
    assert!(s.gpu_note.is_none(), "{:?}", s.gpu_note);
    let gpu_of = |m: &relief_runtime::results::Metrics| {
        let v = serde_json::to_value(m).unwrap();
        let o = v.as_object().unwrap().clone();
        (m.pipeline.to_string(), o.into_iter().filter(|(k, _)| k.starts_with("gpu_")).collect::<Vec<_>>())
    };
    let mut a: Vec<_> = rows.iter().map(|r| gpu_of(&r.metrics)).collect();
    let mut b: Vec<_> =
        relief_runtime::results::read(&recorded).unwrap().rows.iter().map(|r| gpu_of(&r.metrics)).collect();
    a.sort_by(|x, y| x.0.cmp(&y.0));
    b.sort_by(|x, y| x.0.cmp(&y.0));
    assert_eq!(a, b);
    assert_eq!(a[0].1.len(), 11, "{a:?}");
    // The file with csm(16) taken out.
    let all: Vec<relief_runtime::cost::PipelineCost> = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    let some: Vec<_> = all.iter().filter(|c| !c.pipeline.starts_with("csm")).cloned().collect();
    assert!(some.len() < all.len());
    let json_some = dir.join("some.json");
    std::fs::write(&json_some, serde_json::to_vec(&some).unwrap()).unwrap();
    let partial = dir.join("partial");
    let s = run(&partial, Some(Compiler::from_recorded(&json_some).unwrap()));
    let note = s.gpu_note.expect("the run says that a pipeline was not priced");
    assert!(note.starts_with("1 of 3 pipelines have no GPU compiler columns") && note.contains("csm(16)"), "{note}");
    for r in relief_runtime::results::read(&partial).unwrap().rows {
        assert_eq!(r.metrics.gpu_navi21_instr_px.is_some(), !r.metrics.pipeline.to_string().starts_with("csm"));
    }
    // A file that is not one: one line.
    std::fs::write(dir.join("bad.json"), "{\"pipeline\": 3").unwrap();
    let e = Compiler::from_recorded(dir.join("bad.json")).unwrap_err().to_string();
    assert!(e.contains("bad.json") && e.contains("relief cost --json") && !e.contains('\n'), "{e}");

    // Without the compiler (its program missing): no GPU columns, the reason once.
    let without = dir.join("without");
    let s = run(&without, Some(Compiler::new("/nonexistent/relief")));
    let note = s.gpu_note.expect("the run says why it has no GPU columns");
    assert!(note.starts_with("no GPU compiler columns:") && !note.contains('\n'), "{note}");
    let text = std::fs::read_to_string(without.join("results.jsonl")).unwrap();
    assert!(!text.contains("gpu_"), "{text}");
    let csv = std::fs::read_to_string(without.join("results.csv")).unwrap();
    assert!(!csv.contains("gpu_"));
    relief_runtime::report::write(&without).expect("report");
    assert!(!std::fs::read_to_string(without.join("tables.md")).unwrap().contains("GPU compiler's model"));
    std::fs::remove_dir_all(&dir).ok();
}

/// `relief cost` prices mesh modules: every method of the stability matrix's mesh conditions
/// under each `curved=` mode compiles on RDNA2 and RDNA3 (nothing valid is refused), each of
/// `vs_mesh`, `fs_mesh` and `fs_mesh_depth` has registers and instructions, the colour and
/// depth entries of a marching search hold its loop, and the depth-only entry, the same trace
/// with no shading, has fewer instructions than the colour entry.
#[test]
fn mesh_modules_are_priced_on_rdna2_and_rdna3() {
    use relief_dsl::spec::Curved;
    let families: Vec<String> = relief_runtime::cost::DEFAULT_FAMILIES.iter().map(|s| s.to_string()).collect();
    let pipelines: Vec<relief_dsl::Pipeline> = relief_runtime::stability::mesh_methods()
        .into_iter()
        .flat_map(|p| Curved::ALL.map(|m| p.clone().with_curved(Some(m))))
        .collect();
    let each = compiler().cost_mesh_each(&pipelines, &families, false).unwrap();
    let refused: Vec<String> =
        pipelines.iter().zip(&each).filter_map(|(p, c)| c.as_ref().err().map(|e| format!("{p}: {e}"))).collect();
    assert!(refused.is_empty(), "{}", refused.join("\n"));
    for (p, costs) in pipelines.iter().zip(each) {
        let costs = costs.unwrap();
        assert_eq!(costs.iter().map(|c| c.family.as_str()).collect::<Vec<_>>(), ["navi21", "gfx1100"]);
        for c in &costs {
            for (what, s) in [("vs_mesh", &c.vertex), ("fs_mesh", &c.fragment), ("fs_mesh_depth", &c.depth)] {
                assert!(s.instructions > 0 && s.vgprs > 0 && s.code_bytes > 0, "{p} on {}: {what} {s:?}", c.family);
            }
            assert!(c.depth.instructions < c.fragment.instructions, "{p} on {}: depth-only has no shading", c.family);
            if p.coarse.name == "linear" {
                assert!(c.fragment_loop_body() > 0, "{p} on {}: linear's march is a loop", c.family);
                assert!(!c.depth.shape.loops.is_empty(), "{p} on {}: and so is the depth entry's", c.family);
            }
        }
    }
    // The command line prints the three entries per family, for a pipeline and for the mesh grid.
    let out = Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(["cost", "linear(32)+binary(5)+curved=prism", "--grid", "meshes"])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}\n{}", String::from_utf8_lossy(&out.stderr));
    assert!(text.contains("a model, not a clock"), "{text}");
    for what in ["vs", "fs", "depth"] {
        let lines =
            text.lines().filter(|l| l.trim_start().starts_with(&format!("{what} ")) && l.contains("instr")).count();
        assert_eq!(lines, 3 * 2, "{what}: the grid's three modes (prism once) on two families:\n{text}");
    }
}
