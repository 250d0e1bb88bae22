//! `examples/integrate.rs` — an engine's own material shader importing a generated WGSL
//! library — draws the same picture as `relief render` (the render entry relief composes
//! itself) for the same pipeline and scene.
//!
//! Both run the same search on the same rasterized quad with the same lighting, so they
//! differ only where the two shaders' arithmetic rounds differently (a ray that lands on the
//! other side of a texel edge or of a step). The goal stated here: a mean absolute difference
//! of at most 1 (of 255) per channel, and at most 1 % of the pixels differing by more than 8.

use crate::common::frames;
#[path = "../examples/integrate.rs"]
#[allow(dead_code)]
mod example;

use relief::runtime::gpu::{Gpu, SceneTextures};
use relief::runtime::Scene;
use relief::Pipeline;

#[test]
fn the_integration_example_matches_relief_render() {
    let size = 128;
    let g = Gpu::new().unwrap();
    for (pipe, scene) in [
        ("linear(32)+binary(5)+shadow=soft(16)", "lion"),
        ("csm(15)+binary(4)+shadow=soft_ratio(10)+ao=cone_ratio", "rock_bump"),
        ("maxmip(64)+shadow=hard(16)", "shapes"),
    ] {
        let p: Pipeline = pipe.parse().unwrap();
        let scene = Scene::by_name(scene, Some(64)).unwrap();
        let frame = example::run(&p, &scene, size).unwrap();
        let ours = frame.rgba;
        let theirs = frames::relief_render(&g, &p, &scene, size);
        let (mean, share) = frames::frame_difference(&ours, &theirs);
        println!(
            "{pipe} on {}: mean |difference| {mean:.4} of 255, {:.3} % of pixels off by more than 8",
            scene.name,
            share * 100.0
        );
        assert!(mean <= 1.0, "{pipe}: mean absolute difference {mean}");
        assert!(share <= 0.01, "{pipe}: {:.3} % of pixels differ by more than 8", share * 100.0);
        // The picture is not empty: the quad covers most of the frame in lit colours.
        let lit = ours.chunks(4).filter(|px| px[0] > 20 || px[1] > 20 || px[2] > 20).count();
        assert!(lit > (size * size / 3) as usize, "{pipe}: only {lit} lit pixels");
    }
}

/// `relief_trace` from a user's compute shader over a flat relief at height 0.5: the hit lies
/// where the unit view ray from `(uv, 0)` has descended half the depth, so (independently of
/// the search) `depth_offset = 0.5 · d / −v.z` and `hit.uv = uv + depth_offset · v.xy`.
/// linear(32) lands on t = 16/32 = 0.5 exactly or brackets it in a step of 1/32, and binary(6)
/// narrows that to 1/32 / 2⁶ = 1/2048 in t: the tolerance, scaled to each quantity, plus 1e-5
/// for f32 rounding.
#[test]
fn depth_offset_is_the_distance_along_the_view_ray() {
    use relief::dsl::emit::{library, LibraryOptions};
    use relief::runtime::HeightMap;
    use wgpu::util::DeviceExt;

    let p: Pipeline = "linear(32)+binary(6)".parse().unwrap();
    let lib = library(&p, &LibraryOptions::default()).unwrap();
    let user = r#"
struct Query { uv: vec2<f32>, depth_scale: f32, pad: f32, view: vec4<f32> };
@group(1) @binding(0) var<storage, read> queries: array<Query>;
@group(1) @binding(1) var<storage, read_write> results: array<vec4<f32>>;
@compute @workgroup_size(1) fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let q = queries[id.x];
    let hit = relief_trace(q.uv, q.view.xyz, q.depth_scale);
    results[2u * id.x] = vec4(hit.uv, hit.height, hit.t);
    results[2u * id.x + 1u] = vec4(hit.depth_offset, 0.0, 0.0, 0.0);
}
"#;
    let g = Gpu::new().unwrap();
    let scene = Scene::from_height_map("flat half", HeightMap::from_fn(16, 16, |_, _| 0.5));
    let tex = SceneTextures::new(&g, &scene);
    let module = g
        .checked(|| {
            g.device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: None,
                source: wgpu::ShaderSource::Wgsl(format!("{}\n{user}", lib.wgsl).into()),
            })
        })
        .unwrap();
    let pipe = g
        .checked(|| {
            g.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: None,
                layout: None,
                module: &module,
                entry_point: Some("main"),
                compilation_options: Default::default(),
                cache: None,
            })
        })
        .unwrap();
    // Views from 0° to 80° off the normal at several azimuths, some not normalized.
    let mut queries: Vec<[f32; 8]> = Vec::new();
    for (i, angle) in [0.0f32, 20.0, 45.0, 60.0, 80.0].into_iter().enumerate() {
        for (j, az) in [0.0f32, 100.0, 215.0].into_iter().enumerate() {
            let (a, z) = (angle.to_radians(), az.to_radians());
            let len = if (i + j) % 2 == 0 { 1.0 } else { 3.0 };
            let v = [a.sin() * z.cos() * len, a.sin() * z.sin() * len, -a.cos() * len];
            let depth = [0.05f32, 0.1, 0.2][j];
            queries.push([0.1 + 0.17 * i as f32, 0.3 + 0.2 * j as f32, depth, 0.0, v[0], v[1], v[2], 0.0]);
        }
    }
    let qbuf = g.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents: bytemuck::cast_slice(&queries),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let out_size = (queries.len() * 32) as u64;
    let rbuf = g.device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: out_size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let read = g.device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: out_size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let lib_entries: Vec<wgpu::BindGroupEntry> = lib
        .bindings
        .iter()
        .map(|b| wgpu::BindGroupEntry {
            binding: b.binding,
            resource: match b.name.as_str() {
                "relief_height" => wgpu::BindingResource::TextureView(&tex.height),
                "relief_sampler" => wgpu::BindingResource::Sampler(&tex.linear),
                other => panic!("linear+binary reads {other}"),
            },
        })
        .collect();
    let bg0 = g.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipe.get_bind_group_layout(0),
        entries: &lib_entries,
    });
    let bg1 = g.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipe.get_bind_group_layout(1),
        entries: &[
            wgpu::BindGroupEntry { binding: 0, resource: qbuf.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 1, resource: rbuf.as_entire_binding() },
        ],
    });
    let mut enc = g.device.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipe);
        pass.set_bind_group(0, &bg0, &[]);
        pass.set_bind_group(1, &bg1, &[]);
        pass.dispatch_workgroups(queries.len() as u32, 1, 1);
    }
    enc.copy_buffer_to_buffer(&rbuf, 0, &read, 0, out_size);
    g.queue.submit([enc.finish()]);
    let out: Vec<f32> = bytemuck::cast_slice(&g.read_buffer(&read).unwrap()).to_vec();
    let step = 1.0 / 2048.0;
    for (k, q) in queries.iter().enumerate() {
        let r = &out[8 * k..8 * k + 8];
        let len = (q[4] * q[4] + q[5] * q[5] + q[6] * q[6]).sqrt();
        let v = [q[4] / len, q[5] / len, q[6] / len];
        let (d, cos) = (q[2], -v[2]);
        let s = 0.5 * d / cos;
        let s_tol = step * d / cos + 1e-5;
        let expect_uv = [q[0] + s * v[0], q[1] + s * v[1]];
        let uv_tol = step * d / cos * (v[0] * v[0] + v[1] * v[1]).sqrt() + 1e-5;
        let what = format!(
            "query {k} (view {v:?}, depth {d}): got uv ({}, {}), height {}, t {}, depth_offset {}",
            r[0], r[1], r[2], r[3], r[4]
        );
        assert!((r[3] - 0.5).abs() <= step + 1e-5, "t: {what}");
        assert!((r[2] - 0.5).abs() <= step + 1e-5, "height: {what}");
        assert!((r[4] - s).abs() <= s_tol, "depth_offset, expected {s}: {what}");
        assert!(
            (r[0] - expect_uv[0]).abs() <= uv_tol && (r[1] - expect_uv[1]).abs() <= uv_tol,
            "uv, expected {expect_uv:?}: {what}"
        );
    }
}

/// The example's pixel depth offset (the library's `depth_offset`, written as the fragment's
/// depth) puts an exact method's depth buffer on the exact reference's hits: NDC depth within
/// 1e-4 (the goal `relief render --write-depth` has for exact methods), on every pixel.
#[test]
fn the_integration_examples_depth_offset_matches_the_reference_hits() {
    let size = 96;
    let p: Pipeline = "maxmip(96)".parse().unwrap();
    for name in ["shapes", "rock_bump"] {
        let scene = Scene::by_name(name, Some(64)).unwrap();
        let frame = example::run(&p, &scene, size).unwrap();
        let g = Gpu::new().unwrap();
        let prep = relief::runtime::measure::Prepared::new(&g, scene, size).unwrap();
        let errors = relief::runtime::measure::depth_errors(&prep, &prep.refs, &frame.depth);
        let worst = errors.iter().copied().fold(0.0, f64::max);
        println!(
            "{name}: depth_offset depth against the reference: max |error| {worst:.2e} over {} pixels",
            errors.len()
        );
        assert!(errors.len() > (size * size / 3) as usize, "{name}: the quad covers the frame");
        assert!(worst <= 1e-4, "{name}: NDC depth off the reference hit by {worst}");
    }
}
