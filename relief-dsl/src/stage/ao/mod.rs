//! Ambient-occlusion stages: hit → ambient factor in [0, 1].
//!
//! The cone above a point is the open sky it sees (Burger 2018 §4.5): a cone of half-angle α
//! (`tan α = r`, `sin α = n_z`) lets in the share `sin² α` of cosine-weighted ambient light.

use crate::ir::{FnBuilder, Val};
use crate::spec::{MapReq, MethodDef};
use crate::stage::{Filter, Hit, StageFn};

/// Ambient occlusion from CSM's cone ratio: `r² / (1 + r²)`.
fn cone_ratio<'a>(s: &'a FnBuilder<'a>, hit: &Hit<'a>) -> Val<'a, f32> {
    let r = s.map(MapReq::Cone, hit.uv, Filter::Nearest).x();
    let r2 = r * r;
    (r2 / (1.0 + r2)).clamp(0.0, 1.0)
}

/// Ambient occlusion from the cone normal: `n_z²`.
fn cone_normal<'a>(s: &'a FnBuilder<'a>, hit: &Hit<'a>) -> Val<'a, f32> {
    let n_z = s.map(MapReq::ConeNormal, hit.uv, Filter::Nearest).x();
    (n_z * n_z).clamp(0.0, 1.0)
}

/// `cone_ratio`: [`cone_ratio`] in the catalogue.
fn cone_ratio_def() -> MethodDef {
    MethodDef::new(
        "cone_ratio",
        "ambient occlusion from the cone ratio at the hit (Burger 4.5)",
        StageFn::Ao(|s, hit, _| Ok(cone_ratio(s, hit))),
    )
    .reads(|_| vec![MapReq::Cone])
}

/// `cone_normal`: [`cone_normal`] in the catalogue.
fn cone_normal_def() -> MethodDef {
    MethodDef::new(
        "cone_normal",
        "ambient occlusion from the cone normal at the hit (Burger 4.5)",
        StageFn::Ao(|s, hit, _| Ok(cone_normal(s, hit))),
    )
    .reads(|_| vec![MapReq::ConeNormal])
}

/// The built-in ao methods, in listing order (`none`: no ambient occlusion, factor 1).
pub(crate) fn methods() -> Vec<MethodDef> {
    let none = MethodDef::new("none", "no ambient occlusion: factor 1", StageFn::Ao(|s, _, _| Ok(s.lit(1.0))));
    vec![none, cone_ratio_def(), cone_normal_def()]
}
