//! The one parser of the text forms. A pipeline text (`linear(10)+binary(5)`) is a grid with
//! one stage per slot, so both forms parse into a [`GridPattern`] with the same methods for
//! stages, arguments and values; the grid machinery ([`GridPattern::pipeline`],
//! [`GridPattern::expand`]) and the catalogue ([`resolve_stage`](super::resolve_stage))
//! then check it. The parser never panics: every input gives a pattern or a [`ParseError`]
//! that names the position, the offending token, what was expected and, for a misspelt name,
//! the nearest valid one.
//!
//! Errors come in reading order: a slot that is complete is checked against the catalogue
//! before a syntax error after it is reported.

use std::fmt;

use super::grid::{ArgPattern, GridPattern, OptionPattern, SlotPattern, StagePattern, ValuePattern};
use super::lex::{lex, Tok, Token};
use super::options::{key_named, Key};
use super::suggest::nearest;
use super::Slot;

/// Which text form is read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TextForm {
    /// `COARSE[+REFINE][+shadow=SHADOW][+ao=AO]`: one stage per slot, one value per
    /// parameter (`relief!` and `relief_shader!` take the same with the grid's punctuation).
    Pipeline,
    /// `SLOT: [STAGE, …]` entries with ranges and lists inside parameters, a `name:` entry
    /// and `#` comments (`relief_grid!` and grid files).
    Grid,
}

/// Why a text pipeline or grid (or a stage built in Rust) was rejected.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParseError {
    /// Where the offending token is: a character offset in a text, or whatever position the
    /// producer of a pattern used (the macros: an index into their table of spans).
    pub pos: usize,
    /// `(line, column)` of `pos`, both from 1, for a text of several lines (a grid text,
    /// see `ParseError::locate`); `None` for a pipeline text, whose errors name `pos`.
    pub line_column: Option<(u32, u32)>,
    /// The offending token (empty at the end of the input).
    pub token: String,
    /// What is wrong, in one sentence.
    pub message: String,
    /// The valid alternatives, when there is a short list.
    pub expected: Vec<String>,
    /// The nearest valid name, for a misspelling.
    pub suggestion: Option<String>,
}

impl ParseError {
    /// The error with its line and column in `text` (`pos` a character offset in it).
    pub(crate) fn locate(mut self, text: &str) -> Self {
        let (mut line, mut column) = (1u32, 1u32);
        for c in text.chars().take(self.pos) {
            if c == '\n' {
                line = line.saturating_add(1);
                column = 1;
            } else {
                column = column.saturating_add(1);
            }
        }
        self.line_column = Some((line, column));
        self
    }
}

impl fmt::Display for ParseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line_column {
            Some((line, column)) => write!(f, "line {line}, column {column}")?,
            None => write!(f, "at {}", self.pos)?,
        }
        if !self.token.is_empty() {
            write!(f, " (`{}`)", super::echo(&self.token))?;
        }
        write!(f, ": {}", self.message)?;
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
        line_column: None,
        token: token.to_string(),
        message: message.into(),
        expected: vec![],
        suggestion: None,
    }
}

/// The slot called `name`, or an error at `pos` that lists the slots and names the nearest.
pub fn slot_named(name: &str, pos: usize) -> Result<Slot, ParseError> {
    if let Some(s) = Slot::ALL.iter().copied().find(|s| s.name() == name) {
        return Ok(s);
    }
    let names: Vec<String> = Slot::ALL.iter().map(|s| s.name().to_string()).collect();
    let mut e = err(pos, name, format!("unknown slot `{name}`"));
    e.suggestion = nearest(name, names.iter().map(String::as_str)).map(str::to_string);
    e.expected = names;
    Err(e)
}

/// Nesting deeper than this is refused (no method needs more than two levels).
pub const MAX_DEPTH: usize = 8;

/// Parses a text of `form` into its pattern (positions are character offsets), checking the
/// slots that are complete before a syntax error after them is reported. The stages are
/// checked against the catalogue only by [`GridPattern::pipeline`] or
/// `GridPattern::expand`.
pub fn parse_pattern(text: &str, form: TextForm) -> Result<GridPattern, ParseError> {
    let mut p = Parser { toks: lex(text, form)?, i: 0, form, pattern: GridPattern::default() };
    let read = match form {
        TextForm::Pipeline => p.pipeline(),
        TextForm::Grid => p.grid(),
    };
    match read {
        Ok(()) => Ok(p.pattern),
        Err(e) => {
            p.pattern.resolve_slots()?;
            Err(e)
        }
    }
}

struct Parser {
    toks: Vec<Token>,
    i: usize,
    form: TextForm,
    /// What is read so far: the complete slots.
    pattern: GridPattern,
}

impl Parser {
    fn peek(&self) -> &Token {
        &self.toks[self.i.min(self.toks.len() - 1)]
    }
    /// Whether the next two tokens are `NAME =` (a named slot or argument); the name if so.
    fn named(&self) -> Option<(String, usize)> {
        match (&self.peek().tok, self.toks.get(self.i + 1).map(|t| &t.tok)) {
            (Tok::Ident(n), Some(Tok::Eq)) => Some((n.clone(), self.peek().pos)),
            _ => None,
        }
    }
    fn next(&mut self) -> Token {
        let t = self.peek().clone();
        if self.i < self.toks.len() {
            self.i += 1;
        }
        t
    }
    fn eat(&mut self, tok: &Tok) -> bool {
        if &self.peek().tok == tok {
            self.next();
            true
        } else {
            false
        }
    }
    fn unexpected(&self, what: &str) -> ParseError {
        let t = self.peek();
        if t.tok == Tok::End {
            err(t.pos, "", format!("the input ends where {what} was expected"))
        } else {
            err(t.pos, &t.text, format!("expected {what}"))
        }
    }
    /// Items up to `close`, separated by commas (a trailing comma is fine), the opening
    /// token already read.
    fn list<T>(
        &mut self,
        close: Tok,
        mut item: impl FnMut(&mut Self) -> Result<T, ParseError>,
    ) -> Result<Vec<T>, ParseError> {
        let mut items = Vec::new();
        loop {
            if self.eat(&close) {
                return Ok(items);
            }
            items.push(item(self)?);
            if !self.eat(&Tok::Comma) {
                if self.eat(&close) {
                    return Ok(items);
                }
                let c = if close == Tok::Close { ")" } else { "]" };
                return Err(self.unexpected(&format!("`,` or `{c}`")));
            }
        }
    }

    /// `COARSE[+REFINE][+shadow=SHADOW][+ao=AO]`, slots also named as `coarse=…`.
    fn pipeline(&mut self) -> Result<(), ParseError> {
        if self.peek().tok == Tok::End {
            return Err(err(0, "", "empty pipeline; expected a coarse stage such as linear(32)"));
        }
        let mut unnamed = 0;
        loop {
            let pos = self.peek().pos;
            let named = match self.named() {
                Some((n, npos)) => {
                    self.i += 2;
                    match key_named(&n, npos)? {
                        Key::Slot(s) => Some(s),
                        Key::Option(key) => {
                            let value = self.stage(0)?;
                            self.pattern.options.push(OptionPattern { key, pos: npos, values: vec![value] });
                            match self.peek().tok {
                                Tok::Plus => {
                                    self.next();
                                    continue;
                                }
                                Tok::End => break,
                                _ => return Err(self.unexpected("`+` or the end of the pipeline")),
                            }
                        }
                    }
                }
                None => None,
            };
            if !self.pattern.options.is_empty() {
                let t = self.toks[self.toks.iter().position(|t| t.pos >= pos).unwrap_or(0)].clone();
                return Err(err(t.pos, &t.text, "options come after the slots: write `+lod=…` at the end"));
            }
            let stage = self.stage(0)?;
            let slot = match named {
                Some(s) => s,
                None => {
                    unnamed += 1;
                    match unnamed {
                        1 => Slot::Coarse,
                        2 => Slot::Refine,
                        _ => {
                            return Err(err(
                                stage.pos,
                                &stage.name,
                                "a third stage needs its slot named: shadow=… or ao=…",
                            ))
                        }
                    }
                }
            };
            self.pattern.slots.push(SlotPattern { slot, pos, stages: vec![stage] });
            match self.peek().tok {
                Tok::Plus => {
                    self.next();
                }
                Tok::End => break,
                _ => return Err(self.unexpected("`+` or the end of the pipeline")),
            }
        }
        self.pattern.end = 0;
        Ok(())
    }

    /// Entries `SLOT: [STAGE, …]`, `SLOT: STAGE` and `name: "…"`, separated by commas or
    /// new lines.
    fn grid(&mut self) -> Result<(), ParseError> {
        let mut name_seen = false;
        loop {
            while self.eat(&Tok::Comma) {}
            let t = self.next();
            let key = match &t.tok {
                Tok::End => break,
                Tok::Ident(k) => k.clone(),
                _ => {
                    self.i -= 1;
                    return Err(self.unexpected("a slot such as `coarse:`"));
                }
            };
            if !self.eat(&Tok::Colon) {
                return Err(self.unexpected(&format!("`:` after `{key}`")));
            }
            if key == "name" {
                if name_seen {
                    return Err(err(t.pos, &t.text, "the grid's name is given twice"));
                }
                name_seen = true;
                let v = self.next();
                self.pattern.name = Some(match v.tok {
                    Tok::Str(s) | Tok::Ident(s) => s,
                    _ => {
                        self.i -= 1;
                        return Err(self.unexpected("the grid's name as a \"string\""));
                    }
                });
                continue;
            }
            let slot = match key_named(&key, t.pos)? {
                Key::Slot(s) => s,
                Key::Option(okey) => {
                    let values = if self.eat(&Tok::LBracket) {
                        self.list(Tok::RBracket, |p| p.stage(0))?
                    } else {
                        vec![self.stage(0)?]
                    };
                    self.pattern.options.push(OptionPattern { key: okey, pos: t.pos, values });
                    continue;
                }
            };
            let stages =
                if self.eat(&Tok::LBracket) { self.list(Tok::RBracket, |p| p.stage(0))? } else { vec![self.stage(0)?] };
            self.pattern.slots.push(SlotPattern { slot, pos: t.pos, stages });
        }
        self.pattern.end = self.toks.last().map_or(0, |t| t.pos);
        Ok(())
    }

    /// `NAME` or `NAME(ARG, …)`.
    fn stage(&mut self, depth: usize) -> Result<StagePattern, ParseError> {
        let t = self.next();
        let Tok::Ident(name) = t.tok else {
            self.i -= 1;
            return Err(self.unexpected("a stage name such as linear(32)"));
        };
        if depth > MAX_DEPTH {
            return Err(err(t.pos, &t.text, "stages nested too deeply"));
        }
        let args = if self.eat(&Tok::Open) {
            Some(self.list(Tok::Close, |p| {
                let name = p.named();
                if name.is_some() {
                    p.i += 2;
                }
                Ok(ArgPattern { name, value: p.value(depth)? })
            })?)
        } else {
            None
        };
        Ok(StagePattern { name, pos: t.pos, args })
    }

    /// A whole number, a name or a nested stage, and in a grid a range or a `[list]`.
    fn value(&mut self, depth: usize) -> Result<ValuePattern, ParseError> {
        let t = self.peek().clone();
        match t.tok {
            Tok::Int(start) => {
                self.next();
                if !self.eat(&Tok::RangeEq) {
                    return Ok(ValuePattern::Int { value: start, pos: t.pos, text: t.text });
                }
                let end = self.int("the range's last value, a whole number")?;
                let mut text = format!("{start}..={end}");
                let mut step = 1;
                if matches!(&self.peek().tok, Tok::Ident(w) if w == "step") {
                    self.next();
                    step = self.int("the range's step, a whole number")?;
                    text = format!("{text} step {step}");
                }
                Ok(ValuePattern::Range { start, end, step, pos: t.pos, text })
            }
            Tok::LBracket => {
                self.next();
                let items = self.list(Tok::RBracket, |p| p.value(depth))?;
                Ok(ValuePattern::List { items, pos: t.pos })
            }
            Tok::Ident(_) => Ok(ValuePattern::Stage(self.stage(depth + 1)?)),
            _ => Err(self.unexpected(match self.form {
                TextForm::Pipeline => "a parameter value (a whole number or a name)",
                TextForm::Grid => "a parameter value (a whole number, a range, a [list] or a name)",
            })),
        }
    }

    fn int(&mut self, what: &str) -> Result<u64, ParseError> {
        match self.peek().tok {
            Tok::Int(n) => {
                self.next();
                Ok(n)
            }
            _ => Err(self.unexpected(what)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Grid, Pipeline};
    use super::*;

    fn pipeline_err(text: &str) -> ParseError {
        text.parse::<Pipeline>().unwrap_err()
    }

    #[test]
    fn a_pipeline_is_a_grid_of_one_cell() {
        for (pipeline, grid) in [
            ("linear(10)+binary(5)", "coarse: linear(10), refine: binary(5)"),
            ("ao=cone_ratio+coarse=csm(15, sample=min4)", "ao: [cone_ratio]\ncoarse: csm(steps = 15, sample = min4)"),
            ("parallax+shadow=hard(linear(20))", "coarse: parallax, shadow: hard(20)"),
        ] {
            let p: Pipeline = pipeline.parse().unwrap();
            let g: Grid = grid.parse().unwrap();
            assert_eq!(g.cells(), std::slice::from_ref(&p), "{pipeline}");
            assert_eq!(parse_pattern(pipeline, TextForm::Pipeline).unwrap().expand().unwrap().cells(), [p]);
        }
        // A pattern of several cells is not one pipeline: an error at the slot, not a pick.
        let e =
            parse_pattern("coarse: linear(4)\nrefine: binary([4, 8])", TextForm::Grid).unwrap().pipeline().unwrap_err();
        assert_eq!((e.pos, e.token.as_str()), (18, "refine"), "{e}");
        assert!(e.message.contains("declares 2 stages"), "{e}");
    }

    #[test]
    fn errors_come_in_reading_order() {
        // A complete slot is checked before a later syntax error ...
        let e = pipeline_err("lnear(3)+");
        assert_eq!((e.pos, e.token.as_str()), (0, "lnear"), "{e}");
        let e = "coarse: [lnear]\nrefine: [binary(3)".parse::<Grid>().unwrap_err();
        assert_eq!((e.line_column, e.token.as_str()), (Some((1, 10)), "lnear"), "{e}");
        // ... and the syntax error is reported when the slots before it are valid.
        let e = pipeline_err("linear(3)+");
        assert!(e.message.contains("the input ends"), "{e}");
        assert_eq!(e.pos, 10);
        // A slot's own syntax comes before its stages: the stage being read is not checked.
        let e = pipeline_err("lnear(3");
        assert!(e.message.contains("`,` or `)`"), "{e}");
    }

    #[test]
    fn one_error_type_two_ways_to_name_the_place() {
        let e = pipeline_err("linear(10)+binary(0)");
        assert_eq!((e.pos, e.line_column), (18, None));
        assert!(e.to_string().starts_with("at 18 (`0`): step count 0"), "{e}");
        let e = "coarse: linear(10)\nrefine: binary(0)".parse::<Grid>().unwrap_err();
        assert_eq!((e.pos, e.line_column), (34, Some((2, 16))));
        assert!(e.to_string().starts_with("line 2, column 16 (`0`): step count 0"), "{e}");
    }

    #[test]
    fn trailing_commas_and_form_specific_punctuation() {
        // The stage grammar is shared: a trailing comma in the parameters is fine in both.
        assert_eq!("linear(10,)".parse::<Pipeline>().unwrap().to_string(), "linear(10)");
        assert_eq!("coarse: linear(10,)".parse::<Grid>().unwrap().cells()[0].to_string(), "linear(10)");
        // A range or a list is only a grid's; `+` only a pipeline's.
        for text in ["linear(1..=2)", "linear([1])"] {
            let e = pipeline_err(text);
            assert!(e.message.starts_with("unexpected character; a pipeline is made of"), "{text}: {e}");
        }
        let e = "coarse: linear(10)+binary(3)".parse::<Grid>().unwrap_err();
        assert_eq!((e.line_column, e.token.as_str()), (Some((1, 19)), "+"), "{e}");
    }
}
