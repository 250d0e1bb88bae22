//! Refining searches: ray + bracket → hit. One file per method; each method's catalogue entry
//! (a `*_def` function returning its [`MethodDef`]) sits beside its code.

pub(crate) mod binary;
pub(crate) mod interval;
pub(crate) mod secant;

use crate::spec::MethodDef;
use crate::stage::{Hit, StageFn};

/// `none`: no refinement, the hit is the bracket's far end (the coarse search's answer).
fn none_def() -> MethodDef {
    MethodDef::new(
        "none",
        "no refinement: the hit is the bracket's far end",
        StageFn::Refine(|_, ray, b, _| Ok(Hit::at(ray, b.below))),
    )
}

/// The built-in refine methods, in listing order.
pub(crate) fn methods() -> Vec<MethodDef> {
    vec![none_def(), binary::binary_def(), interval::interval_def(), secant::secant_def()]
}
