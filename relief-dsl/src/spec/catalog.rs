//! The catalogue of methods: names, slots, parameters, defaults, the maps each reads and the
//! function that builds it. Every method is registered here once; the text form, the macros,
//! `relief gen --list` and the composer all read it, so they cannot disagree.
//!
//! The built-in methods are listed in [`catalog`]; a program adds its own with
//! [`register`] (see its docs for when that must happen).
//!
//! The catalogue is data: names, parameters, maps, checks. The code that writes a stage
//! into a module sits above the spec, in `stage`: a registered method carries its builder
//! as a [`Builder`] (the stage layer's `Build`), and the built-in methods' builders are the
//! stage layer's own table (`stage::builtins`), which a test keeps equal to this one.

use std::any::Any;
use std::sync::{Arc, OnceLock, RwLock};

use super::choice::{Form, SampleChoice, StartChoice};
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
    pub fn stage_or(name: &'static str, slot: Slot, default: u32) -> Self {
        ParamDef { name, kind: ParamKind::StageOr(slot), default: Some(Value::Int(default)) }
    }
}

/// A stage's resolved parameters as its builder reads them: typed getters over the
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
            Some(Value::Word(w)) => C::from_word(w)
                .ok_or_else(|| self.error(format!("`{name}={w}` is not a choice this stage knows ({})", C::WORDS.join("|")))),
            Some(other) => Err(self.error(format!("`{name}={other}` is not a word"))),
            None => Err(self.error(format!("no parameter `{name}`"))),
        }
    }
    /// The step-count-or-stage parameter `name`.
    pub fn stage_or(&self, name: &str) -> Result<StageOr<'s>, CompileError> {
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

/// The code that builds a method, as the catalogue holds it: any value that knows its slot.
/// The stage layer's `Build` is the one implementation; the composer takes it back with
/// [`Builder::as_any`]. The catalogue itself never calls it.
pub trait Builder: Any + Send + Sync {
    /// The slot the builder fills.
    fn slot(&self) -> Slot;
    /// The builder as `Any`, to be taken back as its own type.
    fn as_any(&self) -> &dyn Any;
}

/// One method: its slot, parameters, the maps it reads and its builder.
///
/// Make one with [`MethodDef::new`], then [`MethodDef::param`], [`MethodDef::reads`] and
/// [`MethodDef::check`]; add it with [`register`].
#[derive(Clone)]
pub struct MethodDef {
    /// The name in the text form (lower_snake).
    pub name: &'static str,
    /// The slot it fills (always the slot of [`MethodDef::build`], where there is one).
    pub slot: Slot,
    /// One line for `relief gen --list`, with the source.
    pub summary: &'static str,
    /// The parameters, in positional order.
    pub params: Vec<ParamDef>,
    /// The maps a stage with these parameters reads, besides the height map.
    pub maps: fn(&StageSpec) -> Vec<MapReq>,
    /// Whether stage code exists for it (the catalogue may name methods still to come).
    pub implemented: bool,
    /// Parameter combinations that cannot work, refused at resolution (`Err(message)`).
    pub check: fn(&StageSpec) -> Result<(), String>,
    /// The function that writes the stage into a module, for a registered method; `None`
    /// for a built-in one, whose builder is the stage layer's.
    pub build: Option<Arc<dyn Builder>>,
}

fn no_check(_: &StageSpec) -> Result<(), String> {
    Ok(())
}

impl MethodDef {
    /// A method called `name` in the slot of `build`, with no parameters and no maps besides
    /// the height map.
    pub fn new(name: &'static str, summary: &'static str, build: impl Builder) -> Self {
        let slot = build.slot();
        MethodDef { name, slot, summary, params: vec![], maps: no_maps, implemented: true, check: no_check, build: Some(Arc::new(build)) }
    }
    /// A built-in method of `slot` (its builder is the stage layer's).
    fn builtin(name: &'static str, summary: &'static str, slot: Slot) -> Self {
        MethodDef { name, slot, summary, params: vec![], maps: no_maps, implemented: true, check: no_check, build: None }
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
/// slot that is not the builder's, two parameters with one name, a default outside its
/// parameter's range.
pub fn register(def: MethodDef) -> Result<(), RegisterError> {
    let refuse = |message: String| RegisterError { name: def.name.to_string(), message };
    let snake = def.name.chars().next().is_some_and(|c| c.is_ascii_lowercase())
        && def.name.chars().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
    if !snake {
        return Err(refuse("a method name is lower_snake: a-z, 0-9 and `_`, starting with a letter".into()));
    }
    match &def.build {
        None => return Err(refuse("a registered method needs a builder".into())),
        Some(b) if b.slot() != def.slot => {
            return Err(refuse(format!("declared a {} stage but its builder is a {} stage", def.slot, b.slot())));
        }
        Some(_) => {}
    }
    for (i, p) in def.params.iter().enumerate() {
        if def.params[..i].iter().any(|q| q.name == p.name) {
            return Err(refuse(format!("two parameters called `{}`", p.name)));
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
            return Err(refuse(format!("the default of `{}` is not {}", p.name, p.kind.describe())));
        }
    }
    let mut current = CATALOG.write().unwrap_or_else(|e| e.into_inner());
    let mut all: Vec<&'static MethodDef> = match *current {
        Some(c) => c.to_vec(),
        None => builtins().iter().collect(),
    };
    if all.iter().any(|m| m.slot == def.slot && m.name == def.name) {
        return Err(refuse(format!("the {} slot already has a method called `{}`", def.slot, def.name)));
    }
    // The text form prints a stage from its name alone, so a name has the same parameters
    // in every slot that has it.
    let same_params = |m: &MethodDef| {
        m.params.len() == def.params.len() && m.params.iter().zip(&def.params).all(|(a, b)| a.name == b.name && a.kind == b.kind)
    };
    if let Some(other) = all.iter().find(|m| m.name == def.name && !same_params(m)) {
        return Err(refuse(format!("the {} method `{}` has other parameters; a name has the same parameters in every slot", other.slot, def.name)));
    }
    all.push(Box::leak(Box::new(def)));
    *current = Some(Box::leak(all.into_boxed_slice()));
    Ok(())
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
fn normal_map(_: &StageSpec) -> Vec<MapReq> {
    vec![MapReq::Normal]
}
fn cone(_: &StageSpec) -> Vec<MapReq> {
    vec![MapReq::Cone]
}
fn cone_normal(_: &StageSpec) -> Vec<MapReq> {
    vec![MapReq::ConeNormal]
}
/// The map a cone method reads: the texel-sample map for `form=textbook`, the cell map for
/// `form=safe`.
fn by_form(s: &StageSpec, textbook: MapReq, safe: MapReq) -> Vec<MapReq> {
    // A word outside the choice (only a hand-edited spec has one) fails to compile; the safe
    // form's map is as good a guess as any for it.
    match Form::from_word(s.word("form")) {
        Some(Form::Textbook) => vec![textbook],
        Some(Form::Safe) | None => vec![safe],
    }
}
fn csm_maps(s: &StageSpec) -> Vec<MapReq> {
    by_form(s, MapReq::Cone, MapReq::CellCone)
}
fn quad_cone(s: &StageSpec) -> Vec<MapReq> {
    by_form(s, MapReq::QuadCone, MapReq::CellQuadCone)
}
fn relaxed_cone(s: &StageSpec) -> Vec<MapReq> {
    by_form(s, MapReq::RelaxedCone, MapReq::CellRelaxedCone)
}
fn cns_maps(s: &StageSpec) -> Vec<MapReq> {
    by_form(s, MapReq::ConeNormal, MapReq::CellConeNormal)
}
fn relaxed_cone_normal(s: &StageSpec) -> Vec<MapReq> {
    by_form(s, MapReq::RelaxedConeNormal, MapReq::CellRelaxedCone)
}
fn multi_cone(s: &StageSpec) -> Vec<MapReq> {
    by_form(s, MapReq::MultiCone(s.int("k")), MapReq::CellMultiCone(s.int("k")))
}
fn piecewise_cone(s: &StageSpec) -> Vec<MapReq> {
    by_form(s, MapReq::PiecewiseCone(s.int("k")), MapReq::CellPiecewiseCone(s.int("k")))
}
fn distance_field(_: &StageSpec) -> Vec<MapReq> {
    vec![MapReq::DistanceField]
}
fn max_mip(_: &StageSpec) -> Vec<MapReq> {
    vec![MapReq::MaxMip]
}

/// `form=safe|textbook` of the cone methods: `safe` (the default) steps on cones of the
/// bilinear cells and never passes the first hit; `textbook` steps on the texel-sample maps
/// as the papers print it.
fn form() -> ParamDef {
    ParamDef::choice::<Form>("form")
}
fn cones(default: u32) -> ParamDef {
    ParamDef::count("k", 1, 4, default)
}

fn min_le_max(s: &StageSpec) -> Result<(), String> {
    if s.int("min") > s.int("max") {
        return Err(format!("`linear_dynamic` needs min <= max, got min {} and max {}", s.int("min"), s.int("max")));
    }
    Ok(())
}

/// The built-in methods, in listing order.
fn builtins() -> &'static [MethodDef] {
    static BUILTINS: OnceLock<Vec<MethodDef>> = OnceLock::new();
    BUILTINS.get_or_init(|| {
        use Slot::{Ao, Coarse, Refine, Shadow};
        let steps = ParamDef::steps;
        let def = MethodDef::builtin;
        vec![
            def("none", "plain texture mapping: the hit is the entry point", Coarse),
            def("parallax", "parallax mapping (Kaneko et al. 2001; Burger eq. 2.3-2.5)", Coarse),
            def("offset_limited", "parallax with offset limiting (Welsh 2004; survey 4.1.3)", Coarse),
            def("slope_parallax", "parallax along the normal map's slope (survey 4.1.4)", Coarse).reads(normal_map),
            def("iterative_parallax", "iterative parallax with slope (Premecz 2006; survey 4.2.1)", Coarse)
                .param(steps("steps", 4))
                .reads(normal_map),
            def("linear", "linear search (Burger Algorithm 1)", Coarse).param(steps("steps", 32)),
            def(
                "linear_dynamic",
                "linear search, step count from the view angle (Tatarchuk 2006; Amaro & Gustafsson 2.1.3)",
                Coarse,
            )
            .param(steps("min", 8))
            .param(steps("max", 32))
            .check(min_le_max),
            def(
                "linear_distance",
                "linear search, layer count from the view angle and the camera distance (Amaro & Gustafsson 2.1.3)",
                Coarse,
            )
            .param(steps("min", 16))
            .param(steps("max", 180))
            .param(steps("theta_min", 4)),
            def(
                "csm",
                "cone step mapping (Dummer 2006; Burger Algorithm 4); form=safe|textbook; sample=linear|nearest|min4 for form=textbook (Burger 4.3.1), auto: the cell's cone (safe) or linear (textbook)",
                Coarse,
            )
            .param(steps("steps", 15))
            .param(form())
            .param(ParamDef::choice::<SampleChoice>("sample"))
            .reads(csm_maps),
            def("qcsm", "quad-directional cone stepping (Policarpo & Oliveira, GPU Gems 3 18.4.1); form=safe|textbook", Coarse)
                .param(steps("steps", 15))
                .param(form())
                .reads(quad_cone),
            def(
                "rcs",
                "relaxed cone stepping (GPU Gems 3 Listing 18-3); form=safe|textbook; start=hk|bracket (Fig. 18-10), auto: bracket (safe) or hk (textbook)",
                Coarse,
            )
            .param(steps("steps", 15))
            .param(form())
            .param(ParamDef::choice::<StartChoice>("start"))
            .reads(relaxed_cone),
            def("cns", "cone normal stepping (Burger 3.3, eq. 3.2); form=safe|textbook", Coarse)
                .param(steps("steps", 15))
                .param(form())
                .reads(cns_maps),
            def("rcns", "relaxed cone normal stepping (Burger 4.3.4); form=safe|textbook", Coarse)
                .param(steps("steps", 15))
                .param(form())
                .reads(relaxed_cone_normal),
            def("mcns", "multiple cone normal stepping, K stacked cones (Burger 3.4, method 1); form=safe|textbook", Coarse)
                .param(steps("steps", 15))
                .param(cones(4))
                .param(form())
                .reads(multi_cone),
            def("pcns", "piecewise cone normal stepping, K cone pieces (Burger 3.4, method 2); form=safe|textbook", Coarse)
                .param(steps("steps", 15))
                .param(cones(4))
                .param(form())
                .reads(piecewise_cone),
            def("sphere", "sphere tracing a 3D distance field (Donnelly 2005)", Coarse)
                .param(steps("steps", 15))
                .reads(distance_field),
            def(
                "maxmip",
                "maximum-mipmap traversal with the exact bilinear patch in the finest cells (Tevs et al. 2008)",
                Coarse,
            )
            .param(steps("steps", 64))
            .reads(max_mip),
            def("none", "no refinement: the hit is the bracket's far end", Refine),
            def("binary", "binary search (Burger Algorithm 2)", Refine).param(steps("steps", 5)),
            def("interval", "interval mapping, false position (Burger Algorithm 3; Risser et al. 2005)", Refine)
                .param(steps("steps", 5)),
            def("secant", "the true secant method on the last two guesses (survey 4.2.3), guarded", Refine)
                .param(steps("steps", 5)),
            def("none", "no self-shadowing: visibility 1", Shadow),
            def("hard", "hard shadow: a coarse search toward the light (Amaro & Gustafsson 2.1.1)", Shadow)
                .param(ParamDef::stage_or("search", Slot::Coarse, 16)),
            def(
                "soft",
                "soft shadow from the deepest blocker, 1 - w/(0.24 + w) (Tatarchuk 2006; Amaro & Gustafsson 2.1.2)",
                Shadow,
            )
            .param(steps("steps", 16)),
            def(
                "soft_cone",
                "soft shadow from the cone-normal distance d = h n_z (Burger 3.2) with penumbra k d / t",
                Shadow,
            )
            .param(steps("steps", 16))
            .reads(cone_normal),
            def("soft_ratio", "the same soft shadow from CSM's cone ratio", Shadow)
                .param(steps("steps", 16))
                .reads(cone),
            def("none", "no ambient occlusion: factor 1", Ao),
            def("cone_ratio", "ambient occlusion from the cone ratio at the hit (Burger 4.5)", Ao).reads(cone),
            def("cone_normal", "ambient occlusion from the cone normal at the hit (Burger 4.5)", Ao)
                .reads(cone_normal),
        ]
    })
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
