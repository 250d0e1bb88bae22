//! The stage interface and the resources stages read.
//!
//! Conventions (ARCHITECTURE.md): texture space with u, v in texture coordinates and z the height
//! in [0, 1], the polygon at z = 1. A [`Ray`] enters at `(origin, 1)` with direction `dir`,
//! `dir.z < 0`, scaled so that t = 1 reaches z = 0. Every stage speaks in this t.
//!
//! - coarse: ray → [`Bracket`] (`above`: a t known to be above the surface, `below`: the first
//!   t found at or below it, `found`: whether it found one);
//! - refine: ray + bracket → [`Hit`];
//! - shadow: hit + light direction → visibility in [0, 1];
//! - ao: hit → ambient factor in [0, 1].
//!
//! A method that yields a single point (parallax and its relatives) returns
//! [`Bracket::point`]: the bracket from the ray's entry (t = 0) to that point, so that any
//! refine after it searches between the two. A search that runs out of steps before it
//! finds the surface returns [`Bracket::searched`] with `found` false.
//!
//! Each method is a function of one of the four [`StageFn`] shapes, declared once in its own
//! file as a [`MethodDef`] (name, citation, parameters, maps, stage function). Each slot's `mod.rs`
//! lists its methods, and [`Stages`] hands the lists to the catalogue
//! ([`crate::spec::catalog`]); [`crate::spec::register`] adds a method written outside relief
//! through the same [`MethodDef`].

pub(crate) mod ao;
pub(crate) mod coarse;
pub(crate) mod refine;
pub(crate) mod sampling;
pub(crate) mod shadow;

use crate::ir::{FnBuilder, IntoVal, Val, Vec2, Vec3};
use crate::spec::{Args, MethodDef, Slot, StageLayer, StageSpec, Stages};
use crate::CompileError;
pub(crate) use sampling::sample_level_global;
pub use sampling::Filter;

/// A coarse stage: writes the search for `ray` into the stage function and returns its
/// bracket.
pub type CoarseFn = for<'a> fn(&'a FnBuilder<'a>, &Ray<'a>, &Args) -> Result<Bracket<'a>, CompileError>;
/// A refine stage: narrows the bracket found for `ray` down to a hit.
pub type RefineFn = for<'a> fn(&'a FnBuilder<'a>, &Ray<'a>, Bracket<'a>, &Args) -> Result<Hit<'a>, CompileError>;
/// A shadow stage: the visibility of the light from the hit, in [0, 1].
pub type ShadowFn = for<'a> fn(&'a FnBuilder<'a>, &Hit<'a>, &Light<'a>, &Args) -> Result<Val<'a, f32>, CompileError>;
/// An ambient-occlusion stage: the ambient factor at the hit, in [0, 1].
pub type AoFn = for<'a> fn(&'a FnBuilder<'a>, &Hit<'a>, &Args) -> Result<Val<'a, f32>, CompileError>;

/// The function that writes a method's stage, by slot: what a [`MethodDef`] runs when a pipeline
/// names it. The [`Args`] are the method's parameters, already checked against
/// its parameter definitions.
#[derive(Clone, Copy, Debug)]
pub enum StageFn {
    /// A coarse search.
    Coarse(CoarseFn),
    /// A refinement.
    Refine(RefineFn),
    /// A shadow.
    Shadow(ShadowFn),
    /// Ambient occlusion.
    Ao(AoFn),
}

impl StageFn {
    /// The slot the function fills.
    pub fn slot(&self) -> Slot {
        match self {
            StageFn::Coarse(_) => Slot::Coarse,
            StageFn::Refine(_) => Slot::Refine,
            StageFn::Shadow(_) => Slot::Shadow,
            StageFn::Ao(_) => Slot::Ao,
        }
    }
}

/// The light as a shadow stage sees it.
#[derive(Clone, Copy)]
pub struct Light<'a> {
    /// Toward the light in normalized tangent space, scaled so that `dir.z = 1`: the light
    /// ray from the hit leaves the volume after `1 - hit.z`.
    pub dir: Val<'a, Vec3>,
    /// Cosine of the angle between the light direction and the surface normal.
    pub cos: Val<'a, f32>,
}

/// The stage layer's side of the catalogue: the type of a stage function and the built-in methods,
/// slot by slot in listing order (each slot's `methods`).
impl StageLayer for Stages {
    type StageFn = StageFn;
    fn slot(f: &StageFn) -> Slot {
        f.slot()
    }
    fn builtins() -> Vec<MethodDef> {
        [coarse::methods(), refine::methods(), shadow::methods(), ao::methods()].concat()
    }
}

/// The catalogue's stage function for the method of `slot` that `spec` names.
fn stage_fn_of(slot: Slot, spec: &StageSpec) -> Result<StageFn, CompileError> {
    let def = crate::spec::method(slot, &spec.name).ok_or_else(|| CompileError {
        stage: format!("{slot} {}", spec.name),
        message: format!("the catalogue has no {slot} method `{}`", spec.name),
    })?;
    Ok(def.stage_fn)
}

/// The error for a stage function of another slot than the one it is registered in, which
/// [`crate::spec::register`] refuses (so only a catalogue bug reaches it).
fn wrong_slot(slot: Slot, spec: &StageSpec, f: StageFn) -> CompileError {
    CompileError {
        stage: format!("{slot} {}", spec.name),
        message: format!("the catalogue's `{}` of the {slot} slot writes a {} stage", spec.name, f.slot()),
    }
}

/// Writes the coarse stage `spec` into the current function, with its catalogue stage function.
pub(crate) fn coarse<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>, spec: &StageSpec) -> Result<Bracket<'a>, CompileError> {
    match stage_fn_of(Slot::Coarse, spec)? {
        StageFn::Coarse(f) => f(s, ray, &Args::new(Slot::Coarse, spec)),
        other => Err(wrong_slot(Slot::Coarse, spec, other)),
    }
}

/// Writes the refine stage `spec` into the current function.
pub(crate) fn refine<'a>(
    s: &'a FnBuilder<'a>,
    ray: &Ray<'a>,
    b: Bracket<'a>,
    spec: &StageSpec,
) -> Result<Hit<'a>, CompileError> {
    match stage_fn_of(Slot::Refine, spec)? {
        StageFn::Refine(f) => f(s, ray, b, &Args::new(Slot::Refine, spec)),
        other => Err(wrong_slot(Slot::Refine, spec, other)),
    }
}

/// Writes the shadow stage `spec` into the current function.
pub(crate) fn shadow<'a>(
    s: &'a FnBuilder<'a>,
    hit: &Hit<'a>,
    light: &Light<'a>,
    spec: &StageSpec,
) -> Result<Val<'a, f32>, CompileError> {
    match stage_fn_of(Slot::Shadow, spec)? {
        StageFn::Shadow(f) => f(s, hit, light, &Args::new(Slot::Shadow, spec)),
        other => Err(wrong_slot(Slot::Shadow, spec, other)),
    }
}

/// Writes the ao stage `spec` into the current function.
pub(crate) fn ao<'a>(s: &'a FnBuilder<'a>, hit: &Hit<'a>, spec: &StageSpec) -> Result<Val<'a, f32>, CompileError> {
    match stage_fn_of(Slot::Ao, spec)? {
        StageFn::Ao(f) => f(s, hit, &Args::new(Slot::Ao, spec)),
        other => Err(wrong_slot(Slot::Ao, spec, other)),
    }
}

/// A ray in normalized tangent space.
#[derive(Clone, Copy)]
pub struct Ray<'a> {
    /// Texture coordinates where the ray enters the volume (z = 1).
    pub origin: Val<'a, Vec2>,
    /// Direction, `dir.z < 0`; t = 1 reaches z = 0 when `dir.z = -1`.
    pub dir: Val<'a, Vec3>,
    /// Cosine of the angle between the (unscaled) view ray and the surface normal.
    pub cos_view: Val<'a, f32>,
}

crate::ir::record!(Ray "Ray" { origin: Vec2, dir: Vec3, cos_view: f32 });

impl<'a> Ray<'a> {
    /// The point at parameter t: `(origin + t·dir.xy, 1 + t·dir.z)`.
    pub fn at(&self, t: impl IntoVal<'a, f32>) -> Val<'a, Vec3> {
        let s = self.origin.builder();
        let t = t.into_val(s);
        s.vec3(self.origin + self.dir.xy() * t, 1.0 + self.dir.z() * t)
    }
    /// The t at which the ray reaches z = 0, the bottom of the volume.
    pub fn t_max(&self) -> Val<'a, f32> {
        1.0 / -self.dir.z()
    }
}

/// What a coarse search found: an interval of the ray that holds the first intersection,
/// or, when the search ran out of steps first, the last point known to be above the surface.
#[derive(Clone, Copy)]
pub struct Bracket<'a> {
    /// A t above the surface: when `found` is false, the last such point the search knows of.
    pub above: Val<'a, f32>,
    /// A t at or below the surface when `found` holds (meaningless otherwise).
    pub below: Val<'a, f32>,
    /// Whether `[above, below]` holds a crossing. When it does not, no stage after the search
    /// reports anything past `above` (the composer skips the refinement: ARCHITECTURE.md, "The stage
    /// interface").
    pub found: Val<'a, bool>,
}

crate::ir::record!(Bracket "Bracket" { above: f32, below: f32, found: bool });

impl<'a> Bracket<'a> {
    /// The bracket `[above, below]`, a crossing found.
    pub fn new(above: Val<'a, f32>, below: Val<'a, f32>) -> Self {
        Bracket { above, below, found: above.builder().lit_bool(true) }
    }
    /// What a search that may run out of steps returns: `[above, below]` when `found`, else
    /// `above`, the last point it knows to be above the surface.
    pub fn searched(above: Val<'a, f32>, below: Val<'a, f32>, found: Val<'a, bool>) -> Self {
        Bracket { above, below, found }
    }
    /// A single point from a one-shot method, as the bracket from the entry to it. A one-shot
    /// method does not search, so its point counts as found; how often it lies above the
    /// surface is what `relief stability` measures.
    pub fn point(t: Val<'a, f32>) -> Self {
        let s = t.builder();
        Bracket::new(s.lit(0.0), t)
    }
}

/// A hit: the ray parameter, where it lands in texture space and its height.
///
/// The t is the search's raw result: nothing clamps it into the volume, so that the probe
/// measures what the search computed (a clamp that keeps a drawn pixel inside the volume
/// belongs to the fragment entry only).
#[derive(Clone, Copy)]
pub struct Hit<'a> {
    /// The ray parameter.
    pub t: Val<'a, f32>,
    /// Where the hit lands in texture coordinates.
    pub uv: Val<'a, Vec2>,
    /// The height at the hit (the ray's z at `t`).
    pub z: Val<'a, f32>,
    /// Whether the coarse search found the surface (false: the hit is the last point known
    /// to be above it).
    pub found: Val<'a, bool>,
}

crate::ir::record!(Hit "Hit" { t: f32, uv: Vec2, z: f32, found: bool });

impl<'a> Hit<'a> {
    /// The hit at parameter t along `ray`, as found.
    pub fn at(ray: &Ray<'a>, t: Val<'a, f32>) -> Self {
        Self::at_found(ray, t, t.builder().lit_bool(true))
    }
    /// The hit at parameter t along `ray`, `found` saying whether the search found the surface.
    pub fn at_found(ray: &Ray<'a>, t: Val<'a, f32>, found: Val<'a, bool>) -> Self {
        let p = ray.at(t);
        Hit { t, uv: p.xy(), z: p.z(), found }
    }
}
