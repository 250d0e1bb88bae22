//! No method produces NaN, Inf or a hit outside the volume, at any angle, on the stress
//! scenes, measured on the raw hits (nothing clamps them before they are counted), and the
//! scores see a stage that is broken on purpose.

use relief_runtime::gpu::Gpu;
use relief_runtime::stability;

#[test]
fn every_method_stays_finite_and_inside_the_volume_at_every_angle() {
    let gpu = Gpu::new().unwrap();
    let methods = stability::methods();
    assert_eq!(
        methods.len(),
        (17 + 7) * 4,
        "every implemented coarse × refine at default parameters, cone methods in both forms"
    );
    let scenes = ["spikes", "flat1", "seam", "walls", "boxes", "rock_bump"];
    let cells = stability::run(&gpu, 16, &methods, &scenes, &stability::ANGLES, |_, _| {}).unwrap();
    assert_eq!(cells.len(), methods.len() * scenes.len() * stability::ANGLES.len());
    // The safe cone methods, sphere tracing and maxmip never end past the first hit, with any
    // refinement after them.
    let safe = |m: &str| {
        let coarse = m.split('+').next().unwrap();
        ["csm", "qcsm", "cns", "mcns", "pcns", "sphere", "maxmip"].iter().any(|n| coarse.starts_with(&format!("{n}(")))
            && !coarse.contains("textbook")
    };
    let past: Vec<String> = cells
        .iter()
        .filter(|c| safe(&c.method) && c.past_count > 0)
        .map(|c| {
            format!(
                "{} on {} at {}°: {} rays past the first hit (max t error {:.2e})",
                c.method, c.scene, c.angle, c.past_count, c.ref_err_t_max
            )
        })
        .collect();
    assert!(past.is_empty(), "{} cells:\n{}", past.len(), past.join("\n"));
    let bad: Vec<_> = cells.iter().filter(|c| c.nan_count > 0 || c.outside_count > 0).collect();
    let list: Vec<String> = bad
        .iter()
        .map(|c| {
            format!(
                "{} on {} at {}°: {} NaN, {} outside (max t error {:.3})",
                c.method, c.scene, c.angle, c.nan_count, c.outside_count, c.ref_err_t_max
            )
        })
        .collect();
    assert!(bad.is_empty(), "{} bad cells:\n{}", bad.len(), list.join("\n"));
}

#[test]
fn the_scores_see_what_they_measure() {
    // On a flat surface at height 1 every ray hits at its entry; a method that answers t = 0
    // is exact there, and the same answer on flat 0 has not converged.
    use relief_runtime::gpu::GpuHit;
    let flat1 = stability::scene("flat1", 16).unwrap();
    let rays = stability::rays(&flat1, 4, 60.0);
    let refs = relief_runtime::reference::reference_hits(&flat1, &rays, relief_runtime::reference::Sampling::Bilinear)
        .unwrap();
    let at_entry: Vec<GpuHit> = rays
        .iter()
        .map(|r| GpuHit {
            t: 0.0,
            u: r.origin[0],
            v: r.origin[1],
            z: 1.0,
            coarse_steps: 1,
            refine_steps: 0,
            fetches: 1,
            converged: 1,
            clipped: 0,
        })
        .collect();
    let c = stability::score("entry", &flat1, 60.0, &rays, &at_entry, &refs);
    assert_eq!(
        (c.nan_count, c.outside_count, c.missed_rate, c.nonconverged_rate, c.above_surface_rate),
        (0, 0, 0.0, 0.0, 0.0)
    );
    let flat0 = stability::scene("flat0", 16).unwrap();
    let refs0 = relief_runtime::reference::reference_hits(&flat0, &rays, relief_runtime::reference::Sampling::Bilinear)
        .unwrap();
    let c = stability::score("entry", &flat0, 60.0, &rays, &at_entry, &refs0);
    assert_eq!((c.nonconverged_rate, c.above_surface_rate, c.missed_rate), (0.0, 1.0, 0.0));
    assert!((c.ref_err_t_max - 1.0).abs() < 1e-6);
    let gave_up: Vec<GpuHit> = at_entry.iter().map(|h| GpuHit { converged: 0, ..*h }).collect();
    assert_eq!(stability::score("gave up", &flat0, 60.0, &rays, &gave_up, &refs0).nonconverged_rate, 1.0);
    let mut broken = at_entry.clone();
    broken[0].t = f32::NAN;
    broken[1].t = -0.5;
    let c = stability::score("broken", &flat1, 60.0, &rays, &broken, &refs);
    assert_eq!((c.nan_count, c.outside_count), (1, 1));
}

/// `linear(4)` with its probe variant's coarse search made to return `bracket` (WGSL, `RAY`
/// standing for the function's ray argument) instead of what it found: a stage broken on
/// purpose.
fn broken_linear(bracket: &str) -> relief_runtime::gpu::Program {
    let mut p = relief_runtime::gpu::Program::new(&"linear(4)".parse().unwrap()).unwrap();
    let start = p.wgsl.find("fn coarse_linear_counted(").expect("the probe variant of the coarse stage");
    let args = start + "fn coarse_linear_counted(".len();
    let ray = p.wgsl[args..args + p.wgsl[args..].find(':').unwrap()].to_string();
    let ret = start + p.wgsl[start..].find("return Bracket(").unwrap();
    let end = ret + p.wgsl[ret..].find(";\n").unwrap();
    p.wgsl.replace_range(ret..end, &format!("return {}", bracket.replace("RAY", &ray)));
    p
}

#[test]
fn a_broken_stage_is_caught_by_the_scores_and_the_metrics() {
    use relief_runtime::gpu::{self, SceneTextures};
    let g = Gpu::new().unwrap();
    let scene = stability::scene("walls", 16).unwrap();
    let tex = SceneTextures::new(&g, &scene);
    let rays = stability::rays(&scene, 8, 45.0);
    let refs = relief_runtime::reference::reference_hits(&scene, &rays, relief_runtime::reference::Sampling::Bilinear)
        .unwrap();
    let n = rays.len();
    let run = |program: &relief_runtime::gpu::Program| {
        let hits = gpu::probe(&g, program, &scene, &tex, &rays).unwrap();
        let cell = stability::score("broken", &scene, 45.0, &rays, &hits, &refs);
        let mut m = relief_runtime::metrics::Metrics::default();
        relief_runtime::metrics::set_accuracy(&mut m, &rays, &hits, &refs, &scene.height, scene.edge);
        (cell, m)
    };
    // Ends below the floor: t = 2 where the floor is at t = 1.
    let (cell, m) = run(&broken_linear("Bracket(0f, 2f, true)"));
    assert_eq!((cell.outside_count, cell.nan_count), (n, 0), "{cell:?}");
    assert_eq!(m.outside_count as usize, n);
    assert_eq!(cell.missed_rate, 1.0, "a hit one whole depth past the first hit has missed");
    // Returns NaN (0/0 at run time: WGSL has no NaN constant).
    let (cell, m) = run(&broken_linear("Bracket(0f, (RAY.dir.z - RAY.dir.z) / (RAY.dir.z - RAY.dir.z), true)"));
    assert_eq!((cell.nan_count, cell.missed_rate), (n, 1.0), "{cell:?}");
    assert_eq!(m.nan_count as usize, n);
    assert!(m.mse_dissertation >= n as f64 && m.missed_rate == 1.0, "NaN hits count as errors: {m:?}");
    // Runs out of steps: refinement is skipped and the probe reports it.
    let (cell, m) = run(&broken_linear("Bracket(0.125f, 0.25f, false)"));
    assert_eq!((cell.nonconverged_rate, m.nonconverged_rate), (1.0, 1.0));
    // The unbroken stage, for contrast.
    let (cell, m) = run(&relief_runtime::gpu::Program::new(&"linear(4)".parse().unwrap()).unwrap());
    assert_eq!((cell.nan_count, cell.outside_count, m.nonconverged_rate), (0, 0, 0.0));
}

/// One texel of travel, the one definition the metrics, the stability scores and the cone
/// tests share: a ray crosses a texel horizontally after 1/(N·|d.xy|), or 1/N of the depth
/// after 1/(N·|d.z|), whichever comes first. A straight-down ray therefore crosses a texel
/// after 1/N (the old `max(1e-9)` form made that 1e9/N: nothing could count as missed).
#[test]
fn one_texel_of_travel_is_horizontal_or_vertical_whichever_comes_first() {
    use relief_runtime::metrics::one_texel_t;
    use relief_runtime::scene::ProbeRay;
    let ray = |dir: [f32; 3]| ProbeRay { origin: [0.5, 0.5], dir, x: 0, y: 0, pixel_size: 0.0 };
    assert!((one_texel_t(&ray([0.0, 0.0, -1.0]), 64.0) - 1.0 / 64.0).abs() < 1e-12);
    assert!(
        (one_texel_t(&ray([0.5, 0.0, -1.0]), 64.0) - 1.0 / 64.0).abs() < 1e-12,
        "steeper than 45°: the depth decides"
    );
    assert!(
        (one_texel_t(&ray([3.0, 4.0, -1.0]), 64.0) - 1.0 / (64.0 * 5.0)).abs() < 1e-12,
        "grazing: the horizontal texel decides"
    );
}
