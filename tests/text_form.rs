//! The text form: round trips, canonical printing, and errors that name the problem.

use proptest::prelude::*;
use relief::dsl::spec::{catalog, MethodDef, ParamKind, Pipeline, Slot, StageSpec, Value, MAX_STEPS};

fn methods(slot: Slot) -> Vec<&'static MethodDef> {
    catalog().iter().filter(|m| m.slot == slot).collect()
}

/// A random stage of `slot` with random valid parameters.
fn stage(slot: Slot) -> impl Strategy<Value = StageSpec> {
    let ms = methods(slot);
    (
        0..ms.len(),
        proptest::collection::vec(1u32..=MAX_STEPS, 4),
        proptest::collection::vec(any::<prop::sample::Index>(), 4),
    )
        .prop_map(move |(i, ints, picks)| {
            let m = ms[i];
            let mut values: Vec<Value> = m
                .params
                .iter()
                .enumerate()
                .map(|(k, p)| match &p.kind {
                    ParamKind::Steps | ParamKind::StageOr(_) => Value::Int(ints[k]),
                    ParamKind::Count { min, max } => Value::Int(min + ints[k] % (max - min + 1)),
                    ParamKind::Choice(words) => Value::Word(picks[k].get(words).to_string()),
                })
                .collect();
            if m.name == "linear_dynamic" {
                values.sort_by_key(|v| match v {
                    Value::Int(n) => *n,
                    _ => 0,
                });
            }
            StageSpec::new(slot, m.name, &values).expect("generated parameters are valid")
        })
}

fn pipeline() -> impl Strategy<Value = Pipeline> {
    (stage(Slot::Coarse), stage(Slot::Refine), stage(Slot::Shadow), stage(Slot::Ao))
        .prop_map(|(c, r, s, a)| Pipeline::new(c, r, s, a))
}

proptest! {
    #[test]
    fn parse_of_print_is_identity(p in pipeline()) {
        let text = p.to_string();
        let back: Pipeline = text.parse().map_err(|e| TestCaseError::fail(format!("{text}: {e}")))?;
        prop_assert_eq!(back, p);
    }

    #[test]
    fn arbitrary_strings_never_panic_and_errors_name_a_position(s in "\\PC{0,40}") {
        if let Err(e) = s.parse::<Pipeline>() {
            prop_assert!(e.pos <= s.chars().count());
            let prefix = format!("at {}", e.pos);
            prop_assert!(e.to_string().starts_with(&prefix));
        }
    }

    #[test]
    fn near_miss_strings_never_panic(s in "[a-z_]{1,12}(\\(([0-9]{1,6}|[a-z]{1,6})?(, ?[a-z]{1,5}=[0-9a-z]{1,5})?\\))?(\\+(shadow=|ao=|refine=)?[a-z_]{1,10}(\\([0-9]{0,5}\\))?){0,3}") {
        let _ = s.parse::<Pipeline>();
    }
}

#[test]
fn canonical_form_examples() {
    for (input, canonical) in [
        ("linear(10)+binary(5)", "linear(10)+binary(5)"),
        ("linear( steps = 10 )+ binary(5)", "linear(10)+binary(5)"),
        ("linear", "linear(32)"),
        ("linear(10)+interval(3)+shadow=soft(30)", "linear(10)+interval(3)+shadow=soft(30)"),
        ("coarse=linear(10)+refine=none+shadow=none+ao=none", "linear(10)"),
        ("ao=none+shadow=hard(linear(20))+coarse=parallax", "parallax+shadow=hard(20)"),
        ("linear_dynamic(max=64, min=4)", "linear_dynamic(4, 64)"),
    ] {
        let p: Pipeline = input.parse().unwrap_or_else(|e| panic!("{input}: {e}"));
        assert_eq!(p.to_string(), canonical, "{input}");
    }
}

#[test]
fn bad_inputs_give_errors_that_name_the_problem() {
    let cases: &[(&str, &[&str])] = &[
        ("", &["empty pipeline"]),
        (
            "lnear(10)",
            &["at 0 (`lnear`)", "unknown coarse stage", "did you mean `linear`", "expected one of: none, parallax"],
        ),
        ("linear(10)+binery(3)", &["at 11 (`binery`)", "unknown refine stage", "did you mean `binary`"]),
        ("binary(5)", &["`binary` is a refine stage, not a coarse stage"]),
        ("linear(10)+linear(5)", &["`linear` is a coarse stage, not a refine stage"]),
        ("linear(0)", &["at 7 (`0`)", "step count 0", "out of range: allowed 1..=4096"]),
        ("linear(4097)", &["step count 4097", "allowed 1..=4096"]),
        ("linear(99999999999999999999)", &["not a whole number"]),
        ("linear(10", &["the input ends", "`,` or `)`"]),
        ("linear(10))", &["expected `+` or the end"]),
        ("linear(10, 5)", &["takes at most 1 parameter"]),
        ("linear(stpes=10)", &["has no parameter `stpes`", "did you mean `steps`"]),
        ("parallax(3)", &["`parallax` takes no parameters"]),
        ("linear(steps=1, steps=2)", &["given twice"]),
        ("linear(10)+binary(5)+soft(3)", &["third stage needs its slot named"]),
        ("linear(10)+shadw=soft(3)", &["unknown slot or option `shadw`", "did you mean `shadow`"]),
        ("linear(10)+shadow=soft(3)+shadow=hard(2)", &["shadow slot is given twice"]),
        ("shadow=soft(3)", &["no coarse stage"]),
        ("linear(-3)", &["negative numbers"]),
        ("linear(10)*binary(3)", &["at 10 (`*`)", "unexpected character"]),
        ("linear_dynamic(40, 10)", &["min <= max"]),
        ("linear(ten)", &["not a whole number for `steps` of `linear`"]),
        ("linear(10)+shadow=hard(binary(3))", &["`binary` is a refine stage, not a coarse stage"]),
    ];
    for (input, fragments) in cases {
        let err = match input.parse::<Pipeline>() {
            Ok(p) => panic!("`{input}` parsed as {p}"),
            Err(e) => e.to_string(),
        };
        for f in *fragments {
            assert!(err.contains(f), "error for `{input}` is `{err}`, which lacks `{f}`");
        }
    }
}

#[test]
fn file_stems_are_file_safe_and_distinct() {
    let all = Pipeline::all_defaults();
    let mut stems: Vec<String> = all.iter().map(|p| p.file_stem()).collect();
    for s in &stems {
        assert!(s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-'), "{s}");
    }
    stems.sort();
    stems.dedup();
    assert_eq!(stems.len(), all.len());
    let p: Pipeline = "linear(10)+binary(5)+shadow=soft(30)".parse().unwrap();
    assert_eq!(p.file_stem(), "linear_10__binary_5__shadow-soft_30");
}
