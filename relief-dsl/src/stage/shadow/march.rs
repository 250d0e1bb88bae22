//! Shadows found by marching from the hit toward the light.
//!
//! The light ray starts at the hit and rises with direction `light` (normalized tangent
//! space, scaled so that `light.z = 1`); it leaves the volume after `1 - hit.z`.

use crate::ir::{FnBuilder, Val, Vec3};
use crate::spec::{Args, MethodDef, ParamDef, Slot, StageOr};
use crate::stage::{Bracket, Hit, Light, Ray, StageFn};
use crate::CompileError;

/// The light ray's point at parameter τ.
fn toward_light<'a>(hit: &Hit<'a>, light: Val<'a, Vec3>, tau: Val<'a, f32>) -> Val<'a, Vec3> {
    let s = tau.builder();
    s.vec3(hit.uv + light.xy() * tau, hit.z + tau)
}

/// Hard shadow (Amaro & Gustafsson §2.1.1): a linear search of `steps` equal steps from the
/// hit to the top of the volume; any sample below the surface blocks the light.
pub(crate) fn hard<'a>(s: &'a FnBuilder<'a>, hit: &Hit<'a>, light: Val<'a, Vec3>, steps: u32) -> Val<'a, f32> {
    let step = (1.0 - hit.z) / steps as f32;
    let tau = s.var("tau", step);
    let visible = s.var("visible", 1.0);
    s.repeat(steps, |s| {
        let p = toward_light(hit, light, tau.get());
        let blocked = s.height(p.xy()).gt(p.z());
        visible.set(s.select(blocked, 0.0, visible.get()));
        s.break_if(blocked);
        tau.set(tau.get() + step);
    });
    visible.get()
}

/// How wide the light is, as the blocker slope (depth over distance) that fully covers it.
const LIGHT_WIDTH: f32 = 0.25;

/// Soft shadow after Tatarchuk (2006), with the shadow factor of Amaro & Gustafsson §2.1.2:
/// march the whole light ray, keep the strongest blocker — the largest depth under the
/// surface per distance travelled, `w = (h - z) / τ` — and turn it into a visibility with
/// the fast sigmoid `1 - w / (0.24 + w)`, clamped to [0, 1]. `w` is measured in units of
/// the light's width ([`LIGHT_WIDTH`]).
pub(crate) fn soft<'a>(s: &'a FnBuilder<'a>, hit: &Hit<'a>, light: Val<'a, Vec3>, steps: u32) -> Val<'a, f32> {
    let step = (1.0 - hit.z) / steps as f32;
    let tau = s.var("tau", step);
    let w = s.var("w", 0.0);
    s.repeat(steps, |s| {
        let p = toward_light(hit, light, tau.get());
        let blocker = (s.height(p.xy()) - p.z()) / tau.get().max(1e-6);
        w.set(w.get().max(blocker / LIGHT_WIDTH));
        tau.set(tau.get() + step);
    });
    (1.0 - w.get() / (0.24 + w.get())).clamp(0.0, 1.0)
}

/// `soft(steps)`: [`soft`] in the catalogue.
pub(crate) fn soft_def() -> MethodDef {
    MethodDef::new(
        "soft",
        "soft shadow from the deepest blocker, 1 - w/(0.24 + w) (Tatarchuk 2006; Amaro & Gustafsson 2.1.2)",
        StageFn::Shadow(|s, hit, light, a| Ok(soft(s, hit, light.dir, a.int("steps")?))),
    )
    .param(ParamDef::steps("steps", 16))
}

/// Hard shadow with any coarse search: the light ray is traced from where it enters the
/// volume down toward the hit — an ordinary view ray, so every coarse stage applies — and the
/// hit is in shadow when the search stops on the surface clearly before reaching it.
pub(crate) fn hard_with<'a>(
    s: &'a FnBuilder<'a>,
    hit: &Hit<'a>,
    light: Val<'a, Vec3>,
    light_cos: Val<'a, f32>,
    search: impl FnOnce(&'a FnBuilder<'a>, &Ray<'a>) -> Bracket<'a>,
) -> Val<'a, f32> {
    let t_hit = 1.0 - hit.z;
    let ray = Ray { origin: hit.uv + light.xy() * t_hit, dir: s.vec3(-light.xy(), -1.0), cos_view: light_cos };
    let b = search(s, &ray);
    let p = ray.at(b.below);
    let on_surface = s.height(p.xy()).ge(p.z());
    let before_hit = b.below.lt(t_hit * 0.99 - 1e-3);
    s.select(b.found & on_surface & before_hit, 0.0, 1.0)
}

/// `hard(n)` or `hard(COARSE)`: [`hard`] or [`hard_with`] in the catalogue.
pub(crate) fn hard_def() -> MethodDef {
    MethodDef::new(
        "hard",
        "hard shadow: a coarse search toward the light (Amaro & Gustafsson 2.1.1)",
        StageFn::Shadow(hard_stage),
    )
    .param(ParamDef::stage_or("search", Slot::Coarse, 16))
}

/// A step count is [`hard`]'s linear search; a coarse stage is [`hard_with`] that search.
fn hard_stage<'a>(
    s: &'a FnBuilder<'a>,
    hit: &Hit<'a>,
    light: &Light<'a>,
    a: &Args,
) -> Result<Val<'a, f32>, CompileError> {
    Ok(match a.stage_or("search")? {
        StageOr::Steps(n) => hard(s, hit, light.dir, n),
        StageOr::Stage(inner) => {
            let mut result = Ok(());
            let v = hard_with(s, hit, light.dir, light.cos, |s, ray| match crate::stage::coarse(s, ray, inner) {
                Ok(b) => b,
                Err(e) => {
                    result = Err(e);
                    Bracket::new(s.lit(0.0), s.lit(0.0))
                }
            });
            result?;
            v
        }
    })
}
