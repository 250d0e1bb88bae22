//! Grids: many pipelines declared at once, as the cartesian product of the stages listed for
//! each slot.
//!
//! # Grid form
//!
//! The text that `relief sweep` reads and the body of `relief_grid!` (relief-macros) share
//! one grammar:
//!
//! ```text
//! # a comment runs to the end of the line
//! name: "small"                                  # optional
//! coarse: [linear(5..=35 step 5), linear_dynamic(8, 32)]
//! refine: [none, binary(3), interval([3, 6])]
//! shadow: none                                   # one stage needs no brackets
//! ```
//!
//! - An entry is `SLOT: [STAGE, …]` or `SLOT: STAGE`, for the slots `coarse`, `refine`,
//!   `shadow` and `ao`, plus an optional `name: "…"`. Entries are separated by new lines or
//!   commas (or both); trailing commas are fine.
//! - A stage is written as in the text form (`linear(10)`, `linear(steps = 10)`,
//!   `hard(linear(20))`), except that any parameter may be a **range** `a..=b` or
//!   `a..=b step s` (inclusive), or a **list** `[v1, v2, …]`. Such a stage stands for one
//!   stage per value, and a stage with several of them for their cartesian product (first
//!   parameter outermost).
//! - The grid is the product of the slots' lists, coarse outermost, then refine, shadow, ao;
//!   a slot left out is `none`, except coarse, which must be given. A stage that occurs
//!   twice in a slot's list (after expansion and resolution) is kept once, at its first place.
//!
//! Every stage is checked against the catalogue exactly like the text form
//! ([`resolve_stage`]), so a grid holds only valid pipelines; errors name the line, the
//! column and the offending token.
//!
//! ```
//! use relief_dsl::spec::Grid;
//! let grid: Grid = "coarse: [linear(8..=16 step 8), parallax]\nrefine: [none, binary(3)]".parse()?;
//! let texts: Vec<String> = grid.iter().map(|p| p.to_string()).collect();
//! assert_eq!(texts, ["linear(8)", "linear(8)+binary(3)", "linear(16)", "linear(16)+binary(3)",
//!                    "parallax", "parallax+binary(3)"]);
//! let err = "coarse: [linear(8), lnear(4)]".parse::<Grid>().unwrap_err();
//! assert_eq!(err.line_column, Some((1, 21)));
//! assert!(err.to_string().contains("did you mean `linear`"));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::collections::HashSet;
use std::str::FromStr;

use super::options::{resolve_option, Curved, Lod, OptionKey, OptionValue, Silhouette};
use super::parse::{err, parse_pattern, ParseError, TextForm};
use super::resolve::{resolve_stage, RawArg, RawStage, RawValue};
use super::{Pipeline, Slot, StageSpec};

/// The most pipelines one grid may hold (and the most stages one stage pattern may expand
/// to): a guard against a typo such as `1..=4096 step 1` in several places.
pub const MAX_CELLS: usize = 100_000;

/// A list of pipelines in declaration order: what a grid file or `relief_grid!` declares.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Grid {
    /// The grid's name, from its `name:` entry.
    pub name: Option<String>,
    cells: Vec<Pipeline>,
}

impl Grid {
    /// A grid of the given pipelines, in this order.
    pub fn new(name: Option<String>, cells: Vec<Pipeline>) -> Self {
        Grid { name, cells }
    }
    /// The cartesian product of the stages of each slot (`lists` indexed like [`Slot::ALL`]),
    /// coarse outermost, then refine, shadow, ao. The stages are taken as they are: build
    /// them with [`StageSpec::new`] or [`resolve_stage`] to have them checked.
    pub fn product(name: Option<String>, lists: [Vec<StageSpec>; 4]) -> Self {
        Grid::product_with_options(name, lists, &[Lod::Zero], &[Silhouette::None], &[None])
    }
    /// [`Grid::product`] with the pipeline options as further axes, innermost (after ao):
    /// lod, then silhouette, then curved, so that the variants of one pipeline stand next to
    /// each other.
    pub fn product_with_options(
        name: Option<String>,
        lists: [Vec<StageSpec>; 4],
        lods: &[Lod],
        silhouettes: &[Silhouette],
        curved: &[Option<Curved>],
    ) -> Self {
        let [coarse, r, s, a] = lists;
        let n = coarse.len() * r.len() * s.len() * a.len() * lods.len() * silhouettes.len() * curved.len();
        let mut cells = Vec::with_capacity(n);
        for c in &coarse {
            for r in &r {
                for s in &s {
                    for a in &a {
                        for &lod in lods {
                            for &sil in silhouettes {
                                for &cur in curved {
                                    let p = Pipeline::new(c.clone(), r.clone(), s.clone(), a.clone());
                                    cells.push(p.with_lod(lod).with_silhouette(sil).with_curved(cur));
                                }
                            }
                        }
                    }
                }
            }
        }
        Grid { name, cells }
    }
    /// The number of pipelines.
    pub fn len(&self) -> usize {
        self.cells.len()
    }
    /// Whether the grid holds no pipeline (never the case for a parsed grid).
    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }
    /// The pipelines in declaration order.
    pub fn iter(&self) -> std::slice::Iter<'_, Pipeline> {
        self.cells.iter()
    }
    /// The pipelines as a slice.
    pub fn cells(&self) -> &[Pipeline] {
        &self.cells
    }
    /// The pipelines, by value.
    pub fn into_cells(self) -> Vec<Pipeline> {
        self.cells
    }
}

impl IntoIterator for Grid {
    type Item = Pipeline;
    type IntoIter = std::vec::IntoIter<Pipeline>;
    fn into_iter(self) -> Self::IntoIter {
        self.cells.into_iter()
    }
}

impl<'a> IntoIterator for &'a Grid {
    type Item = &'a Pipeline;
    type IntoIter = std::slice::Iter<'a, Pipeline>;
    fn into_iter(self) -> Self::IntoIter {
        self.cells.iter()
    }
}

impl FromStr for Grid {
    type Err = ParseError;
    /// Parses a grid text; errors carry their line and column ([`ParseError::line_column`]).
    fn from_str(s: &str) -> Result<Self, ParseError> {
        parse_pattern(s, TextForm::Grid).and_then(|p| p.expand()).map_err(|e| e.locate(s))
    }
}

// ---------------------------------------------------------------------------------------
// Patterns: a grid as written, before expansion. The text parser (`spec::parse`) and
// relief-macros both build these, with their own positions (character offsets, span indices).

/// A grid as written: the parsed form of a grid text, of a pipeline text (one stage per
/// slot) or of a macro body.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct GridPattern {
    /// The `name:` entry.
    pub name: Option<String>,
    /// The slot entries in the order written.
    pub slots: Vec<SlotPattern>,
    /// The position to report for what is missing at the end (no coarse slot).
    pub end: usize,
    /// The pipeline-option entries (`lod: [zero, auto]`, `+lod=auto`) in the order written.
    pub options: Vec<OptionPattern>,
}

/// `OPTION: [VALUE, …]`: the values are written like stages (`auto`, `level(1..=3)`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OptionPattern {
    /// The option.
    pub key: OptionKey,
    /// Where the option's name is.
    pub pos: usize,
    /// The values listed, in order.
    pub values: Vec<StagePattern>,
}

/// `SLOT: [STAGE, …]`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SlotPattern {
    /// The slot.
    pub slot: Slot,
    /// Where the slot's name is.
    pub pos: usize,
    /// The stages listed, in order.
    pub stages: Vec<StagePattern>,
}

/// A stage whose parameters may hold ranges and lists.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StagePattern {
    /// The method's name.
    pub name: String,
    /// Where the name is.
    pub pos: usize,
    /// `None` for a bare name.
    pub args: Option<Vec<ArgPattern>>,
}

/// `value` or `name = value`, where the value may be a range or a list.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ArgPattern {
    /// The parameter's name and where it is.
    pub name: Option<(String, usize)>,
    /// The value or values.
    pub value: ValuePattern,
}

/// A parameter value that may stand for several.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ValuePattern {
    /// One whole number.
    Int {
        /// The number.
        value: u64,
        /// Where it is.
        pos: usize,
        /// As written.
        text: String,
    },
    /// `start..=end step step`, inclusive (`step` 1 when not written).
    Range {
        /// The first value.
        start: u64,
        /// The upper bound, inclusive: the values are `start`, `start + step`, … up to it.
        end: u64,
        /// The distance between values.
        step: u64,
        /// Where the range is.
        pos: usize,
        /// As written.
        text: String,
    },
    /// `[v1, v2, …]`.
    List {
        /// The values.
        items: Vec<ValuePattern>,
        /// Where the list is.
        pos: usize,
    },
    /// A name or a nested stage (which may itself hold ranges and lists).
    Stage(StagePattern),
}

impl ValuePattern {
    fn expand(&self, out: &mut Vec<(RawValue, usize, String)>) -> Result<(), ParseError> {
        match self {
            ValuePattern::Int { value, pos, text } => out.push((RawValue::Int(*value), *pos, text.clone())),
            ValuePattern::Range { start, end, step, pos, text } => {
                if *step == 0 {
                    return Err(err(*pos, text, "a range's step must be at least 1"));
                }
                if start > end {
                    return Err(err(*pos, text, format!("empty range: {start} is greater than {end}")));
                }
                let count = (end - start) / step + 1;
                if count > MAX_CELLS as u64 {
                    return Err(err(*pos, text, format!("the range has {count} values, more than {MAX_CELLS}")));
                }
                let mut v = *start;
                loop {
                    out.push((RawValue::Int(v), *pos, v.to_string()));
                    match v.checked_add(*step) {
                        Some(n) if n <= *end => v = n,
                        _ => break,
                    }
                }
            }
            ValuePattern::List { items, pos } => {
                if items.is_empty() {
                    return Err(err(*pos, "[", "an empty list; a list needs at least one value"));
                }
                for item in items {
                    item.expand(out)?;
                }
            }
            ValuePattern::Stage(s) => {
                for raw in s.expand()? {
                    let (pos, text) = (raw.pos, raw.name.clone());
                    out.push((RawValue::Stage(raw), pos, text));
                }
            }
        }
        Ok(())
    }
}

impl StagePattern {
    /// The stages this pattern stands for, in declaration order (first parameter outermost),
    /// not yet checked against the catalogue.
    pub(crate) fn expand(&self) -> Result<Vec<RawStage>, ParseError> {
        let Some(args) = &self.args else {
            return Ok(vec![RawStage { name: self.name.clone(), pos: self.pos, args: None }]);
        };
        // Each argument's values first, the count checked before any combination is built;
        // then each combination is built once (an odometer over the value lists, the last
        // argument fastest), so the work is linear in the size of the result.
        let mut per_arg = Vec::with_capacity(args.len());
        let mut count: usize = 1;
        for a in args {
            let mut values = Vec::new();
            a.value.expand(&mut values)?;
            count = count.saturating_mul(values.len());
            if count > MAX_CELLS {
                return Err(err(self.pos, &self.name, format!("the stage stands for more than {MAX_CELLS} stages")));
            }
            per_arg.push(values);
        }
        let mut combos: Vec<Vec<RawArg>> = Vec::with_capacity(count);
        let mut digits = vec![0usize; args.len()];
        for _ in 0..count {
            let combo = args
                .iter()
                .zip(&per_arg)
                .zip(&digits)
                .map(|((a, values), &d)| {
                    let (value, pos, text) = &values[d];
                    RawArg { name: a.name.clone(), value: value.clone(), pos: *pos, text: text.clone() }
                })
                .collect();
            combos.push(combo);
            for (d, values) in digits.iter_mut().zip(&per_arg).rev() {
                *d += 1;
                if *d < values.len() {
                    break;
                }
                *d = 0;
            }
        }
        Ok(combos
            .into_iter()
            .map(|args| RawStage { name: self.name.clone(), pos: self.pos, args: Some(args) })
            .collect())
    }
}

fn none() -> Vec<StageSpec> {
    vec![StageSpec::none()]
}

impl GridPattern {
    /// Expands and resolves the stages of each slot written, in reading order: the distinct
    /// stages in declaration order, indexed like [`Slot::ALL`] (`None` for a slot left out).
    pub(crate) fn resolve_slots(&self) -> Result<[Option<Vec<StageSpec>>; 4], ParseError> {
        let mut lists: [Option<Vec<StageSpec>>; 4] = [None, None, None, None];
        for sp in &self.slots {
            let idx = sp.slot as usize;
            // The slot's name, or the stage where the slot follows from the order (`+`).
            let token = match sp.stages.first() {
                Some(first) if first.pos == sp.pos => first.name.as_str(),
                _ => sp.slot.name(),
            };
            if lists[idx].is_some() {
                return Err(err(sp.pos, token, format!("the {} slot is given twice", sp.slot)));
            }
            if sp.stages.is_empty() {
                return Err(err(sp.pos, token, format!("the {} slot's list is empty", sp.slot)));
            }
            let mut seen = HashSet::new();
            let mut specs = Vec::new();
            for stage in &sp.stages {
                for raw in stage.expand()? {
                    let spec = resolve_stage(sp.slot, raw)?;
                    if seen.insert(spec.clone()) {
                        specs.push(spec);
                    }
                }
            }
            lists[idx] = Some(specs);
        }
        Ok(lists)
    }

    /// Expands and resolves every stage, then forms the product of the slots.
    pub(crate) fn expand(&self) -> Result<Grid, ParseError> {
        let lists = self.resolve()?;
        let (lods, sils, curved) = self.resolve_options()?;
        let total =
            lists.iter().map(Vec::len).product::<usize>().saturating_mul(lods.len() * sils.len() * curved.len());
        if total > MAX_CELLS {
            let pos = self.options.first().map_or(self.end, |o| o.pos);
            return Err(err(pos, "", format!("the grid has more than {MAX_CELLS} pipelines")));
        }
        Ok(Grid::product_with_options(self.name.clone(), lists, &lods, &sils, &curved))
    }

    /// Expands and resolves the option entries: the distinct values of each option in
    /// declaration order (`[zero]`, `[none]`, `[None]` (the flat tile) for an option left out).
    #[allow(clippy::type_complexity)]
    pub fn resolve_options(&self) -> Result<(Vec<Lod>, Vec<Silhouette>, Vec<Option<Curved>>), ParseError> {
        let (mut lods, mut sils): (Option<Vec<Lod>>, Option<Vec<Silhouette>>) = (None, None);
        let mut curved: Option<Vec<Option<Curved>>> = None;
        for op in &self.options {
            let given = match op.key {
                OptionKey::Lod => lods.is_some(),
                OptionKey::Silhouette => sils.is_some(),
                OptionKey::Curved => curved.is_some(),
            };
            if given {
                return Err(err(op.pos, op.key.name(), format!("the {} option is given twice", op.key)));
            }
            if op.values.is_empty() {
                return Err(err(op.pos, op.key.name(), format!("the {} option's list is empty", op.key)));
            }
            let (mut l, mut s, mut c) = (Vec::new(), Vec::new(), Vec::new());
            for v in &op.values {
                for raw in v.expand()? {
                    match resolve_option(op.key, &raw)? {
                        OptionValue::Lod(x) if !l.contains(&x) => l.push(x),
                        OptionValue::Silhouette(x) if !s.contains(&x) => s.push(x),
                        OptionValue::Curved(x) if !c.contains(&Some(x)) => c.push(Some(x)),
                        _ => {}
                    }
                }
            }
            match op.key {
                OptionKey::Lod => lods = Some(l),
                OptionKey::Silhouette => sils = Some(s),
                OptionKey::Curved => curved = Some(c),
            }
        }
        Ok((lods.unwrap_or(vec![Lod::Zero]), sils.unwrap_or(vec![Silhouette::None]), curved.unwrap_or(vec![None])))
    }

    /// The pattern as one pipeline: each slot must hold one stage with one value per
    /// parameter (what a pipeline text or `relief!` body declares). Checks the stages like
    /// [`GridPattern::resolve`]; slots left out are `none`, and coarse must be given.
    pub fn pipeline(&self) -> Result<Pipeline, ParseError> {
        let [c, r, s, a] = self.resolve_slots()?;
        let Some(coarse) = c else {
            return Err(err(self.end, "", "the pipeline has no coarse stage; start it with one such as linear(32)"));
        };
        let one = |slot: Slot, list: Option<Vec<StageSpec>>| -> Result<StageSpec, ParseError> {
            let list = list.unwrap_or_else(none);
            let n = list.len();
            let [stage] = <[StageSpec; 1]>::try_from(list).map_err(|_| {
                let pos = self.slots.iter().find(|sp| sp.slot == slot).map_or(self.end, |sp| sp.pos);
                err(pos, slot.name(), format!("the {slot} slot declares {n} stages where a pipeline has one"))
            })?;
            Ok(stage)
        };
        let p = Pipeline::new(
            one(Slot::Coarse, Some(coarse))?,
            one(Slot::Refine, r)?,
            one(Slot::Shadow, s)?,
            one(Slot::Ao, a)?,
        );
        let (lods, sils, curved) = self.resolve_options()?;
        let (&[lod], &[sil], &[cur]) = (lods.as_slice(), sils.as_slice(), curved.as_slice()) else {
            let op = self.options.iter().find(|o| o.values.len() > 1).or(self.options.first());
            let (pos, key) = op.map_or((self.end, ""), |o| (o.pos, o.key.name()));
            return Err(err(pos, key, format!("the {key} option declares several values where a pipeline has one")));
        };
        Ok(p.with_lod(lod).with_silhouette(sil).with_curved(cur))
    }

    /// Expands and resolves every stage: the distinct stages of each slot in declaration
    /// order, indexed like [`Slot::ALL`] (`[none]` for a slot left out). Checks that the
    /// grid has a coarse slot and at most [`MAX_CELLS`] pipelines.
    pub fn resolve(&self) -> Result<[Vec<StageSpec>; 4], ParseError> {
        let lists = self.resolve_slots()?;
        let [c, r, s, a] = lists;
        let Some(coarse) = c else {
            return Err(err(self.end, "", "the grid has no coarse slot; add one such as `coarse: [linear(32)]`"));
        };
        let (r, s, a) = (r.unwrap_or_else(none), s.unwrap_or_else(none), a.unwrap_or_else(none));
        let total = [coarse.len(), r.len(), s.len(), a.len()].iter().try_fold(1usize, |acc, n| acc.checked_mul(*n));
        if total.is_none_or(|t| t > MAX_CELLS) {
            let pos = self.slots.iter().find(|sp| sp.slot == Slot::Coarse).map_or(self.end, |sp| sp.pos);
            return Err(err(pos, "coarse", format!("the grid has more than {MAX_CELLS} pipelines")));
        }
        Ok([coarse, r, s, a])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn texts(g: &Grid) -> Vec<String> {
        g.iter().map(|p| p.to_string()).collect()
    }

    #[test]
    fn product_in_declaration_order() {
        let g: Grid = "# a grid\nname: \"t\"\ncoarse: [linear(5..=15 step 5), linear_dynamic(8, 32)]  # coarse\n\
                       refine: [none, binary(3), interval(3)]\nshadow: [none]\n"
            .parse()
            .unwrap();
        assert_eq!(g.name.as_deref(), Some("t"));
        assert_eq!(g.len(), 12);
        assert_eq!(texts(&g)[..4], ["linear(5)", "linear(5)+binary(3)", "linear(5)+interval(3)", "linear(10)"]);
        assert_eq!(texts(&g)[11], "linear_dynamic(8, 32)+interval(3)");
    }

    #[test]
    fn lists_ranges_names_and_nesting() {
        let g: Grid = "coarse: linear(steps = [8, 16]), refine: binary(1..=2), shadow: [hard(linear([4, 8])), soft(2..=6 step 4)],"
            .parse()
            .unwrap();
        assert_eq!(g.len(), 2 * 2 * 4);
        assert_eq!(texts(&g)[0], "linear(8)+binary(1)+shadow=hard(4)");
        assert_eq!(texts(&g)[3], "linear(8)+binary(1)+shadow=soft(6)");
        let g: Grid = "coarse: linear_dynamic([4, 8], 16..=32 step 16)".parse().unwrap();
        assert_eq!(
            texts(&g),
            ["linear_dynamic(4, 16)", "linear_dynamic(4, 32)", "linear_dynamic(8, 16)", "linear_dynamic(8, 32)"]
        );
        // Duplicates after resolution are kept once.
        let g: Grid = "coarse: [linear(32), linear, linear(steps=32)]".parse().unwrap();
        assert_eq!(g.len(), 1);
        let all: Vec<Pipeline> = g.clone().into_iter().collect();
        assert_eq!(all, g.cells());
    }

    #[test]
    fn errors_name_line_column_and_token() {
        let cases = [
            ("coarse: [linear(5)]\nrefine: [binary(3), lnear(3)]", 2, 21, "lnear", "unknown refine stage"),
            ("coarse: [linear(5)]\nrefine: [linear(3)]", 2, 10, "linear", "is a coarse stage, not a refine stage"),
            ("coarse: [linear(0..=8 step 4)]", 1, 17, "0", "out of range"),
            ("coarse: [linear(8..=4)]", 1, 17, "8..=4", "empty range"),
            ("coarse: [linear(4..=8 step 0)]", 1, 17, "4..=8 step 0", "step must be at least 1"),
            ("coarse: [linear_dynamic(32, 8)]", 1, 10, "linear_dynamic", "min <= max"),
            ("coarse: [linear(stps = 4)]", 1, 17, "stps", "no parameter `stps`"),
            ("  corse: [linear]", 1, 3, "corse", "unknown slot"),
            ("coarse: [linear]\ncoarse: [parallax]", 2, 1, "coarse", "given twice"),
            ("refine: [binary]", 1, 17, "", "no coarse slot"),
            ("coarse: []", 1, 1, "coarse", "list is empty"),
            ("coarse: [linear([])]", 1, 17, "[", "empty list"),
            ("coarse: [linear(4..8)]", 1, 18, "..", "inclusive"),
            ("coarse: [linear(4) binary]", 1, 20, "binary", "expected `,` or `]`"),
        ];
        for (text, line, column, token, msg) in cases {
            let e = text.parse::<Grid>().unwrap_err();
            assert_eq!((e.line_column, e.token.as_str()), (Some((line, column)), token), "{text}: {e}");
            assert!(e.to_string().contains(msg), "{text}: {e}");
            assert!(e.to_string().starts_with(&format!("line {line}, column {column}")), "{e}");
        }
    }

    #[test]
    fn too_many_cells_is_an_error() {
        let e = "coarse: linear(1..=4096), refine: binary(1..=4096)".parse::<Grid>().unwrap_err();
        assert!(e.to_string().contains("more than"), "{e}");
    }
}
