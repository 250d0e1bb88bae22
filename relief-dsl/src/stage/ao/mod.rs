//! Ambient-occlusion stages: hit → ambient factor in [0, 1].

use crate::compose::CompileError;
use crate::ir::{Stage, Val};
use crate::spec::StageSpec;
use crate::stage::Hit;

/// Builds the ao stage `spec` into the current function.
pub fn build<'a>(s: &'a Stage<'a>, _hit: &Hit<'a>, spec: &StageSpec) -> Result<Val<'a, f32>, CompileError> {
    match spec.name.as_str() {
        "none" => Ok(s.lit(1.0)),
        other => Err(CompileError::not_implemented("ao", other)),
    }
}
