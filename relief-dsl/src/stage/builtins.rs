//! The builders of the built-in methods: the code behind the catalogue's data
//! (`spec::catalog`), by slot and name, in the catalogue's listing order. The catalogue sits
//! below the stages and cannot name them; this table, above it, can.

use super::Build::{self, Ao, Coarse, Refine, Shadow};
use super::{ao, coarse as c, refine as r, shadow as sh};
use crate::spec::Slot;

/// `(slot, name, builder)` of every built-in method.
static BUILDERS: &[(Slot, &str, Build)] = &[
    (Slot::Coarse, "none", Coarse(c::build_none)),
    (Slot::Coarse, "parallax", Coarse(c::build_parallax)),
    (Slot::Coarse, "offset_limited", Coarse(c::build_offset_limited)),
    (Slot::Coarse, "slope_parallax", Coarse(c::build_slope_parallax)),
    (Slot::Coarse, "iterative_parallax", Coarse(c::build_iterative_parallax)),
    (Slot::Coarse, "linear", Coarse(c::build_linear)),
    (Slot::Coarse, "linear_dynamic", Coarse(c::build_linear_dynamic)),
    (Slot::Coarse, "linear_distance", Coarse(c::build_linear_distance)),
    (Slot::Coarse, "csm", Coarse(c::build_csm)),
    (Slot::Coarse, "qcsm", Coarse(c::build_qcsm)),
    (Slot::Coarse, "rcs", Coarse(c::build_rcs)),
    (Slot::Coarse, "cns", Coarse(c::build_cns)),
    (Slot::Coarse, "rcns", Coarse(c::build_rcns)),
    (Slot::Coarse, "mcns", Coarse(c::build_mcns)),
    (Slot::Coarse, "pcns", Coarse(c::build_pcns)),
    (Slot::Coarse, "sphere", Coarse(c::build_sphere)),
    (Slot::Coarse, "maxmip", Coarse(c::build_maxmip)),
    (Slot::Refine, "none", Refine(r::build_none)),
    (Slot::Refine, "binary", Refine(r::build_binary)),
    (Slot::Refine, "interval", Refine(r::build_interval)),
    (Slot::Refine, "secant", Refine(r::build_secant)),
    (Slot::Shadow, "none", Shadow(sh::build_none)),
    (Slot::Shadow, "hard", Shadow(sh::build_hard)),
    (Slot::Shadow, "soft", Shadow(sh::build_soft)),
    (Slot::Shadow, "soft_cone", Shadow(sh::build_soft_cone)),
    (Slot::Shadow, "soft_ratio", Shadow(sh::build_soft_ratio)),
    (Slot::Ao, "none", Ao(ao::build_none)),
    (Slot::Ao, "cone_ratio", Ao(ao::build_cone_ratio)),
    (Slot::Ao, "cone_normal", Ao(ao::build_cone_normal)),
];

/// The built-in builder of the method `name` of `slot`.
pub(super) fn builder(slot: Slot, name: &str) -> Option<Build> {
    BUILDERS.iter().find(|(s, n, _)| *s == slot && *n == name).map(|(_, _, b)| *b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spec::{catalog, method, register, MethodDef, ParamDef, Pipeline, Value};

    fn coarse_linear() -> Build {
        builder(Slot::Coarse, "linear").unwrap()
    }

    /// The catalogue's built-in methods (data, in `spec`) and this table (code) name the
    /// same methods in the same slots.
    #[test]
    fn every_built_in_method_has_its_builder_and_no_builder_is_left_over() {
        let builtins: Vec<_> = catalog().iter().filter(|m| m.build.is_none()).map(|m| (m.slot, m.name)).collect();
        let table: Vec<_> = BUILDERS.iter().map(|(slot, name, _)| (*slot, *name)).collect();
        assert_eq!(builtins, table);
        for (slot, name, b) in BUILDERS {
            assert_eq!(b.slot(), *slot, "{name}");
        }
        assert!(method(Slot::Coarse, "linear").unwrap().build.is_none());
    }

    #[test]
    fn register_refuses_what_the_text_form_could_not_read() {
        let refused = |def: MethodDef, why: &str| {
            let e = register(def).unwrap_err();
            assert!(e.message.contains(why), "{e}");
        };
        refused(MethodDef::new("Linear2", "", coarse_linear()), "lower_snake");
        refused(MethodDef::new("2linear", "", coarse_linear()), "lower_snake");
        refused(MethodDef::new("linear", "", coarse_linear()), "already has a method called `linear`");
        let mut wrong_slot = MethodDef::new("test_wrong_slot", "", coarse_linear());
        wrong_slot.slot = Slot::Refine;
        refused(wrong_slot, "builder is a coarse stage");
        refused(
            MethodDef::new("test_twice", "", coarse_linear()).param(ParamDef::steps("n", 4)).param(ParamDef::steps("n", 8)),
            "two parameters called `n`",
        );
        refused(MethodDef::new("test_range", "", coarse_linear()).param(ParamDef::count("k", 1, 4, 5)), "default of `k`");
        refused(MethodDef::new("test_steps", "", coarse_linear()).param(ParamDef::steps("n", 0)), "default of `n`");
        // `none` exists in every slot without parameters; a coarse `binary` would print with
        // the refine `binary`'s parameters.
        refused(MethodDef::new("binary", "", coarse_linear()), "has other parameters");
        for name in ["Linear2", "2linear", "test_wrong_slot", "test_twice", "test_range", "test_steps"] {
            assert!(catalog().iter().all(|m| m.name != name), "{name} was added");
        }
    }

    #[test]
    fn a_registered_stage_parses_prints_and_compiles() {
        register(MethodDef::new("test_search", "a test", coarse_linear()).param(ParamDef::steps("steps", 7))).unwrap();
        let p: Pipeline = "test_search+binary(2)".parse().unwrap();
        assert_eq!(p.to_string(), "test_search(7)+binary(2)");
        let e = "test_search(0)".parse::<Pipeline>().unwrap_err();
        assert!(e.message.contains("out of range"), "{e}");
        // The builder is linear's: the module has the registered name and linear's loop.
        let wgsl = crate::emit::emit(&p).unwrap().wgsl;
        assert!(wgsl.contains("fn coarse_test_search("), "{wgsl}");
        assert!(catalog().iter().any(|m| m.name == "test_search"));
    }

    #[test]
    fn a_hand_edited_choice_is_an_error_not_a_default() {
        for (text, param) in [("csm(8)", "form"), ("csm(8)", "sample"), ("rcs(8)", "start"), ("qcsm(8)", "form")] {
            let mut p: Pipeline = text.parse().unwrap();
            let v = p.coarse.params.iter_mut().find(|(n, _)| n == param).unwrap();
            v.1 = Value::Word("sideways".into());
            let e = crate::compile(&p).err().unwrap_or_else(|| panic!("{text} with {param}=sideways compiled"));
            assert!(e.stage.starts_with("coarse "), "{e}");
            assert!(e.message.contains(&format!("`{param}=sideways` is not a choice")), "{e}");
        }
    }
}
