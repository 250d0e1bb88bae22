//! Shadow stages: hit + light direction → visibility in [0, 1].

pub mod march;

use crate::compose::CompileError;
use crate::ir::{Stage, Val, Vec3};
use crate::spec::{StageSpec, Value};
use crate::stage::Hit;

/// Builds the shadow stage `spec` into the current function.
pub fn build<'a>(
    s: &'a Stage<'a>,
    hit: &Hit<'a>,
    light: Val<'a, Vec3>,
    spec: &StageSpec,
) -> Result<Val<'a, f32>, CompileError> {
    Ok(match spec.name.as_str() {
        "none" => s.lit(1.0),
        "hard" => match spec.get("search") {
            Some(Value::Int(n)) => march::hard(s, hit, light, *n),
            Some(Value::Stage(inner)) => {
                return Err(CompileError::not_implemented("shadow search", &inner.name))
            }
            _ => return Err(CompileError::not_implemented("shadow", "hard without a search")),
        },
        "soft" => march::soft(s, hit, light, spec.int("steps")),
        other => return Err(CompileError::not_implemented("shadow", other)),
    })
}
