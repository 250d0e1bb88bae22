//! Binary search refinement.

use crate::ir::FnBuilder;
use crate::spec::{MethodDef, ParamDef};
use crate::stage::{Bracket, Hit, Ray, StageFn};

/// Binary search (Burger 2018, Algorithm 2): start half a step back from the coarse hit,
/// then move by half the previous move each time: backward while below the surface,
/// forward while above it.
pub fn binary<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>, b: Bracket<'a>, steps: u32) -> Hit<'a> {
    let step = s.var("step", (b.below - b.above) / 2.0);
    let t = s.var("t", b.below - step.get());
    s.repeat(steps, |s| {
        let p = ray.at(t.get());
        let below = s.height(p.xy()).ge(p.z());
        step.set(step.get() / 2.0);
        t.set(t.get() + s.select(below, -step.get(), step.get()));
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
