//! Compiling every default combination (every coarse × refine × shadow stage of the
//! catalogue at default parameters) to all three targets: build the module, validate, and
//! write WGSL, SPIR-V and GLSL for each entry point. Goal: under 1 s for all of them on a
//! 2-core machine.

use criterion::{criterion_group, criterion_main, Criterion};
use relief_dsl::{emit, Pipeline};

fn all_targets(c: &mut Criterion) {
    let all = Pipeline::all_defaults();
    let mut g = c.benchmark_group("compile");
    g.sample_size(10);
    g.bench_function(format!("all_{}_default_combinations_to_wgsl_spirv_glsl", all.len()), |b| {
        b.iter(|| {
            for p in &all {
                let out = emit::emit(p).expect("every default combination compiles");
                std::hint::black_box(out);
            }
        })
    });
    g.bench_function("one_pipeline_linear32_binary5", |b| {
        let p: Pipeline = "linear(32)+binary(5)".parse().unwrap();
        b.iter(|| std::hint::black_box(emit::emit(&p).unwrap()))
    });
    g.finish();
}

criterion_group!(benches, all_targets);
criterion_main!(benches);
