//! Refining searches: ray + bracket → hit. One file per method family; the builders below
//! are the ones the catalogue ([`crate::spec::catalog`]) registers.

pub(crate) mod binary;
pub(crate) mod secant;

use crate::ir::Stage;
use crate::spec::{Args, Slot, StageSpec};
use crate::stage::{Bracket, Build, Hit, Ray};
use crate::CompileError;

/// Builds the refine stage `spec` into the current function.
pub(crate) fn build<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, b: Bracket<'a>, spec: &StageSpec) -> Result<Hit<'a>, CompileError> {
    match super::lookup(Slot::Refine, spec)? {
        Build::Refine(f) => f(s, ray, b, &Args::new(Slot::Refine, spec)),
        other => Err(CompileError::wrong_slot(Slot::Refine, &spec.name, other.slot())),
    }
}

/// No refinement: the hit is the bracket's far end, the coarse search's answer.
pub(crate) fn build_none<'a>(_: &'a Stage<'a>, ray: &Ray<'a>, b: Bracket<'a>, _: &Args) -> Result<Hit<'a>, CompileError> {
    Ok(Hit::at(ray, b.below))
}
pub(crate) fn build_binary<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, b: Bracket<'a>, a: &Args) -> Result<Hit<'a>, CompileError> {
    Ok(binary::binary(s, ray, b, a.int("steps")?))
}
pub(crate) fn build_interval<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, b: Bracket<'a>, a: &Args) -> Result<Hit<'a>, CompileError> {
    Ok(secant::interval(s, ray, b, a.int("steps")?))
}
pub(crate) fn build_secant<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, b: Bracket<'a>, a: &Args) -> Result<Hit<'a>, CompileError> {
    Ok(secant::secant(s, ray, b, a.int("steps")?))
}
