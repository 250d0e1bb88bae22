// Combinations that cannot work, and slots given wrongly.
fn main() {
    let _ = relief::relief! { coarse: linear_dynamic(32, 8) };
    let _ = relief::relief! { coarse: linear_dynamic(max = 4) };
    let _ = relief::relief! { coarse: linear(10), coarse: parallax };
    let _ = relief::relief! { refine: binary(5) };
}
