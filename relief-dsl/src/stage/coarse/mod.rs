//! Coarse searches: ray → bracket. One file per method family.

pub mod linear;
pub mod parallax;

use crate::compose::CompileError;
use crate::ir::Stage;
use crate::spec::StageSpec;
use crate::stage::{Bracket, Ray};

/// Builds the coarse stage `spec` into the current function.
pub fn build<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, spec: &StageSpec) -> Result<Bracket<'a>, CompileError> {
    Ok(match spec.name.as_str() {
        "none" => parallax::none(s, ray),
        "parallax" => parallax::parallax(s, ray),
        "offset_limited" => parallax::offset_limited(s, ray),
        "slope_parallax" => parallax::slope_parallax(s, ray),
        "iterative_parallax" => parallax::iterative_parallax(s, ray, spec.int("steps")),
        "linear" => linear::linear(s, ray, spec.int("steps")),
        "linear_dynamic" => linear::linear_dynamic(s, ray, spec.int("min"), spec.int("max")),
        other => return Err(CompileError::not_implemented("coarse", other)),
    })
}
