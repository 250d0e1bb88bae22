//! Rust tokens → relief-dsl's grid patterns, the structures the text grid parser also
//! produces. Positions in the patterns are indices into a table of spans, so that every
//! error relief-dsl reports (it carries the position unchanged) maps back to its token.

use proc_macro2::{Span, TokenStream};
use relief_dsl::__private::{key_named, Key, ParseError, TextForm, MAX_DEPTH};
use relief_dsl::__private::{ArgPattern, GridPattern, OptionPattern, SlotPattern, StagePattern, ValuePattern};
use syn::ext::IdentExt;
use syn::parse::ParseStream;
use syn::spanned::Spanned;
use syn::{Ident, LitInt, LitStr, Token};

/// The spans behind pattern positions: `(first token, last token)` of each.
#[derive(Default)]
pub struct Spans(Vec<(Span, Span)>);

impl Spans {
    pub fn push(&mut self, first: Span, last: Span) -> usize {
        self.0.push((first, last));
        self.0.len() - 1
    }
    pub fn one(&mut self, span: Span) -> usize {
        self.push(span, span)
    }

    /// A compile error for `e` at the token(s) its position names.
    pub fn error(&self, e: &ParseError) -> syn::Error {
        let (first, last) = self.0.get(e.pos).copied().unwrap_or((Span::call_site(), Span::call_site()));
        let mut msg = e.message.clone();
        // A valid name in the wrong slot: the message says where it belongs; a look-alike of
        // this slot would only mislead.
        let wrong_slot =
            e.message.contains(" stage, not a ") && relief_dsl::spec::catalog().iter().any(|m| m.name == e.token);
        match &e.suggestion {
            Some(s) if !wrong_slot => msg.push_str(&format!("; did you mean `{s}`?")),
            // Short lists only (slots, choices): the catalogue's longer lists grow.
            None if !e.expected.is_empty() && e.expected.len() <= 6 => {
                msg.push_str(&format!(" (expected one of: {})", e.expected.join(", ")))
            }
            _ => {}
        }
        spanned_error(first, last, msg)
    }
}

/// An error covering the tokens from `first` to `last` (on stable Rust a span cannot be
/// joined, but an error can still start at one token and end at another).
pub fn spanned_error(first: Span, last: Span, msg: impl std::fmt::Display) -> syn::Error {
    let mut ts = TokenStream::new();
    ts.extend([proc_macro2::TokenTree::Ident(Ident::new("a", first))]);
    ts.extend([proc_macro2::TokenTree::Ident(Ident::new("b", last))]);
    syn::Error::new_spanned(ts, msg)
}

/// Parses a whole body: `SLOT: STAGE, …` and `OPTION: VALUE, …` (and, for grids,
/// `SLOT: [STAGE, …]`, `OPTION: [VALUE, …]`, `name: "…"`).
pub fn body(input: ParseStream, form: TextForm, spans: &mut Spans) -> syn::Result<GridPattern> {
    let mut g = GridPattern::default();
    let mut name_seen = false;
    while !input.is_empty() {
        let key = input
            .call(Ident::parse_any)
            .map_err(|e| syn::Error::new(e.span(), "expected a slot such as `coarse: linear(32)`"))?;
        let key_str = key.to_string();
        input.parse::<Token![:]>().map_err(|e| syn::Error::new(e.span(), format!("expected `:` after `{key_str}`")))?;
        if key_str == "name" && form == TextForm::Grid {
            if name_seen {
                return Err(syn::Error::new(key.span(), "the grid's name is given twice"));
            }
            name_seen = true;
            g.name = Some(if input.peek(LitStr) {
                input.parse::<LitStr>()?.value()
            } else {
                input
                    .call(Ident::parse_any)
                    .map_err(|e| syn::Error::new(e.span(), "expected the grid's name as a \"string\""))?
                    .to_string()
            });
        } else {
            let pos = spans.one(key.span());
            let key = key_named(&key_str, pos).map_err(|e| spans.error(&e))?;
            let stages = if input.peek(syn::token::Bracket) {
                let content;
                let bracket = syn::bracketed!(content in input);
                if form == TextForm::Pipeline {
                    return Err(syn::Error::new(
                        bracket.span.join(),
                        "a list of stages declares several pipelines: use `relief_grid!`",
                    ));
                }
                let mut stages = Vec::new();
                while !content.is_empty() {
                    stages.push(stage(&content, form, spans, 0)?);
                    if content.is_empty() {
                        break;
                    }
                    content.parse::<Token![,]>()?;
                }
                stages
            } else {
                vec![stage(input, form, spans, 0)?]
            };
            match key {
                Key::Slot(slot) => g.slots.push(SlotPattern { slot, pos, stages }),
                Key::Option(key) => g.options.push(OptionPattern { key, pos, values: stages }),
            }
        }
        if input.is_empty() {
            break;
        }
        input.parse::<Token![,]>().map_err(|e| syn::Error::new(e.span(), "expected `,` between slots"))?;
    }
    g.end = spans.one(Span::call_site());
    Ok(g)
}

fn stage(input: ParseStream, form: TextForm, spans: &mut Spans, depth: usize) -> syn::Result<StagePattern> {
    let name = input
        .call(Ident::parse_any)
        .map_err(|e| syn::Error::new(e.span(), "expected a stage name such as `linear(32)`"))?;
    if depth > MAX_DEPTH {
        return Err(syn::Error::new(name.span(), "stages nested too deeply"));
    }
    let pos = spans.one(name.span());
    let args = if input.peek(syn::token::Paren) {
        let content;
        syn::parenthesized!(content in input);
        let mut args = Vec::new();
        while !content.is_empty() {
            let mut pname = None;
            if (content.peek(Ident::peek_any)) && content.peek2(Token![=]) && !content.peek2(Token![==]) {
                let n = content.call(Ident::parse_any)?;
                content.parse::<Token![=]>()?;
                pname = Some((n.to_string(), spans.one(n.span())));
            }
            args.push(ArgPattern { name: pname, value: value(&content, form, spans, depth)? });
            if content.is_empty() {
                break;
            }
            content.parse::<Token![,]>().map_err(|e| syn::Error::new(e.span(), "expected `,` or `)`"))?;
        }
        Some(args)
    } else {
        None
    };
    Ok(StagePattern { name: name.to_string(), pos, args })
}

fn int(input: ParseStream) -> syn::Result<(u64, LitInt)> {
    let lit: LitInt = input.parse()?;
    if lit.base10_digits().starts_with('-') {
        return Err(syn::Error::new(lit.span(), "negative numbers are not allowed"));
    }
    if !lit.suffix().is_empty() {
        return Err(syn::Error::new(lit.span(), "write parameters as plain whole numbers, without a type suffix"));
    }
    let n = lit.base10_parse::<u64>()?;
    Ok((n, lit))
}

fn value(input: ParseStream, form: TextForm, spans: &mut Spans, depth: usize) -> syn::Result<ValuePattern> {
    if input.peek(LitInt) {
        let (start, lit) = int(input)?;
        if input.peek(Token![..=]) || input.peek(Token![..]) {
            let dots = input.parse::<syn::RangeLimits>()?;
            if let syn::RangeLimits::HalfOpen(d) = dots {
                return Err(syn::Error::new(d.span(), "ranges are inclusive: write `a..=b` or `a..=b step s`"));
            }
            let (end, end_lit) =
                int(input).map_err(|e| syn::Error::new(e.span(), "expected the range's last value, a whole number"))?;
            let mut last = end_lit.span();
            let mut text = format!("{start}..={end}");
            let mut step = 1;
            if input.peek(Ident) && input.fork().parse::<Ident>().is_ok_and(|i| i == "step") {
                input.parse::<Ident>()?;
                let (s, s_lit) =
                    int(input).map_err(|e| syn::Error::new(e.span(), "expected the range's step, a whole number"))?;
                step = s;
                last = s_lit.span();
                text = format!("{text} step {s}");
            }
            if form == TextForm::Pipeline {
                return Err(spanned_error(lit.span(), last, "a range declares several pipelines: use `relief_grid!`"));
            }
            let pos = spans.push(lit.span(), last);
            return Ok(ValuePattern::Range { start, end, step, pos, text });
        }
        let pos = spans.one(lit.span());
        return Ok(ValuePattern::Int { value: start, pos, text: lit.base10_digits().to_string() });
    }
    if input.peek(syn::token::Bracket) {
        let content;
        let bracket = syn::bracketed!(content in input);
        if form == TextForm::Pipeline {
            return Err(syn::Error::new(
                bracket.span.join(),
                "a list of values declares several pipelines: use `relief_grid!`",
            ));
        }
        let pos = spans.one(bracket.span.open());
        let mut items = Vec::new();
        while !content.is_empty() {
            items.push(value(&content, form, spans, depth)?);
            if content.is_empty() {
                break;
            }
            content.parse::<Token![,]>().map_err(|e| syn::Error::new(e.span(), "expected `,` or `]`"))?;
        }
        return Ok(ValuePattern::List { items, pos });
    }
    if input.peek(Ident::peek_any) {
        return Ok(ValuePattern::Stage(stage(input, form, spans, depth + 1)?));
    }
    if input.peek(Token![-]) {
        let m: Token![-] = input.parse()?;
        return Err(syn::Error::new(m.span, "negative numbers are not allowed"));
    }
    if input.peek(syn::LitFloat) {
        let f: syn::LitFloat = input.parse()?;
        return Err(syn::Error::new(f.span(), "not a whole number (parameters are whole numbers or names)"));
    }
    Err(input.error("expected a parameter value (a whole number or a name)"))
}
