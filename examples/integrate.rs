//! An engine's own material shader that imports a relief library (`relief gen --library`)
//! and draws a relief quad headless to a PNG.
//!
//! The program owns everything around the search: a vertex buffer with its own layout
//! (position, uv), a camera uniform of its own shape, its material textures (albedo, normal)
//! and sampler in group 0, and the library's resources in group 1 from binding 0, as the
//! library's header lists them. The quad lies in tangent space (tangent = +x, bitangent = +y,
//! normal = +z), so the view direction in tangent space is the world one.
//!
//! Pixel depth offset: the fragment moves its depth to the hit with the library's
//! `depth_offset` (the distance behind the polygon along the unit view ray), so the depth
//! attachment holds the relief's surface and other geometry intersects it correctly.
//!
//! `cargo run --release --example integrate -- 'linear(32)+binary(5)+shadow=soft(16)' scene:lion 256 out.png`

use std::path::Path;

use relief::dsl::emit::{self, LibraryFiles, LibraryOptions};
use relief::runtime::gpu::{draw_frame, Gpu, SceneTextures, DEPTH_FORMAT, FORMAT};
use relief::runtime::EdgeMode;
use relief::runtime::Scene;
use relief::Pipeline;
use wgpu::util::DeviceExt;

/// The material shader: everything but the `relief_*` functions and globals.
const MATERIAL: &str = r#"
struct Camera {
    view_proj: mat4x4<f32>,
    eye: vec4<f32>,        // xyz: the eye in world (= tangent) space; w: the relief depth
    light: vec4<f32>,      // xyz: toward the light; w: ambient share
};
@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var albedo_tex: texture_2d<f32>;
@group(0) @binding(2) var normal_tex: texture_2d<f32>;
@group(0) @binding(3) var material_sampler: sampler;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) uv: vec2<f32>,
};
struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) uv: vec2<f32>,
};

@vertex fn vs(v: VertexIn) -> VertexOut {
    return VertexOut(camera.view_proj * vec4(v.position, 1.0), v.position, v.uv);
}

struct FragmentOut {
    @location(0) color: vec4<f32>,
    @builtin(frag_depth) depth: f32,
};

@fragment fn fs(in: VertexOut) -> FragmentOut {
    let depth = camera.eye.w;
    let view = normalize(in.world - camera.eye.xyz);
    let hit = relief_trace(in.uv, view, depth);
    // Pixel depth offset: the hit lies `depth_offset` behind the polygon along the view ray.
    let at = camera.view_proj * vec4(in.world + view * hit.depth_offset, 1.0);
    let to_light = camera.light.xyz;
    let visibility = SHADOW;
    let occlusion = AO;
    let n = normalize(textureSampleLevel(normal_tex, material_sampler, hit.uv, 0.0).xyz * 2.0 - 1.0);
    let albedo = textureSampleLevel(albedo_tex, material_sampler, hit.uv, 0.0).rgb;
    let ambient = camera.light.w;
    let color = albedo * (ambient * occlusion + (1.0 - ambient) * max(dot(n, to_light), 0.0) * visibility);
    return FragmentOut(vec4(color, 1.0), at.z / at.w);
}
"#;

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct CameraUniform {
    view_proj: [f32; 16],
    eye: [f32; 4],
    light: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Vertex {
    position: [f32; 3],
    uv: [f32; 2],
}

/// The ambient share `relief render` lights with.
pub use relief::runtime::gpu::AMBIENT as AMBIENT_SHARE;

/// The user's shader source: the library, then the material.
pub fn shader_source(lib: &LibraryFiles) -> String {
    let material = MATERIAL
        .replace("SHADOW", if lib.has_shadow { "relief_shadow(hit, to_light, depth)" } else { "1.0" })
        .replace("AO", if lib.has_ao { "relief_ao(hit)" } else { "1.0" });
    format!("{}\n{material}", lib.wgsl)
}

/// A rendered frame.
pub struct Frame {
    /// RGBA8 (sRGB) rows, top row first.
    pub rgba: Vec<u8>,
    /// The depth attachment (NDC depth, cleared to 1), row-major, top row first.
    pub depth: Vec<f32>,
}

/// Renders `pipeline` on `scene` at `size²` pixels through the material shader, with a
/// depth attachment the fragment writes the hit's depth to.
pub fn run(pipeline: &Pipeline, scene: &Scene, size: u32) -> Result<Frame, Box<dyn std::error::Error>> {
    let gpu = Gpu::new()?;
    let lib = emit::library(
        pipeline,
        &LibraryOptions { group: 1, binding: 0, edge_clamp: scene.edge == EdgeMode::Clamp, ..Default::default() },
    )?;
    let mut tex = SceneTextures::new(&gpu, scene);
    tex.add_maps(&gpu, scene, &pipeline.required_maps())?;
    let module = gpu.checked(|| {
        gpu.device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("material"),
            source: wgpu::ShaderSource::Wgsl(shader_source(&lib).into()),
        })
    })?;
    let pipe = gpu.checked(|| {
        gpu.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("material"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<Vertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x2],
                })],
            },
            primitive: wgpu::PrimitiveState { topology: wgpu::PrimitiveTopology::TriangleList, ..Default::default() },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs"),
                compilation_options: Default::default(),
                targets: &[Some(FORMAT.into())],
            }),
            multiview_mask: None,
            cache: None,
        })
    })?;
    // The quad [0, tiling]² on z = 0, uv = position (the texture repeats `tiling` times).
    let t = scene.tiling;
    let corner = |x: f32, y: f32| Vertex { position: [x * t, y * t, 0.0], uv: [x * t, y * t] };
    let vertices = [corner(0., 0.), corner(1., 0.), corner(0., 1.), corner(0., 1.), corner(1., 0.), corner(1., 1.)];
    let vbuf = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("quad"),
        contents: bytemuck::cast_slice(&vertices),
        usage: wgpu::BufferUsages::VERTEX,
    });
    let eye = scene.camera.camera_position();
    let l = scene.light_dir.normalize();
    let cam = CameraUniform {
        view_proj: scene.camera.view_proj(1.0).to_cols_array(),
        eye: [eye.x, eye.y, eye.z, scene.depth_scale],
        light: [l.x, l.y, l.z, AMBIENT_SHARE],
    };
    let ubuf = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("camera"),
        contents: bytemuck::bytes_of(&cam),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let material = gpu.checked(|| {
        gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("material"),
            layout: &pipe.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: ubuf.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&tex.albedo) },
                wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(&tex.normal) },
                wgpu::BindGroupEntry { binding: 3, resource: wgpu::BindingResource::Sampler(&tex.linear) },
            ],
        })
    })?;
    // The library's resources, by the names its header lists.
    let reqs = pipeline.required_maps();
    let mut entries = Vec::new();
    for b in &lib.bindings {
        let base = b.name.strip_prefix("relief_").unwrap_or(&b.name);
        let resource = match base {
            "sampler" => wgpu::BindingResource::Sampler(&tex.linear),
            "sampler_nearest" => wgpu::BindingResource::Sampler(&tex.nearest),
            "height" | "height_nearest" => wgpu::BindingResource::TextureView(&tex.height),
            other => {
                let map = other.strip_suffix("_nearest").unwrap_or(other);
                let req = reqs
                    .iter()
                    .find(|r| r.name() == map)
                    .ok_or_else(|| format!("the library reads `{}`, which the pipeline's maps do not name", b.name))?;
                let view = relief::runtime::gpu::MapKey::of(*req)
                    .and_then(|k| tex.maps.get(&k))
                    .ok_or_else(|| format!("map for `{}` not built", b.name))?;
                wgpu::BindingResource::TextureView(view)
            }
        };
        entries.push(wgpu::BindGroupEntry { binding: b.binding, resource });
    }
    let relief_group = gpu.checked(|| {
        gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("relief"),
            layout: &pipe.get_bind_group_layout(1),
            entries: &entries,
        })
    })?;

    // One headless frame with a depth attachment (relief's helper for offscreen programs).
    let clear = wgpu::Color { r: 0.02, g: 0.02, b: 0.03, a: 1.0 };
    let frame = draw_frame(&gpu, size, true, clear, |pass| {
        pass.set_pipeline(&pipe);
        pass.set_bind_group(0, &material, &[]);
        pass.set_bind_group(1, &relief_group, &[]);
        pass.set_vertex_buffer(0, vbuf.slice(..));
        pass.draw(0..6, 0..1);
    })?;
    Ok(Frame { rgba: frame.rgba, depth: frame.depth.expect("drawn with a depth attachment") })
}

#[allow(dead_code)]
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let pipeline: Pipeline =
        args.first().map(String::as_str).unwrap_or("linear(32)+binary(5)+shadow=soft(16)").parse()?;
    let scene = relief::runtime::scene_from_arg(args.get(1).map(String::as_str).unwrap_or("scene:lion"))?;
    let size: u32 = args.get(2).map(|s| s.parse()).transpose()?.unwrap_or(256);
    let out = args.get(3).map(String::as_str).unwrap_or("integrate.png");
    let frame = run(&pipeline, &scene, size)?;
    relief::runtime::io::png::write_rgba8(Path::new(out), size, size, frame.rgba)?;
    println!("wrote {out}: {pipeline} on {} at {size}² through a material shader that imports the library", scene.name);
    Ok(())
}
