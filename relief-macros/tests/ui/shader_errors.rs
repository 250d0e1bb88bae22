// relief_shader! checks like relief!, and wants `mod NAME { … }`.
relief::relief_shader! {
    mod pom { coarse: linear(10), refine: binry(5) }
}

relief::relief_shader! {
    coarse: linear(10)
}

fn main() {}
