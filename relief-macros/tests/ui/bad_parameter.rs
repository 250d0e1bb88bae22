// Parameters that do not fit the method: unknown names, wrong kinds, too many, given twice,
// missing values.
fn main() {
    let _ = relief::relief! { coarse: linear(stps = 10) };
    let _ = relief::relief! { coarse: linear(fast) };
    let _ = relief::relief! { coarse: linear(10, 20) };
    let _ = relief::relief! { coarse: parallax(4) };
    let _ = relief::relief! { coarse: linear(10, steps = 12) };
    let _ = relief::relief! { coarse: linear(steps = ) };
    let _ = relief::relief! { coarse: linear(2.5) };
    let _ = relief::relief! { coarse: linear(10u32) };
}
