//! `examples/integrate.rs` — an engine's own material shader importing a generated WGSL
//! library — draws the same picture as `relief render` (the render entry relief composes
//! itself) for the same pipeline and scene.
//!
//! Both run the same search on the same rasterized quad with the same lighting, so they
//! differ only where the two shaders' arithmetic rounds differently (a ray that lands on the
//! other side of a texel edge or of a step). The goal stated here: a mean absolute difference
//! of at most 1 (of 255) per channel, and at most 1 % of the pixels differing by more than 8.

#[path = "../examples/integrate.rs"]
#[allow(dead_code)]
mod integrate;

use relief::runtime::gpu::{self, Gpu, Program, SceneTextures};
use relief::runtime::scene::Scene;
use relief::Pipeline;

fn relief_render(p: &Pipeline, scene: &Scene, size: u32) -> Vec<u8> {
    let g = Gpu::new().unwrap();
    let program = Program::new(p).unwrap();
    let mut tex = SceneTextures::new(&g, scene);
    tex.add_maps(&g, scene, &p.required_maps()).unwrap();
    gpu::render(&g, &program, scene, &tex, size, 0, 1).unwrap().rgba
}

#[test]
fn the_integration_example_matches_relief_render() {
    let size = 128;
    for (pipe, scene) in [
        ("linear(32)+binary(5)+shadow=soft(16)", "lion"),
        ("csm(15)+binary(4)+shadow=soft_ratio(10)+ao=cone_ratio", "rock_bump"),
        ("maxmip(64)+shadow=hard(16)", "shapes"),
    ] {
        let p: Pipeline = pipe.parse().unwrap();
        let scene = Scene::by_name(scene, Some(64)).unwrap();
        let ours = integrate::run(&p, &scene, size).unwrap();
        let theirs = relief_render(&p, &scene, size);
        assert_eq!(ours.len(), theirs.len());
        let (mut sum, mut n, mut big) = (0u64, 0u64, 0u64);
        for (px_a, px_b) in ours.chunks(4).zip(theirs.chunks(4)) {
            let mut worst = 0;
            for c in 0..3 {
                let d = (px_a[c] as i32 - px_b[c] as i32).unsigned_abs();
                sum += d as u64;
                n += 1;
                worst = worst.max(d);
            }
            if worst > 8 {
                big += 1;
            }
        }
        let mean = sum as f64 / n as f64;
        let share = big as f64 / (size * size) as f64;
        println!("{pipe} on {}: mean |difference| {mean:.4} of 255, {:.3} % of pixels off by more than 8", scene.name, share * 100.0);
        assert!(mean <= 1.0, "{pipe}: mean absolute difference {mean}");
        assert!(share <= 0.01, "{pipe}: {:.3} % of pixels differ by more than 8", share * 100.0);
        // The picture is not empty: the quad covers most of the frame in lit colours.
        let lit = ours.chunks(4).filter(|px| px[0] > 20 || px[1] > 20 || px[2] > 20).count();
        assert!(lit > (size * size / 3) as usize, "{pipe}: only {lit} lit pixels");
    }
}
