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

/// A flat condition's cell for the tests of the written files: 100 rays, `skipped` the
/// skipped rate, nothing past, no NaN, t error 0.1 at most and 0.01 RMS, no mesh figures.
pub(crate) fn flat_cell(method: &str, scene: &str, angle: f32, skipped: f64) -> stability::Cell {
    stability::Cell {
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
        coverage_error: None,
        extra: None,
        missing: None,
    }
}

/// `worst.md` picks each method's worst condition by skipped rate first: a condition where
/// every ray ends a little past the hit is not worse than one where some jumped geometry.
#[test]
fn the_worst_condition_is_the_one_that_skipped_geometry() {
    let cell = |scene: &str, skipped: f64, past: f64| stability::Cell {
        past_rate: past,
        missed_rate: past,
        ..flat_cell("linear(8)", scene, 60.0, skipped)
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
    let cells = [
        flat_cell("linear(8)", "scene:flat1", 0.0, 0.0),
        flat_cell("linear(8)", "scene:spikes", 60.0, 0.5),
        flat_cell("csm(8)", "scene:flat1", 0.0, 0.01),
        flat_cell("csm(8)", "scene:spikes", 60.0, 0.0),
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

/// The mesh conditions' cells checked against an independent computation on a hand-built
/// case: a flat square (−1..1)² in z = 0, normal +z, uv = (p + 1)/2, with a constant height
/// h (as the device stores ½) and clamp edges, so that S is the square lowered to
/// z = −depth·(1 − h), with no walls. Per pixel-centre ray, in closed form: the base square is
/// drawn where the ray meets it (`curved=none` draws exactly those pixels, its search finding
/// the lowered plane below every drawn pixel), the reference hits where the ray meets the
/// lowered square. So `extra` is the pixels whose ray meets the square but not the lowered one,
/// `missing` the reverse, and on pixels both hit the GPU's t lies within the search's last
/// bracket of the plane's: `linear(32)+binary(5)` ends within 1/1024 of the depth along the
/// normal, 1/(1024·|d.z|) depths along the ray. The cell's RMS t and past count must match the
/// test's own from the GPU's hits and the plane's t, within the reference's ε (a hit within ε
/// of S lies within ε/|d.z| of the plane along the ray).
#[test]
fn a_mesh_cell_matches_the_closed_form_on_a_lowered_square() {
    use glam::{DVec3, Vec3};
    use relief_dsl::spec::Curved;
    use relief_runtime::gpu::mesh::{probe_mesh, MeshProgram};
    use relief_runtime::gpu::SceneTextures;
    use relief_runtime::mesh::{MeshReference, MeshScene};
    let g = Gpu::new().unwrap();
    let mut sc = relief_runtime::Scene::from_height_map("square", relief_runtime::HeightMap::new(8, 8, vec![0.5; 64]));
    sc.edge = relief_runtime::EdgeMode::Clamp;
    sc.depth_scale = 0.1;
    sc.camera.angle_deg = 70.0;
    sc.camera.azimuth_deg = -60.0;
    sc.camera.distance = 2.5;
    sc.camera.fov_deg = 60.0;
    sc.camera.target = Vec3::ZERO;
    let ms = MeshScene { scene: sc, mesh: super::meshes::flat_square(), notes: Default::default() };
    let h = SceneTextures::new(&g, &ms.scene).heights_on_device[0] as f64;
    let depth = ms.scene.depth_scale as f64;
    let eps = MeshReference::default_tolerance(&ms.mesh, depth);
    let size = 24;
    let text = "linear(32)+binary(5)+curved=none";
    let pipeline: relief_dsl::Pipeline = text.parse().unwrap();
    assert_eq!(pipeline.curved, Some(Curved::None));
    let programs = vec![(text.to_string(), MeshProgram::new(&pipeline).unwrap())];
    let cells = stability::mesh_condition(&g, size, &programs, ms.clone(), 70.0).unwrap();
    assert_eq!(cells.len(), 1);
    let cell = &cells[0];
    assert!(cell.is_mesh());
    // The test's own: closed-form coverage, and the GPU's t against the plane's.
    let probe = probe_mesh(&g, &programs[0].1, &ms, &SceneTextures::new(&g, &ms.scene), size).unwrap();
    let plane = -depth * (1.0 - h);
    let meets = |o: DVec3, d: DVec3, z: f64| {
        let t = (z - o.z) / d.z;
        let p = o + t * d;
        (t > 0.0 && p.x.abs() <= 1.0 && p.y.abs() <= 1.0).then_some(t)
    };
    let (mut extra, mut missing, mut both) = (0, 0, 0);
    let (mut sum, mut past_lo, mut past_hi, mut dz_min) = (0.0, 0, 0, f64::INFINITY);
    for (r, hit) in ms.rays(size, size).iter().zip(&probe.hits) {
        let (o, d) = (DVec3::from(r.origin.map(f64::from)), DVec3::from(r.dir.map(f64::from)));
        let (top, low) = (meets(o, d, 0.0), meets(o, d, plane));
        assert_eq!(hit[3] > 0.5, top.is_some(), "pixel ({}, {}): curved=none draws the base square", r.x, r.y);
        match (top, low) {
            (Some(_), None) => extra += 1,
            (None, Some(_)) => missing += 1,
            (Some(_), Some(t)) => {
                both += 1;
                let dt = (hit[2] as f64 - t) / depth;
                let bound = 1.0 / (1024.0 * d.z.abs()) + 1e-4;
                assert!(dt.abs() <= bound, "pixel ({}, {}): t off by {dt} depths (bound {bound})", r.x, r.y);
                sum += dt * dt;
                dz_min = dz_min.min(d.z.abs());
                // The cell's slack, with the reference's t anywhere within ε/|d.z| of the plane's.
                let slack = |t_ref: f64| relief_runtime::mesh_measure::past_slack(eps, t_ref, depth);
                let shift = eps / d.z.abs() / depth;
                past_lo += usize::from(dt - shift > slack(t) + shift);
                past_hi += usize::from(dt + shift > slack(t) - shift);
            }
            (None, None) => {}
        }
    }
    assert!(extra > 0 && missing > 0 && both > 100, "the view shows both edges: {extra} {missing} {both}");
    assert_eq!((cell.extra, cell.missing, cell.rays), (Some(extra), Some(missing), (size * size) as usize));
    let cov = (extra + missing) as f64 / (size * size) as f64;
    assert!((cell.coverage_error.unwrap() - cov).abs() < 1e-12, "{cell:?}");
    let rms = (sum / both as f64).sqrt();
    let tol = eps / dz_min / depth;
    assert!((cell.ref_err_t_rms - rms).abs() <= tol, "RMS t {} against {rms} (±{tol})", cell.ref_err_t_rms);
    assert!((past_lo..=past_hi).contains(&cell.past_count), "past {} not in {past_lo}..={past_hi}", cell.past_count);
    assert_eq!((cell.nan_count, cell.outside_count), (0, 0));
}

/// `relief stability`'s files with mesh cells: `stability.csv` holds them with their
/// coverage columns (empty for flat cells) and parses back, `worst.md` gains the mesh table,
/// and the mesh heat maps exist with one `<rect>` per mesh cell; without mesh cells none of
/// that is written and the flat files are the same bytes.
#[test]
fn mesh_cells_appear_in_the_csv_the_worst_table_and_their_heat_maps() {
    let flat = |method: &str, skipped: f64| flat_cell(method, "scene:flat1", 60.0, skipped);
    let mesh = |mode: &str, angle: f32, extra: usize, missing: usize| stability::Cell {
        method: format!("linear(32)+binary(5)+curved={mode}"),
        scene: "sphere:rocks".into(),
        angle,
        rays: 400,
        skipped_rate: f64::NAN,
        past_rate: f64::NAN,
        missed_rate: f64::NAN,
        nonconverged_rate: f64::NAN,
        above_surface_rate: f64::NAN,
        past_count: 3,
        ref_err_t_rms: 0.25,
        coverage_error: Some((extra + missing) as f64 / 400.0),
        extra: Some(extra),
        missing: Some(missing),
        ..flat("x", 0.0)
    };
    let flat_cells = vec![flat("linear(8)", 0.1), flat("csm(8)", 0.0)];
    let mut cells = flat_cells.clone();
    cells.extend([
        mesh("none", 75.0, 8, 0),
        mesh("none", 89.0, 12, 0),
        mesh("prism", 75.0, 0, 4),
        mesh("prism", 89.0, 1, 1),
    ]);
    let base = std::env::temp_dir().join(format!("relief-stability-mesh-{}", std::process::id()));
    let (with, without) = (base.join("with"), base.join("without"));
    stability::write(&with, &cells).unwrap();
    stability::write(&without, &flat_cells).unwrap();
    // The CSV parses back: 6 records, the mesh ones with their coverage columns.
    let mut r = csv::Reader::from_path(with.join("stability.csv")).unwrap();
    let headers = r.headers().unwrap().clone();
    let col = |n: &str| headers.iter().position(|h| h == n).unwrap_or_else(|| panic!("no column {n}"));
    let records: Vec<csv::StringRecord> = r.records().map(Result::unwrap).collect();
    assert_eq!(records.len(), 6);
    let meshes: Vec<_> = records.iter().filter(|r| !r[col("coverage_error")].is_empty()).collect();
    assert_eq!(meshes.len(), 4);
    assert_eq!(meshes[1][col("extra")].parse::<usize>().unwrap(), 12);
    assert_eq!(meshes[1][col("coverage_error")].parse::<f64>().unwrap(), 0.03);
    assert_eq!(&meshes[3][col("method")], "linear(32)+binary(5)+curved=prism");
    // worst.md: the flat table, then the mesh table with each mode's worst condition.
    let worst = std::fs::read_to_string(with.join("worst.md")).unwrap();
    let flat_md = std::fs::read_to_string(without.join("worst.md")).unwrap();
    assert!(worst.starts_with(&flat_md) && !flat_md.contains("Mesh conditions"), "{worst}");
    assert!(worst.contains("| `linear(32)+binary(5)+curved=none` | sphere:rocks at 89° | 3.00% | 12 | 0 |"), "{worst}");
    assert!(worst.contains("| `linear(32)+binary(5)+curved=prism` | sphere:rocks at 75° | 1.00% | 0 | 4 |"), "{worst}");
    for metric in ["coverage_error", "ref_err_t_rms", "past_count"] {
        let name = format!("stability_meshes_{metric}.svg");
        let svg = std::fs::read_to_string(with.join(&name)).unwrap();
        assert_eq!(svg.matches("<rect ").count(), 4, "{name}: one rect per mesh cell");
        assert!(!without.join(&name).exists(), "{name} without mesh cells");
    }
    for f in ["stability_skipped_rate.svg", "stability_ref_err_t_rms.svg"] {
        let a = std::fs::read(with.join(f)).unwrap();
        assert_eq!(a, std::fs::read(without.join(f)).unwrap(), "{f}: the flat maps hold the flat cells only");
    }
    std::fs::remove_dir_all(&base).ok();
}

/// The mesh conditions' angle is the view's angle from the normal at the frame's centre:
/// the ray through the centre meets the smooth sphere and torus at their outer equator's
/// point on +x (normal +x) at that angle, whichever map they carry; each carries its map as
/// the flat matrix loads it (64², the same heights), and the maps are two real maps, not one.
#[test]
fn a_mesh_condition_sees_the_frames_centre_at_its_angle() {
    assert_eq!(stability::MESH_MAPS.len(), 2);
    for map in stability::MESH_MAPS {
        assert!(stability::SCENES.contains(&map), "{map} is not a scene of the flat matrix");
        assert!(relief_runtime::REAL_SCENES.iter().any(|r| r.name == map), "{map} is not a real map");
    }
    for (mesh, x) in [("sphere", 1.0f32), ("torus", 1.5)] {
        for (map, angle) in stability::MESH_MAPS.iter().flat_map(|m| stability::MESH_ANGLES.map(|a| (*m, a))) {
            let ms = stability::mesh_scene(mesh, map, angle).unwrap();
            assert_eq!(ms.scene.name, format!("{mesh}:{map}"));
            let flat = stability::scene(map, 64).unwrap();
            assert_eq!((ms.scene.height.width, ms.scene.height.height), (64, 64), "{mesh}:{map}");
            assert!(ms.scene.height.data == flat.height.data, "{mesh}:{map}: not the flat matrix's heights");
            let eye = ms.scene.camera.camera_position();
            let to_eye = (eye - glam::Vec3::new(x, 0.0, 0.0)).normalize();
            let seen = to_eye.dot(glam::Vec3::X).clamp(-1.0, 1.0).acos().to_degrees();
            assert!((seen - angle).abs() < 1e-3, "{mesh} at {angle}°: {seen}°");
            // The frame's centre ray (of an even frame, between the four middle pixels) points at it.
            let forward = ms.scene.camera.basis().0;
            assert!((forward + to_eye).length() < 1e-5, "{mesh}: the camera looks at the point");
        }
    }
}

/// `run_meshes` builds a mesh-with-map's textures, maps and reference once for all its angles,
/// and each program's pipeline once for all conditions: its cells must be the cells of each
/// condition measured on its own (`mesh_condition`, which builds everything afresh), field for
/// field (NaN as NaN), for programs that read an acceleration map (`csm`) and the prism's.
#[test]
fn the_mesh_conditions_run_together_measure_as_each_alone() {
    use relief_dsl::spec::Curved;
    use relief_runtime::gpu::mesh::MeshProgram;
    let g = Gpu::new().unwrap();
    let size = 16;
    let methods: Vec<relief_dsl::Pipeline> =
        ["linear(8)+binary(3)", "csm(8)+binary(3)"].iter().map(|t| t.parse().unwrap()).collect();
    let modes = [Curved::None, Curved::Prism];
    let angles = [75.0, 89.0];
    let mut seen = vec![];
    let together = stability::run_meshes(&g, size, &methods, &modes, &["torus"], &["four"], &angles, |s, a| {
        seen.push((s.to_string(), a))
    })
    .unwrap();
    assert_eq!(seen, [("torus:four".to_string(), 75.0), ("torus:four".to_string(), 89.0)]);
    let programs: Vec<(String, MeshProgram)> = methods
        .iter()
        .flat_map(|p| modes.map(|m| p.clone().with_curved(Some(m))))
        .map(|p| (p.to_string(), MeshProgram::new(&p).unwrap()))
        .collect();
    let mut alone = vec![];
    for angle in angles {
        let ms = stability::mesh_scene("torus", "four", angle).unwrap();
        alone.extend(stability::mesh_condition(&g, size, &programs, ms, angle).unwrap());
    }
    assert_eq!(together.len(), 8);
    assert!(together.iter().any(|c| c.extra.unwrap() + c.missing.unwrap() + c.past_count > 0), "nothing to compare");
    for (a, b) in together.iter().zip(&alone) {
        assert_eq!(format!("{a:?}"), format!("{b:?}"));
    }
}
