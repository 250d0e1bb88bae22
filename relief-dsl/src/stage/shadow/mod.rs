//! Shadow stages: hit + light direction → visibility in [0, 1]. The builders below are the
//! ones the catalogue ([`crate::spec::catalog`]) registers.

pub(crate) mod cone;
pub(crate) mod march;

use crate::ir::{Stage, Val};
use crate::spec::{Args, Slot, StageOr, StageSpec};
use crate::stage::{Bracket, Build, Hit, Light};
use crate::CompileError;

/// Builds the shadow stage `spec` into the current function.
pub(crate) fn build<'a>(s: &'a Stage<'a>, hit: &Hit<'a>, light: &Light<'a>, spec: &StageSpec) -> Result<Val<'a, f32>, CompileError> {
    match super::lookup(Slot::Shadow, spec)? {
        Build::Shadow(f) => f(s, hit, light, &Args::new(Slot::Shadow, spec)),
        other => Err(CompileError::wrong_slot(Slot::Shadow, &spec.name, other.slot())),
    }
}

pub(crate) fn build_none<'a>(s: &'a Stage<'a>, _: &Hit<'a>, _: &Light<'a>, _: &Args) -> Result<Val<'a, f32>, CompileError> {
    Ok(s.lit(1.0))
}
pub(crate) fn build_hard<'a>(s: &'a Stage<'a>, hit: &Hit<'a>, light: &Light<'a>, a: &Args) -> Result<Val<'a, f32>, CompileError> {
    Ok(match a.stage_or("search")? {
        StageOr::Steps(n) => march::hard(s, hit, light.dir, n),
        StageOr::Stage(inner) => {
            let mut result = Ok(());
            let v = march::hard_with(s, hit, light.dir, light.cos, |s, ray| match crate::stage::coarse::build(s, ray, inner) {
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
pub(crate) fn build_soft<'a>(s: &'a Stage<'a>, hit: &Hit<'a>, light: &Light<'a>, a: &Args) -> Result<Val<'a, f32>, CompileError> {
    Ok(march::soft(s, hit, light.dir, a.int("steps")?))
}
pub(crate) fn build_soft_cone<'a>(s: &'a Stage<'a>, hit: &Hit<'a>, light: &Light<'a>, a: &Args) -> Result<Val<'a, f32>, CompileError> {
    Ok(cone::soft(s, hit, light.dir, a.int("steps")?, cone::Source::ConeNormal))
}
pub(crate) fn build_soft_ratio<'a>(s: &'a Stage<'a>, hit: &Hit<'a>, light: &Light<'a>, a: &Args) -> Result<Val<'a, f32>, CompileError> {
    Ok(cone::soft(s, hit, light.dir, a.int("steps")?, cone::Source::ConeRatio))
}
