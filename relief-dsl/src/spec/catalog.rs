//! The catalogue of methods: names, slots, parameters, defaults, the maps each reads and the
//! function that builds it. The text form, the macros, `relief gen --list` and the composer
//! all read it, so they cannot disagree.
//!
//! Each built-in method is declared once, in its own file under `stage/` (a function that
//! returns its [`MethodDef`]), and `stage/mod.rs` lists them. The spec sits below the stage
//! layer and cannot name it: the catalogue reaches that list, and the type of a stage function,
//! through the trait [`StageLayer`], which the stage layer implements for [`Stages`]. A
//! program adds its own methods with [`register`], through the same [`MethodDef`].

use std::sync::{OnceLock, RwLock};

use super::{Choice, MapReq, Slot, StageSpec, Value};
use crate::CompileError;

/// The largest step count any parameter accepts.
pub const MAX_STEPS: u32 = 4096;

/// What a parameter accepts.
#[derive(Clone, Debug, PartialEq)]
pub enum ParamKind {
    /// A step count in `1..=MAX_STEPS`.
    Steps,
    /// A whole number in `min..=max`.
    Count {
        /// The smallest value accepted.
        min: u32,
        /// The largest value accepted.
        max: u32,
    },
    /// One word of a fixed set (the words of a [`Choice`]).
    Choice(&'static [&'static str]),
    /// A step count (short for `linear(n)`) or a stage of the given slot.
    StageOr(Slot),
}

impl ParamKind {
    /// How the accepted values are described in errors and `--list`.
    pub fn describe(&self) -> String {
        match self {
            ParamKind::Steps => format!("a step count in 1..={MAX_STEPS}"),
            ParamKind::Count { min, max } => format!("a whole number in {min}..={max}"),
            ParamKind::Choice(words) => format!("one of {}", words.join("|")),
            ParamKind::StageOr(slot) => {
                format!("a step count in 1..={MAX_STEPS} or a {slot} stage such as linear(16)")
            }
        }
    }
}

/// One parameter of a method.
#[derive(Clone, Debug)]
pub struct ParamDef {
    /// The parameter's name (`steps`), as written in `name = value`.
    pub name: &'static str,
    /// What it accepts.
    pub kind: ParamKind,
    /// `None`: the parameter must be given.
    pub default: Option<Value>,
}

impl ParamDef {
    /// A step count in `1..=MAX_STEPS` with a default.
    pub fn steps(name: &'static str, default: u32) -> Self {
        ParamDef { name, kind: ParamKind::Steps, default: Some(Value::Int(default)) }
    }
    /// A whole number in `min..=max` with a default.
    pub fn count(name: &'static str, min: u32, max: u32, default: u32) -> Self {
        ParamDef { name, kind: ParamKind::Count { min, max }, default: Some(Value::Int(default)) }
    }
    /// One word of the choice `C`, its first word the default.
    pub fn choice<C: Choice>(name: &'static str) -> Self {
        ParamDef { name, kind: ParamKind::Choice(C::WORDS), default: Some(Value::Word(C::WORDS[0].to_string())) }
    }
    /// A step count or a stage of `slot`, `default` steps when left out.
    pub(crate) fn stage_or(name: &'static str, slot: Slot, default: u32) -> Self {
        ParamDef { name, kind: ParamKind::StageOr(slot), default: Some(Value::Int(default)) }
    }
}

/// A stage's resolved parameters as its stage function reads them: typed getters over the
/// [`StageSpec`], with errors that name the stage.
///
/// Resolution ([`super::resolve_stage`], the text forms, [`StageSpec::new`]) has already
/// checked every value against its [`ParamDef`], so these getters fail only for a
/// [`StageSpec`] edited by hand into something the catalogue does not allow.
pub struct Args<'s> {
    slot: Slot,
    spec: &'s StageSpec,
}

impl<'s> Args<'s> {
    /// The parameters of `spec`, a stage of `slot`.
    pub fn new(slot: Slot, spec: &'s StageSpec) -> Self {
        Args { slot, spec }
    }
    /// The stage as resolved.
    pub fn spec(&self) -> &'s StageSpec {
        self.spec
    }
    fn error(&self, message: String) -> CompileError {
        CompileError { stage: format!("{} {}", self.slot, self.spec.name), message }
    }
    /// The whole-number parameter `name` (a step count or a count).
    pub fn int(&self, name: &str) -> Result<u32, CompileError> {
        match self.spec.get(name) {
            Some(Value::Int(n)) => Ok(*n),
            Some(other) => Err(self.error(format!("`{name}={other}` is not a whole number"))),
            None => Err(self.error(format!("no parameter `{name}`"))),
        }
    }
    /// The choice parameter `name` as its typed value.
    pub fn choice<C: Choice>(&self, name: &str) -> Result<C, CompileError> {
        match self.spec.get(name) {
            Some(Value::Word(w)) => C::from_word(w).ok_or_else(|| {
                self.error(format!("`{name}={w}` is not a choice this stage knows ({})", C::WORDS.join("|")))
            }),
            Some(other) => Err(self.error(format!("`{name}={other}` is not a word"))),
            None => Err(self.error(format!("no parameter `{name}`"))),
        }
    }
    /// The step-count-or-stage parameter `name`.
    pub(crate) fn stage_or(&self, name: &str) -> Result<StageOr<'s>, CompileError> {
        match self.spec.get(name) {
            Some(Value::Int(n)) => Ok(StageOr::Steps(*n)),
            Some(Value::Stage(s)) => Ok(StageOr::Stage(s)),
            Some(other) => Err(self.error(format!("`{name}={other}` is neither a step count nor a stage"))),
            None => Err(self.error(format!("no parameter `{name}`"))),
        }
    }
}

/// The value of a [`ParamKind::StageOr`] parameter.
pub enum StageOr<'s> {
    /// A step count: `linear(n)`.
    Steps(u32),
    /// Another stage.
    Stage(&'s StageSpec),
}

/// What the catalogue needs from the stage layer, which sits above the spec and cannot be
/// named from here: the type of a method's stage function and the list of built-in methods. The
/// stage layer implements it once, for [`Stages`]; nothing else does (nor can: the trait and
/// the type are both this crate's).
pub trait StageLayer {
    /// The function that writes a method's stage into a module (the stage layer's `StageFn`).
    type StageFn: Copy + std::fmt::Debug + Send + Sync + 'static;
    /// The slot a stage function fills.
    fn slot(f: &Self::StageFn) -> Slot;
    /// The built-in methods, in listing order.
    fn builtins() -> Vec<MethodDef>;
}

/// The stage layer as the catalogue sees it (see [`StageLayer`]).
#[derive(Clone, Copy, Debug)]
pub struct Stages;

/// A method's stage function: the stage layer's `StageFn` (`relief_dsl::stage::StageFn`, the same
/// type under the name the spec layer can reach), one function type per slot shape.
pub type StageFn = <Stages as StageLayer>::StageFn;

/// One method: its name, slot, parameters, the maps it reads, the combinations it refuses and
/// its stage function.
///
/// Make one with [`MethodDef::new`], then [`MethodDef::param`], [`MethodDef::reads`] and
/// [`MethodDef::check`]; add it with [`register`]. The built-in methods are made the same way,
/// each in its own file under `stage/`.
#[derive(Clone, Debug)]
pub struct MethodDef {
    /// The name in the text form (lower_snake).
    pub name: &'static str,
    /// The slot it fills (always the slot of [`MethodDef::stage_fn`]).
    pub slot: Slot,
    /// One line for `relief gen --list`, with the source.
    pub summary: &'static str,
    /// The parameters, in positional order.
    pub params: Vec<ParamDef>,
    /// The maps a stage with these parameters reads, besides the height map.
    pub maps: fn(&StageSpec) -> Vec<MapReq>,
    /// Parameter combinations that cannot work, refused at resolution (`Err(message)`).
    pub check: fn(&StageSpec) -> Result<(), String>,
    /// The function that writes the stage into a module.
    pub stage_fn: StageFn,
}

fn no_check(_: &StageSpec) -> Result<(), String> {
    Ok(())
}

impl MethodDef {
    /// A method called `name` in the slot of `stage_fn`, with no parameters and no maps besides
    /// the height map.
    pub fn new(name: &'static str, summary: &'static str, stage_fn: StageFn) -> Self {
        let slot = <Stages as StageLayer>::slot(&stage_fn);
        MethodDef { name, slot, summary, params: vec![], maps: no_maps, check: no_check, stage_fn }
    }
    /// Adds a parameter (after those already added).
    pub fn param(mut self, p: ParamDef) -> Self {
        self.params.push(p);
        self
    }
    /// Sets the maps the method reads.
    pub fn reads(mut self, maps: fn(&StageSpec) -> Vec<MapReq>) -> Self {
        self.maps = maps;
        self
    }
    /// Sets the combination check run at resolution.
    pub fn check(mut self, check: fn(&StageSpec) -> Result<(), String>) -> Self {
        self.check = check;
        self
    }

    /// The method at its default parameters, or with the catalogue's example values for
    /// parameters that have no default.
    pub fn default_spec(&self) -> StageSpec {
        StageSpec {
            name: self.name.to_string(),
            params: self
                .params
                .iter()
                .map(|p| (p.name.to_string(), p.default.clone().unwrap_or(Value::Int(8))))
                .collect(),
        }
    }
}

/// Why [`register`] refused a method.
#[derive(Debug, Clone, thiserror::Error)]
#[error("cannot register `{name}`: {message}")]
pub struct RegisterError {
    /// The method's name.
    pub name: String,
    /// What is wrong.
    pub message: String,
}

/// The catalogue as of the last [`register`]: the built-in methods, then the registered
/// ones. Each registration leaks one new list (a few pointers), so that [`catalog`] can
/// hand out a `'static` slice without holding the lock.
static CATALOG: RwLock<Option<&'static [&'static MethodDef]>> = RwLock::new(None);

/// Adds a method to the catalogue, for the text form, grids, [`crate::compile`] and
/// everything in relief-runtime that reads pipelines (render, sweep, report), as if it were
/// built in.
///
/// Registration is global to the process and permanent (the definition is leaked to live
/// as long as the catalogue). It is thread-safe (a lock), but a pipeline that names the
/// method parses only after the call returns: register before parsing any text or grid that
/// uses it, and before starting threads that parse. The macros (`relief_pipeline!`,
/// `relief_grid!`) run in the compiler and see only the built-in methods.
///
/// Refused: a name that is not lower_snake, a name already taken in the method's slot, a
/// slot that is not its stage function's, two parameters with one name, a default outside its
/// parameter's range.
pub fn register(def: MethodDef) -> Result<(), RegisterError> {
    let mut current = CATALOG.write().unwrap_or_else(|e| e.into_inner());
    let mut all: Vec<&'static MethodDef> = match *current {
        Some(c) => c.to_vec(),
        None => builtins().iter().collect(),
    };
    if let Some(message) = refusal(&def, &all) {
        return Err(RegisterError { name: def.name.to_string(), message });
    }
    all.push(Box::leak(Box::new(def)));
    *current = Some(Box::leak(all.into_boxed_slice()));
    Ok(())
}

/// Why `def` cannot join the methods `others` (see [`register`]), or `None`.
fn refusal(def: &MethodDef, others: &[&MethodDef]) -> Option<String> {
    let snake = def.name.chars().next().is_some_and(|c| c.is_ascii_lowercase())
        && def.name.chars().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
    if !snake {
        return Some("a method name is lower_snake: a-z, 0-9 and `_`, starting with a letter".into());
    }
    let built = <Stages as StageLayer>::slot(&def.stage_fn);
    if built != def.slot {
        return Some(format!("declared a {} stage but its stage function is a {} stage", def.slot, built));
    }
    for (i, p) in def.params.iter().enumerate() {
        if def.params[..i].iter().any(|q| q.name == p.name) {
            return Some(format!("two parameters called `{}`", p.name));
        }
        let ok = match (&p.kind, &p.default) {
            (_, None) => true,
            (ParamKind::Steps | ParamKind::StageOr(_), Some(Value::Int(n))) => (1..=MAX_STEPS).contains(n),
            (ParamKind::Count { min, max }, Some(Value::Int(n))) => (*min..=*max).contains(n),
            (ParamKind::Choice(words), Some(Value::Word(w))) => words.contains(&w.as_str()),
            (ParamKind::StageOr(_), Some(Value::Stage(_))) => true,
            _ => false,
        };
        if !ok {
            return Some(format!("the default of `{}` is not {}", p.name, p.kind.describe()));
        }
    }
    if others.iter().any(|m| m.slot == def.slot && m.name == def.name) {
        return Some(format!("the {} slot already has a method called `{}`", def.slot, def.name));
    }
    // The text form prints a stage from its name alone, so a name has the same parameters
    // in every slot that has it.
    let same_params = |m: &MethodDef| {
        m.params.len() == def.params.len()
            && m.params.iter().zip(&def.params).all(|(a, b)| a.name == b.name && a.kind == b.kind)
    };
    let other = others.iter().find(|m| m.name == def.name && !same_params(m))?;
    Some(format!(
        "the {} method `{}` has other parameters; a name has the same parameters in every slot",
        other.slot, def.name
    ))
}

/// Every method relief knows, in listing order: the built-in ones, then those added with
/// [`register`] in the order they were added.
pub fn catalog() -> Catalog {
    if let Some(c) = *CATALOG.read().unwrap_or_else(|e| e.into_inner()) {
        return Catalog(c);
    }
    let mut current = CATALOG.write().unwrap_or_else(|e| e.into_inner());
    Catalog(current.get_or_insert_with(|| Box::leak(builtins().iter().collect::<Vec<_>>().into_boxed_slice())))
}

/// The catalogue at one moment (see [`catalog`]): a method registered later is not in it.
#[derive(Clone, Copy)]
pub struct Catalog(&'static [&'static MethodDef]);

impl Catalog {
    /// The methods in listing order.
    pub fn iter(&self) -> std::iter::Copied<std::slice::Iter<'static, &'static MethodDef>> {
        self.0.iter().copied()
    }
    /// How many methods there are.
    pub fn len(&self) -> usize {
        self.0.len()
    }
    /// Whether there are none (never: the built-in methods are always there).
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

impl IntoIterator for Catalog {
    type Item = &'static MethodDef;
    type IntoIter = std::iter::Copied<std::slice::Iter<'static, &'static MethodDef>>;
    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

/// The method `name` of `slot`.
pub fn method(slot: Slot, name: &str) -> Option<&'static MethodDef> {
    catalog().iter().find(|m| m.slot == slot && m.name == name)
}

/// The first method called `name` in any slot (for printing: a name's parameters are the
/// same in every slot that has it).
pub(crate) fn method_any(name: &str) -> Option<&'static MethodDef> {
    catalog().iter().find(|m| m.name == name)
}

/// No maps besides the height map.
pub fn no_maps(_: &StageSpec) -> Vec<MapReq> {
    vec![]
}

/// The built-in methods, in listing order (the stage layer's list, made once).
fn builtins() -> &'static [MethodDef] {
    static BUILTINS: OnceLock<Vec<MethodDef>> = OnceLock::new();
    BUILTINS.get_or_init(<Stages as StageLayer>::builtins)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spec::Pipeline;

    #[test]
    fn the_catalogues_choices_are_the_choice_words() {
        // The catalogue's choices are these words, in this order (the first is the default).
        let words = |name: &str, param: &str| {
            let def = method(Slot::Coarse, name).unwrap();
            match &def.params.iter().find(|p| p.name == param).unwrap().kind {
                ParamKind::Choice(w) => w.to_vec(),
                other => panic!("{other:?}"),
            }
        };
        assert_eq!(words("csm", "sample"), ["auto", "linear", "nearest", "min4"]);
        assert_eq!(words("rcs", "start"), ["auto", "hk", "bracket"]);
        assert_eq!(words("cns", "form"), ["safe", "textbook"]);
    }

    fn coarse_linear() -> StageFn {
        method(Slot::Coarse, "linear").unwrap().stage_fn
    }

    /// The built-in methods pass the checks a registered one must pass, each against those
    /// listed before it: lower_snake names, no name twice in a slot, defaults in range, the
    /// stage function's slot, one parameter list per name.
    #[test]
    fn every_built_in_method_could_have_been_registered() {
        let all = builtins();
        assert!(all.len() >= 29, "{}", all.len());
        for (i, def) in all.iter().enumerate() {
            let before: Vec<&MethodDef> = all[..i].iter().collect();
            assert_eq!(refusal(def, &before), None, "{} {}", def.slot, def.name);
        }
        for slot in Slot::ALL {
            assert_eq!(all.iter().filter(|m| m.slot == slot).map(|m| m.name).next(), Some("none"), "{slot}");
        }
    }

    #[test]
    fn register_refuses_what_the_text_form_could_not_read() {
        let refused = |def: MethodDef, why: &str| {
            let e = register(def).unwrap_err();
            assert!(e.message.contains(why), "{e}");
        };
        refused(MethodDef::new("Linear2", "", coarse_linear()), "lower_snake");
        refused(MethodDef::new("2linear", "", coarse_linear()), "lower_snake");
        refused(MethodDef::new("linear", "", coarse_linear()), "already has a method called `linear`");
        let mut wrong_slot = MethodDef::new("test_wrong_slot", "", coarse_linear());
        wrong_slot.slot = Slot::Refine;
        refused(wrong_slot, "stage function is a coarse stage");
        refused(
            MethodDef::new("test_twice", "", coarse_linear())
                .param(ParamDef::steps("n", 4))
                .param(ParamDef::steps("n", 8)),
            "two parameters called `n`",
        );
        refused(
            MethodDef::new("test_range", "", coarse_linear()).param(ParamDef::count("k", 1, 4, 5)),
            "default of `k`",
        );
        refused(MethodDef::new("test_steps", "", coarse_linear()).param(ParamDef::steps("n", 0)), "default of `n`");
        // `none` exists in every slot without parameters; a coarse `binary` would print with
        // the refine `binary`'s parameters.
        refused(MethodDef::new("binary", "", coarse_linear()), "has other parameters");
        for name in ["Linear2", "2linear", "test_wrong_slot", "test_twice", "test_range", "test_steps"] {
            assert!(catalog().iter().all(|m| m.name != name), "{name} was added");
        }
    }

    #[test]
    fn a_registered_stage_parses_prints_and_compiles() {
        register(MethodDef::new("test_search", "a test", coarse_linear()).param(ParamDef::steps("steps", 7))).unwrap();
        let p: Pipeline = "test_search+binary(2)".parse().unwrap();
        assert_eq!(p.to_string(), "test_search(7)+binary(2)");
        let e = "test_search(0)".parse::<Pipeline>().unwrap_err();
        assert!(e.message.contains("out of range"), "{e}");
        // The stage function is linear's: the module has the registered name and linear's loop.
        let wgsl = crate::emit::emit(&p).unwrap().wgsl;
        assert!(wgsl.contains("fn coarse_test_search("), "{wgsl}");
        assert!(catalog().iter().any(|m| m.name == "test_search"));
    }

    #[test]
    fn a_hand_edited_choice_is_an_error_not_a_default() {
        for (text, param) in [("csm(8)", "form"), ("csm(8)", "sample"), ("rcs(8)", "start"), ("qcsm(8)", "form")] {
            let mut p: Pipeline = text.parse().unwrap();
            let v = p.coarse.params.iter_mut().find(|(n, _)| n == param).unwrap();
            v.1 = Value::Word("sideways".into());
            let e = crate::compile(&p).err().unwrap_or_else(|| panic!("{text} with {param}=sideways compiled"));
            assert!(e.stage.starts_with("coarse "), "{e}");
            assert!(e.message.contains(&format!("`{param}=sideways` is not a choice")), "{e}");
        }
    }
}
