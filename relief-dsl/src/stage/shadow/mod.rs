//! Shadow stages: hit + light direction → visibility in [0, 1].

pub mod cone;
pub mod march;

use crate::CompileError;
use crate::ir::{Stage, Val, Vec3};
use crate::spec::{StageSpec, Value};
use crate::stage::{Bracket, Hit};

/// Builds the shadow stage `spec` into the current function.
pub fn build<'a>(
    s: &'a Stage<'a>,
    hit: &Hit<'a>,
    light: Val<'a, Vec3>,
    light_cos: Val<'a, f32>,
    spec: &StageSpec,
) -> Result<Val<'a, f32>, CompileError> {
    Ok(match spec.name.as_str() {
        "none" => s.lit(1.0),
        "hard" => match spec.get("search") {
            Some(Value::Int(n)) => march::hard(s, hit, light, *n),
            Some(Value::Stage(inner)) => {
                let mut result = Ok(());
                let v = march::hard_with(s, hit, light, light_cos, |s, ray| match crate::stage::coarse::build(s, ray, inner) {
                    Ok(b) => b,
                    Err(e) => {
                        result = Err(e);
                        Bracket::new(s.lit(0.0), s.lit(0.0))
                    }
                });
                result?;
                v
            }
            _ => return Err(CompileError::not_implemented("shadow", "hard without a search")),
        },
        "soft" => march::soft(s, hit, light, spec.int("steps")),
        "soft_cone" => cone::soft(s, hit, light, spec.int("steps"), cone::Source::ConeNormal),
        "soft_ratio" => cone::soft(s, hit, light, spec.int("steps"), cone::Source::ConeRatio),
        other => return Err(CompileError::not_implemented("shadow", other)),
    })
}
