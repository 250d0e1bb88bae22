//! The catalogue of methods: names, slots, parameters, defaults and maps. The text form, the
//! macros and `relief gen --list` all read it, so they cannot disagree.

use std::sync::OnceLock;

use super::{MapReq, Slot, StageSpec, Value};

/// The largest step count any parameter accepts.
pub const MAX_STEPS: u32 = 4096;

/// What a parameter accepts.
#[derive(Clone, Debug, PartialEq)]
pub enum ParamKind {
    /// A step count in `1..=MAX_STEPS`.
    Steps,
    /// A whole number in `min..=max`.
    Count { min: u32, max: u32 },
    /// One word of a fixed set.
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
    pub name: &'static str,
    pub kind: ParamKind,
    /// `None`: the parameter must be given.
    pub default: Option<Value>,
}

/// One method: its slot, parameters and the maps it reads.
#[derive(Clone)]
pub struct MethodDef {
    pub name: &'static str,
    pub slot: Slot,
    /// One line for `relief gen --list`, with the source.
    pub summary: &'static str,
    pub params: Vec<ParamDef>,
    /// The maps a stage with these parameters reads, besides the height map.
    pub maps: fn(&StageSpec) -> Vec<MapReq>,
    /// Whether stage code exists for it (the catalogue may name methods still to come).
    pub implemented: bool,
}

impl MethodDef {
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

fn no_maps(_: &StageSpec) -> Vec<MapReq> {
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
    vec![if s.word("form") == "textbook" { textbook } else { safe }]
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

/// `form=safe|textbook` of the cone methods: `safe` (the default) steps on cones of the
/// bilinear cells and never passes the first hit; `textbook` steps on the texel-sample maps
/// as the papers print it.
fn form() -> ParamDef {
    choice("form", &["safe", "textbook"])
}
fn distance_field(_: &StageSpec) -> Vec<MapReq> {
    vec![MapReq::DistanceField]
}
fn max_mip(_: &StageSpec) -> Vec<MapReq> {
    vec![MapReq::MaxMip]
}

fn cones(default: u32) -> ParamDef {
    ParamDef { name: "k", kind: ParamKind::Count { min: 1, max: 4 }, default: Some(Value::Int(default)) }
}

fn choice(name: &'static str, words: &'static [&'static str]) -> ParamDef {
    ParamDef { name, kind: ParamKind::Choice(words), default: Some(Value::Word(words[0].to_string())) }
}

fn steps(name: &'static str, default: u32) -> ParamDef {
    ParamDef { name, kind: ParamKind::Steps, default: Some(Value::Int(default)) }
}

fn def(
    slot: Slot,
    name: &'static str,
    summary: &'static str,
    params: Vec<ParamDef>,
    maps: fn(&StageSpec) -> Vec<MapReq>,
) -> MethodDef {
    MethodDef { name, slot, summary, params, maps, implemented: true }
}

/// Every method relief knows, in listing order.
pub fn catalog() -> &'static [MethodDef] {
    static CATALOG: OnceLock<Vec<MethodDef>> = OnceLock::new();
    CATALOG.get_or_init(|| {
        use Slot::*;
        vec![
            def(Coarse, "none", "plain texture mapping: the hit is the entry point", vec![], no_maps),
            def(Coarse, "parallax", "parallax mapping (Kaneko et al. 2001; Burger eq. 2.3-2.5)", vec![], no_maps),
            def(Coarse, "offset_limited", "parallax with offset limiting (Welsh 2004; survey 4.1.3)", vec![], no_maps),
            def(Coarse, "slope_parallax", "parallax along the normal map's slope (survey 4.1.4)", vec![], normal_map),
            def(Coarse, "iterative_parallax", "iterative parallax with slope (Premecz 2006; survey 4.2.1)", vec![steps("steps", 4)], normal_map),
            def(Coarse, "linear", "linear search (Burger Algorithm 1)", vec![steps("steps", 32)], no_maps),
            def(
                Coarse,
                "linear_dynamic",
                "linear search, step count from the view angle (Tatarchuk 2006; Amaro & Gustafsson 2.1.3)",
                vec![steps("min", 8), steps("max", 32)],
                no_maps,
            ),
            def(
                Coarse,
                "csm",
                "cone step mapping (Dummer 2006; Burger Algorithm 4); form=safe|textbook; sample=linear|nearest|min4 for form=textbook (Burger 4.3.1), auto: the cell's cone (safe) or linear (textbook)",
                vec![steps("steps", 15), form(), choice("sample", &["auto", "linear", "nearest", "min4"])],
                csm_maps,
            ),
            def(Coarse, "qcsm", "quad-directional cone stepping (Policarpo & Oliveira, GPU Gems 3 18.4.1); form=safe|textbook", vec![steps("steps", 15), form()], quad_cone),
            def(
                Coarse,
                "rcs",
                "relaxed cone stepping (GPU Gems 3 Listing 18-3); form=safe|textbook; start=hk|bracket (Fig. 18-10), auto: bracket (safe) or hk (textbook)",
                vec![steps("steps", 15), form(), choice("start", &["auto", "hk", "bracket"])],
                relaxed_cone,
            ),
            def(Coarse, "cns", "cone normal stepping (Burger 3.3, eq. 3.2); form=safe|textbook", vec![steps("steps", 15), form()], cns_maps),
            def(Coarse, "rcns", "relaxed cone normal stepping (Burger 4.3.4); form=safe|textbook", vec![steps("steps", 15), form()], relaxed_cone_normal),
            def(
                Coarse,
                "mcns",
                "multiple cone normal stepping, K stacked cones (Burger 3.4, method 1); form=safe|textbook",
                vec![steps("steps", 15), cones(4), form()],
                multi_cone,
            ),
            def(
                Coarse,
                "pcns",
                "piecewise cone normal stepping, K cone pieces (Burger 3.4, method 2); form=safe|textbook",
                vec![steps("steps", 15), cones(4), form()],
                piecewise_cone,
            ),
            def(Coarse, "sphere", "sphere tracing a 3D distance field (Donnelly 2005)", vec![steps("steps", 15)], distance_field),
            def(Coarse, "maxmip", "maximum-mipmap traversal with the exact bilinear patch in the finest cells (Tevs et al. 2008)", vec![steps("steps", 64)], max_mip),
            def(Refine, "none", "no refinement: the hit is the bracket's far end", vec![], no_maps),
            def(Refine, "binary", "binary search (Burger Algorithm 2)", vec![steps("steps", 5)], no_maps),
            def(Refine, "interval", "interval mapping, false position (Burger Algorithm 3; Risser et al. 2005)", vec![steps("steps", 5)], no_maps),
            def(Refine, "secant", "the true secant method on the last two guesses (survey 4.2.3), guarded", vec![steps("steps", 5)], no_maps),
            def(Shadow, "none", "no self-shadowing: visibility 1", vec![], no_maps),
            def(
                Shadow,
                "hard",
                "hard shadow: a coarse search toward the light (Amaro & Gustafsson 2.1.1)",
                vec![ParamDef { name: "search", kind: ParamKind::StageOr(Coarse), default: Some(Value::Int(16)) }],
                no_maps,
            ),
            def(
                Shadow,
                "soft",
                "soft shadow from the deepest blocker, 1 - w/(0.24 + w) (Tatarchuk 2006; Amaro & Gustafsson 2.1.2)",
                vec![steps("steps", 16)],
                no_maps,
            ),
            def(
                Shadow,
                "soft_cone",
                "soft shadow from the cone-normal distance d = h n_z (Burger 3.2) with penumbra k d / t",
                vec![steps("steps", 16)],
                cone_normal,
            ),
            def(Shadow, "soft_ratio", "the same soft shadow from CSM's cone ratio", vec![steps("steps", 16)], cone),
            def(Ao, "none", "no ambient occlusion: factor 1", vec![], no_maps),
            def(Ao, "cone_ratio", "ambient occlusion from the cone ratio at the hit (Burger 4.5)", vec![], cone),
            def(Ao, "cone_normal", "ambient occlusion from the cone normal at the hit (Burger 4.5)", vec![], cone_normal),
        ]
    })
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
