//! Cone stepping and its relatives: each step jumps to where the ray leaves the empty cone
//! standing on the surface below the current point.
//!
//! Units (relief-runtime's `maps`): a cone ratio `r` is horizontal distance in texture
//! coordinates per unit of height; a cone normal `n_z = r / sqrt(1 + r²)`. For a ray point at
//! height `Δ` above the cone's apex, with horizontal speed `L = |d.xy|` and vertical speed
//! `-d.z`, the ray meets the cone's side after `r·Δ / (L + r·(-d.z))` (Burger Algorithm 4
//! with an unnormalized d).
//!
//! Every method comes in two forms ([`ConeForm`]):
//! - `textbook`: the papers' algorithm as printed, on the texel-sample maps (a cone per
//!   texel), the gap measured from the bilinear height under the point. The shader meets the
//!   bilinear surface between texel centres, which rises through texel cones, so these steps
//!   can pass the first hit (relief's cone tests measure by how much).
//! - `safe` (the default): the same step rule on cones of the bilinear *cells*, apex at the
//!   cell's highest corner ([`super::cell`]); where a step would stay in the cell the cell's
//!   patch is met exactly. Never past the first hit, no padding, no minimum step.
//!
//! Conservative methods (`csm`, `qcsm`, `cns`, `mcns`, `pcns`) stop at the first point at or
//! below the surface, or after their steps; relaxed methods (`rcs`, `rcns`) let the ray enter
//! the surface once and return the bracket around that crossing.

use super::cell::{relaxed_march, safe_march, Cell};
use crate::ir::{FnBuilder, Val, Vec3};
use crate::spec::{Args, Choice, MapReq, MethodDef, ParamDef, SampleChoice, StageSpec, StartChoice};
use crate::stage::{Bracket, Filter, Ray, StageFn};
use crate::CompileError;

/// Which cones a method steps on (see the module docs).
pub(crate) use crate::spec::ConeForm;

/// How the textbook CSM reads its cone map (Burger §4.3.1: linear filtering of ratios causes
/// artifacts; the minimum of the four texels fixes them at a cost).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ConeSample {
    Linear,
    Nearest,
    Min4,
}

/// Guards divisions by a speed that may be zero (a ray straight down into a zero-width cone).
const TINY: f32 = 1e-7;

/// Distance along the ray (in t) to the side of a cone of ratio `r` whose apex is `gap`
/// below the current point; `horiz` is the ray's horizontal speed `|d.xy|` (computed once
/// per ray where the caller can).
fn cone_step<'a>(horiz: Val<'a, f32>, ray: &Ray<'a>, r: Val<'a, f32>, gap: Val<'a, f32>) -> Val<'a, f32> {
    r * gap / (horiz + r * -ray.dir.z()).max(TINY)
}

/// The step to the plane of a cone side with normal z `n_z`, its apex `gap` below the ray
/// point: Burger eq. 3.2, `t = -gap·n_z / (n·d)` with `n = (-sqrt(1 - n_z²)·d̂_xy, n_z)`;
/// `horiz` is `|d.xy|`.
fn cone_normal_step<'a>(horiz: Val<'a, f32>, ray: &Ray<'a>, n_z: Val<'a, f32>, gap: Val<'a, f32>) -> Val<'a, f32> {
    let n_dot_d = -(1.0 - n_z * n_z).max(0.0).sqrt() * horiz + n_z * ray.dir.z();
    -gap * n_z / n_dot_d.min(-TINY)
}

/// The cone ratio of a cone side with normal z `n_z`: `r = n_z / sqrt(1 - n_z²)`.
fn ratio_of<'a>(n_z: Val<'a, f32>) -> Val<'a, f32> {
    n_z / (1.0 - n_z * n_z).max(TINY).sqrt()
}

/// The cone normal of a cone of ratio `r`: `n_z = r / sqrt(1 + r²)`.
fn normal_of<'a>(r: Val<'a, f32>) -> Val<'a, f32> {
    r / (1.0 + r * r).sqrt()
}

/// `form=safe|textbook` of the cone methods: `safe` (the default) steps on cones of the
/// bilinear cells and never passes the first hit; `textbook` steps on the texel-sample maps
/// as the papers print it.
fn form() -> ParamDef {
    ParamDef::choice::<ConeForm>("form")
}

/// `k`, the number of cones of `mcns` and `pcns`.
fn cones(default: u32) -> ParamDef {
    ParamDef::count("k", 1, 4, default)
}

/// The map a cone method reads: the texel-sample map for `form=textbook`, the cell map for
/// `form=safe`.
fn by_form(s: &StageSpec, textbook: MapReq, safe: MapReq) -> Vec<MapReq> {
    // A word outside the choice (only a hand-edited spec has one) fails to compile; the safe
    // form's map is as good a guess as any for it.
    match ConeForm::from_word(s.word("form")) {
        Some(ConeForm::Textbook) => vec![textbook],
        Some(ConeForm::Safe) | None => with_patches(safe),
    }
}

/// A safe march's cell map, and the patch map where the march reads its cells' patches
/// there ([`MapReq::patches_read_with`]).
pub(super) fn with_patches(cells: MapReq) -> Vec<MapReq> {
    if cells.patches_read_with() {
        vec![cells, MapReq::CellPatch]
    } else {
        vec![cells]
    }
}

/// The error for a sampling choice of the textbook form given with `form=safe`.
fn only_textbook(stage: &str, what: &str) -> CompileError {
    CompileError {
        stage: format!("coarse {stage}"),
        message: format!(
            "`{what}` applies to `form=textbook` only: the safe form reads the cone of the cell under the ray point"
        ),
    }
}

/// Where the textbook loop ended.
#[derive(Clone, Copy)]
struct Marched<'a> {
    /// The last point checked and found above the surface.
    prev: Val<'a, f32>,
    /// The point the loop ended at: at or below the surface when `found`; otherwise where
    /// the last step led, not checked.
    end: Val<'a, f32>,
    found: Val<'a, bool>,
}

impl<'a> Marched<'a> {
    /// The bracket of a conservative method as printed: out of steps, the method trusts its
    /// cones and ends where the last step led.
    fn conservative(self) -> Bracket<'a> {
        let s = self.end.builder();
        Bracket::searched(s.select(self.found, self.prev, self.end), self.end, self.found)
    }
    /// The bracket of a relaxed method: out of steps, the last point checked.
    fn relaxed(self) -> Bracket<'a> {
        Bracket::searched(self.prev, self.end, self.found)
    }
}

/// Burger's Algorithm 4 loop as printed: for each of `steps` passes, h ← GETHEIGHT(p.xy); if
/// h ≥ p.z the search is over, else advance by the cone step `step(p, h)`.
fn textbook_march<'a>(
    s: &'a FnBuilder<'a>,
    ray: &Ray<'a>,
    steps: u32,
    step: impl Fn(&'a FnBuilder<'a>, Val<'a, Vec3>, Val<'a, f32>) -> Val<'a, f32>,
) -> Marched<'a> {
    let mut t = s.var("t", 0.0);
    let t_prev = s.var("t_prev", 0.0);
    let found = s.var("found", false);
    s.repeat(steps, |l| {
        let p = ray.at(t);
        let h = l.height(p.xy()).named("h");
        found.set(h.ge(p.z()));
        l.break_if(found.get());
        t_prev.set(t);
        t += step(l, p, h);
    });
    Marched { prev: t_prev.get(), end: t.get(), found: found.get() }
}

/// The textbook cone ratio under `uv`.
fn ratio<'a>(s: &'a FnBuilder<'a>, uv: Val<'a, crate::ir::Vec2>, sample: ConeSample) -> Val<'a, f32> {
    match sample {
        ConeSample::Linear => s.map(MapReq::Cone, uv, Filter::Linear).x(),
        ConeSample::Nearest => s.map(MapReq::Cone, uv, Filter::Nearest).x(),
        ConeSample::Min4 => s.map_min4(MapReq::Cone, uv),
    }
}

/// Cone step mapping (Dummer 2006; Burger Algorithm 4): while above the surface, step to the
/// side of the conservative cone below.
pub(crate) fn csm<'a>(
    s: &'a FnBuilder<'a>,
    ray: &Ray<'a>,
    steps: u32,
    form: ConeForm,
    sample: ConeSample,
) -> Bracket<'a> {
    match form {
        ConeForm::Safe => safe_march(s, ray, steps, Some(MapReq::CellCone), |s, p, c| {
            let (cone, apex) = c.cones_and_apex(s, MapReq::CellCone);
            cone_step(c.grid.horiz, ray, cone.x().named("r"), c.over(p.z(), apex))
        }),
        ConeForm::Textbook => textbook_march(s, ray, steps, |s, p, h| {
            let r = ratio(s, p.xy(), sample).named("r");
            cone_step(ray.dir.xy().length(), ray, r, p.z() - h)
        })
        .conservative(),
    }
}

/// The safe CSM step from the ray point `p` in cell `c`: the cone step from the cell's apex on
/// its cone in the cell cone map (how far, in t, the ray stays above the surface).
pub(super) fn cell_cone_step<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>, p: Val<'a, Vec3>, c: &Cell<'a>) -> Val<'a, f32> {
    let (cone, apex) = c.cones_and_apex(s, MapReq::CellCone);
    let r = cone.x().named("r");
    cone_step(c.grid.horiz, ray, r, c.clearance(p.z(), apex))
}

/// `csm(steps, form, sample)`: [`csm`] in the catalogue.
pub(crate) fn csm_def() -> MethodDef {
    MethodDef::new(
        "csm",
        "cone step mapping (Dummer 2006; Burger Algorithm 4); form=safe|textbook; sample=linear|nearest|min4 for form=textbook (Burger 4.3.1), auto: the cell's cone (safe) or linear (textbook)",
        StageFn::Coarse(csm_stage),
    )
    .param(ParamDef::steps("steps", 15))
    .param(form())
    .param(ParamDef::choice::<SampleChoice>("sample"))
    .reads(|s| by_form(s, MapReq::Cone, MapReq::CellCone))
}

/// `sample=auto` is the safe form's cell cone or the textbook's linear read; a textbook
/// sampling with `form=safe` is an error, not ignored.
fn csm_stage<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>, a: &Args) -> Result<Bracket<'a>, CompileError> {
    let form = a.choice::<ConeForm>("form")?;
    let sample = match (form, a.choice::<SampleChoice>("sample")?) {
        (ConeForm::Safe, SampleChoice::Auto) => ConeSample::Linear,
        (ConeForm::Textbook, SampleChoice::Auto | SampleChoice::Linear) => ConeSample::Linear,
        (ConeForm::Textbook, SampleChoice::Nearest) => ConeSample::Nearest,
        (ConeForm::Textbook, SampleChoice::Min4) => ConeSample::Min4,
        (ConeForm::Safe, SampleChoice::Linear) => return Err(only_textbook("csm", "sample=linear")),
        (ConeForm::Safe, SampleChoice::Nearest) => return Err(only_textbook("csm", "sample=nearest")),
        (ConeForm::Safe, SampleChoice::Min4) => return Err(only_textbook("csm", "sample=min4")),
    };
    Ok(csm(s, ray, a.int("steps")?, form, sample))
}

/// The quadrant cone of a ray heading `dir` from channels `+u+v, -u+v, -u-v, +u-v`.
fn quadrant<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>, q: Val<'a, crate::ir::Vec4>) -> Val<'a, f32> {
    let west = ray.dir.x().lt(0.0);
    let south = ray.dir.y().lt(0.0);
    s.select(south, s.select(west, q.z(), q.w()), s.select(west, q.y(), q.x()))
}

/// Quad-directional cone stepping (Policarpo & Oliveira 2007, GPU Gems 3 §18.4.1): as CSM, with
/// the cone of the quadrant the ray is heading into (channels `+u+v, -u+v, -u-v, +u-v`). The
/// safe form's cell map holds each cell's quadrants in 2 × 2 texels of `[ratio, apex]`, and the
/// cell's entry is read at the ray's quadrant (`cell::quadrant_texel`): the texel is that
/// quadrant's cone.
pub(crate) fn qcsm<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>, steps: u32, form: ConeForm) -> Bracket<'a> {
    match form {
        ConeForm::Safe => safe_march(s, ray, steps, Some(MapReq::CellQuadCone), |s, p, c| {
            let (cone, apex) = c.cones_and_apex(s, MapReq::CellQuadCone);
            let r = cone.x().named("r");
            cone_step(c.grid.horiz, ray, r, c.over(p.z(), apex))
        }),
        ConeForm::Textbook => textbook_march(s, ray, steps, |s, p, h| {
            let r = quadrant(s, ray, s.map(MapReq::QuadCone, p.xy(), Filter::Nearest)).named("r");
            cone_step(ray.dir.xy().length(), ray, r, p.z() - h)
        })
        .conservative(),
    }
}

/// `qcsm(steps, form)`: [`qcsm`] in the catalogue.
pub(crate) fn qcsm_def() -> MethodDef {
    MethodDef::new(
        "qcsm",
        "quad-directional cone stepping (Policarpo & Oliveira, GPU Gems 3 18.4.1); form=safe|textbook",
        StageFn::Coarse(|s, ray, a| Ok(qcsm(s, ray, a.int("steps")?, a.choice("form")?))),
    )
    .param(ParamDef::steps("steps", 15))
    .param(form())
    .reads(|s| by_form(s, MapReq::QuadCone, MapReq::CellQuadCone))
}

/// Where relaxed stepping starts the refinement (GPU Gems 3 Fig. 18-10).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum RelaxedStart {
    /// From H, halfway between the entry and the stopping point K, to K (textbook only).
    Hk,
    /// From J, the last point visited before K, to K.
    Bracket,
}

/// Relaxed cone stepping (Policarpo & Oliveira 2007, GPU Gems 3 Listing 18-3): step with the
/// relaxed cone, whose ray may enter the surface but never leave it; stop at the first point
/// below the surface (K). The safe form always brackets from J: on cells, the one crossing
/// inside the cone lies between J and K.
pub(crate) fn rcs<'a>(
    s: &'a FnBuilder<'a>,
    ray: &Ray<'a>,
    steps: u32,
    form: ConeForm,
    start: RelaxedStart,
) -> Bracket<'a> {
    match form {
        ConeForm::Safe => relaxed_march(s, ray, steps, MapReq::CellRelaxedCone, |s, p, c| {
            let (cone, apex) = c.cones_and_apex(s, MapReq::CellRelaxedCone);
            let r = cone.x().named("r");
            cone_step(c.grid.horiz, ray, r, c.clearance(p.z(), apex))
        }),
        ConeForm::Textbook => {
            let m = textbook_march(s, ray, steps, |s, p, h| {
                let r = s.map(MapReq::RelaxedCone, p.xy(), Filter::Nearest).x().named("r");
                cone_step(ray.dir.xy().length(), ray, r, p.z() - h)
            });
            match start {
                RelaxedStart::Hk => Bracket::searched(s.select(m.found, m.end / 2.0, m.prev), m.end, m.found),
                RelaxedStart::Bracket => m.relaxed(),
            }
        }
    }
}

/// `rcs(steps, form, start)`: [`rcs`] in the catalogue.
pub(crate) fn rcs_def() -> MethodDef {
    MethodDef::new(
        "rcs",
        "relaxed cone stepping (GPU Gems 3 Listing 18-3); form=safe|textbook; start=hk|bracket (Fig. 18-10), auto: bracket (safe) or hk (textbook)",
        StageFn::Coarse(rcs_stage),
    )
    .param(ParamDef::steps("steps", 15))
    .param(form())
    .param(ParamDef::choice::<StartChoice>("start"))
    .reads(|s| by_form(s, MapReq::RelaxedCone, MapReq::CellRelaxedCone))
}

/// `start=auto` is the bracket from J (safe) or from H (textbook); `start=hk` with
/// `form=safe` is an error.
fn rcs_stage<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>, a: &Args) -> Result<Bracket<'a>, CompileError> {
    let form = a.choice::<ConeForm>("form")?;
    let start = match (form, a.choice::<StartChoice>("start")?) {
        (ConeForm::Safe, StartChoice::Auto | StartChoice::Bracket) => RelaxedStart::Bracket,
        (ConeForm::Textbook, StartChoice::Auto | StartChoice::Hk) => RelaxedStart::Hk,
        (ConeForm::Textbook, StartChoice::Bracket) => RelaxedStart::Bracket,
        (ConeForm::Safe, StartChoice::Hk) => return Err(only_textbook("rcs", "start=hk")),
    };
    Ok(rcs(s, ray, a.int("steps")?, form, start))
}

/// Cone normal stepping (Burger 2018 §3.3): CSM with the cone stored as the normal of its
/// side, stepping by the ray-plane intersection of eq. 3.2.
pub(crate) fn cns<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>, steps: u32, form: ConeForm) -> Bracket<'a> {
    match form {
        ConeForm::Safe => safe_march(s, ray, steps, Some(MapReq::CellConeNormal), |s, p, c| {
            let (cone, apex) = c.cones_and_apex(s, MapReq::CellConeNormal);
            let n_z = cone.x().named("n_z");
            cone_normal_step(c.grid.horiz, ray, n_z, c.over(p.z(), apex))
        }),
        ConeForm::Textbook => textbook_march(s, ray, steps, |s, p, h| {
            let n_z = s.map(MapReq::ConeNormal, p.xy(), Filter::Nearest).x().named("n_z");
            cone_normal_step(ray.dir.xy().length(), ray, n_z, p.z() - h)
        })
        .conservative(),
    }
}

/// `cns(steps, form)`: [`cns`] in the catalogue.
pub(crate) fn cns_def() -> MethodDef {
    MethodDef::new(
        "cns",
        "cone normal stepping (Burger 3.3, eq. 3.2); form=safe|textbook",
        StageFn::Coarse(|s, ray, a| Ok(cns(s, ray, a.int("steps")?, a.choice("form")?))),
    )
    .param(ParamDef::steps("steps", 15))
    .param(form())
    .reads(|s| by_form(s, MapReq::ConeNormal, MapReq::CellConeNormal))
}

/// Relaxed cone normal stepping (Burger §4.3.4): cone normal stepping on the relaxed cones;
/// returns the bracket around the crossing (from J, the last point above the surface).
pub(crate) fn rcns<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>, steps: u32, form: ConeForm) -> Bracket<'a> {
    match form {
        ConeForm::Safe => relaxed_march(s, ray, steps, MapReq::CellRelaxedCone, |s, p, c| {
            let (cone, apex) = c.cones_and_apex(s, MapReq::CellRelaxedCone);
            let r = cone.x();
            cone_normal_step(c.grid.horiz, ray, normal_of(r).named("n_z"), c.clearance(p.z(), apex))
        }),
        ConeForm::Textbook => textbook_march(s, ray, steps, |s, p, h| {
            let n_z = s.map(MapReq::RelaxedConeNormal, p.xy(), Filter::Nearest).x().named("n_z");
            cone_normal_step(ray.dir.xy().length(), ray, n_z, p.z() - h)
        })
        .relaxed(),
    }
}

/// `rcns(steps, form)`: [`rcns`] in the catalogue.
pub(crate) fn rcns_def() -> MethodDef {
    MethodDef::new(
        "rcns",
        "relaxed cone normal stepping (Burger 4.3.4); form=safe|textbook",
        StageFn::Coarse(|s, ray, a| Ok(rcns(s, ray, a.int("steps")?, a.choice("form")?))),
    )
    .param(ParamDef::steps("steps", 15))
    .param(form())
    .reads(|s| by_form(s, MapReq::RelaxedConeNormal, MapReq::CellRelaxedCone))
}

/// The first K channels of a cone map entry.
fn channels<'a>(c: Val<'a, crate::ir::Vec4>, k: u32) -> Vec<Val<'a, f32>> {
    [c.x(), c.y(), c.z(), c.w()].into_iter().take(k as usize).collect()
}

/// Multiple cone normal stepping, method 1 (Burger §3.4): K cones stacked at heights
/// `b_k = h + (1 - h)·k/K` above the base height h; of the cones below the ray point, take the
/// one that gives the longest step. The base is the bilinear height (textbook) or the cell's
/// apex (safe).
pub(crate) fn mcns<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>, steps: u32, k: u32, form: ConeForm) -> Bracket<'a> {
    let longest = |p: Val<'a, Vec3>, base: Val<'a, f32>, cones: Vec<Val<'a, f32>>, c: Option<&Cell<'a>>| {
        let mut step = p.z() * 0.0;
        for (i, n_z) in cones.into_iter().enumerate() {
            let b_k = base + (1.0 - base) * (i as f32 / k as f32);
            let gap = match c {
                Some(c) => c.clearance(p.z(), b_k),
                None => (p.z() - b_k).max(0.0),
            };
            let horiz = c.map_or_else(|| ray.dir.xy().length(), |c| c.grid.horiz);
            step = step.max(cone_normal_step(horiz, ray, n_z, gap));
        }
        step
    };
    match form {
        ConeForm::Safe => safe_march(s, ray, steps, Some(MapReq::CellMultiCone(k)), |s, p, c| {
            let (cones, apex) = c.cones_and_apex(s, MapReq::CellMultiCone(k));
            longest(p, apex, channels(cones, k), Some(c))
        }),
        ConeForm::Textbook => textbook_march(s, ray, steps, |s, p, h| {
            longest(p, h, channels(s.map(MapReq::MultiCone(k), p.xy(), Filter::Nearest), k), None)
        })
        .conservative(),
    }
}

/// `mcns(steps, k, form)`: [`mcns`] in the catalogue.
pub(crate) fn mcns_def() -> MethodDef {
    MethodDef::new(
        "mcns",
        "multiple cone normal stepping, K stacked cones (Burger 3.4, method 1); form=safe|textbook",
        StageFn::Coarse(|s, ray, a| Ok(mcns(s, ray, a.int("steps")?, a.int("k")?, a.choice("form")?))),
    )
    .param(ParamDef::steps("steps", 15))
    .param(cones(4))
    .param(form())
    .reads(|s| by_form(s, MapReq::MultiCone(s.int("k")), MapReq::CellMultiCone(s.int("k"))))
}

/// Multiple cone normal stepping, method 2 (Burger §3.4, proposed there and never
/// evaluated): one empty region bounded by K cone pieces, piece j spanning heights
/// `[b_j, b_(j+1)]` with its own slope, so the region's radius grows piece by piece from 0 at
/// the base. The ray leaves the region in the highest piece at whose bottom it is already
/// outside (piece 0 when there is none); within piece j it meets the piece's line after
/// `(R_j + r_j·(z - b_j)) / (L + r_j·(-d.z))`. The base is the bilinear height (textbook) or
/// the cell's apex (safe).
pub(crate) fn pcns<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>, steps: u32, k: u32, form: ConeForm) -> Bracket<'a> {
    let speed = ray.dir.xy().length();
    let fall = -ray.dir.z();
    let leave = move |s: &'a FnBuilder<'a>, p: Val<'a, Vec3>, base: Val<'a, f32>, cones: Vec<Val<'a, f32>>| {
        let piece = (1.0 - base) / k as f32;
        let slopes: Vec<Val<'a, f32>> = cones.into_iter().map(ratio_of).collect();
        // The region's radius at each b_j.
        let mut radius = vec![-s.lit(0.0)];
        for j in 0..k as usize {
            radius.push(radius[j] + slopes[j] * piece);
        }
        let b = |j: usize| base + piece * j as f32;
        let meet = |j: usize| (radius[j] + slopes[j] * (p.z() - b(j))) / (speed + slopes[j] * fall).max(TINY);
        let mut step = meet(0);
        for (j, r_j) in radius.iter().enumerate().take(k as usize).skip(1) {
            let outside = p.z().gt(b(j)) & (speed * (p.z() - b(j))).gt(*r_j * fall);
            step = s.select(outside, meet(j), step);
        }
        step.max(0.0)
    };
    match form {
        ConeForm::Safe => safe_march(s, ray, steps, Some(MapReq::CellPiecewiseCone(k)), |s, p, c| {
            let (cones, apex) = c.cones_and_apex(s, MapReq::CellPiecewiseCone(k));
            leave(s, p, apex, channels(cones, k))
        }),
        ConeForm::Textbook => textbook_march(s, ray, steps, |s, p, h| {
            leave(s, p, h, channels(s.map(MapReq::PiecewiseCone(k), p.xy(), Filter::Nearest), k))
        })
        .conservative(),
    }
}

/// `pcns(steps, k, form)`: [`pcns`] in the catalogue.
pub(crate) fn pcns_def() -> MethodDef {
    MethodDef::new(
        "pcns",
        "piecewise cone normal stepping, K cone pieces (Burger 3.4, method 2); form=safe|textbook",
        StageFn::Coarse(|s, ray, a| Ok(pcns(s, ray, a.int("steps")?, a.int("k")?, a.choice("form")?))),
    )
    .param(ParamDef::steps("steps", 15))
    .param(cones(4))
    .param(form())
    .reads(|s| by_form(s, MapReq::PiecewiseCone(s.int("k")), MapReq::CellPiecewiseCone(s.int("k"))))
}
