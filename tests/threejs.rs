//! three.js as a client of relief's libraries, in a real browser: headless Chromium
//! (SwiftShader) draws the relief quad with three.js (`tests/browser/pages/threejs.html`,
//! npm `three` pinned by `tests/browser/package-lock.json`) twice per pipeline:
//!
//! - WebGL2: the `glsl-es` library in a `ShaderMaterial` (GLSL3), compiled by ANGLE;
//! - WebGPU: the `tsl` library (WGSL with the resources as arguments) included by a TSL
//!   `wgslFn`, on three's `WebGPURenderer`, compiled by Tint.
//!
//! Each picture is compared with `relief render`'s frame (the render entry relief composes
//! itself, drawn by wgpu here) for the same scene, camera and pipeline. The page gets what
//! relief's own render uses: the textures in the layouts the runtime uploads (heights,
//! normals, albedo with their mip chains, the acceleration maps), the same filters and edge
//! mode, the scene's `view_proj`, eye, light and ambient share; the material shades as the
//! render entry does and writes sRGB like relief's `Rgba8UnormSrgb` target.
//!
//! The goal (the bar of `tests/integrate.rs`): a mean absolute difference of at most 1 of
//! 255 per channel and at most 1 % of the pixels differing by more than 8 in a channel.

use crate::common::{browser, frames};

use std::path::{Path, PathBuf};
use std::time::Duration;

use browser::{run_page, Page};
use relief::dsl::emit::{library_forms, LibraryForm, LibraryOptions};
use relief::runtime::gpu::{self, Gpu, MapKey, Program, SceneTextures, Upload};
use relief::runtime::EdgeMode;
use relief::runtime::Scene;
use relief::Pipeline;
use serde_json::{json, Value};

/// The frame's side, pixels.
const SIZE: u32 = 128;

/// The pipelines and scenes drawn: a linear search with binary refinement and a soft shadow
/// on a real height map, a safe cone method on a rough procedural surface, and the max-mip
/// traversal on one-texel walls and pillars with clamped edges.
const CASES: [(&str, &str, EdgeMode); 3] = [
    ("linear(32)+binary(5)+shadow=soft(16)", "lion", EdgeMode::Repeat),
    ("csm(64)", "rock_bump", EdgeMode::Repeat),
    ("maxmip(96)", "shapes", EdgeMode::Clamp),
];

fn relief_render(g: &Gpu, p: &Pipeline, scene: &Scene) -> Vec<u8> {
    let program = Program::new(p).unwrap();
    let mut tex = SceneTextures::new(g, scene);
    tex.add_maps(g, scene, &p.required_maps()).unwrap();
    gpu::render(g, &program, scene, &tex, SIZE, 0, 1).unwrap().rgba
}

/// Writes an upload's levels as raw files `NAME_L{k}.bin` and returns its manifest entry.
fn write_upload(dir: &Path, name: &str, u: &Upload) -> Value {
    assert_eq!(u.depth, 1, "{name}: the page draws 2D textures only");
    let levels: Vec<Value> = u
        .levels
        .iter()
        .enumerate()
        .map(|(k, bytes)| {
            let file = format!("{name}_L{k}.bin");
            std::fs::write(dir.join(&file), bytes).unwrap();
            json!({ "file": file, "width": (u.width >> k).max(1), "height": (u.height >> k).max(1) })
        })
        .collect();
    json!({ "format": format!("{:?}", u.format), "levels": levels })
}

/// One case's folder: its textures and its manifest entry (libraries, camera, bindings).
fn write_case(dir: &Path, i: usize, p: &Pipeline, scene: &Scene, float32: bool) -> Value {
    let sub = format!("case{i}");
    let cdir = dir.join(&sub);
    std::fs::create_dir_all(&cdir).unwrap();
    let u = gpu::scene_uploads(scene, float32);
    let mut textures = serde_json::Map::new();
    textures.insert("height".into(), write_upload(&cdir, "height", &u.height));
    textures.insert("normal".into(), write_upload(&cdir, "normal", &u.normal));
    textures.insert("albedo".into(), write_upload(&cdir, "albedo", &u.albedo));
    let reqs = p.required_maps();
    for req in &reqs {
        let Some(key) = MapKey::of(*req) else { continue };
        let name = format!("map_{}", req.name());
        textures.insert(name.clone(), write_upload(&cdir, &name, &gpu::map_upload_of(scene, key).unwrap()));
    }
    let opts = LibraryOptions { edge_clamp: scene.edge == EdgeMode::Clamp, ..Default::default() };
    // Both forms of every case: a pipeline the glsl-es form refused would fail here.
    let lib = library_forms(p, &opts, &[LibraryForm::Tsl, LibraryForm::GlslEs]).unwrap_or_else(|e| panic!("{p}: {e}"));
    // What each of the library's resources takes, as `examples/integrate.rs` binds them.
    let bindings: Vec<Value> = lib
        .bindings
        .iter()
        .map(|b| {
            let base = b.name.strip_prefix("relief_").unwrap_or(&b.name);
            let nearest = base == "sampler_nearest" || base.ends_with("_nearest");
            let source = match base {
                "sampler" | "sampler_nearest" => "height".to_string(),
                "height" | "height_nearest" => "height".to_string(),
                other => {
                    let map = other.strip_suffix("_nearest").unwrap_or(other);
                    assert!(reqs.iter().any(|r| r.name() == map), "{p}: the library reads `{}`", b.name);
                    format!("map_{map}")
                }
            };
            let kind = if base.starts_with("sampler") { "sampler" } else { "texture" };
            json!({ "name": b.name, "kind": kind, "source": source, "filter": if nearest { "nearest" } else { "linear" } })
        })
        .collect();
    let eye = scene.camera.camera_position();
    let l = scene.light_dir.normalize();
    json!({
        "pipeline": p.to_string(),
        "scene": scene.name,
        "dir": sub,
        "tsl": lib.files[0].text,
        "glsl_es": lib.files[1].text,
        "has_shadow": lib.has_shadow,
        "has_ao": lib.has_ao,
        "view_proj": scene.camera.view_proj(1.0).to_cols_array(),
        "eye": [eye.x, eye.y, eye.z, scene.depth_scale],
        "light": [l.x, l.y, l.z, gpu::AMBIENT],
        "tiling": scene.tiling,
        "edge": if scene.edge == EdgeMode::Clamp { "clamp" } else { "repeat" },
        "textures": textures,
        "bindings": bindings,
    })
}

/// The page's pictures come back as hex (RGBA8, top row first).
fn from_hex(s: &str) -> Vec<u8> {
    assert!(s.len().is_multiple_of(2) && s.is_ascii(), "a picture's hex has an odd length or stray characters");
    (0..s.len()).step_by(2).map(|i| u8::from_str_radix(&s[i..i + 2], 16).expect("a picture's hex")).collect()
}

fn temp_dir() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("relief-threejs-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn threejs_draws_relief_renders_frame_in_webgl2_and_webgpu() {
    let g = Gpu::new().unwrap();
    let dir = temp_dir();
    let mut cases = Vec::new();
    let mut references = Vec::new();
    for (i, (pipe, scene, edge)) in CASES.iter().enumerate() {
        let p: Pipeline = pipe.parse().unwrap();
        let mut scene = Scene::by_name(scene, Some(64)).unwrap();
        scene.edge = *edge;
        cases.push(write_case(&dir, i, &p, &scene, g.float32_filterable));
        references.push(relief_render(&g, &p, &scene));
    }
    std::fs::write(dir.join("manifest.json"), json!({ "size": SIZE, "cases": cases }).to_string()).unwrap();
    let mut page = Page::new("pages/threejs.html");
    page.mounts.push(("data", &dir));
    page.size = (SIZE, SIZE);
    page.timeout = Duration::from_secs(120);
    let r = run_page(&page);
    let keep = std::env::var_os("RELIEF_THREEJS_KEEP").is_some();
    let mut failures = Vec::new();
    let mut drawn = 0;
    for (i, (pipe, scene, _)) in CASES.iter().enumerate() {
        for api in ["webgl2", "webgpu"] {
            let pic = &r["cases"][i][api];
            assert!(!pic.is_null(), "{pipe}: no {api} picture: {}", r["cases"][i]);
            let rgba = from_hex(pic["rgba"].as_str().unwrap_or_else(|| panic!("{pipe} {api}: {pic}")));
            assert_eq!(rgba.len(), (SIZE * SIZE * 4) as usize, "{pipe} {api}: picture size");
            let (mad, share) = frames::frame_difference(&rgba, &references[i]);
            println!(
                "{pipe} on {scene}, {api} (three.js): mean |difference| {mad:.4} of 255, {:.3} % of pixels off by more than 8",
                share * 100.0
            );
            let lit = rgba.chunks(4).filter(|px| px[0] > 20 || px[1] > 20 || px[2] > 20).count();
            if mad > 1.0 || share > 0.01 || lit <= (SIZE * SIZE / 3) as usize || keep {
                for (what, px) in [("threejs", &rgba), ("relief", &references[i])] {
                    let file = dir.join(format!("case{i}_{api}_{what}.png"));
                    relief::runtime::io::png::write_rgba8(&file, SIZE, SIZE, px.clone()).unwrap();
                }
            }
            if mad > 1.0 || share > 0.01 {
                failures.push(format!(
                    "{pipe} on {scene}, {api}: mean |difference| {mad:.4}, {:.3} % off by > 8 (pictures in {})",
                    share * 100.0,
                    dir.display()
                ));
            }
            assert!(lit > (SIZE * SIZE / 3) as usize, "{pipe} {api}: only {lit} lit pixels");
            drawn += 1;
        }
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
