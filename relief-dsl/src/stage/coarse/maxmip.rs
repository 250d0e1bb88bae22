//! Maximum-mipmap traversal (Tevs, Ihrke & Seidel 2008, *Maximum Mipmaps for Fast, Accurate,
//! and Scalable Dynamic Height Field Rendering*; the survey's pyramidal methods).
//!
//! The pyramid holds, per node, the highest point of the bilinear surface over the node's
//! cells (a cell spans four texel centres; level 0 is the cells, level L nodes of `2^L`
//! cells a side, up to one node). The ray is walked from node to node: where it stays above
//! a node's maximum it skips the whole node and climbs a level; where it dips below it
//! descends; in a single cell it meets the bilinear patch exactly (a quadratic in t).
//! Each pass through the loop is one node visit.

use super::cell::{Coeffs, Grid, Patch, Sentinel};
use crate::ir::{FnBuilder, Val, Vec2};
use crate::spec::{MapReq, MethodDef, ParamDef};
use crate::stage::{Bracket, Ray, StageFn};

/// Maximum-mipmap traversal with the exact bilinear-patch intersection in the finest cells
/// (Tevs, Ihrke & Seidel 2008; the survey's pyramidal displacement mapping), one node per
/// pass:
///
/// 1. find the node of the current level the ray is in, its maximum, where the ray leaves
///    it (`exit`) and where it comes down to the maximum (`down`);
/// 2. if the ray stays above the maximum through the node, skip the node, and climb a level
///    where it also leaves the node's parent;
/// 3. else, above the finest level, descend into the node at `down`;
/// 4. else (one cell) decide whether the cell's bilinear patch holds the first hit between
///    `down` and `exit` (the search is then over), else on to the exit.
///
/// After the loop, the hit in the cell found is solved exactly, once.
pub(crate) fn maxmip<'a>(s: &'a FnBuilder<'a>, ray: &Ray<'a>, steps: u32) -> Bracket<'a> {
    // Cell coordinates: cell i spans X in [i, i + 1), X = u·N - 1/2; the per-ray terms once,
    // before the loop (see [`Grid`]).
    let g = Grid::of(s, ray, None);
    let size = g.size;
    let top = size.x().max(size.y()).log2().floor();
    let inv_fall = (1.0 / ray.dir.z()).named("inv_fall");
    let t = s.var("t", 0.0);
    // The level as a whole number, so that a pass reads its node with no conversion.
    let top_level = top.to_u32().named("top_level");
    let level = s.var("level", top_level);
    // `2^level`, halved and doubled with the level (exact), not an `exp2` a pass.
    let span = s.var("span", top.exp2());
    // A pass that finds its cell to hold the first hit stores `−t` ([`Sentinel`]), with t where
    // the ray came down into the cell.
    let over = Sentinel::of(&g);
    s.repeat(steps, |l| {
        l.break_if(over.ended(t.get()));
        // 1. The node, its maximum, and where the ray leaves it and comes down to it.
        let x = g.x0 + g.speed * t;
        let node = ((x + g.ahead) / span).floor();
        // The node's place in the pyramid: wrapped (repeat) or clamped (clamp).
        let nodes = (size / span).floor().max(1.0);
        let wrapped = node - nodes * (node / nodes).floor();
        let clamped = node.clamp(0.0, nodes - 1.0);
        let at = s.vec2(s.select(g.clamp, clamped.x(), wrapped.x()), s.select(g.clamp, clamped.y(), wrapped.y()));
        let node_max = s.map_height(s.map_texel(MapReq::MaxMip, at.to_u32(), level.get()).x()).named("node_max");
        let to_side = ((node + g.side) * span - x) * g.inv_speed;
        let (exit_x, exit_y) = (to_side.x().abs(), to_side.y().abs());
        let exit = t + exit_x.min(exit_y).min(g.t_max - t);
        let down = ((node_max - 1.0) * inv_fall).max(t);
        // 2. Above the node's maximum all through it: skip the node, and climb where the ray
        //    leaves the parent node too ([`leaves_parent`]).
        l.if_(!down.lt(exit), |l| {
            t.set(exit);
            let up = leaves_parent(l, node, g.speed, exit_x.le(exit_y)) & level.lt(top_level);
            level.set(l.select(up, level + 1u32, level.get()));
            span.set(l.select(up, span * 2.0, span.get()));
            l.continue_();
        });
        // 3. Below it, on a coarser level: descend.
        l.if_(level.gt(0u32), |l| {
            t.set(down);
            level.set(level - 1u32);
            span.set(span * 0.5);
            l.continue_();
        });
        // 4. One cell: whether its bilinear patch holds the first hit between `down` and
        //    `exit` (the search is then over, the hit solved once after the loop), else on to
        //    the exit.
        let cell = (g.x0 + g.speed * down + g.ahead).floor();
        // The four corners in one gather at the cell's centre: (i, j+1), (i+1, j+1), (i+1, j), (i, j).
        let corners = s.height_gather(cell.mul_add(g.inv_size, g.inv_size));
        let holds = Patch::of(ray, &g, cell, Coeffs::of_corners(corners), down).meets_within(exit - down);
        t.set(s.select(holds, -down, exit));
    });
    // The first hit in the cell found, exactly, once. Reaching the floor is a hit (every
    // height is at least 0). Out of steps, the ray is known to be above the surface up to
    // where the traversal stopped.
    let (end, in_cell) = over.solve(s, ray, t.get());
    Bracket::searched(end, end, in_cell | t.ge(g.t_max))
}

/// Whether a ray leaving `node` (whole node coordinates at its level) through its side along x
/// (`by_x`, else along y), moving `speed`, also leaves the node's parent at the next level up:
/// the neighbour it enters has another parent. Why: climbing inside the same parent fetches
/// the parent's maximum, which the ray was already below when it descended into this node, so
/// the pass after would only descend again; staying at the level skips that pair of passes. The
/// choice of level changes only how far a pass may skip, never the guarantee (every node's
/// maximum bounds the surface under it).
fn leaves_parent<'a>(
    s: &'a FnBuilder<'a>,
    node: Val<'a, Vec2>,
    speed: Val<'a, Vec2>,
    by_x: Val<'a, bool>,
) -> Val<'a, bool> {
    // A node's parity along an axis: 0 for the lower child of its parent, 1 for the upper.
    let parity = node - 2.0 * (node / 2.0).floor();
    let leaves = |odd: Val<'a, f32>, v: Val<'a, f32>| s.select(v.ge(0.0), odd.gt(0.5), odd.lt(0.5));
    s.select(by_x, leaves(parity.x(), speed.x()), leaves(parity.y(), speed.y()))
}

/// `maxmip(steps)`: [`maxmip`] in the catalogue.
pub(crate) fn maxmip_def() -> MethodDef {
    MethodDef::new(
        "maxmip",
        "maximum-mipmap traversal with the exact bilinear patch in the finest cells (Tevs et al. 2008)",
        StageFn::Coarse(|s, ray, a| Ok(maxmip(s, ray, a.int("steps")?))),
    )
    .param(ParamDef::steps("steps", 64))
    .reads(|_| vec![MapReq::MaxMip])
}
