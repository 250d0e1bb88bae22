// An unknown stage name: the error points at the name and suggests the nearest valid one.
fn main() {
    let _ = relief::relief! { coarse: lnear(10), refine: binary(5) };
    let _ = relief::relief! { coarse: linear(10), refine: bianry(5) };
    let _ = relief::relief! { coarse: linear(10), corse: none };
}
