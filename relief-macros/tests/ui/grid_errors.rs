// Grid errors point at the offending token inside the lists.
fn main() {
    let _ = relief::relief_grid! { coarse: [linear(5..=35 step 5), lnear(5)], refine: [none] };
    let _ = relief::relief_grid! { coarse: [linear(8)], refine: [none, binary(3), linear(3)] };
    let _ = relief::relief_grid! { coarse: [linear(40..=8)] };
    let _ = relief::relief_grid! { coarse: [linear(0..=8 step 4)] };
    let _ = relief::relief_grid! { coarse: [linear(4..=8 step 0)] };
    let _ = relief::relief_grid! { coarse: [linear(4..8)] };
    let _ = relief::relief_grid! { coarse: [linear_dynamic([8, 64], 32)] };
    let _ = relief::relief_grid! { coarse: [], refine: [none] };
}
