// Step counts outside 1..=4096.
fn main() {
    let _ = relief::relief! { coarse: linear(0) };
    let _ = relief::relief! { coarse: linear(10), refine: binary(5000) };
    let _ = relief::relief! { coarse: linear(10), shadow: soft(steps = 99999999999) };
    let _ = relief::relief! { coarse: linear(-3) };
}
