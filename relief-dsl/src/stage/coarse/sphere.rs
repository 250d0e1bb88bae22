//! Sphere tracing a distance field.

use crate::ir::Stage;
use crate::stage::{Bracket, Ray};

/// Sphere tracing a 3D distance field (Donnelly 2005; survey §4.3): each step moves by the
/// distance to the nearest surface, which is free space in every direction. Distances are in
/// the (u, v, height) unit cube, so a step of `D` is `D / |d|` in t.
///
/// The field holds distances to the texel columns; the bilinear surface between them comes
/// up to a cell diagonal closer, and trilinear filtering of the field errs by up to half a
/// voxel diagonal, so each step is shortened by both. The march stops at the first point at
/// or below the surface, and moves at least a quarter texel per step.
pub fn sphere<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, steps: u32, z_resolution: u32) -> Bracket<'a> {
    let size = s.height_map_size();
    let texel = 1.0 / size.x().min(size.y());
    let voxel_half_diagonal = (texel * texel * 2.0 + 1.0 / (z_resolution * z_resolution) as f32).sqrt() / 2.0;
    let margin = texel * std::f32::consts::SQRT_2 + voxel_half_diagonal;
    let speed = ray.dir.length();
    let min_step = super::cone::MIN_STEP_TEXELS * texel / ray.dir.xy().length().max(-ray.dir.z());
    let t = s.var("t", 0.0);
    let t_prev = s.var("t_prev", 0.0);
    let found = s.var("found", false);
    s.repeat(steps, |s| {
        let p = ray.at(t.get());
        found.set(s.height(p.xy()).ge(p.z()));
        s.break_if(found.get());
        let d = s.distance(p);
        t_prev.set(t.get());
        t.set((t.get() + ((d - margin) / speed).max(min_step)).min(ray.t_max()));
    });
    // A step never passes the surface: out of steps, the end point is still above it.
    Bracket::searched(s.select(found.get(), t_prev.get(), t.get()), t.get(), found.get())
}
