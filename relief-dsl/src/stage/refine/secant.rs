//! Refinements that intersect the ray with a line through two samples of the surface.

use crate::ir::{Stage, Val};
use crate::stage::{Bracket, Hit, Ray};

/// Interval mapping (Burger 2018, Algorithm 3; Risser et al. 2005), which is the method of
/// false position: intersect the ray with the line through the surface samples at both ends
/// of the bracket, sample there, and keep the half that still brackets the crossing.
///
/// Algorithm 3 as printed replaces `p1` when the new point is below the surface; with `t1`
/// the end above and `t2` the end below, the end a point below replaces is `t2`, as here.
pub fn interval<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, b: Bracket<'a>, steps: u32) -> Hit<'a> {
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

/// The true secant method (survey §4.2.3: "worth checking … its convergence is not
/// guaranteed"): the next guess is where the line through the *last two guesses* of
/// g(t) = z(t) − h(t) crosses zero, whether or not they bracket the crossing.
///
/// Guards against divergence: a guess never leaves the coarse bracket, and the iteration
/// stops when the two last values of g are (numerically) equal.
pub fn secant<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, b: Bracket<'a>, steps: u32) -> Hit<'a> {
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
