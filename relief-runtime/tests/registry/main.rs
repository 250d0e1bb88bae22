//! Tests that add methods to the catalogue with `register`, in a test binary of their own.
//!
//! The catalogue is global to a process and a registration is permanent, so a registered
//! method would join the stability matrix (`stability::methods`, every method in the
//! catalogue) and what the other tests count. Those tests live in the `runtime` binary; the
//! ones that register live here.

use relief_runtime::gpu::{self, Gpu, Program, SceneTextures};
use relief_runtime::Scene;

fn gpu() -> Gpu {
    Gpu::new().unwrap_or_else(|e| panic!("{e}"))
}

/// A coarse stage whose loop skips the rest of every pass after the fifth with `continue_if`:
/// ten passes, five of them counted. Its bracket is at t = counted/16 (exact in f32).
fn count_with_continue<'a>(
    s: &'a relief_dsl::ir::FnBuilder<'a>,
    _: &relief_dsl::stage::Ray<'a>,
    _: &relief_dsl::spec::Args,
) -> Result<relief_dsl::stage::Bracket<'a>, relief_dsl::CompileError> {
    let mut pass = s.var("pass", 0.0);
    let mut counted = s.var("counted", 0.0);
    s.repeat(10, |l| {
        pass += 1.0;
        l.continue_if(pass.gt(5.0));
        counted += 1.0;
    });
    let t = counted / 16.0;
    Ok(relief_dsl::stage::Bracket::searched(t, t, s.lit_bool(true)))
}

#[test]
fn a_loop_with_continue_still_counts_every_pass() {
    use relief_dsl::spec::{register, MethodDef};
    use relief_dsl::stage::StageFn;
    register(MethodDef::new("test_continue_count", "a test", StageFn::Coarse(count_with_continue))).unwrap();
    let p: relief_dsl::Pipeline = "test_continue_count".parse().unwrap();
    let g = gpu();
    let scene = Scene::by_name("rock_bump", Some(32)).unwrap();
    let program = Program::new(&p).unwrap();
    let tex = SceneTextures::new(&g, &scene);
    let rays = scene.rays(8);
    let hits = gpu::probe(&g, &program, &scene, &tex, &rays).unwrap_or_else(|e| panic!("{e}"));
    assert!(!hits.is_empty());
    for h in &hits {
        // Every one of the ten passes runs (the pass counter steps in the loop's continuing
        // block, which a `continue` does not skip); the five after the fifth skip the count.
        assert_eq!(h.coarse_steps, 10, "{h:?}");
        assert_eq!(h.t, 5.0 / 16.0, "{h:?}");
    }
}
