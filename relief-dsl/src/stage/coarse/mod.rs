//! Coarse searches: ray → bracket. One file per method family.

pub mod cell;
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
            let form = form(spec)?;
            let sample = match (form, spec.word("sample")) {
                (cone::Form::Safe, "auto") => cone::ConeSample::Linear,
                (cone::Form::Textbook, "auto" | "linear") => cone::ConeSample::Linear,
                (cone::Form::Textbook, "nearest") => cone::ConeSample::Nearest,
                (cone::Form::Textbook, "min4") => cone::ConeSample::Min4,
                (cone::Form::Safe, other) => return Err(only_textbook("csm", &format!("sample={other}"))),
                (_, other) => return Err(bad_choice("csm", "sample", other)),
            };
            cone::csm(s, ray, spec.int("steps"), form, sample)
        }
        "qcsm" => cone::qcsm(s, ray, spec.int("steps"), form(spec)?),
        "rcs" => {
            let form = form(spec)?;
            let start = match (form, spec.word("start")) {
                (cone::Form::Safe, "auto" | "bracket") => cone::RelaxedStart::Bracket,
                (cone::Form::Textbook, "auto" | "hk") => cone::RelaxedStart::Hk,
                (cone::Form::Textbook, "bracket") => cone::RelaxedStart::Bracket,
                (cone::Form::Safe, "hk") => return Err(only_textbook("rcs", "start=hk")),
                (_, other) => return Err(bad_choice("rcs", "start", other)),
            };
            cone::rcs(s, ray, spec.int("steps"), form, start)
        }
        "cns" => cone::cns(s, ray, spec.int("steps"), form(spec)?),
        "rcns" => cone::rcns(s, ray, spec.int("steps"), form(spec)?),
        "mcns" => cone::mcns(s, ray, spec.int("steps"), spec.int("k"), form(spec)?),
        "pcns" => cone::pcns(s, ray, spec.int("steps"), spec.int("k"), form(spec)?),
        "maxmip" => maxmip::maxmip(s, ray, spec.int("steps")),
        "sphere" => sphere::sphere(s, ray, spec.int("steps")),
        other => return Err(CompileError::not_implemented("coarse", other)),
    })
}

/// The `form` of a cone method.
fn form(spec: &StageSpec) -> Result<cone::Form, CompileError> {
    match spec.word("form") {
        "safe" => Ok(cone::Form::Safe),
        "textbook" => Ok(cone::Form::Textbook),
        other => Err(bad_choice(&spec.name, "form", other)),
    }
}

fn only_textbook(stage: &str, what: &str) -> CompileError {
    CompileError {
        stage: format!("coarse {stage}"),
        message: format!("`{what}` applies to `form=textbook` only: the safe form reads the cone of the cell under the ray point"),
    }
}

fn bad_choice(stage: &str, param: &str, word: &str) -> CompileError {
    CompileError { stage: format!("coarse {stage}"), message: format!("`{param}={word}` is not a choice this stage knows") }
}
