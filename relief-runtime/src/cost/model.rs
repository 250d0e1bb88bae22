//! The modeled GPU cost per pixel: the compiler's counts times the probe's passes, per SIMD
//! group (the module docs of [`super`] say what it counts and what it leaves out).

use relief_dsl::abi::ProbeHit;
use serde::{Deserialize, Serialize};

use super::PipelineCost;
use crate::scene::ProbeRay;

/// The model's figures for one pipeline on one frame and one family.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct GpuModel {
    /// Instructions a lane issues, groups of 32 lanes (8 × 4 pixels), averaged over the
    /// launched groups.
    pub instr_w32: f64,
    /// The same for groups of 64 lanes (8 × 8 pixels).
    pub instr_w64: f64,
    /// The same for the group size the compiler chose for the fragment shader (its
    /// subgroup size): the figure to compare pipelines by.
    pub instr_px: f64,
}

/// Per tile of `tw × th` pixels, the largest coarse and refine passes of its lanes.
fn group_max(rays: &[ProbeRay], hits: &[ProbeHit], tw: u32, th: u32) -> Vec<(u32, u32)> {
    let mut tiles: std::collections::BTreeMap<(u32, u32), (u32, u32)> = Default::default();
    for (r, h) in rays.iter().zip(hits) {
        let g = tiles.entry((r.y / th, r.x / tw)).or_default();
        g.0 = g.0.max(h.coarse_steps);
        g.1 = g.1.max(h.refine_steps);
    }
    tiles.into_values().collect()
}

/// The modeled instructions per pixel of `cost`'s fragment shader on the frame whose probe
/// rays are `rays` and hits `hits` (same order). NaN when no ray hits the quad.
///
/// A group issues `S + B_c · max coarse passes + B_r · max refine passes + B_l`, where `S`
/// is the shader's instructions outside its loops, `B_c`, `B_r`, `B_l` the coarse,
/// refine and lighting loops' bodies ([`PipelineCost::stage_bodies`]), and the maxima run
/// over the group's lanes; loops before the coarse search (none in relief's shaders) enter
/// once. The figure is averaged over launched groups.
pub fn modeled(cost: &PipelineCost, rays: &[ProbeRay], hits: &[ProbeHit]) -> GpuModel {
    let f = &cost.fragment;
    let (bc, br, bl) = cost.stage_bodies();
    let base_loops: u32 = f.shape.top_level().take(cost.stage_loops.base as usize).map(|l| l.body).sum();
    let straight = (f.straight_line() + base_loops + bl) as f64;
    let per = |tw: u32, th: u32| {
        let g = group_max(rays, hits, tw, th);
        if g.is_empty() {
            return f64::NAN;
        }
        g.iter().map(|&(c, r)| straight + bc as f64 * c as f64 + br as f64 * r as f64).sum::<f64>() / g.len() as f64
    };
    let instr_w32 = per(8, 4);
    let instr_w64 = per(8, 8);
    GpuModel { instr_w32, instr_w64, instr_px: if f.subgroup_size == 32 { instr_w32 } else { instr_w64 } }
}

/// Writes the results row's GPU columns (`gpu_driver`, `gpu_FAMILY_*`) from `costs`, the
/// pipeline's costs per family, for the frame whose probe rays and hits are `rays` and
/// `hits`. Families without columns of their own ([`crate::results::GPU_COLUMNS`]) are
/// left out.
pub fn set_columns(m: &mut crate::results::Metrics, costs: &[PipelineCost], rays: &[ProbeRay], hits: &[ProbeHit]) {
    for c in costs {
        let g = modeled(c, rays, hits);
        let (bc, br, _) = c.stage_bodies();
        let f = &c.fragment;
        let slots = match c.family.as_str() {
            "navi21" => (
                &mut m.gpu_navi21_instr_px,
                &mut m.gpu_navi21_instr_w32,
                &mut m.gpu_navi21_vgprs,
                &mut m.gpu_navi21_instructions,
                &mut m.gpu_navi21_loop_body,
            ),
            "gfx1100" => (
                &mut m.gpu_gfx1100_instr_px,
                &mut m.gpu_gfx1100_instr_w32,
                &mut m.gpu_gfx1100_vgprs,
                &mut m.gpu_gfx1100_instructions,
                &mut m.gpu_gfx1100_loop_body,
            ),
            _ => continue,
        };
        *slots.0 = Some(g.instr_px);
        *slots.1 = Some(g.instr_w32);
        *slots.2 = Some(f.vgprs);
        *slots.3 = Some(f.instructions);
        *slots.4 = Some(bc + br);
        m.gpu_driver = Some(c.driver.clone());
    }
}

/// Writes a mesh row's GPU columns from its mode's mesh module costs per family: `fs_mesh`'s
/// VGPRs, instructions and top-level loop bodies (`gpu_FAMILY_vgprs`, `_instructions`,
/// `_loop_body`) and `gpu_driver`. The per-pixel model (`_instr_px`, `_instr_w32`) stays
/// empty: the mesh module's measurement entry has no pass counters.
pub fn set_mesh_columns(m: &mut crate::results::Metrics, costs: &[super::MeshCost]) {
    for c in costs {
        let slots = match c.family.as_str() {
            "navi21" => (&mut m.gpu_navi21_vgprs, &mut m.gpu_navi21_instructions, &mut m.gpu_navi21_loop_body),
            "gfx1100" => (&mut m.gpu_gfx1100_vgprs, &mut m.gpu_gfx1100_instructions, &mut m.gpu_gfx1100_loop_body),
            _ => continue,
        };
        *slots.0 = Some(c.fragment.vgprs);
        *slots.1 = Some(c.fragment.instructions);
        *slots.2 = Some(c.fragment_loop_body());
        m.gpu_driver = Some(c.driver.clone());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cost::{IsaLoop, IsaShape, ShaderCost, StageLoops};

    fn cost(wave: u32) -> PipelineCost {
        // 100 instructions: a coarse loop of 20 (holding a nested loop of 5), a refine loop of
        // 10 and a shadow loop of 8; straight line 100 − 38 = 62.
        let shape = IsaShape {
            instructions: 100,
            loops: vec![
                IsaLoop { body: 20, depth: 0, start: 10 },
                IsaLoop { body: 5, depth: 1, start: 12 },
                IsaLoop { body: 10, depth: 0, start: 40 },
                IsaLoop { body: 8, depth: 0, start: 70 },
            ],
        };
        PipelineCost {
            pipeline: "x".into(),
            family: "navi21".into(),
            device: String::new(),
            driver: String::new(),
            fragment: ShaderCost { subgroup_size: wave, instructions: 100, shape, ..Default::default() },
            probe: ShaderCost::default(),
            stage_loops: StageLoops { base: 0, coarse: 1, refine: 1, lighting: 1 },
        }
    }

    #[test]
    fn a_group_issues_its_slowest_lanes_passes_per_loop() {
        let c = cost(64);
        assert_eq!(c.stage_bodies(), (20, 10, 8));
        assert_eq!(c.fragment.straight_line(), 62);
        // One 8 × 8 tile: lane (0, 0) takes 3 coarse + 1 refine passes, lane (1, 0) 1 + 4.
        let ray = |x, y| ProbeRay { origin: [0.0; 2], dir: [0.0, 0.0, -1.0], x, y, pixel_size: 0.0 };
        let hit = |c, r| ProbeHit { coarse_steps: c, refine_steps: r, ..bytemuck::Zeroable::zeroed() };
        let rays = [ray(0, 0), ray(1, 0), ray(0, 5)];
        let hits = [hit(3, 1), hit(1, 4), hit(0, 0)];
        let m = modeled(&c, &rays, &hits);
        // Groups of 64: one group, 62 + 8 + 20·3 + 10·4 = 170.
        assert_eq!(m.instr_w64, 170.0);
        assert_eq!(m.instr_px, 170.0);
        // Groups of 32: rows 0–3 (170) and rows 4–7 (lane (0, 5): 70).
        assert_eq!(m.instr_w32, (170.0 + 70.0) / 2.0);
        assert!(modeled(&c, &[], &[]).instr_px.is_nan());
        assert_eq!(modeled(&cost(32), &rays, &hits).instr_px, 120.0);
    }
}
