//! Ambient-occlusion stages: hit → ambient factor in [0, 1].
//!
//! The cone above a point is the open sky it sees (Burger 2018 §4.5): a cone of half-angle α
//! (`tan α = r`, `sin α = n_z`) lets in the share `sin² α` of cosine-weighted ambient light.

use crate::ir::{Stage, Val};
use crate::spec::{Args, MapReq, Slot, StageSpec};
use crate::stage::{Build, Filter, Hit};
use crate::CompileError;

/// Ambient occlusion from CSM's cone ratio: `r² / (1 + r²)`.
fn cone_ratio<'a>(s: &'a Stage<'a>, hit: &Hit<'a>) -> Val<'a, f32> {
    let r = s.map(MapReq::Cone, hit.uv, Filter::Nearest).x();
    let r2 = r * r;
    (r2 / (1.0 + r2)).clamp(0.0, 1.0)
}

/// Ambient occlusion from the cone normal: `n_z²`.
fn cone_normal<'a>(s: &'a Stage<'a>, hit: &Hit<'a>) -> Val<'a, f32> {
    let n_z = s.map(MapReq::ConeNormal, hit.uv, Filter::Nearest).x();
    (n_z * n_z).clamp(0.0, 1.0)
}

/// Builds the ao stage `spec` into the current function.
pub(crate) fn build<'a>(s: &'a Stage<'a>, hit: &Hit<'a>, spec: &StageSpec) -> Result<Val<'a, f32>, CompileError> {
    match super::lookup(Slot::Ao, spec)? {
        Build::Ao(f) => f(s, hit, &Args::new(Slot::Ao, spec)),
        other => Err(CompileError::wrong_slot(Slot::Ao, &spec.name, other.slot())),
    }
}

pub(crate) fn build_none<'a>(s: &'a Stage<'a>, _: &Hit<'a>, _: &Args) -> Result<Val<'a, f32>, CompileError> {
    Ok(s.lit(1.0))
}
pub(crate) fn build_cone_ratio<'a>(s: &'a Stage<'a>, hit: &Hit<'a>, _: &Args) -> Result<Val<'a, f32>, CompileError> {
    Ok(cone_ratio(s, hit))
}
pub(crate) fn build_cone_normal<'a>(s: &'a Stage<'a>, hit: &Hit<'a>, _: &Args) -> Result<Val<'a, f32>, CompileError> {
    Ok(cone_normal(s, hit))
}
