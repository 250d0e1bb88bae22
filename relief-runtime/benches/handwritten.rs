//! Generated vs hand-written: `linear(32)+binary(5)` from relief against the same method
//! written by hand in WGSL (`handwritten_pom.wgsl`), rendered on the same scene in the same
//! run, alternating, with render-pass timestamps. Run with `LP_NUM_THREADS=1`.
//!
//! Prints each side's median frame time and the ratio generated / hand-written (goal ≤ 1.02).

use relief_runtime::gpu::{self, Gpu, Program, SceneTextures};
use relief_runtime::metrics::percentile;
use relief_runtime::Scene;

fn main() {
    if std::env::args().any(|a| a == "--list") {
        println!("generated_vs_handwritten: benchmark");
        return;
    }
    let g = Gpu::new().unwrap_or_else(|e| panic!("{e}"));
    let scene = Scene::by_name("rock_bump", Some(256)).unwrap();
    let tex = SceneTextures::new(&g, &scene);
    let generated = Program::new(&"linear(32)+binary(5)".parse().unwrap()).unwrap();
    // The hand-written shader binds what the generated one binds, at the same numbers.
    let hand = Program {
        wgsl: include_str!("handwritten_pom.wgsl").to_string(),
        bindings: generated.bindings.clone(),
        render_bindings: vec![0, 1, 2, 4, 5],
        probe_bindings: vec![],
        maps: vec![],
        writes_depth: false,
        map_levels: false,
    };
    let size = 512;
    let rounds = 8;
    let frames = 25;
    let (mut gen_ms, mut hand_ms) = (Vec::new(), Vec::new());
    for round in 0..rounds {
        // Alternate which goes first, so drift on a shared machine hits both alike.
        let order: [(&Program, &mut Vec<f64>); 2] = if round % 2 == 0 {
            [(&generated, &mut gen_ms), (&hand, &mut hand_ms)]
        } else {
            [(&hand, &mut hand_ms), (&generated, &mut gen_ms)]
        };
        for (prog, out) in order {
            let r = gpu::render(&g, prog, &scene, &tex, size, 3, frames).unwrap_or_else(|e| panic!("{e}"));
            out.extend(r.frame_ms);
        }
    }
    let (mg, mh) = (percentile(&gen_ms, 0.5), percentile(&hand_ms, 0.5));
    println!("adapter: {} ({})", g.adapter, g.driver);
    println!("scene rock_bump, {size}x{size}, {} frames each, {rounds} alternating rounds", rounds * frames);
    println!(
        "generated   linear(32)+binary(5): median {mg:.3} ms (p10 {:.3}, p90 {:.3})",
        percentile(&gen_ms, 0.1),
        percentile(&gen_ms, 0.9)
    );
    println!(
        "hand-written linear 32 + binary 5: median {mh:.3} ms (p10 {:.3}, p90 {:.3})",
        percentile(&hand_ms, 0.1),
        percentile(&hand_ms, 0.9)
    );
    println!("ratio generated / hand-written: {:.4}", mg / mh);
}
