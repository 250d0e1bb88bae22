//! Ambient-occlusion stages: hit → ambient factor in [0, 1].
//!
//! The cone above a point is the open sky it sees (Burger 2018 §4.5): a cone of half-angle α
//! (`tan α = r`, `sin α = n_z`) lets in the share `sin² α` of cosine-weighted ambient light.

use crate::CompileError;
use crate::ir::{Stage, Val};
use crate::spec::{MapReq, StageSpec};
use crate::stage::{Filter, Hit};

/// Ambient occlusion from CSM's cone ratio: `r² / (1 + r²)`.
pub fn cone_ratio<'a>(s: &'a Stage<'a>, hit: &Hit<'a>) -> Val<'a, f32> {
    let r = s.map(MapReq::Cone, hit.uv, Filter::Nearest).x();
    let r2 = r * r;
    (r2 / (1.0 + r2)).clamp(0.0, 1.0)
}

/// Ambient occlusion from the cone normal: `n_z²`.
pub fn cone_normal<'a>(s: &'a Stage<'a>, hit: &Hit<'a>) -> Val<'a, f32> {
    let n_z = s.map(MapReq::ConeNormal, hit.uv, Filter::Nearest).x();
    (n_z * n_z).clamp(0.0, 1.0)
}

/// Builds the ao stage `spec` into the current function.
pub fn build<'a>(s: &'a Stage<'a>, hit: &Hit<'a>, spec: &StageSpec) -> Result<Val<'a, f32>, CompileError> {
    match spec.name.as_str() {
        "none" => Ok(s.lit(1.0)),
        "cone_ratio" => Ok(cone_ratio(s, hit)),
        "cone_normal" => Ok(cone_normal(s, hit)),
        other => Err(CompileError::not_implemented("ao", other)),
    }
}
