//! Coarse searches: ray → bracket. One file per method family; the builders below are the
//! ones the catalogue ([`crate::spec::catalog`]) registers.

pub(crate) mod cell;
pub(crate) mod cone;
pub(crate) mod linear;
pub(crate) mod maxmip;
pub(crate) mod parallax;
pub(crate) mod sphere;

use crate::ir::Stage;
use crate::spec::{Args, SampleChoice, Slot, StageSpec, StartChoice};
use crate::stage::{Bracket, Build, Ray};
use crate::CompileError;
use cone::{ConeSample, Form, RelaxedStart};

/// Builds the coarse stage `spec` into the current function, with the builder the
/// catalogue registers for it.
pub(crate) fn build<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, spec: &StageSpec) -> Result<Bracket<'a>, CompileError> {
    match super::lookup(Slot::Coarse, spec)? {
        Build::Coarse(f) => f(s, ray, &Args::new(Slot::Coarse, spec)),
        other => Err(CompileError::wrong_slot(Slot::Coarse, &spec.name, other.slot())),
    }
}

pub(crate) fn build_none<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, _: &Args) -> Result<Bracket<'a>, CompileError> {
    Ok(parallax::none(s, ray))
}
pub(crate) fn build_parallax<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, _: &Args) -> Result<Bracket<'a>, CompileError> {
    Ok(parallax::parallax(s, ray))
}
pub(crate) fn build_offset_limited<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, _: &Args) -> Result<Bracket<'a>, CompileError> {
    Ok(parallax::offset_limited(s, ray))
}
pub(crate) fn build_slope_parallax<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, _: &Args) -> Result<Bracket<'a>, CompileError> {
    Ok(parallax::slope_parallax(s, ray))
}
pub(crate) fn build_iterative_parallax<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, a: &Args) -> Result<Bracket<'a>, CompileError> {
    Ok(parallax::iterative_parallax(s, ray, a.int("steps")?))
}
pub(crate) fn build_linear<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, a: &Args) -> Result<Bracket<'a>, CompileError> {
    Ok(linear::linear(s, ray, a.int("steps")?))
}
pub(crate) fn build_linear_dynamic<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, a: &Args) -> Result<Bracket<'a>, CompileError> {
    Ok(linear::linear_dynamic(s, ray, a.int("min")?, a.int("max")?))
}
pub(crate) fn build_linear_distance<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, a: &Args) -> Result<Bracket<'a>, CompileError> {
    Ok(linear::linear_distance(s, ray, a.int("min")?, a.int("max")?, a.int("theta_min")?))
}
pub(crate) fn build_csm<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, a: &Args) -> Result<Bracket<'a>, CompileError> {
    let form = a.choice::<Form>("form")?;
    let sample = match (form, a.choice::<SampleChoice>("sample")?) {
        (Form::Safe, SampleChoice::Auto) => ConeSample::Linear,
        (Form::Textbook, SampleChoice::Auto | SampleChoice::Linear) => ConeSample::Linear,
        (Form::Textbook, SampleChoice::Nearest) => ConeSample::Nearest,
        (Form::Textbook, SampleChoice::Min4) => ConeSample::Min4,
        (Form::Safe, SampleChoice::Linear) => return Err(only_textbook("csm", "sample=linear")),
        (Form::Safe, SampleChoice::Nearest) => return Err(only_textbook("csm", "sample=nearest")),
        (Form::Safe, SampleChoice::Min4) => return Err(only_textbook("csm", "sample=min4")),
    };
    Ok(cone::csm(s, ray, a.int("steps")?, form, sample))
}
pub(crate) fn build_qcsm<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, a: &Args) -> Result<Bracket<'a>, CompileError> {
    Ok(cone::qcsm(s, ray, a.int("steps")?, a.choice("form")?))
}
pub(crate) fn build_rcs<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, a: &Args) -> Result<Bracket<'a>, CompileError> {
    let form = a.choice::<Form>("form")?;
    let start = match (form, a.choice::<StartChoice>("start")?) {
        (Form::Safe, StartChoice::Auto | StartChoice::Bracket) => RelaxedStart::Bracket,
        (Form::Textbook, StartChoice::Auto | StartChoice::Hk) => RelaxedStart::Hk,
        (Form::Textbook, StartChoice::Bracket) => RelaxedStart::Bracket,
        (Form::Safe, StartChoice::Hk) => return Err(only_textbook("rcs", "start=hk")),
    };
    Ok(cone::rcs(s, ray, a.int("steps")?, form, start))
}
pub(crate) fn build_cns<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, a: &Args) -> Result<Bracket<'a>, CompileError> {
    Ok(cone::cns(s, ray, a.int("steps")?, a.choice("form")?))
}
pub(crate) fn build_rcns<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, a: &Args) -> Result<Bracket<'a>, CompileError> {
    Ok(cone::rcns(s, ray, a.int("steps")?, a.choice("form")?))
}
pub(crate) fn build_mcns<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, a: &Args) -> Result<Bracket<'a>, CompileError> {
    Ok(cone::mcns(s, ray, a.int("steps")?, a.int("k")?, a.choice("form")?))
}
pub(crate) fn build_pcns<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, a: &Args) -> Result<Bracket<'a>, CompileError> {
    Ok(cone::pcns(s, ray, a.int("steps")?, a.int("k")?, a.choice("form")?))
}
pub(crate) fn build_maxmip<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, a: &Args) -> Result<Bracket<'a>, CompileError> {
    Ok(maxmip::maxmip(s, ray, a.int("steps")?))
}
pub(crate) fn build_sphere<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, a: &Args) -> Result<Bracket<'a>, CompileError> {
    Ok(sphere::sphere(s, ray, a.int("steps")?))
}

fn only_textbook(stage: &str, what: &str) -> CompileError {
    CompileError {
        stage: format!("coarse {stage}"),
        message: format!("`{what}` applies to `form=textbook` only: the safe form reads the cone of the cell under the ray point"),
    }
}
