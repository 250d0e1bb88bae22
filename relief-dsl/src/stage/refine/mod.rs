//! Refining searches: ray + bracket → hit. One file per method family.

pub mod binary;
pub mod secant;

use crate::CompileError;
use crate::ir::Stage;
use crate::spec::StageSpec;
use crate::stage::{Bracket, Hit, Ray};

/// No refinement: the hit is the bracket's far end, the coarse search's answer.
pub fn none<'a>(ray: &Ray<'a>, b: Bracket<'a>) -> Hit<'a> {
    Hit::at(ray, b.below)
}

/// Builds the refine stage `spec` into the current function.
pub fn build<'a>(
    s: &'a Stage<'a>,
    ray: &Ray<'a>,
    b: Bracket<'a>,
    spec: &StageSpec,
) -> Result<Hit<'a>, CompileError> {
    Ok(match spec.name.as_str() {
        "none" => none(ray, b),
        "binary" => binary::binary(s, ray, b, spec.int("steps")),
        "interval" => secant::interval(s, ray, b, spec.int("steps")),
        "secant" => secant::secant(s, ray, b, spec.int("steps")),
        other => return Err(CompileError::not_implemented("refine", other)),
    })
}
