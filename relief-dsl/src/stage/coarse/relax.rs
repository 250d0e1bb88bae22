//! Exact step relaxation of the safe marches (after Bán & Valasek 2023, *Automatic Step Size
//! Relaxation in Sphere Tracing*): over-step the bound by a factor taken from how the bound
//! changed over the last step, and step back to the proven point when the bound at the new
//! point does not reach back over the gap.
//!
//! A safe step's bound covers the ray on both sides of the point it is taken from, at least as
//! far back as forward: a distance-field sphere is symmetric, and a cell cone bounds the
//! surface by `A_C + dist(y, C)/R`, which rises at most `1/R` per unit of horizontal distance
//! from the point, so behind the point (where the ray is higher) the ray stays above that
//! bound at least as long as ahead of it. So with `[0, proven]` known to be above the surface
//! and a probe at `t > proven` whose step (its forward reach) is `reach`, the whole gap is above
//! the surface when `t − reach < proven`; then `[0, t + reach]` is. Where the bounds do not
//! overlap the probe is dropped and the march steps back to `proven`, from which the next step
//! is the plain safe one. Nothing the march reports is past the first hit: it ends at a
//! proven point (the patch's hit, the floor, or, out of steps, `proven`).

use super::cell::{cell_at, CellStep, Grid, Sentinel};
use crate::ir::{FnBuilder, Val};
use crate::spec::{MapReq, MethodDef, ParamDef};
use crate::stage::{Bracket, Ray, StageFn};

/// The largest over-step factor ω. With the bound changing linearly along the ray by `m` per
/// unit t (`m ∈ [−1, 0]` toward a surface), a probe `ω·reach` ahead reaches back over the gap
/// when `ω < 2 / (1 − m)`; the march takes 90 % of that, so 1.8 where the bound stays level.
const OMEGA_MAX: f32 = 1.8;

/// The over-step factor ω for a step of `reach` from `t`, given the previous accepted point
/// `last_t` and its reach `last_reach` (the running estimate of the bound's slope along the
/// ray): `0.9 · 2 / (1 − m)`, within `[1, OMEGA_MAX]`; 1 where there is no previous point
/// (the entry, after the patch's pass, after a step back).
fn omega<'a>(
    s: &'a FnBuilder<'a>,
    t: Val<'a, f32>,
    reach: Val<'a, f32>,
    last_t: Val<'a, f32>,
    last_reach: Val<'a, f32>,
) -> Val<'a, f32> {
    let run = t - last_t;
    let slope = (reach - last_reach) / run.max(1e-7);
    let relaxed = (OMEGA_MAX / (1.0 - slope).max(1.0)).max(1.0);
    s.select(run.gt(0.0), relaxed, s.lit(1.0))
}

/// The safe march with exact step relaxation (`step(p, cell)` a safe step, never past the
/// surface, whose bound reaches back at least as far as forward; see the module docs), one
/// probe per pass:
///
/// 1. stop if the search is over;
/// 2. find the probe's cell and the method's step from it (`reach`);
/// 3. if the probe is past the proven point and its bound does not reach back to it, step back
///    to the proven point and start again from there ([`omega`] is then 1);
/// 4. else the ray is above the surface to `t + reach`: where that leaves the cell, it is the
///    new proven point and the next probe is `ω·reach` ahead; where it stays in the cell, the
///    patch decides, as in the safe march, whether the cell holds the first hit (the search
///    is then over, the cell's hit solved once after the loop), else the cell's exit is the
///    new proven point;
/// 5. the search is over in the cell of the first hit (`proven` then holds `−t`,
///    [`Sentinel`]), or with the floor proven reached.
///
/// Returns `[proven, proven]`: the hit, or out of steps the proven point.
pub(super) fn relaxing_march<'a>(
    s: &'a FnBuilder<'a>,
    ray: &Ray<'a>,
    steps: u32,
    cells: Option<MapReq>,
    step: impl CellStep<'a>,
) -> Bracket<'a> {
    let g = Grid::of(s, ray, cells);
    let t = s.var("t", 0.0);
    let proven = s.var("proven", 0.0);
    let last_t = s.var("last_t", 0.0);
    let last_reach = s.var("last_reach", 0.0);
    // A pass that finds its cell to hold the first hit stores `−t` in `proven` ([`Sentinel`]).
    let over = Sentinel::of(&g);
    s.repeat(steps, |l| {
        // 1. Over: the floor proven reached, or the cell of the first hit found.
        l.break_if(over.ended(proven.get()));
        // 2. The probe's cell and its step.
        let c = cell_at(g, t.get());
        let reach = step(l, ray.at(t), &c).named("reach");
        // 3. A probe whose bound leaves a gap behind it: back to the proven point.
        let covered = t.le(proven) | (t - reach).lt(proven);
        l.if_(!covered, |l| {
            t.set(proven);
            last_t.set(proven);
            l.continue_();
        });
        // 4. Above the surface to t + reach: relax on where it leaves the cell, else the patch.
        let cone = t + reach;
        let w = omega(l, t.get(), reach, last_t.get(), last_reach.get());
        l.if_else(
            cone.ge(c.exit),
            |_| {
                proven.set(cone.min(g.t_max));
                last_t.set(t);
                last_reach.set(reach);
                t.set((t + w * reach).min(g.t_max));
            },
            |l| {
                proven.set(c.decided(l, ray, t));
                t.set(proven);
                last_t.set(proven);
            },
        );
    });
    // The first hit in the cell found, exactly, once.
    let (end, in_cell) = over.solve(s, ray, proven.get());
    Bracket::searched(end, end, in_cell | proven.ge(g.t_max))
}

/// Cone step mapping on the cell cones (the safe `csm`) with exact step relaxation: see
/// [`relaxing_march`]. Exact as the safe `csm` is; fewer passes where the cones' steps shrink
/// slowly (grazing rays over open ground), one wasted pass per step back.
pub(crate) fn csm_relax<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>, steps: u32) -> Bracket<'a> {
    relaxing_march(s, ray, steps, Some(MapReq::CellCone), |s, p, c| super::cone::cell_cone_step(s, ray, p, c))
}

/// `csm_relax(steps)`: [`csm_relax`] in the catalogue.
pub(crate) fn csm_relax_def() -> MethodDef {
    MethodDef::new(
        "csm_relax",
        "safe cone step mapping with exact step relaxation (after Bán & Valasek 2023): over-steps, steps back where the bounds do not overlap",
        StageFn::Coarse(|s, ray, a| Ok(csm_relax(s, ray, a.int("steps")?))),
    )
    .param(ParamDef::steps("steps", 15))
    .reads(|_| super::cone::with_patches(MapReq::CellCone))
}

/// Sphere tracing (`sphere`) with exact step relaxation (Bán & Valasek 2023): see
/// [`relaxing_march`]; the field's spheres are symmetric, so a probe's sphere reaches back as
/// far as forward.
pub(crate) fn sphere_relax<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>, steps: u32) -> Bracket<'a> {
    relaxing_march(s, ray, steps, None, |s, p, _| super::sphere::sphere_step(s, ray, p))
}

/// `sphere_relax(steps)`: [`sphere_relax`] in the catalogue.
pub(crate) fn sphere_relax_def() -> MethodDef {
    MethodDef::new(
        "sphere_relax",
        "sphere tracing with exact step relaxation (Bán & Valasek 2023): over-steps, steps back where the spheres do not overlap",
        StageFn::Coarse(|s, ray, a| Ok(sphere_relax(s, ray, a.int("steps")?))),
    )
    .param(ParamDef::steps("steps", 15))
    .reads(|_| vec![MapReq::DistanceField])
}
