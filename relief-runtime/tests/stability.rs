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
        (19 + 7) * 4,
        "every implemented coarse × refine at default parameters, cone methods in both forms"
    );
    let scenes = ["spikes", "flat1", "seam", "walls", "boxes", "rock_bump"];
    let cells = stability::run(&gpu, 16, &methods, &scenes, &stability::ANGLES, |_, _| {}).unwrap();
    assert_eq!(cells.len(), methods.len() * scenes.len() * stability::ANGLES.len());
    // The safe cone methods, sphere tracing and maxmip never end past the first hit, with any
    // refinement after them.
    let safe = |m: &str| {
        let coarse = m.split('+').next().unwrap();
        ["csm", "qcsm", "cns", "mcns", "pcns", "sphere", "maxmip", "csm_relax", "sphere_relax"]
            .iter()
            .any(|n| coarse.starts_with(&format!("{n}(")))
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
    let refs = relief_runtime::reference_hits(&flat1, &rays, relief_runtime::Sampling::Bilinear).unwrap();
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
    let refs0 = relief_runtime::reference_hits(&flat0, &rays, relief_runtime::Sampling::Bilinear).unwrap();
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
    let refs = relief_runtime::reference_hits(&scene, &rays, relief_runtime::Sampling::Bilinear).unwrap();
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
    use relief_runtime::ProbeRay;
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

/// A 16 × 16 map, floor at 0, one texel (8, 8) at height 1: along texel row 8 the bilinear
/// surface is the tent h = 1 − |x − 8| in cell coordinates (x = 16u − 0.5), 0 elsewhere.
fn pillar(edge: relief_runtime::EdgeMode) -> relief_runtime::Scene {
    use relief_runtime::HeightMap;
    let hm = HeightMap::from_fn(16, 16, |x, y| if (x, y) == (8, 8) { 1.0 } else { 0.0 });
    let mut s = relief_runtime::Scene::from_height_map("pillar", hm);
    s.edge = edge;
    s
}

/// The ray along texel row 8 from u = 0.25 (x = 3.5) with dir (0.5, 0, −1): x = 3.5 + 8t,
/// z = 1 − t. It meets the pillar's front face (h = x − 7) where 1 − t = 8t − 3.5, at t = 1/2;
/// it is below the back face (h = 9 − x) until 1 − t = 5.5 − 8t, t = 9/14, and above the
/// surface from there until it reaches the floor at t = 1.
fn over_the_pillar() -> relief_runtime::ProbeRay {
    relief_runtime::ProbeRay { origin: [0.25, 8.5 / 16.0], dir: [0.5, 0.0, -1.0], x: 0, y: 0, pixel_size: 0.0 }
}

#[test]
fn skipped_rate_counts_a_ray_that_linear_search_carries_over_a_one_texel_pillar() {
    use relief_runtime::gpu::{self, Program, SceneTextures};
    use relief_runtime::metrics::Accuracy;
    use relief_runtime::EdgeMode;
    let g = Gpu::new().unwrap();
    for edge in [EdgeMode::Repeat, EdgeMode::Clamp] {
        let scene = pillar(edge);
        let tex = SceneTextures::new(&g, &scene);
        let rays = vec![over_the_pillar()];
        let refs = relief_runtime::reference_hits(&scene, &rays, relief_runtime::Sampling::Bilinear).unwrap();
        assert!(
            (refs[0].unwrap().t - 0.5).abs() < 1e-9,
            "{edge:?}: the exact hit is on the front face at t = 1/2: {refs:?}"
        );
        // linear(3) samples t = 1/3 (x = 6.17, h = 0), 2/3 (x = 8.83, h = 0.17 < z = 0.33) and
        // 1 (the floor): it steps over the pillar.
        let hits = gpu::probe(&g, &Program::new(&"linear(3)".parse().unwrap()).unwrap(), &scene, &tex, &rays).unwrap();
        assert!(hits[0].t as f64 > 9.0 / 14.0 + 0.1, "{edge:?}: linear(3) should end past the pillar: {:?}", hits[0]);
        let a = Accuracy::of(&rays, &hits, &refs, &scene.height, edge);
        assert_eq!((a.skipped, a.missed), (1, 1), "{edge:?}: jumped over the pillar, and past it: {a:?}");
        let c = stability::score("linear(3)", &scene, 45.0, &rays, &hits, &refs);
        assert_eq!((c.skipped_rate, c.past_rate), (1.0, 1.0), "{edge:?}: {c:?}");
        // Ending on the back face before t = 9/14 (still inside the pillar) skipped nothing.
        let inside = relief_runtime::gpu::GpuHit { t: 0.6, u: 0.25 + 0.3, v: 8.5 / 16.0, z: 0.4, ..hits[0] };
        let a = Accuracy::of(&rays, &[inside], &refs, &scene.height, edge);
        assert_eq!((a.skipped, a.missed), (0, 1), "{edge:?}: inside the pillar, past but not skipped: {a:?}");
    }
}

#[test]
fn a_hit_three_texels_past_a_flat_floor_is_past_but_not_skipped() {
    use relief_runtime::metrics::{one_texel_t, Accuracy};
    use relief_runtime::{EdgeMode, HeightMap};
    for edge in [EdgeMode::Repeat, EdgeMode::Clamp] {
        let floor = HeightMap::from_fn(16, 16, |_, _| 0.5);
        let ray = relief_runtime::ProbeRay { origin: [0.25, 0.5], dir: [0.5, 0.0, -1.0], x: 0, y: 0, pixel_size: 0.0 };
        // The exact hit: z = 1 − t = 0.5 at t = 1/2. One texel of travel is 1/16 in t (the
        // depth's 1/16 comes before the 1/8 a texel across takes), so 3 texels is t = 11/16.
        assert_eq!(one_texel_t(&ray, 16.0), 1.0 / 16.0);
        let exact = relief_runtime::RefHit { t: 0.5, u: 0.5, v: 0.5, z: 0.5 };
        let t = 0.5 + 3.0 / 16.0;
        let hit = relief_runtime::gpu::GpuHit {
            t,
            u: 0.25 + 0.5 * t,
            v: 0.5,
            z: 1.0 - t,
            coarse_steps: 1,
            refine_steps: 0,
            fetches: 1,
            converged: 1,
            clipped: 0,
        };
        let a = Accuracy::of(&[ray], &[hit], &[Some(exact)], &floor, edge);
        assert_eq!((a.skipped, a.missed, a.past), (0, 1, 1), "{edge:?}: {a:?}");
        let mut m = relief_runtime::metrics::Metrics::default();
        relief_runtime::metrics::set_accuracy(&mut m, &[ray], &[hit], &[Some(exact)], &floor, edge);
        assert_eq!((m.skipped_rate, m.past_rate, m.missed_rate), (0.0, 1.0, 1.0), "the old name is the same measure");
        // `relief stability` scores it with the same rules.
        let mut scene = relief_runtime::Scene::from_height_map("floor", floor.clone());
        scene.edge = edge;
        let c = stability::score("late", &scene, 45.0, &[ray], &[hit], &[Some(exact)]);
        assert_eq!((c.skipped_rate, c.past_rate, c.missed_rate), (0.0, 1.0, 1.0), "{edge:?}: {c:?}");
    }
}

/// `worst.md` picks each method's worst condition by skipped rate first: a condition where
/// every ray ends a little past the hit is not worse than one where some jumped geometry.
#[test]
fn the_worst_condition_is_the_one_that_skipped_geometry() {
    let cell = |scene: &str, skipped: f64, past: f64| stability::Cell {
        method: "linear(8)".into(),
        scene: scene.into(),
        angle: 60.0,
        rays: 100,
        nan_count: 0,
        outside_count: 0,
        skipped_rate: skipped,
        past_rate: past,
        missed_rate: past,
        nonconverged_rate: 0.0,
        above_surface_rate: 0.0,
        past_count: 0,
        ref_err_t_max: 0.1,
        ref_err_t_rms: 0.01,
    };
    let md = stability::worst_table(&[cell("flat1", 0.0, 0.9), cell("spikes", 0.05, 0.3)]);
    assert!(md.contains("| skipped rate | past rate |"), "{md}");
    assert!(md.contains("| `linear(8)` | spikes at 60° | 5.00% | 30.0% |"), "{md}");
}

/// A heat map has one `<rect>` per cell, in the group that strokes them grey and fills them
/// white; a cell at zero states no fill, the worst one is dark red (155, 0, 0), one in between
/// is lighter, and every cell's value is in its `<title>`.
#[test]
fn heat_maps_fill_only_the_cells_that_are_not_white() {
    let cell = |method: &str, scene: &str, angle: f32, skipped: f64| stability::Cell {
        method: method.into(),
        scene: scene.into(),
        angle,
        rays: 100,
        nan_count: 0,
        outside_count: 0,
        skipped_rate: skipped,
        past_rate: 0.0,
        missed_rate: 0.0,
        nonconverged_rate: 0.0,
        above_surface_rate: 0.0,
        past_count: 0,
        ref_err_t_max: 0.1,
        ref_err_t_rms: 0.01,
    };
    let cells = [
        cell("linear(8)", "scene:flat1", 0.0, 0.0),
        cell("linear(8)", "scene:spikes", 60.0, 0.5),
        cell("csm(8)", "scene:flat1", 0.0, 0.01),
        cell("csm(8)", "scene:spikes", 60.0, 0.0),
    ];
    let dir = std::env::temp_dir().join(format!("relief-stability-svg-{}", std::process::id()));
    stability::write(&dir, &cells).unwrap();
    let svg = std::fs::read_to_string(dir.join("stability_skipped_rate.svg")).unwrap();
    let group = &svg[svg.find("<g fill=\"#fff\" stroke=\"#ddd\">").expect("the cells' group")..];
    assert_eq!(group.matches("<rect ").count(), 4, "{svg}");
    assert_eq!(svg.matches("<rect ").count(), 4, "every rect in the group: {svg}");
    let rect = |m: &str, s: &str, a: u32| -> &str {
        let title = format!("<title>{m} on scene:{s} at {a}°: ");
        let end = group.find(&title).unwrap_or_else(|| panic!("{title} in {svg}"));
        &group[group[..end].rfind("<rect ").unwrap()..end]
    };
    // Columns flat1 0°, spikes 60°; rows linear(8), csm(8); cells 14 wide from x = 230, y = 120.
    assert_eq!(rect("linear(8)", "flat1", 0), "<rect x=\"230\" y=\"120\" width=\"14\" height=\"14\">");
    assert_eq!(
        rect("linear(8)", "spikes", 60),
        "<rect x=\"244\" y=\"120\" width=\"14\" height=\"14\" fill=\"#9b0000\">"
    );
    assert_eq!(rect("csm(8)", "spikes", 60), "<rect x=\"244\" y=\"134\" width=\"14\" height=\"14\">");
    // 0.01 is the floor of the log scale: k = 0.15, so (255 - 15, 255·0.85, 255·0.85) = (240, 216, 216).
    assert_eq!(rect("csm(8)", "flat1", 0), "<rect x=\"230\" y=\"134\" width=\"14\" height=\"14\" fill=\"#f0d8d8\">");
    assert!(group.contains("at 60°: 5.0000e-1</title>"), "{svg}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn robust_statistics_match_a_hand_computed_list() {
    use relief_runtime::{EdgeMode, HeightMap};
    // 101 rays onto a flat floor at 0.5 (exact hit t = 1/2), hit i ending i/1000 past it:
    // |t − t_ref| = i/1000, and the height error is the same i/1000 (z = 1 − t).
    let floor = HeightMap::from_fn(16, 16, |_, _| 0.5);
    let rays: Vec<_> = (0..101)
        .map(|i| relief_runtime::ProbeRay {
            origin: [i as f32 / 101.0, 0.5],
            dir: [0.5, 0.0, -1.0],
            x: i,
            y: 0,
            pixel_size: 0.0,
        })
        .collect();
    let refs: Vec<_> = rays
        .iter()
        .map(|r| Some(relief_runtime::RefHit { t: 0.5, u: r.origin[0] as f64 + 0.25, v: 0.5, z: 0.5 }))
        .collect();
    let hits: Vec<_> = (0..101)
        .map(|i| {
            let t = 0.5 + i as f32 / 1000.0;
            relief_runtime::gpu::GpuHit {
                t,
                u: rays[i].origin[0] + 0.5 * t,
                v: 0.5,
                z: 1.0 - t,
                coarse_steps: 1,
                refine_steps: 0,
                fetches: 1,
                converged: 1,
                clipped: 0,
            }
        })
        .collect();
    let mut m = relief_runtime::metrics::Metrics::default();
    relief_runtime::metrics::set_accuracy(&mut m, &rays, &hits, &refs, &floor, EdgeMode::Repeat);
    // Nearest rank on 101 sorted values: the median is the 51st (0.050), p90 the 91st
    // (0.090), p99 the 100th (0.099).
    for (got, want, what) in
        [(m.ref_err_t_median, 0.050, "median"), (m.ref_err_t_p90, 0.090, "p90"), (m.ref_err_t_p99, 0.099, "p99")]
    {
        assert!((got - want).abs() < 1e-6, "{what}: {got} (want {want})");
    }
    // The worst 1 % is ⌈1.01⌉ = 2 rays: (0.100² + 0.099²) / Σ (i/1000)² = 0.019801 / 0.33835.
    let share = 0.019801 / 0.33835;
    assert!((m.mse_worst1_share - share).abs() < 1e-4 * share, "worst 1 %: {} (want {share})", m.mse_worst1_share);
}
