//! The secant method: the next guess from the line through the last two guesses.

use crate::ir::{FnBuilder, Val};
use crate::spec::{MethodDef, ParamDef};
use crate::stage::{Bracket, Hit, Ray, StageFn};

/// The true secant method (survey §4.2.3: "worth checking … its convergence is not
/// guaranteed"): the next guess is where the line through the *last two guesses* of
/// g(t) = z(t) − h(t) crosses zero, whether or not they bracket the crossing.
///
/// Guards against divergence: a guess never leaves the coarse bracket, and the iteration
/// stops when the two last values of g are (numerically) equal.
pub(crate) fn secant<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>, b: Bracket<'a>, steps: u32) -> Hit<'a> {
    let gap = |t: Val<'a, f32>| {
        let p = ray.at(t);
        p.z() - s.height(p.xy())
    };
    let t0 = s.var("t0", b.above);
    let t1 = s.var("t1", b.below);
    let g0 = s.var("g0", gap(b.above));
    let g1 = s.var("g1", gap(b.below));
    s.repeat(steps, |s| {
        let den = g1.get() - g0.get();
        s.break_if(den.abs().lt(1e-7));
        let t2 = (t1.get() - g1.get() * (t1.get() - t0.get()) / den).clamp(b.above, b.below);
        t0.set(t1.get());
        g0.set(g1.get());
        t1.set(t2);
        g1.set(gap(t2));
    });
    Hit::at(ray, t1.get())
}

/// `secant(steps)`: [`secant`] in the catalogue.
pub(crate) fn secant_def() -> MethodDef {
    MethodDef::new(
        "secant",
        "the true secant method on the last two guesses (survey 4.2.3), guarded",
        StageFn::Refine(|s, ray, b, a| Ok(secant(s, ray, b, a.int("steps")?))),
    )
    .param(ParamDef::steps("steps", 5))
}
