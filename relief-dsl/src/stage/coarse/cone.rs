//! Cone stepping and its relatives: each step jumps to where the ray leaves the empty cone
//! standing on the surface below the current point.
//!
//! Units (relief-runtime's `maps`): a cone ratio `r` is horizontal distance in texture
//! coordinates per unit of height; a cone normal `n_z = r / sqrt(1 + r²)`. For a ray point at
//! height `Δ` above the surface, with horizontal speed `L = |d.xy|` and vertical speed
//! `-d.z`, the ray meets the cone's side after `r·Δ / (L + r·(-d.z))` (Burger Algorithm 4
//! with an unnormalized d).
//!
//! A cone belongs to a texel: its apex is the texel's own sample (read with nearest
//! filtering) at the texel's centre, not the bilinear surface under the ray point. The ray
//! point is up to half a texel off that axis, so the gap a step may cover is measured from
//! the apex raised by `δ / r` (δ the point's distance from the texel centre): the cone of
//! radius `r·gap` around the point then lies inside the texel's cone. Measuring from the
//! bilinear height under the point instead lets steps end inside plateaus as high as the
//! apex (relief's cone tests found hits up to 27 texels past the first intersection on 64²
//! maps). When that leaves no gap (the point is closer to the surface than the padding) the
//! ray moves a quarter texel, so it never stalls: see [`MIN_STEP_TEXELS`].
//!
//! Conservative methods (`csm`, `qcsm`, `cns`, `mcns`, `pcns`) stop at the first point at
//! or below the surface, or after their steps; they return the bracket from the previous
//! point to the last one. Relaxed methods (`rcs`, `rcns`) let the ray enter the surface once
//! and return the bracket around that crossing.

use crate::ir::{Stage, Val, Vec2, Vec3};
use crate::spec::MapReq;
use crate::stage::{Bracket, Filter, Ray};

/// How CSM reads its cone map (Burger §4.3.1: linear filtering of ratios causes artifacts;
/// the minimum of the four texels fixes them at a cost).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConeSample {
    Linear,
    Nearest,
    Min4,
    /// The best of the four corner texels' cones, each padded for the point's offset from
    /// its axis ([`Corners`]).
    Corners,
}

/// Guards divisions by a speed that may be zero (a ray straight down into a zero-width cone).
const TINY: f32 = 1e-7;

/// The smallest move, in texels of travel, once a cone gives no clearance: the ray point is
/// then within a fraction of a texel of the surface.
pub const MIN_STEP_TEXELS: f32 = 0.25;

/// Where a ray point stands relative to the texel whose cone it reads.
#[derive(Clone, Copy)]
struct Footing<'a> {
    /// The texel's own height, where its cones' heights `b_k` start.
    texel_height: Val<'a, f32>,
    /// The cone apex: the texel's own height, at least the surface under the point.
    apex: Val<'a, f32>,
    /// Horizontal distance from the point to the texel centre.
    offset: Val<'a, f32>,
    /// The step in t that moves the ray a quarter texel.
    min_step: Val<'a, f32>,
}

/// The step in t that moves the ray [`MIN_STEP_TEXELS`] of a texel.
fn min_step<'a>(s: &'a Stage<'a>, ray: &Ray<'a>) -> Val<'a, f32> {
    let size = s.height_map_size();
    (MIN_STEP_TEXELS / size.x().max(size.y()) / ray.dir.xy().length().max(-ray.dir.z())).named("min_step")
}

fn footing<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, uv: Val<'a, Vec2>, h: Val<'a, f32>) -> Footing<'a> {
    let size = s.height_map_size();
    let centre = ((uv * size).floor() + 0.5) / size;
    let texel_height = apex(s, uv).named("texel_height");
    Footing {
        texel_height,
        apex: texel_height.max(h).named("apex"),
        offset: (uv - centre).length().named("offset"),
        min_step: min_step(s, ray),
    }
}

impl<'a> Footing<'a> {
    /// The height above the apex the point may descend through, padded for its offset from
    /// the apex's axis in a cone of ratio `r`.
    fn clearance(&self, p_z: Val<'a, f32>, r: Val<'a, f32>) -> Val<'a, f32> {
        (p_z - self.apex - self.offset / r.max(TINY)).max(0.0)
    }
}

/// The cone ratio under `uv`.
fn ratio<'a>(s: &'a Stage<'a>, map: MapReq, uv: Val<'a, Vec2>, sample: ConeSample) -> Val<'a, f32> {
    match sample {
        ConeSample::Linear => s.map(map, uv, Filter::Linear).x(),
        ConeSample::Nearest => s.map(map, uv, Filter::Nearest).x(),
        ConeSample::Min4 => s.map_min4(map, uv),
        ConeSample::Corners => unreachable!("corner sampling steps with Corners::best_step"),
    }
}

/// Distance along the ray (in t) to the side of a cone of ratio `r` whose apex is `gap`
/// below the current point.
fn cone_step<'a>(ray: &Ray<'a>, r: Val<'a, f32>, gap: Val<'a, f32>) -> Val<'a, f32> {
    r * gap / (ray.dir.xy().length() + r * -ray.dir.z()).max(TINY)
}

/// The four texels around a ray point — the corners of its bilinear cell — each with the
/// value of a single-channel cone map. Every corner's cone is free of the surface's samples,
/// so so is their union, and a step may follow whichever corner's cone reaches farthest.
/// The corner the point is lowest above usually has the clearance the padding takes from
/// the others, so steps keep shrinking in proportion to the gap instead of stalling: on
/// relief's Rock-Bump-like scene CSM's error at 15 steps falls by a third.
///
/// But near its apex a texel's cone is pierced by the bilinear patches around it (three
/// high corners around a low one rise √2 times faster along the diagonal than along the
/// axes), and following the lowest corner's cone walks into exactly that: relief's cone
/// tests measured stretches of 4 texels inside one-texel walls. The texel-sample cone maps
/// would need the patches' slopes next to the apex folded in to make this safe.
struct Corners<'a> {
    heights: [Val<'a, f32>; 4],
    offsets: [Val<'a, f32>; 4],
    values: [Val<'a, f32>; 4],
}

fn corners<'a>(s: &'a Stage<'a>, uv: Val<'a, Vec2>, map: MapReq) -> Corners<'a> {
    let size = s.height_map_size();
    let base = (uv * size - 0.5).floor();
    let h = s.height_gather(uv);
    let v = s.map_gather(map, uv);
    // Gather order: (i, j+1), (i+1, j+1), (i+1, j), (i, j).
    let at = |dx: f32, dy: f32| ((base + s.vec2(dx + 0.5, dy + 0.5)) / size - uv).length();
    Corners {
        heights: [h.x(), h.y(), h.z(), h.w()],
        offsets: [at(0.0, 1.0), at(1.0, 1.0), at(1.0, 0.0), at(0.0, 0.0)],
        values: [v.x(), v.y(), v.z(), v.w()],
    }
}

impl<'a> Corners<'a> {
    /// The longest step any corner's cone allows: `step(value, clearance)` for each corner,
    /// with the clearance above that corner's apex padded for the point's offset from it.
    fn best_step(
        &self,
        p_z: Val<'a, f32>,
        ratio: impl Fn(Val<'a, f32>) -> Val<'a, f32>,
        step: impl Fn(Val<'a, f32>, Val<'a, f32>) -> Val<'a, f32>,
    ) -> Val<'a, f32> {
        let mut best = p_z * 0.0;
        for i in 0..4 {
            let r = ratio(self.values[i]);
            let clearance = (p_z - self.heights[i] - self.offsets[i] / r.max(TINY)).max(0.0);
            best = best.max(step(self.values[i], clearance));
        }
        best
    }
}

/// The height of the cone's apex: the sample of the texel the cone map was read at.
fn apex<'a>(s: &'a Stage<'a>, uv: Val<'a, Vec2>) -> Val<'a, f32> {
    s.sample("height_map", crate::abi::binding::HEIGHT, uv, Filter::Nearest).x()
}

/// Where the loop all cone searches share ended.
#[derive(Clone, Copy)]
struct Marched<'a> {
    /// The last point checked and found above the surface.
    prev: Val<'a, f32>,
    /// The point the loop ended at: at or below the surface when `found`; otherwise where
    /// the last step led, not checked.
    end: Val<'a, f32>,
    /// Whether the march stopped on the surface (false: it ran out of steps).
    found: Val<'a, bool>,
}

impl<'a> Marched<'a> {
    /// The bracket of a conservative search: a step never passes the surface, so when the
    /// steps run out the end point is still above it.
    fn conservative(self) -> Bracket<'a> {
        let s = self.end.stage();
        Bracket::searched(s.select(self.found, self.prev, self.end), self.end, self.found)
    }
}

/// The floor (z = 0) is surface everywhere, since no height is below 0: a step that would
/// take the ray past it (the minimum step near the floor, or a piecewise cone's step) stops
/// on it instead, so that the search ends on the floor rather than below the volume (`relief
/// stability` found csm, qcsm and pcns hits below the floor on the spikes scene).
fn not_past_the_floor<'a>(ray: &Ray<'a>, t: Val<'a, f32>) -> Val<'a, f32> {
    t.min(ray.t_max())
}

/// The loop all cone searches share (Burger Algorithm 4's): from the entry, while the ray
/// point is above the surface, advance by `step(s, p, footing)` (never less than the
/// minimum step).
fn march<'a>(
    s: &'a Stage<'a>,
    ray: &Ray<'a>,
    steps: u32,
    step: impl Fn(&'a Stage<'a>, Val<'a, Vec3>, &Footing<'a>) -> Val<'a, f32>,
) -> Marched<'a> {
    let t = s.var("t", 0.0);
    let t_prev = s.var("t_prev", 0.0);
    let found = s.var("found", false);
    s.repeat(steps, |s| {
        let p = ray.at(t.get());
        let h = s.height(p.xy()).named("h");
        found.set(h.ge(p.z()));
        s.break_if(found.get());
        let foot = footing(s, ray, p.xy(), h);
        let advance = step(s, p, &foot).max(foot.min_step);
        t_prev.set(t.get());
        t.set(not_past_the_floor(ray, t.get() + advance));
    });
    Marched { prev: t_prev.get(), end: t.get(), found: found.get() }
}

/// Cone step mapping (Dummer 2006; Burger Algorithm 4): while above the surface, step to the
/// side of the conservative cone below.
pub fn csm<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, steps: u32, sample: ConeSample) -> Bracket<'a> {
    march(s, ray, steps, |s, p, foot| match sample {
        ConeSample::Corners => corners(s, p.xy(), MapReq::Cone).best_step(p.z(), |r| r, |r, gap| cone_step(ray, r, gap)),
        _ => {
            let r = ratio(s, MapReq::Cone, p.xy(), sample).named("r");
            cone_step(ray, r, foot.clearance(p.z(), r))
        }
    })
    .conservative()
}

/// Quad-directional cone stepping (Policarpo & Oliveira, GPU Gems 3 §18.4.1): as CSM, with
/// the cone of the quadrant the ray is heading into (channels `+u+v, -u+v, -u-v, +u-v`).
pub fn qcsm<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, steps: u32) -> Bracket<'a> {
    let west = ray.dir.x().lt(0.0);
    let south = ray.dir.y().lt(0.0);
    march(s, ray, steps, |s, p, foot| {
        let q = s.map(MapReq::QuadCone, p.xy(), Filter::Nearest);
        let r = s.select(south, s.select(west, q.z(), q.w()), s.select(west, q.y(), q.x()));
        cone_step(ray, r, foot.clearance(p.z(), r))
    })
    .conservative()
}

/// Where relaxed stepping starts the refinement (GPU Gems 3 Fig. 18-10).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RelaxedStart {
    /// From H, halfway between the entry and the stopping point K, to K.
    Hk,
    /// From J, the last point visited before K, to K.
    Bracket,
}

/// Relaxed cone stepping (Policarpo & Oliveira, GPU Gems 3 Listing 18-3): step with the
/// relaxed cone, whose ray may enter the surface but never leave it; stop at the first point
/// below the surface (K). A relaxed step may end inside the surface, so when the steps run
/// out the last point known to be above it is J, the last one checked.
pub fn rcs<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, steps: u32, start: RelaxedStart) -> Bracket<'a> {
    let m = march(s, ray, steps, |s, p, foot| {
        let r = s.map(MapReq::RelaxedCone, p.xy(), Filter::Nearest).x().named("r");
        cone_step(ray, r, foot.clearance(p.z(), r))
    });
    let (j, k) = (m.prev, m.end);
    match start {
        RelaxedStart::Hk => Bracket::searched(s.select(m.found, k / 2.0, j), k, m.found),
        RelaxedStart::Bracket => Bracket::searched(j, k, m.found),
    }
}

/// The step to the plane of a cone side with normal z `n_z`, its apex `gap` below the ray
/// point: Burger eq. 3.2, `t = -gap·n_z / (n·d)` with `n = (-sqrt(1 - n_z²)·d̂_xy, n_z)`.
fn cone_normal_step<'a>(ray: &Ray<'a>, n_z: Val<'a, f32>, gap: Val<'a, f32>) -> Val<'a, f32> {
    let n_dot_d = -(1.0 - n_z * n_z).max(0.0).sqrt() * ray.dir.xy().length() + n_z * ray.dir.z();
    -gap * n_z / n_dot_d.min(-TINY)
}

/// Cone normal stepping (Burger 2018 §3.3): CSM with the cone stored as the normal of its
/// side, stepping by the ray-plane intersection of eq. 3.2.
pub fn cns<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, steps: u32) -> Bracket<'a> {
    normal_stepping(s, ray, steps, MapReq::ConeNormal).conservative()
}

/// Relaxed cone normal stepping (Burger §4.3.4): cone normal stepping on the relaxed cones;
/// returns the bracket around the crossing (as [`rcs`] with `start=bracket`).
pub fn rcns<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, steps: u32) -> Bracket<'a> {
    let m = normal_stepping(s, ray, steps, MapReq::RelaxedConeNormal);
    Bracket::searched(m.prev, m.end, m.found)
}

fn normal_stepping<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, steps: u32, map: MapReq) -> Marched<'a> {
    march(s, ray, steps, |s, p, foot| {
        let n_z = s.map(map, p.xy(), Filter::Nearest).x().named("n_z");
        let gap = foot.clearance(p.z(), ratio_of(n_z)).named("gap");
        cone_normal_step(ray, n_z, gap)
    })
}

/// The cone ratio of a cone side with normal z `n_z`: `r = n_z / sqrt(1 - n_z²)`.
fn ratio_of<'a>(n_z: Val<'a, f32>) -> Val<'a, f32> {
    n_z / (1.0 - n_z * n_z).max(TINY).sqrt()
}

/// The K channels of a multi-cone map as values.
fn channels<'a>(s: &'a Stage<'a>, map: MapReq, uv: Val<'a, Vec2>, k: u32) -> Vec<Val<'a, f32>> {
    let c = s.map(map, uv, Filter::Nearest);
    [c.x(), c.y(), c.z(), c.w()].into_iter().take(k as usize).collect()
}

/// Multiple cone normal stepping, method 1 (Burger §3.4): K cones stacked on the texel's axis
/// at heights `b_k = h + (1 - h)·k/K`; of the cones below the ray point, take the one that
/// gives the longest step.
pub fn mcns<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, steps: u32, k: u32) -> Bracket<'a> {
    march(s, ray, steps, |s, p, foot| {
        // The cones stand at b_k = h + (1 - h)·k/K above the texel's height h; where the
        // surface under the point is higher, all of them are raised with the apex (a raised
        // cone lies inside the original one).
        let h = foot.texel_height;
        let mut step = foot.min_step;
        for (i, n_z) in channels(s, MapReq::MultiCone(k), p.xy(), k).into_iter().enumerate() {
            let b_k = foot.apex + (1.0 - h) * (i as f32 / k as f32);
            let cone = Footing { apex: b_k, ..*foot };
            step = step.max(cone_normal_step(ray, n_z, cone.clearance(p.z(), ratio_of(n_z))));
        }
        step
    })
    .conservative()
}

/// Multiple cone normal stepping, method 2 (Burger §3.4, proposed there and never
/// evaluated): one empty region bounded by K cone pieces, piece j spanning heights
/// `[b_j, b_(j+1)]` with its own slope, so the region's radius grows piece by piece from 0 at
/// the surface. The ray leaves the region in the highest piece at whose bottom it is already
/// outside (piece 0 when there is none); within piece j it meets the piece's line after
/// `(R_j + r_j·(z - b_j)) / (L + r_j·(-d.z))`.
pub fn pcns<'a>(s: &'a Stage<'a>, ray: &Ray<'a>, steps: u32, k: u32) -> Bracket<'a> {
    let speed = ray.dir.xy().length();
    let fall = -ray.dir.z();
    march(s, ray, steps, |s, p, foot| {
        // Pieces of height (1 - h)/K from the texel's height h, the whole profile raised
        // with the apex where the surface under the point is higher (a raised region lies
        // inside the original one).
        let piece = (1.0 - foot.texel_height) / k as f32;
        let slopes: Vec<Val<'a, f32>> =
            channels(s, MapReq::PiecewiseCone(k), p.xy(), k).into_iter().map(ratio_of).collect();
        // The region's radius at each b_j, less the point's offset from its axis.
        let mut radius = vec![-foot.offset];
        for j in 0..k as usize {
            radius.push(radius[j] + slopes[j] * piece);
        }
        let base = |j: usize| foot.apex + piece * j as f32;
        let meet = |j: usize| (radius[j] + slopes[j] * (p.z() - base(j))) / (speed + slopes[j] * fall).max(TINY);
        let mut step = meet(0);
        for j in 1..k as usize {
            let outside = p.z().gt(base(j)) & (speed * (p.z() - base(j))).gt(radius[j] * fall);
            step = s.select(outside, meet(j), step);
        }
        step
    })
    .conservative()
}
