//! Cone-family, distance-field stages against the exact reference on the device: the
//! conservative methods never place a hit beyond the true first intersection, the relaxed
//! ones refine to it, over random rays including grazing ones.

use relief_runtime::gpu::{self, Gpu, GpuHit, Program, SceneTextures};
use relief_runtime::reference::{reference_hits, RefHit, Sampling};
use relief_runtime::scene::{ProbeRay, Scene};

/// Random rays over the map: origins anywhere, horizontal travel per unit depth from 0
/// (straight down) to 3 map widths (grazing), any azimuth. Deterministic (a fixed LCG).
fn random_rays(n: usize, seed: u64) -> Vec<ProbeRay> {
    let mut state = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    let mut next = move || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((state >> 33) as f64 / (1u64 << 31) as f64) as f32
    };
    (0..n)
        .map(|i| {
            let (u, v) = (next(), next());
            let reach = 3.0 * next().powi(2);
            let az = next() * std::f32::consts::TAU;
            ProbeRay { origin: [u, v], dir: [reach * az.cos(), reach * az.sin(), -1.0], x: i as u32, y: 0, pad: 0 }
        })
        .collect()
}

struct Probe {
    rays: Vec<ProbeRay>,
    refs: Vec<Option<RefHit>>,
    scene: Scene,
}

impl Probe {
    fn new(name: &str, size: usize, seed: u64) -> Probe {
        let scene = Scene::by_name(name, Some(size)).unwrap();
        let rays = random_rays(4096, seed);
        let refs = reference_hits(&scene, &rays, Sampling::Bilinear).unwrap();
        Probe { rays, refs, scene }
    }

    fn run(&self, g: &Gpu, pipeline: &str) -> Vec<GpuHit> {
        let p: relief_dsl::Pipeline = pipeline.parse().unwrap();
        let program = Program::new(&p).unwrap();
        let mut tex = SceneTextures::new(g, &self.scene);
        assert!(g.float32_filterable, "these tests upload f32 heights");
        tex.add_maps(g, &self.scene, &p.required_maps()).unwrap();
        gpu::probe(g, &program, &self.scene, &tex, &self.rays).unwrap_or_else(|e| panic!("{pipeline}: {e}"))
    }

    /// The t it takes `ray` to cross one texel (the metrics' definition).
    fn texel_t(&self, ray: &ProbeRay) -> f64 {
        relief_runtime::metrics::one_texel_t(ray, self.scene.height.width as f64)
    }

    /// The longest stretch of the ray before the hit that runs inside the surface, in texels
    /// of travel (dense sampling, 16 samples a texel), for each ray.
    fn skipped(&self, hits: &[GpuHit]) -> Vec<f64> {
        use rayon::prelude::*;
        let m = &self.scene.height;
        hits.par_iter()
            .zip(&self.rays)
            .map(|(h, ray)| {
                if !h.t.is_finite() {
                    return f64::INFINITY;
                }
                let dt = self.texel_t(ray) / 16.0;
                let (mut run, mut longest, mut t) = (0usize, 0usize, 0.0);
                while t < h.t as f64 {
                    let (u, v) = (ray.origin[0] as f64 + t * ray.dir[0] as f64, ray.origin[1] as f64 + t * ray.dir[1] as f64);
                    let z = 1.0 + t * ray.dir[2] as f64;
                    if m.bilinear(u, v, self.scene.edge) > z {
                        run += 1;
                        longest = longest.max(run);
                    } else {
                        run = 0;
                    }
                    t += dt;
                }
                longest as f64 / 16.0
            })
            .collect()
    }
}

/// The cone maps are exact for the texel samples (relief-runtime `maps::cone`), and the
/// stages pad each step for the ray point's offset from the texel's axis; between texels the
/// bilinear surface can still rise through a cone by a fraction of a texel, and the
/// quarter-texel minimum step can cross a sliver that thin. What must never happen is
/// skipping geometry: passing through a whole texel of surface before the reported hit (the
/// `missed_rate` criterion of the metrics).
const SLACK: f64 = 1.0;

/// Relaxed cone maps are exact for the texel samples too (a texel constrains a cone when the
/// ray through it is still outside the surface one texel further), so on the bilinear
/// surface a bracket can hold a sliver of a second crossing: measured worst 1.44 texels.
const SLACK_RELAXED: f64 = 1.5;

#[test]
fn cone_methods_never_skip_geometry() {
    let g = Gpu::new().unwrap();
    let mut failures = vec![];
    for (scene, seed) in [("rock_bump", 1), ("lion", 2), ("spikes", 3), ("walls", 4)] {
        let probe = Probe::new(scene, 64, seed);
        for method in [
            "csm(24, sample=nearest)",
            "csm(24, sample=min4)",
            "qcsm(24)",
            "cns(24)",
            "mcns(24, 3)",
            "pcns(24, 1)",
            "sphere(24)",
            "maxmip(64)",
            // Relaxed cones let the ray cross the surface once; refined, the hit is the first
            // crossing.
            "rcs(24, start=bracket)+binary(8)",
            "rcs(24)+binary(8)",
            "rcns(24)+binary(8)",
        ] {
            let hits = probe.run(&g, method);
            let skipped = probe.skipped(&hits);
            let worst = skipped.iter().cloned().fold(0.0, f64::max);
            let past = hits.iter().zip(&probe.refs).filter(|(h, r)| h.t as f64 > r.unwrap().t + 1e-4).count();
            eprintln!("{method} on {scene}: longest stretch skipped {worst:.3} texel; {past} rays end past the exact first hit");
            if method.starts_with("maxmip") {
                // Exact traversal of the bilinear surface: never past the first hit at all.
                assert_eq!(past, 0, "{method} on {scene}: {past} rays end past the exact first hit");
            }
            let slack = if method.starts_with('r') { SLACK_RELAXED } else { SLACK };
            let bad: Vec<(usize, f64)> = skipped.iter().copied().enumerate().filter(|(_, s)| *s >= slack).collect();
            if !bad.is_empty() {
                failures.push(format!(
                    "{method} on {scene}: {} of {} rays pass through {slack} texel(s) of surface or more, e.g. (ray, texels) {:?}",
                    bad.len(),
                    hits.len(),
                    &bad[..bad.len().min(3)]
                ));
            }
            let outside: Vec<_> = hits.iter().zip(&probe.rays).enumerate().filter(|(_, (h, r))| !h.is_finite() || h.outside(r)).take(3).collect();
            assert!(outside.is_empty(), "{method} on {scene}: hit outside the volume: {outside:?}");
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn following_the_best_corner_cone_is_not_conservative_on_the_bilinear_surface() {
    // csm(sample=corners): near its apex a texel's cone is pierced by the bilinear patches
    // around it, and the lowest corner's cone leads right into them (see the stage's docs).
    let g = Gpu::new().unwrap();
    let probe = Probe::new("walls", 64, 4);
    let hits = probe.run(&g, "csm(24, sample=corners)");
    let worst = probe.skipped(&hits).into_iter().fold(0.0, f64::max);
    assert!(worst > 2.0, "csm(sample=corners) skips at most {worst} texels on one-texel walls");
}

#[test]
fn piecewise_cones_over_texel_samples_are_not_conservative_on_the_bilinear_surface() {
    // Burger's method 2 with pieces fitted to the texel columns (maps::multi_cone): above
    // the first piece the region reaches out to the columns themselves, but the bilinear
    // surface spreads a column's height over the neighbouring cells, so rays pass through
    // walls. Recorded here so that a map definition that fixes it shows up as a change.
    let g = Gpu::new().unwrap();
    let probe = Probe::new("walls", 64, 4);
    let hits = probe.run(&g, "pcns(24, 3)");
    let worst = probe.skipped(&hits).into_iter().fold(0.0, f64::max);
    assert!(worst > 2.0, "pcns(24, 3) skips at most {worst} texels on one-texel walls");
}

#[test]
fn conservative_cone_stepping_converges_from_above() {
    // The guarantee's other half: the hit approaches the surface from above, so more steps
    // never make it worse.
    let g = Gpu::new().unwrap();
    let probe = Probe::new("rock_bump", 64, 7);
    let err = |hits: &[GpuHit]| -> f64 {
        hits.iter().zip(&probe.refs).map(|(h, r)| (r.unwrap().t - h.t as f64).max(0.0)).sum::<f64>()
    };
    let e8 = err(&probe.run(&g, "cns(8)"));
    let e32 = err(&probe.run(&g, "cns(32)"));
    assert!(e32 < e8 * 0.5, "cns(32) error {e32} vs cns(8) {e8}");
}
