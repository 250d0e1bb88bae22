//! Mesh scenes drawn on the device (issue 38, docs/meshes.md "Drawing and measuring"): the
//! mesh module's picture and measurement entries against independent computations on the
//! CPU (a brute-force ray–triangle test over the base mesh, the exact reference).

use glam::DVec3;
use relief_dsl::spec::Curved;
use relief_dsl::Pipeline;
use relief_runtime::gpu::mesh::{mesh_textures, probe_mesh, render_mesh, MeshProgram};
use relief_runtime::mesh::{Mesh, MeshScene};
use relief_runtime::mesh_measure::{score, PrismMiss};
use relief_runtime::{EdgeMode, Gpu};

const SIZE: u32 = 64;
const BASE: &str = "linear(32)+binary(5)";

fn gpu() -> Gpu {
    Gpu::new().unwrap_or_else(|e| panic!("{e}"))
}

fn scene(name: &str, edge: EdgeMode) -> MeshScene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("scenes/meshes/{name}.toml"));
    let mut s = relief_runtime::load_scene_file(&path).unwrap();
    s.edge = edge;
    MeshScene::from_scene(s).unwrap()
}

fn pipeline(mode: Curved) -> Pipeline {
    BASE.parse::<Pipeline>().unwrap().with_curved(Some(mode))
}

/// Whether the ray `o + t·d` meets the base mesh with every triangle's barycentric
/// coordinates widened by `margin` (negative: narrowed), Möller–Trumbore in f64, every
/// triangle tried.
fn meets_base(mesh: &Mesh, o: DVec3, d: DVec3, margin: f64) -> bool {
    mesh.triangles.iter().any(|t| {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize].as_dvec3());
        let (e1, e2) = (b - a, c - a);
        let p = d.cross(e2);
        let det = e1.dot(p);
        if det.abs() < 1e-14 {
            return false;
        }
        let s = o - a;
        let u = s.dot(p) / det;
        let q = s.cross(e1);
        let v = d.dot(q) / det;
        let t = e2.dot(q) / det;
        t > 0.0 && u >= -margin && v >= -margin && u + v <= 1.0 + margin
    })
}

/// `curved=none` draws every fragment of the base mesh (it discards nothing): its covered
/// pixels are those whose pixel-centre ray meets the base mesh, by a ray–triangle test written
/// here. A pixel is left out only where widening or narrowing every triangle by 1e-4 in
/// barycentric terms (far more than f32 rasterization's error on a unit mesh) changes the
/// answer: its ray grazes the base mesh's outline. On the limb and the grazing torus, in both
/// edge modes; a discard in `none` (or a wrong vertex layout or camera) would fail it.
#[test]
fn curved_none_covers_exactly_the_base_mesh() {
    let g = gpu();
    for name in ["sphere_limb", "torus_grazing"] {
        for edge in [EdgeMode::Repeat, EdgeMode::Clamp] {
            let ms = scene(name, edge);
            let prog = MeshProgram::new(&pipeline(Curved::None)).unwrap();
            let tex = mesh_textures(&g, &ms, &prog).unwrap();
            let probe = probe_mesh(&g, &prog, &ms, &tex, SIZE).unwrap();
            let (mut checked, mut covered) = (0u32, 0u32);
            for (r, hit) in ms.rays(SIZE, SIZE).iter().zip(&probe.hits) {
                let (o, d) = (DVec3::from(r.origin.map(f64::from)), DVec3::from(r.dir.map(f64::from)));
                let (wide, narrow) = (meets_base(&ms.mesh, o, d, 1e-4), meets_base(&ms.mesh, o, d, -1e-4));
                if wide != narrow {
                    continue;
                }
                checked += 1;
                covered += wide as u32;
                assert_eq!(hit[3] > 0.5, wide, "{name} {edge:?}: pixel ({}, {})", r.x, r.y);
            }
            // Both kinds of pixel are there: the frame holds the outline.
            assert!(checked > SIZE * SIZE * 9 / 10 && covered > 100 && checked - covered > 100, "{name}");
        }
    }
}

/// The picture and the measurement share the trace and the discards: the pixels the
/// measurement covers are exactly those the picture draws (not the clear colour), in each
/// mode.
#[test]
fn the_picture_draws_exactly_the_pixels_the_measurement_covers() {
    let g = gpu();
    let ms = scene("sphere_limb", EdgeMode::Repeat);
    let clear = {
        let c = relief_runtime::gpu::CLEAR;
        // Linear → sRGB bytes, as the target encodes the clear colour.
        let enc = |x: f64| {
            let s = if x <= 0.0031308 { 12.92 * x } else { 1.055 * x.powf(1.0 / 2.4) - 0.055 };
            (s * 255.0).round() as u8
        };
        [enc(c.r), enc(c.g), enc(c.b)]
    };
    for mode in [Curved::None, Curved::Quadric, Curved::Prism] {
        let prog = MeshProgram::new(&pipeline(mode)).unwrap();
        let tex = mesh_textures(&g, &ms, &prog).unwrap();
        let probe = probe_mesh(&g, &prog, &ms, &tex, SIZE).unwrap();
        let frame = render_mesh(&g, &prog, &ms, &tex, SIZE).unwrap();
        let mut differ = 0;
        for (i, h) in probe.hits.iter().enumerate() {
            let px = &frame.rgba[i * 4..i * 4 + 3];
            let drawn = px.iter().zip(clear).any(|(&a, b)| a.abs_diff(b) > 1);
            // A drawn pixel can be as dark as the clear colour only in a full shadow: none here
            // (no shadow stage, ambient 0.25 of a grey albedo).
            differ += (drawn != (h[3] > 0.5)) as usize;
        }
        assert_eq!(differ, 0, "{mode}");
        // The depth buffer holds the hit's depth where covered, the clear value elsewhere.
        for (h, d) in probe.hits.iter().zip(&probe.depth) {
            assert_eq!(h[3] > 0.5, *d < 1.0, "{mode}");
        }
    }
}

/// `quadric` and `prism` exist to draw the displaced surface's silhouette instead of the base
/// mesh's: on the limb and the grazing torus, in both edge modes, each draws fewer pixels
/// where the exact reference sees no relief than `none` (which draws the whole base mesh), and
/// `prism` has fewer pixels whose coverage disagrees with the reference than `none`. Not
/// asserted because it is false: `quadric`'s total coverage error is above `none`'s on the
/// limb with clamp edges (its search stops at the floor plane, so it loses hits on the deep
/// clamped border below that plane; docs/notes/meshes.md). The goals (prism ≤ 0.5 %,
/// quadric ≤ 2 %) are measured in that note, not asserted here.
#[test]
fn quadric_and_prism_silhouettes_are_closer_to_the_reference_than_the_base_mesh() {
    let g = gpu();
    for name in ["sphere_limb", "torus_grazing"] {
        for edge in [EdgeMode::Repeat, EdgeMode::Clamp] {
            let ms = scene(name, edge);
            let reference = ms.reference_hits(SIZE, SIZE).unwrap();
            let figures: Vec<_> = [Curved::None, Curved::Quadric, Curved::Prism]
                .map(|mode| {
                    let prog = MeshProgram::new(&pipeline(mode)).unwrap();
                    let tex = mesh_textures(&g, &ms, &prog).unwrap();
                    score(&probe_mesh(&g, &prog, &ms, &tex, SIZE).unwrap(), &reference, &ms)
                })
                .into();
            let none = &figures[0];
            assert!(
                none.extra > 0 && none.missing == 0,
                "{name} {edge:?}: none covers the base mesh, outside S: {none:?}"
            );
            for (mode, f) in ["quadric", "prism"].iter().zip(&figures[1..]) {
                assert!(f.extra < none.extra, "{name} {edge:?} {mode}: {f:?} vs none {none:?}");
            }
            let prism = &figures[2];
            assert!(prism.coverage_error < none.coverage_error, "{name} {edge:?} prism: {prism:?} vs none {none:?}");
        }
    }
}

/// The flat tile's paths refuse a mesh pipeline in one line, naming the mode; the mesh
/// program refuses a flat one.
#[test]
fn flat_paths_refuse_mesh_pipelines_and_the_reverse() {
    let e = relief_runtime::Program::new(&pipeline(Curved::Prism)).err().unwrap().to_string();
    assert!(e.contains("curved=prism") && !e.contains('\n'), "{e}");
    let e = MeshProgram::new(&BASE.parse().unwrap()).err().unwrap().to_string();
    assert!(e.contains("curved=") && !e.contains('\n'), "{e}");
}

// ---------------------------------------------------------------------------------------------
// An independent first hit along one ray: a dense march against the solid under S
// ---------------------------------------------------------------------------------------------

/// The relief's solid over the mesh, written here apart from the reference (no patches, no
/// boxes around S, no BVH): a point X lies in triangle i's prism where
/// `X = Σ λⱼ (Pⱼ − d·Nⱼ)` with λ ≥ 0, Σλ = 1 and d ∈ [0, depth] (the layer at d is the flat
/// triangle of the extruded vertices, N interpolated and not renormalized as S defines it),
/// and it is *under* S where its layer height `k = 1 − d/depth` is at most h at its uv.
struct Solid<'a> {
    mesh: &'a Mesh,
    map: &'a relief_runtime::HeightMap,
    edge: EdgeMode,
    depth: f64,
    /// Each triangle's prism box: the six extruded corners hold it (each point of the prism
    /// is a convex combination of them).
    boxes: Vec<(DVec3, DVec3)>,
}

/// Where a point lies in one prism: its layer height k, h at its uv, and how near a side wall.
#[derive(Clone, Copy, Debug)]
struct Place {
    k: f64,
    h: f64,
    /// The smallest barycentric coordinate: near 0 on the prism's side wall.
    edge: f64,
}

impl<'a> Solid<'a> {
    fn new(ms: &'a MeshScene) -> Solid<'a> {
        let mesh = &ms.mesh;
        let depth = ms.scene.depth_scale as f64;
        let boxes = mesh
            .triangles
            .iter()
            .map(|t| {
                let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
                for &i in t {
                    let (p, n) = (mesh.positions[i as usize].as_dvec3(), mesh.normals[i as usize].as_dvec3());
                    for q in [p, p - depth * n] {
                        (lo, hi) = (lo.min(q), hi.max(q));
                    }
                }
                (lo - 1e-9, hi + 1e-9)
            })
            .collect();
        Solid { mesh, map: &ms.scene.height, edge: ms.scene.edge, depth, boxes }
    }

    /// The triangles whose prism box the ray `o + t·d` meets, with the t interval inside it.
    fn candidates(&self, o: DVec3, d: DVec3) -> Vec<(usize, f64, f64)> {
        let mut out = Vec::new();
        for (i, (lo, hi)) in self.boxes.iter().enumerate() {
            let (mut a, mut b) = (0.0f64, f64::INFINITY);
            for k in 0..3 {
                let (t0, t1) = ((lo[k] - o[k]) / d[k], (hi[k] - o[k]) / d[k]);
                a = a.max(t0.min(t1));
                b = b.min(t0.max(t1));
            }
            if a <= b {
                out.push((i, a, b));
            }
        }
        out
    }

    /// The places of `x` in triangle `tri`'s prism (the roots d in [0, depth] of the cubic
    /// `(X − P₀ + d·N₀) · ((E₁ − d·F₁) × (E₂ − d·F₂)) = 0`, found by sign changes on a fine
    /// sampling and bisection, then λ by Cramer's rule in that layer).
    fn places(&self, x: DVec3, tri: usize) -> Vec<Place> {
        let t = self.mesh.triangles[tri].map(|i| i as usize);
        let p = t.map(|i| self.mesh.positions[i].as_dvec3());
        let n = t.map(|i| self.mesh.normals[i].as_dvec3());
        let uv = t.map(|i| self.mesh.uvs[i].as_dvec2());
        let layer = |d: f64| {
            let (a, b) = (p[1] - d * n[1] - (p[0] - d * n[0]), p[2] - d * n[2] - (p[0] - d * n[0]));
            (x - (p[0] - d * n[0]), a, b)
        };
        let f = |d: f64| {
            let (r, a, b) = layer(d);
            r.dot(a.cross(b))
        };
        let steps = 64;
        let mut out = Vec::new();
        let mut prev = (0.0, f(0.0));
        for s in 1..=steps {
            let d1 = self.depth * s as f64 / steps as f64;
            let f1 = f(d1);
            let (d0, f0) = prev;
            prev = (d1, f1);
            if f0 == 0.0 || f0.signum() != f1.signum() {
                let (mut lo, mut hi, mut flo) = (d0, d1, f0);
                if f0 != 0.0 {
                    for _ in 0..80 {
                        let mid = 0.5 * (lo + hi);
                        let fm = f(mid);
                        if fm.signum() == flo.signum() {
                            (lo, flo) = (mid, fm);
                        } else {
                            hi = mid;
                        }
                    }
                }
                let d = 0.5 * (lo + hi);
                let (r, a, b) = layer(d);
                let c = a.cross(b);
                let l1 = r.cross(b).dot(c) / c.length_squared();
                let l2 = a.cross(r).dot(c) / c.length_squared();
                let tol = 1e-9;
                if l1 >= -tol && l2 >= -tol && l1 + l2 <= 1.0 + tol {
                    let q = uv[0] * (1.0 - l1 - l2) + uv[1] * l1 + uv[2] * l2;
                    let h = self.map.bilinear(q.x, q.y, self.edge);
                    out.push(Place { k: 1.0 - d / self.depth, h, edge: l1.min(l2).min(1.0 - l1 - l2) });
                }
            }
        }
        out
    }

    /// Whether `x` lies under S in one of `cands`' prisms (those whose t interval holds `t`).
    fn under(&self, x: DVec3, t: f64, cands: &[(usize, f64, f64)]) -> Option<Place> {
        cands.iter().filter(|c| c.1 <= t && t <= c.2).flat_map(|c| self.places(x, c.0)).find(|pl| pl.k <= pl.h)
    }

    /// The first t in `[t0, t1]` at which the ray is under S, marching with step `step` and
    /// bisecting the first step that enters the solid to 1e-12: a crossing of the solid
    /// shorter than `step` can be stepped over (the caller compares with a finer march).
    fn first_under(&self, o: DVec3, d: DVec3, t0: f64, t1: f64, step: f64) -> Option<(f64, Place)> {
        let cands = self.candidates(o, d);
        let lo_t = cands.iter().map(|c| c.1).fold(f64::INFINITY, f64::min).max(t0);
        let mut prev = lo_t;
        let mut t = lo_t;
        while t <= t1 {
            if let Some(pl) = self.under(o + d * t, t, &cands) {
                let (mut a, mut b, mut best) = (prev, t, pl);
                while b - a > 1e-12 {
                    let m = 0.5 * (a + b);
                    match self.under(o + d * m, m, &cands) {
                        Some(p) => (b, best) = (m, p),
                        None => a = m,
                    }
                }
                return Some((b, best));
            }
            prev = t;
            t += step;
        }
        None
    }
}

/// The figures' largest t errors (issue 38): on the grazing torus and the sphere at 30°, 96²,
/// the three pixels of each mode with the largest |t_gpu − t_ref| and the one whose GPU hit
/// comes earliest before the reference's. On each, the dense march along the pixel's ray
/// ([`Solid`], written apart from the reference) must find the reference's first hit: t within
/// 1e-6 + ε/cos (the reference's leaf tolerance ε = 1e-6·(radius + depth), the march bisected to
/// 1e-12; cos, the incidence on S, taken ≥ 1e-3: a goal, not derived), both with a step of depth/200 from the start and with depth/4000
/// near the two hits, so that a thin crossing the coarse march steps over is caught by the
/// fine one. The one exception allowed is a ray that enters the solid through a prism's side
/// wall (its first point has a barycentric coordinate below 1e-6) at a uv seam, where S,
/// defined per triangle, is open: the sphere's poles, where each segment's pole vertex has
/// its own u, so the heights on the two sides of a pole edge differ and the reference's ray
/// passes through the crack (docs/meshes.md). And where the GPU's hit comes more than one depth
/// before the reference's, its point must lie outside the solid: the mode stopped the ray
/// where S is not (the ray passes above S there), not a hit the reference missed.
#[test]
fn the_worst_t_errors_are_hits_off_s_and_the_reference_is_the_first_hit() {
    let g = gpu();
    let size = 96;
    let mut sphere30 = {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/meshes/sphere_rocks.toml");
        relief_runtime::load_scene_file(&path).unwrap()
    };
    sphere30.camera.angle_deg = 30.0;
    sphere30.depth_scale = 0.08;
    let scenes = [
        ("torus_grazing", scene("torus_grazing", EdgeMode::Repeat)),
        ("sphere30", MeshScene::from_scene(sphere30).unwrap()),
    ];
    let mut cracks = 0;
    for (name, ms) in &scenes {
        let solid = Solid::new(ms);
        let depth = ms.scene.depth_scale as f64;
        let refr = ms.reference().unwrap();
        let eps = refr.tolerance();
        let reference = refr.trace_all(&ms.rays(size, size));
        let rays = ms.rays(size, size);
        for mode in [Curved::None, Curved::Quadric, Curved::Prism] {
            let prog = MeshProgram::new(&pipeline(mode)).unwrap();
            let tex = mesh_textures(&g, ms, &prog).unwrap();
            let probe = probe_mesh(&g, &prog, ms, &tex, size).unwrap();
            let mut both: Vec<(usize, f64)> = probe
                .hits
                .iter()
                .zip(&reference)
                .enumerate()
                .filter_map(|(i, (gh, r))| r.filter(|_| gh[3] > 0.5).map(|r| (i, (gh[2] as f64 - r.t) / depth)))
                .collect();
            both.sort_by(|a, b| b.1.abs().total_cmp(&a.1.abs()));
            let earliest = both.iter().copied().min_by(|a, b| a.1.total_cmp(&b.1)).unwrap();
            let mut picks: Vec<(usize, f64)> = both[..3].to_vec();
            picks.push(earliest);
            for (i, dt) in picks {
                let r = rays[i];
                let (o, d) = (DVec3::from(r.origin.map(f64::from)), DVec3::from(r.dir.map(f64::from)));
                let rf = reference[i].unwrap();
                let tg = probe.hits[i][2] as f64;
                let end = rf.t.max(tg) + 2.0 * depth;
                let at = |t: f64| {
                    format!("{name} {mode} pixel ({}, {}): dt {dt:.3}, reference t {}, march {t}", r.x, r.y, rf.t)
                };
                for (from, step) in [(0.0, depth / 200.0), (tg.min(rf.t) - 3.0 * depth, depth / 4000.0)] {
                    let (t, place) = solid.first_under(o, d, from, end, step).expect("the march meets the solid");
                    let tol = 1e-6 + eps / 1e-3;
                    if (t - rf.t).abs() > tol {
                        // Only through a crack of S at a uv seam, before the reference's hit.
                        assert!(t < rf.t && place.edge < 1e-6, "{}", at(t));
                        cracks += 1;
                    }
                }
                if dt < -1.0 {
                    let x = o + d * tg;
                    assert!(
                        solid.under(x, tg, &solid.candidates(o, d)).is_none(),
                        "{}: the GPU's point lies in the solid",
                        at(f64::NAN)
                    );
                }
            }
        }
    }
    // The sphere's pole crack is among the sphere's worst pixels (one pixel, both marches, in
    // each mode whose worst pixels hold it); the test would pass vacuously without it.
    assert!(cracks > 0);
}

/// S descends `depth·(1 − h)·N` with N interpolated and *not* renormalized, so where the
/// vertex normals differ the relief is shallower than `depth` along the unit normal (by |N|).
/// One flat equilateral triangle in z = 0 around the origin, its vertex normals tilted 40°
/// outwards (radially): N_z = cos 40° everywhere, so with a constant height h = ½ S is the
/// plane z = −½·depth·cos 40° (exactly: the layer's lateral shift keeps z), and a pixel's t
/// follows from its ray alone. Looking straight down through a 2° frame at the centroid, `none`
/// and `prism` must find it within 0.005 of the depth along the ray: the search's last bracket
/// is 1/1024 of the depth (`linear(32)+binary(5)`), the fragment normal's tilt at the frame's
/// edge (ρ/r ≤ 0.05, ≤ 0.03 rad) moves the descent by ≤ 1e-3 of it. A shader that descends
/// the full depth along the renormalized normal is ½·(1 − cos 40°) ≈ 0.12 depths late.
#[test]
fn the_trace_descends_the_interpolated_normals_length_as_s_does() {
    let g = gpu();
    let alpha = 40f32.to_radians();
    let ms = splayed_triangle(alpha, 0.0, -90.0, 2.0, 2.0);
    let depth = ms.scene.depth_scale as f64;
    let plane = -0.5 * depth * (alpha as f64).cos();
    let size = 16;
    for mode in [Curved::None, Curved::Prism] {
        let prog = MeshProgram::new(&pipeline(mode)).unwrap();
        let tex = mesh_textures(&g, &ms, &prog).unwrap();
        let probe = probe_mesh(&g, &prog, &ms, &tex, size).unwrap();
        let mut worst = 0f64;
        for (r, hit) in ms.rays(size, size).iter().zip(&probe.hits) {
            let (o, d) = (DVec3::from(r.origin.map(f64::from)), DVec3::from(r.dir.map(f64::from)));
            let t = (plane - o.z) / d.z;
            assert!(hit[3] > 0.5, "{mode}: pixel ({}, {}) not drawn", r.x, r.y);
            worst = worst.max(((hit[2] as f64 - t) / depth).abs());
        }
        assert!(worst <= 0.005, "{mode}: t off by {worst} depths");
    }
}

/// The prism traced along the true ray (issue 38): the exact entry and exit, the chord between
/// them, and the polish of the hit onto S. The flat triangle of the test above (normals
/// splayed 40° outward, constant h = ½, S the plane z = −½·depth·cos 40°), seen at 80° from
/// its normal: every pixel whose ray meets that plane inside the triangle's layer-½ triangle
/// (by a margin of 0.01 in barycentrics, away from the walls, whose crossings the rasterized
/// faces approximate) must be drawn, its t within 1e-3 depths of the plane's (issue 38's RMS
/// goal, here asserted on every pixel: Newton stops within 1e-4 depths of S). Among those
/// pixels are rays the fragment's own frame could not trace: at the hit, the interpolated
/// normal faces away from the eye (`v·N ≥ 0`), which the shader before the exact entry
/// discarded as "entered from below"; at least 20 such pixels are asserted drawn.
#[test]
fn the_prism_is_traced_along_the_true_ray_at_a_grazing_view() {
    let g = gpu();
    let alpha = 40f32.to_radians();
    let ms = splayed_triangle(alpha, 80.0, -90.0, 50.0, 2.5);
    let corners = ms.mesh.positions.clone();
    let normals = ms.mesh.normals.clone();
    let depth = ms.scene.depth_scale as f64;
    let plane = -0.5 * depth * (alpha as f64).cos();
    // The layer-½ triangle: the corners moved ½·depth along their normals.
    let layer: Vec<DVec3> =
        corners.iter().zip(&normals).map(|(p, n)| p.as_dvec3() - n.as_dvec3() * (0.5 * depth)).collect();
    let size = 64;
    let prog = MeshProgram::new(&pipeline(Curved::Prism)).unwrap();
    let tex = mesh_textures(&g, &ms, &prog).unwrap();
    let probe = probe_mesh(&g, &prog, &ms, &tex, size).unwrap();
    let (mut checked, mut away, mut worst) = (0, 0, 0f64);
    for (r, hit) in ms.rays(size, size).iter().zip(&probe.hits) {
        let (o, d) = (DVec3::from(r.origin.map(f64::from)), DVec3::from(r.dir.map(f64::from)));
        let t = (plane - o.z) / d.z;
        let x = o + d * t;
        // Barycentrics of x in the layer triangle (x lies in its plane, z = plane).
        let (e1, e2, q) = (layer[1] - layer[0], layer[2] - layer[0], x - layer[0]);
        let det = e1.x * e2.y - e1.y * e2.x;
        let (b1, b2) = ((q.x * e2.y - q.y * e2.x) / det, (e1.x * q.y - e1.y * q.x) / det);
        let b = [1.0 - b1 - b2, b1, b2];
        if b.iter().any(|&c| c < 0.01) {
            continue;
        }
        checked += 1;
        assert!(hit[3] > 0.5, "pixel ({}, {}) not drawn", r.x, r.y);
        worst = worst.max(((hit[2] as f64 - t) / depth).abs());
        let n: DVec3 = (0..3).map(|k| normals[k].as_dvec3() * b[k]).sum();
        away += (d.dot(n) >= 0.0) as usize;
    }
    println!("{checked} pixels see the triangle, {away} of them face away; t off by at most {worst:.2e} depths");
    assert!(checked >= 100, "only {checked} pixels see the triangle ({away} face away, t off by {worst})");
    assert!(away >= 20, "only {away} rays face away from the interpolated normal (of {checked})");
    assert!(worst <= 1e-3, "t off by {worst} depths");
}

/// One flat equilateral triangle in z = 0 around the origin (corners at unit distance, uv =
/// xy + ½), its vertex normals splayed `alpha` outwards (radially), under a constant height ½
/// (8² map, depth 0.1, no albedo or normal map), seen from `distance` at `angle` degrees from
/// +z and `azimuth`, with the vertical field of view `fov` (degrees), looking at the origin.
fn splayed_triangle(alpha: f32, angle: f32, azimuth: f32, fov: f32, distance: f32) -> MeshScene {
    use glam::{Vec2, Vec3, Vec4};
    let mut sc = {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/meshes/sphere_rocks.toml");
        relief_runtime::load_scene_file(&path).unwrap()
    };
    sc.height = relief_runtime::HeightMap::new(8, 8, vec![0.5; 64]);
    sc.albedo = None;
    sc.normal = None;
    sc.depth_scale = 0.1;
    sc.camera.angle_deg = angle;
    sc.camera.azimuth_deg = azimuth;
    sc.camera.fov_deg = fov;
    sc.camera.distance = distance;
    sc.camera.target = Vec3::ZERO;
    let corners: Vec<Vec3> =
        (0..3).map(|k| std::f32::consts::TAU * k as f32 / 3.0).map(|a| Vec3::new(a.cos(), a.sin(), 0.0)).collect();
    let mesh = Mesh {
        name: "splayed".into(),
        positions: corners.clone(),
        normals: corners.iter().map(|c| Vec3::new(c.x * alpha.sin(), c.y * alpha.sin(), alpha.cos())).collect(),
        tangents: vec![Vec4::new(1.0, 0.0, 0.0, 1.0); 3],
        uvs: corners.iter().map(|c| Vec2::new(c.x, c.y) + 0.5).collect(),
        triangles: vec![[0, 1, 2]],
    };
    MeshScene { scene: sc, mesh, notes: Default::default() }
}

/// `curved=prism`'s measurement of `ms` at `size²` with the stages `stages`, drawn as the
/// runtime draws it (the walk, each chord searched with its share of the layers).
fn prism_probe(g: &Gpu, ms: &MeshScene, stages: &str, size: u32) -> relief_runtime::gpu::mesh::MeshProbe {
    prism_probe_of(g, ms, stages, size, MeshProgram::new)
}

/// [`prism_probe`] with the program `make` compiles.
fn prism_probe_of(
    g: &Gpu,
    ms: &MeshScene,
    stages: &str,
    size: u32,
    make: fn(&Pipeline) -> Result<MeshProgram, relief_dsl::CompileError>,
) -> relief_runtime::gpu::mesh::MeshProbe {
    let p = stages.parse::<Pipeline>().unwrap().with_curved(Some(Curved::Prism));
    let prog = make(&p).unwrap();
    let tex = mesh_textures(g, ms, &prog).unwrap();
    probe_mesh(g, &prog, ms, &tex, size).unwrap()
}

/// What the prism's t error check asserts on one frame (issue 38's "coverage and t error
/// asserted against the reference"): on every pixel both hit, `|t_gpu − t_ref|` is within
/// `T_BOUND` (1e-3 depths, the RMS goal taken per pixel) or the pixel has a named
/// cause (`mesh_measure::prism_t_causes`: a seam of S, the polish not kept, the search
/// stepping over a crossing that `linear(256)+binary(8)` finds, the chord missing the
/// crossing the view ray makes), never "other"; and the CPU's emulation of the prisms'
/// fragments gives the GPU's t on each such pixel (within `mesh_measure::emulation_bound`:
/// 1e-3 depths, and two of the search's last brackets where the polish was not kept). The
/// emulation searches every chord with all of its layers, as the full draw does, so these
/// causes are decided on the walk with all its layers (`MeshProgram::walked_with_all_layers`,
/// `BASE`'s stages); `probe`, the runtime's walk (each chord with its share of the layers),
/// may in addition step over a crossing those layers catch: each of its pixels over the bound
/// is over it in the walk with all layers too, or the dense probe meets the reference there
/// (the shared layers stepped over a crossing). Returns (pixels both hit, pixels over the
/// bound) of `probe`.
fn prism_t_is_within_the_bound_or_explained(
    g: &Gpu,
    ms: &MeshScene,
    reference: &[Option<relief_runtime::mesh::MeshHit>],
    probe: &relief_runtime::gpu::mesh::MeshProbe,
    size: u32,
    what: &str,
) -> (usize, usize) {
    use relief_runtime::mesh_measure::{prism_t_causes, PrismTCause, T_BOUND};
    let depth = ms.scene.depth_scale as f64;
    let dense = prism_probe(g, ms, "linear(256)+binary(8)", size);
    let whole = prism_probe_of(g, ms, BASE, size, MeshProgram::walked_with_all_layers);
    let causes = prism_t_causes(ms, reference, &whole, &dense, size, 32, 5);
    let (mut both, mut over) = (0, Vec::new());
    for (i, (h, r)) in whole.hits.iter().zip(reference).enumerate() {
        if let (true, Some(r)) = (h[3] > 0.5, r) {
            both += 1;
            if ((h[2] as f64 - r.t) / depth).abs() > T_BOUND {
                over.push(i);
            }
        }
    }
    let named: Vec<usize> = causes.iter().map(|c| c.index).collect();
    assert_eq!(named, over, "{what}: the pixels over the bound are those the causes list");
    for c in &causes {
        assert_ne!(c.cause, PrismTCause::Other, "{what}: pixel {} unexplained: {c:?}", c.index);
        let (e, f) = c
            .emulated_dt
            .zip(c.fragment)
            .unwrap_or_else(|| panic!("{what}: the emulation draws nothing at pixel {}", c.index));
        let bound = relief_runtime::mesh_measure::emulation_bound(&f);
        assert!((e - c.dt).abs() <= bound, "{what}: pixel {}: emulated {e}, GPU {} (bound {bound})", c.index, c.dt);
    }
    println!(
        "{what}: with all layers, {both} pixels both hit, {} over {T_BOUND} depths: {:?}",
        over.len(),
        causes.iter().map(|c| c.cause.name()).collect::<Vec<_>>()
    );
    the_emulation_draws_what_the_walk_with_all_layers_draws(ms, reference, &whole, size, what);
    let depth = ms.scene.depth_scale as f64;
    let (mut both, mut shared_over, mut searched) = (0, 0, 0);
    for (i, (h, r)) in probe.hits.iter().zip(reference).enumerate() {
        let (true, Some(r)) = (h[3] > 0.5, r) else { continue };
        both += 1;
        if ((h[2] as f64 - r.t) / depth).abs() <= T_BOUND {
            continue;
        }
        shared_over += 1;
        if over.contains(&i) {
            continue;
        }
        let dense_dt = dense.hits[i].map(f64::from);
        let met = dense_dt[3] > 0.5 && ((dense_dt[2] - r.t) / depth).abs() <= T_BOUND;
        assert!(
            met,
            "{what}: pixel {i} of the walk over the bound, unexplained (dense {dense_dt:?}, reference {})",
            r.t
        );
        searched += 1;
    }
    println!(
        "{what}: the walk, {both} pixels both hit, {shared_over} over the bound, {searched} of them its shared layers'"
    );
    (both, shared_over)
}

/// The shipped prism trace against its CPU emulation on every pixel (not only those over the
/// t bound): `whole` (the walk with all its layers, `BASE`'s stages) and
/// `mesh_measure::emulate_prism_pixel` (f64, every prism's exact entry and exit, the chord bent
/// through the view ray's exact middle, the search, the polish and its discard) draw the same
/// pixels and the same t, within `mesh_measure::emulation_bound` (1e-3 depths, the issue's
/// per-pixel bound, and two of the search's last brackets where the polish was not kept).
/// Where they differ in coverage, the ray
/// crosses a uv seam's wall before the pixel's hit (the emulation's or the reference's): S is
/// open there, and the walk cannot follow the ray through the crack as the emulation of the
/// full draw does (at the sphere's pole, one pixel of the 96² view at 30°).
/// With the shader's bend left out (`PRISM_BEND_STEPS` 0: the straight chord) the limb's and
/// the torus's views still pass (there the straight chord's search, once polished, lands
/// within 10⁻³ depths of the bent one's on every pixel); the sphere's at 30° fails first on
/// its RMS goal (`prism_meets_the_t_goal_on_the_sphere_where_the_straight_chord_missed_it`).
fn the_emulation_draws_what_the_walk_with_all_layers_draws(
    ms: &MeshScene,
    reference: &[Option<relief_runtime::mesh::MeshHit>],
    whole: &relief_runtime::gpu::mesh::MeshProbe,
    size: u32,
    what: &str,
) {
    use relief_runtime::mesh_measure::{
        crosses_a_seam_before, emulate_prism_pixel, emulation_bound, seam_walls, PolishRule,
    };
    let depth = ms.scene.depth_scale as f64;
    let (vertices, indices) = relief_runtime::mesh::vertices::mesh_vertices(&ms.mesh, Curved::Prism);
    let walls = seam_walls(ms);
    let (mut compared, mut seams) = (0, 0);
    for (i, ray) in ms.rays(size, size).iter().enumerate() {
        let (o, d) = (DVec3::from(ray.origin.map(|c| c as f64)), DVec3::from(ray.dir.map(|c| c as f64)));
        let e = emulate_prism_pixel(ms, &vertices, &indices, o, d, (32, 5), PolishRule::SHADER);
        let g = whole.hits[i];
        match (e, g[3] > 0.5) {
            (Some(e), true) => {
                let bound = emulation_bound(&e);
                let dt = (g[2] as f64 - e.t) / depth;
                assert!(
                    dt.abs() <= bound,
                    "{what}: pixel {i}: GPU t off the emulation's by {dt} depths (bound {bound})"
                );
                compared += 1;
            }
            (None, false) => {}
            (e, _) => {
                let at = e.map(|e| e.t).into_iter().chain(reference[i].as_ref().map(|r| r.t));
                let seam = at.into_iter().any(|t| crosses_a_seam_before(&walls, o, d, t, depth));
                assert!(
                    seam,
                    "{what}: pixel {i}: the emulation draws {e:?}, the GPU {g:?}, and the ray crosses no seam"
                );
                seams += 1;
            }
        }
    }
    println!("{what}: the emulation gives the GPU's t on {compared} pixels; {seams} differ in coverage at seams");
}

/// Issue 38's "Done means" on a real map at grazing views, in both edge modes: `curved=prism`
/// on the sphere's limb and the grazing torus (`rocks`, 48²) against the exact reference.
/// Coverage: within the goal, 0.5 % of the pixels (met; docs/notes/meshes.md). t: every pixel
/// both hit within 1e-3 depths of the reference or explained by a named cause
/// ([`prism_t_is_within_the_bound_or_explained`]); the RMS goal itself is missed where such
/// pixels exist and is not asserted. Seen to fail: with the polish's result ignored (the
/// search's hit drawn; `polish_on_s` returning `hit`), the pixels over the bound are
/// hundreds and "other" (the emulation, which polishes, disagrees with the GPU).
#[test]
fn prism_coverage_and_t_against_the_reference_at_grazing_views_in_both_edge_modes() {
    let g = gpu();
    let size = 48;
    for name in ["sphere_limb", "torus_grazing"] {
        for edge in [EdgeMode::Repeat, EdgeMode::Clamp] {
            let what = format!("{name} {edge:?}");
            let ms = scene(name, edge);
            let reference = ms.reference_hits(size, size).unwrap();
            let probe = prism_probe(&g, &ms, BASE, size);
            let s = score(&probe, &reference, &ms);
            assert!(
                s.both > (size * size / 5) as usize && s.both + s.missing < (size * size) as usize,
                "{what}: {s:?}"
            );
            assert!(s.coverage_error <= 0.005, "{what}: coverage error {} above the goal 0.5 %", s.coverage_error);
            prism_t_is_within_the_bound_or_explained(&g, &ms, &reference, &probe, size, &what);
        }
    }
}

/// Issue 38's RMS t goal where the straight chord missed it: the sphere with `rocks` at 30°
/// and 60° from its pole axis (two of the goals table's cells, docs/notes/meshes.md; 96²,
/// repeat), where the chord, straight in texture space, passed crossings the view ray's curve
/// makes (2 and 3 pixels over 1e-3 depths, cause "chord", before the bend). With the chord bent
/// through the curve's exact middle, and a hit the polish does not keep discarded (the pole's
/// uv-seam crack), the walk with all its layers has
/// every pixel both hit within 1e-3 depths of the reference (so the RMS goal, 1e-3 depths, is
/// met, asserted), the emulation giving its t on every pixel
/// ([`prism_t_is_within_the_bound_or_explained`]). Seen to fail with the bend left out
/// (`PRISM_BEND_STEPS` 0).
#[test]
fn prism_meets_the_t_goal_on_the_sphere_where_the_straight_chord_missed_it() {
    let g = gpu();
    let size = 96;
    for angle in [30.0, 60.0] {
        let what = format!("sphere_rocks at {angle}°");
        let mut ms = scene("sphere_rocks", EdgeMode::Repeat);
        ms.scene.camera.angle_deg = angle;
        let reference = ms.reference_hits(size, size).unwrap();
        let whole = prism_probe_of(&g, &ms, BASE, size, MeshProgram::walked_with_all_layers);
        let s = score(&whole, &reference, &ms);
        assert!(s.both > (size * size / 5) as usize, "{what}: {s:?}");
        assert!(s.rms_t <= 1e-3, "{what}: RMS t {} depths above the goal 1e-3", s.rms_t);
        let probe = prism_probe(&g, &ms, BASE, size);
        let (_, over) = prism_t_is_within_the_bound_or_explained(&g, &ms, &reference, &probe, size, &what);
        println!(
            "{what}: all layers RMS t {:.2e} depths, coverage error {:.4}; the walk {over} pixels over",
            s.rms_t, s.coverage_error
        );
    }
}

/// Issue 38's RMS t goal on `lion` (the procedural stand-in: crossings narrower than any
/// linear search's step, docs/notes/meshes.md), met with an exact coarse stage: the sphere at
/// 30° and 60° from its pole axis and the torus at 30° (three of the goals table's cells; 96²,
/// repeat; the sphere at 60° under clamp too), `qcsm(64)` under `curved=prism`, drawn as the runtime draws it (the walk). The safe march finds the
/// first crossing of a straight ray exactly, and follows the view ray's curve through each
/// prism as up to four straight pieces of the bent chord (`compose::mesh`'s piece search):
/// RMS t ≤ 1e-3 depths and coverage error ≤ 0.5 % against the reference, asserted. Seen to
/// fail before the pieces (the chord searched straight: the sphere 2.7e-2 at 30°, 1.3e-2 at
/// 60°, the torus 2.2e-2).
#[test]
fn prism_with_a_safe_march_meets_the_t_goal_on_lion() {
    let g = gpu();
    let size = 96;
    let lion = relief_runtime::scene_from_arg("scene:lion").unwrap().height;
    // The goals table's scenes: the sphere 3 units away with depth 0.08, the torus 3.5 with 0.05.
    for (mesh, angle, distance, depth, edge) in [
        ("sphere", 30.0, 3.0, 0.08, EdgeMode::Repeat),
        ("sphere", 60.0, 3.0, 0.08, EdgeMode::Repeat),
        ("sphere", 60.0, 3.0, 0.08, EdgeMode::Clamp),
        ("torus", 30.0, 3.5, 0.05, EdgeMode::Repeat),
    ] {
        let what = format!("{mesh} with lion at {angle}° ({edge:?})");
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/meshes/sphere_rocks.toml");
        let mut sc = relief_runtime::load_scene_file(&path).unwrap();
        sc.mesh = Some(relief_runtime::MeshSource::Builtin(mesh.to_string()));
        sc.camera.distance = distance;
        sc.depth_scale = depth;
        sc.height = lion.clone();
        sc.albedo = None;
        sc.normal = None;
        sc.edge = edge;
        sc.camera.angle_deg = angle;
        let ms = MeshScene::from_scene(sc).unwrap();
        let reference = ms.reference_hits(size, size).unwrap();
        let probe = prism_probe(&g, &ms, "qcsm(64)", size);
        let s = score(&probe, &reference, &ms);
        println!("{what}: RMS t {:.2e} depths, coverage error {:.4}", s.rms_t, s.coverage_error);
        assert!(s.both > (size * size / 5) as usize, "{what}: {s:?}");
        assert!(s.coverage_error <= 0.005, "{what}: coverage error {} above the goal 0.5 %", s.coverage_error);
        assert!(s.rms_t <= 1e-3, "{what}: RMS t {} depths above the goal 1e-3", s.rms_t);
    }
}

/// The sphere (12 × 6 segments) under an 8² map whose texel column 7 is a wall of height 1 on
/// a floor of 0 (u ≈ 0.94, 22.5° in front of the right limb seen from −y), depth 0.2: the
/// mirror image of the configuration
/// `meshes::the_reference_agrees_with_its_twin_on_a_one_texel_wall_at_the_silhouette_and_grazing_rays`
/// checks the reference on, its wall now beside the u seam, seen from (0.95, −3, 0) toward the
/// right limb, 20° field of view.
fn one_texel_wall(edge: EdgeMode) -> MeshScene {
    let mut sc = {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/meshes/sphere_rocks.toml");
        relief_runtime::load_scene_file(&path).unwrap()
    };
    sc.height = relief_runtime::HeightMap::from_fn(8, 8, |x, _| if x == 7 { 1.0 } else { 0.0 });
    sc.albedo = None;
    sc.normal = None;
    sc.depth_scale = 0.2;
    sc.edge = edge;
    sc.camera.angle_deg = 90.0;
    sc.camera.azimuth_deg = -90.0;
    sc.camera.fov_deg = 20.0;
    sc.camera.distance = 3.0;
    sc.camera.target = glam::Vec3::new(0.95, 0.0, 0.0);
    let mesh = relief_runtime::mesh::builtin::sphere(12, 6, [1.0, 1.0]);
    MeshScene { scene: sc, mesh, notes: Default::default() }
}

/// Issue 38's "a one-texel wall at the silhouette", both edge modes. The goal, "the wall's
/// pixels covered exactly as the reference covers them", is met with clamp edges and missed
/// by one pixel with repeat edges (its cause: the chord, `PrismMiss::AfterExit`), so what is
/// asserted is what holds: `curved=prism` covers the pixels the exact reference covers, one
/// by one, but for pixels whose reference answer changes when the ray is moved by 1e-4 of the
/// depth (grazing the relief's outline, where f32 may decide either way; at most 1 % of the
/// frame) and missing pixels whose cause is the chord or the search (`prism_miss_causes`);
/// coverage error within the goal 0.5 %; t as [`prism_t_is_within_the_bound_or_explained`].
/// The reference itself is checked against the brute-force twin (`meshes::twin`, its bound
/// e < 4e-3) on every other wall pixel's ray. Under repeat edges the wall's bilinear support
/// (texel 7's cells) runs across the u seam on the right limb; under clamp it is a plateau
/// to the seam. Seen to fail: see [`prism_coverage_and_t_against_the_reference_at_grazing_views_in_both_edge_modes`].
#[test]
fn prism_covers_a_one_texel_wall_at_the_silhouette_as_the_reference_does() {
    let g = gpu();
    let size = 64;
    for edge in [EdgeMode::Repeat, EdgeMode::Clamp] {
        let what = format!("wall {edge:?}");
        let ms = one_texel_wall(edge);
        let depth = ms.scene.depth_scale as f64;
        let r = ms.reference().unwrap();
        let reference = ms.reference_hits(size, size).unwrap();
        let probe = prism_probe(&g, &ms, BASE, size);
        let rays = ms.rays(size, size);
        let (mut ambiguous, mut wall, mut unlike) = (0, Vec::new(), Vec::<usize>::new());
        for (i, ray) in rays.iter().enumerate() {
            let (o, d) = (DVec3::from(ray.origin.map(f64::from)), DVec3::from(ray.dir.map(f64::from)));
            let hit = reference[i];
            // The wall's cells: u·8 − ½ within (3, 5) (texel 4's bilinear support), repeat.
            if let Some(h) = hit {
                if h.u * 8.0 - 0.5 > 6.0 {
                    wall.push(i);
                }
            }
            if (probe.hits[i][3] > 0.5) == hit.is_some() {
                continue;
            }
            let (a, b) = d.any_orthonormal_pair();
            let shift = 1e-4 * depth;
            let flips = (0..8).any(|k| {
                let phi = k as f64 * std::f64::consts::FRAC_PI_4;
                let oo = (o + (a * phi.cos() + b * phi.sin()) * shift).as_vec3();
                r.first_hit(oo.to_array(), d.as_vec3().to_array()).is_some() != hit.is_some()
            });
            if flips {
                ambiguous += 1;
            } else {
                unlike.push(i);
            }
        }
        // Pixels decided otherwise than the reference: missing ones, each with a named cause
        // of the chord or the search (`prism_miss_causes`), never extra, "no face" or "other".
        let causes = relief_runtime::mesh_measure::prism_miss_causes(&ms, &reference, &probe, size, 32, 5);
        let explained: Vec<usize> = causes
            .iter()
            .filter(|(_, c)| matches!(c, PrismMiss::AfterExit | PrismMiss::Search))
            .map(|(i, _)| *i)
            .collect();
        println!("{what}: unlike the reference {unlike:?}, causes of the missing pixels {causes:?}");
        assert!(unlike.iter().all(|i| explained.contains(i)), "{what}: {unlike:?} unexplained: {causes:?}");
        let s = score(&probe, &reference, &ms);
        println!("{what}: {s:?}; {} wall pixels, {ambiguous} ambiguous", wall.len());
        assert!(wall.len() >= 40 && s.both > 200 && s.pixels - s.both - s.extra - s.missing > 200, "{what}: {s:?}");
        assert!(ambiguous * 100 <= s.pixels, "{what}: {ambiguous} ambiguous pixels");
        assert!(s.coverage_error <= 0.005, "{what}: coverage error {} above the goal 0.5 %", s.coverage_error);
        prism_t_is_within_the_bound_or_explained(&g, &ms, &reference, &probe, size, &what);
        // The reference against its twin on every other wall pixel's ray.
        let tw = super::meshes::twin(&ms.mesh, &ms.scene.height, edge, depth, 40);
        assert!(tw.e < 4e-3, "the twin's bound {} is too loose", tw.e);
        let wall_rays: Vec<(DVec3, DVec3)> = wall
            .iter()
            .step_by(2)
            .map(|&i| (DVec3::from(rays[i].origin.map(f64::from)), DVec3::from(rays[i].dir.map(f64::from))))
            .collect();
        let (hits, _, amb) = super::meshes::compare(&r, &tw, &wall_rays);
        assert!(hits == wall_rays.len() && amb * 10 <= hits, "{what}: twin: {hits} hits, {amb} ambiguous");
    }
}

/// Issue 38's map-based coarse stages under `curved=prism`: the stages that read a precomputed
/// map (the safe cone march on cell cones, its quadrant form, max-mip) search the chord
/// untilted wherever it descends, with the maps' absolute heights raised by the same constant
/// lift (`FnBuilder::map_height`), so that their maps still bound the field they search.
/// Against the exact reference on the grazing torus (`rocks`, 48², both edge modes): coverage
/// error within the prism's goal, 0.5 % of the pixels. Printed, not asserted: the pixels past
/// the reference and the sphere's limb, where the goal is missed (0.6–1.0 %,
/// docs/notes/meshes.md). Seen to fail on main's tilted lift of every long chord (471585f): `csm(15)+binary(5)`
/// on the torus, repeat, 4.5 % wrong and 96 pixels past (0.39 % and 1 after).
#[test]
fn map_based_coarse_stages_under_prism_keep_their_bounds_at_grazing_views() {
    let g = gpu();
    let size = 48;
    for name in ["torus_grazing", "sphere_limb"] {
        for edge in [EdgeMode::Repeat, EdgeMode::Clamp] {
            let ms = scene(name, edge);
            let reference = ms.reference_hits(size, size).unwrap();
            let base = score(&prism_probe(&g, &ms, BASE, size), &reference, &ms);
            for stages in ["csm(15)+binary(5)", "qcsm(15)+binary(5)", "maxmip(64)+binary(5)"] {
                let what = format!("{name} {edge:?} {stages}");
                let s = score(&prism_probe(&g, &ms, stages, size), &reference, &ms);
                println!(
                    "{what}: coverage error {:.4}, past {} ({BASE}: {:.4}, {})",
                    s.coverage_error, s.past, base.coverage_error, base.past
                );
                assert!(s.both > (size * size / 5) as usize, "{what}: {s:?}");
                if name == "torus_grazing" {
                    assert!(
                        s.coverage_error <= 0.005,
                        "{what}: coverage error {} above the goal 0.5 %",
                        s.coverage_error
                    );
                }
            }
        }
    }
}
