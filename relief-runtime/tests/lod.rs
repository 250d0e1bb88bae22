//! Sampling at a mip level on the real device (lavapipe in CI): under `lod=auto` and
//! `lod=level(k)` the probe meets the bilinear surface of the level it sampled, which the
//! exact reference intersects on the same mip data, for both edge modes.

use relief_dsl::spec::Lod;
use relief_runtime::gpu::{self, Gpu, Program};
use relief_runtime::measure::Prepared;
use relief_runtime::metrics::{self, Metrics};
use relief_runtime::EdgeMode;
use relief_runtime::Scene;

fn gpu() -> Gpu {
    Gpu::new().unwrap_or_else(|e| panic!("{e}"))
}

/// Probes `pipeline` on `scene` at `size²` and scores it against the reference of the levels
/// the rays sampled; also returns those levels.
fn measure(g: &Gpu, pipeline: &str, scene: Scene, size: u32) -> (Metrics, Vec<usize>) {
    let p: relief_dsl::Pipeline = pipeline.parse().unwrap();
    let program = Program::new(&p).unwrap_or_else(|e| panic!("{pipeline}: {e}"));
    let mut prep = Prepared::new(g, scene, size).unwrap();
    prep.textures.add_maps_lod(g, &prep.scene, &p.required_maps(), p.lod).unwrap();
    let hits = gpu::probe(g, &program, &prep.scene, &prep.textures, &prep.rays).unwrap_or_else(|e| panic!("{e}"));
    let (levels, refs) = prep.refs_for(p.lod).unwrap();
    let (levels, refs) = (levels.to_vec(), refs.to_vec());
    let mut m =
        Metrics { pipeline: pipeline.parse().unwrap(), scene: prep.scene.name.clone(), size, ..Default::default() };
    metrics::set_accuracy_levels(
        &mut m,
        &prep.rays,
        &hits,
        &refs,
        &prep.textures.height_levels,
        &levels,
        prep.scene.edge,
    );
    assert_eq!(m.nan_count, 0, "{pipeline}");
    (m, levels)
}

// The bound is the one the level-0 exactness test uses (tests/gpu.rs): 400 linear steps are
// finer than any level's texels at these depths and 8 false-position steps converge to f32
// precision on a bilinear patch, so what is left is rounding; a ray traced on another level
// than the shader sampled, or a gather at a level addressing the wrong texels, is off by a
// texel step (~1e-2 in t) and fails it.
const AGREE_T_RMS: f64 = 1e-4;

#[test]
fn lod_auto_meets_the_reference_of_the_footprint_level_on_real_maps() {
    let g = gpu();
    for (name, edge) in [("rocks", EdgeMode::Repeat), ("four", EdgeMode::Clamp), ("rocks", EdgeMode::Clamp)] {
        let mut scene = Scene::by_name(name, None).unwrap();
        scene.edge = edge;
        let (m, levels) = measure(&g, "linear(400)+interval(8)+lod=auto", scene.clone(), 64);
        eprintln!(
            "{name} {edge:?}: t_rms {} levels {:?}..={:?}",
            m.ref_err_t_rms,
            levels.iter().min(),
            levels.iter().max()
        );
        // maxmip walks every cell of the level it samples: exact there too.
        let (mm, _) = measure(&g, "maxmip(128)+lod=auto", scene, 64);
        assert!(
            mm.ref_err_t_rms < AGREE_T_RMS && mm.past_rate == 0.0,
            "maxmip on {name} {edge:?}: t error {}, missed {}",
            mm.ref_err_t_rms,
            mm.past_rate
        );
        // At 64² pixels a 256² map is minified: the footprint is above one texel, so the
        // rays sample levels above 0 (else the test would not test the levels).
        assert!(levels.iter().any(|&l| l >= 1), "{name}: all rays at level 0");
        assert!(m.ref_err_t_rms < AGREE_T_RMS, "{name} {edge:?}: t error {}", m.ref_err_t_rms);
        assert!(m.past_rate < 0.01, "{name}: missed {}", m.past_rate);
    }
}

#[test]
fn lod_level_meets_the_reference_of_that_level_on_a_procedural_map() {
    let g = gpu();
    for edge in [EdgeMode::Repeat, EdgeMode::Clamp] {
        let mut scene = Scene::by_name("rock_bump", Some(128)).unwrap();
        scene.edge = edge;
        let (m, levels) = measure(&g, "linear(400)+interval(8)+lod=level(2)", scene.clone(), 64);
        assert!(levels.iter().all(|&l| l == 2));
        assert!(m.ref_err_t_rms < AGREE_T_RMS, "{edge:?}: t error {}", m.ref_err_t_rms);
        // The test sees the level: the same hits scored against level 0's surface are off.
        let p: relief_dsl::Pipeline = "linear(400)+interval(8)+lod=level(2)".parse().unwrap();
        let prep = Prepared::new(&g, scene, 64).unwrap();
        let hits = gpu::probe(&g, &Program::new(&p).unwrap(), &prep.scene, &prep.textures, &prep.rays).unwrap();
        let mut at0 = Metrics::default();
        metrics::set_accuracy(&mut at0, &prep.rays, &hits, &prep.refs, &prep.on_device.height, edge);
        assert!(at0.ref_err_t_rms > 10.0 * AGREE_T_RMS, "{edge:?}: level 2 looks like level 0 ({})", at0.ref_err_t_rms);
    }
}

#[test]
fn a_level_the_map_does_not_have_is_an_error() {
    let g = gpu();
    let scene = Scene::by_name("rock_bump", Some(16)).unwrap();
    let mut prep = Prepared::new(&g, scene, 8).unwrap();
    let e = prep.refs_for(Lod::Level(9)).unwrap_err().to_string();
    assert!(e.contains("has only 5 mip levels"), "{e}");
}

/// The `form=safe` conservative cone methods at a level (the cells and cell maps of the level
/// they sample) never end past the exact first hit on that level's surface — the property
/// they have at level 0 (tests/cones.rs) — under `lod=auto` on real maps and `lod=level(2)`
/// on one-texel boxes, both edge modes. The relaxed ones (`rcs`, `rcns`) bracket the first
/// crossing, so after an exact refinement they agree with it.
#[test]
fn safe_cone_methods_at_a_level_never_pass_the_first_hit_of_that_level() {
    let g = gpu();
    let boxes = Scene::from_height_map("boxes", relief_runtime::stability::boxes(64, 5));
    let cases = [
        (Scene::by_name("rocks", None).unwrap(), "lod=auto"),
        (Scene::by_name("four", None).unwrap(), "lod=auto"),
        (boxes, "lod=level(2)"),
    ];
    for (scene, lod) in cases {
        for edge in [EdgeMode::Repeat, EdgeMode::Clamp] {
            let mut scene = scene.clone();
            scene.edge = edge;
            scene.camera.angle_deg = 60.0;
            let mut prep = Prepared::new(&g, scene, 48).unwrap();
            for method in [
                "csm(40)",
                "qcsm(40)",
                "cns(40)",
                "mcns(40, 2)",
                "pcns(40, 2)",
                "rcs(40)+interval(12)",
                "rcns(40)+interval(12)",
            ] {
                let text = format!("{method}+{lod}");
                let p: relief_dsl::Pipeline = text.parse().unwrap();
                prep.textures.add_maps_lod(&g, &prep.scene, &p.required_maps(), p.lod).unwrap();
                let hits = gpu::probe(
                    &g,
                    &Program::new(&p).unwrap_or_else(|e| panic!("{text}: {e}")),
                    &prep.scene,
                    &prep.textures,
                    &prep.rays,
                )
                .unwrap();
                let (levels, refs) = prep.refs_for(p.lod).unwrap();
                let (levels, refs) = (levels.to_vec(), refs.to_vec());
                assert!(levels.iter().any(|&l| l >= 1), "{text}: every ray at level 0");
                let a =
                    metrics::Accuracy::of_levels(&prep.rays, &hits, &refs, &prep.textures.height_levels, &levels, edge);
                let name = &prep.scene.name;
                assert_eq!(a.nan, 0, "{text} on {name} {edge:?}");
                if method.starts_with('r') {
                    assert!(a.t_rms() < AGREE_T_RMS, "{text} on {name} {edge:?}: t error {}", a.t_rms());
                } else {
                    let bad: Vec<_> = hits
                        .iter()
                        .zip(&refs)
                        .zip(&levels)
                        .filter_map(|((h, r), l)| r.filter(|r| h.t as f64 - r.t > 1e-5).map(|r| (h.t as f64 - r.t, *l)))
                        .collect();
                    assert_eq!(
                        a.past,
                        0,
                        "{text} on {name} {edge:?}: {} of {} rays past the first hit: {:?}",
                        a.past,
                        a.rays,
                        &bad[..bad.len().min(9)]
                    );
                }
            }
        }
    }
}

/// Sampling level k of a map is sampling level 0 of a map that is level k: the probe's hits
/// under `lod=level(2)` on a scene equal its hits under `lod=zero` on the same scene with
/// level 2 of the height map's chain as its height map (same rays, same texels, the cone map
/// built from the same heights), for methods that read the height map, gathers and texel
/// cone maps. On lavapipe they are bitwise equal; the bound leaves room for a device whose
/// texel addressing at a level rounds differently, and is far below the ~1e-2 of a texel
/// step a wrong level or a cone map of the wrong level gives.
#[test]
fn a_level_is_the_level_0_of_its_own_map() {
    let g = gpu();
    for edge in [EdgeMode::Repeat, EdgeMode::Clamp] {
        let mut scene = Scene::by_name("rock_bump", Some(128)).unwrap();
        scene.edge = edge;
        let mut small = scene.clone();
        small.height = relief_runtime::maps::mips::height_chain(&scene.height)[2].clone();
        small.normal = None;
        for pipeline in [
            "linear(100)+interval(8)",
            "csm(60, form=textbook)+binary(5)",
            "csm(60, form=textbook, sample=min4)+binary(5)",
            "rcs(30, form=textbook)+secant(4)",
            // The safe forms: the march over the level's cells and the level's cell maps
            // (one atlas of every level's cell map).
            "csm(60)+binary(5)",
            "rcs(30)+secant(4)",
            "pcns(30, 2)+binary(3)",
            // The max-mip pyramid over the level's cells (one array layer per level).
            "maxmip(64)",
        ] {
            let at_level: relief_dsl::Pipeline = format!("{pipeline}+lod=level(2)").parse().unwrap();
            let at_zero: relief_dsl::Pipeline = pipeline.parse().unwrap();
            let mut prep = Prepared::new(&g, scene.clone(), 48).unwrap();
            let mut prep_small = Prepared::new(&g, small.clone(), 48).unwrap();
            prep.textures.add_maps_lod(&g, &prep.scene, &at_level.required_maps(), at_level.lod).unwrap();
            prep_small.textures.add_maps(&g, &prep_small.scene, &at_zero.required_maps()).unwrap();
            let hits =
                gpu::probe(&g, &Program::new(&at_level).unwrap(), &prep.scene, &prep.textures, &prep.rays).unwrap();
            let hits_small = gpu::probe(
                &g,
                &Program::new(&at_zero).unwrap(),
                &prep_small.scene,
                &prep_small.textures,
                &prep_small.rays,
            )
            .unwrap();
            assert_eq!(hits.len(), hits_small.len());
            let worst = hits.iter().zip(&hits_small).map(|(a, b)| (a.t - b.t).abs()).fold(0.0f32, f32::max);
            eprintln!("{pipeline} {edge:?}: worst {worst}");
            assert!(worst < 1e-4, "{pipeline} {edge:?}: hits differ by up to {worst} in t");
        }
    }
}
