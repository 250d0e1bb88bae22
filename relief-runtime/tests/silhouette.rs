//! `silhouette=clip` against an independent computation of the outline.
//!
//! With clamp edges and `silhouette=clip`, a ray has a hit only if it meets the surface
//! before it leaves the quad's square `[0, tiling]²` sideways. The test computes that
//! without the code under test's clip: the first hit of the unclipped exact reference, and
//! the parameter `t_exit` at which the ray leaves the square's prism (the nearest side plane
//! it crosses, solved per axis). A hit exists iff `t_ref ≤ t_exit`. Rays with
//! `|t_ref − t_exit|` under the t agreement goal of an exact method (1e-4) are ambiguous and
//! not judged; the test also requires that they are few, so that it judges something.

use relief_dsl::compose::Options;
use relief_runtime::gpu::Gpu;
use relief_runtime::measure::{measure_with, Prepared};
use relief_runtime::EdgeMode;
use relief_runtime::{ProbeRay, Scene};

/// The t agreement of an exact method with the reference (the goal the exactness tests use).
const EXACT_T: f64 = 1e-4;

/// Where the ray leaves the prism over `[0, tiling]²` (it starts inside).
fn t_exit(r: &ProbeRay, tiling: f64) -> f64 {
    (0..2)
        .map(|a| {
            let (o, d) = (r.origin[a] as f64, r.dir[a] as f64);
            if d > 0.0 {
                (tiling - o) / d
            } else if d < 0.0 {
                -o / d
            } else {
                f64::INFINITY
            }
        })
        .fold(f64::INFINITY, f64::min)
}

fn grazing(mut scene: Scene) -> Scene {
    scene.edge = EdgeMode::Clamp;
    scene.depth_scale = 0.2;
    scene.camera.angle_deg = 70.0;
    scene.camera.azimuth_deg = -60.0;
    scene
}

fn check(g: &Gpu, scene: Scene, pipeline: &str) {
    let name = scene.name.clone();
    let size = 96;
    let mut prep = Prepared::new(g, grazing(scene), size).unwrap();
    let tiling = prep.scene.tiling as f64;
    // Expected hit/no-hit from the unclipped reference and the exit parameter.
    let expected: Vec<Option<bool>> = prep
        .rays
        .iter()
        .zip(&prep.refs)
        .map(|(r, rf)| {
            let t_ref = rf.expect("with clamp edges every ray meets the surface").t;
            let te = t_exit(r, tiling);
            ((t_ref - te).abs() > EXACT_T).then_some(t_ref <= te)
        })
        .collect();
    let judged = expected.iter().flatten().count();
    let outside = expected.iter().flatten().filter(|h| !**h).count();
    assert!(
        judged as f64 >= 0.99 * expected.len() as f64,
        "{name}: too many ambiguous rays ({judged} of {})",
        expected.len()
    );
    assert!(
        outside as f64 >= 0.05 * judged as f64,
        "{name}: the view must show the outline ({outside} of {judged} rays leave the square)"
    );
    assert!(outside < judged, "{name}: some rays must hit");

    let p: relief_dsl::Pipeline = format!("{pipeline}+silhouette=clip").parse().unwrap();
    let m = measure_with(g, &mut prep, &p, &Options { frag_depth: true, ..Default::default() }, 0, 1).unwrap();
    let depth = m.frame.depth.as_ref().expect("frag_depth keeps the depth buffer");
    let mut wrong_probe = Vec::new();
    let mut wrong_pixel = Vec::new();
    for (((r, h), e), rf) in prep.rays.iter().zip(&m.hits).zip(&expected).zip(&prep.refs) {
        let Some(hit) = *e else { continue };
        if (h.clipped == 0) != hit {
            wrong_probe.push((
                r.x,
                r.y,
                h.clipped,
                h.t,
                h.u,
                h.v,
                h.converged,
                t_exit(r, tiling),
                rf.map(|x| (x.t, x.u, x.v, x.z)),
                r.origin,
                r.dir,
            ));
        }
        // A discarded pixel keeps the cleared depth 1.
        let drawn = depth[(r.y * size + r.x) as usize] < 1.0;
        if drawn != hit {
            wrong_pixel.push((r.x, r.y, drawn));
        }
    }
    assert!(
        wrong_probe.is_empty(),
        "{name} {pipeline}: probe clip flag disagrees on {} rays, first {:?}",
        wrong_probe.len(),
        &wrong_probe[..wrong_probe.len().min(5)]
    );
    assert!(
        wrong_pixel.is_empty(),
        "{name} {pipeline}: rendered outline disagrees on {} pixels, first {:?}",
        wrong_pixel.len(),
        &wrong_pixel[..wrong_pixel.len().min(5)]
    );
    // The metrics see the same outline: no false hits beyond the ambiguous rays, and no more
    // misses than the search makes without the clip (a ray that leaves the square first no
    // longer has a hit to miss) plus the ambiguous rays.
    let ambiguous = (expected.len() - judged) as f64 / expected.len() as f64;
    let unclipped = measure_with(g, &mut prep, &pipeline.parse().unwrap(), &Options::default(), 0, 1).unwrap();
    assert!(
        m.metrics.past_rate <= unclipped.metrics.past_rate + ambiguous,
        "{name} {pipeline}: missed {} > {} without the clip + ambiguous share {ambiguous}",
        m.metrics.past_rate,
        unclipped.metrics.past_rate
    );
    assert!(
        m.metrics.false_hit_rate <= ambiguous,
        "{name} {pipeline}: false hits {} > ambiguous share {ambiguous}",
        m.metrics.false_hit_rate
    );
    assert!(
        m.refs.iter().filter(|r| r.is_none()).count() >= outside,
        "the clipped reference has no hit where the ray leaves first"
    );
}

#[test]
fn clip_matches_the_outline_on_hard_and_real_maps() {
    let g = Gpu::new().unwrap();
    let boxes = Scene::from_height_map("boxes", relief_runtime::stability::boxes(64, 3));
    let rocks = Scene::by_name("rocks", Some(256)).unwrap();
    // maxmip walks every cell the ray crosses: exact on the boxes' single-texel pillars,
    // where linear(400) misses crossings that graze a pillar's tip (by design of a linear
    // search, and not what this test is about).
    check(&g, boxes, "maxmip(96)");
    for pipeline in ["maxmip(96)", "linear(400)+interval(8)"] {
        check(&g, rocks.clone(), pipeline);
    }
}

#[test]
fn without_clip_no_ray_is_clipped_and_with_repeat_edges_clip_is_refused() {
    let g = Gpu::new().unwrap();
    let scene = grazing(Scene::from_height_map("boxes", relief_runtime::stability::boxes(32, 1)));
    let mut prep = Prepared::new(&g, scene.clone(), 32).unwrap();
    let p: relief_dsl::Pipeline = "linear(32)+binary(5)".parse().unwrap();
    let m = measure_with(&g, &mut prep, &p, &Options::default(), 0, 1).unwrap();
    assert!(m.hits.iter().all(|h| h.clipped == 0));
    assert_eq!(m.metrics.false_hit_rate, 0.0);

    let mut repeat = scene;
    repeat.edge = EdgeMode::Repeat;
    let mut prep = Prepared::new(&g, repeat, 32).unwrap();
    let clip: relief_dsl::Pipeline = "linear(32)+binary(5)+silhouette=clip".parse().unwrap();
    let err = measure_with(&g, &mut prep, &clip, &Options::default(), 0, 1).err().expect("refused");
    assert!(err.to_string().contains("silhouette=clip needs a scene with clamp edges"), "{err}");
}
