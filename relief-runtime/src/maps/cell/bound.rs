//! The per-cell bound (`piece_ratio`, exactly decidable from a cell's corners; the
//! derivation is in the [`super`] docs), its early-exit form for the search, the node test,
//! and the scorer of one cone piece built on them.

use super::geometry::norm;
use super::search::{CellScorer, Side};
use super::Corner;

/// The largest slope `r ≥ 0` that this module certifies for one cell `D` (corners `c`, seen
/// from `C`), for a cone piece starting at height `lo` with radius `rho` (texture units) and
/// ending at height `hi`:
///
/// ```text
/// ρ + r (min(S(y), hi) − lo) ≤ dist(y, C)   for every y in D with S(y) > lo.
/// ```
///
/// The plain cell cone is `lo = A_C, hi = +inf, rho = 0`: then the condition reads
/// `S(y) ≤ A_C + dist(y, C) / r`. Returns `+inf` when no corner is above `lo` (the bilinear
/// patch is then nowhere above `lo`). The result is the largest of these certified values:
///
/// 1. for each candidate direction `e` (the unit gap vector of each corner with a non-zero
///    gap), the largest `r` with `r (S_c − lo) ≤ ℓ_e(c) − ρ` at all four corners `c`; since
///    `r (S − lo) + ρ − ℓ_e` is bilinear on `D` (module docs), that makes it hold on all of
///    `D`, and `min(S, hi) ≤ S`, `ℓ_e ≤ dist` give the condition. Corners with `S_c ≤ lo`
///    bound `r` from below when `ℓ_e(c) < ρ`; an empty range gives no value;
/// 2. `(d_min − ρ) / (min(M, hi) − lo)` with `M` the largest corner and `d_min` the smallest
///    corner distance (the exact minimum of `dist` over `D`), when `d_min ≥ ρ`: then
///    `ρ + r (min(S, hi) − lo) ≤ ρ + r (min(M, hi) − lo) ≤ d_min ≤ dist`;
/// 3. `0` (callers guarantee `ρ ≤ dist(y, C)` wherever `S(y) > lo`: for `ρ = 0` trivially,
///    for the pieces of [`multi_cone`](super::multi_cone) by the piece below).
///
/// The condition is monotone in `r` (smaller `r` keeps it true), so the minimum over cells
/// of these values is certified for every cell at once.
pub fn piece_ratio(lo: f64, hi: f64, rho: f64, c: &[Corner; 4]) -> f64 {
    let m = c[0].height.max(c[1].height).max(c[2].height).max(c[3].height);
    if m <= lo {
        return f64::INFINITY;
    }
    let dmin = norm(c[0].gx.min(c[1].gx), c[0].gy.min(c[2].gy));
    let top = m.min(hi) - lo;
    let mut best = 0.0f64;
    if dmin >= rho {
        best = best.max((dmin - rho) / top);
    }
    for e in c {
        let n = norm(e.gx, e.gy);
        if n <= 0.0 {
            continue;
        }
        let (ex, ey) = (e.gx / n, e.gy / n);
        let (mut lower, mut upper) = (0.0f64, f64::INFINITY);
        let mut feasible = true;
        for q in c {
            let l = ex * q.gx + ey * q.gy - rho;
            let ds = q.height - lo;
            if ds > 0.0 {
                upper = upper.min(l / ds);
            } else if l < 0.0 {
                if ds == 0.0 {
                    feasible = false;
                } else {
                    lower = lower.max(l / ds);
                }
            }
        }
        if feasible && upper >= lower && upper > best {
            best = upper;
        }
    }
    best
}

/// [`piece_ratio`] when it is below `best`, else `None`: the search only needs a cell whose
/// value can lower the minimum. Bit-identical to [`piece_ratio`] where it returns a value
/// (the same operations on the same operands; a maximum does not depend on the order of its
/// terms), and faster: it stops as soon as one certified term reaches `best` (the maximum is
/// then `≥ best`), drops a candidate direction once its running minimum falls to the largest
/// term so far (it can no longer be the maximum), and tries the direction of the highest
/// corner first (the usual binding point, so the usual early stop). With `ρ = 0` that first
/// direction is checked against `best` without divisions before anything else
/// (`reaches_along`); most cells the search scores cannot lower the minimum and leave there.
#[inline]
pub fn piece_ratio_below(lo: f64, hi: f64, rho: f64, c: &[Corner; 4], best: f64) -> Option<f64> {
    let mut top_k = 0;
    for k in 1..4 {
        if c[k].height > c[top_k].height {
            top_k = k;
        }
    }
    let m = c[top_k].height;
    if m <= lo {
        return None;
    }
    if rho == 0.0 && reaches_along(c, &c[top_k], lo, best) {
        return None;
    }
    let dmin = norm(c[0].gx.min(c[1].gx), c[0].gy.min(c[2].gy));
    let top = m.min(hi) - lo;
    let mut v = 0.0f64;
    if dmin >= rho {
        v = v.max((dmin - rho) / top);
    }
    if v >= best {
        return None;
    }
    for o in 0..4 {
        let e = &c[(top_k + o) & 3];
        let n = norm(e.gx, e.gy);
        if n <= 0.0 {
            continue;
        }
        let (ex, ey) = (e.gx / n, e.gy / n);
        let (mut lower, mut upper) = (0.0f64, f64::INFINITY);
        let mut feasible = true;
        for q in c {
            let l = ex * q.gx + ey * q.gy - rho;
            let ds = q.height - lo;
            if ds > 0.0 {
                upper = upper.min(l / ds);
                if upper <= v {
                    feasible = false;
                    break;
                }
            } else if l < 0.0 {
                if ds == 0.0 {
                    feasible = false;
                    break;
                } else {
                    lower = lower.max(l / ds);
                }
            }
        }
        if feasible && upper >= lower && upper > v {
            if upper >= best {
                return None;
            }
            v = upper;
        }
    }
    Some(v)
}

/// Whether option 1 of [`piece_ratio`] (`ρ = 0`) along the gap vector of corner `e` is
/// certainly at least `best`, decided without divisions: with `n = |g_e|`, the term is the
/// minimum over corners `q` above `lo` of `(g_e · g_q) / (n (S_q − lo))`, and each such
/// corner is checked as `g_e · g_q ≥ best · n · (S_q − lo) · (1 + 1e-12)` (a margin far
/// above the few ulp by which the division form can differ). `true` means the cell cannot
/// score below `best` (the maximum over options is at least that term), so
/// [`piece_ratio_below`] would return `None`.
#[inline]
fn reaches_along(c: &[Corner; 4], e: &Corner, lo: f64, best: f64) -> bool {
    let n = norm(e.gx, e.gy);
    if n <= 0.0 || best == f64::INFINITY {
        return false;
    }
    let bar = best * n * (1.0 + 1e-12);
    c.iter().all(|q| {
        let ds = q.height - lo;
        ds <= 0.0 || e.gx * q.gx + e.gy * q.gy >= bar * ds
    })
}

/// The node test for a bound `sqrt(d2) / dh` (`dh > 0`): `None` when it reaches `best` with
/// the search's margin, decided first without a square root or division: `d2 ≥ (best dh)²
/// (1 + 4e-9)` implies `sqrt(d2) / dh ≥ best (1 + 2e-9)` up to a few ulp, so such a node is
/// also dropped by the margin test `b (1 − 1e-9) ≥ best` on the bound itself.
#[inline]
pub fn prune_ratio(d2: f64, dh: f64, best: f64) -> Option<f64> {
    let t = best * dh;
    if d2 >= t * t * (1.0 + 4e-9) {
        return None;
    }
    let b = d2.sqrt() / dh;
    (b * (1.0 - 1e-9) < best).then_some(b)
}

/// `h.min(hi)` as one comparison (the same value, `hi` also for a NaN `h`): `f64::min`'s
/// handling of NaN operands costs several instructions in the search's node test.
#[inline(always)]
fn below(h: f64, hi: f64) -> f64 {
    if h < hi {
        h
    } else {
        hi
    }
}

/// Scorer of a cone piece: [`piece_ratio`] with fixed `lo`, `hi`, `rho`.
pub(crate) struct PieceScorer {
    pub lo: f64,
    pub hi: f64,
    pub rho: f64,
}

impl CellScorer for PieceScorer {
    #[inline]
    fn bound(&self, dmin: f64, hmax: f32, _flags: u8, _sx: Side, _sy: Side) -> Option<f64> {
        let hmax = hmax as f64;
        if hmax <= self.lo {
            return None;
        }
        // Option 2 of `piece_ratio` with the node's smallest distance and largest height.
        Some(((dmin - self.rho) / (hmax.min(self.hi) - self.lo)).max(0.0))
    }
    #[inline]
    fn prune(&self, d2: f64, hmax: f32, _flags: u8, _sx: Side, _sy: Side, best: f64) -> Option<f64> {
        let hmax = hmax as f64;
        if hmax <= self.lo {
            return None;
        }
        let dh = below(hmax, self.hi) - self.lo;
        if self.rho == 0.0 {
            return prune_ratio(d2, dh, best);
        }
        let b = ((d2.sqrt() - self.rho) / dh).max(0.0);
        (b * (1.0 - 1e-9) < best).then_some(b)
    }
    #[inline]
    fn leaf(
        &self,
        _d: usize,
        c: &[Corner; 4],
        _dx: [f64; 2],
        _dy: [f64; 2],
        _cx: [f64; 2],
        _cy: [f64; 2],
        _sx: Side,
        _sy: Side,
    ) -> Option<f64> {
        let r = piece_ratio(self.lo, self.hi, self.rho, c);
        (r < f64::INFINITY).then_some(r)
    }
    #[inline]
    fn leaf_below(
        &self,
        _d: usize,
        c: &[Corner; 4],
        _dx: [f64; 2],
        _dy: [f64; 2],
        _cx: [f64; 2],
        _cy: [f64; 2],
        _sx: Side,
        _sy: Side,
        best: f64,
    ) -> Option<f64> {
        piece_ratio_below(self.lo, self.hi, self.rho, c, best)
    }
}
