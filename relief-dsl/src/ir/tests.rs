//! The builder's output, checked as text: each test builds one small function through
//! [`FnBuilder`] and compares the WGSL naga writes for it with the text written out by hand
//! below it (in the manner of cranelift's `check` tests). A change to what the builder emits
//! (emit ranges, loop shape, where a load happens, the probe's counters) shows up here as a
//! readable diff rather than as a different frame somewhere downstream.

use super::*;

/// Builds one function `name(args…) -> f32` with `body` under the plain policy (see
/// [`wgsl_under`]).
fn wgsl_of<'c>(
    ctx: &'c ModuleCtx,
    name: &str,
    args: &[&str],
    body: impl for<'s> FnOnce(&'s FnBuilder<'s>) -> Handle<Expression>,
) -> String {
    wgsl_under(ctx, &Plain::default(), name, args, body)
}

/// Builds one function `name(args…) -> f32` with `body` under `policy`, validates the module
/// with naga's validator (every check on) and returns the WGSL of the whole module.
fn wgsl_under<'c>(
    ctx: &'c ModuleCtx,
    policy: &dyn Policy,
    name: &str,
    args: &[&str],
    body: impl for<'s> FnOnce(&'s FnBuilder<'s>) -> Handle<Expression>,
) -> String {
    let f32_ty = ctx.ty(f32::inner());
    let args: Vec<(&str, Handle<naga::Type>, Option<naga::Binding>)> =
        args.iter().map(|a| (*a, f32_ty, None)).collect();
    let f = {
        let s = ctx.function(name, &args, policy);
        let value = body(&s);
        s.finish(Some((f32_ty, None, value)))
    };
    ctx.add_function(f);
    let module = ctx.module.borrow();
    let info = naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::default())
        .validate(&module)
        .unwrap_or_else(|e| panic!("the built module does not validate: {:?}", e.into_inner()));
    naga::back::wgsl::write_string(&module, &info, naga::back::wgsl::WriterFlags::empty()).unwrap()
}

/// Compares line by line, ignoring blank lines and indentation, and prints both texts on a
/// mismatch. naga names a value it stores in a `let` after its expression's index (`_e5`);
/// those indices count every expression in the function, literals included, and say nothing
/// about the shader's meaning, so both sides are compared with them renumbered in order of
/// first appearance.
fn check(actual: &str, expected: &str) {
    let canonical = |t: &str| -> Vec<String> {
        let mut seen: Vec<String> = Vec::new();
        let mut out = Vec::new();
        for line in t.lines().map(str::trim).filter(|l| !l.is_empty()) {
            let mut text = String::new();
            let mut rest = line;
            while let Some(k) = rest.find("_e") {
                let digits: String = rest[k + 2..].chars().take_while(char::is_ascii_digit).collect();
                let starts_name = k == 0 || !rest[..k].ends_with(|c: char| c.is_alphanumeric() || c == '_');
                if digits.is_empty() || !starts_name {
                    text.push_str(&rest[..k + 2]);
                    rest = &rest[k + 2..];
                    continue;
                }
                let name = format!("_e{digits}");
                let n = seen.iter().position(|s| *s == name).unwrap_or_else(|| {
                    seen.push(name.clone());
                    seen.len() - 1
                });
                text.push_str(&rest[..k]);
                text.push_str(&format!("%{n}"));
                rest = &rest[k + name.len()..];
            }
            text.push_str(rest);
            out.push(text);
        }
        out
    };
    assert_eq!(canonical(actual), canonical(expected), "\n--- actual ---\n{actual}\n--- expected ---\n{expected}");
}

#[test]
fn arithmetic_chain_folds_host_constants() {
    let ctx = ModuleCtx::new();
    let steps = 4u32;
    let src = wgsl_of(&ctx, "chain", &["x"], |s| {
        let x = s.arg::<f32>(0);
        // `1.0 / steps` is a host constant: it reaches the shader as one literal, 0.25.
        let step = 1.0 / steps as f32;
        let y = (x * 2.0 + step).named("y");
        (y - x / 8.0).max(0.0).handle()
    });
    check(
        &src,
        "fn chain(x: f32) -> f32 {
            let y = ((x * 2f) + 0.25f);
            return max((y - (x / 8f)), 0f);
        }",
    );
}

#[test]
fn loop_with_break_and_compound_assignment() {
    let ctx = ModuleCtx::new();
    let src = wgsl_of(&ctx, "march", &["limit"], |s| {
        let limit = s.arg::<f32>(0);
        let mut t = s.var("t", 0.0);
        s.repeat(8, |l| {
            l.break_if(t.ge(limit));
            t += 0.125;
        });
        t.get().handle()
    });
    // The pass counter `i` is the builder's: its test opens the body, and it steps in the
    // `continuing` block, so that a `continue` would step it too.
    check(
        &src,
        "fn march(limit: f32) -> f32 {
            var t: f32;
            var i: u32;

            t = 0f;
            i = 0u;
            loop {
                let _e5 = i;
                if (_e5 >= 8u) {
                    break;
                }
                let _e8 = t;
                if (_e8 >= limit) {
                    break;
                }
                let _e10 = t;
                t = (_e10 + 0.125f);
                continuing {
                    let _e13 = i;
                    i = (_e13 + 1u);
                }
            }
            let _e16 = t;
            return _e16;
        }",
    );
}

#[test]
fn select_evaluates_both_sides() {
    let ctx = ModuleCtx::new();
    let src = wgsl_of(&ctx, "magnitude", &["x"], |s| {
        let x = s.arg::<f32>(0);
        s.select(x.lt(0.0), -x, x).handle()
    });
    // naga's `select(reject, accept, condition)` puts the condition last.
    check(
        &src,
        "fn magnitude(x: f32) -> f32 {
            return select(x, -(x), (x < 0f));
        }",
    );
}

#[test]
fn if_else_stores_into_a_local() {
    let ctx = ModuleCtx::new();
    let src = wgsl_of(&ctx, "halve_or_double", &["x"], |s| {
        let x = s.arg::<f32>(0);
        let v = s.var("v", x);
        // `Var` is `Copy`: each branch takes its own copy to assign through.
        s.if_else(
            x.gt(1.0),
            |_| {
                let mut v = v;
                v /= 2.0;
            },
            |_| {
                let mut v = v;
                v *= 2.0;
            },
        );
        v.get().handle()
    });
    check(
        &src,
        "fn halve_or_double(x: f32) -> f32 {
            var v: f32;

            v = x;
            if (x > 1f) {
                let _e4 = v;
                v = (_e4 / 2f);
            } else {
                let _e7 = v;
                v = (_e7 * 2f);
            }
            let _e10 = v;
            return _e10;
        }",
    );
}

#[test]
fn counting_loops_add_to_the_step_counter() {
    // The probe's copy of a stage: every pass of a loop adds one to the private counter the
    // composer named (here the refine stage's), after the pass's exit test.
    let ctx = ModuleCtx::new();
    let plain = Plain::default();
    let probe = Counting { inner: &plain, steps: counter::REFINE_STEPS };
    let src = wgsl_under(&ctx, &probe, "passes", &["x"], |s| {
        let x = s.arg::<f32>(0);
        let mut acc = s.var("acc", x);
        s.repeat(2, |_| acc += 1.0);
        acc.get().handle()
    });
    check(
        &src,
        "var<private> relief_refine_steps: u32;

        fn passes(x: f32) -> f32 {
            var acc: f32;
            var i: u32;

            acc = x;
            i = 0u;
            loop {
                let _e4 = i;
                if (_e4 >= 2u) {
                    break;
                }
                let _e8 = relief_refine_steps;
                relief_refine_steps = (_e8 + 1u);
                let _e11 = acc;
                acc = (_e11 + 1f);
                continuing {
                    let _e14 = i;
                    i = (_e14 + 1u);
                }
            }
            let _e17 = acc;
            return _e17;
        }",
    );
}

/// The binding table records each bound global once, where it is first declared, and two
/// resources at one binding make `finish` fail with both named (the composer's error), not
/// a module whose bind group would silently take the first.
#[test]
fn two_resources_at_one_binding_are_an_error_naming_both() {
    let sampler = |m: &ModuleCtx| m.ty(naga::TypeInner::Sampler { comparison: false });
    let ctx = ModuleCtx::new();
    let a = ctx.bound("linear_sampler", naga::AddressSpace::Handle, 2, Resource::Sampler(Filter::Linear), sampler);
    let again = ctx.bound("linear_sampler", naga::AddressSpace::Handle, 2, Resource::Sampler(Filter::Linear), sampler);
    assert_eq!(a, again, "a second ask is the same global");
    assert_eq!(ctx.bindings().len(), 1);
    let (_, table) = ctx.finish().expect("one resource per binding");
    assert_eq!(table.resource(2), Some(Resource::Sampler(Filter::Linear)));
    assert_eq!(table.get(2).map(|e| e.name.as_str()), Some("linear_sampler"));

    let ctx = ModuleCtx::new();
    ctx.bound("linear_sampler", naga::AddressSpace::Handle, 2, Resource::Sampler(Filter::Linear), sampler);
    ctx.bound("nearest_sampler", naga::AddressSpace::Handle, 2, Resource::Sampler(Filter::Nearest), sampler);
    let e = ctx.finish().expect_err("two resources at binding 2");
    assert!(e.contains("binding 2") && e.contains("`linear_sampler`") && e.contains("`nearest_sampler`"), "{e}");
}
