//! 3D distance field for sphere tracing (Donnelly 2005, *Per-Pixel Displacement Mapping with
//! Distance Functions*, GPU Gems 2 ch. 8; surveyed by Szirmay-Kalos & Umenhoffer,
//! *Displacement Mapping on the GPU*, section on sphere tracing, paper 002).
//!
//! # Definition
//!
//! The solid under the surface is taken as the union of the texel columns
//! `{q} x [0, h_q]` (the point samples, extended down to the floor). Voxel `(x, y, k)` of a
//! `width x height x depth` grid sits at texture coordinates `((x + .5)/width, (y + .5)/height)`
//! and height `z_k = (k + .5) / depth`; `depth` (the z resolution) is a parameter. It stores the
//! exact Euclidean distance, in the unscaled (u, v, height) unit cube, to the nearest column:
//!
//! ```text
//! D(p, z) = min over texels q of sqrt(dist(p, q)² + max(0, z - h_q)²)
//! ```
//!
//! so `D = 0` inside the solid (unsigned; a sphere of radius `D` around the voxel centre is
//! free of the texel columns). `dist` wraps the shorter way round with [`EdgeMode::Repeat`];
//! with [`EdgeMode::Clamp`] the extended border columns are never nearer than the border itself,
//! so no wrapping. Stored as f32 rounded down. Layout: slice-major, `data[(k * height + y) * width + x]`,
//! slice 0 at the bottom.
//!
//! # Algorithm and complexity
//!
//! For each slice the squared distance is a 2D generalised distance transform of the sampled
//! function `f(q) = max(0, z_k - h_q)²`: `min_q |p - q|² + f(q)`, separable into a pass along
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

/// The distance field, `width * height * depth` values (see the module docs).
pub fn distance_field(map: &HeightMap, edge: EdgeMode, depth: usize) -> Vec<f32> {
    use rayon::prelude::*;
    let (w, h) = (map.width, map.height);
    let wrap = edge == EdgeMode::Repeat;
    let mut out = vec![0.0f32; w * h * depth];
    out.par_chunks_mut(w * h).enumerate().for_each(|(k, slice)| {
        let zk = (k as f64 + 0.5) / depth as f64;
        let mut g: Vec<f64> = map
            .data
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
                slice[y * w + x] = super::encode::f32_down(col_out[y].max(0.0).sqrt());
            }
        }
    });
    out
}
