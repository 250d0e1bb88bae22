//! Tests that add methods to the catalogue with `register`, in a test binary of their own.
//!
//! The catalogue is global to a process and a registration is permanent, so a registered
//! method would show up in what the other tests count and list (every built-in method × every
//! refinement, `Pipeline::all_defaults`, the text form's random stages). Those tests live in
//! the `facade` binary; the ones that register live here.

#[path = "../../examples/custom_stage.rs"]
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
    let names: Vec<String> = rows.iter().map(|r| r.metrics.pipeline.to_string()).collect();
    assert_eq!(
        names,
        ["linear(16)", "geometric(16, 10)", "geometric(16, 0)", "geometric(16, 25)+binary(5)", "linear(16)+binary(5)"]
    );
    assert!(rows.iter().all(|r| r.status.is_ok() && r.metrics.frame_ms_median > 0.0), "{rows:#?}");
    let by = |p: &str| &rows.iter().find(|r| r.metrics.pipeline.to_string() == p).unwrap().metrics;
    // At growth 0 the search takes linear(16)'s steps exactly (first step 1/16, the same
    // f32 sums), so it finds the same brackets: the same steps taken, the same error.
    let (lin, geo0) = (by("linear(16)"), by("geometric(16, 0)"));
    assert_eq!(lin.avg_coarse_steps, geo0.avg_coarse_steps);
    assert_eq!(lin.ref_err_t_rms, geo0.ref_err_t_rms);
    assert!(rows.iter().all(|r| r.metrics.nan_count == 0 && r.metrics.ref_err_t_rms.is_finite()), "{rows:#?}");
    std::fs::remove_dir_all(&dir).unwrap();
}
