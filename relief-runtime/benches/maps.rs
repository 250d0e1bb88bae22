//! Map generator timings at 1024² (goals: exact conservative cone map ≤ 2 s,
//! relaxed ≤ 10 s on 2 cores). `cargo bench -p relief-runtime --bench maps`.
//! White noise and 6-octave value noise (fBm) as inputs.
//!
//! The cell kinds (goals on 2 cores: `cell_cone` 1024² ≤ 1 s and
//! `cell_relaxed_cone` 1024² ≤ 5 s, on fBm and on a hard-edged map of boxes, one-texel walls
//! and single-texel pillars): group `cells_1024`, e.g.
//! `cargo bench -p relief-runtime --bench maps -- cells`.

use criterion::{criterion_group, criterion_main, Criterion};
use relief_runtime::maps::cell::cone::cell_cone;
use relief_runtime::maps::cell::patch::cell_patch;
use relief_runtime::maps::cell::relaxed_cone::cell_relaxed_cone;
use relief_runtime::maps::cone::cone_ratios;
use relief_runtime::maps::relaxed_cone::relaxed_cone_ratios;
use relief_runtime::{EdgeMode, HeightMap};
use std::time::Duration;

struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// White noise: every texel independent.
fn white_noise(n: usize) -> HeightMap {
    let mut r = Lcg(1);
    HeightMap::from_fn(n, n, |_, _| r.next())
}

/// Value noise, 6 octaves (fBm), tileable: smooth hills where cones are wide.
fn fbm(n: usize) -> HeightMap {
    let mut r = Lcg(2);
    let lattice: Vec<Vec<f32>> = (0..6).map(|o| (0..(4usize << o).pow(2)).map(|_| r.next()).collect()).collect();
    let mut data = vec![0.0f32; n * n];
    for y in 0..n {
        for x in 0..n {
            let mut s = 0.0;
            let mut amp = 0.5;
            for (o, lat) in lattice.iter().enumerate() {
                let g = 4usize << o;
                let fx = x as f32 / n as f32 * g as f32;
                let fy = y as f32 / n as f32 * g as f32;
                let (x0, y0) = (fx.floor() as usize % g, fy.floor() as usize % g);
                let (x1, y1) = ((x0 + 1) % g, (y0 + 1) % g);
                let (tx, ty) = (fx.fract(), fy.fract());
                let (tx, ty) = (tx * tx * (3.0 - 2.0 * tx), ty * ty * (3.0 - 2.0 * ty));
                let a = lat[y0 * g + x0] + (lat[y0 * g + x1] - lat[y0 * g + x0]) * tx;
                let b = lat[y1 * g + x0] + (lat[y1 * g + x1] - lat[y1 * g + x0]) * tx;
                s += amp * (a + (b - a) * ty);
                amp *= 0.5;
            }
            data[y * n + x] = s / 0.984375;
        }
    }
    HeightMap::new(n, n, data)
}

/// Hard edges: 40 flat-topped boxes (4–64 texels a side), 20 one-texel walls (up to 256 long)
/// and 200 single-texel pillars on a floor at 0.1.
fn hard_edged(n: usize) -> HeightMap {
    let mut r = Lcg(3);
    let mut m = HeightMap::from_fn(n, n, |_, _| 0.1);
    let mut set = |x: usize, y: usize, z: f32| m.data[(y % n) * n + x % n] = z;
    for _ in 0..40 {
        let (x0, y0) = ((r.next() * n as f32) as usize, (r.next() * n as f32) as usize);
        let (bw, bh) = (4 + (r.next() * 60.0) as usize, 4 + (r.next() * 60.0) as usize);
        let z = 0.3 + 0.7 * r.next();
        for y in y0..y0 + bh {
            for x in x0..x0 + bw {
                set(x, y, z);
            }
        }
    }
    for k in 0..20 {
        let (x0, y0) = ((r.next() * n as f32) as usize, (r.next() * n as f32) as usize);
        let len = (r.next() * 256.0) as usize;
        let z = 0.5 + 0.5 * r.next();
        for t in 0..len {
            if k % 2 == 0 {
                set(x0 + t, y0, z);
            } else {
                set(x0, y0 + t, z);
            }
        }
    }
    for _ in 0..200 {
        let (x, y) = ((r.next() * n as f32) as usize, (r.next() * n as f32) as usize);
        set(x, y, 0.4 + 0.6 * r.next());
    }
    m
}

fn bench_cells(c: &mut Criterion) {
    let mut g = c.benchmark_group("cells_1024");
    g.sample_size(10).warm_up_time(Duration::from_millis(1)).measurement_time(Duration::from_secs(1));
    let hills = fbm(1024);
    let hard = hard_edged(1024);
    for edge in [EdgeMode::Repeat, EdgeMode::Clamp] {
        let e = if edge == EdgeMode::Repeat { "repeat" } else { "clamp" };
        g.bench_function(format!("cell_cone_fbm_{e}"), |b| b.iter(|| cell_cone(&hills, edge)));
        g.bench_function(format!("cell_cone_hard_{e}"), |b| b.iter(|| cell_cone(&hard, edge)));
        g.bench_function(format!("cell_relaxed_cone_fbm_{e}"), |b| b.iter(|| cell_relaxed_cone(&hills, edge)));
        g.bench_function(format!("cell_relaxed_cone_hard_{e}"), |b| b.iter(|| cell_relaxed_cone(&hard, edge)));
        // The patch map the safe csm, cns and csm_relax read beside their cell map: one pass over
        // the cells, next to the cone's search.
        g.bench_function(format!("cell_patch_fbm_{e}"), |b| b.iter(|| cell_patch(&hills, edge)));
    }
    g.finish();
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("maps_1024");
    g.sample_size(10).warm_up_time(Duration::from_millis(1)).measurement_time(Duration::from_secs(1));
    let white = white_noise(1024);
    let hills = fbm(1024);
    g.bench_function("cone_white_noise", |b| b.iter(|| cone_ratios(&white, EdgeMode::Repeat)));
    g.bench_function("cone_fbm", |b| b.iter(|| cone_ratios(&hills, EdgeMode::Repeat)));
    g.bench_function("relaxed_cone_white_noise", |b| b.iter(|| relaxed_cone_ratios(&white, EdgeMode::Repeat)));
    g.finish();
    // Relaxed cones on smooth terrain are far slower (see the report / relaxed_cone docs):
    // measured at 256² so the bench finishes.
    let mut g = c.benchmark_group("maps_256");
    g.sample_size(10).warm_up_time(Duration::from_millis(1)).measurement_time(Duration::from_secs(1));
    let hills256 = fbm(256);
    g.bench_function("relaxed_cone_fbm", |b| b.iter(|| relaxed_cone_ratios(&hills256, EdgeMode::Repeat)));
    g.finish();
}

criterion_group!(benches, bench_cells, bench);
criterion_main!(benches);
