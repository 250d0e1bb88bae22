//! Every fast map generator against its brute-force definition (kept here, written from the
//! definitions in the module docs), plus encoding, cache and ray-safety properties.

use proptest::prelude::*;
use relief_runtime::io::npy;
use relief_runtime::maps::cone::cone_ratios;
use relief_runtime::maps::cone_normal::{cone_normals, normal_z, relaxed_cone_normals};
use relief_runtime::maps::distance_field::distance_field;
use relief_runtime::maps::encode::{self, f32_down, Encoding, Format, Rounding};
use relief_runtime::maps::multi_cone::{cone_heights, piecewise_cone_normals, stacked_cone_normals};
use relief_runtime::maps::quad_cone::quad_cone_ratios;
use relief_runtime::maps::relaxed_cone::{exits, relaxed_cone_ratios};
use relief_runtime::maps::search::texel_distance;
use relief_runtime::maps::{self, Map, MapCache, MapKind, MapParams};
use relief_runtime::maps::{file, filter};
use relief_runtime::{EdgeMode, HeightMap};

// ------------------------------------------------------------------------------------------
// Test height maps
// ------------------------------------------------------------------------------------------

/// A small LCG (Numerical Recipes constants) so the maps are the same everywhere.
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
}

fn noise(w: usize, h: usize, seed: u64) -> HeightMap {
    let mut r = Lcg(seed);
    HeightMap::from_fn(w, h, |_, _| r.next())
}

/// Noise quantised to 8 levels: many equal heights (ties).
fn coarse_noise(w: usize, h: usize, seed: u64) -> HeightMap {
    let mut r = Lcg(seed);
    HeightMap::from_fn(w, h, |_, _| (r.next() * 8.0).floor() / 8.0)
}

/// Smooth bumps: a few wide features, where cones are wide and the search goes far.
fn bumps(w: usize, h: usize, seed: u64) -> HeightMap {
    let mut r = Lcg(seed);
    let c: Vec<(f32, f32, f32)> = (0..5).map(|_| (r.next(), r.next(), 0.05 + 0.2 * r.next())).collect();
    HeightMap::from_fn(w, h, |x, y| {
        let (u, v) = ((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
        let mut s = 0.0f32;
        for &(cu, cv, rad) in &c {
            let d2 = (u - cu).powi(2) + (v - cv).powi(2);
            s = s.max((1.0 - d2 / (rad * rad)).max(0.0));
        }
        s * 0.9
    })
}

fn spikes(w: usize, h: usize) -> HeightMap {
    HeightMap::from_fn(w, h, |x, y| match (x, y) {
        (3, 4) => 1.0,
        (x, y) if x == w - 2 && y == h / 2 => 0.6,
        (0, 0) => 0.3,
        _ => 0.1,
    })
}

fn wall(w: usize, h: usize) -> HeightMap {
    HeightMap::from_fn(w, h, |x, y| {
        if x == w / 3 {
            1.0
        } else if y == h / 2 {
            0.5
        } else {
            0.0
        }
    })
}

fn step(w: usize, h: usize) -> HeightMap {
    HeightMap::from_fn(w, h, |x, _| if x < w / 2 { 0.2 } else { 0.8 })
}

fn flat(w: usize, h: usize, v: f32) -> HeightMap {
    HeightMap::from_fn(w, h, |_, _| v)
}

fn suite(w: usize, h: usize) -> Vec<(&'static str, HeightMap)> {
    vec![
        ("noise", noise(w, h, 7 + w as u64)),
        ("coarse noise", coarse_noise(w, h, 11)),
        ("bumps", bumps(w, h, 3)),
        ("spikes", spikes(w, h)),
        ("wall", wall(w, h)),
        ("flat 0", flat(w, h, 0.0)),
        ("flat 1", flat(w, h, 1.0)),
        ("step", step(w, h)),
    ]
}

const EDGES: [EdgeMode; 2] = [EdgeMode::Repeat, EdgeMode::Clamp];

// ------------------------------------------------------------------------------------------
// Brute-force definitions
// ------------------------------------------------------------------------------------------

/// Signed offset from p to q along one axis: shorter way round when wrapping (ties positive).
fn offset(p: usize, q: usize, n: usize, edge: EdgeMode) -> i64 {
    let d = q as i64 - p as i64;
    match edge {
        EdgeMode::Clamp => d,
        EdgeMode::Repeat => {
            let d = d.rem_euclid(n as i64);
            if d <= n as i64 - d {
                d
            } else {
                d - n as i64
            }
        }
    }
}

fn h_at(m: &HeightMap, x: usize, y: usize) -> f32 {
    m.data[y * m.width + x]
}

/// min over texels q with h_q > apex of dist / (h_q - apex), over the texels `keep` accepts.
fn brute_min(
    m: &HeightMap,
    edge: EdgeMode,
    px: usize,
    py: usize,
    apex: f64,
    mut off: impl FnMut(usize, usize) -> Option<(i64, i64)>,
    mut keep: impl FnMut(i64, i64, f32) -> bool,
) -> f64 {
    let _ = edge;
    let mut best = f64::INFINITY;
    for qy in 0..m.height {
        for qx in 0..m.width {
            let hq = h_at(m, qx, qy);
            if (hq as f64) <= apex {
                continue;
            }
            let Some((ox, oy)) = off(qx, qy) else { continue };
            if !keep(ox, oy, hq) {
                continue;
            }
            let r = texel_distance(ox, oy, m.width, m.height) / (hq as f64 - apex);
            best = best.min(r);
        }
    }
    let _ = (px, py);
    best
}

fn brute_cone(m: &HeightMap, edge: EdgeMode) -> Vec<f32> {
    let mut out = Vec::new();
    for py in 0..m.height {
        for px in 0..m.width {
            let off = |qx, qy| Some((offset(px, qx, m.width, edge), offset(py, qy, m.height, edge)));
            out.push(f32_down(brute_min(m, edge, px, py, h_at(m, px, py) as f64, off, |_, _, _| true)));
        }
    }
    out
}

/// Quadrant offsets: sign (+1 / -1) per axis; the way the ray goes round when wrapping.
fn quadrant_offset(p: usize, q: usize, n: usize, sign: i64, edge: EdgeMode) -> Option<i64> {
    let d = (q as i64 - p as i64) * sign;
    match edge {
        EdgeMode::Clamp => (d >= 0).then_some(d * sign),
        EdgeMode::Repeat => Some(d.rem_euclid(n as i64) * sign),
    }
}

fn brute_quad(m: &HeightMap, edge: EdgeMode) -> Vec<f32> {
    let signs = [(1, 1), (-1, 1), (-1, -1), (1, -1)];
    let mut out = Vec::new();
    for py in 0..m.height {
        for px in 0..m.width {
            for (sx, sy) in signs {
                let off = |qx, qy| {
                    Some((quadrant_offset(px, qx, m.width, sx, edge)?, quadrant_offset(py, qy, m.height, sy, edge)?))
                };
                out.push(f32_down(brute_min(m, edge, px, py, h_at(m, px, py) as f64, off, |_, _, _| true)));
            }
        }
    }
    out
}

fn brute_relaxed(m: &HeightMap, edge: EdgeMode) -> Vec<f32> {
    let mut out = Vec::new();
    for py in 0..m.height {
        for px in 0..m.width {
            let (u0, v0) = ((px as f64 + 0.5) / m.width as f64, (py as f64 + 0.5) / m.height as f64);
            let off = |qx, qy| Some((offset(px, qx, m.width, edge), offset(py, qy, m.height, edge)));
            let keep = |ox, oy, hq| exits(m, edge, u0, v0, ox, oy, hq);
            out.push(f32_down(brute_min(m, edge, px, py, h_at(m, px, py) as f64, off, keep)));
        }
    }
    out
}

fn brute_stacked(m: &HeightMap, edge: EdgeMode, k: usize) -> Vec<f32> {
    let mut out = Vec::new();
    for py in 0..m.height {
        for px in 0..m.width {
            let b = cone_heights(h_at(m, px, py), k);
            for apex in b.iter().take(k) {
                let off = |qx, qy| Some((offset(px, qx, m.width, edge), offset(py, qy, m.height, edge)));
                let r = brute_min(m, edge, px, py, *apex, off, |_, _, _| true);
                out.push(normal_z(f32_down(r)));
            }
        }
    }
    out
}

fn brute_piecewise(m: &HeightMap, edge: EdgeMode, k: usize) -> Vec<f32> {
    let mut out = Vec::new();
    for py in 0..m.height {
        for px in 0..m.width {
            let b = cone_heights(h_at(m, px, py), k);
            let mut radius = 0.0f64;
            for s in 0..k {
                if radius.is_infinite() {
                    out.push(1.0);
                    continue;
                }
                let mut best = f64::INFINITY;
                for qy in 0..m.height {
                    for qx in 0..m.width {
                        let hq = h_at(m, qx, qy) as f64;
                        let dh = hq.min(b[s + 1]) - b[s];
                        if hq <= b[s] || dh <= 0.0 {
                            continue;
                        }
                        let d = texel_distance(
                            offset(px, qx, m.width, edge),
                            offset(py, qy, m.height, edge),
                            m.width,
                            m.height,
                        );
                        best = best.min((d - radius).max(0.0) / dh);
                    }
                }
                let stored = f32_down(best);
                radius += stored as f64 * (b[s + 1] - b[s]);
                out.push(normal_z(stored));
            }
        }
    }
    out
}

/// The distance field's definition (`maps::distance_field` docs): distance from each voxel to
/// the union of the boxes `cell × [0, largest corner]` of the bilinear cells, minus the voxel
/// diagonal, at least 0. Computed directly from the boxes (not by the 3×3 regrouping).
fn brute_distance(m: &HeightMap, edge: EdgeMode, depth: usize) -> Vec<f64> {
    let (w, h) = (m.width, m.height);
    let (cw, ch) = if edge == EdgeMode::Repeat { (w, h) } else { (w + 1, h + 1) };
    // Cell extent along an axis in texel-centre units, and its corner texels.
    let ext = |i: usize, n: usize| -> (f64, f64, usize, usize) {
        match edge {
            EdgeMode::Repeat => (i as f64, i as f64 + 1.0, i, (i + 1) % n),
            EdgeMode::Clamp => (
                (i as f64 - 1.0).max(-0.5),
                (i as f64).min(n as f64 - 0.5),
                i.saturating_sub(1).min(n - 1),
                i.min(n - 1),
            ),
        }
    };
    // Gap from integer coordinate p to [a, b] (with repeat: the shorter way round).
    let gap = |p: f64, a: f64, b: f64, n: f64| -> f64 {
        let g = |p: f64| (a - p).max(p - b).max(0.0);
        if edge == EdgeMode::Repeat {
            g(p).min(g(p + n)).min(g(p - n))
        } else {
            g(p)
        }
    };
    let diag = ((1.0 / w as f64).powi(2) + (1.0 / h as f64).powi(2) + (1.0 / depth as f64).powi(2)).sqrt();
    let mut out = Vec::new();
    for k in 0..depth {
        let z = (k as f64 + 0.5) / depth as f64;
        for py in 0..h {
            for px in 0..w {
                let mut best = f64::INFINITY;
                for j in 0..ch {
                    let (y0, y1, ta, tb) = ext(j, h);
                    for i in 0..cw {
                        let (x0, x1, sa, sb) = ext(i, w);
                        let top = [h_at(m, sa, ta), h_at(m, sb, ta), h_at(m, sa, tb), h_at(m, sb, tb)]
                            .into_iter()
                            .fold(0.0f32, f32::max);
                        let gx = gap(px as f64, x0, x1, w as f64) / w as f64;
                        let gy = gap(py as f64, y0, y1, h as f64) / h as f64;
                        let dz = (z - top as f64).max(0.0);
                        best = best.min((gx * gx + gy * gy + dz * dz).sqrt());
                    }
                }
                out.push((best - diag).max(0.0));
            }
        }
    }
    out
}

fn assert_same(name: &str, fast: &[f32], brute: &[f32]) {
    assert_eq!(fast.len(), brute.len(), "{name}: length");
    for (i, (a, b)) in fast.iter().zip(brute).enumerate() {
        assert!(a.to_bits() == b.to_bits(), "{name}: value {i}: fast {a} != brute {b}");
    }
}

// ------------------------------------------------------------------------------------------
// Fast == brute force
// ------------------------------------------------------------------------------------------

#[test]
fn cone_matches_brute_force_exactly() {
    for (w, h) in [(32, 32), (64, 64), (24, 40)] {
        for (name, m) in suite(w, h) {
            for edge in EDGES {
                assert_same(&format!("cone {name} {w}x{h} {edge:?}"), &cone_ratios(&m, edge), &brute_cone(&m, edge));
            }
        }
    }
}

#[test]
fn quad_cone_matches_brute_force_exactly() {
    for (w, h) in [(32, 32), (20, 36)] {
        for (name, m) in suite(w, h) {
            for edge in EDGES {
                assert_same(
                    &format!("quad {name} {w}x{h} {edge:?}"),
                    &quad_cone_ratios(&m, edge),
                    &brute_quad(&m, edge),
                );
            }
        }
    }
}

#[test]
fn quad_cone_at_least_isotropic_cone() {
    let m = bumps(48, 48, 9);
    for edge in EDGES {
        let c = cone_ratios(&m, edge);
        let q = quad_cone_ratios(&m, edge);
        for i in 0..c.len() {
            for k in 0..4 {
                assert!(q[4 * i + k] >= c[i], "texel {i} channel {k}");
            }
        }
    }
}

#[test]
fn relaxed_cone_matches_brute_force() {
    for (w, h) in [(32, 32), (64, 64)] {
        for (name, m) in suite(w, h) {
            for edge in EDGES {
                let fast = relaxed_cone_ratios(&m, edge);
                assert_same(&format!("relaxed {name} {w}x{h} {edge:?}"), &fast, &brute_relaxed(&m, edge));
                // A subset of the conservative constraints: never narrower.
                let cons = cone_ratios(&m, edge);
                assert!(fast.iter().zip(&cons).all(|(r, c)| r >= c), "relaxed < conservative on {name}");
            }
        }
    }
}

#[test]
fn relaxed_cone_is_wider_on_a_valley_wall() {
    // A pit in a plateau: from the pit floor, the near wall faces the texel (entries only).
    let m = HeightMap::from_fn(32, 32, |x, y| if (12..20).contains(&x) && (12..20).contains(&y) { 0.1 } else { 0.7 });
    let c = cone_ratios(&m, EdgeMode::Repeat);
    let r = relaxed_cone_ratios(&m, EdgeMode::Repeat);
    let i = 16 * 32 + 16;
    assert!(r[i] > 2.0 * c[i], "relaxed {} vs conservative {}", r[i], c[i]);
}

#[test]
fn cone_normals_match_ratios() {
    for (name, m) in suite(32, 32) {
        for edge in EDGES {
            let r = cone_ratios(&m, edge);
            let n = cone_normals(&m, edge);
            for (a, b) in r.iter().zip(&n) {
                assert_eq!(normal_z(*a).to_bits(), b.to_bits(), "{name}");
                assert!((0.0..=1.0).contains(b));
                let exact = if a.is_infinite() { 1.0 } else { *a as f64 / (1.0 + (*a as f64).powi(2)).sqrt() };
                assert!((*b as f64) <= exact && exact - (*b as f64) < 1e-6);
            }
            let rr = relaxed_cone_ratios(&m, edge);
            let rn = relaxed_cone_normals(&m, edge);
            assert!(rr.iter().zip(&rn).all(|(a, b)| normal_z(*a) == *b));
        }
    }
    // No cap: a flat map gives flat cones.
    assert!(cone_normals(&flat(8, 8, 0.5), EdgeMode::Repeat).iter().all(|&v| v == 1.0));
}

#[test]
fn multi_and_piecewise_cones_match_brute_force_exactly() {
    for (name, m) in suite(24, 24) {
        for edge in EDGES {
            for k in [1, 3] {
                assert_same(
                    &format!("stacked {name} k={k} {edge:?}"),
                    &stacked_cone_normals(&m, edge, k),
                    &brute_stacked(&m, edge, k),
                );
                assert_same(
                    &format!("piecewise {name} k={k} {edge:?}"),
                    &piecewise_cone_normals(&m, edge, k),
                    &brute_piecewise(&m, edge, k),
                );
            }
        }
    }
}

#[test]
fn stacked_cone_zero_is_the_cone_map_and_cones_widen_upward() {
    let m = noise(32, 32, 5);
    let k = 4;
    let s = stacked_cone_normals(&m, EdgeMode::Repeat, k);
    let c = cone_normals(&m, EdgeMode::Repeat);
    for i in 0..c.len() {
        assert_eq!(s[i * k], c[i]);
        for j in 1..k {
            assert!(s[i * k + j] >= s[i * k + j - 1]);
        }
    }
    // Piece 0 only clears the surface up to b_1: at least the conservative cone.
    let p = piecewise_cone_normals(&m, EdgeMode::Repeat, k);
    assert!((0..c.len()).all(|i| p[i * k] >= c[i]));
}

#[test]
fn distance_field_matches_brute_force() {
    for (w, h, d) in [(32, 32, 8), (20, 28, 5)] {
        for (name, m) in suite(w, h) {
            for edge in EDGES {
                let fast = distance_field(&m, edge, d);
                let brute = brute_distance(&m, edge, d);
                for (i, (a, b)) in fast.iter().zip(&brute).enumerate() {
                    assert!((*a as f64) <= *b + 1e-12, "{name} {edge:?} voxel {i}: {a} > {b}");
                    assert!((*a as f64 - b).abs() <= 1e-6 * (1.0 + b), "{name} {edge:?} voxel {i}: {a} vs {b}");
                }
            }
        }
    }
}

#[test]
fn build_dispatches_every_kind() {
    let m = bumps(16, 16, 1);
    let p = MapParams { cones: 3, z_resolution: 4 };
    for kind in MapKind::ALL {
        let map = maps::build(&m, kind, &p, EdgeMode::Clamp).unwrap();
        assert_eq!(map.channels, kind.channels(&p), "{kind}");
        // Per cell: 17 × 17 cells under clamp, the quad cone map's 2 × 2 texels a cell.
        let cells = match kind {
            MapKind::CellQuadCone => 34 * 34,
            _ if kind.per_cell() => 17 * 17,
            _ => 16 * 16,
        };
        assert_eq!((map.data.len(), map.width * map.height), (cells * map.depth * map.channels, cells), "{kind}");
        assert_eq!(kind.name().parse::<MapKind>().unwrap(), kind);
        // `relief maps --list` states the same count in words ("1 channel", "K+1 channels").
        let words: Vec<&str> = kind.describe().split([' ', ';']).collect();
        if let Some(i) = words.iter().position(|w| w.starts_with("channel")) {
            let k = p.cones as usize;
            let said = match words[i - 1] {
                "K" => k,
                "K+1" => k + 1,
                n => n.parse().unwrap(),
            };
            assert_eq!(said, kind.channels(&p), "{kind}: {}", kind.describe());
        }
    }
    let mm = maps::build(&m, MapKind::MaxMip, &p, EdgeMode::Clamp).unwrap();
    assert_eq!(mm.mips.last().unwrap().data.len(), 1);
    let top = mm.mips.last().unwrap().data[0];
    assert_eq!(top, m.data.iter().cloned().fold(0.0, f32::max));
    assert!(maps::build(&m, MapKind::MultiCone, &MapParams { cones: 0, ..p }, EdgeMode::Clamp).is_err());
    assert!("nope".parse::<MapKind>().is_err());
}

// ------------------------------------------------------------------------------------------
// Encoding
// ------------------------------------------------------------------------------------------

#[test]
fn encodings_round_toward_conservative() {
    let mut r = Lcg(99);
    let mut values: Vec<f32> = (0..2000).map(|_| r.next() * r.next() * 3.0).collect();
    values.extend([0.0, 1.0, 0.5, 1e-9, 70000.0, f32::INFINITY, 1.0 / 3.0]);
    for format in [Format::F32, Format::F16, Format::Unorm8, Format::Unorm16] {
        for sqrt in [false, true] {
            let enc = Encoding { format, sqrt, max_value: 1.0 };
            for &v in &values {
                let down = enc.decode_code(enc.encode_value(v, Rounding::Down));
                assert!(down <= v, "{format:?} sqrt={sqrt}: {v} -> {down}");
                let up = enc.decode_code(enc.encode_value(v.min(1.0), Rounding::Up));
                assert!(up >= v.min(1.0), "{format:?} sqrt={sqrt} up: {v} -> {up}");
                // And close: within one code.
                if matches!(format, Format::Unorm8) && v <= 1.0 && !sqrt {
                    assert!(v - down <= 1.0 / 255.0 + 1e-6);
                }
            }
        }
    }
    // Only encodings clamp; f16 keeps inf; unorm clamps to max_value.
    let e8 = Encoding { format: Format::Unorm8, sqrt: true, max_value: 2.0 };
    assert_eq!(e8.decode_code(e8.encode_value(f32::INFINITY, Rounding::Down)), 2.0);
    let e16 = Encoding { format: Format::F16, sqrt: false, max_value: 1.0 };
    assert!(e16.decode_code(e16.encode_value(f32::INFINITY, Rounding::Down)).is_infinite());
    // sqrt spends codes on small ratios: 0.01 is representable far better.
    let plain = Encoding { format: Format::Unorm8, sqrt: false, max_value: 1.0 };
    let sq = Encoding { format: Format::Unorm8, sqrt: true, max_value: 1.0 };
    let v = 0.0123;
    assert!(
        (v - sq.decode_code(sq.encode_value(v, Rounding::Down)))
            < (v - plain.decode_code(plain.encode_value(v, Rounding::Down)))
    );
}

#[test]
fn min3x3_bounds_bilinear_filtering() {
    let m = noise(16, 16, 3);
    let cones = Map::new_2d(16, 16, 1, cone_ratios(&m, EdgeMode::Repeat).into_iter().map(|v| v.min(4.0)).collect());
    let f = filter::min3x3(&cones, EdgeMode::Repeat);
    let mut r = Lcg(5);
    for _ in 0..2000 {
        let (u, v) = (r.next() as f64, r.next() as f64);
        let x = u * 16.0 - 0.5;
        let y = v * 16.0 - 0.5;
        let (x0, y0) = (x.floor() as i64, y.floor() as i64);
        let (fx, fy) = (x - x0 as f64, y - y0 as f64);
        let g = |m: &Map, dx: i64, dy: i64| {
            m.get(EdgeMode::Repeat.index(x0 + dx, 16), EdgeMode::Repeat.index(y0 + dy, 16), 0, 0) as f64
        };
        let bil = (g(&f, 0, 0) * (1.0 - fx) + g(&f, 1, 0) * fx) * (1.0 - fy)
            + (g(&f, 0, 1) * (1.0 - fx) + g(&f, 1, 1) * fx) * fy;
        let narrowest = g(&cones, 0, 0).min(g(&cones, 1, 0)).min(g(&cones, 0, 1)).min(g(&cones, 1, 1));
        assert!(bil <= narrowest + 1e-6);
    }
}

fn temp_dir(tag: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("relief-maps-test-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn files_round_trip() {
    let dir = temp_dir("files");
    let m = bumps(20, 12, 2);
    let q = maps::build(&m, MapKind::QuadCone, &MapParams::default(), EdgeMode::Repeat).unwrap();
    // .npy float32 [h, w, c], read back by the height-map loader channel by channel.
    let e = encode::encode(&q, &Encoding::F32, Rounding::Down);
    let p = dir.join("q.npy");
    file::write_map(&p, &e).unwrap();
    let bytes = std::fs::read(&p).unwrap();
    let hdr = npy::parse_npy_header(&bytes).unwrap();
    assert_eq!(hdr.shape, vec![12, 20, 4]);
    assert_eq!(hdr.data_offset % 64, 0);
    let back: Vec<f32> =
        bytes[hdr.data_offset..].chunks_exact(4).map(|b| f32::from_le_bytes(b.try_into().unwrap())).collect();
    assert_same("npy", &back, &q.data);
    // .png 8 and 16 bit.
    for format in [Format::Unorm8, Format::Unorm16] {
        let enc = Encoding { format, sqrt: true, max_value: 1.0 };
        let c = maps::build(&m, MapKind::Cone, &MapParams::default(), EdgeMode::Repeat).unwrap();
        let e = encode::encode(&c, &enc, Rounding::Down);
        let p = dir.join(format!("c{format:?}.png"));
        file::write_map(&p, &e).unwrap();
        let img = image::open(&p).unwrap();
        assert_eq!((img.width(), img.height()), (20, 12));
        match format {
            Format::Unorm8 => assert_eq!(img.to_luma8().as_raw().as_slice(), e.bytes.as_slice()),
            _ => {
                let l = img.to_luma16();
                let codes: Vec<u16> = (0..240).map(|i| e.code(i) as u16).collect();
                assert_eq!(l.as_raw(), &codes);
            }
        }
    }
    // .exr (float) through image.
    let c = maps::build(&m, MapKind::ConeNormal, &MapParams::default(), EdgeMode::Repeat).unwrap();
    let p = dir.join("n.exr");
    file::write_map(&p, &encode::encode(&c, &Encoding::F32, Rounding::Down)).unwrap();
    let img = image::open(&p).unwrap().to_rgb32f();
    assert!(img.pixels().zip(&c.data).all(|(px, v)| px.0[0] == *v));
    // Errors, not panics.
    assert!(file::write_map(&dir.join("x.png"), &encode::encode(&c, &Encoding::F32, Rounding::Down)).is_err());
    assert!(file::write_map(&dir.join("x.txt"), &e).is_err());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn cache_builds_each_key_once() {
    let dir = temp_dir("cache");
    let m = noise(16, 16, 1);
    let p = MapParams::default();
    let cache = MapCache::with_dir(&dir);
    let a = cache.get(&m, MapKind::Cone, &p, EdgeMode::Repeat, &Encoding::F32).unwrap();
    let b =
        cache.get(&m, MapKind::Cone, &MapParams { z_resolution: 3, ..p }, EdgeMode::Repeat, &Encoding::F32).unwrap();
    assert!(std::sync::Arc::ptr_eq(&a, &b), "irrelevant parameters must not split the cache");
    assert_eq!(cache.builds(), 1);
    cache.get(&m, MapKind::Cone, &p, EdgeMode::Clamp, &Encoding::F32).unwrap();
    let u8e = Encoding { format: Format::Unorm8, sqrt: true, max_value: 1.0 };
    cache.get(&m, MapKind::Cone, &p, EdgeMode::Repeat, &u8e).unwrap();
    assert_eq!(cache.builds(), 3);
    let mut m2 = m.clone();
    m2.data[5] = 0.25;
    cache.get(&m2, MapKind::Cone, &p, EdgeMode::Repeat, &Encoding::F32).unwrap();
    assert_eq!(cache.builds(), 4);
    // A second cache over the same directory finds the maps on disk, identical.
    let again = MapCache::with_dir(&dir);
    let c = again.get(&m, MapKind::Cone, &p, EdgeMode::Repeat, &u8e).unwrap();
    assert_eq!(again.builds(), 0);
    assert_eq!(*c, *cache.get(&m, MapKind::Cone, &p, EdgeMode::Repeat, &u8e).unwrap());
    let _ = std::fs::remove_dir_all(&dir);
}

/// A map on disk whose channels are not the kind's (a file of a former layout: `cell_quad_cone`
/// held 5 channels a cell before it held 2 × 2 texels of 2) is built again, not read.
#[test]
fn cache_builds_again_a_map_stored_in_another_layout() {
    let dir = temp_dir("cache-layout");
    let (m, p) = (noise(8, 8, 2), MapParams::default());
    let f32e = Encoding::F32;
    let fresh = MapCache::with_dir(&dir).get(&m, MapKind::CellQuadCone, &p, EdgeMode::Repeat, &f32e).unwrap();
    let file = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|f| f.to_string_lossy().contains("cell_quad_cone"))
        .expect("the cache stored the map");
    // The former layout's shape, 8 × 8 cells of 5 values, at the same file.
    std::fs::write(&file, npy::npy_bytes(&[8, 8, 5], &[0.5; 320])).unwrap();
    let again = MapCache::with_dir(&dir);
    let read = again.get(&m, MapKind::CellQuadCone, &p, EdgeMode::Repeat, &f32e).unwrap();
    assert_eq!(again.builds(), 1, "a map of another layout was read from disk");
    assert_eq!(*read, *fresh);
    let _ = std::fs::remove_dir_all(&dir);
}

// ------------------------------------------------------------------------------------------
// Rays stepped with conservative cones never pass through the surface
// ------------------------------------------------------------------------------------------

/// Steps a ray with the cone map and checks it against a dense sampling of the bilinear
/// surface. The stepping rule is the one a safe tracer on the bilinear surface must use when
/// it reads the cone of the nearest texel `p` at a point `x` that is not `p`'s centre: every
/// corner `c` of the cell under a point `y` has `h_c <= h_p + |c - p| / r` (definition), and
/// `|c - p| <= |y - x| + δ + |x - p|` (δ = cell diagonal), so the surface stays under the cone
/// with apex height `h_p + (δ + |x - p|) / r` at `x` and ratio `r`.
fn ray_never_pierces(
    m: &HeightMap,
    edge: EdgeMode,
    cones: &[f32],
    u: f64,
    v: f64,
    dir: (f64, f64),
) -> Result<f64, String> {
    let (w, h) = (m.width as f64, m.height as f64);
    let delta = (1.0 / (w * w) + 1.0 / (h * h)).sqrt();
    let speed = (dir.0 * dir.0 + dir.1 * dir.1).sqrt();
    let at = |t: f64| (u + dir.0 * t, v + dir.1 * t, 1.0 - t);
    let mut t = 0.0f64;
    for _ in 0..64 {
        let (x, y, z) = at(t);
        let (px, py) = ((x * w).floor() as i64, (y * h).floor() as i64);
        let (ix, iy) = (edge.index(px, m.width), edge.index(py, m.height));
        let r = cones[iy * m.width + ix] as f64;
        let hp = m.data[iy * m.width + ix] as f64;
        // Distance from x to the centre of the texel read (in its own copy of the map).
        let (cx, cy) = ((px as f64 + 0.5) / w, (py as f64 + 0.5) / h);
        let near = ((x - cx).powi(2) + (y - cy).powi(2)).sqrt();
        let apex = if r.is_infinite() { hp } else { hp + (delta + near) / r };
        if z <= apex {
            break;
        }
        let dt = if r.is_infinite() { z - apex } else { (z - apex) / (1.0 + speed / r) };
        if dt < 1e-7 {
            break;
        }
        t = (t + dt).min(1.0);
    }
    // Dense check of [0, t].
    let n = 4000;
    for i in 0..=n {
        let s = t * i as f64 / n as f64;
        let (x, y, z) = at(s);
        let surf = m.bilinear(x, y, edge);
        if z < surf - 1e-9 {
            return Err(format!("ray below the surface at t = {s} (of {t}): z = {z}, surface = {surf}"));
        }
    }
    Ok(t)
}

fn prop_map(kind: u8, seed: u64) -> HeightMap {
    match kind % 4 {
        0 => noise(16, 16, seed),
        1 => bumps(20, 16, seed),
        2 => coarse_noise(16, 20, seed),
        _ => HeightMap::from_fn(16, 16, |x, y| if (x + 3 * y + seed as usize).is_multiple_of(7) { 0.9 } else { 0.2 }),
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, .. ProptestConfig::default() })]
    #[test]
    fn conservative_cone_rays_never_pierce(kind in 0u8..4, seed in 0u64..1000, clamp in any::<bool>(),
                                          u in 0.0f64..1.0, v in 0.0f64..1.0,
                                          angle in 0.0f64..std::f64::consts::TAU, slope in 0.05f64..3.0) {
        let m = prop_map(kind, seed);
        let edge = if clamp { EdgeMode::Clamp } else { EdgeMode::Repeat };
        let cones = cone_ratios(&m, edge);
        let dir = (angle.cos() * slope, angle.sin() * slope);
        if let Err(e) = ray_never_pierces(&m, edge, &cones, u, v, dir) {
            return Err(TestCaseError::fail(e));
        }
    }
}

#[test]
fn cone_stepping_makes_progress() {
    // Not vacuous: on a flat map one step lands on the surface, on bumps rays advance.
    let m = flat(16, 16, 0.25);
    let c = cone_ratios(&m, EdgeMode::Repeat);
    let t = ray_never_pierces(&m, EdgeMode::Repeat, &c, 0.3, 0.3, (0.5, 0.2)).unwrap();
    assert!((t - 0.75).abs() < 1e-12);
    let m = bumps(32, 32, 4);
    let c = cone_ratios(&m, EdgeMode::Repeat);
    let t = ray_never_pierces(&m, EdgeMode::Repeat, &c, 0.1, 0.7, (0.3, 0.1)).unwrap();
    assert!(t > 0.05, "t = {t}");
}

#[test]
fn map_kinds_and_requests_name_each_other() {
    use relief_dsl::spec::MapReq;
    // Every request but the normal map has exactly one kind, of the same name; the cone
    // count travels with the multi-cone requests.
    let reqs = [
        MapReq::Cone,
        MapReq::QuadCone,
        MapReq::RelaxedCone,
        MapReq::ConeNormal,
        MapReq::RelaxedConeNormal,
        MapReq::MultiCone(7),
        MapReq::PiecewiseCone(3),
        MapReq::MaxMip,
        MapReq::DistanceField,
        MapReq::CellCone,
        MapReq::CellQuadCone,
        MapReq::CellRelaxedCone,
        MapReq::CellConeNormal,
        MapReq::CellMultiCone(5),
        MapReq::CellPiecewiseCone(2),
        MapReq::CellPatch,
    ];
    assert!(MapKind::of(MapReq::Normal).is_none());
    let mut seen = Vec::new();
    for r in reqs {
        let (k, p) = MapKind::of(r).unwrap_or_else(|| panic!("{r:?} has no kind"));
        assert_eq!(k.name(), r.name());
        assert_eq!(k.name().parse::<MapKind>().unwrap(), k);
        if let MapReq::MultiCone(n)
        | MapReq::PiecewiseCone(n)
        | MapReq::CellMultiCone(n)
        | MapReq::CellPiecewiseCone(n) = r
        {
            assert_eq!(p.cones, n);
        }
        seen.push(k);
    }
    assert_eq!(seen, MapKind::ALL.to_vec(), "one request per kind, in the listing order");
}

/// `.exr` is written as scanline blocks (Babylon.js and three.js refuse tiled EXR; issue 39),
/// read back with the `exr` crate itself: not tiled, one part, and every texel's channels
/// equal to the map's (1 channel replicated to RGB, 2 with B = 0, 4 as they are), row 0 first.
#[test]
fn exr_is_scanline_and_texel_equal() {
    use exr::meta::{BlockDescription, MetaData};
    use exr::prelude::read_first_rgba_layer_from_file;
    let dir = temp_dir("exr-scanline");
    let m = bumps(24, 20, 5);
    for kind in [MapKind::Cone, MapKind::CellCone, MapKind::QuadCone] {
        let map = maps::build(&m, kind, &MapParams::default(), EdgeMode::Repeat).unwrap();
        let p = dir.join(format!("{kind}.exr"));
        file::write_map(&p, &encode::encode(&map, &Encoding::F32, Rounding::Down)).unwrap();
        let meta = MetaData::read_from_file(&p, false).unwrap();
        assert_eq!(meta.headers.len(), 1, "{kind}");
        assert!(matches!(meta.headers[0].blocks, BlockDescription::ScanLines), "{kind}: {:?}", meta.headers[0].blocks);
        let img = read_first_rgba_layer_from_file(
            &p,
            |size, _| (size.0, vec![[0f32; 4]; size.0 * size.1]),
            |(w, px), pos, (r, g, b, a): (f32, f32, f32, f32)| px[pos.1 * *w + pos.0] = [r, g, b, a],
        )
        .unwrap();
        let (w, px) = &img.layer_data.channel_data.pixels;
        assert_eq!((*w, px.len()), (map.width, map.width * map.height), "{kind}");
        let c = map.channels;
        for (i, got) in px.iter().enumerate() {
            let t = &map.data[i * c..(i + 1) * c];
            let want = match c {
                1 => [t[0], t[0], t[0], 1.0],
                2 => [t[0], t[1], 0.0, 1.0],
                3 => [t[0], t[1], t[2], 1.0],
                _ => [t[0], t[1], t[2], t[3]],
            };
            assert_eq!(got.map(f32::to_bits), want.map(f32::to_bits), "{kind}: texel {i} (row {})", i / map.width);
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
