//! 3D distance field for sphere tracing (Donnelly 2005, *Per-Pixel Displacement Mapping with
//! Distance Functions*, GPU Gems 2 ch. 8; surveyed by Szirmay-Kalos & Umenhoffer 2008,
//! *Displacement Mapping on the GPU*, section on sphere tracing).
//!
//! # Definition
//!
//! The solid is everything under the **bilinear surface** `S` the shaders sample
//! (`{(y, z) : z ≤ S(y)}`, with the edge mode). Voxel `(x, y, k)` of a
//! `width x height x depth` grid sits at texture coordinates `((x + .5)/width, (y + .5)/height)`
//! (a texel centre) and height `z_k = (k + .5) / depth`; `depth` (the z resolution) is a
//! parameter. Distances are Euclidean in the unscaled (u, v, height) unit cube.
//!
//! **Box bound.** A bilinear cell `D` ([`super::cell`]) never rises above its largest corner
//! `M_D`, so the solid lies inside the union of the boxes `D × [0, M_D]`, and the distance to
//! that union is a lower bound of the distance to the solid. From a texel centre `p` the gap
//! to a cell along each axis is the gap to the nearer of its two corner columns (cells and
//! texel centres share the integer grid), so the horizontal distance from `p` to `D` is the
//! distance to `D`'s nearest corner texel. Regrouping the minimum by corner texel `q`, with
//! `H_q` the largest `M_D` over the (up to four) cells with corner `q` — the maximum of the
//! 3×3 texels around `q` —
//!
//! ```text
//! B(p, z) = min over texels q of sqrt(dist(p, q)² + max(0, z − H_q)²)
//! ```
//!
//! is exactly the distance from voxel `p` to the union of boxes (with [`EdgeMode::Clamp`] the
//! half-texel border cells have the border texels as corners, so the same holds).
//!
//! **Trilinear filtering.** A stage reads the field trilinearly at any point `x`: the result
//! is `Σ w_i F(v_i)` over the 8 voxel centres `v_i` around `x` (weights `w_i ≥ 0`, sum 1; at the
//! volume's faces clamp-to-edge keeps `v_i` among the nearest centres). The true distance `d`
//! to the solid is 1-Lipschitz, so `d(v_i) ≤ d(x) + |v_i − x| ≤ d(x) + δ`, with `δ` the voxel
//! diagonal `sqrt(1/width² + 1/height² + 1/depth²)` (every `v_i` is within one diagonal of `x`).
//! Storing
//!
//! ```text
//! D(p, z) = max(0, B(p, z) − δ)
//! ```
//!
//! gives `F(v_i) ≤ max(0, d(x) + δ − δ) = d(x)` for every `i`, hence `Σ w_i F(v_i) ≤ d(x)`: the
//! interpolated value is a lower bound of the distance at `x` itself, so a sphere of that
//! radius around any ray point is free of the surface. (Subtracting only the mean
//! interpolation error `δ/2` would need negative stored values, which unorm encodings clamp.)
//! The price: within `δ` of the surface the field reads 0, so a sphere-tracing stage needs
//! another way to close the last voxel (e.g. a bilinear-patch intersection). Unsigned; `dist`
//! wraps the shorter way round with [`EdgeMode::Repeat`]. Stored as f32 rounded down. Layout:
//! slice-major, `data[(k * height + y) * width + x]`, slice 0 at the bottom.
//!
//! # Algorithm and complexity
//!
//! For each slice the squared distance is a 2D generalised distance transform of the sampled
//! function `f(q) = max(0, z_k - H_q)²`: `min_q |p - q|² + f(q)`, separable into a pass along
//! x then along y, each the lower envelope of parabolas (Felzenszwalb & Huttenlocher 2012,
//! *Distance Transforms of Sampled Functions*). Wrapping lines are unrolled three times so the
//! envelope sees every copy within half a period. Exact (up to rounding) in Θ(width · height ·
//! depth) time; slices run in parallel with rayon.

use crate::heightmap::{EdgeMode, HeightMap};

/// One line of the 1D transform: `out[i] = min_j (spacing (i - j))² + f[j]`.
/// `v`, `z` are scratch of length `f.len()` and `f.len() + 1`.
fn envelope(f: &[f64], spacing: f64, out: &mut [f64], v: &mut [usize], z: &mut [f64]) {
    let n = f.len();
    let pos = |i: usize| i as f64 * spacing;
    let mut k = 0usize;
    v[0] = 0;
    z[0] = f64::NEG_INFINITY;
    z[1] = f64::INFINITY;
    for q in 1..n {
        loop {
            let p = v[k];
            let s = ((f[q] + pos(q) * pos(q)) - (f[p] + pos(p) * pos(p))) / (2.0 * (pos(q) - pos(p)));
            if s <= z[k] && k > 0 {
                k -= 1;
                continue;
            }
            if s <= z[k] {
                // k == 0 and the new parabola dominates from -inf.
                v[0] = q;
                z[1] = f64::INFINITY;
                break;
            }
            k += 1;
            v[k] = q;
            z[k] = s;
            z[k + 1] = f64::INFINITY;
            break;
        }
    }
    k = 0;
    for (q, o) in out.iter_mut().enumerate() {
        while z[k + 1] < pos(q) {
            k += 1;
        }
        let d = pos(q) - pos(v[k]);
        *o = d * d + f[v[k]];
    }
}

/// 1D transform along a line, wrapping or not.
fn line(f: &[f64], spacing: f64, wrap: bool, out: &mut [f64], scratch: &mut Scratch) {
    let n = f.len();
    if wrap && n > 1 {
        scratch.ext.clear();
        for _ in 0..3 {
            scratch.ext.extend_from_slice(f);
        }
        let m = 3 * n;
        scratch.res.resize(m, 0.0);
        scratch.v.resize(m, 0);
        scratch.z.resize(m + 1, 0.0);
        envelope(&scratch.ext, spacing, &mut scratch.res, &mut scratch.v, &mut scratch.z);
        out.copy_from_slice(&scratch.res[n..2 * n]);
    } else {
        scratch.v.resize(n, 0);
        scratch.z.resize(n + 1, 0.0);
        envelope(f, spacing, out, &mut scratch.v, &mut scratch.z);
    }
}

#[derive(Default)]
struct Scratch {
    ext: Vec<f64>,
    res: Vec<f64>,
    v: Vec<usize>,
    z: Vec<f64>,
}

/// `H_q`: the largest texel of the 3×3 neighbourhood of each texel (module docs).
pub(crate) fn cell_box_heights(map: &HeightMap, edge: EdgeMode) -> Vec<f32> {
    let (w, h) = (map.width, map.height);
    let mut out = Vec::with_capacity(w * h);
    for y in 0..h as i64 {
        for x in 0..w as i64 {
            let mut m = f32::NEG_INFINITY;
            for dy in -1..=1 {
                for dx in -1..=1 {
                    m = m.max(map.texel(x + dx, y + dy, edge));
                }
            }
            out.push(m);
        }
    }
    out
}

/// The voxel diagonal `δ` subtracted for trilinear filtering (module docs), rounded up.
pub(crate) fn voxel_diagonal(w: usize, h: usize, depth: usize) -> f64 {
    let (a, b, c) = (1.0 / w as f64, 1.0 / h as f64, 1.0 / depth as f64);
    (a * a + b * b + c * c).sqrt() * (1.0 + 1e-12)
}

/// The distance field, `width * height * depth` values (see the module docs).
pub fn distance_field(map: &HeightMap, edge: EdgeMode, depth: usize) -> Vec<f32> {
    use rayon::prelude::*;
    let (w, h) = (map.width, map.height);
    let wrap = edge == EdgeMode::Repeat;
    let mut out = vec![0.0f32; w * h * depth];
    let hmax = cell_box_heights(map, edge);
    let diag = voxel_diagonal(w, h, depth);
    out.par_chunks_mut(w * h).enumerate().for_each(|(k, slice)| {
        let zk = (k as f64 + 0.5) / depth as f64;
        let mut g: Vec<f64> = hmax
            .iter()
            .map(|&hq| {
                let d = (zk - hq as f64).max(0.0);
                d * d
            })
            .collect();
        let mut scratch = Scratch::default();
        let mut row_out = vec![0.0f64; w];
        for y in 0..h {
            line(&g[y * w..(y + 1) * w], 1.0 / w as f64, wrap, &mut row_out, &mut scratch);
            g[y * w..(y + 1) * w].copy_from_slice(&row_out);
        }
        let mut col = vec![0.0f64; h];
        let mut col_out = vec![0.0f64; h];
        for x in 0..w {
            for y in 0..h {
                col[y] = g[y * w + x];
            }
            line(&col, 1.0 / h as f64, wrap, &mut col_out, &mut scratch);
            for y in 0..h {
                slice[y * w + x] = super::encode::f32_down((col_out[y].max(0.0).sqrt() - diag).max(0.0));
            }
        }
    });
    out
}
