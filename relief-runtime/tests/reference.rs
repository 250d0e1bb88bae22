//! The exact reference against a brute-force oracle that samples each ray densely, and the
//! max-mip skipping against plain cell-by-cell traversal.

use proptest::prelude::*;
use relief_runtime::Scene;
use relief_runtime::{reference_hits, Reference, Sampling};
use relief_runtime::{EdgeMode, HeightMap};

/// Samples per ray in the oracle (then bisection between the last sample above and the
/// first at or below the surface).
const ORACLE_SAMPLES: u32 = 200_000;

/// Brute-force first hit: march in `ORACLE_SAMPLES` equal steps to height 0, then bisect.
/// It can only be late (a feature thinner than a step is missed), never early.
fn oracle(r: &Reference, o: [f64; 2], d: [f64; 3]) -> f64 {
    let t_end = -1.0 / d[2];
    let g = |t: f64| r.height_at(o[0] + t * d[0], o[1] + t * d[1]) - (1.0 + t * d[2]);
    if g(0.0) >= 0.0 {
        return 0.0;
    }
    let mut lo = 0.0;
    for i in 1..=ORACLE_SAMPLES {
        let t = t_end * i as f64 / ORACLE_SAMPLES as f64;
        if g(t) >= 0.0 {
            let mut hi = t;
            for _ in 0..80 {
                let mid = 0.5 * (lo + hi);
                if g(mid) >= 0.0 {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            return hi;
        }
        lo = t;
    }
    t_end // unreachable for heights >= 0: g(t_end) = height >= 0
}

/// A small xorshift generator for test maps.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Test maps by kind: 0 white noise, 1 smooth noise, 2 spikes, 3 step, 4 checker of single
/// texels, 5 one-texel walls, 6 flat at a random height.
fn test_map(kind: u8, w: usize, h: usize, seed: u64) -> HeightMap {
    let mut rng = Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1);
    let flat = rng.next() as f32;
    let phase = rng.next() as f32 * 6.0;
    HeightMap::from_fn(w, h, |x, y| match kind {
        0 => rng.next() as f32,
        1 => {
            let (u, v) = (x as f32 / w as f32, y as f32 / h as f32);
            let tau = std::f32::consts::TAU;
            (0.5 + 0.25 * (tau * 2.0 * u + phase).sin() + 0.2 * (tau * 3.0 * v).cos() * (tau * u).sin()).clamp(0.0, 1.0)
        }
        2 => {
            if rng.next() < 0.04 {
                0.3 + 0.7 * rng.next() as f32
            } else {
                0.0
            }
        }
        3 => {
            if x < w / 2 {
                0.125
            } else {
                0.875
            }
        }
        4 => ((x + y) % 2) as f32,
        5 => {
            if x % 5 == 0 || y % 7 == 3 {
                1.0
            } else {
                0.05
            }
        }
        _ => flat,
    })
}

/// Checks one ray against the oracle. Returns true when the oracle missed a thin feature the
/// reference found (allowed, counted by the caller).
fn check(r: &Reference, o: [f64; 2], d: [f64; 3], sampling: Sampling) -> Result<bool, TestCaseError> {
    let hit = r
        .first_hit(o, d)
        .map_err(|e| TestCaseError::fail(e.to_string()))?
        .ok_or_else(|| TestCaseError::fail("reference found no hit"))?;
    let t_o = oracle(r, o, d);
    let g = |t: f64| r.height_at(o[0] + t * d[0], o[1] + t * d[1]) - (1.0 + t * d[2]);
    // A nearest-texel wall hit lies on the boundary between two texels, where the sampled
    // texel depends on the side; look just past it, into the texel the ray enters.
    let g_in = |t: f64| if sampling == Sampling::Nearest { g(t).max(g(t + 1e-10)) } else { g(t) };
    // Never later than a point the oracle proved to be under the surface.
    prop_assert!(hit.t <= t_o + 1e-9, "late: ref t {} > oracle t {t_o} ({hit:?})", hit.t);
    // The reported point is consistent with t and lies on (bilinear) or under (walls) the surface.
    prop_assert!((hit.u - (o[0] + hit.t * d[0])).abs() < 1e-12);
    prop_assert!((hit.z - (1.0 + hit.t * d[2])).abs() < 1e-12);
    prop_assert!(g_in(hit.t) >= -1e-9, "ref hit above the surface by {}", -g_in(hit.t));
    if sampling == Sampling::Bilinear && hit.t > 0.0 {
        prop_assert!(g(hit.t) < 1e-9, "ref hit below the surface by {}", g(hit.t));
    }
    prop_assert!((0.0..=-1.0 / d[2] + 1e-12).contains(&hit.t));
    Ok(hit.t < t_o - 1e-9)
}

fn ray_strategy() -> impl Strategy<Value = ([f64; 2], [f64; 3])> {
    // Origins past [0, 1] too (edge modes); horizontal travel from 0.001 to 4 map widths per
    // unit of t (steep to extremely grazing), in any direction, a few axis-aligned.
    (-0.5f64..1.5, -0.5f64..1.5, 0.0f64..std::f64::consts::TAU, -7.0f64..1.4, 0u8..10).prop_map(
        |(u, v, phi, log_len, axis)| {
            let len = log_len.exp();
            let (mut dx, mut dy) = (len * phi.cos(), len * phi.sin());
            match axis {
                0 => dx = 0.0,
                1 => dy = 0.0,
                _ => {}
            }
            ([u, v], [dx, dy, -1.0])
        },
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 1500, ..ProptestConfig::default() })]

    /// Random maps (noise, spikes, step, checker, walls, flat), sizes that are not powers of
    /// two, both edge modes, both samplings, random rays including grazing ones.
    #[test]
    fn reference_agrees_with_the_dense_oracle(
        kind in 0u8..7,
        w in 3usize..40,
        h in 3usize..40,
        seed in any::<u64>(),
        clamp in any::<bool>(),
        nearest in any::<bool>(),
        (o, d) in ray_strategy(),
    ) {
        let edge = if clamp { EdgeMode::Clamp } else { EdgeMode::Repeat };
        let sampling = if nearest { Sampling::Nearest } else { Sampling::Bilinear };
        let map = test_map(kind, w, h, seed);
        let r = Reference::new(&map, edge, sampling);
        check(&r, o, d, sampling)?;
        // Skipping never changes the answer.
        let a = r.first_hit(o, d).unwrap().unwrap();
        let b = r.first_hit_cells(o, d).unwrap().unwrap();
        prop_assert!((a.t - b.t).abs() < 1e-12, "skip {a:?} vs cells {b:?}");
    }
}

/// Many grazing rays over the thinnest features: the oracle may miss a clip thinner than its
/// step, but only rarely; the reference must never be late.
#[test]
fn grazing_rays_over_spikes_and_walls() {
    let mut rng = Rng(12345);
    let mut early = 0;
    let mut n = 0;
    for kind in [2u8, 4, 5] {
        for edge in [EdgeMode::Repeat, EdgeMode::Clamp] {
            for sampling in [Sampling::Bilinear, Sampling::Nearest] {
                let map = test_map(kind, 24, 20, 99);
                let r = Reference::new(&map, edge, sampling);
                for _ in 0..12 {
                    let phi = rng.next() * std::f64::consts::TAU;
                    let len = 0.5 + 2.5 * rng.next();
                    let o = [rng.next(), rng.next()];
                    let d = [len * phi.cos(), len * phi.sin(), -1.0];
                    early += check(&r, o, d, sampling).unwrap_or_else(|e| panic!("{e}")) as usize;
                    n += 1;
                }
            }
        }
    }
    assert!(early * 10 <= n, "the oracle missed {early} of {n}: suspicious");
}

/// Skipping with the max-mip gives the same hits as visiting every cell, on the procedural
/// scenes, both edge modes and samplings, for the camera's rays and random grazing rays.
#[test]
fn max_mip_skipping_matches_plain_cell_traversal() {
    let mut rng = Rng(777);
    for name in ["lion", "self_shadow", "collage", "shapes", "rock_bump", "spikes", "walls", "step", "checker"] {
        let scene = Scene::by_name(name, Some(64)).unwrap();
        for edge in [EdgeMode::Repeat, EdgeMode::Clamp] {
            for sampling in [Sampling::Bilinear, Sampling::Nearest] {
                let r = Reference::new(&scene.height, edge, sampling);
                let mut rays: Vec<([f64; 2], [f64; 3])> = scene
                    .rays(24)
                    .iter()
                    .map(|p| ([p.origin[0] as f64, p.origin[1] as f64], [p.dir[0] as f64, p.dir[1] as f64, -1.0]))
                    .collect();
                for _ in 0..200 {
                    let phi = rng.next() * std::f64::consts::TAU;
                    let len = (rng.next() * 8.0 - 6.0).exp();
                    rays.push(([rng.next() * 2.0 - 0.5, rng.next()], [len * phi.cos(), len * phi.sin(), -1.0]));
                }
                for (o, d) in rays {
                    let a = r.first_hit(o, d).unwrap().expect("skip: no hit");
                    let b = r.first_hit_cells(o, d).unwrap().expect("cells: no hit");
                    assert!((a.t - b.t).abs() < 1e-12, "{name} {edge:?} {sampling:?} {o:?} {d:?}: {a:?} vs {b:?}");
                }
            }
        }
    }
}

#[test]
fn closed_form_cases() {
    let r = |m: HeightMap, s| Reference::new(&m, EdgeMode::Repeat, s);
    for s in [Sampling::Bilinear, Sampling::Nearest] {
        // Flat at 1: hit at the entry. Flat at 0: at t = 1, exactly.
        let one = r(HeightMap::from_fn(5, 7, |_, _| 1.0), s);
        assert_eq!(one.first_hit([0.3, 0.2], [2.0, 1.0, -1.0]).unwrap().unwrap().t, 0.0);
        let zero = r(HeightMap::from_fn(5, 7, |_, _| 0.0), s);
        let hz = zero.first_hit([0.3, 0.2], [2.0, -1.0, -1.0]).unwrap().unwrap();
        assert_eq!((hz.t, hz.z), (1.0, 0.0));
        // Flat at 0.25 with a steeper normalization (dz = -2: height 0 at t = 0.5).
        let q = r(HeightMap::from_fn(4, 4, |_, _| 0.25), s);
        assert!((q.first_hit([0.1, 0.9], [0.3, 0.0, -2.0]).unwrap().unwrap().t - 0.375).abs() < 1e-15);
        // Vertical ray: t = 1 - h(origin).
        let m = test_map(1, 13, 11, 5);
        let rr = r(m.clone(), s);
        let h = rr.height_at(0.37, 0.61);
        assert!((rr.first_hit([0.37, 0.61], [0.0, 0.0, -1.0]).unwrap().unwrap().t - (1.0 - h)).abs() < 1e-12);
        // Rays that point up or are not finite have no hit.
        assert!(rr.first_hit([0.5, 0.5], [0.1, 0.0, 0.0]).unwrap().is_none());
        assert!(rr.first_hit([f64::NAN, 0.5], [0.1, 0.0, -1.0]).unwrap().is_none());
    }
    // Nearest: a ray running along +u into the 0.875 half of the step hits its wall at u = 0.5.
    let st = r(test_map(3, 8, 8, 0), Sampling::Nearest);
    let hit = st.first_hit([0.25, 0.5], [1.0, 0.0, -1.0]).unwrap().unwrap();
    assert!((hit.u - 0.5).abs() < 1e-12 && (hit.t - 0.25).abs() < 1e-12, "{hit:?}");
    // Bilinear: the same cliff is a ramp between the texel centres at u = 7/16 and 9/16
    // (0.125 to 0.875); a ray at height 0.5 hits it half way, at u = 0.5.
    let sb = r(test_map(3, 8, 8, 0), Sampling::Bilinear);
    let hit = sb.first_hit([0.25, 0.5], [1.0, 0.0, -2.0]).unwrap().unwrap();
    assert!((hit.u - 0.5).abs() < 1e-12 && (hit.z - 0.5).abs() < 1e-12, "{hit:?}");
}

/// In clamp mode the surface continues with the border texels: a ray that leaves the map far
/// to the right meets the last column's height.
#[test]
fn clamp_continues_past_the_edge() {
    let map = HeightMap::from_fn(8, 8, |x, _| if x == 7 { 0.625 } else { 0.0 });
    let r = Reference::new(&map, EdgeMode::Clamp, Sampling::Bilinear);
    // Starts left of the last column, passes over its ramp and goes far right, where the
    // height is 0.625 everywhere: it comes down to it at t = 0.375, u = 7.6.
    let hit = r.first_hit([0.1, 0.5], [20.0, 0.0, -1.0]).unwrap().unwrap();
    assert!((hit.z - 0.625).abs() < 1e-12 && (hit.u - 7.6).abs() < 1e-9, "{hit:?}");
    let rep = Reference::new(&map, EdgeMode::Repeat, Sampling::Bilinear);
    let h2 = rep.first_hit([0.1, 0.5], [20.0, 0.0, -1.0]).unwrap().unwrap();
    // Repeated, the map is mostly 0 out there: the same ray goes further.
    assert!(h2.t > hit.t, "{h2:?}");
}

/// The camera's rays on a real scene: every one hits, in [0, 1], and in parallel the same as
/// one at a time.
#[test]
fn scene_rays_all_hit() {
    let scene = Scene::by_name("rock_bump", Some(128)).unwrap();
    let rays = scene.rays(64);
    let hits = reference_hits(&scene, &rays, Sampling::Bilinear).unwrap();
    let r = Reference::for_scene(&scene, Sampling::Bilinear);
    assert_eq!(hits.len(), rays.len());
    for (ray, h) in rays.iter().zip(&hits) {
        let h = h.expect("every camera ray hits");
        assert!((0.0..=1.0).contains(&h.t));
        assert_eq!(Some(h), r.trace(ray).unwrap());
    }
}

/// The traversal's loop guard is an error that names the ray, never a silent "no hit": with
/// a pass limit of 3, a grazing ray across a 64² map (which needs far more passes) fails,
/// and the message gives its origin and direction.
#[test]
fn a_traversal_that_does_not_finish_is_an_error_naming_the_ray() {
    let scene = Scene::by_name("rock_bump", Some(64)).unwrap();
    let r = Reference::for_scene(&scene, Sampling::Bilinear);
    let (o, d) = ([0.125, 0.5], [3.0, 0.25, -1.0]);
    assert!(r.first_hit(o, d).unwrap().is_some(), "with the default limit the ray hits");
    let err = r.with_pass_limit(3).first_hit(o, d).unwrap_err();
    let text = err.to_string();
    assert!(
        text.contains("(0.125, 0.5)") && text.contains("(3, 0.25, -1)") && text.contains("3 traversal passes"),
        "{text}"
    );
}
