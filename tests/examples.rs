//! The examples' bodies, run as tests (cargo builds the examples themselves with the tests).

#[path = "../examples/declare.rs"]
#[allow(dead_code)]
mod declare;
#[path = "../examples/generate.rs"]
#[allow(dead_code)]
mod generate;

#[test]
fn declare_prints_the_combinations() {
    let lines = declare::run();
    assert!(lines.iter().any(|l| l.contains("linear(15)+binary(6)+shadow=soft(30)")), "{lines:#?}");
    assert!(lines.iter().any(|l| l.contains("iterative_parallax(4)+shadow=hard(24)  (reads: normal)")), "{lines:#?}");
    assert!(
        lines.iter().any(|l| l.contains("a grid of 15 pipelines, from linear(8) to linear_dynamic(8, 32)+interval(3)")),
        "{lines:#?}"
    );
}

#[test]
fn generate_writes_five_files_per_pipeline() {
    let dir = std::env::temp_dir().join(format!("relief-example-generate-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let stems = generate::run(&dir).unwrap();
    assert_eq!(stems.len(), 3 * 3 * 2);
    assert!(stems.contains(&"linear_16__interval_4__shadow-soft_16".to_string()), "{stems:?}");
    let files = std::fs::read_dir(&dir).unwrap().count();
    assert_eq!(files, stems.len() * 5);
    for s in &stems {
        let wgsl = std::fs::read_to_string(dir.join(format!("{s}.wgsl"))).unwrap();
        assert!(wgsl.contains("fn fs_main("), "{s}");
        let spv = std::fs::read(dir.join(format!("{s}.spv"))).unwrap();
        assert_eq!(&spv[..4], &0x0723_0203u32.to_le_bytes(), "{s}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[path = "../examples/sweep.rs"]
#[allow(dead_code)]
mod sweep;

#[test]
fn sweep_measures_the_grid_and_writes_the_report() {
    let dir = std::env::temp_dir().join(format!("relief-example-sweep-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let (cells, files) = sweep::run(&dir).unwrap();
    assert_eq!(cells, 4 * 2 * 2, "4 coarse × 2 refine × 2 scenes");
    assert!(files > 0);
    let rows = relief::runtime::results::read_for_append(&dir).unwrap();
    assert_eq!(rows.len(), cells);
    assert!(rows.iter().all(|r| r.status == "ok" && r.metrics.frame_ms_median > 0.0));
    assert!(dir.join("index.html").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[path = "../examples/custom_stage.rs"]
#[allow(dead_code)]
mod custom_stage;

#[test]
fn a_registered_stage_reads_like_a_built_in() {
    custom_stage::register_geometric().unwrap();
    // Registering twice in one slot is refused; the first definition stays.
    let again = relief::dsl::spec::MethodDef::new("geometric", "", custom_stage::stage_fn());
    let e = relief::dsl::spec::register(again).unwrap_err();
    assert!(e.to_string().contains("already has a method called `geometric`"), "{e}");
    // The text form: defaults filled in, canonical text, the catalogue's range checks.
    let p: relief::Pipeline = "geometric(12)+binary(4)".parse().unwrap();
    assert_eq!(p.to_string(), "geometric(12, 10)+binary(4)");
    let e = "geometric(12, 101)".parse::<relief::Pipeline>().unwrap_err();
    assert!(e.to_string().contains("out of range: allowed 0..=100"), "{e}");
    let e = "geometrc(12)".parse::<relief::Pipeline>().unwrap_err();
    assert!(e.to_string().contains("did you mean `geometric`"), "{e}");
    // Grids and the catalogue listing see it; the shader has its stage function and reads
    // only the height map.
    let g: relief::Grid = "coarse: geometric([8, 16], growth = 0..=20 step 10)".parse().unwrap();
    assert_eq!(g.cells().len(), 6);
    assert!(relief::dsl::spec::catalog().iter().any(|m| m.name == "geometric" && m.slot == relief::Slot::Coarse));
    assert!(p.required_maps().is_empty());
    let shaders = relief::dsl::emit::emit(&p).unwrap();
    assert!(shaders.wgsl.contains("fn coarse_geometric("), "{}", shaders.wgsl);
}

#[test]
fn custom_stage_sweeps_against_linear() {
    let dir = std::env::temp_dir().join(format!("relief-example-custom-stage-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let rows = custom_stage::run(&dir).unwrap();
    let names: Vec<&str> = rows.iter().map(|r| r.metrics.pipeline.as_str()).collect();
    assert_eq!(
        names,
        ["linear(16)", "geometric(16, 10)", "geometric(16, 0)", "geometric(16, 25)+binary(5)", "linear(16)+binary(5)"]
    );
    assert!(rows.iter().all(|r| r.status == "ok" && r.metrics.frame_ms_median > 0.0), "{rows:#?}");
    let by = |p: &str| &rows.iter().find(|r| r.metrics.pipeline == p).unwrap().metrics;
    // At growth 0 the search takes linear(16)'s steps exactly (first step 1/16, the same
    // f32 sums), so it finds the same brackets: the same steps taken, the same error.
    let (lin, geo0) = (by("linear(16)"), by("geometric(16, 0)"));
    assert_eq!(lin.avg_coarse_steps, geo0.avg_coarse_steps);
    assert_eq!(lin.ref_err_t_rms, geo0.ref_err_t_rms);
    assert!(rows.iter().all(|r| r.metrics.nan_count == 0 && r.metrics.ref_err_t_rms.is_finite()), "{rows:#?}");
    std::fs::remove_dir_all(&dir).unwrap();
}
