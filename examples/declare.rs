//! Declaring pipelines in Rust: `relief!` for one, `relief_grid!` for many. Both are checked
//! while compiling (try misspelling a stage) and print in the canonical text form.
//!
//! `cargo run --release --example declare`

use relief::{relief, relief_grid, relief_shader, Pipeline};

// Shaders composed, validated and emitted while compiling: no naga at run time.
relief_shader! {
    /// Parallax occlusion mapping: linear search, then binary search, with a soft shadow.
    mod pom { coarse: linear(16), refine: binary(5), shadow: soft(16) }
}

/// The example's body (also run by tests/examples.rs).
pub fn run() -> Vec<String> {
    let combos: Vec<(&str, Pipeline)> = vec![
        ("plain texture mapping", relief! { coarse: none }),
        ("parallax with offset limiting", relief! { coarse: offset_limited }),
        ("steep parallax", relief! { coarse: linear(32) }),
        ("parallax occlusion mapping", relief! { coarse: linear(15), refine: binary(6), shadow: soft(30) }),
        (
            "dynamic steps, interval refinement",
            relief! { coarse: linear_dynamic(min = 8, max = 48), refine: interval(steps = 4) },
        ),
        ("iterative parallax, hard shadow", relief! { coarse: iterative_parallax(4), shadow: hard(linear(24)) }),
        ("the text form, checked too", relief!("linear(10)+secant(3)")),
    ];
    let mut lines = Vec::new();
    for (what, p) in &combos {
        let maps: Vec<&str> = p.required_maps().iter().map(|m| m.name()).collect();
        let maps = if maps.is_empty() { String::new() } else { format!("  (reads: {})", maps.join(", ")) };
        lines.push(format!("{what:<36} {p}{maps}"));
    }
    let grid = relief_grid! {
        coarse: [linear(8..=32 step 8), linear_dynamic(8, 32)],
        refine: [none, binary(3), interval(3)],
    };
    lines.push(format!(
        "a grid of {} pipelines, from {} to {}",
        grid.len(),
        grid.cells()[0],
        grid.cells()[grid.len() - 1]
    ));
    lines.push(format!(
        "{} compiled at build time: {} bytes of WGSL, {} SPIR-V words",
        pom::TEXT,
        pom::WGSL.len(),
        pom::SPIRV.len()
    ));
    lines
}

#[allow(dead_code)]
fn main() {
    for line in run() {
        println!("{line}");
    }
}
