//! The parallax family: one-shot (or few-shot) offsets that assume the surface is locally a
//! plane. Each yields a single point, returned as [`Bracket::point`]. Sources: Burger 2018
//! §2.2 (eq. 2.3–2.6) and the survey of Szirmay-Kalos & Umenhoffer, §4.1.2–4.2.1.
//!
//! In normalized tangent space the ray reaches depth `1 - h` at `t = (1 - h) / -dir.z`. The
//! survey's "offset limiting" and "safe slope" variants drop the division by the view
//! vector's z, which in this parameterization multiplies that t by `cos θ` (θ the angle of
//! the view ray from the normal).

use crate::ir::{FnBuilder, Val};
use crate::spec::{MapReq, MethodDef, ParamDef, StageSpec};
use crate::stage::{Bracket, Ray, StageFn};

fn normal_map(_: &StageSpec) -> Vec<MapReq> {
    vec![MapReq::Normal]
}

/// Plain texture mapping: the hit is where the ray enters, t = 0.
pub(crate) fn none<'a>(s: &'a FnBuilder<'a>, _ray: &Ray<'a>) -> Bracket<'a> {
    Bracket::point(s.lit(0.0))
}

/// `none`: [`none`] in the catalogue.
pub(crate) fn none_def() -> MethodDef {
    MethodDef::new(
        "none",
        "plain texture mapping: the hit is the entry point",
        StageFn::Coarse(|s, ray, _| Ok(none(s, ray))),
    )
}

/// Parallax mapping (Kaneko et al. 2001; Burger eq. 2.3): the surface is taken to be the
/// plane at the height found under the entry point, `t = (1 - h) / -d.z`.
pub(crate) fn parallax<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>) -> Bracket<'a> {
    let h = s.height(ray.origin);
    Bracket::point((1.0 - h) / -ray.dir.z())
}

/// `parallax`: [`parallax`] in the catalogue.
pub(crate) fn parallax_def() -> MethodDef {
    MethodDef::new(
        "parallax",
        "parallax mapping (Kaneko et al. 2001; Burger eq. 2.3-2.5)",
        StageFn::Coarse(|s, ray, _| Ok(parallax(s, ray))),
    )
}

/// Parallax with offset limiting (Welsh 2004; survey §4.1.3, Burger eq. 2.6): the offset is
/// the depth along the *normalized* view vector, so it never exceeds the depth itself.
pub(crate) fn offset_limited<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>) -> Bracket<'a> {
    let h = s.height(ray.origin);
    Bracket::point((1.0 - h) * ray.cos_view / -ray.dir.z())
}

/// `offset_limited`: [`offset_limited`] in the catalogue.
pub(crate) fn offset_limited_def() -> MethodDef {
    MethodDef::new(
        "offset_limited",
        "parallax with offset limiting (Welsh 2004; survey 4.1.3)",
        StageFn::Coarse(|s, ray, _| Ok(offset_limited(s, ray))),
    )
}

/// Parallax along the slope (survey §4.1.4, the "safer" form): the depth is scaled by the
/// normal map's z, `offset = h · N.z · V.xy`.
pub(crate) fn slope_parallax<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>) -> Bracket<'a> {
    let h = s.height(ray.origin);
    let n = s.normal(ray.origin);
    Bracket::point((1.0 - h) * n.z() * ray.cos_view / -ray.dir.z())
}

/// `slope_parallax`: [`slope_parallax`] in the catalogue.
pub(crate) fn slope_parallax_def() -> MethodDef {
    MethodDef::new(
        "slope_parallax",
        "parallax along the normal map's slope (survey 4.1.4)",
        StageFn::Coarse(|s, ray, _| Ok(slope_parallax(s, ray))),
    )
    .reads(normal_map)
}

/// Iterative parallax mapping (Premecz 2006; survey §4.2.1): repeat the slope correction
/// `uvh += (h - uvh.z) · N.z · V` at the current point, `steps` times.
pub(crate) fn iterative_parallax<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>, steps: u32) -> Bracket<'a> {
    let t = s.var("t", 0.0);
    s.repeat(steps, |s| {
        let p = ray.at(t.get());
        let h = s.height(p.xy());
        let n = s.normal(p.xy());
        let step: Val<'a, f32> = (p.z() - h) * n.z() * ray.cos_view / -ray.dir.z();
        t.set(t.get() + step);
    });
    Bracket::point(t.get())
}

/// `iterative_parallax(steps)`: [`iterative_parallax`] in the catalogue.
pub(crate) fn iterative_parallax_def() -> MethodDef {
    MethodDef::new(
        "iterative_parallax",
        "iterative parallax with slope (Premecz 2006; survey 4.2.1)",
        StageFn::Coarse(|s, ray, a| Ok(iterative_parallax(s, ray, a.int("steps")?))),
    )
    .param(ParamDef::steps("steps", 4))
    .reads(normal_map)
}
