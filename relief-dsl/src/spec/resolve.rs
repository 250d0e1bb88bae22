//! Resolution: a stage as written ([`RawStage`]) checked against the catalogue and turned
//! into a [`StageSpec`] with every parameter filled in. Every form reaches the catalogue
//! through here: the text forms, the macros, and [`StageSpec::new`] for stages built in Rust.

use super::catalog::{catalog, method, ParamKind, MAX_STEPS};
use super::parse::{err, ParseError};
use super::suggest::nearest;
use super::{Slot, StageSpec, Value};

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

/// A stage as written with one value per parameter, before it is checked against the
/// catalogue: what a [`StagePattern`](super::grid::StagePattern) expands to, whether the
/// text parser or the macros (relief-macros, from Rust tokens) built the pattern, so that
/// every form is checked by the same [`resolve_stage`].
///
/// Positions (`pos`) are whatever the producer uses to point back at the source: character
/// offsets in the text forms, indices into a table of spans in the macros. Errors carry them
/// unchanged in [`ParseError::pos`].
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

/// Resolves a stage as written against the catalogue for `slot`, with the same checks as
/// the text form: the method exists in that slot, named and positional arguments land on
/// parameters, values are in range, defaults are filled in, nested stages are resolved, and
/// the combination can work. Errors carry the positions found in `raw`.
pub fn resolve_stage(slot: Slot, raw: RawStage) -> Result<StageSpec, ParseError> {
    let mut args = Vec::new();
    for a in raw.args.unwrap_or_default() {
        let value = match a.value {
            RawValue::Int(n) => {
                let n = u32::try_from(n)
                    .map_err(|_| err(a.pos, &a.text, format!("{n} is too large; step counts are 1..={MAX_STEPS}")))?;
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
            Some(other) => err(pos, name, format!("`{name}` is a {} stage, not a {slot} stage", other.slot)),
            None => err(pos, name, format!("unknown {slot} stage `{name}`")),
        };
        e.suggestion = nearest(name, names.iter().map(String::as_str)).map(str::to_string);
        e.expected = names;
        return Err(e);
    };
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
                    e.suggestion = nearest(pname, names.iter().map(String::as_str)).map(str::to_string);
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
            err(a.pos, &text, format!("{what} for `{}` of `{name}`: expected {}", pdef.name, pdef.kind.describe()))
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
                    let mut e = err(a.pos, &w, format!("`{w}` is not a valid `{}` for `{name}`", pdef.name));
                    e.expected = words.iter().map(|s| s.to_string()).collect();
                    e.suggestion = nearest(&w, words.iter().copied()).map(str::to_string);
                    return Err(e);
                }
                Value::Word(w)
            }
            (ParamKind::StageOr(inner), ArgVal::Word(w)) => normalize_nested(resolve(*inner, &w, a.pos, vec![])?),
            (ParamKind::StageOr(inner), ArgVal::Raw(raw)) => normalize_nested(resolve_stage(*inner, raw)?),
            (ParamKind::StageOr(inner), ArgVal::Spec(spec)) => {
                let args = spec
                    .params
                    .into_iter()
                    .map(|(n, v)| Arg { name: Some((n, a.pos)), value: v.into(), pos: a.pos })
                    .collect();
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
    (def.check)(&spec).map_err(|message| err(pos, name, message))?;
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
