//! Sphere tracing a distance field.

use crate::ir::{FnBuilder, Val, Vec3};
use crate::spec::{MapReq, MethodDef, ParamDef};
use crate::stage::{Bracket, Ray, StageFn};

/// Sphere tracing a 3D distance field (Donnelly 2005; survey §4.3): each step moves by the
/// distance to the nearest surface, which is free space in every direction. Distances are in
/// the (u, v, height) unit cube, so a step of `D` is `D / |d|` in t.
///
/// The field (relief-runtime's `maps::distance_field`) is a lower bound of the distance to
/// the bilinear surface even after trilinear filtering, so a step never passes the surface;
/// within a voxel of the surface it reads 0, and there the cell's bilinear patch closes the
/// gap exactly ([`super::cell::safe_march`]), so the search neither stalls nor passes the
/// first hit.
pub(crate) fn sphere<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>, steps: u32) -> Bracket<'a> {
    super::cell::safe_march(s, ray, steps, None, |s, p, _| sphere_step(s, ray, p))
}

/// The sphere-tracing step from the ray point `p`: the field's distance, in t.
pub(super) fn sphere_step<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>, p: Val<'a, Vec3>) -> Val<'a, f32> {
    s.distance(p) / ray.dir.length()
}

/// `sphere(steps)`: [`sphere`] in the catalogue.
pub(crate) fn sphere_def() -> MethodDef {
    MethodDef::new(
        "sphere",
        "sphere tracing a 3D distance field (Donnelly 2005)",
        StageFn::Coarse(|s, ray, a| Ok(sphere(s, ray, a.int("steps")?))),
    )
    .param(ParamDef::steps("steps", 15))
    .reads(|_| vec![MapReq::DistanceField])
}
