//! Interval mapping: false position between the two ends of the bracket.

use crate::ir::FnBuilder;
use crate::spec::{MethodDef, ParamDef};
use crate::stage::{Bracket, Hit, Ray, StageFn};

/// Interval mapping (Burger 2018, Algorithm 3; Risser et al. 2005), which is the method of
/// false position: intersect the ray with the line through the surface samples at both ends
/// of the bracket, sample there, and keep the half that still brackets the crossing.
///
/// Algorithm 3 as printed replaces `p1` when the new point is below the surface; with `t1`
/// the end above and `t2` the end below, the end a point below replaces is `t2`, as here.
pub(crate) fn interval<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>, b: Bracket<'a>, steps: u32) -> Hit<'a> {
    let t1 = s.var("t1", b.above);
    let t2 = s.var("t2", b.below);
    let h1 = s.var("h1", s.height(ray.at(b.above).xy()));
    let h2 = s.var("h2", s.height(ray.at(b.below).xy()));
    let t_int = s.var("t_int", b.below);
    s.repeat(steps, |s| {
        let (p1, p2) = (ray.at(t1.get()), ray.at(t2.get()));
        let num = h1.get() - p1.z();
        // (p2.z - p1.z) - (h2 - h1) is negative for a true bracket; never divide by zero.
        let den = ((p2.z() - p1.z()) - (h2.get() - h1.get())).min(-1e-12);
        let f = (num / den).clamp(0.0, 1.0);
        t_int.set(f * (t2.get() - t1.get()) + t1.get());
        let p_int = ray.at(t_int.get());
        let h_int = s.height(p_int.xy());
        s.if_else(
            h_int.ge(p_int.z()),
            |_| {
                t2.set(t_int.get());
                h2.set(h_int);
            },
            |_| {
                t1.set(t_int.get());
                h1.set(h_int);
            },
        );
    });
    Hit::at(ray, t_int.get())
}

/// `interval(steps)`: [`interval`] in the catalogue.
pub(crate) fn interval_def() -> MethodDef {
    MethodDef::new(
        "interval",
        "interval mapping, false position (Burger Algorithm 3; Risser et al. 2005)",
        StageFn::Refine(|s, ray, b, a| Ok(interval(s, ray, b, a.int("steps")?))),
    )
    .param(ParamDef::steps("steps", 5))
}
