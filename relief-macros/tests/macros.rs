//! The macros: compile errors (trybuild, messages checked against tests/ui/*.stderr), and
//! agreement with the text forms and with emitting at run time.

use relief::dsl::spec::{Grid, Pipeline};
use relief::{relief, relief_grid, relief_shader};

/// Each file in tests/ui must fail to compile with exactly the messages in its `.stderr`.
/// Regenerate with `TRYBUILD=overwrite cargo test --release -p relief-macros --test macros` and review them.
#[test]
fn compile_errors_point_at_the_offending_token() {
    let t = trybuild::TestCases::new();
    t.compile_fail("tests/ui/*.rs");
}

fn parse(text: &str) -> Pipeline {
    text.parse().unwrap_or_else(|e| panic!("{text}: {e}"))
}

#[test]
fn relief_equals_the_text_form() {
    let cases: Vec<(Pipeline, &str)> = vec![
        (
            relief! { coarse: linear(15), refine: binary(6), shadow: soft(30), ao: none },
            "linear(15)+binary(6)+shadow=soft(30)",
        ),
        (relief! { coarse: linear(steps = 10) }, "linear(10)"),
        (relief! { coarse: linear }, "linear"),
        (relief! { refine: interval(3), coarse: parallax, }, "parallax+interval(3)"),
        (relief! { coarse: linear_dynamic(max = 64, min = 4), refine: secant(4) }, "linear_dynamic(4, 64)+secant(4)"),
        (relief! { coarse: iterative_parallax(6), shadow: hard(linear(20)) }, "iterative_parallax(6)+shadow=hard(20)"),
        (
            relief! { coarse: slope_parallax, shadow: hard(iterative_parallax(3)) },
            "slope_parallax+shadow=hard(iterative_parallax(3))",
        ),
        (relief! { coarse: offset_limited, shadow: hard }, "offset_limited+shadow=hard"),
        (relief! { coarse: none, refine: none, shadow: none, ao: none }, "none"),
        (relief!("linear(10)+binary(5)"), "linear(10)+binary(5)"),
        (relief! { coarse: linear(32), refine: binary(5), lod: auto }, "linear(32)+binary(5)+lod=auto"),
        (relief! { coarse: linear(32), lod: level(3), silhouette: clip }, "linear(32)+lod=level(3)+silhouette=clip"),
        (relief!("linear(32)+lod=level(2)"), "linear(32)+lod=level(2)"),
    ];
    for (p, text) in cases {
        assert_eq!(p, parse(text), "{text}");
        assert_eq!(p, parse(&p.to_string()), "{text}");
    }
}

#[test]
fn relief_grid_equals_the_text_grid() {
    let g = relief_grid! {
        coarse: [linear(5..=35 step 5), linear_dynamic(8, 32), parallax],
        refine: [none, binary(3), interval(3)],
        shadow: [none],
    };
    let text = "coarse: [linear(5..=35 step 5), linear_dynamic(8, 32), parallax]\n\
                refine: [none, binary(3), interval(3)]\n\
                shadow: [none]\n";
    assert_eq!(g, text.parse::<Grid>().unwrap());
    assert_eq!(g.len(), 9 * 3);
    assert_eq!(g.iter().next().unwrap(), &parse("linear(5)"));
    assert_eq!(g.iter().nth(1).unwrap(), &parse("linear(5)+binary(3)"));
    assert_eq!(g.iter().last().unwrap(), &parse("parallax+interval(3)"));

    // Names, lists and ranges inside parameters, single stages without brackets, nesting.
    let g = relief_grid! {
        name: "nested",
        coarse: linear_dynamic([4, 8], 16..=32 step 16),
        refine: binary(steps = 1..=2),
        shadow: [none, hard(linear([4, 8]))],
        ao: none,
    };
    let text = "# the same grid as a file\nname: \"nested\"\ncoarse: linear_dynamic([4, 8], 16..=32 step 16)\n\
                refine: binary(steps = 1..=2)  # named\nshadow: [none, hard(linear([4, 8]))], ao: none";
    assert_eq!(g, text.parse::<Grid>().unwrap());
    assert_eq!(g.name.as_deref(), Some("nested"));
    assert_eq!(g.len(), 4 * 2 * 3);
    let texts: Vec<String> = g.into_iter().map(|p| p.to_string()).take(3).collect();
    assert_eq!(
        texts,
        [
            "linear_dynamic(4, 16)+binary(1)",
            "linear_dynamic(4, 16)+binary(1)+shadow=hard(4)",
            "linear_dynamic(4, 16)+binary(1)+shadow=hard(8)"
        ]
    );

    // Pipeline options as grid axes, innermost.
    let g = relief_grid! { coarse: linear([8, 16]), refine: binary(5), lod: [zero, auto, level(1..=2)] };
    let text = "coarse: linear([8, 16])\nrefine: binary(5)\nlod: [zero, auto, level(1..=2)]";
    assert_eq!(g, text.parse::<Grid>().unwrap());
    assert_eq!(g.len(), 2 * 4);
    assert_eq!(g.iter().nth(1).unwrap(), &parse("linear(8)+binary(5)+lod=auto"));
}

relief_shader! {
    /// Linear search refined by binary search.
    mod pom { coarse: linear(10), refine: binary(5) }
    pub(crate) mod shadowed { coarse: iterative_parallax(4), refine: interval(3), shadow: soft(8) }
}

#[test]
fn relief_shader_constants_equal_emitting_at_run_time() {
    for (text, wgsl, spirv, vert, frag, comp, maps, p) in [
        (pom::TEXT, pom::WGSL, pom::SPIRV, pom::GLSL_VERT, pom::GLSL_FRAG, pom::GLSL_COMP, pom::MAPS, pom::pipeline()),
        (
            shadowed::TEXT,
            shadowed::WGSL,
            shadowed::SPIRV,
            shadowed::GLSL_VERT,
            shadowed::GLSL_FRAG,
            shadowed::GLSL_COMP,
            shadowed::MAPS,
            shadowed::pipeline(),
        ),
    ] {
        assert_eq!(p, parse(text));
        assert_eq!(p.to_string(), text);
        let out = relief::dsl::emit::emit(&p).unwrap();
        assert_eq!(wgsl, out.wgsl, "{text}");
        assert_eq!(spirv, &out.spirv[..], "{text}");
        let glsl = |suffix: &str| out.glsl.iter().find(|(s, _)| *s == suffix).unwrap().1.clone();
        assert_eq!(vert, glsl("vert"), "{text}");
        assert_eq!(frag, glsl("frag"), "{text}");
        assert_eq!(comp, glsl("comp"), "{text}");
        let names: Vec<&str> = p.required_maps().iter().map(|m| m.name()).collect();
        assert_eq!(maps, &names[..]);
    }
    assert_eq!(pom::TEXT, "linear(10)+binary(5)");
    assert_eq!(shadowed::MAPS, ["normal"]);
}
