//! The bilinear cell under a ray point, and the march that the `form=safe` cone methods share.
//!
//! The surface the shader samples is one bilinear patch per *cell*, the square between four
//! texel centres. In texel-centre coordinates `X = u·N − ½` the cell of a point is
//! `floor(X)`; its four corners come in one gather. A cell map (relief-runtime's
//! `maps::cell`) stores, per cell C, a cone that keeps the whole bilinear surface below
//! `A_C + dist(y, C)/R_C`, with A_C the highest corner of C and dist the horizontal distance
//! to the square C. From a point p at height z over C, the ray is then above the surface for
//! the whole textbook cone step `R·(z − A_C) / (|d.xy| + R·(−d.z))`.
//!
//! That step needs no pad for a point outside a clamp-mode map, where the cell's entry clamps
//! to a border strip C that the point is not in. Proof: let P project a horizontal point onto
//! the map's square `[−½, N − ½]²` (per axis, a clamp). Under clamp the surface is
//! `S(y) = S(P(y))` for every y, P is non-expansive (`|P(y) − P(p)| ≤ |y − p|`), and P(p) lies
//! in C: the clamped cell of p is the strip or cell that holds p's clamped coordinates (up
//! to the [`AHEAD_CELLS`] nudge, which a point inside the map has too). So for every y,
//! `S(y) = S(P(y)) ≤ A_C + dist(P(y), C)/R_C ≤ A_C + |P(y) − P(p)|/R_C ≤ A_C + |y − p|/R_C`:
//! the cone stands at p as it would at a point of C. The bounds of the other cell maps follow
//! the same way: a quadrant cone's (P moves each coordinate monotonically, so P(y) lies in the
//! quadrant of P(p) that y lies in of p), the piecewise cones' (a radius that grows with the
//! distance to C), and the relaxed cone's (the projected ray starts in C, stays in its cone,
//! and has the same `z − S` along it; outside the map in one axis it runs along a strip where
//! `∂S` across the strip is 0, so `∇S · d ≥ 0` on a rising cell holds for it as for the ray).
//! Earlier rounds padded the step by p's distance to the map's square: no ray needed it
//! (`relief-runtime/tests/cones.rs`, rays marching outside a comb of one-texel border walls,
//! gave 0 past the first hit without it, and went red with the pad's sign flipped).
//!
//! Where that step would end inside C (the point is below A_C, or C's cone is narrow), the
//! march decides exactly whether C's patch holds a hit (the ray's height over the patch is a
//! quadratic in t; [`Patch::meets_within`] decides without solving it) and either stops in C
//! or moves to where the ray leaves C. So every pass leaves a cell or ends the search, none
//! stalls, and the search never ends past the first intersection: the hit in the cell it
//! stopped in is solved once, after the loop ([`hit_in`]).
//!
//! A pass that leaves its cell by the cone step needs only the cone and `A_C`, which the cell
//! map carries in one texel where they fit ([`crate::abi::cell_apex_on_device`]); the patch
//! is read only in a pass that meets it: one load from the patch map (`cell_patch`, the
//! patch's coefficients per cell, [`MapReq::patches_read_with`]) for the cell cone and the
//! cell cone normal, else a gather of the four corners. So a pass costs one fetch, two where
//! it meets a patch (a map without the apex gathers the corners every pass, as the patch's
//! pass then reuses them).

use crate::ir::{FnBuilder, Image, Val, Var, Vec2, Vec3, Vec4};
use crate::spec::MapReq;
use crate::stage::{Bracket, Filter, Ray};
use std::cell::Cell as Kept;

/// How far ahead along the ray (in cells) the cell of a point on a cell boundary is picked:
/// the cell the ray is entering, not the one it leaves.
const AHEAD_CELLS: f32 = 1e-4;

/// The exit t along an axis the ray does not move on (|speed| < 1e-12 cells per unit t):
/// larger than any real exit (at most about one cell over 1e-12, i.e. 1e12) so that the
/// other axis or the floor decides, and a finite f32 that every shader compiler accepts as a
/// literal (`f32::MAX` is written `340282350000000000000000000000000000000`, a decimal just
/// above f32's range, which Chromium's Tint rejects).
const NO_EXIT: f32 = 1e30;

/// What a cell march needs of its ray and map, computed once before the loop: the shader
/// compiler keeps a value computed in the loop in the loop (AMD's ACO hoists nothing), so
/// every term that depends only on the ray, the map's size and the edge mode is made here.
#[derive(Clone, Copy)]
pub(super) struct Grid<'a> {
    /// The height map's size in texels.
    pub size: Val<'a, Vec2>,
    /// `1 / size`.
    pub inv_size: Val<'a, Vec2>,
    /// The ray's entry in texel-centre coordinates, `origin·N − ½`.
    pub x0: Val<'a, Vec2>,
    /// The ray's horizontal speed in cells per unit t, `d.xy·N`.
    pub speed: Val<'a, Vec2>,
    /// `speed.x · speed.y`, the patch's quadratic term per unit of twist ([`Patch`]).
    speed_xy: Val<'a, f32>,
    /// [`ahead`] of the speed.
    pub ahead: Val<'a, Vec2>,
    /// Per axis, 1 where the ray moves up the axis (it leaves a cell by its upper side), else 0.
    pub side: Val<'a, Vec2>,
    /// Per axis, `1 / speed` ([`inverse_speed`]).
    pub inv_speed: Val<'a, Vec2>,
    /// Whether the map's edges clamp.
    pub clamp: Val<'a, bool>,
    /// The ray's horizontal speed in texture units, `|d.xy|`.
    pub horiz: Val<'a, f32>,
    /// The t at which the ray reaches the floor ([`Ray::t_max`]).
    pub t_max: Val<'a, f32>,
    /// A cell's texture coordinate in a cell map is `cell·cell_scale + cell_bias` ([`Cell::entry`]).
    cell_scale: Val<'a, Vec2>,
    /// See `cell_scale`.
    cell_bias: Val<'a, Vec2>,
    /// Whether the march reads a map of 2 × 2 texels a cell (the quad cone map,
    /// [`MapReq::cell_texels`]) at level 0, at the texel of the ray's quadrant
    /// ([`quadrant_texel`]).
    quadrants: bool,
    /// Whether a cell's patch is read from the patch map (one load at the cell map's
    /// coordinate, [`Cell::patch`]) rather than gathered from the height map
    /// ([`MapReq::patches_read_with`]).
    patches: bool,
}

impl<'a> Grid<'a> {
    /// The grid of `ray` over the height map the stage samples (call before the loop), with
    /// `cells` the cell map the march reads, if any.
    ///
    /// The cell map's entry coordinate is scaled by its own size, queried here: N cells per
    /// axis under repeat, N + 1 under clamp (see [`Cell::entry`]). Querying the map before
    /// the loop also loads its descriptor there, where AMD's compiler then reuses it in every
    /// pass instead of loading it again in each (`docs/notes/safe-step.md`, round 8).
    pub(super) fn of(s: &'a FnBuilder<'a>, ray: &Ray<'a>, cells: Option<MapReq>) -> Grid<'a> {
        let size = s.height_map_size().named("size");
        let speed = (ray.dir.xy() * size).named("speed");
        let clamp = s.edge_is_clamp();
        // A map of 2 × 2 texels a cell read at level 0 (under a `lod` its texel is loaded by
        // index, [`Cell::entry`]).
        let quadrants = cells.is_some_and(|m| m.cell_texels() == 2) && s.sample_level().is_none();
        // Cells stored per axis.
        let stored = match (cells, s.sample_level()) {
            (Some(map), None) if quadrants => s.image_size(Image::of(map), Filter::Nearest) * 0.5,
            (Some(map), None) => s.image_size(Image::of(map), Filter::Nearest),
            _ => size + s.select(clamp, 1.0, 0.0),
        };
        let cell_scale = 1.0 / stored;
        Grid {
            size,
            inv_size: (1.0 / size).named("inv_size"),
            x0: (ray.origin * size - 0.5).named("x0"),
            speed,
            speed_xy: (speed.x() * speed.y()).named("speed_xy"),
            ahead: ahead(s, speed).named("ahead"),
            side: s.vec2(s.select(speed.x().ge(0.0), 1.0, 0.0), s.select(speed.y().ge(0.0), 1.0, 0.0)).named("side"),
            inv_speed: s.vec2(inverse_speed(s, speed.x()), inverse_speed(s, speed.y())).named("inv_speed"),
            clamp,
            horiz: ray.dir.xy().length().named("horiz"),
            t_max: s.march_end(ray.t_max()).named("t_max"),
            cell_scale: cell_scale.named("cell_scale"),
            cell_bias: (cell_scale * s.select(clamp, 1.5, 0.5)).named("cell_bias"),
            quadrants,
            patches: cells.is_some_and(MapReq::patches_read_with) && s.policy().cell_patches(),
        }
    }
}

/// Where a pass reads a map of 2 × 2 texels a cell (the quad cone map) at level 0: the cell
/// `(i, j)`, stored at `(i, j) + border`, is the texels `2·(i, j) + 2·border + side`, where
/// `side` (per axis 1 where the ray moves up the axis) is the quadrant the ray heads into, the
/// same all along the ray. The cell's coordinate in a map of one texel a cell (the patch map),
/// `at = cell·scale + bias`, is the corner between its four texels; the quadrant's texel is a
/// quarter of a cell from it toward the ray's direction, `± scale/4` per axis, written as the
/// [`ahead`] nudge (`±AHEAD_CELLS`, which the pass keeps anyway) times `scale/(4·AHEAD_CELLS)`
/// (where the ray does not move along an axis the nudge is 0 and the coordinate lies on the
/// edge between the two quadrants' texels: either is that ray's cone). The sampler's address
/// mode does the rest: under repeat its wrap of `2N` texels is a wrap of N cells, each keeping
/// its quadrant; under clamp its clamp to the edge gives a point beyond the map the outermost
/// texel whichever quadrant the ray heads into, which the map makes right by storing there the
/// narrower of the two quadrants' cones across that edge (relief-runtime's `maps::cell::cone`).
///
/// The factor is computed in the pass (two multiplies) rather than once per ray: a per-ray pair
/// stays live through the loop, and the forms that kept one (this factor, or a per-ray
/// quadrant bias with its offset to the patch map's coordinate) took 40 VGPRs on RDNA2 where
/// this one takes 32. Also measured: a clamp of the cell in the shader instead of the map's
/// edge rule cost four `min`/`max` a pass, about 5 % of a pass on lavapipe
/// (`docs/notes/safe-step.md`, round 12).
fn quadrant_texel<'a>(g: &Grid<'a>, at: Val<'a, Vec2>) -> Val<'a, Vec2> {
    g.ahead.mul_add(g.cell_scale * (0.25 / AHEAD_CELLS), at)
}

/// `1 / v` for an axis the ray moves along at `v` cells per unit t; where it does not
/// (|v| < 1e-12) ±[`NO_EXIT`], so that its exit is beyond any real one (the distance to the
/// side it moves toward is positive, at least the point's rounding, so the exit is beyond
/// 1e24) and the other axis or the floor decides.
fn inverse_speed<'a>(s: &'a FnBuilder<'a>, v: Val<'a, f32>) -> Val<'a, f32> {
    let none = s.select(v.lt(0.0), -NO_EXIT, NO_EXIT);
    s.select(v.abs().lt(1e-12), none, 1.0 / v)
}

/// The bilinear cell a ray point is in (or entering), with what the safe cone steps need.
pub(super) struct Cell<'a> {
    /// The ray's grid (per-ray terms).
    pub grid: Grid<'a>,
    /// The cell's lower-left texel-centre coordinates (`floor(X)`).
    pub cell: Val<'a, Vec2>,
    /// The corners gathered in the pass's own block ([`Cell::keep_corners`]), for every later
    /// use in the pass; `None` until then.
    kept: Kept<Option<Val<'a, Vec4>>>,
    /// The t at which the ray leaves the cell (at most the floor's t).
    pub exit: Val<'a, f32>,
}

/// The cell of the ray point at `t`.
///
/// The exit is `t + (cell + side − X(t))/speed`, not the shorter `(cell + side − x0)/speed`
/// with a per-ray `(side − x0)/speed` (three instructions fewer a pass): rounded at the cell
/// coordinates of a 1024² map that one fell short of the cell's side by more than the
/// [`AHEAD_CELLS`] nudge, the next pass found the same cell and exit, and the ray stalled
/// there (`relief-runtime/tests/cones.rs`, `safe_marches_take_no_empty_pass_…`: 2 of 4096
/// grazing rays under clamp ran out of 2048 passes; `docs/notes/safe-step.md`, round 8).
pub(super) fn cell_at<'a>(g: Grid<'a>, t: Val<'a, f32>) -> Cell<'a> {
    let x = g.x0 + g.speed * t;
    let cell = (x + g.ahead).floor().named("cell");
    let exit = g.exit(cell, x, t);
    Cell { grid: g, cell, kept: Kept::new(None), exit: exit.named("exit") }
}

impl<'a> Grid<'a> {
    /// Where the ray, at `x` (texel-centre coordinates) at `t`, leaves `cell`: to the cell's
    /// side it moves toward, along each axis, in t `(cell + side − X)/speed`; at most the floor.
    pub(super) fn exit(&self, cell: Val<'a, Vec2>, x: Val<'a, Vec2>, t: Val<'a, f32>) -> Val<'a, f32> {
        let to_side = (cell + self.side - x) * self.inv_speed;
        (t + to_side.x().min(to_side.y())).min(self.t_max)
    }
}

fn sign<'a>(s: &'a FnBuilder<'a>, v: Val<'a, f32>) -> Val<'a, f32> {
    s.select(v.gt(0.0), 1.0, s.select(v.lt(0.0), -1.0, 0.0))
}

/// A nudge of [`AHEAD_CELLS`] along a ray moving `speed` cells per unit t: added to a point
/// before flooring it to a cell (or node), it picks the cell the ray is entering when the
/// point lies on a boundary. The ray's t itself is never nudged (a nudge of 1e-3 cells in t
/// ended rays up to 1.3e-4 in t past the first hit in relief's cone tests).
pub(super) fn ahead<'a>(s: &'a FnBuilder<'a>, speed: Val<'a, Vec2>) -> Val<'a, Vec2> {
    s.vec2(sign(s, speed.x()), sign(s, speed.y())) * AHEAD_CELLS
}

impl<'a> Cell<'a> {
    /// Channel values of the cell's entry in the cell map `map` (one fetch, no filtering: a
    /// blend of two cells' cones is neither cell's cone).
    ///
    /// Storage: repeat wraps the N cells; clamp stores N + 1 (two half-texel border strips),
    /// entry i + 1 covering X in [max(i, -1/2), min(i + 1, N - 1/2)]. At level 0 the entry is
    /// a sample through the nearest sampler at the entry's centre, whose address mode is the
    /// edge mode: it wraps the cell (repeat) or clamps it to the border strips (clamp) with no
    /// arithmetic in the shader. Under a `lod` the maps of all levels share one atlas, which
    /// no address mode wraps, so the entry's index is computed and loaded ([`Cell::index`]).
    /// The same for the patch map, which lies on the cell maps' grid.
    /// A map of 2 × 2 texels a cell (the quad cone map) is read at the texel of the ray's
    /// quadrant ([`quadrant_texel`]).
    fn entry(&self, s: &'a FnBuilder<'a>, map: MapReq) -> Val<'a, Vec4> {
        let g = &self.grid;
        let quad = map.cell_texels() == 2;
        match s.sample_level() {
            None => {
                assert!(
                    !quad || g.quadrants,
                    "{}: a map of 2 × 2 texels a cell read on a grid made for another",
                    map.name()
                );
                let at = self.cell * g.cell_scale + g.cell_bias;
                let at = if quad { quadrant_texel(g, at) } else { at };
                s.sample(Image::of(map), at, Filter::Nearest)
            }
            Some(_) => s.cell_map_texel(map, self.index(s), quad.then_some(g.side)),
        }
    }

    /// Where the cell's entry is stored in a cell map (whole texel coordinates): the cell
    /// wrapped (repeat) or shifted by the border strip and clamped (clamp), see [`Cell::entry`].
    fn index(&self, s: &'a FnBuilder<'a>) -> Val<'a, Vec2> {
        let (g, cell) = (&self.grid, self.cell);
        let wrapped = cell - g.size * (cell * g.inv_size).floor();
        let clamped = (cell + 1.0).clamp(0.0, g.size);
        s.vec2(s.select(g.clamp, clamped.x(), wrapped.x()), s.select(g.clamp, clamped.y(), wrapped.y()))
    }

    /// The cell's entry in `map` and its apex `A_C`: the channel after the cones where the
    /// map carries it on the device, else the highest of the corners, gathered and kept for
    /// the pass (call in the pass's own block).
    pub(super) fn cones_and_apex(&self, s: &'a FnBuilder<'a>, map: MapReq) -> (Val<'a, Vec4>, Val<'a, f32>) {
        let texel = self.entry(s, map);
        let n = map.channels();
        let apex = if crate::abi::cell_apex_on_device(n) {
            // A height of the unlifted field: raised as the gathered corners are.
            s.map_height([texel.x(), texel.y(), texel.z(), texel.w()][n - 1])
        } else {
            let c = self.keep_corners(s);
            c.x().max(c.y()).max(c.z().max(c.w()))
        };
        (texel, apex.named("apex"))
    }

    /// The four corner heights in gather order `(i, j+1), (i+1, j+1), (i+1, j), (i, j)`,
    /// gathered in `s` and kept for the rest of the pass: `s` must be the pass's own block
    /// (a value made inside a branch does not exist after it).
    pub(super) fn keep_corners(&self, s: &'a FnBuilder<'a>) -> Val<'a, Vec4> {
        let c = match self.kept.get() {
            Some(c) => c,
            None => s.height_gather(self.centre()).named("corners"),
        };
        self.kept.set(Some(c));
        c
    }

    /// The cell's centre in texture coordinates, where a gather reads its four corners
    /// (one `fma` per axis: a centre's rounding does not matter).
    fn centre(&self) -> Val<'a, Vec2> {
        self.cell.mul_add(self.grid.inv_size, self.grid.inv_size)
    }

    /// The cell's patch: from the corners kept for the pass; else, where the march reads the
    /// patch map ([`MapReq::patches_read_with`]), from the cell's entry there (one load
    /// at the cell map's coordinate, which the pass has already computed for the cone, in
    /// place of a gather and the corners' differences; `docs/notes/safe-step.md`, round 11);
    /// else from a gather in `s` at the cell's centre, not kept.
    /// `after` names what is read for the solve after the loop (`hit_…`) rather than a pass.
    fn patch(&self, s: &'a FnBuilder<'a>, after: bool) -> Coeffs<'a> {
        let (patch, corners) = if after { ("hit_patch", "hit_corners") } else { ("patch", "corners") };
        match self.kept.get() {
            Some(c) => Coeffs::of_corners(c),
            None if self.grid.patches => {
                Coeffs::of_entry(s, self.entry(s, MapReq::CellPatch).named(patch), self.centre())
            }
            None => Coeffs::of_corners(s.height_gather(self.centre()).named(corners)),
        }
    }

    /// The height above the cone's apex that a step may descend through: the point's height
    /// over `apex` (no pad outside a clamp-mode map: the module's proof).
    pub(super) fn clearance(&self, p_z: Val<'a, f32>, apex: Val<'a, f32>) -> Val<'a, f32> {
        (p_z - apex).max(0.0)
    }

    /// The point's height over `apex`, negative below it: for a conservative cone step in
    /// [`safe_march`], where a step from below the apex is negative and so, like a step of 0,
    /// short of the cell's exit: the pass meets the patch either way, and no `max` is spent
    /// on it. (Not for [`Cell::clearance`]'s other users, which need a step ≥ 0.)
    pub(super) fn over(&self, p_z: Val<'a, f32>, apex: Val<'a, f32>) -> Val<'a, f32> {
        p_z - apex
    }

    /// The bilinear surface at `p` (within the cell), from the corners kept for the pass.
    pub(super) fn height(&self, s: &'a FnBuilder<'a>, t: Val<'a, f32>) -> Val<'a, f32> {
        let f = fraction(&self.grid, self.cell, t);
        let c = self.keep_corners(s);
        let (h01, h11, h10, h00) = (c.x(), c.y(), c.z(), c.w());
        let bottom = h00 + (h10 - h00) * f.x();
        let top = h01 + (h11 - h01) * f.x();
        bottom + (top - bottom) * f.y()
    }

    /// Whether the ray meets the cell's patch between `from` and the cell's exit
    /// ([`Patch::meets_within`]: no root, no division).
    pub(super) fn holds_hit(&self, s: &'a FnBuilder<'a>, ray: &Ray<'a>, from: Val<'a, f32>) -> Val<'a, bool> {
        Patch::of(ray, &self.grid, self.cell, self.patch(s, false), from).meets_within(self.exit - from)
    }

    /// Where a pass at `t` goes when its cone step stays in this cell: the patch decides
    /// ([`Cell::holds_hit`]), and the pass either marks `t` as the cell of the first hit (`−t`,
    /// [`Sentinel`]) or moves to the cell's exit.
    pub(super) fn decided(&self, s: &'a FnBuilder<'a>, ray: &Ray<'a>, t: Var<'a, f32>) -> Val<'a, f32> {
        let holds = self.holds_hit(s, ray, t.get());
        s.select(holds, -t.get(), self.exit)
    }
}

/// The ray's position at `t` within `cell`, in cells: `(origin·N − ½ − cell) + (d.xy·N)·t`.
/// Summed in this order the entry term is exact in f32 (N a power of two), where
/// `(origin + d.xy·t)·N − ½ − cell` rounds the position at the map's scale first: on a ray
/// nearly parallel to a one-texel ramp that rounding moved the patch's root by 1.4e-5 in t
/// (relief's cone tests).
fn fraction<'a>(g: &Grid<'a>, cell: Val<'a, Vec2>, t: Val<'a, f32>) -> Val<'a, Vec2> {
    (g.x0 - cell) + g.speed * t
}

/// A cell's bilinear patch in the cell's own coordinates (the fractions `f` in [0, 1]²):
/// `h = h00 + dx·f.x + dy·f.y + k·f.x·f.y`, with `dx = h10 − h00`, `dy = h01 − h00` and
/// `k = (h11 − h10) − dy`, in that order of operations (the patch map,
/// relief-runtime's `maps::cell::patch`, stores them computed in the same order, so a patch
/// read from it is the gathered one bit for bit).
#[derive(Clone, Copy)]
pub(super) struct Coeffs<'a> {
    h00: Val<'a, f32>,
    dx: Val<'a, f32>,
    dy: Val<'a, f32>,
    k: Val<'a, f32>,
}

impl<'a> Coeffs<'a> {
    /// From the four corners in gather order `(i, j+1), (i+1, j+1), (i+1, j), (i, j)`.
    pub(super) fn of_corners(corners: Val<'a, Vec4>) -> Coeffs<'a> {
        let (h01, h11, h10, h00) = (corners.x(), corners.y(), corners.z(), corners.w());
        let (dx, dy) = (h10 - h00, h01 - h00);
        Coeffs { h00, dx, dy, k: h11 - h10 - dy }
    }

    /// From a patch-map entry `(h00, dx, dy, k)`, its `h00` raised as a gather at `centre`
    /// (the cell's centre) raises the corners ([`FnBuilder::height_raised_at`]).
    fn of_entry(s: &'a FnBuilder<'a>, entry: Val<'a, Vec4>, centre: Val<'a, Vec2>) -> Coeffs<'a> {
        Coeffs { h00: s.height_raised_at(entry.x(), centre), dx: entry.y(), dy: entry.z(), k: entry.w() }
    }
}

/// The ray over a cell's bilinear patch from `from`: along the ray the patch height is
/// quadratic in t. With the corner heights h00, h10, h01, h11 and the fractions (fx, fy)
/// moving at (ax, ay) per unit t, `h − z = A s² + B s + C`, `s = t − from`.
pub(super) struct Patch<'a> {
    a: Val<'a, f32>,
    b: Val<'a, f32>,
    /// `h − z` at `from`: negative where the ray is above the patch.
    c: Val<'a, f32>,
}

impl<'a> Patch<'a> {
    /// The quadratic of the ray from `from` over `cell`, whose patch is `q`.
    pub(super) fn of(ray: &Ray<'a>, g: &Grid<'a>, cell: Val<'a, Vec2>, q: Coeffs<'a>, from: Val<'a, f32>) -> Patch<'a> {
        let f = fraction(g, cell, from);
        let z = 1.0 + ray.dir.z() * from;
        let Coeffs { h00, dx, dy, k } = q;
        let a = g.speed;
        Patch {
            a: k * g.speed_xy,
            b: dx * a.x() + dy * a.y() + k * (f.x() * a.y() + f.y() * a.x()) - ray.dir.z(),
            c: h00 + dx * f.x() + dy * f.y() + k * (f.x() * f.y()) - z,
        }
    }

    /// Whether the ray meets the patch in `[from, from + span]`, without a root: from above
    /// the patch (C < 0, the march's invariant; C ≥ 0 is a hit at `from`), it is under or on
    /// the patch at the end (`g(span) ≥ 0`, g = h − z), or it rises to the patch inside: g
    /// rising at `from` (B > 0) and falling at the end (`g′(span) < 0`, so g is concave with
    /// its maximum inside) and that maximum at least 0 (`B² − 4AC ≥ 0`, for A < 0). If g is
    /// negative at both ends and the maximum is not inside, g is negative all through.
    ///
    /// Written as one compare, `max(C, g(span), min(B, −g′(span), B² − 4AC)) ≥ 0` (AMD's
    /// `max3`/`min3`): where B = 0 or `g′(span)` = 0 with g negative at both ends, the maximum
    /// is at an end and `B² − 4AC` is negative, so the inner term's `≥ 0` in place of `> 0`
    /// changes nothing. Written with `|` and `&` the compiler branched around the inner test.
    ///
    /// The `C` operand alone sees a ray that enters the cell on or under its patch where the
    /// surface then falls away faster than the ray descends (g < 0 at the end, B < 0): a ray
    /// starting, at the volume's top, on a height-1 summit (relief-runtime's cones test
    /// `safe_methods_stop_at_once_on_a_summit_…`, red without it).
    pub(super) fn meets_within(&self, span: Val<'a, f32>) -> Val<'a, bool> {
        let (a, b, c) = (self.a, self.b, self.c);
        // Horner: `u = A·span + B`, `g(span) = u·span + C`, `g′(span) = 2A·span + B = u + A·span`.
        let u = a.mul_add(span, b);
        let at_end = u.mul_add(span, c);
        let slope_end = a.mul_add(span, u);
        let disc = b * b - 4.0 * a * c;
        let rises_inside = b.min(-slope_end).min(disc);
        c.max(at_end).max(rises_inside).ge(0.0)
    }

    /// The first root in `s ≥ 0` from above the patch (C < 0), in a form without cancellation
    /// for either sign of B (the textbook `(−B ± √disc)/2A` loses the root of near-vertical
    /// rays, where A is tiny: relief's cone tests caught rays passing 12 texels through the
    /// surface), with the discriminant `B² − 4AC`:
    /// - B ≥ 0: `−2C / (B + √disc)` (the smaller of two positive roots when A < 0, the one
    ///   positive root when A > 0, the linear root −C/B when A = 0);
    /// - B < 0: `(√disc − B) / 2A`, a root ≥ 0 only when A > 0 (the one positive root; with
    ///   A ≤ 0 both roots are negative, or the quotient is negative or −∞).
    ///
    /// One division and no second root to order; `B² − 4AC` is written `B² + (2A)(−2C)`, with
    /// the two products the root needs. Where the discriminant is negative the root is taken
    /// at `disc = 0` (the vertex, for B ≥ 0).
    fn first_root(&self, s: &'a FnBuilder<'a>) -> (Val<'a, f32>, Val<'a, f32>) {
        let (minus_2c, two_a) = (-2.0 * self.c, 2.0 * self.a);
        let big_b = self.b;
        let disc = big_b * big_b + two_a * minus_2c;
        let root_disc = disc.max(0.0).sqrt();
        let up = big_b.ge(0.0);
        let root = s.select(up, minus_2c, root_disc - big_b) / s.select(up, big_b + root_disc, two_a);
        (root, disc)
    }
}

/// The first hit in the cell `c` that a march found, by [`Patch::meets_within`], to hold
/// the ray's first hit between `from` and the cell's exit (call once, after the loop): the
/// patch's first root ([`Patch::first_root`]), kept within `[from, exit]` (rounding can put the
/// root a little outside where the decision was made at the edge: at the exit, or at the
/// vertex of a ray that only touches the patch), and `from` itself where the ray is already
/// under the patch. The patch is read as the loop read it ([`Cell::patch`]).
pub(super) fn hit_in<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>, c: &Cell<'a>, from: Val<'a, f32>) -> Val<'a, f32> {
    let q = Patch::of(ray, &c.grid, c.cell, c.patch(s, true), from);
    let (root, _) = q.first_root(s);
    let at = (from + root.max(0.0)).min(c.exit);
    s.select(q.c.ge(0.0), from, at)
}

/// A method's step in a cell march: from the ray point `p` in cell `c`, how far (in t) the
/// method's cone lets the ray advance.
pub(super) trait CellStep<'a>: Fn(&'a FnBuilder<'a>, Val<'a, Vec3>, &Cell<'a>) -> Val<'a, f32> {}
impl<'a, F: Fn(&'a FnBuilder<'a>, Val<'a, Vec3>, &Cell<'a>) -> Val<'a, f32>> CellStep<'a> for F {}

/// One pass's move once its cone step `cone` is known: to the cone step where it leaves the
/// cell; otherwise the cell's patch decides ([`Cell::decided`]).
///
/// Why: the cell's cone keeps the surface below it only from the cell's highest corner up, so
/// from a point below that corner (or under a narrow cone) the cone step is zero or tiny and a
/// march of cone steps alone would stall there; the patch's exact decision either marks the
/// cell of the first hit or proves the ray above the patch to the cell's exit, so every pass
/// leaves its cell or ends the search.
fn advance<'a>(l: &'a FnBuilder<'a>, ray: &Ray<'a>, c: &Cell<'a>, t: Var<'a, f32>, cone: Val<'a, f32>) {
    l.if_else(cone.ge(c.exit), |_| t.set(cone), |l| t.set(c.decided(l, ray, t)));
}

/// The march of the `form=safe` conservative cone methods (the method's step rule is
/// `step(p, cell)`, a cone step from the cell's apex), one pass per cell left:
///
/// 1. stop if the search is over;
/// 2. find the cell of the ray point at t, where the ray leaves it and how far the method's
///    cone lets it advance;
/// 3. advance by the cone step where it leaves the cell; else the cell's patch decides
///    whether it holds the first hit ([`Cell::holds_hit`]: the coefficients of the ray's
///    quadratic over the patch and a few compares, no root): if it does, the search is over
///    in this cell, else the ray moves on to the cell's exit. This is what the safe form adds
///    so that a pass never stalls and never passes the surface between texel centres;
/// 4. the search is also over on the floor (no height is below 0).
///
/// After the loop, a ray whose search ended in a cell meets that cell's patch exactly, once
/// ([`hit_in`]): the loop's passes carry no square root and no division for the patch.
///
/// Returns the bracket `[hit, hit]`, or, out of steps, the point reached (above the surface
/// everywhere before it).
///
/// `cells` is the cell map `step` reads, if any ([`Grid::of`]).
pub(super) fn safe_march<'a>(
    s: &'a FnBuilder<'a>,
    ray: &Ray<'a>,
    steps: u32,
    cells: Option<MapReq>,
    step: impl CellStep<'a>,
) -> Bracket<'a> {
    let g = Grid::of(s, ray, cells);
    // A pass that finds its cell to hold the first hit stores `−t` ([`Sentinel`]).
    let t = s.var("t", 0.0);
    let over = Sentinel::of(&g);
    s.repeat(steps, |l| {
        // 1. Over: the floor reached, or the cell of the first hit found.
        l.break_if(over.ended(t.get()));
        // 2. The cell, its exit, and the cone step.
        let c = cell_at(g, t.get());
        let cone = t.get() + step(l, ray.at(t), &c);
        // 3. Advance by the cone step, or the patch decides.
        advance(l, ray, &c, t, cone);
    });
    let (end, in_cell) = over.solve(s, ray, t.get());
    Bracket::searched(end, end, in_cell | t.ge(g.t_max))
}

/// How a cell march marks, in its own `t`, that a pass found its cell to hold the first hit:
/// `t` becomes `−t` (exact, and `−0` where t = 0). The loop then tests one thing, whether the
/// bits of t as an unsigned integer reach those of the floor's t: floats ≥ +0 order as their
/// bits, and a float with its sign bit set is above them all. So the floor and a found cell
/// end the loop by one compare, and no flag is carried from pass to pass (AMD's compiler
/// keeps a flag as a lane mask and merges it at every exit of the loop).
#[derive(Clone, Copy)]
pub(super) struct Sentinel<'a> {
    grid: Grid<'a>,
    /// The bits of the floor's t.
    floor_bits: Val<'a, u32>,
}

impl<'a> Sentinel<'a> {
    /// The sentinel of a march over `g` (call before the loop).
    pub(super) fn of(g: &Grid<'a>) -> Sentinel<'a> {
        Sentinel { grid: *g, floor_bits: g.t_max.bits().named("floor_bits") }
    }

    /// Whether the march is over at `t`: the floor reached (or a NaN), or a cell found.
    pub(super) fn ended(&self, t: Val<'a, f32>) -> Val<'a, bool> {
        t.bits().ge(self.floor_bits)
    }

    /// After the loop: where the march ended, the first hit solved exactly in the cell found
    /// ([`hit_in`], the cell found again from where the ray entered it, `−t`, with the loop's
    /// own [`cell_at`], so that the loop carries no cell from pass to pass), else `t` at most
    /// the floor's; and whether a cell was found. (Two copies of `cell_at` rounded apart could
    /// differ only for an entry within an ulp of a cell side; the answer is then the entry,
    /// never a point past the hit: `docs/notes/safe-step.md`, round 9.)
    pub(super) fn solve(&self, s: &'a FnBuilder<'a>, ray: &Ray<'a>, t: Val<'a, f32>) -> (Val<'a, f32>, Val<'a, bool>) {
        let in_cell = t.bits().ge(0x8000_0000u32).named("in_cell");
        let end = s.var("end", t.min(self.grid.t_max));
        s.if_(in_cell, |s| {
            let from = -t;
            let c = cell_at(self.grid, from);
            end.set(hit_in(s, ray, &c, from));
        });
        (end.get(), in_cell)
    }
}

/// The march of the `form=safe` relaxed cone methods (`step(p, cell)` is a relaxed cone step:
/// after it the ray may be under the surface, having crossed it once inside the cone, the cell
/// relaxed cone's guarantee), one pass per point visited:
///
/// 1. stop if the search is over;
/// 2. find the cell of the ray point at t; if the point is at or below the cell's patch, the
///    search is over: the first crossing lies in `[previous point, t]` (the previous point is
///    then stored negated, so that no flag is carried from pass to pass: see [`Sentinel`]);
/// 3. take the relaxed cone step from t, remembering t as the previous point;
/// 4. where that step would stay in the cell, the patch decides instead, as in
///    [`safe_march`]: if the cell holds the first hit the search is over, else the ray moves
///    on to the cell's exit.
///
/// After the loop, a ray whose search ended in a cell meets that cell's patch exactly
/// ([`Sentinel::solve`]), with the bracket `[hit, hit]`.
///
/// `cells` is the cell map `step` reads ([`Grid::of`]).
pub(super) fn relaxed_march<'a>(
    s: &'a FnBuilder<'a>,
    ray: &Ray<'a>,
    steps: u32,
    cells: MapReq,
    step: impl CellStep<'a>,
) -> Bracket<'a> {
    let g = Grid::of(s, ray, Some(cells));
    let t = s.var("t", 0.0);
    let t_prev = s.var("t_prev", 0.0);
    let over = Sentinel::of(&g);
    s.repeat(steps, |l| {
        // 1. Over: the floor reached, or the cell of the first hit found.
        l.break_if(over.ended(t.get()));
        // 2. The cell; under its patch, the bracket is found.
        let c = cell_at(g, t.get());
        let p = ray.at(t);
        let under = c.height(l, t.get()).ge(p.z());
        t_prev.set(l.select(under, -t_prev.get(), t_prev.get()));
        l.break_if(under);
        // 3. The relaxed cone step.
        let cone = t.get() + step(l, p, &c);
        t_prev.set(t);
        // 4. Or the patch decides where the step stays in the cell.
        advance(l, ray, &c, t, cone);
    });
    let (end, in_cell) = over.solve(s, ray, t.get());
    let under = t_prev.get().bits().ge(0x8000_0000u32);
    let above = s.select(in_cell, end, t_prev.get().abs());
    Bracket::searched(above, end, in_cell | under | t.ge(g.t_max))
}
