//! The text form's parser. It never panics: every input gives a pipeline or a [`ParseError`]
//! that names the position, the offending token, what was expected and, for a misspelt
//! name, the nearest valid one.

use std::fmt;

use super::catalog::{catalog, method, ParamKind, MAX_STEPS};
use super::{Pipeline, Slot, StageSpec, Value};

/// Why a text pipeline (or a stage built in Rust) was rejected.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParseError {
    /// Character offset of the offending token in the input.
    pub pos: usize,
    /// The offending token (empty at the end of the input).
    pub token: String,
    /// What is wrong, in one sentence.
    pub message: String,
    /// The valid alternatives, when there is a short list.
    pub expected: Vec<String>,
    /// The nearest valid name, for a misspelling.
    pub suggestion: Option<String>,
}

impl fmt::Display for ParseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.token.is_empty() {
            write!(f, "at {}: {}", self.pos, self.message)?;
        } else {
            write!(f, "at {} (`{}`): {}", self.pos, self.token, self.message)?;
        }
        if !self.expected.is_empty() {
            write!(f, "; expected one of: {}", self.expected.join(", "))?;
        }
        if let Some(s) = &self.suggestion {
            write!(f, "; did you mean `{s}`?")?;
        }
        Ok(())
    }
}

impl std::error::Error for ParseError {}

pub(crate) fn err(pos: usize, token: &str, message: impl Into<String>) -> ParseError {
    ParseError {
        pos,
        token: token.to_string(),
        message: message.into(),
        expected: vec![],
        suggestion: None,
    }
}

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Ident(String),
    Int(u64),
    Open,
    Close,
    Comma,
    Eq,
    Plus,
    End,
}

#[derive(Clone, Debug)]
struct Token {
    tok: Tok,
    pos: usize,
    text: String,
}

fn lex(input: &str) -> Result<Vec<Token>, ParseError> {
    let chars: Vec<char> = input.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let start = i;
        let single = |tok| Token { tok, pos: start, text: c.to_string() };
        match c {
            c if c.is_whitespace() => {
                i += 1;
                continue;
            }
            '(' => out.push(single(Tok::Open)),
            ')' => out.push(single(Tok::Close)),
            ',' => out.push(single(Tok::Comma)),
            '=' => out.push(single(Tok::Eq)),
            '+' => out.push(single(Tok::Plus)),
            c if c.is_ascii_digit() => {
                while i < chars.len() && chars[i].is_ascii_alphanumeric() {
                    i += 1;
                }
                let text: String = chars[start..i].iter().collect();
                let n = text.parse::<u64>().map_err(|_| {
                    err(start, &text, "not a whole number (parameters are whole numbers or names)")
                })?;
                out.push(Token { tok: Tok::Int(n), pos: start, text });
                continue;
            }
            c if c.is_ascii_alphabetic() || c == '_' => {
                while i < chars.len() && (chars[i].is_ascii_alphanumeric() || chars[i] == '_') {
                    i += 1;
                }
                let text: String = chars[start..i].iter().collect();
                out.push(Token { tok: Tok::Ident(text.clone()), pos: start, text });
                continue;
            }
            '-' => {
                return Err(err(start, "-", "negative numbers are not allowed"));
            }
            other => {
                return Err(err(
                    start,
                    &other.to_string(),
                    "unexpected character; a pipeline is made of names, whole numbers, ( ) , = and +",
                ))
            }
        }
        i += 1;
    }
    out.push(Token { tok: Tok::End, pos: chars.len(), text: String::new() });
    Ok(out)
}

/// A raw argument before resolution against the catalogue.
#[derive(Debug)]
pub(crate) struct Arg {
    pub name: Option<(String, usize)>,
    pub value: ArgVal,
    pub pos: usize,
}

/// An argument's value before it is checked against its parameter.
#[derive(Debug)]
pub(crate) enum ArgVal {
    Int(u32),
    Word(String),
    /// A stage written in text, not yet resolved.
    Raw(RawStage),
    /// A stage built in Rust, already resolved.
    Spec(StageSpec),
}

impl ArgVal {
    fn text(&self) -> String {
        match self {
            ArgVal::Int(n) => n.to_string(),
            ArgVal::Word(w) => w.clone(),
            ArgVal::Raw(s) => s.name.clone(),
            ArgVal::Spec(s) => s.to_string(),
        }
    }
}

impl From<Value> for ArgVal {
    fn from(v: Value) -> Self {
        match v {
            Value::Int(n) => ArgVal::Int(n),
            Value::Word(w) => ArgVal::Word(w),
            Value::Stage(s) => ArgVal::Spec(*s),
        }
    }
}

/// A stage as written, before it is checked against the catalogue: what the text parser
/// produces and what the macros (relief-macros) build from Rust tokens, so that both are
/// checked by the same [`resolve_stage`].
///
/// Positions (`pos`) are whatever the producer uses to point back at the source: character
/// offsets in the text form, token numbers in the macros. Errors carry them unchanged in
/// [`ParseError::pos`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RawStage {
    /// The method's name.
    pub name: String,
    /// Where the name is.
    pub pos: usize,
    /// `None` for a bare name (`none`, `linear`), else the arguments in parentheses.
    pub args: Option<Vec<RawArg>>,
}

/// An argument's value as written.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum RawValue {
    /// A whole number (checked against the parameter's range on resolution).
    Int(u64),
    /// A name or a nested stage: a bare name (`args: None`) is a choice word or a stage at
    /// default parameters, whichever the parameter takes.
    Stage(RawStage),
}

/// One argument as written: `value` or `name = value`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RawArg {
    /// The parameter's name and where it is, for a named argument.
    pub name: Option<(String, usize)>,
    /// The value.
    pub value: RawValue,
    /// Where the value is.
    pub pos: usize,
    /// The value as written (the offending token in errors).
    pub text: String,
}

struct Parser {
    toks: Vec<Token>,
    i: usize,
}

/// Nesting deeper than this is refused (no method needs more than two levels).
const MAX_DEPTH: usize = 8;

impl Parser {
    fn peek(&self) -> &Token {
        &self.toks[self.i.min(self.toks.len() - 1)]
    }
    fn next(&mut self) -> Token {
        let t = self.peek().clone();
        if self.i < self.toks.len() {
            self.i += 1;
        }
        t
    }
    fn unexpected(&self, what: &str) -> ParseError {
        let t = self.peek();
        if t.tok == Tok::End {
            err(t.pos, "", format!("the input ends where {what} was expected"))
        } else {
            err(t.pos, &t.text, format!("expected {what}"))
        }
    }

    fn stage(&mut self, depth: usize) -> Result<RawStage, ParseError> {
        let t = self.next();
        let Tok::Ident(name) = t.tok else {
            self.i -= 1;
            return Err(self.unexpected("a stage name such as linear(32)"));
        };
        if depth > MAX_DEPTH {
            return Err(err(t.pos, &t.text, "stages nested too deeply"));
        }
        let args = if self.peek().tok == Tok::Open {
            self.next();
            let mut args = Vec::new();
            if self.peek().tok == Tok::Close {
                self.next();
            } else {
                loop {
                    args.push(self.arg(depth)?);
                    match self.peek().tok {
                        Tok::Comma => {
                            self.next();
                        }
                        Tok::Close => {
                            self.next();
                            break;
                        }
                        _ => return Err(self.unexpected("`,` or `)`")),
                    }
                }
            }
            Some(args)
        } else {
            None
        };
        Ok(RawStage { name, pos: t.pos, args })
    }

    fn arg(&mut self, depth: usize) -> Result<RawArg, ParseError> {
        let start = self.peek().clone();
        let mut name = None;
        if let (Tok::Ident(n), Some(Tok::Eq)) = (&start.tok, self.toks.get(self.i + 1).map(|t| &t.tok)) {
            name = Some((n.clone(), start.pos));
            self.i += 2;
        }
        let vt = self.peek().clone();
        let value = match vt.tok {
            Tok::Int(n) => {
                self.next();
                RawValue::Int(n)
            }
            Tok::Ident(_) => RawValue::Stage(self.stage(depth + 1)?),
            _ => return Err(self.unexpected("a parameter value (a whole number or a name)")),
        };
        Ok(RawArg { name, value, pos: vt.pos, text: vt.text })
    }
}

/// Parses a whole pipeline.
pub(crate) fn pipeline(input: &str) -> Result<Pipeline, ParseError> {
    let toks = lex(input)?;
    let mut p = Parser { toks, i: 0 };
    if p.peek().tok == Tok::End {
        return Err(err(0, "", "empty pipeline; expected a coarse stage such as linear(32)"));
    }
    let mut slots: [Option<StageSpec>; 4] = [None, None, None, None];
    let mut unnamed = 0;
    loop {
        // An explicit slot: `shadow=soft(30)`.
        let mut slot = None;
        let t = p.peek().clone();
        if let (Tok::Ident(n), Some(Tok::Eq)) = (&t.tok, p.toks.get(p.i + 1).map(|t| &t.tok)) {
            let Some(s) = Slot::ALL.iter().copied().find(|s| s.name() == n) else {
                let names: Vec<String> = Slot::ALL.iter().map(|s| s.name().to_string()).collect();
                let mut e = err(t.pos, n, format!("unknown slot `{n}`"));
                e.suggestion = nearest(n, names.iter().map(String::as_str));
                e.expected = names;
                return Err(e);
            };
            slot = Some(s);
            p.i += 2;
        }
        let raw = p.stage(0)?;
        let slot = match slot {
            Some(s) => s,
            None => {
                unnamed += 1;
                match unnamed {
                    1 => Slot::Coarse,
                    2 => Slot::Refine,
                    _ => {
                        return Err(err(
                            raw.pos,
                            &raw.name,
                            "a third stage needs its slot named: shadow=… or ao=…",
                        ))
                    }
                }
            }
        };
        let spec = resolve_raw(slot, raw)?;
        let idx = slot as usize;
        if slots[idx].is_some() {
            return Err(err(t.pos, &t.text, format!("the {slot} slot is given twice")));
        }
        slots[idx] = Some(spec);
        match p.peek().tok {
            Tok::Plus => {
                p.next();
            }
            Tok::End => break,
            _ => return Err(p.unexpected("`+` or the end of the pipeline")),
        }
    }
    let [c, r, s, a] = slots;
    let Some(coarse) = c else {
        return Err(err(0, "", "the pipeline has no coarse stage; start it with one such as linear(32)"));
    };
    Ok(Pipeline::new(
        coarse,
        r.unwrap_or_else(StageSpec::none),
        s.unwrap_or_else(StageSpec::none),
        a.unwrap_or_else(StageSpec::none),
    ))
}

/// Resolves a stage as written against the catalogue for `slot`, with the same checks as
/// the text form: the method exists in that slot, named and positional arguments land on
/// parameters, values are in range, defaults are filled in, nested stages are resolved, and
/// the combination can work. Errors carry the positions found in `raw`.
pub fn resolve_stage(slot: Slot, raw: RawStage) -> Result<StageSpec, ParseError> {
    resolve_raw(slot, raw)
}

fn resolve_raw(slot: Slot, raw: RawStage) -> Result<StageSpec, ParseError> {
    let mut args = Vec::new();
    for a in raw.args.unwrap_or_default() {
        let value = match a.value {
            RawValue::Int(n) => {
                let n = u32::try_from(n).map_err(|_| {
                    err(a.pos, &a.text, format!("{n} is too large; step counts are 1..={MAX_STEPS}"))
                })?;
                ArgVal::Int(n)
            }
            // A bare word: a choice, or a stage with default parameters; the parameter it
            // lands on decides.
            RawValue::Stage(s) if s.args.is_none() => ArgVal::Word(s.name),
            // A nested stage, resolved once the parameter's slot is known.
            RawValue::Stage(s) => ArgVal::Raw(s),
        };
        args.push(Arg { name: a.name, value, pos: a.pos });
    }
    resolve(slot, &raw.name, raw.pos, args)
}

fn method_names(slot: Slot) -> Vec<String> {
    catalog().iter().filter(|m| m.slot == slot).map(|m| m.name.to_string()).collect()
}

/// Resolves a method and its arguments against the catalogue: fills defaults, checks ranges
/// and choices, resolves nested stages.
pub(crate) fn resolve(slot: Slot, name: &str, pos: usize, args: Vec<Arg>) -> Result<StageSpec, ParseError> {
    let Some(def) = method(slot, name) else {
        let names = method_names(slot);
        let mut e = match catalog().iter().find(|m| m.name == name) {
            Some(other) => err(
                pos,
                name,
                format!("`{name}` is a {} stage, not a {slot} stage", other.slot),
            ),
            None => err(pos, name, format!("unknown {slot} stage `{name}`")),
        };
        e.suggestion = nearest(name, names.iter().map(String::as_str));
        e.expected = names;
        return Err(e);
    };
    if !def.implemented {
        return Err(err(pos, name, format!("the {slot} stage `{name}` is not implemented yet")));
    }
    let mut values: Vec<Option<Value>> = vec![None; def.params.len()];
    let mut next_positional = 0;
    for a in args {
        let idx = match &a.name {
            Some((pname, ppos)) => match def.params.iter().position(|p| p.name == pname) {
                Some(i) => i,
                None => {
                    let names: Vec<String> = def.params.iter().map(|p| p.name.to_string()).collect();
                    let msg = if names.is_empty() {
                        format!("`{name}` takes no parameters")
                    } else {
                        format!("`{name}` has no parameter `{pname}`")
                    };
                    let mut e = err(*ppos, pname, msg);
                    e.suggestion = nearest(pname, names.iter().map(String::as_str));
                    e.expected = names;
                    return Err(e);
                }
            },
            None => {
                let i = next_positional;
                next_positional += 1;
                if i >= def.params.len() {
                    let msg = match def.params.len() {
                        0 => format!("`{name}` takes no parameters"),
                        n => format!("`{name}` takes at most {n} parameter(s)"),
                    };
                    return Err(err(a.pos, &a.value.text(), msg));
                }
                i
            }
        };
        if values[idx].is_some() {
            return Err(err(
                a.pos,
                &a.value.text(),
                format!("parameter `{}` of `{name}` is given twice", def.params[idx].name),
            ));
        }
        let pdef = &def.params[idx];
        let text = a.value.text();
        let bad = |what: &str| {
            err(
                a.pos,
                &text,
                format!("{what} for `{}` of `{name}`: expected {}", pdef.name, pdef.kind.describe()),
            )
        };
        let v = match (&pdef.kind, a.value) {
            (ParamKind::Steps, ArgVal::Int(n)) | (ParamKind::StageOr(_), ArgVal::Int(n)) => {
                if n == 0 || n > MAX_STEPS {
                    return Err(err(
                        a.pos,
                        &n.to_string(),
                        format!(
                            "step count {n} for `{}` of `{name}` is out of range: allowed 1..={MAX_STEPS}",
                            pdef.name
                        ),
                    ));
                }
                Value::Int(n)
            }
            (ParamKind::Count { min, max }, ArgVal::Int(n)) => {
                if n < *min || n > *max {
                    return Err(err(
                        a.pos,
                        &n.to_string(),
                        format!("{n} for `{}` of `{name}` is out of range: allowed {min}..={max}", pdef.name),
                    ));
                }
                Value::Int(n)
            }
            (ParamKind::Choice(words), ArgVal::Word(w)) => {
                if !words.contains(&w.as_str()) {
                    let mut e = err(
                        a.pos,
                        &w,
                        format!("`{w}` is not a valid `{}` for `{name}`", pdef.name),
                    );
                    e.expected = words.iter().map(|s| s.to_string()).collect();
                    e.suggestion = nearest(&w, words.iter().copied());
                    return Err(e);
                }
                Value::Word(w)
            }
            (ParamKind::StageOr(inner), ArgVal::Word(w)) => {
                normalize_nested(resolve(*inner, &w, a.pos, vec![])?)
            }
            (ParamKind::StageOr(inner), ArgVal::Raw(raw)) => normalize_nested(resolve_raw(*inner, raw)?),
            (ParamKind::StageOr(inner), ArgVal::Spec(spec)) => {
                let args = spec.params.into_iter().map(|(n, v)| Arg { name: Some((n, a.pos)), value: v.into(), pos: a.pos }).collect();
                normalize_nested(resolve(*inner, &spec.name, a.pos, args)?)
            }
            (ParamKind::Steps, _) | (ParamKind::Count { .. }, _) => return Err(bad("not a whole number")),
            (ParamKind::Choice(_), _) => return Err(bad("not a name")),
        };
        values[idx] = Some(v);
    }
    let mut params = Vec::new();
    for (pdef, v) in def.params.iter().zip(values) {
        let v = match v.or_else(|| pdef.default.clone()) {
            Some(v) => v,
            None => {
                return Err(err(
                    pos,
                    name,
                    format!("`{name}` needs parameter `{}` ({})", pdef.name, pdef.kind.describe()),
                ))
            }
        };
        params.push((pdef.name.to_string(), v));
    }
    let spec = StageSpec { name: name.to_string(), params };
    check_combination(&spec, pos)?;
    Ok(spec)
}

/// A nested `linear(n)` is the same as `n`; a nested stage is kept otherwise.
fn normalize_nested(spec: StageSpec) -> Value {
    if spec.name == "linear" {
        Value::Int(spec.int("steps"))
    } else {
        Value::Stage(Box::new(spec))
    }
}

/// Parameter combinations that cannot work.
fn check_combination(spec: &StageSpec, pos: usize) -> Result<(), ParseError> {
    if spec.name == "linear_dynamic" && spec.int("min") > spec.int("max") {
        return Err(err(
            pos,
            &spec.name,
            format!(
                "`linear_dynamic` needs min <= max, got min {} and max {}",
                spec.int("min"),
                spec.int("max")
            ),
        ));
    }
    Ok(())
}

/// The candidate closest to `word` by edit distance, when it is close enough to be a typo.
pub(crate) fn nearest<'a>(word: &str, candidates: impl Iterator<Item = &'a str>) -> Option<String> {
    let mut best: Option<(usize, &str)> = None;
    for c in candidates {
        let d = edit_distance(word, c);
        if best.is_none_or(|(bd, _)| d < bd) {
            best = Some((d, c));
        }
    }
    let (d, c) = best?;
    let limit = (word.chars().count().max(c.len()) / 2).max(2);
    (d <= limit && d > 0).then(|| c.to_string())
}

fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for i in 1..=a.len() {
        let mut cur = vec![i; b.len() + 1];
        for j in 1..=b.len() {
            let sub = prev[j - 1] + usize::from(a[i - 1] != b[j - 1]);
            cur[j] = sub.min(prev[j] + 1).min(cur[j - 1] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}
