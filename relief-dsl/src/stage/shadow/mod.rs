//! Shadow stages: hit + light direction → visibility in [0, 1]. Each method's catalogue entry
//! (a `*_def` function returning its [`MethodDef`]) sits beside its code.

pub(crate) mod cone_distance;
pub(crate) mod march;

use crate::spec::MethodDef;
use crate::stage::StageFn;

/// `none`: no self-shadowing, visibility 1.
fn none_def() -> MethodDef {
    MethodDef::new("none", "no self-shadowing: visibility 1", StageFn::Shadow(|s, _, _, _| Ok(s.lit(1.0))))
}

/// The built-in shadow methods, in listing order.
pub(crate) fn methods() -> Vec<MethodDef> {
    vec![
        none_def(),
        march::hard_def(),
        march::soft_def(),
        cone_distance::soft_cone_def(),
        cone_distance::soft_ratio_def(),
    ]
}
