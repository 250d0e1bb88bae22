//! The exact first intersection of a ray with the surface the shaders sample, on the CPU.
//!
//! The surface is the height map interpolated **bilinearly between texel centres** (or, for
//! stages that sample nearest, the piecewise-constant **nearest-texel** surface), extended past
//! the map by the scene's edge mode; either way it covers the whole plane. A ray is
//! `(u0 + t·dx, v0 + t·dy, 1 + t·dz)` with `dz < 0` (ARCHITECTURE.md: normalized so that t = -1/dz,
//! usually 1, reaches height 0). Its first hit is the smallest `t >= 0` where the ray's height is
//! at or below the surface. Heights are never negative, so every ray hits by the time it
//! reaches height 0.
//!
//! # Method
//!
//! 1. **Cells.** Between four texel centres the bilinear surface is one patch
//!    `h(x, y) = h00 + (h10 - h00)x + (h01 - h00)y + (h00 - h10 - h01 + h11)xy`. Along a
//!    straight ray both x and y are linear in t, so `h(t) - z(t)` is a quadratic in t; the
//!    first hit inside the cell is its first root in the cell's t-interval (or the interval's
//!    start if the ray already is below there). For nearest sampling a cell is a texel and the
//!    hit is where the ray's height drops to the texel's height (or the entry, for a wall).
//! 2. **Traversal.** The cells are visited in ray order (a 2D DDA, Amanatides & Woo 1987),
//!    so the first root found is the first hit.
//! 3. **Empty-space skipping.** A maximum mipmap over the cells ([`cell_max_mip`], after Tevs,
//!    Ihrke & Seidel 2008, and the pyramidal displacement mapping of Oh & Ki 2006 surveyed in
//!    Szirmay-Kalos & Umenhoffer 2008, section 4.3.3) bounds the surface over blocks of
//!    cells. A block whose maximum lies below the ray wherever the ray crosses it is skipped
//!    whole; otherwise the ray first advances to where it descends to that maximum, then the
//!    block is opened. After a skip the traversal climbs one level. The result is the same as
//!    visiting every cell ([`Reference::first_hit_cells`], used by the tests to check it).
//!
//! All arithmetic is f64.

use rayon::prelude::*;

use crate::heightmap::{EdgeMode, HeightMap};
use crate::maps::max_mip::{cell_max_mip, max_mip, Pyramid};
use crate::scene::{ProbeRay, Scene};
use relief_dsl::spec::Lod;

/// How the surface is reconstructed from the texels.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Sampling {
    /// Bilinear between texel centres (what a linear sampler returns).
    #[default]
    Bilinear,
    /// The nearest texel: flat squares with vertical walls between them.
    Nearest,
}

/// An exact first hit: the ray parameter and the hit point (`z` = the ray's height there,
/// which equals the surface height up to rounding).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RefHit {
    /// The ray parameter, ≥ 0; the ray's height is `1 + t·dz`, so height 0 is at `t = -1/dz`.
    pub t: f64,
    /// The hit's u, `u0 + t·dx`: not wrapped into [0, 1] (the map has period 1 in u).
    pub u: f64,
    /// The hit's v, `v0 + t·dy`, not wrapped either.
    pub v: f64,
    /// The ray's height at the hit, `1 + t·dz`, in [0, 1].
    pub z: f64,
}

/// A height map prepared for exact ray queries (the map, its edge mode, the sampling, and a
/// maximum mipmap over the cells of that sampling).
#[derive(Clone, Debug)]
pub struct Reference {
    map: HeightMap,
    edge: EdgeMode,
    sampling: Sampling,
    pyramid: Pyramid,
    /// The most traversal passes a query may take before it is an error.
    pass_limit: u64,
}

/// The traversal did not end within its pass limit: a logic error in the reference (or a
/// limit set too low with [`Reference::with_pass_limit`]), never a silent "no hit".
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("the exact reference did not finish the ray from ({u}, {v}) with direction ({dx}, {dy}, {dz}) within {passes} traversal passes")]
pub struct ReferenceError {
    /// The ray's origin u (at height 1).
    pub u: f64,
    /// The ray's origin v (at height 1).
    pub v: f64,
    /// The ray direction's u component.
    pub dx: f64,
    /// The ray direction's v component.
    pub dy: f64,
    /// The ray direction's height component (< 0).
    pub dz: f64,
    /// The pass limit the traversal reached.
    pub passes: u64,
}

/// The default pass limit: each pass descends a level or moves to the next cell or block, so
/// a ray over an N² map takes at most a few times N·(levels + 1) passes; 10⁸ is far beyond
/// any map relief loads (8192² included).
pub(crate) const PASS_LIMIT: u64 = 100_000_000;

impl Reference {
    /// Prepares `map` (copied) for queries.
    pub fn new(map: &HeightMap, edge: EdgeMode, sampling: Sampling) -> Reference {
        let pyramid = match sampling {
            Sampling::Bilinear => cell_max_mip(map, edge),
            Sampling::Nearest => max_mip(map),
        };
        Reference { map: map.clone(), edge, sampling, pyramid, pass_limit: PASS_LIMIT }
    }

    /// The same reference with another pass limit (tests use a tiny one to see the error).
    pub fn with_pass_limit(mut self, passes: u64) -> Reference {
        self.pass_limit = passes;
        self
    }

    /// Prepares a scene's height map with the scene's edge mode.
    pub fn for_scene(scene: &Scene, sampling: Sampling) -> Reference {
        Reference::new(&scene.height, scene.edge, sampling)
    }

    /// The surface height at (u, v), as this reference sees it.
    pub fn height_at(&self, u: f64, v: f64) -> f64 {
        match self.sampling {
            Sampling::Bilinear => self.map.bilinear(u, v, self.edge),
            Sampling::Nearest => self.map.nearest(u, v, self.edge),
        }
    }

    /// The first hit of the ray `(origin, 1) + t·dir`, with empty-space skipping. `None` if
    /// `dir.z >= 0`, the ray is not finite, or (only with negative heights) nothing is hit
    /// before height 0; an error if the traversal does not end within its pass limit.
    pub fn first_hit(&self, origin: [f64; 2], dir: [f64; 3]) -> Result<Option<RefHit>, ReferenceError> {
        self.traverse(origin, dir, true)
    }

    /// The same query visiting every cell along the ray (no skipping). Slower; the tests use
    /// it to show that skipping changes nothing.
    pub fn first_hit_cells(&self, origin: [f64; 2], dir: [f64; 3]) -> Result<Option<RefHit>, ReferenceError> {
        self.traverse(origin, dir, false)
    }

    /// The first hit of a probe ray (its f32 values widened exactly to f64).
    pub fn trace(&self, ray: &ProbeRay) -> Result<Option<RefHit>, ReferenceError> {
        let o = [ray.origin[0] as f64, ray.origin[1] as f64];
        let d = [ray.dir[0] as f64, ray.dir[1] as f64, ray.dir[2] as f64];
        self.first_hit(o, d)
    }

    /// [`Reference::trace`] for every ray, in parallel (rayon), in input order; the first
    /// error, naming its ray, if any ray fails.
    pub(crate) fn trace_all(&self, rays: &[ProbeRay]) -> Result<Vec<Option<RefHit>>, ReferenceError> {
        rays.par_iter().map(|r| self.trace(r)).collect()
    }

    fn traverse(&self, origin: [f64; 2], dir: [f64; 3], skip: bool) -> Result<Option<RefHit>, ReferenceError> {
        let finite = origin.iter().chain(dir.iter()).all(|c| c.is_finite());
        let dz = dir[2];
        if !finite || dz >= 0.0 {
            return Ok(None);
        }
        let (w, h) = (self.map.width as f64, self.map.height as f64);
        // Grid coordinates: cell (or texel) c spans [c, c + 1).
        let off = match self.sampling {
            Sampling::Bilinear => 0.5,
            Sampling::Nearest => 0.0,
        };
        let ray = GridRay { x0: origin[0] * w - off, y0: origin[1] * h - off, dx: dir[0] * w, dy: dir[1] * h, dz };
        let t_end = -1.0 / dz;
        let top = if skip { self.pyramid.top() } else { 0 };
        let mut level = top;
        let mut cx = ray.x0.floor() as i64;
        let mut cy = ray.y0.floor() as i64;
        let mut t = 0.0f64;

        // Each pass either descends a level or moves (cx, cy) forward along the ray, so the
        // loop ends; the bound is a guard against a logic error only.
        for _ in 0..self.pass_limit {
            if t > t_end {
                return Ok(None);
            }
            if level == 0 {
                let (tx, ty) = (ray.exit_x(cx, cx + 1), ray.exit_y(cy, cy + 1));
                let t_exit = tx.min(ty);
                let tb = t_exit.min(t_end);
                let s = match self.sampling {
                    Sampling::Bilinear => self.solve_bilinear(&ray, cx, cy, t, tb),
                    Sampling::Nearest => self.solve_nearest(&ray, cx, cy, t, tb),
                };
                if let Some(th) = s {
                    return Ok(Some(hit(origin, dir, th)));
                }
                if t_exit >= t_end {
                    // The ray reached height 0 in this cell: a hit unless heights are negative.
                    let z = self.height_at(origin[0] + t_end * dir[0], origin[1] + t_end * dir[1]);
                    return Ok((z >= -1e-12).then(|| hit(origin, dir, t_end)));
                }
                (cx, cy) = ray.step(cx, cy, tx, ty, [cx, cx + 1, cy, cy + 1]);
                t = t.max(t_exit);
                level = (level + 1).min(top);
                continue;
            }
            let node = self.pyramid.node(level, cx, cy, self.edge);
            let (tx, ty) = (ray.exit_x(node.x0, node.x1), ray.exit_y(node.y0, node.y1));
            let t_exit = tx.min(ty);
            let m = node.value as f64;
            if ray.z(t_exit) > m {
                // Above the whole block: skip it, then look at the coarser level again.
                (cx, cy) = ray.step(cx, cy, tx, ty, [node.x0, node.x1, node.y0, node.y1]);
                t = t.max(t_exit);
                level = (level + 1).min(top);
                continue;
            }
            // Nothing in this block can be hit before the ray descends to its maximum.
            let t_m = (m - 1.0) / dz;
            if t_m > t {
                t = t_m;
                let nx = (ray.x0 + t * ray.dx).floor() as i64;
                let ny = (ray.y0 + t * ray.dy).floor() as i64;
                cx = advance(cx, nx, ray.dx).clamp(node.x0, node.x1 - 1);
                cy = advance(cy, ny, ray.dy).clamp(node.y0, node.y1 - 1);
            }
            level -= 1;
        }
        Err(ReferenceError { u: origin[0], v: origin[1], dx: dir[0], dy: dir[1], dz, passes: self.pass_limit })
    }

    /// First t in [ta, tb] where the ray is at or below the bilinear patch of cell (cx, cy).
    fn solve_bilinear(&self, ray: &GridRay, cx: i64, cy: i64, ta: f64, tb: f64) -> Option<f64> {
        if tb < ta {
            return None;
        }
        let [a, b, c] = gap(&self.map, self.edge, ray, cx, cy, ta);
        if a >= 0.0 {
            return Some(ta);
        }
        let len = tb - ta;
        // Roots without cancellation: q = -(b + sign(b)·√D)/2, roots q/c and a/q.
        let disc = b * b - 4.0 * a * c;
        if disc < 0.0 {
            return None;
        }
        let q = -0.5 * (b + disc.sqrt().copysign(b));
        let mut best = f64::INFINITY;
        for r in [q / c, a / q] {
            if r.is_finite() && r >= 0.0 && r < best {
                best = r;
            }
        }
        // g(0) < 0, so the smallest non-negative root is where the ray first meets the patch.
        (best <= len).then_some(ta + best)
    }

    /// First t in [ta, tb] where the ray is at or below texel (cx, cy) (nearest sampling).
    fn solve_nearest(&self, ray: &GridRay, cx: i64, cy: i64, ta: f64, tb: f64) -> Option<f64> {
        if tb < ta {
            return None;
        }
        let hh = self.map.texel(cx, cy, self.edge) as f64;
        if ray.z(ta) <= hh {
            return Some(ta); // a wall, or the floor right at the entry
        }
        let th = (hh - 1.0) / ray.dz; // where the ray's height drops to the texel's
        (th <= tb).then_some(th)
    }
}

/// The gap between cell (cx, cy)'s bilinear patch and the ray from `ta` on, as the
/// coefficients of g(s) = h(s) − z(s) = a + b·s + c·s² with s = t − ta (Method, step 1).
fn gap(map: &HeightMap, edge: EdgeMode, ray: &GridRay, cx: i64, cy: i64, ta: f64) -> [f64; 3] {
    let h00 = map.texel(cx, cy, edge) as f64;
    let h10 = map.texel(cx + 1, cy, edge) as f64;
    let h01 = map.texel(cx, cy + 1, edge) as f64;
    let h11 = map.texel(cx + 1, cy + 1, edge) as f64;
    // Local coordinates at the interval start.
    let fx = ray.x0 + ta * ray.dx - cx as f64;
    let fy = ray.y0 + ta * ray.dy - cy as f64;
    let (ax, ay, k) = (h10 - h00, h01 - h00, h00 - h10 - h01 + h11);
    let a = h00 + ax * fx + ay * fy + k * fx * fy - ray.z(ta);
    let b = ax * ray.dx + ay * ray.dy + k * (fx * ray.dy + fy * ray.dx) - ray.dz;
    let c = k * ray.dx * ray.dy;
    [a, b, c]
}

/// Whether the ray `(origin, 1) + t·dir` is above `map`'s bilinear surface (between texel
/// centres, with `edge`) by more than `slack` in height somewhere in [t0, t1]: after a first
/// hit at t0, whether the ray comes back out of the surface before t1 — a search that
/// reports t1 has jumped over geometry. Exact: the cells the ray crosses are visited in
/// order, and in each the gap h − z, a quadratic in t, is minimised over the ray's part in
/// it (the ends, and the vertex where the quadratic opens upwards).
pub(crate) fn rises_above(
    map: &HeightMap,
    edge: EdgeMode,
    origin: [f64; 2],
    dir: [f64; 3],
    t0: f64,
    t1: f64,
    slack: f64,
) -> bool {
    if !(t0.is_finite() && t1.is_finite() && t1 > t0) {
        return false;
    }
    let (w, h) = (map.width as f64, map.height as f64);
    let ray = GridRay { x0: origin[0] * w - 0.5, y0: origin[1] * h - 0.5, dx: dir[0] * w, dy: dir[1] * h, dz: dir[2] };
    let mut cx = (ray.x0 + t0 * ray.dx).floor() as i64;
    let mut cy = (ray.y0 + t0 * ray.dy).floor() as i64;
    let mut t = t0;
    // The ray crosses at most this many cell sides between t0 and t1.
    let cells = ((t1 - t0) * (ray.dx.abs() + ray.dy.abs())).ceil() as u64 + 4;
    for _ in 0..cells {
        let (tx, ty) = (ray.exit_x(cx, cx + 1), ray.exit_y(cy, cy + 1));
        let tb = tx.min(ty).min(t1);
        let [a, b, c] = gap(map, edge, &ray, cx, cy, t);
        let len = (tb - t).max(0.0);
        let mut lowest = a.min(a + b * len + c * len * len);
        if c > 0.0 && (0.0..len).contains(&(-b / (2.0 * c))) {
            lowest = lowest.min(a - b * b / (4.0 * c));
        }
        if lowest < -slack {
            return true;
        }
        if tb >= t1 {
            return false;
        }
        (cx, cy) = ray.step(cx, cy, tx, ty, [cx, cx + 1, cy, cy + 1]);
        t = t.max(tb);
    }
    false
}

/// The ray in grid coordinates (texel or cell units) and its height.
struct GridRay {
    x0: f64,
    y0: f64,
    dx: f64,
    dy: f64,
    dz: f64,
}

impl GridRay {
    fn z(&self, t: f64) -> f64 {
        1.0 + t * self.dz
    }

    /// Where the ray leaves the slab [lo, hi) along x (infinite if it runs parallel).
    fn exit_x(&self, lo: i64, hi: i64) -> f64 {
        exit(self.x0, self.dx, lo, hi)
    }

    fn exit_y(&self, lo: i64, hi: i64) -> f64 {
        exit(self.y0, self.dy, lo, hi)
    }

    /// The cell just across the side(s) of the box `[x0, x1) × [y0, y1)` that the ray leaves
    /// by (`tx`, `ty`: when it leaves the box's x and y slabs).
    fn step(&self, cx: i64, cy: i64, tx: f64, ty: f64, [x0, x1, y0, y1]: [i64; 4]) -> (i64, i64) {
        let nx = if tx <= ty {
            if self.dx > 0.0 {
                x1
            } else {
                x0 - 1
            }
        } else {
            cx
        };
        let ny = if ty <= tx {
            if self.dy > 0.0 {
                y1
            } else {
                y0 - 1
            }
        } else {
            cy
        };
        (nx, ny)
    }
}

fn exit(p0: f64, d: f64, lo: i64, hi: i64) -> f64 {
    if d > 0.0 {
        (hi as f64 - p0) / d
    } else if d < 0.0 {
        (lo as f64 - p0) / d
    } else {
        f64::INFINITY
    }
}

/// Never moves a cell index backwards along the ray's direction.
fn advance(cur: i64, new: i64, d: f64) -> i64 {
    if d > 0.0 {
        cur.max(new)
    } else if d < 0.0 {
        cur.min(new)
    } else {
        cur
    }
}

fn hit(o: [f64; 2], d: [f64; 3], t: f64) -> RefHit {
    RefHit { t, u: o[0] + t * d[0], v: o[1] + t * d[1], z: 1.0 + t * d[2] }
}

/// The reference under `silhouette=clip`: a first hit whose (u, v) lies outside the quad's
/// square `[0, tiling]²` becomes no hit. This is the first hit inside the square's prism:
/// a ray enters the volume inside the square and, being straight, leaves the prism once, so
/// the part of it inside comes first; a first hit outside means nothing inside was hit.
pub(crate) fn clip_to_square(refs: &[Option<RefHit>], tiling: f64) -> Vec<Option<RefHit>> {
    let inside = |x: f64| (0.0..=tiling).contains(&x);
    refs.iter().map(|r| r.filter(|h| inside(h.u) && inside(h.v))).collect()
}

/// The mip level each ray samples under `lod`, computed as the shaders compute it
/// (relief-dsl's `compose::lod_level_fn`): 0 under `zero`; k under `level(k)`; under `auto`
/// the footprint level of the ray's pixel ([`Camera::footprint_lambda`] from the ray's entry
/// point and its `pixel_size`, [`footprint_level`]) for a map of `size` texels at level 0
/// and a chain of `levels` levels. An error for `level(k)` past the chain's last level (the
/// shader would clamp it; relief does not measure a level the map does not have).
///
/// [`Camera::footprint_lambda`]: crate::scene::Camera::footprint_lambda
/// [`footprint_level`]: crate::scene::camera::footprint_level
pub(crate) fn ray_levels(
    scene: &Scene,
    rays: &[ProbeRay],
    lod: Lod,
    size: [usize; 2],
    levels: usize,
) -> Result<Vec<usize>, String> {
    Ok(match lod {
        Lod::Zero => vec![0; rays.len()],
        Lod::Level(k) if k as usize >= levels => {
            return Err(format!(
                "lod=level({k}): the height map ({}×{}) has only {levels} mip levels (0..={})",
                size[0],
                size[1],
                levels - 1
            ))
        }
        Lod::Level(k) => vec![k as usize; rays.len()],
        Lod::Auto => rays
            .iter()
            .map(|r| {
                let lambda = scene.camera.footprint_lambda(glam::Vec2::from(r.origin), r.pixel_size, size);
                crate::scene::camera::footprint_level(lambda, levels)
            })
            .collect(),
    })
}

/// Exact first hits of `rays`, ray i on the surface of level `levels[i]` of the mip chain
/// `chain` (the bilinear or nearest surface of that level's texels, with `edge`): the
/// surface a shader sampling at that level meets. In parallel, in input order.
pub(crate) fn reference_hits_at_levels(
    chain: &[HeightMap],
    edge: EdgeMode,
    rays: &[ProbeRay],
    levels: &[usize],
    sampling: Sampling,
) -> Result<Vec<Option<RefHit>>, ReferenceError> {
    assert_eq!(rays.len(), levels.len(), "one level per ray");
    let mut used: Vec<usize> = levels.to_vec();
    used.sort_unstable();
    used.dedup();
    let refs: Vec<(usize, Reference)> = used.iter().map(|&l| (l, Reference::new(&chain[l], edge, sampling))).collect();
    rays.par_iter()
        .zip(levels.par_iter())
        .map(|(r, l)| refs.iter().find(|(k, _)| k == l).expect("every level used has a reference").1.trace(r))
        .collect()
}

/// Exact first hits of `rays` on `scene`'s height map (its edge mode, the given sampling),
/// in parallel and in input order.
pub fn reference_hits(
    scene: &Scene,
    rays: &[ProbeRay],
    sampling: Sampling,
) -> Result<Vec<Option<RefHit>>, ReferenceError> {
    Reference::for_scene(scene, sampling).trace_all(rays)
}
