//! three.js as a client of `relief export` (issue 39), in a real browser: for each pipeline
//! the test runs `relief export PIPELINE --scene MAP --target glsl-es|tsl --out DIR`, serves
//! the folders, and headless Chromium (SwiftShader) draws the relief quad with three.js
//! (`tests/browser/pages/threejs.html`, npm `three` pinned by
//! `tests/browser/package-lock.json`) twice per pipeline:
//!
//! - WebGL2: the `glsl-es` bundle's library in a `ShaderMaterial` (GLSL3), compiled by ANGLE;
//! - WebGPU: the `tsl` bundle's library (WGSL with the resources as arguments) included by a
//!   TSL `wgslFn`, on three's `WebGPURenderer`, compiled by Tint.
//!
//! The page reads `relief.json`, the library and the `.ktx2` files it names, as a three.js
//! user would: every texture through three's own `KTX2Loader` (its data-texture path for
//! uncompressed formats, which needs no Basis transcoder), with the filter and address mode
//! the json gives. The harness hands the page only the camera (relief's `view_proj` and
//! eye); no texture goes to the page but through the bundles' files.
//!
//! Each picture is compared with `relief render`'s frame for the same scene, camera and
//! pipeline, by the bar of `tests/integrate.rs`: a mean absolute difference of at most 1 of
//! 255 per channel and at most 1 % of the pixels differing by more than 8 in a channel. The
//! clamp-edge case is drawn once more with every texture's address mode forced to repeat in
//! the page, and those pictures must miss the bar.

use crate::common::browser;
use crate::common::exe::export;
use crate::common::frames::{
    self, assert_clamp_bundle, engine_picture, from_hex, relief_render, CLAMP_CASE, ENGINE_CASES as CASES,
    ENGINE_SIZE as SIZE,
};

use std::time::Duration;

use browser::{run_page, Page};
use relief::dsl::emit::{library_forms, LibraryForm, LibraryOptions};
use relief::runtime::gpu::Gpu;
use relief::runtime::scene_from_arg;
use relief::Pipeline;
use serde_json::json;

#[test]
fn threejs_draws_relief_renders_frame_from_export_bundles_in_webgl2_and_webgpu() {
    let g = Gpu::new().unwrap();
    let dir = std::env::temp_dir().join(format!("relief-threejs-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    let mut cases = Vec::new();
    let mut references = Vec::new();
    for (i, (pipe, arg)) in CASES.iter().enumerate() {
        // One bundle per API: the glsl-es library for WebGL2, the tsl library for WebGPU.
        let (es, tsl) = (format!("case{i}_glsl_es"), format!("case{i}_tsl"));
        export(pipe, arg, "glsl-es", &dir.join(&es));
        export(pipe, arg, "tsl", &dir.join(&tsl));
        if i == CLAMP_CASE {
            assert_clamp_bundle(&dir.join(&es));
            assert_clamp_bundle(&dir.join(&tsl));
        }
        let p: Pipeline = pipe.parse().unwrap();
        let scene = scene_from_arg(arg).unwrap();
        let eye = scene.camera.camera_position();
        // The camera only: the page takes everything else from the bundles.
        cases.push(json!({
            "webgl2": es,
            "webgpu": tsl,
            "view_proj": scene.camera.view_proj(1.0).to_cols_array(),
            "eye": [eye.x, eye.y, eye.z],
        }));
        references.push(relief_render(&g, &p, &scene, SIZE));
    }
    // The clamp-edge case once more, its textures forced to repeat in the page.
    let mut forced = cases[CLAMP_CASE].clone();
    forced["address_override"] = "repeat".into();
    cases.push(forced);
    std::fs::write(dir.join("manifest.json"), json!({ "size": SIZE, "cases": cases }).to_string()).unwrap();
    let mut page = Page::new("pages/threejs.html");
    page.mounts.push(("data", &dir));
    page.size = (SIZE, SIZE);
    page.timeout = Duration::from_secs(120);
    let r = run_page(&page);
    let keep = std::env::var_os("RELIEF_THREEJS_KEEP").is_some();
    let mut failures = Vec::new();
    let mut drawn = 0;
    for (i, (pipe, arg)) in CASES.iter().enumerate() {
        for api in ["webgl2", "webgpu"] {
            let pic = &r["cases"][i][api];
            assert!(!pic.is_null(), "{pipe}: no {api} picture: {}", r["cases"][i]);
            let rgba = from_hex(pic["rgba"].as_str().unwrap_or_else(|| panic!("{pipe} {api}: {pic}")));
            let what = format!("{pipe} on {arg}, {api} (three.js {}, KTX2Loader)", r["three"]);
            let stem = format!("case{i}_{api}");
            failures.extend(engine_picture("three.js", &what, &rgba, &references[i], &dir, &stem, keep));
            drawn += 1;
        }
    }
    let (pipe, arg) = CASES[CLAMP_CASE];
    for api in ["webgl2", "webgpu"] {
        let pic = &r["cases"][CASES.len()][api];
        let rgba = from_hex(pic["rgba"].as_str().unwrap_or_else(|| panic!("the forced-repeat case, {api}: {pic}")));
        let what = format!("{pipe} on {arg} with every address mode forced to repeat, {api} (three.js)");
        let stem = format!("forced_repeat_{api}");
        let forced = engine_picture("three.js", &what, &rgba, &references[CLAMP_CASE], &dir, &stem, keep);
        assert!(forced.is_some(), "{what}: within the bar, so the clamp case does not show the address mode is taken");
    }
    assert!(failures.is_empty(), "three.js's pictures differ from relief render's:\n{}", failures.join("\n"));
    assert_eq!(drawn, 2 * CASES.len(), "pictures drawn");
    if !keep {
        std::fs::remove_dir_all(&dir).ok();
    }
}

/// Every library of `relief gen --all --library` in the `tsl` form is WGSL that naga parses
/// and validates, and no texture or sampler in it is a global: three.js's node system binds
/// only what a `wgslFn` is passed.
#[test]
fn every_tsl_library_is_valid_wgsl_with_no_global_resource() {
    let pipelines = frames::library_pipelines();
    for p in &pipelines {
        let lib =
            library_forms(p, &LibraryOptions::default(), &[LibraryForm::Tsl]).unwrap_or_else(|e| panic!("{p}: {e}"));
        let text = &lib.files[0].text;
        assert!(lib.files[0].name.ends_with(".tsl.wgsl"), "{p}: {}", lib.files[0].name);
        let module = naga::front::wgsl::parse_str(text).unwrap_or_else(|e| panic!("{p}: {}", e.emit_to_string(text)));
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all())
            .validate(&module)
            .unwrap_or_else(|e| panic!("{p}: {e:?}"));
        assert!(module.global_variables.is_empty(), "{p}: the tsl form declares a global resource");
        assert!(!text.contains("@group"), "{p}: the tsl form has a binding attribute");
        // three.js binds no sampler for a NearestFilter texture: the nearest textures are
        // read with texel loads, and no function takes the nearest sampler.
        assert!(!text.contains("sampler_nearest"), "{p}: the tsl form takes the nearest sampler");
        let nearest = lib.bindings.iter().any(|b| b.name.ends_with("_nearest"));
        assert_eq!(text.contains("fn relief_texel_nearest("), nearest, "{p}: the texel read and the nearest textures");
        // Each resource is an argument of the trace function, as the header lists it.
        let trace = module.functions.iter().find(|(_, f)| f.name.as_deref() == Some("relief_trace")).unwrap().1;
        assert!(trace.arguments.len() >= 3, "{p}: relief_trace takes uv, view and depth first");
        let listed = text
            .lines()
            .skip_while(|l| !l.starts_with("// fn relief_trace("))
            .nth(1)
            .and_then(|l| l.split("resource arguments: ").nth(1))
            .map(|l| l.split(", ").count())
            .unwrap_or(0);
        assert_eq!(trace.arguments.len(), 3 + listed, "{p}: relief_trace's resource arguments and its header");
    }
}

/// The `tsl` form's texel read (`relief_texel_nearest`, which stands for a sample through the
/// nearest sampler) takes the texel the GPU's nearest sampler takes, and the texel
/// `floor(uv · size)` wrapped or clamped as worked out here, for both edge modes, on a
/// 5 × 3 texture (odd sides) at hard coordinates: a quarter texel either side of texel
/// borders, just outside [0, 1], and several tiles away on both sides.
#[test]
fn tsl_texel_read_takes_the_nearest_samplers_texel_in_both_edge_modes() {
    use wgpu::util::DeviceExt;
    let (w, h) = (5u32, 3u32);
    let texels: Vec<f32> = (0..w * h).map(|i| 1.0 + i as f32).collect();
    let mut coords = Vec::new();
    for x in [-7.25f32, -2.75, -0.25, 0.25, 0.75, 1.25, 2.75, 4.25, 4.75, 5.25, 9.75, 13.25] {
        for y in [-4.25f32, -0.25, 0.25, 1.75, 2.25, 2.75, 3.25, 6.75] {
            coords.push([x / w as f32, y / h as f32]);
        }
    }
    let g = Gpu::new().unwrap();
    let tex = g.device.create_texture_with_data(
        &g.queue,
        &wgpu::TextureDescriptor {
            label: None,
            size: wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R32Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(&texels),
    );
    let view = tex.create_view(&Default::default());
    for clamp in [false, true] {
        let p: Pipeline = "csm(64)".parse().unwrap();
        let opts = LibraryOptions { edge_clamp: clamp, ..Default::default() };
        let lib = library_forms(&p, &opts, &[LibraryForm::Tsl]).unwrap();
        let text = &lib.files[0].text;
        let helper = &text[text.find("fn relief_texel_nearest(").expect("the tsl csm library's texel read")..];
        let shader = format!(
            "{helper}
@group(0) @binding(0) var t: texture_2d<f32>;
@group(0) @binding(1) var s: sampler;
@group(0) @binding(2) var<storage, read> uvs: array<vec2<f32>>;
@group(0) @binding(3) var<storage, read_write> out: array<vec2<f32>>;
@compute @workgroup_size(1) fn main(@builtin(global_invocation_id) id: vec3<u32>) {{
    let uv = uvs[id.x];
    out[id.x] = vec2(textureSampleLevel(t, s, uv, 0.0).x, relief_texel_nearest(t, uv, 0.0).x);
}}"
        );
        let module = g
            .checked(|| {
                g.device.create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: None,
                    source: wgpu::ShaderSource::Wgsl(shader.as_str().into()),
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
        let mode = if clamp { wgpu::AddressMode::ClampToEdge } else { wgpu::AddressMode::Repeat };
        let sampler = g.device.create_sampler(&wgpu::SamplerDescriptor {
            address_mode_u: mode,
            address_mode_v: mode,
            mag_filter: wgpu::FilterMode::Nearest,
            min_filter: wgpu::FilterMode::Nearest,
            ..Default::default()
        });
        let ubuf = g.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: None,
            contents: bytemuck::cast_slice(&coords),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let size = (coords.len() * 8) as u64;
        let obuf = g.device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let read = g.device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bg = g.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &pipe.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&view) },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::Sampler(&sampler) },
                wgpu::BindGroupEntry { binding: 2, resource: ubuf.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 3, resource: obuf.as_entire_binding() },
            ],
        });
        let mut enc = g.device.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipe);
            pass.set_bind_group(0, &bg, &[]);
            pass.dispatch_workgroups(coords.len() as u32, 1, 1);
        }
        enc.copy_buffer_to_buffer(&obuf, 0, &read, 0, size);
        g.queue.submit([enc.finish()]);
        let out: Vec<[f32; 2]> = bytemuck::cast_slice(&g.read_buffer(&read).unwrap()).to_vec();
        for (uv, [sampled, loaded]) in coords.iter().zip(out) {
            // The texel worked out here: floor(uv · size), wrapped or clamped.
            let pick = |c: f32, n: u32| {
                let i = (c * n as f32).floor() as i64;
                if clamp {
                    i.clamp(0, n as i64 - 1)
                } else {
                    i.rem_euclid(n as i64)
                }
            };
            let expect = texels[(pick(uv[1], h) * w as i64 + pick(uv[0], w)) as usize];
            let edge = if clamp { "clamp" } else { "repeat" };
            assert_eq!(loaded, sampled, "{edge}, uv {uv:?}: the texel read and the nearest sampler differ");
            assert_eq!(loaded, expect, "{edge}, uv {uv:?}: the texel read is not floor(uv·size) addressed");
        }
    }
}
