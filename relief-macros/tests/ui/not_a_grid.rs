// Lists and ranges declare several pipelines: they belong in relief_grid!.
fn main() {
    let _ = relief::relief! { coarse: [linear(10), parallax] };
    let _ = relief::relief! { coarse: linear(5..=35 step 5) };
    let _ = relief::relief! { coarse: linear([8, 16]) };
}
