//! Linear search: equal steps down the ray until it dips below the surface.

use crate::ir::{FnBuilder, IntoVal, Val};
use crate::spec::{MethodDef, ParamDef, StageSpec};
use crate::stage::{Bracket, Ray, StageFn};

/// Linear search (Burger 2018, Algorithm 1): `steps` equal steps that reach the bottom of the
/// volume after the last one; stop at the first point at or below the surface.
pub(crate) fn linear<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>, steps: u32) -> Bracket<'a> {
    if let Some(n) = s.shared_layers(steps as f32, steps) {
        return linear_up_to(s, ray, n, steps);
    }
    let step = 1.0 / steps as f32;
    let t = s.var("t", 0.0);
    s.repeat(steps, |s| {
        let p = ray.at(t.get());
        s.break_if(s.height(p.xy()).ge(p.z()));
        t.set(t.get() + step);
    });
    one_step_back(t.get(), step)
}

/// [`linear`] with `n` steps (a whole number ≥ 1 known only at run time, at most `bound`).
fn linear_up_to<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>, n: Val<'a, f32>, bound: u32) -> Bracket<'a> {
    let step = 1.0 / n;
    let t = s.var("t", 0.0);
    s.repeat_up_to(bound, n.to_u32(), |s| {
        let p = ray.at(t.get());
        s.break_if(s.height(p.xy()).ge(p.z()));
        t.set(t.get() + step);
    });
    one_step_back(t.get(), step)
}

/// `linear(steps)`: [`linear`] in the catalogue.
pub(crate) fn linear_def() -> MethodDef {
    MethodDef::new(
        "linear",
        "linear search (Burger Algorithm 1)",
        StageFn::Coarse(|s, ray, a| Ok(linear(s, ray, a.int("steps")?))),
    )
    .param(ParamDef::steps("steps", 32))
}

/// The bracket from one step before `t` to `t`, never starting before the entry: when the
/// first sample (t = 0) is already at or below the surface, Algorithm 1's "previous point"
/// would be a step above the polygon, outside the volume, and a refinement would end there
/// (`relief stability` found linear + binary ending at t < 0 on a flat map at height 1).
fn one_step_back<'a>(t: Val<'a, f32>, step: impl IntoVal<'a, f32>) -> Bracket<'a> {
    let step = step.into_val(t.builder());
    Bracket::new((t - step).max(0.0), t)
}

/// Linear search with the step count chosen from the view angle, as parallax occlusion
/// mapping engines do (Tatarchuk 2006; Amaro & Gustafsson §2.1.3 without the distance
/// term): `n = mix(max, min, cos θ)`, many steps at grazing angles, few head-on.
pub(crate) fn linear_dynamic<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>, min: u32, max: u32) -> Bracket<'a> {
    let n = s.lit(max as f32).mix(min as f32, ray.cos_view).floor().max(1.0);
    let n = s.shared_layers(n, max).unwrap_or(n);
    linear_up_to(s, ray, n, max)
}

/// `linear_dynamic(min, max)`: [`linear_dynamic`] in the catalogue.
pub(crate) fn linear_dynamic_def() -> MethodDef {
    MethodDef::new(
        "linear_dynamic",
        "linear search, step count from the view angle (Tatarchuk 2006; Amaro & Gustafsson 2.1.3)",
        StageFn::Coarse(|s, ray, a| Ok(linear_dynamic(s, ray, a.int("min")?, a.int("max")?))),
    )
    .param(ParamDef::steps("min", 8))
    .param(ParamDef::steps("max", 32))
    .check(min_le_max)
}

fn min_le_max(s: &StageSpec) -> Result<(), String> {
    if s.int("min") > s.int("max") {
        return Err(format!("`linear_dynamic` needs min <= max, got min {} and max {}", s.int("min"), s.int("max")));
    }
    Ok(())
}

/// The name of the private global that holds the distance from the camera to the fragment
/// (the `d` of [`linear_distance`]); every entry point that traces writes it first.
pub(crate) const VIEW_DISTANCE: &str = "view_distance";

/// The distance from the camera to the fragment, as the entry point stored it (see
/// [`VIEW_DISTANCE`]).
fn view_distance<'a>(s: &'a FnBuilder<'a>) -> Val<'a, f32> {
    let g = s.module().private::<f32>(VIEW_DISTANCE);
    s.load(s.global_ptr(g))
}

/// Linear search with the layer count of the dynamic layer resolution of Amaro &
/// Gustafsson 2022 (§2.1.3, see [`distance_layers`]): the count depends on the view angle and on
/// the distance `d` from the camera to the fragment (`L = (1 − cos θ)·(L_min·d/(3 + d) +
/// L_max·(1 − d/(3 + d))) + L_θmin·cos θ`, then `max(1, floor(L))` steps), which the entry point stores in
/// [`VIEW_DISTANCE`] (in the scene's world units: the quad's for `fs_main`, the room's for
/// the interior entry). The loop is bounded by `max(min, max, theta_min)`.
pub(crate) fn linear_distance<'a>(
    s: &'a FnBuilder<'a>,
    ray: &Ray<'a>,
    min: u32,
    max: u32,
    theta_min: u32,
) -> Bracket<'a> {
    let d = view_distance(s).max(0.0);
    let w = d / (d + 3.0);
    let c = ray.cos_view.clamp(0.0, 1.0);
    let far_near = w * min as f32 + (1.0 - w) * max as f32;
    let layers = (1.0 - c) * far_near + c * theta_min as f32;
    let bound = min.max(max).max(theta_min);
    let n = s.name("layers", layers.floor().clamp(1.0, bound as f32));
    let n = s.shared_layers(n, bound).unwrap_or(n);
    linear_up_to(s, ray, n, bound)
}

/// `linear_distance(min, max, theta_min)`: [`linear_distance`] in the catalogue.
pub(crate) fn linear_distance_def() -> MethodDef {
    MethodDef::new(
        "linear_distance",
        "linear search, layer count from the view angle and the camera distance (Amaro & Gustafsson 2.1.3)",
        StageFn::Coarse(|s, ray, a| Ok(linear_distance(s, ray, a.int("min")?, a.int("max")?, a.int("theta_min")?))),
    )
    .param(ParamDef::steps("min", 16))
    .param(ParamDef::steps("max", 180))
    .param(ParamDef::steps("theta_min", 4))
}
