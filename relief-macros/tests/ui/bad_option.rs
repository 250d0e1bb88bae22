// A misspelt pipeline option or option value: the error points at the word and suggests the
// nearest valid one; a level out of range names the range.
fn main() {
    let _ = relief::relief! { coarse: linear(32), lod: autp };
    let _ = relief::relief! { coarse: linear(32), lodd: auto };
    let _ = relief::relief! { coarse: linear(32), lod: level(16) };
    let _ = relief::relief_grid! { coarse: linear(32), silhouette: [none, clp] };
}
