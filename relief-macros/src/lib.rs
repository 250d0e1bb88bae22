//! placeholder
use proc_macro::TokenStream;
#[proc_macro]
pub fn relief(_t: TokenStream) -> TokenStream { TokenStream::new() }
