//! Declaring relief pipelines in Rust, checked while the program compiles.
//!
//! The macros parse their tokens into the same structures as relief-dsl's text forms and
//! check them with the same code ([`relief_dsl::spec::resolve_stage`]), so the macros and the
//! text can never disagree. A mistake is a compile error at the offending token: an unknown
//! stage (with the nearest valid name), a stage in the wrong slot, a bad or missing
//! parameter, a step count out of range, a combination that cannot work.
//!
//! Use them through the facade crate `relief` (`relief::relief!` …): the generated code names
//! its types as `::relief::dsl::…`, so the crate that uses a macro must depend on `relief`.
//!
//! # Syntax
//!
//! A pipeline is a comma-separated list of `SLOT: STAGE` for the slots `coarse` (required),
//! `refine`, `shadow` and `ao`, in any order; a left-out slot is `none`. A stage is written
//! as in the text form: `linear(10)`, `linear(steps = 10)`, `linear` (defaults),
//! `hard(linear(20))`. The pipeline options follow the slots as `OPTION: VALUE`
//! (`lod: auto`, `lod: level(2)`, `silhouette: clip`; see `relief_dsl::spec::options`), in a
//! grid also as lists (`lod: [zero, auto]`). Trailing commas are fine.
//!
//! ## `relief!` — a [`Pipeline`] value
//!
//! ```
//! use relief::{relief, Pipeline};
//! let p: Pipeline = relief! { coarse: linear(15), refine: binary(steps = 6), shadow: soft(30) };
//! assert_eq!(p, "linear(15)+binary(6)+shadow=soft(30)".parse().unwrap());
//! assert_eq!(p.to_string(), "linear(15)+binary(6)+shadow=soft(30)");
//! // The text form in a string literal is accepted (and checked) too.
//! assert_eq!(relief!("linear(15)+binary(6)+shadow=soft(30)"), p);
//! let p: Pipeline = relief! { coarse: linear(32), refine: binary(5), lod: auto };
//! assert_eq!(p.to_string(), "linear(32)+binary(5)+lod=auto");
//! ```
//!
//! ## `relief_shader!` — shaders built while compiling
//!
//! `relief_shader! { ATTRS VIS mod NAME { PIPELINE } … }` composes, validates and emits each
//! pipeline while the macro expands and declares a module of constants, so the program
//! needs no naga at run time:
//!
//! | item | what |
//! | --- | --- |
//! | `TEXT: &str` | the canonical text form |
//! | `WGSL: &str` | the whole module (render and probe entries) |
//! | `SPIRV: &[u32]` | the whole module as SPIR-V words |
//! | `GLSL_VERT`, `GLSL_FRAG`, `GLSL_COMP: &str` | GLSL 450 of the entries `vs_main`, `fs_main`, `probe` |
//! | `MAPS: &[&str]` | the maps the pipeline reads besides the height map |
//! | `fn pipeline() -> Pipeline` | the pipeline as data |
//!
//! ```
//! relief::relief_shader! {
//!     /// Linear search refined by binary search.
//!     pub mod pom { coarse: linear(10), refine: binary(5) }
//!     mod steep { coarse: linear(64), shadow: hard(16) }
//! }
//! assert_eq!(pom::TEXT, "linear(10)+binary(5)");
//! assert!(pom::WGSL.contains("fn coarse_linear("));
//! assert_eq!(pom::SPIRV[0], 0x0723_0203); // the SPIR-V magic number
//! assert!(pom::GLSL_FRAG.starts_with("#version 450"));
//! assert_eq!(steep::pipeline(), "linear(64)+shadow=hard(16)".parse().unwrap());
//! ```
//!
//! ## `relief_grid!` — a [`Grid`](relief_dsl::spec::Grid) of pipelines
//!
//! The grid form of relief-dsl (the same grammar as the grid files `relief sweep` reads):
//! a slot takes a list of stages `[…]` or one stage, a parameter may be a range
//! `a..=b` / `a..=b step s` or a list `[v, …]`, and an optional `name: "…"` names the grid.
//! The grid is the cartesian product in declaration order, coarse outermost.
//!
//! ```
//! let grid: relief::Grid = relief::relief_grid! {
//!     name: "small",
//!     coarse: [linear(8..=24 step 8), linear_dynamic(8, 32)],
//!     refine: [none, binary(3), interval([3, 6])],
//!     shadow: [none],
//! };
//! assert_eq!(grid.len(), 4 * 4);
//! assert_eq!(grid.name.as_deref(), Some("small"));
//! let first: Vec<String> = grid.iter().take(3).map(|p| p.to_string()).collect();
//! assert_eq!(first, ["linear(8)", "linear(8)+binary(3)", "linear(8)+interval(3)"]);
//! ```
//!
//! # Errors
//!
//! ```compile_fail
//! let p = relief::relief! { coarse: lnear(10) }; // unknown coarse stage `lnear`; did you mean `linear`?
//! ```
//! ```compile_fail
//! let p = relief::relief! { coarse: linear(10), refine: linear(5) }; // `linear` is a coarse stage, not a refine stage
//! ```
//! ```compile_fail
//! let p = relief::relief! { coarse: linear(0) }; // step count 0 … is out of range: allowed 1..=4096
//! ```
//! ```compile_fail
//! let p = relief::relief! { coarse: linear(32), lod: autp }; // unknown lod value `autp`; did you mean `auto`?
//! ```

#![warn(missing_docs)]

use proc_macro::TokenStream;
use proc_macro2::TokenStream as TokenStream2;
use quote::quote;
use relief_dsl::spec::{Curved, Lod, Pipeline, Silhouette, StageSpec, Value};
use syn::parse::{ParseStream, Parser};

mod syntax;

use relief_dsl::__private::TextForm;
use syntax::Spans;

/// The path of relief-dsl as the generated code sees it: through the facade.
fn dsl() -> TokenStream2 {
    quote!(::relief::dsl)
}

fn string(s: &str) -> TokenStream2 {
    quote!(::std::string::String::from(#s))
}

fn value_tokens(v: &Value) -> TokenStream2 {
    let k = dsl();
    match v {
        Value::Int(n) => quote!(#k::spec::Value::Int(#n)),
        Value::Word(w) => {
            let w = string(w);
            quote!(#k::spec::Value::Word(#w))
        }
        Value::Stage(s) => {
            let s = stage_tokens(s);
            quote!(#k::spec::Value::Stage(::std::boxed::Box::new(#s)))
        }
    }
}

fn stage_tokens(s: &StageSpec) -> TokenStream2 {
    let k = dsl();
    let name = string(&s.name);
    let params = s.params.iter().map(|(n, v)| {
        let n = string(n);
        let v = value_tokens(v);
        quote!((#n, #v))
    });
    quote!(#k::spec::StageSpec { name: #name, params: ::std::vec![#(#params),*] })
}

fn pipeline_tokens(p: &Pipeline) -> TokenStream2 {
    let k = dsl();
    let [c, r, s, a] = [&p.coarse, &p.refine, &p.shadow, &p.ao].map(stage_tokens);
    let (lod, sil, cur) = (lod_tokens(p.lod), silhouette_tokens(p.silhouette), curved_tokens(p.curved));
    quote!(#k::spec::Pipeline::new(#c, #r, #s, #a).with_lod(#lod).with_silhouette(#sil).with_curved(#cur))
}

fn curved_tokens(c: Option<Curved>) -> TokenStream2 {
    let k = dsl();
    match c {
        None => quote!(::std::option::Option::None),
        Some(Curved::None) => quote!(::std::option::Option::Some(#k::spec::Curved::None)),
        Some(Curved::Quadric) => quote!(::std::option::Option::Some(#k::spec::Curved::Quadric)),
        Some(Curved::Prism) => quote!(::std::option::Option::Some(#k::spec::Curved::Prism)),
    }
}

fn lod_tokens(lod: Lod) -> TokenStream2 {
    let k = dsl();
    match lod {
        Lod::Zero => quote!(#k::spec::Lod::Zero),
        Lod::Auto => quote!(#k::spec::Lod::Auto),
        Lod::Level(n) => quote!(#k::spec::Lod::Level(#n)),
    }
}

fn silhouette_tokens(s: Silhouette) -> TokenStream2 {
    let k = dsl();
    match s {
        Silhouette::None => quote!(#k::spec::Silhouette::None),
        Silhouette::Clip => quote!(#k::spec::Silhouette::Clip),
    }
}

/// Parses and checks a pipeline body (`SLOT: STAGE, …`, or the text form in a string
/// literal).
fn pipeline_body(input: ParseStream) -> syn::Result<Pipeline> {
    if input.peek(syn::LitStr) && input.peek2(syn::parse::End) {
        let lit: syn::LitStr = input.parse()?;
        return lit.value().parse::<Pipeline>().map_err(|e| syn::Error::new(lit.span(), e.to_string()));
    }
    let mut spans = Spans::default();
    let pattern = syntax::body(input, TextForm::Pipeline, &mut spans)?;
    if !pattern.slots.iter().any(|s| s.slot == relief_dsl::Slot::Coarse) {
        return Err(syn::Error::new(
            proc_macro2::Span::call_site(),
            "the pipeline has no coarse stage; add one such as `coarse: linear(32)`",
        ));
    }
    pattern.pipeline().map_err(|e| spans.error(&e))
}

/// A [`Pipeline`] declared in Rust and checked at
/// compile time: `relief!{ coarse: linear(15), refine: binary(6), shadow: soft(30) }`.
/// See the [crate docs](crate) for the syntax.
#[proc_macro]
pub fn relief(input: TokenStream) -> TokenStream {
    match pipeline_body.parse(input) {
        Ok(p) => pipeline_tokens(&p).into(),
        Err(e) => e.to_compile_error().into(),
    }
}

/// A [`Grid`](relief_dsl::spec::Grid) declared in Rust and checked at
/// compile time: `relief_grid!{ coarse: [linear(5..=35 step 5)], refine: [none, binary(3)] }`.
/// See the [crate docs](crate) for the syntax.
#[proc_macro]
pub fn relief_grid(input: TokenStream) -> TokenStream {
    let mut spans = Spans::default();
    let parsed = (|input: ParseStream| syntax::body(input, TextForm::Grid, &mut spans)).parse(input);
    let pattern = match parsed {
        Ok(p) => p,
        Err(e) => return e.to_compile_error().into(),
    };
    let checked = pattern.resolve().and_then(|l| Ok((l, pattern.resolve_options()?)));
    let (lists, (lods, sils, curved)) = match checked {
        Ok(l) => l,
        Err(e) => return spans.error(&e).to_compile_error().into(),
    };
    grid_tokens(pattern.name.as_deref(), &lists, &lods, &sils, &curved).into()
}

fn grid_tokens(
    name: Option<&str>,
    lists: &[Vec<StageSpec>; 4],
    lods: &[Lod],
    sils: &[Silhouette],
    curved: &[Option<Curved>],
) -> TokenStream2 {
    let k = dsl();
    let name = match name {
        Some(n) => {
            let n = string(n);
            quote!(::std::option::Option::Some(#n))
        }
        None => quote!(::std::option::Option::None),
    };
    let [c, r, s, a] = lists.each_ref().map(|l| {
        let stages = l.iter().map(stage_tokens);
        quote!(::std::vec![#(#stages),*])
    });
    let lods = lods.iter().copied().map(lod_tokens);
    let sils = sils.iter().copied().map(silhouette_tokens);
    let curved = curved.iter().copied().map(curved_tokens);
    quote!(#k::spec::Grid::product_with_options(#name, [#c, #r, #s, #a], &[#(#lods),*], &[#(#sils),*], &[#(#curved),*]))
}

/// Shaders built, validated and emitted at compile time, embedded as constants:
/// `relief_shader!{ pub mod pom { coarse: linear(10), refine: binary(5) } }`.
/// See the [crate docs](crate) for the items of the generated module.
#[proc_macro]
pub fn relief_shader(input: TokenStream) -> TokenStream {
    match shader_modules.parse(input) {
        Ok(ts) => ts.into(),
        Err(e) => e.to_compile_error().into(),
    }
}

fn shader_modules(input: ParseStream) -> syn::Result<TokenStream2> {
    let mut out = TokenStream2::new();
    if input.is_empty() {
        return Err(input.error("expected `mod NAME { coarse: …, refine: … }`"));
    }
    while !input.is_empty() {
        let attrs = input.call(syn::Attribute::parse_outer)?;
        let vis: syn::Visibility = input.parse()?;
        input
            .parse::<syn::Token![mod]>()
            .map_err(|e| syn::Error::new(e.span(), "expected `mod NAME { coarse: …, refine: … }`"))?;
        let name: syn::Ident = input.parse()?;
        let content;
        syn::braced!(content in input);
        let p = pipeline_body(&content)?;
        out.extend(shader_module(&attrs, &vis, &name, &p)?);
    }
    Ok(out)
}

fn shader_module(
    attrs: &[syn::Attribute],
    vis: &syn::Visibility,
    name: &syn::Ident,
    p: &Pipeline,
) -> syn::Result<TokenStream2> {
    let k = dsl();
    let out = relief_dsl::emit::emit(p)
        .map_err(|e| syn::Error::new(name.span(), format!("pipeline `{p}` does not compile: {e}")))?;
    let glsl =
        |suffix: &str| -> syn::Result<String> {
            out.glsl.iter().find(|(s, _)| *s == suffix).map(|(_, src)| src.clone()).ok_or_else(|| {
                syn::Error::new(name.span(), format!("pipeline `{p}`: no GLSL for the `{suffix}` entry"))
            })
        };
    let (vert, frag, comp) = (glsl("vert")?, glsl("frag")?, glsl("comp")?);
    let text = p.to_string();
    let wgsl = &out.wgsl;
    let words = &out.spirv;
    let maps: Vec<&str> = p.required_maps().iter().map(|m| m.name()).collect();
    let build = pipeline_tokens(p);
    let doc = format!("Shaders of `{text}`, built while compiling.");
    let has_doc = attrs.iter().any(|a| a.path().is_ident("doc"));
    let doc = if has_doc { quote!() } else { quote!(#[doc = #doc]) };
    Ok(quote! {
        #doc
        #(#attrs)*
        #vis mod #name {
            /// The pipeline's canonical text form.
            pub const TEXT: &str = #text;
            /// The whole module (render entries `vs_main`, `fs_main`; probe entry `probe`) as WGSL.
            pub const WGSL: &str = #wgsl;
            /// The whole module as SPIR-V words.
            pub const SPIRV: &[u32] = &[#(#words),*];
            /// GLSL 450 of the vertex entry `vs_main`.
            pub const GLSL_VERT: &str = #vert;
            /// GLSL 450 of the fragment entry `fs_main`.
            pub const GLSL_FRAG: &str = #frag;
            /// GLSL 450 of the compute (probe) entry `probe`.
            pub const GLSL_COMP: &str = #comp;
            /// The maps the pipeline reads besides the height map (names as in `relief maps`).
            pub const MAPS: &[&str] = &[#(#maps),*];
            /// The pipeline as data.
            pub fn pipeline() -> #k::spec::Pipeline {
                #build
            }
        }
    })
}
