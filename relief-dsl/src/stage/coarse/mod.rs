//! Coarse searches: ray → bracket. One file per method family.

pub mod cone;
pub mod linear;
pub mod maxmip;
pub mod parallax;
pub mod sphere;

use crate::CompileError;
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
        "csm" => {
            let sample = match spec.word("sample") {
                "nearest" => cone::ConeSample::Nearest,
                "min4" => cone::ConeSample::Min4,
                "corners" => cone::ConeSample::Corners,
                _ => cone::ConeSample::Linear,
            };
            cone::csm(s, ray, spec.int("steps"), sample)
        }
        "qcsm" => cone::qcsm(s, ray, spec.int("steps")),
        "rcs" => {
            let start = match spec.word("start") {
                "bracket" => cone::RelaxedStart::Bracket,
                _ => cone::RelaxedStart::Hk,
            };
            cone::rcs(s, ray, spec.int("steps"), start)
        }
        "cns" => cone::cns(s, ray, spec.int("steps")),
        "rcns" => cone::rcns(s, ray, spec.int("steps")),
        "mcns" => cone::mcns(s, ray, spec.int("steps"), spec.int("k")),
        "pcns" => cone::pcns(s, ray, spec.int("steps"), spec.int("k")),
        "maxmip" => maxmip::maxmip(s, ray, spec.int("steps")),
        "sphere" => sphere::sphere(s, ray, spec.int("steps"), crate::abi::DISTANCE_FIELD_Z),
        other => return Err(CompileError::not_implemented("coarse", other)),
    })
}
