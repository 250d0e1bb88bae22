//! Coarse searches: ray → bracket. One file per method family; each method's catalogue entry
//! (a `*_def` function returning its [`MethodDef`]) sits beside its code.

pub(crate) mod cell;
pub(crate) mod cone;
pub(crate) mod linear;
pub(crate) mod maxmip;
pub(crate) mod parallax;
pub(crate) mod relax;
pub(crate) mod sphere;

use crate::spec::MethodDef;

/// The built-in coarse methods, in listing order.
pub(crate) fn methods() -> Vec<MethodDef> {
    vec![
        parallax::none_def(),
        parallax::parallax_def(),
        parallax::offset_limited_def(),
        parallax::slope_parallax_def(),
        parallax::iterative_parallax_def(),
        linear::linear_def(),
        linear::linear_dynamic_def(),
        linear::linear_distance_def(),
        cone::csm_def(),
        cone::qcsm_def(),
        cone::rcs_def(),
        cone::cns_def(),
        cone::rcns_def(),
        cone::mcns_def(),
        cone::pcns_def(),
        sphere::sphere_def(),
        maxmip::maxmip_def(),
        relax::csm_relax_def(),
        relax::sphere_relax_def(),
    ]
}
