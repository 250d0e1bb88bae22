// A stage of another slot: the error names the slot the stage belongs to.
fn main() {
    let _ = relief::relief! { coarse: linear(10), refine: linear(5) };
    let _ = relief::relief! { coarse: binary(5) };
    let _ = relief::relief! { coarse: linear(10), shadow: hard(binary(4)) };
}
