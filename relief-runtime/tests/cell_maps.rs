//! Cone maps on bilinear cells and the distance field to the bilinear surface:
//! every fast generator against a brute-force minimum over all cells (bit for bit), the cone
//! property checked by dense sampling of the surface (without the generator's lower bound),
//! the relaxed rule checked by marching rays, encodings, and the distance field's bound under
//! trilinear filtering.
//!
//! Tolerances: the dense checks compare f64 evaluations of O(1) quantities (heights in [0, 1],
//! distances ≤ 1.5, a few operations each, relative error ≲ 1e-15); `TOL = 1e-12` relative is
//! a 1000× margin over that and far below one f32 ulp of a height (6e-8).

use proptest::prelude::*;
use relief_runtime::maps::cell::cone::{cell_cone, cell_cone_normal, cell_quad_cone, QUADRANTS};
use relief_runtime::maps::cell::multi_cone::{cell_multi_cone, cell_piecewise_cone, heights};
use relief_runtime::maps::cell::relaxed_cone::{cap, cell_relaxed_cone, rising};
use relief_runtime::maps::cell::{piece_ratio, CellGrid, Corner, Dir};
use relief_runtime::maps::cone_normal::normal_z;
use relief_runtime::maps::distance_field::distance_field;
use relief_runtime::maps::encode::{f32_down, Encoding, Format};
use relief_runtime::maps::{self, MapKind, MapParams};
use relief_runtime::{EdgeMode, HeightMap};

const TOL: f64 = 1e-12;

/// The ratio of a stored `n_z`, in f64 (`n / sqrt(1 - n²)`, `+inf` at 1).
fn ratio_of(n: f32) -> f64 {
    let n = n as f64;
    if n >= 1.0 {
        f64::INFINITY
    } else {
        n / (1.0 - n * n).sqrt()
    }
}
const EDGES: [EdgeMode; 2] = [EdgeMode::Repeat, EdgeMode::Clamp];

struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
    fn f(&mut self) -> f64 {
        self.next() as f64
    }
}

fn noise(w: usize, h: usize, seed: u64) -> HeightMap {
    let mut r = Lcg(seed);
    HeightMap::from_fn(w, h, |_, _| r.next())
}

fn coarse_noise(w: usize, h: usize, seed: u64) -> HeightMap {
    let mut r = Lcg(seed);
    HeightMap::from_fn(w, h, |_, _| (r.next() * 4.0).floor() / 4.0)
}

/// Smooth value noise (a few octaves of bilinearly interpolated lattices, smoothstepped).
fn smooth(w: usize, h: usize, seed: u64) -> HeightMap {
    let mut r = Lcg(seed);
    let lat: Vec<Vec<f32>> = (0..3).map(|o| (0..(2usize << o).pow(2)).map(|_| r.next()).collect()).collect();
    HeightMap::from_fn(w, h, |x, y| {
        let mut s = 0.0;
        let mut amp = 0.57;
        for (o, l) in lat.iter().enumerate() {
            let g = 2usize << o;
            let fx = x as f32 / w as f32 * g as f32;
            let fy = y as f32 / h as f32 * g as f32;
            let (x0, y0) = (fx.floor() as usize % g, fy.floor() as usize % g);
            let (x1, y1) = ((x0 + 1) % g, (y0 + 1) % g);
            let (tx, ty) = (fx.fract(), fy.fract());
            let (tx, ty) = (tx * tx * (3.0 - 2.0 * tx), ty * ty * (3.0 - 2.0 * ty));
            let a = l[y0 * g + x0] + (l[y0 * g + x1] - l[y0 * g + x0]) * tx;
            let b = l[y1 * g + x0] + (l[y1 * g + x1] - l[y1 * g + x0]) * tx;
            s += amp * (a + (b - a) * ty);
            amp *= 0.5;
        }
        s
    })
}

/// Hard edges: boxes, a one-texel wall and single-texel pillars on a low floor.
fn boxes(w: usize, h: usize, seed: u64) -> HeightMap {
    let mut r = Lcg(seed);
    let mut m = HeightMap::from_fn(w, h, |_, _| 0.1);
    for _ in 0..3 {
        let (x0, y0) = ((r.next() * w as f32) as usize, (r.next() * h as f32) as usize);
        let (bw, bh) = (1 + (r.next() * 5.0) as usize, 1 + (r.next() * 5.0) as usize);
        let z = 0.3 + 0.7 * r.next();
        for y in y0..(y0 + bh).min(h) {
            for x in x0..(x0 + bw).min(w) {
                m.data[y * w + x] = z;
            }
        }
    }
    let wx = (r.next() * w as f32) as usize;
    for y in 0..h / 2 {
        m.data[y * w + wx] = 0.8;
    }
    for _ in 0..4 {
        let (x, y) = ((r.next() * w as f32) as usize, (r.next() * h as f32) as usize);
        m.data[y * w + x] = 1.0;
    }
    m
}

fn suite(w: usize, h: usize) -> Vec<(&'static str, HeightMap)> {
    vec![
        ("noise", noise(w, h, 5 + w as u64)),
        ("coarse", coarse_noise(w, h, 9)),
        ("smooth", smooth(w, h, 4)),
        ("boxes", boxes(w, h, 2)),
        ("flat", HeightMap::from_fn(w, h, |_, _| 0.5)),
    ]
}

// ------------------------------------------------------------------------------------------
// The cell grid, written from the docs of `maps::cell`
// ------------------------------------------------------------------------------------------

/// Storage cell `i` along an axis of `n` texels: its two corner texels and its extent in
/// texel-centre coordinates.
fn ext(i: usize, n: usize, edge: EdgeMode) -> (usize, usize, f64, f64) {
    match edge {
        EdgeMode::Repeat => (i, (i + 1) % n, i as f64, i as f64 + 1.0),
        EdgeMode::Clamp => {
            let a = if i == 0 { 0 } else { (i - 1).min(n - 1) };
            (a, i.min(n - 1), (i as f64 - 1.0).max(-0.5), (i as f64).min(n as f64 - 0.5))
        }
    }
}

fn cells(n: usize, edge: EdgeMode) -> usize {
    if edge == EdgeMode::Repeat {
        n
    } else {
        n + 1
    }
}

/// Every copy of every cell along one axis seen from cell `c`: (storage index, D extent,
/// C extent), both extents in the same frame (repeat: relative, C = [0, 1]).
fn copies(c: usize, n: usize, edge: EdgeMode, dir: Dir) -> Vec<(usize, [f64; 2], [f64; 2])> {
    let mut out = Vec::new();
    match edge {
        EdgeMode::Repeat => {
            let n = n as i64;
            for d in 0..n {
                let mut ks = vec![d - c as i64, d - c as i64 - n, d - c as i64 + n];
                ks.sort();
                ks.dedup();
                for k in ks {
                    let ok = match dir {
                        Dir::Both => k.abs() < n,
                        Dir::Forward => (0..n).contains(&k),
                        Dir::Backward => k <= 0 && k > -n,
                    };
                    if ok {
                        out.push((d as usize, [k as f64, k as f64 + 1.0], [0.0, 1.0]));
                    }
                }
            }
        }
        EdgeMode::Clamp => {
            let (_, _, c0, c1) = ext(c, n, edge);
            for d in 0..=n {
                let ok = match dir {
                    Dir::Both => true,
                    Dir::Forward => d >= c,
                    Dir::Backward => d <= c,
                };
                if ok {
                    let (_, _, d0, d1) = ext(d, n, edge);
                    out.push((d, [d0, d1], [c0, c1]));
                }
            }
        }
    }
    out
}

fn corner_heights(m: &HeightMap, edge: EdgeMode, i: usize, j: usize) -> [f32; 4] {
    let (x0, x1, _, _) = ext(i, m.width, edge);
    let (y0, y1, _, _) = ext(j, m.height, edge);
    let t = |x: usize, y: usize| m.data[y * m.width + x];
    [t(x0, y0), t(x1, y0), t(x0, y1), t(x1, y1)]
}

fn gap(x: f64, c: [f64; 2]) -> f64 {
    (c[0] - x).max(x - c[1]).max(0.0)
}

fn corners(m: &HeightMap, hd: &[f32; 4], dx: [f64; 2], dy: [f64; 2], cx: [f64; 2], cy: [f64; 2]) -> [Corner; 4] {
    let (w, h) = (m.width as f64, m.height as f64);
    let mut out = [Corner { gx: 0.0, gy: 0.0, height: 0.0 }; 4];
    for b in 0..2 {
        for a in 0..2 {
            out[2 * b + a] = Corner { gx: gap(dx[a], cx) / w, gy: gap(dy[b], cy) / h, height: hd[2 * b + a] as f64 };
        }
    }
    out
}

/// Everything a brute-force minimum needs about one cell `D` seen from `C`.
struct Pair<'a> {
    hd: [f32; 4],
    c: [Corner; 4],
    dx: [f64; 2],
    dy: [f64; 2],
    cx: [f64; 2],
    cy: [f64; 2],
    _m: &'a HeightMap,
}

/// `min over every copy of every cell D of f(pair)`, starting from `init`.
#[allow(clippy::too_many_arguments)]
fn brute_min(
    m: &HeightMap,
    edge: EdgeMode,
    i: usize,
    j: usize,
    ax: Dir,
    ay: Dir,
    init: f64,
    f: &dyn Fn(&Pair) -> Option<f64>,
) -> f64 {
    let mut best = init;
    let xs = copies(i, m.width, edge, ax);
    let ys = copies(j, m.height, edge, ay);
    for &(dj, dy, cy) in &ys {
        for &(di, dx, cx) in &xs {
            let hd = corner_heights(m, edge, di, dj);
            let p = Pair { hd, c: corners(m, &hd, dx, dy, cx, cy), dx, dy, cx, cy, _m: m };
            if let Some(v) = f(&p) {
                best = best.min(v);
            }
        }
    }
    best
}

fn apex(c: &[f32; 4]) -> f32 {
    c.iter().cloned().fold(f32::NEG_INFINITY, f32::max)
}

fn cone_of(a: f64) -> impl Fn(&Pair) -> Option<f64> {
    move |p: &Pair| Some(piece_ratio(a, f64::INFINITY, 0.0, &p.c))
}

fn brute_cell_cone(m: &HeightMap, edge: EdgeMode) -> Vec<f32> {
    let mut out = Vec::new();
    for j in 0..cells(m.height, edge) {
        for i in 0..cells(m.width, edge) {
            let a = apex(&corner_heights(m, edge, i, j));
            out.push(f32_down(brute_min(m, edge, i, j, Dir::Both, Dir::Both, f64::INFINITY, &cone_of(a as f64))));
            out.push(a);
        }
    }
    out
}

fn brute_quad(m: &HeightMap, edge: EdgeMode) -> Vec<f32> {
    let mut out = Vec::new();
    for j in 0..cells(m.height, edge) {
        for i in 0..cells(m.width, edge) {
            let a = apex(&corner_heights(m, edge, i, j));
            for (ax, ay) in QUADRANTS {
                out.push(f32_down(brute_min(m, edge, i, j, ax, ay, f64::INFINITY, &cone_of(a as f64))));
            }
            out.push(a);
        }
    }
    out
}

fn brute_relaxed(m: &HeightMap, edge: EdgeMode) -> Vec<f32> {
    let mut out = Vec::new();
    for j in 0..cells(m.height, edge) {
        for i in 0..cells(m.width, edge) {
            let a = apex(&corner_heights(m, edge, i, j));
            let cons = brute_min(m, edge, i, j, Dir::Both, Dir::Both, f64::INFINITY, &cone_of(a as f64));
            let rel = brute_min(m, edge, i, j, Dir::Both, Dir::Both, f64::INFINITY, &|p: &Pair| {
                (!rising(&p.hd, p.dx, p.dy, p.cx, p.cy)).then(|| piece_ratio(a as f64, f64::INFINITY, 0.0, &p.c))
            });
            let r = cons.max(rel.min(cap(m.width, m.height, edge, a)));
            out.push(f32_down(r));
            out.push(a);
        }
    }
    out
}

fn brute_multi(m: &HeightMap, edge: EdgeMode, k: usize) -> Vec<f32> {
    let mut out = Vec::new();
    for j in 0..cells(m.height, edge) {
        for i in 0..cells(m.width, edge) {
            let a = apex(&corner_heights(m, edge, i, j));
            let b = heights(a, k);
            for bk in b.iter().take(k) {
                out.push(normal_z(f32_down(brute_min(
                    m,
                    edge,
                    i,
                    j,
                    Dir::Both,
                    Dir::Both,
                    f64::INFINITY,
                    &cone_of(*bk),
                ))));
            }
            out.push(a);
        }
    }
    out
}

fn brute_piecewise(m: &HeightMap, edge: EdgeMode, k: usize) -> Vec<f32> {
    let mut out = Vec::new();
    for j in 0..cells(m.height, edge) {
        for i in 0..cells(m.width, edge) {
            let a = apex(&corner_heights(m, edge, i, j));
            let b = heights(a, k);
            let mut rho = 0.0f64;
            for q in 0..k {
                let r = if rho.is_infinite() {
                    f64::INFINITY
                } else {
                    let (lo, hi) = (b[q], b[q + 1]);
                    brute_min(m, edge, i, j, Dir::Both, Dir::Both, f64::INFINITY, &|p: &Pair| {
                        Some(piece_ratio(lo, hi, rho, &p.c))
                    })
                };
                rho = if r.is_infinite() { f64::INFINITY } else { rho + f32_down(r) as f64 * (b[q + 1] - b[q]) };
                out.push(normal_z(f32_down(r)));
            }
            out.push(a);
        }
    }
    out
}

fn assert_bits(name: &str, fast: &[f32], brute: &[f32]) {
    assert_eq!(fast.len(), brute.len(), "{name}: length");
    for (i, (a, b)) in fast.iter().zip(brute).enumerate() {
        assert_eq!(a.to_bits(), b.to_bits(), "{name}: value {i}: fast {a} vs brute {b}");
    }
}

const SIZES: [(usize, usize); 3] = [(16, 16), (24, 20), (32, 32)];

/// `cell_patch` per cell, from the test's own corner resolver ([`corner_heights`], written
/// from the docs of `maps::cell`): `[h00, h10 − h00, h01 − h00, (h11 − h10) − (h01 − h00)]` in
/// f32, in the order the shader's `Coeffs::of_corners` computes it from a gather (relief-dsl
/// `stage/coarse/cell.rs`), so the map's patch is the gathered one bit for bit.
fn brute_patch(m: &HeightMap, edge: EdgeMode) -> Vec<f32> {
    let mut out = Vec::new();
    for j in 0..cells(m.height, edge) {
        for i in 0..cells(m.width, edge) {
            let [h00, h10, h01, h11] = corner_heights(m, edge, i, j);
            let dy = h01 - h00;
            out.extend([h00, h10 - h00, dy, (h11 - h10) - dy]);
        }
    }
    out
}

/// The patch map holds, per cell of the grid (border strips included under clamp), the
/// coefficients the shader would compute from the cell's four corners, bit for bit; and those
/// coefficients reproduce the four corners. The bound of the second check is derived: heights
/// lie in [0, 1], so each f32 difference is rounded by at most 2⁻²⁴·2 (|h10 − h00| ≤ 1, and
/// `(h11 − h10) − dy` is two roundings of values ≤ 2 in magnitude), and the patch at a corner
/// sums at most three coefficients each off by at most two such roundings: ≤ 6·2⁻²³ ≈ 7.2e-7.
#[test]
fn cell_patch_is_the_gathered_patch_bit_for_bit() {
    let bound = 6.0 * 2f64.powi(-23);
    for (w, h) in SIZES {
        for (name, m) in suite(w, h) {
            for edge in EDGES {
                let map = relief_runtime::maps::cell::patch::cell_patch(&m, edge);
                assert_bits(&format!("cell_patch {name} {w}x{h} {edge:?}"), &map, &brute_patch(&m, edge));
                let built = maps::build(&m, MapKind::CellPatch, &MapParams::default(), edge).unwrap();
                assert_eq!((built.width, built.height, built.channels), (cells(w, edge), cells(h, edge), 4));
                assert_bits(&format!("cell_patch via build {name}"), &built.data, &map);
                for j in 0..cells(h, edge) {
                    for i in 0..cells(w, edge) {
                        let c = &map[(j * cells(w, edge) + i) * 4..][..4];
                        let at = |fx: f64, fy: f64| {
                            c[0] as f64 + c[1] as f64 * fx + c[2] as f64 * fy + c[3] as f64 * fx * fy
                        };
                        let [h00, h10, h01, h11] = corner_heights(&m, edge, i, j);
                        for (got, want) in [(at(0., 0.), h00), (at(1., 0.), h10), (at(0., 1.), h01), (at(1., 1.), h11)]
                        {
                            assert!(
                                (got - want as f64).abs() <= bound,
                                "{name} {edge:?} cell ({i}, {j}): {got} vs {want}"
                            );
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn cell_cone_matches_brute_force_bit_for_bit() {
    for (w, h) in SIZES {
        for (name, m) in suite(w, h) {
            for edge in EDGES {
                assert_bits(
                    &format!("cell_cone {name} {w}x{h} {edge:?}"),
                    &cell_cone(&m, edge),
                    &brute_cell_cone(&m, edge),
                );
            }
        }
    }
    for m in [smooth(64, 64, 8), boxes(64, 64, 3)] {
        for edge in EDGES {
            assert_bits(&format!("cell_cone 64 {edge:?}"), &cell_cone(&m, edge), &brute_cell_cone(&m, edge));
        }
    }
}

#[test]
fn cell_quad_and_normal_match_brute_force_bit_for_bit() {
    for (w, h) in SIZES {
        for (name, m) in suite(w, h) {
            for edge in EDGES {
                assert_bits(
                    &format!("cell_quad_cone {name} {w}x{h} {edge:?}"),
                    &cell_quad_cone(&m, edge),
                    &brute_quad(&m, edge),
                );
                let n: Vec<f32> = brute_cell_cone(&m, edge).chunks(2).flat_map(|c| [normal_z(c[0]), c[1]]).collect();
                assert_bits(&format!("cell_cone_normal {name} {w}x{h} {edge:?}"), &cell_cone_normal(&m, edge), &n);
            }
        }
    }
}

/// The quad cone map as the GPU reads it (`maps::build` of the kind `cell_quad_cone`): cell
/// `(i, j)` is the 2 × 2 texels `(2i + qx, 2j + qy)`, each `[ratio, apex]`, the ratio that of
/// the quadrant a ray moving toward `+u` (`qx` = 1) or `−u` (`qx` = 0) and toward `+v`
/// (`qy` = 1) or `−v` (`qy` = 0) heads into, against the brute-force quad cones (channels
/// `+u+v, −u+v, −u−v, +u−v`, then the apex), bit for bit; the quadrant's channel written here
/// from that order, not taken from the map's code. Under clamp the outermost texel columns
/// (rows) hold the smaller ratio of their cell's two quadrants across u (v), a corner the
/// smallest of the four: what a point beyond the edge reads through the sampler's clamp,
/// heading either way.
#[test]
fn the_quad_cone_map_holds_each_quadrant_in_its_own_texel() {
    let channel = |qx: usize, qy: usize| match (qx, qy) {
        (1, 1) => 0,
        (0, 1) => 1,
        (0, 0) => 2,
        _ => 3,
    };
    let mut narrowed = 0;
    for (w, h) in [(8, 8), (5, 7)] {
        for (name, m) in suite(w, h) {
            for edge in EDGES {
                let (cw, ch) = (cells(w, edge), cells(h, edge));
                let want = brute_quad(&m, edge);
                let map = maps::build(&m, MapKind::CellQuadCone, &MapParams::default(), edge).unwrap();
                assert_eq!((map.width, map.height, map.channels), (2 * cw, 2 * ch, 2), "{name} {w}x{h} {edge:?}");
                let clamp = edge == EdgeMode::Clamp;
                for (j, i, qx, qy) in
                    (0..ch).flat_map(|j| (0..cw).flat_map(move |i| (0..4).map(move |q| (j, i, q % 2, q / 2))))
                {
                    let c = j * cw + i;
                    let (tx, ty) = (2 * i + qx, 2 * j + qy);
                    let got =
                        [map.data[(ty * 2 * cw + tx) * 2].to_bits(), map.data[(ty * 2 * cw + tx) * 2 + 1].to_bits()];
                    // The quadrants the texel serves: both across u in the first and last
                    // column under clamp, both across v in the first and last row.
                    let xs = if clamp && (tx == 0 || tx == 2 * cw - 1) { vec![0, 1] } else { vec![qx] };
                    let ys = if clamp && (ty == 0 || ty == 2 * ch - 1) { vec![0, 1] } else { vec![qy] };
                    let mut ratio = f32::INFINITY;
                    for (&x, &y) in xs.iter().flat_map(|x| ys.iter().map(move |y| (x, y))) {
                        ratio = ratio.min(want[5 * c + channel(x, y)]);
                    }
                    narrowed += usize::from(ratio != want[5 * c + channel(qx, qy)]);
                    let expect = [ratio.to_bits(), want[5 * c + 4].to_bits()];
                    assert_eq!(got, expect, "{name} {w}x{h} {edge:?}: cell ({i}, {j}), qx {qx}, qy {qy}");
                }
            }
        }
    }
    // The edge rule is exercised: some edge texel holds a ratio narrower than its own.
    assert!(narrowed > 0, "no edge texel was narrowed");
}

#[test]
fn cell_multi_and_piecewise_match_brute_force_bit_for_bit() {
    for (w, h) in [(16, 16), (24, 20)] {
        for (name, m) in suite(w, h) {
            for edge in EDGES {
                for k in [1, 3] {
                    assert_bits(
                        &format!("cell_multi_cone {name} {w}x{h} {edge:?} K={k}"),
                        &cell_multi_cone(&m, edge, k),
                        &brute_multi(&m, edge, k),
                    );
                    assert_bits(
                        &format!("cell_piecewise_cone {name} {w}x{h} {edge:?} K={k}"),
                        &cell_piecewise_cone(&m, edge, k),
                        &brute_piecewise(&m, edge, k),
                    );
                }
            }
        }
    }
}

#[test]
fn cell_relaxed_cone_matches_brute_force_bit_for_bit() {
    for (w, h) in SIZES {
        for (name, m) in suite(w, h) {
            for edge in EDGES {
                assert_bits(
                    &format!("cell_relaxed_cone {name} {w}x{h} {edge:?}"),
                    &cell_relaxed_cone(&m, edge),
                    &brute_relaxed(&m, edge),
                );
            }
        }
    }
    let m = smooth(64, 64, 8);
    for edge in EDGES {
        assert_bits(
            &format!("cell_relaxed_cone smooth 64 {edge:?}"),
            &cell_relaxed_cone(&m, edge),
            &brute_relaxed(&m, edge),
        );
    }
}

/// A tilted plane `z = z0 + sx x + sy y` (texel units), clamped to [0, 1]: long smooth slopes
/// where every cell along the slope ties with the cone's binding cell (axis-aligned slopes
/// give exactly equal ratios), the case the search's node and cell tests must not get wrong.
fn plane(w: usize, h: usize, z0: f32, sx: f32, sy: f32) -> HeightMap {
    HeightMap::from_fn(w, h, |x, y| (z0 + sx * x as f32 + sy * y as f32).clamp(0.0, 1.0))
}

#[test]
fn cell_cone_and_relaxed_match_brute_force_on_long_slopes() {
    let maps = [
        ("axis plane", plane(40, 36, 0.05, 1.0 / 64.0, 0.0)),
        ("diagonal plane", plane(40, 36, 0.0, 1.0 / 96.0, 1.0 / 128.0)),
        ("smooth", smooth(48, 48, 11)),
    ];
    for (name, m) in &maps {
        for edge in EDGES {
            assert_bits(&format!("cell_cone {name} {edge:?}"), &cell_cone(m, edge), &brute_cell_cone(m, edge));
            assert_bits(
                &format!("cell_relaxed_cone {name} {edge:?}"),
                &cell_relaxed_cone(m, edge),
                &brute_relaxed(m, edge),
            );
        }
    }
}

/// A random small map: continuous heights, heights on a few levels (many exact ties, flat
/// regions, one-texel steps) or an integer-slope plane (ties along the slope).
fn random_map(w: usize, h: usize, style: u8, seed: u64) -> HeightMap {
    let mut r = Lcg(seed);
    match style {
        0 => HeightMap::from_fn(w, h, |_, _| r.next()),
        1 => HeightMap::from_fn(w, h, |_, _| (r.next() * 3.0).floor() / 4.0),
        _ => {
            let (sx, sy) = ((r.next() * 8.0).floor() / 32.0 - 0.125, (r.next() * 8.0).floor() / 32.0 - 0.125);
            plane(w, h, 0.5, sx, sy)
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    #[test]
    fn cell_kinds_match_brute_force_on_random_maps(
        w in 2usize..14,
        h in 2usize..14,
        style in 0u8..3,
        seed in any::<u64>(),
        clamp in any::<bool>(),
    ) {
        let m = random_map(w, h, style, seed);
        let edge = if clamp { EdgeMode::Clamp } else { EdgeMode::Repeat };
        let what = format!("{w}x{h} style {style} seed {seed} {edge:?}");
        assert_bits(&format!("cell_cone {what}"), &cell_cone(&m, edge), &brute_cell_cone(&m, edge));
        assert_bits(&format!("cell_quad_cone {what}"), &cell_quad_cone(&m, edge), &brute_quad(&m, edge));
        assert_bits(&format!("cell_relaxed_cone {what}"), &cell_relaxed_cone(&m, edge), &brute_relaxed(&m, edge));
        assert_bits(&format!("cell_piecewise_cone {what}"), &cell_piecewise_cone(&m, edge, 3), &brute_piecewise(&m, edge, 3));
    }
}

// ------------------------------------------------------------------------------------------
// Dense sampling of the surface (independent of the generator's lower bound)
// ------------------------------------------------------------------------------------------

/// Calls `f(dist to C, S(y))` for 17 × 17 points (16 × 16 cells of the sampling grid plus
/// the edges) of every copy of every cell in the directions `(ax, ay)` from cell `(i, j)`.
/// `S` comes from `HeightMap::bilinear` at the point's texture coordinates; the distance is the
/// Euclidean distance from the point to the square `C` in texture units.
fn sample_around(m: &HeightMap, edge: EdgeMode, i: usize, j: usize, ax: Dir, ay: Dir, f: &mut dyn FnMut(f64, f64)) {
    let (w, h) = (m.width as f64, m.height as f64);
    // Absolute origin of the relative frame (repeat) or 0 (clamp).
    let (ox, oy) = if edge == EdgeMode::Repeat { (i as f64, j as f64) } else { (0.0, 0.0) };
    for (_, dy, cy) in copies(j, m.height, edge, ay) {
        for (_, dx, cx) in copies(i, m.width, edge, ax) {
            for b in 0..=16 {
                let y = dy[0] + (dy[1] - dy[0]) * b as f64 / 16.0;
                for a in 0..=16 {
                    let x = dx[0] + (dx[1] - dx[0]) * a as f64 / 16.0;
                    let s = m.bilinear((x + ox + 0.5) / w, (y + oy + 0.5) / h, edge);
                    let d = ((gap(x, cx) / w).powi(2) + (gap(y, cy) / h).powi(2)).sqrt();
                    f(d, s);
                }
            }
        }
    }
}

#[allow(clippy::too_many_arguments)]
fn check_cone(what: &str, m: &HeightMap, edge: EdgeMode, i: usize, j: usize, ax: Dir, ay: Dir, apex: f64, r: f64) {
    sample_around(m, edge, i, j, ax, ay, &mut |d, s| {
        let lim = if d == 0.0 { apex } else { apex + d / r };
        assert!(s <= lim + TOL * (1.0 + lim.abs()), "{what}: cell ({i}, {j}): S = {s} > {apex} + {d} / {r}");
    });
}

fn dense_maps() -> Vec<(&'static str, HeightMap)> {
    vec![
        ("noise", noise(12, 12, 3)),
        ("smooth", smooth(16, 16, 6)),
        ("boxes", boxes(16, 14, 7)),
        ("coarse", coarse_noise(12, 10, 2)),
    ]
}

#[test]
fn cell_cones_hold_on_densely_sampled_surface() {
    for (name, m) in dense_maps() {
        for edge in EDGES {
            let g = CellGrid::new(m.width, m.height, edge);
            let cone = cell_cone(&m, edge);
            let quad = cell_quad_cone(&m, edge);
            let nrm = cell_cone_normal(&m, edge);
            for j in 0..g.ch {
                for i in 0..g.cw {
                    let c = j * g.cw + i;
                    let a = cone[2 * c + 1] as f64;
                    check_cone(
                        &format!("cell_cone {name} {edge:?}"),
                        &m,
                        edge,
                        i,
                        j,
                        Dir::Both,
                        Dir::Both,
                        a,
                        cone[2 * c] as f64,
                    );
                    for (q, (ax, ay)) in QUADRANTS.into_iter().enumerate() {
                        check_cone(
                            &format!("cell_quad_cone {name} {edge:?} q{q}"),
                            &m,
                            edge,
                            i,
                            j,
                            ax,
                            ay,
                            quad[5 * c + 4] as f64,
                            quad[5 * c + q] as f64,
                        );
                    }
                    let r = ratio_of(nrm[2 * c]) as f64;
                    check_cone(
                        &format!("cell_cone_normal {name} {edge:?}"),
                        &m,
                        edge,
                        i,
                        j,
                        Dir::Both,
                        Dir::Both,
                        nrm[2 * c + 1] as f64,
                        r,
                    );
                }
            }
        }
    }
}

#[test]
fn cell_multi_and_piecewise_cones_hold_on_densely_sampled_surface() {
    let k = 3;
    for (name, m) in dense_maps() {
        for edge in EDGES {
            let g = CellGrid::new(m.width, m.height, edge);
            let multi = cell_multi_cone(&m, edge, k);
            let piece = cell_piecewise_cone(&m, edge, k);
            for j in 0..g.ch {
                for i in 0..g.cw {
                    let c = j * g.cw + i;
                    let a = multi[(k + 1) * c + k];
                    let b = heights(a, k);
                    for q in 0..k {
                        let r = ratio_of(multi[(k + 1) * c + q]) as f64;
                        check_cone(
                            &format!("cell_multi_cone {name} {edge:?} k{q}"),
                            &m,
                            edge,
                            i,
                            j,
                            Dir::Both,
                            Dir::Both,
                            b[q],
                            r,
                        );
                    }
                    // Piecewise: rebuild R(z) from the stored slopes, as a shader does.
                    let slopes: Vec<f64> = (0..k).map(|q| ratio_of(piece[(k + 1) * c + q]) as f64).collect();
                    let radius = |z: f64| -> f64 {
                        let mut r = 0.0;
                        for q in 0..k {
                            if z <= b[q] + TOL {
                                break;
                            }
                            if slopes[q].is_infinite() {
                                return f64::INFINITY;
                            }
                            r += slopes[q] * (z.min(b[q + 1]) - b[q]);
                        }
                        r
                    };
                    sample_around(&m, edge, i, j, Dir::Both, Dir::Both, &mut |d, s| {
                        // No point of the solid dist <= R(z) lies below the surface: R(S(y)) <= dist.
                        let rr = radius(s.min(1.0));
                        if s > b[0] {
                            assert!(
                                rr <= d + TOL * (1.0 + d),
                                "cell_piecewise_cone {name} {edge:?} ({i}, {j}): R({s}) = {rr} > dist {d}"
                            );
                        }
                    });
                }
            }
        }
    }
}

// ------------------------------------------------------------------------------------------
// The relaxed rule, by marching rays
// ------------------------------------------------------------------------------------------

#[test]
fn relaxed_cell_cone_rays_cross_at_most_once_inside_the_cone() {
    let mut r = Lcg(77);
    let mut pierced = 0usize;
    let mut rays = 0usize;
    let mut wider = 0usize;
    for (name, m) in [
        ("smooth", smooth(32, 32, 3)),
        ("boxes", boxes(24, 24, 5)),
        ("noise", noise(16, 16, 9)),
        ("smooth2", smooth(24, 20, 11)),
    ] {
        for edge in EDGES {
            let g = CellGrid::new(m.width, m.height, edge);
            let rel = cell_relaxed_cone(&m, edge);
            let cons = cell_cone(&m, edge);
            let (w, h) = (m.width as f64, m.height as f64);
            wider += (0..g.cw * g.ch).filter(|&c| rel[2 * c] > cons[2 * c]).count();
            for _ in 0..600 {
                let i = ((r.f() * g.cw as f64) as usize).min(g.cw - 1);
                let j = ((r.f() * g.ch as f64) as usize).min(g.ch - 1);
                let c = j * g.cw + i;
                let (ratio, a) = (rel[2 * c] as f64, rel[2 * c + 1] as f64);
                let (_, _, cx0, cx1) = ext(i, m.width, edge);
                let (_, _, cy0, cy1) = ext(j, m.height, edge);
                for _ in 0..8 {
                    // Start: a point of C, at a height in [A, 1]; direction 0-89 degrees down.
                    let x0 = cx0 + (cx1 - cx0) * r.f();
                    let y0 = cy0 + (cy1 - cy0) * r.f();
                    let z0 = a + (1.0 - a) * r.f();
                    let th = r.f() * std::f64::consts::TAU;
                    let dip = (r.f() * 89.0).to_radians().tan();
                    let (du, dv) = (th.cos(), th.sin());
                    let step = 1.0 / (32.0 * w.max(h));
                    let mut sign = 0i32;
                    let mut changes = 0;
                    let mut went_below = false;
                    let mut t = 0.0f64;
                    while t < 1.0 {
                        let (x, y) = (x0 + du * t * w, y0 + dv * t * h);
                        let z = z0 - dip * t;
                        if edge == EdgeMode::Clamp && !((-0.5..=w - 0.5).contains(&x) && (-0.5..=h - 0.5).contains(&y))
                        {
                            break;
                        }
                        let d = ((gap(x, [cx0, cx1]) / w).powi(2) + (gap(y, [cy0, cy1]) / h).powi(2)).sqrt();
                        let inside = if d == 0.0 { z >= a } else { z >= a + d / ratio };
                        if !inside || z < 0.0 {
                            break;
                        }
                        let gz = z - m.bilinear((x + 0.5) / w, (y + 0.5) / h, edge);
                        let s = if gz > 1e-9 {
                            1
                        } else if gz < -1e-9 {
                            -1
                        } else {
                            0
                        };
                        if s != 0 {
                            if sign != 0 && s != sign {
                                changes += 1;
                            }
                            sign = s;
                            went_below |= s < 0;
                        }
                        t += step;
                    }
                    rays += 1;
                    pierced += usize::from(went_below);
                    assert!(changes <= 1, "{name} {edge:?} cell ({i}, {j}) R = {ratio}: {changes} sign changes from ({x0}, {y0}, {z0}) dir {th} dip {dip}");
                }
            }
        }
    }
    // The test must exercise relaxed cones that the surface actually pierces.
    eprintln!(
        "relaxed rays: {pierced} of {rays} went below the surface inside the cone; {wider} cells wider than cell_cone"
    );
    assert!(
        wider > 0 && pierced >= 100,
        "relaxed cones too narrow to test: wider {wider}, pierced {pierced} of {rays}"
    );
}

// ------------------------------------------------------------------------------------------
// Kinds, encodings, grid
// ------------------------------------------------------------------------------------------

#[test]
fn cell_kinds_build_list_and_round_safely() {
    let m = boxes(16, 12, 4);
    let p = MapParams { cones: 3, z_resolution: 4 };
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_relief")).args(["maps", "--list"]).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let list = String::from_utf8(out.stdout).unwrap();
    for kind in MapKind::ALL.into_iter().filter(|k| k.is_cell()) {
        assert!(list.contains(kind.name()), "{kind} missing from --list");
        for edge in EDGES {
            let g = CellGrid::new(16, 12, edge);
            let map = maps::build(&m, kind, &p, edge).unwrap();
            // The quad cone map stores a cell as 2 × 2 texels (see the test below).
            let k = if kind == MapKind::CellQuadCone { 2 } else { 1 };
            assert_eq!(
                (map.width, map.height, map.channels),
                (k * g.cw, k * g.ch, kind.channels(&p)),
                "{kind} {edge:?}"
            );
            for (format, sqrt) in [
                (Format::F16, false),
                (Format::F16, true),
                (Format::Unorm8, true),
                (Format::Unorm8, false),
                (Format::Unorm16, true),
            ] {
                let enc = Encoding { format, sqrt, max_value: 1.0 };
                let dec = maps::build_encoded(&m, kind, &p, edge, &enc).unwrap().base.decode();
                for (n, (&v, &d)) in map.data.iter().zip(&dec.data).enumerate() {
                    if n % map.channels == map.channels - 1 {
                        assert!(d >= v, "{kind} {format:?}: apex {v} encoded down to {d}");
                    } else {
                        assert!(d <= v, "{kind} {format:?}: ratio / n_z {v} encoded up to {d}");
                    }
                }
            }
        }
    }
    for name in [
        "cell_cone",
        "cell_quad_cone",
        "cell_relaxed_cone",
        "cell_cone_normal",
        "cell_multi_cone",
        "cell_piecewise_cone",
    ] {
        assert!(name.parse::<MapKind>().unwrap().is_cell());
    }
}

#[test]
fn cell_of_uv_finds_the_cell_that_contains_the_point() {
    let mut r = Lcg(3);
    for edge in EDGES {
        for (w, h) in [(16, 16), (7, 5), (1, 3)] {
            let g = CellGrid::new(w, h, edge);
            for _ in 0..2000 {
                let (u, v) = (r.f(), r.f());
                let (i, j) = g.cell_of_uv(u, v);
                let (x, y) = (u * w as f64 - 0.5, v * h as f64 - 0.5);
                let (_, _, x0, x1) = ext(i, w, edge);
                let (_, _, y0, y1) = ext(j, h, edge);
                let inside = |p: f64, a: f64, b: f64, n: f64| match edge {
                    EdgeMode::Repeat => {
                        let q = (p - a).rem_euclid(n);
                        q <= b - a
                    }
                    EdgeMode::Clamp => a <= p && p <= b,
                };
                assert!(
                    inside(x, x0, x1, w as f64) && inside(y, y0, y1, h as f64),
                    "{edge:?} {w}x{h}: ({u}, {v}) -> ({i}, {j})"
                );
            }
        }
    }
}

// ------------------------------------------------------------------------------------------
// Distance field to the bilinear surface
// ------------------------------------------------------------------------------------------

/// Points of the solid under the bilinear surface: the surface sampled 8 × 8 per texel.
fn surface_samples(m: &HeightMap, edge: EdgeMode) -> Vec<(f64, f64, f64)> {
    let n = 8;
    let mut out = Vec::new();
    for b in 0..m.height * n {
        for a in 0..m.width * n {
            let (u, v) = ((a as f64 + 0.5) / (m.width * n) as f64, (b as f64 + 0.5) / (m.height * n) as f64);
            out.push((u, v, m.bilinear(u, v, edge)));
        }
    }
    out
}

/// Distance from `(u, v, z)` to the nearest sample of the solid (an upper bound of the true
/// distance to the solid; with repeat the shorter way round).
fn sampled_distance(samples: &[(f64, f64, f64)], edge: EdgeMode, u: f64, v: f64, z: f64) -> f64 {
    let wrap = |d: f64| if edge == EdgeMode::Repeat { d.abs().min(1.0 - d.abs()) } else { d };
    samples
        .iter()
        .map(|&(su, sv, s)| {
            let (du, dv, dz) = (wrap(su - u), wrap(sv - v), (z - s).max(0.0));
            (du * du + dv * dv + dz * dz).sqrt()
        })
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn distance_field_is_a_lower_bound_under_trilinear_filtering() {
    let mut r = Lcg(21);
    for (name, m) in [("smooth", smooth(16, 16, 5)), ("boxes", boxes(16, 12, 6)), ("noise", noise(12, 12, 8))] {
        for edge in EDGES {
            let depth = 8;
            let (w, h) = (m.width, m.height);
            let f = distance_field(&m, edge, depth);
            let samples = surface_samples(&m, edge);
            // At the voxels.
            for k in 0..depth {
                for y in 0..h {
                    for x in 0..w {
                        let (u, v, z) =
                            ((x as f64 + 0.5) / w as f64, (y as f64 + 0.5) / h as f64, (k as f64 + 0.5) / depth as f64);
                        let d = sampled_distance(&samples, edge, u, v, z);
                        let s = f[(k * h + y) * w + x] as f64;
                        assert!(s <= d + TOL, "{name} {edge:?} voxel ({x}, {y}, {k}): stored {s} > sampled {d}");
                    }
                }
            }
            // Trilinear reads anywhere (clamp-to-edge in z; u, v by the edge mode).
            let idx = |i: i64, n: usize| edge.index(i, n);
            for _ in 0..1500 {
                let (u, v, z) = (r.f(), r.f(), r.f());
                let (fx, fy, fz) =
                    (u * w as f64 - 0.5, v * h as f64 - 0.5, (z * depth as f64 - 0.5).clamp(0.0, depth as f64 - 1.0));
                let (x0, y0, z0) = (fx.floor(), fy.floor(), fz.floor().min(depth as f64 - 1.0));
                let (tx, ty, tz) = (fx - x0, fy - y0, fz - z0);
                let mut val = 0.0;
                for c in 0..8 {
                    let (ox, oy, oz) = ((c & 1) as i64, ((c >> 1) & 1) as i64, (c >> 2) as i64);
                    let wgt = (if ox == 1 { tx } else { 1.0 - tx })
                        * (if oy == 1 { ty } else { 1.0 - ty })
                        * (if oz == 1 { tz } else { 1.0 - tz });
                    let kz = ((z0 as i64 + oz) as usize).min(depth - 1);
                    val += wgt * f[(kz * h + idx(y0 as i64 + oy, h)) * w + idx(x0 as i64 + ox, w)] as f64;
                }
                let d = sampled_distance(&samples, edge, u, v, z);
                assert!(val <= d + TOL, "{name} {edge:?} at ({u}, {v}, {z}): trilinear {val} > sampled distance {d}");
            }
            // And it is not trivially zero: some voxel far above the surface has room.
            if name == "smooth" {
                assert!(f.iter().any(|&s| s > 0.1), "{name} {edge:?}: field is all but zero");
            }
        }
    }
}
