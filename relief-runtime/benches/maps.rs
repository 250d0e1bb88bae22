//! Map generator timings at 1024² (the goals: exact conservative cone map ≤ 2 s,
//! relaxed ≤ 10 s on 2 cores). `cargo bench -p relief-runtime --bench maps`.
//! White noise and 6-octave value noise (fBm) as inputs.

use criterion::{criterion_group, criterion_main, Criterion};
use relief_runtime::heightmap::{EdgeMode, HeightMap};
use relief_runtime::maps::cone::cone_ratios;
use relief_runtime::maps::relaxed_cone::relaxed_cone_ratios;
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

criterion_group!(benches, bench);
criterion_main!(benches);
