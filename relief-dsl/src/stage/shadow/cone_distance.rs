//! Shadows from the cone maps: the cone gives a conservative distance to the surface
//! (Burger 2018 §3.2: `d = h·n_z` for a point `h` above the cone's apex), which drives the
//! distance-field penumbra `k·d / τ` (Quílez-style; Burger §4.4).

use crate::ir::{FnBuilder, Val, Vec3};
use crate::spec::{MapReq, MethodDef, ParamDef};
use crate::stage::{Filter, Hit, StageFn};

/// Penumbra sharpness `k`: the light is fully visible once the distance to the surface is
/// at least `τ / k` at distance τ along the light ray.
const SHARPNESS: f32 = 8.0;

/// Which cone map gives the distance.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Source {
    /// `n_z` from the cone normal map.
    ConeNormal,
    /// `n_z = r / sqrt(1 + r²)` from CSM's cone ratio.
    ConeRatio,
}

/// Soft shadow from cone distances: march `steps` equal steps toward the light; at each
/// sample the cone below bounds the distance to the surface, `d = (z - h)·n_z`, and the
/// visibility is the smallest `k·d / τ` seen (0 under the surface).
pub(crate) fn soft<'a>(
    s: &'a FnBuilder<'a>,
    hit: &Hit<'a>,
    light: Val<'a, Vec3>,
    steps: u32,
    source: Source,
) -> Val<'a, f32> {
    let step = (1.0 - hit.z) / steps as f32;
    let tau = s.var("tau", step);
    let visible = s.var("visible", 1.0);
    s.repeat(steps, |s| {
        let p = s.vec3(hit.uv + light.xy() * tau.get(), hit.z + tau.get());
        let gap = p.z() - s.height(p.xy());
        let n_z = match source {
            Source::ConeNormal => s.map(MapReq::ConeNormal, p.xy(), Filter::Nearest).x(),
            Source::ConeRatio => {
                let r = s.map(MapReq::Cone, p.xy(), Filter::Nearest).x();
                r / (1.0 + r * r).sqrt()
            }
        };
        let d = gap.max(0.0) * n_z;
        visible.set(visible.get().min(SHARPNESS * d / tau.get().max(1e-6)));
        tau.set(tau.get() + step);
    });
    visible.get().clamp(0.0, 1.0)
}

/// `soft_cone(steps)`: [`soft`] from the cone normal map in the catalogue.
pub(crate) fn soft_cone_def() -> MethodDef {
    MethodDef::new(
        "soft_cone",
        "soft shadow from the cone-normal distance d = h n_z (Burger 3.2) with penumbra k d / t",
        StageFn::Shadow(|s, hit, light, a| Ok(soft(s, hit, light.dir, a.int("steps")?, Source::ConeNormal))),
    )
    .param(ParamDef::steps("steps", 16))
    .reads(|_| vec![MapReq::ConeNormal])
}

/// `soft_ratio(steps)`: [`soft`] from CSM's cone ratio in the catalogue.
pub(crate) fn soft_ratio_def() -> MethodDef {
    MethodDef::new(
        "soft_ratio",
        "the same soft shadow from CSM's cone ratio",
        StageFn::Shadow(|s, hit, light, a| Ok(soft(s, hit, light.dir, a.int("steps")?, Source::ConeRatio))),
    )
    .param(ParamDef::steps("steps", 16))
    .reads(|_| vec![MapReq::Cone])
}
