//! The pipeline as data: which method fills each slot (coarse, refine, shadow, ao) and with
//! which parameters, its canonical text form, and the maps it needs.
//!
//! # Text form
//!
//! `COARSE[+REFINE][+shadow=SHADOW][+ao=AO][+lod=LOD][+silhouette=SILHOUETTE][+curved=CURVED]`, for example
//! `linear(10)+binary(5)` or `linear(10)+interval(3)+shadow=soft(30)+lod=auto`. Names are lower_snake. Parameters are positional
//! or named (`linear(steps=10)`, `csm(15, form=textbook, sample=min4)`), and a parameter may itself be a
//! stage (`shadow=hard(linear(20))`). Slots may also be named explicitly
//! (`coarse=linear(10)+refine=binary(5)`). Left-out slots are `none`, left-out parameters take
//! their defaults. [`Pipeline`]'s `Display` prints the canonical form: positional numbers,
//! named options only where they differ from the default, `none` slots left out.
//!
//! After the slots come the pipeline-level [`options`]: `lod=zero|auto|level(k)` (which mip
//! level the stages sample, default `zero`), `silhouette=none|clip` (default `none`) and
//! `curved=none|quadric|prism` (absent: the flat tile; present: a mesh module), printed only
//! where they differ from the default. Grids and the macros take them as
//! entries like the slots (`lod: [zero, auto]`), a grid repeating its pipelines once per
//! value.
//!
//! ```
//! use relief_dsl::spec::Pipeline;
//! let p: Pipeline = "linear( steps = 10 ) + binary(5)".parse().unwrap();
//! assert_eq!(p.to_string(), "linear(10)+binary(5)");
//! let p: Pipeline = "linear(32)+binary(5)+lod=level(2)".parse().unwrap();
//! assert_eq!(p.lod, relief_dsl::spec::Lod::Level(2));
//! let err = "lnear(10)".parse::<Pipeline>().unwrap_err();
//! assert!(err.to_string().contains("did you mean `linear`"));
//! ```
//!
//! # How text is read
//!
//! One lexer (`lex`) and one parser ([`parse_pattern`]) read both text forms: a pipeline is
//! a grid with one stage per slot, so both parse into a [`grid::GridPattern`]. The macros
//! (relief-macros) build the same patterns from Rust tokens. A pattern is expanded (ranges,
//! lists) and each stage is checked against the [`catalog`] by [`resolve_stage`];
//! [`grid::GridPattern::pipeline`] makes the one pipeline of a pipeline text, and
//! `grid::GridPattern::expand` the [`Grid`] of a grid text. Every error is a
//! [`ParseError`]; "did you mean" comes from [`suggest::nearest`].

mod catalog;
mod choice;
mod echo;
pub mod grid;
mod lex;
pub mod options;
mod parse;
mod resolve;
pub mod suggest;

use std::fmt;
use std::str::FromStr;

pub use catalog::{
    catalog, method, no_maps, register, Args, Catalog, MethodDef, ParamDef, ParamKind, RegisterError, StageFn,
    StageLayer, StageOr, Stages, MAX_STEPS,
};
pub use choice::{Choice, ConeForm, SampleChoice, StartChoice};
pub use echo::{echo, one_line, ECHO_MAX, LINE_MAX};
pub use grid::Grid;
pub use options::{Curved, Lod, OptionKey, Silhouette, MAX_LOD_LEVEL};
pub use parse::ParseError;
// The parser's pieces for the macros (relief-macros): not part of the documented surface,
// reached through `crate::__private`.
#[doc(hidden)]
pub use parse::{parse_pattern, slot_named, TextForm, MAX_DEPTH};
#[doc(hidden)]
pub use resolve::{resolve_stage, RawArg, RawStage, RawValue};

/// The four slots of a pipeline.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Slot {
    /// Finds a bracket around the first intersection.
    Coarse,
    /// Narrows the bracket down to a hit.
    Refine,
    /// Visibility of the light from the hit.
    Shadow,
    /// Ambient occlusion at the hit.
    Ao,
}

impl Slot {
    /// All slots in pipeline order.
    pub const ALL: [Slot; 4] = [Slot::Coarse, Slot::Refine, Slot::Shadow, Slot::Ao];
    /// The slot's name in the text form.
    pub fn name(self) -> &'static str {
        match self {
            Slot::Coarse => "coarse",
            Slot::Refine => "refine",
            Slot::Shadow => "shadow",
            Slot::Ao => "ao",
        }
    }
}

impl fmt::Display for Slot {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A parameter value.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Value {
    /// A whole number (step counts, cone counts).
    Int(u32),
    /// A word from a fixed choice (`min4`, `hk`).
    Word(String),
    /// A nested stage (`hard(linear(20))`).
    Stage(Box<StageSpec>),
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Int(n) => write!(f, "{n}"),
            Value::Word(w) => f.write_str(w),
            Value::Stage(s) => write!(f, "{s}"),
        }
    }
}

/// One method with all its parameters resolved (defaults filled in), in declaration order.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct StageSpec {
    /// The method's name, e.g. `linear`.
    pub name: String,
    /// `(parameter name, value)` for every parameter of the method, in its declared order.
    pub params: Vec<(String, Value)>,
}

impl StageSpec {
    /// The `none` method of any slot.
    pub fn none() -> Self {
        StageSpec { name: "none".into(), params: vec![] }
    }
    /// Whether this is the `none` method.
    pub fn is_none(&self) -> bool {
        self.name == "none"
    }
    /// The value of parameter `name`.
    pub fn get(&self, name: &str) -> Option<&Value> {
        self.params.iter().find(|(n, _)| n == name).map(|(_, v)| v)
    }
    /// The whole-number parameter `name` (0 when missing, which resolution rules out).
    pub fn int(&self, name: &str) -> u32 {
        match self.get(name) {
            Some(Value::Int(n)) => *n,
            _ => 0,
        }
    }
    /// The word parameter `name`.
    pub fn word(&self, name: &str) -> &str {
        match self.get(name) {
            Some(Value::Word(w)) => w,
            _ => "",
        }
    }
    /// Builds a spec from a method name and parameters given in order, checking them the
    /// same way the text form does.
    pub fn new(slot: Slot, name: &str, params: &[Value]) -> Result<Self, ParseError> {
        let args: Vec<resolve::Arg> =
            params.iter().map(|v| resolve::Arg { name: None, value: v.clone().into(), pos: 0 }).collect();
        resolve::resolve(slot, name, 0, args)
    }
}

impl fmt::Display for StageSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.name)?;
        let Some(def) = catalog::method_any(&self.name) else {
            return Ok(());
        };
        let mut parts = Vec::new();
        for (pdef, (_, v)) in def.params.iter().zip(&self.params) {
            match pdef.kind {
                ParamKind::Choice(_) => {
                    if pdef.default.as_ref() != Some(v) {
                        parts.push(format!("{}={v}", pdef.name));
                    }
                }
                _ => parts.push(v.to_string()),
            }
        }
        if !parts.is_empty() {
            write!(f, "({})", parts.join(", "))?;
        }
        Ok(())
    }
}

/// A whole pipeline: one method per slot, and the pipeline-level [`options`].
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Pipeline {
    /// Finds a bracket around the first intersection.
    pub coarse: StageSpec,
    /// Narrows the bracket down to a hit (`none`: the bracket's far end).
    pub refine: StageSpec,
    /// Visibility of the light from the hit (`none`: 1).
    pub shadow: StageSpec,
    /// Ambient occlusion at the hit (`none`: 1).
    pub ao: StageSpec,
    /// The mip level the stages sample (`lod=`, default [`Lod::Zero`]).
    pub lod: Lod,
    /// What happens where the ray leaves the tile (`silhouette=`, default
    /// [`Silhouette::None`]); carried and printed, its behaviour is the composer's.
    pub silhouette: Silhouette,
    /// The mesh module's correction for a curved base surface (`curved=`); `None` (absent):
    /// the flat tile's module.
    pub curved: Option<Curved>,
}

impl Pipeline {
    /// A pipeline from its four stages, with the default options.
    pub fn new(coarse: StageSpec, refine: StageSpec, shadow: StageSpec, ao: StageSpec) -> Self {
        Pipeline { coarse, refine, shadow, ao, lod: Lod::Zero, silhouette: Silhouette::None, curved: None }
    }
    /// The pipeline with option `lod`.
    pub fn with_lod(mut self, lod: Lod) -> Self {
        self.lod = lod;
        self
    }
    /// The pipeline with option `silhouette`.
    pub fn with_silhouette(mut self, silhouette: Silhouette) -> Self {
        self.silhouette = silhouette;
        self
    }
    /// The pipeline with option `curved` (`None`: the flat tile).
    pub fn with_curved(mut self, curved: Option<Curved>) -> Self {
        self.curved = curved;
        self
    }
    /// The stage in `slot`.
    pub fn slot(&self, slot: Slot) -> &StageSpec {
        match slot {
            Slot::Coarse => &self.coarse,
            Slot::Refine => &self.refine,
            Slot::Shadow => &self.shadow,
            Slot::Ao => &self.ao,
        }
    }
    /// Mutable access to the stage in `slot`.
    pub fn slot_mut(&mut self, slot: Slot) -> &mut StageSpec {
        match slot {
            Slot::Coarse => &mut self.coarse,
            Slot::Refine => &mut self.refine,
            Slot::Shadow => &mut self.shadow,
            Slot::Ao => &mut self.ao,
        }
    }

    /// The maps the pipeline's stages read, besides the height map every pipeline reads,
    /// without duplicates, in a stable order.
    pub fn required_maps(&self) -> Vec<MapReq> {
        let mut out = Vec::new();
        for slot in Slot::ALL {
            collect_maps(slot, self.slot(slot), &mut out);
        }
        out.sort();
        out.dedup();
        out
    }

    /// The maps the stage in `slot` reads (with the stages it nests), besides the height map,
    /// without duplicates, in a stable order: [`Pipeline::required_maps`] for one slot.
    pub fn maps_of(&self, slot: Slot) -> Vec<MapReq> {
        let mut out = Vec::new();
        collect_maps(slot, self.slot(slot), &mut out);
        out.sort();
        out.dedup();
        out
    }

    /// The canonical text made safe as a file name: `(` → `_`, `)` dropped, `,` → `_`,
    /// `=` → `-`, `+` → `__`, spaces dropped. `linear(10)+binary(5)+shadow=soft(30)` becomes
    /// `linear_10__binary_5__shadow-soft_30`.
    pub fn file_stem(&self) -> String {
        file_safe(&self.to_string())
    }

    /// Every combination of the methods in the catalogue at default parameters, for the
    /// slots coarse, refine and shadow (ao `none`), in catalogue order.
    pub fn all_defaults() -> Vec<Pipeline> {
        let of = |slot: Slot| -> Vec<StageSpec> {
            catalog().iter().filter(|m| m.slot == slot).map(|m| m.default_spec()).collect()
        };
        let mut out = Vec::new();
        for c in of(Slot::Coarse) {
            for r in of(Slot::Refine) {
                for s in of(Slot::Shadow) {
                    out.push(Pipeline::new(c.clone(), r.clone(), s.clone(), StageSpec::none()));
                }
            }
        }
        out
    }
}

/// See [`Pipeline::file_stem`].
pub fn file_safe(text: &str) -> String {
    let mut s = String::new();
    for ch in text.chars() {
        match ch {
            '(' | ',' => s.push('_'),
            ')' | ' ' => {}
            '=' => s.push('-'),
            '+' => s.push_str("__"),
            c => s.push(c),
        }
    }
    s
}

fn collect_maps(slot: Slot, spec: &StageSpec, out: &mut Vec<MapReq>) {
    if let Some(def) = method(slot, &spec.name) {
        out.extend((def.maps)(spec));
        for (pdef, (_, v)) in def.params.iter().zip(&spec.params) {
            if let (ParamKind::StageOr(inner_slot), Value::Stage(inner)) = (&pdef.kind, v) {
                collect_maps(*inner_slot, inner, out);
            }
        }
    }
}

/// A map a stage reads, besides the height map. Names, channels and units are those of
/// `relief maps` (relief-runtime's `maps` module).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum MapReq {
    /// The tangent-space normal map (encoded `n * 0.5 + 0.5`).
    Normal,
    /// Conservative cone ratio (CSM).
    Cone,
    /// Four quadrant cone ratios (QCSM), channels `+u+v, -u+v, -u-v, +u-v`.
    QuadCone,
    /// Relaxed cone ratio (RCS).
    RelaxedCone,
    /// `n_z` of the conservative cone (CNS).
    ConeNormal,
    /// `n_z` of the relaxed cone (RCNS).
    RelaxedConeNormal,
    /// `n_z` of K stacked cones (MCNS), K channels.
    MultiCone(u32),
    /// `n_z` of K piecewise cone slopes (PCNS), K channels.
    PiecewiseCone(u32),
    /// The maximum-height pyramid over the bilinear cells, as a mip chain.
    MaxMip,
    /// 3D Euclidean distance to the surface.
    DistanceField,
    /// Per bilinear cell: the conservative cone ratio (the apex, the cell's highest corner,
    /// is read from the height map).
    CellCone,
    /// Per bilinear cell: four quadrant cone ratios, each with the cell's apex, one texel per
    /// quadrant of the ray's direction: the cell `(i, j)` is the 2 × 2 texels `(2i + qx,
    /// 2j + qy)`, `qx` = 1 for a ray moving toward +u (0 toward −u), `qy` likewise for v,
    /// each `[ratio, apex]` ([`MapReq::cell_texels`]).
    CellQuadCone,
    /// Per bilinear cell: the relaxed cone ratio.
    CellRelaxedCone,
    /// Per bilinear cell: `n_z` of the conservative cone.
    CellConeNormal,
    /// Per bilinear cell: `n_z` of K stacked cones, K channels.
    CellMultiCone(u32),
    /// Per bilinear cell: `n_z` of K piecewise cone slopes, K channels.
    CellPiecewiseCone(u32),
    /// Per bilinear cell: the coefficients `(h00, h10 − h00, h01 − h00, (h11 − h10) −
    /// (h01 − h00))` of its bilinear patch, read by the safe cone marches whose cell map
    /// carries its apex in place of a gather of the four corners.
    CellPatch,
}

impl MapReq {
    /// The name used for the map's shader binding and its kind in `relief maps`.
    pub fn name(self) -> &'static str {
        match self {
            MapReq::Normal => "normal",
            MapReq::Cone => "cone",
            MapReq::QuadCone => "quad_cone",
            MapReq::RelaxedCone => "relaxed_cone",
            MapReq::ConeNormal => "cone_normal",
            MapReq::RelaxedConeNormal => "relaxed_cone_normal",
            MapReq::MultiCone(_) => "multi_cone",
            MapReq::PiecewiseCone(_) => "piecewise_cone",
            MapReq::MaxMip => "max_mip",
            MapReq::DistanceField => "distance_field",
            MapReq::CellCone => "cell_cone",
            MapReq::CellQuadCone => "cell_quad_cone",
            MapReq::CellRelaxedCone => "cell_relaxed_cone",
            MapReq::CellConeNormal => "cell_cone_normal",
            MapReq::CellMultiCone(_) => "cell_multi_cone",
            MapReq::CellPiecewiseCone(_) => "cell_piecewise_cone",
            MapReq::CellPatch => "cell_patch",
        }
    }

    /// The shader binding (group 0) the map is bound at.
    pub fn binding(self) -> u32 {
        use crate::abi::binding as b;
        match self {
            MapReq::Normal => b::NORMAL,
            MapReq::Cone => b::CONE,
            MapReq::QuadCone => b::QUAD_CONE,
            MapReq::RelaxedCone => b::RELAXED_CONE,
            MapReq::ConeNormal => b::CONE_NORMAL,
            MapReq::RelaxedConeNormal => b::RELAXED_CONE_NORMAL,
            MapReq::MultiCone(_) => b::MULTI_CONE,
            MapReq::PiecewiseCone(_) => b::PIECEWISE_CONE,
            MapReq::MaxMip => b::MAX_MIP,
            MapReq::DistanceField => b::DISTANCE_FIELD,
            MapReq::CellCone => b::CELL_CONE,
            MapReq::CellQuadCone => b::CELL_QUAD_CONE,
            MapReq::CellRelaxedCone => b::CELL_RELAXED_CONE,
            MapReq::CellConeNormal => b::CELL_CONE_NORMAL,
            MapReq::CellMultiCone(_) => b::CELL_MULTI_CONE,
            MapReq::CellPiecewiseCone(_) => b::CELL_PIECEWISE_CONE,
            MapReq::CellPatch => b::CELL_PATCH,
        }
    }

    /// Whether the runtime can give the map a mip chain of its own level's data, so that a
    /// stage may read it at a level other than 0 (`lod=auto`, `lod=level(k)`): the normal map
    /// (box-filtered like the height map) and the texel maps defined per texel sample of the
    /// height map in texture units (cone ratios and cone normals), which relief-runtime
    /// builds again from each level of the height map's mip chain. Not the per-cell maps (one
    /// texel per bilinear cell of level 0), the max-mip pyramid or the 3D distance field.
    pub fn has_levels(self) -> bool {
        match self {
            MapReq::Normal
            | MapReq::Cone
            | MapReq::QuadCone
            | MapReq::RelaxedCone
            | MapReq::ConeNormal
            | MapReq::RelaxedConeNormal
            | MapReq::MultiCone(_)
            | MapReq::PiecewiseCone(_) => true,
            MapReq::MaxMip
            | MapReq::DistanceField
            | MapReq::CellCone
            | MapReq::CellQuadCone
            | MapReq::CellRelaxedCone
            | MapReq::CellConeNormal
            | MapReq::CellMultiCone(_)
            | MapReq::CellPiecewiseCone(_)
            | MapReq::CellPatch => false,
        }
    }

    /// The values per texel of the map as relief-runtime builds it (before the upload drops
    /// what no texel holds: [`crate::abi::cell_apex_on_device`]): the one place each kind's
    /// count is stated. A cell map ([`MapReq::is_cell`]) carries its apex `A_C`, the cell's
    /// highest corner, in the last channel, after its cones.
    pub fn channels(self) -> usize {
        match self {
            MapReq::Normal => 3,
            MapReq::Cone
            | MapReq::RelaxedCone
            | MapReq::ConeNormal
            | MapReq::RelaxedConeNormal
            | MapReq::MaxMip
            | MapReq::DistanceField => 1,
            MapReq::QuadCone => 4,
            MapReq::MultiCone(k) | MapReq::PiecewiseCone(k) => k as usize,
            MapReq::CellCone | MapReq::CellRelaxedCone | MapReq::CellConeNormal | MapReq::CellQuadCone => 2,
            MapReq::CellPatch => 4,
            MapReq::CellMultiCone(k) | MapReq::CellPiecewiseCone(k) => k as usize + 1,
        }
    }

    /// The number K of cones the map holds per texel, for the kinds that take it (stacked
    /// and piecewise cones, per texel or per cell); `None` for the others.
    pub fn cones(self) -> Option<u32> {
        match self {
            MapReq::MultiCone(k)
            | MapReq::PiecewiseCone(k)
            | MapReq::CellMultiCone(k)
            | MapReq::CellPiecewiseCone(k) => Some(k),
            MapReq::Normal
            | MapReq::Cone
            | MapReq::QuadCone
            | MapReq::RelaxedCone
            | MapReq::ConeNormal
            | MapReq::RelaxedConeNormal
            | MapReq::MaxMip
            | MapReq::DistanceField
            | MapReq::CellCone
            | MapReq::CellQuadCone
            | MapReq::CellRelaxedCone
            | MapReq::CellConeNormal
            | MapReq::CellPatch => None,
        }
    }

    /// Whether the map holds one entry per bilinear cell of the height map, its apex last
    /// (the cell maps), rather than one per texel or a pyramid or a volume. Not the patch
    /// map ([`MapReq::CellPatch`]): one entry per cell too, but no apex ([`MapReq::per_cell`]).
    pub fn is_cell(self) -> bool {
        match self {
            MapReq::CellPatch => false,
            MapReq::CellCone
            | MapReq::CellQuadCone
            | MapReq::CellRelaxedCone
            | MapReq::CellConeNormal
            | MapReq::CellMultiCone(_)
            | MapReq::CellPiecewiseCone(_) => true,
            MapReq::Normal
            | MapReq::Cone
            | MapReq::QuadCone
            | MapReq::RelaxedCone
            | MapReq::ConeNormal
            | MapReq::RelaxedConeNormal
            | MapReq::MultiCone(_)
            | MapReq::PiecewiseCone(_)
            | MapReq::MaxMip
            | MapReq::DistanceField => false,
        }
    }

    /// Whether the map holds one entry per bilinear cell, on the cell grid (the cell maps
    /// and the patch map): read by cell index, uploaded under a `lod` as an atlas of every
    /// level's cells.
    pub fn per_cell(self) -> bool {
        self.is_cell() || self == MapReq::CellPatch
    }

    /// Whether a safe cell march over this cell map reads its cells' patches from the patch
    /// map ([`MapReq::CellPatch`]: one load at the cell's coordinate) instead of gathering
    /// the four corners: the cell cone, the cell cone normal and the quad cone map, which
    /// carry their apex on the device, so that their pass reads no corner at all outside the
    /// patch. The maps without the apex (stacked and piecewise cones) gather the corners every
    /// pass for the apex and reuse them for the patch, and the relaxed cone's march tests the
    /// point's height from gathered corners every pass: both keep the gather
    /// (`docs/notes/safe-step.md`, rounds 10 to 12).
    pub fn patches_read_with(self) -> bool {
        matches!(self, MapReq::CellCone | MapReq::CellConeNormal | MapReq::CellQuadCone)
    }

    /// Texels per cell along each axis of a per-cell map ([`MapReq::per_cell`]): 2 for the
    /// quad cone map, whose cell is 2 × 2 texels, one per quadrant of the ray's direction, so
    /// that a pass reads its quadrant's ratio and the apex in one texel (a ray moves toward
    /// one quadrant all its way: the texel is picked by its direction); 1 for the others.
    pub fn cell_texels(self) -> usize {
        if self == MapReq::CellQuadCone {
            2
        } else {
            1
        }
    }

    /// The map's texture name in the generated shader.
    pub fn texture_name(self) -> String {
        format!("{}_map", self.name())
    }
}

impl fmt::Display for Pipeline {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.coarse)?;
        if !self.refine.is_none() {
            write!(f, "+{}", self.refine)?;
        }
        if !self.shadow.is_none() {
            write!(f, "+shadow={}", self.shadow)?;
        }
        if !self.ao.is_none() {
            write!(f, "+ao={}", self.ao)?;
        }
        if self.lod != Lod::Zero {
            write!(f, "+lod={}", self.lod)?;
        }
        if self.silhouette != Silhouette::None {
            write!(f, "+silhouette={}", self.silhouette)?;
        }
        if let Some(c) = self.curved {
            write!(f, "+curved={c}")?;
        }
        Ok(())
    }
}

impl FromStr for Pipeline {
    type Err = ParseError;
    fn from_str(s: &str) -> Result<Self, ParseError> {
        parse_pattern(s, TextForm::Pipeline)?.pipeline()
    }
}
