//! Binary search refinement.

use crate::ir::FnBuilder;
use crate::spec::{MethodDef, ParamDef};
use crate::stage::{Bracket, Hit, Ray, StageFn};

/// Binary search (Burger 2018, Algorithm 2): start half a step back from the coarse hit,
/// then move by half the previous move each time: backward while below the surface,
/// forward while above it.
///
/// Departs from the printed box, follows its prose (Burger 2018, §2.3): the box writes
/// `s ← −s ÷ 2` when below and `s ← s ÷ 2` when above, so a sign flipped once stays flipped
/// and a point above the surface after a point below it moves backward again; the prose
/// (and Policarpo's search it describes) moves forward from a point above. Here the step
/// stays positive and the direction comes from the test each pass.
pub(crate) fn binary<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>, b: Bracket<'a>, steps: u32) -> Hit<'a> {
    // s ← stepSize ÷ 2; t ← linearT − s
    let mut step = s.var("step", (b.below - b.above) / 2.0);
    let mut t = s.var("t", b.below - step);
    s.repeat(steps, |s| {
        // p ← p_o + d·t; h ← GETHEIGHT(p.xy)
        let p = ray.at(t);
        let below = s.height(p.xy()).ge(p.z());
        // s ← s ÷ 2; t ← t ∓ s (backward when h ≥ p.z)
        step /= 2.0;
        t += s.select(below, -step, step);
    });
    Hit::at(ray, t.get())
}

/// `binary(steps)`: [`binary`] in the catalogue.
pub(crate) fn binary_def() -> MethodDef {
    MethodDef::new(
        "binary",
        "binary search (Burger Algorithm 2)",
        StageFn::Refine(|s, ray, b, a| Ok(binary(s, ray, b, a.int("steps")?))),
    )
    .param(ParamDef::steps("steps", 5))
}
