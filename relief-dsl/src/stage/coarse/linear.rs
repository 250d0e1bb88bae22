//! Linear search: equal steps down the ray until it dips below the surface.

use crate::ir::{IntoVal, Stage, Val};
use crate::stage::{Bracket, Ray};

/// Linear search (Burger 2018, Algorithm 1): `steps` equal steps that reach the bottom of the
/// volume after the last one; stop at the first point at or below the surface.
pub fn linear<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, steps: u32) -> Bracket<'a> {
    let step = 1.0 / steps as f32;
    let t = s.var("t", 0.0);
    s.repeat(steps, |s| {
        let p = ray.at(t.get());
        s.break_if(s.height(p.xy()).ge(p.z()));
        t.set(t.get() + step);
    });
    one_step_back(t.get(), step)
}

/// The bracket from one step before `t` to `t`, never starting before the entry: when the
/// first sample (t = 0) is already at or below the surface, Algorithm 1's "previous point"
/// would be a step above the polygon, outside the volume, and a refinement would end there
/// (`relief stability` found linear + binary ending at t < 0 on a flat map at height 1).
fn one_step_back<'a>(t: Val<'a, f32>, step: impl IntoVal<'a, f32>) -> Bracket<'a> {
    let step = step.into_val(t.stage());
    Bracket::new((t - step).max(0.0), t)
}

/// Linear search with the step count chosen from the view angle, as parallax occlusion
/// mapping engines do (Tatarchuk 2006; Amaro & Gustafsson §2.1.3 without the distance
/// term): `n = mix(max, min, cos θ)`, many steps at grazing angles, few head-on.
pub fn linear_dynamic<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, min: u32, max: u32) -> Bracket<'a> {
    let n = s.lit(max as f32).mix(min as f32, ray.cos_view).floor().max(1.0);
    let step = 1.0 / n;
    let t = s.var("t", 0.0);
    s.repeat_up_to(max, n.to_u32(), |s| {
        let p = ray.at(t.get());
        s.break_if(s.height(p.xy()).ge(p.z()));
        t.set(t.get() + step);
    });
    one_step_back(t.get(), step)
}
