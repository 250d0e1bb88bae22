//! A GPU cost model beside the clock: what the probe's per-ray counters cost when rays run
//! in SIMD groups, as a GPU runs its fragments.
//!
//! A GPU runs a group of pixels (a warp of 32 lanes, a wavefront of 64) in lock step: the
//! group takes as many loop passes as its slowest lane, and the lanes that finished early
//! wait. A CPU rasterizer such as lavapipe shows little of that cost in its timing. The
//! model groups the probe's rays by their pixel and takes, per group, the largest count of
//! its lanes:
//!
//! - a group of 32 is an 8 × 4 tile of the frame (8 pixels across, 4 down), a group of 64 an
//!   8 × 8 tile, tiles aligned to the frame's top-left pixel;
//! - a lane is a pixel of the tile; its count is its ray's coarse + refine loop passes
//!   (steps) or its texture fetches, as the probe reports them;
//! - **empty lanes**: a pixel whose camera ray misses the quad has no probe ray, and a pixel
//!   of a tile that lies outside the frame (frames whose side is not a multiple of the
//!   tile's) does not exist. Both are idle lanes: they take no passes and wait for the
//!   group. They enter neither the group's largest count nor its mean (the mean is over the
//!   lanes that hold a ray). A tile with no ray at all is not launched and is not a group;
//!   [`SimdCost::groups32`] counts the launched groups and [`SimdCost::lanes32`] the share
//!   of their lanes that hold a ray, so nothing is dropped without being counted.
//!
//! The figures: `simd32_steps` and `simd64_steps`, the group's largest step count averaged
//! over groups; `simd32_fetches`, the same for fetches in groups of 32; and
//! `simd32_divergence`, the group's largest step count over the mean of its lanes' step
//! counts, averaged over groups (1 where every lane takes as many steps as the slowest; a
//! group whose lanes all take 0 steps has divergence 1: no lane waits for another). The
//! probe traces only, so shadow and ambient-occlusion work is not in the model.

use relief_dsl::abi::ProbeHit;

use crate::scene::ProbeRay;

/// The cost model's figures for one frame (see the module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SimdCost {
    /// The largest coarse + refine step count of a group of 32 (8 × 4 pixels), averaged
    /// over the launched groups.
    pub simd32_steps: f64,
    /// The same over groups of 64 (8 × 8 pixels).
    pub simd64_steps: f64,
    /// The largest fetch count of a group of 32, averaged over the launched groups.
    pub simd32_fetches: f64,
    /// A group of 32's largest step count over its lanes' mean, averaged over groups.
    pub simd32_divergence: f64,
    /// Groups of 32 launched (tiles with at least one ray).
    pub groups32: usize,
    /// The share of the launched groups' 32 lanes that hold a ray.
    pub lanes32: f64,
}

/// One group's counts: per lane holding a ray, (steps, fetches).
#[derive(Default)]
struct Group {
    lanes: u32,
    max_steps: u32,
    max_fetches: u32,
    sum_steps: u64,
}

/// Per tile of `tw × th` pixels: the counts of its rays' lanes, launched tiles only, in
/// tile order.
fn groups(rays: &[ProbeRay], hits: &[ProbeHit], tw: u32, th: u32) -> Vec<Group> {
    let mut tiles: std::collections::BTreeMap<(u32, u32), Group> = Default::default();
    for (r, h) in rays.iter().zip(hits) {
        let g = tiles.entry((r.y / th, r.x / tw)).or_default();
        let steps = h.coarse_steps + h.refine_steps;
        g.lanes += 1;
        g.max_steps = g.max_steps.max(steps);
        g.max_fetches = g.max_fetches.max(h.fetches);
        g.sum_steps += steps as u64;
    }
    tiles.into_values().collect()
}

/// The model's figures for `hits`, the probe's hits of `rays` (same order; rays carry their
/// pixel). Every figure is NaN when there are no rays.
pub(crate) fn simd_cost(rays: &[ProbeRay], hits: &[ProbeHit]) -> SimdCost {
    let g32 = groups(rays, hits, 8, 4);
    let g64 = groups(rays, hits, 8, 8);
    if g32.is_empty() {
        return SimdCost {
            simd32_steps: f64::NAN,
            simd64_steps: f64::NAN,
            simd32_fetches: f64::NAN,
            simd32_divergence: f64::NAN,
            groups32: 0,
            lanes32: f64::NAN,
        };
    }
    let mean = |gs: &[Group], f: &dyn Fn(&Group) -> f64| gs.iter().map(f).sum::<f64>() / gs.len() as f64;
    SimdCost {
        simd32_steps: mean(&g32, &|g| g.max_steps as f64),
        simd64_steps: mean(&g64, &|g| g.max_steps as f64),
        simd32_fetches: mean(&g32, &|g| g.max_fetches as f64),
        simd32_divergence: mean(&g32, &|g| {
            if g.sum_steps == 0 {
                1.0
            } else {
                g.max_steps as f64 * g.lanes as f64 / g.sum_steps as f64
            }
        }),
        groups32: g32.len(),
        lanes32: g32.iter().map(|g| g.lanes as f64).sum::<f64>() / (32 * g32.len()) as f64,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ray(x: u32, y: u32) -> ProbeRay {
        ProbeRay { origin: [0.5, 0.5], dir: [0.0, 0.0, -1.0], x, y, pixel_size: 0.0 }
    }

    fn hit(coarse: u32, refine: u32, fetches: u32) -> ProbeHit {
        ProbeHit { coarse_steps: coarse, refine_steps: refine, fetches, converged: 1, ..bytemuck::Zeroable::zeroed() }
    }

    /// A 12 × 6 frame: groups of 32 are the tiles x 0–7 / 8–11 by y 0–3 / 4–5 (the right
    /// and bottom tiles are cut by the frame's edge), groups of 64 the tiles x 0–7 / 8–11 by
    /// y 0–5. Pixels: every pixel of the top-left tile holds a ray with 2 coarse + 1 refine
    /// steps and 4 fetches, except pixel (3, 1): 10 + 2 steps, 20 fetches. The top-right tile
    /// holds one ray, at (9, 2): 0 steps, 1 fetch. The bottom-left tile holds rays at (0, 4)
    /// with 4 + 0 steps, 5 fetches, and (7, 5) with 8 + 0 steps, 9 fetches. The bottom-right
    /// tile holds none (its pixels miss the quad): it is not launched.
    #[test]
    fn groups_of_a_small_frame_by_hand() {
        let mut rays = Vec::new();
        let mut hits = Vec::new();
        for y in 0..4 {
            for x in 0..8 {
                rays.push(ray(x, y));
                hits.push(if (x, y) == (3, 1) { hit(10, 2, 20) } else { hit(2, 1, 4) });
            }
        }
        rays.push(ray(9, 2));
        hits.push(hit(0, 0, 1));
        rays.push(ray(0, 4));
        hits.push(hit(4, 0, 5));
        rays.push(ray(7, 5));
        hits.push(hit(8, 0, 9));
        let c = simd_cost(&rays, &hits);
        // Groups of 32: top-left max 12 steps, 20 fetches, mean (31·3 + 12)/32 = 105/32;
        // top-right one lane, 0 steps (divergence 1), 1 fetch; bottom-left max 8 steps, 9
        // fetches, mean 6.
        assert_eq!(c.groups32, 3);
        assert!((c.simd32_steps - (12.0 + 0.0 + 8.0) / 3.0).abs() < 1e-12, "{c:?}");
        assert!((c.simd32_fetches - (20.0 + 1.0 + 9.0) / 3.0).abs() < 1e-12, "{c:?}");
        let div = (12.0 / (105.0 / 32.0) + 1.0 + 8.0 / 6.0) / 3.0;
        assert!((c.simd32_divergence - div).abs() < 1e-12, "{} vs {div}", c.simd32_divergence);
        assert!((c.lanes32 - 35.0 / 96.0).abs() < 1e-12);
        // Groups of 64: left tile (rows 0–5) max 12; right tile max 0.
        assert!((c.simd64_steps - (12.0 + 0.0) / 2.0).abs() < 1e-12, "{c:?}");
    }

    #[test]
    fn uniform_work_has_no_divergence_and_no_rays_give_nan() {
        let rays: Vec<ProbeRay> = (0..64).map(|i| ray(i % 16, i / 16)).collect();
        let hits = vec![hit(5, 3, 9); 64];
        let c = simd_cost(&rays, &hits);
        assert_eq!((c.simd32_steps, c.simd64_steps, c.simd32_fetches, c.simd32_divergence), (8.0, 8.0, 9.0, 1.0));
        assert_eq!(c.lanes32, 1.0);
        let none = simd_cost(&[], &[]);
        assert!(none.simd32_steps.is_nan() && none.simd32_divergence.is_nan());
    }
}
