//! The real-geometry baseline of Amaro & Gustafsson 2022, §3.1.2: each wall's height map displaced into a
//! grid of `grid × grid` vertices (the paper used 320 × 320) and rasterised with a depth
//! buffer, lit by the room's light (Lambert and the ambient share, no shadows: the paper's
//! "basic lighting"), coloured by the wall's albedo at each vertex. A facade at z = 0 with
//! the window cut out hides everything outside the window, as the interior entry draws only
//! the window quad.
//!
//! The frame's alpha holds the wall of each pixel, `(wall + 1) / 8` ([`wall_of_alpha`]),
//! for the silhouette test; the depth buffer holds NDC depth.

use wgpu::util::DeviceExt;

use super::{Room, RoomLight, WALLS};
use crate::gpu::{render_pipeline, timed_frames, Draw, Frames};
use crate::gpu::{Gpu, GpuError};
use crate::heightmap::EdgeMode;

/// The paper's grid size.
pub const DEFAULT_GRID: usize = 320;

/// One vertex: position, normal, linear colour, wall index (−1: the facade).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct Vertex {
    pos: [f32; 3],
    normal: [f32; 3],
    color: [f32; 3],
    wall: f32,
}

/// The baseline's geometry.
pub struct RoomMesh {
    vertices: Vec<Vertex>,
    indices: Vec<u32>,
    /// Triangles of the walls (the facade's not counted).
    pub wall_triangles: usize,
}

fn srgb_to_linear(c: u8) -> f32 {
    let c = c as f32 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The wall value of a baseline pixel's alpha: `Some(wall)`, or `None` outside the walls.
pub fn wall_of_alpha(a: u8) -> Option<usize> {
    let k = (a as f32 / 255.0 * 8.0).round() as i32 - 1;
    (0..WALLS as i32).contains(&k).then_some(k as usize)
}

impl RoomMesh {
    /// Every wall as a `grid × grid` grid over u, v ∈ [0, 1] at the bilinear height of its
    /// map (edge mode clamp), and the facade.
    pub fn new(room: &Room, grid: usize) -> RoomMesh {
        let n = grid.max(2);
        let mut vertices = Vec::new();
        let mut indices = Vec::new();
        for k in 0..WALLS {
            let w = &room.walls[k];
            let base = vertices.len() as u32;
            let at = |i: usize, j: usize| {
                let (u, v) = (i as f64 / (n - 1) as f64, j as f64 / (n - 1) as f64);
                let h = w.height.bilinear(u, v, EdgeMode::Clamp);
                room.wall_point(k, u, v, h)
            };
            for j in 0..n {
                for i in 0..n {
                    let p = at(i, j);
                    let du = at((i + 1).min(n - 1), j) - at(i.saturating_sub(1), j);
                    let dv = at(i, (j + 1).min(n - 1)) - at(i, j.saturating_sub(1));
                    let normal = du.cross(dv).normalize_or_zero();
                    let (u, v) = (i as f64 / (n - 1) as f64, j as f64 / (n - 1) as f64);
                    let color = match &w.albedo {
                        Some(a) => {
                            let x = ((u * a.width as f64) as usize).min(a.width - 1);
                            let y = ((v * a.height as f64) as usize).min(a.height - 1);
                            let t = &a.rgba[4 * (y * a.width + x)..];
                            [srgb_to_linear(t[0]), srgb_to_linear(t[1]), srgb_to_linear(t[2])]
                        }
                        None => [180, 170, 160].map(srgb_to_linear),
                    };
                    vertices.push(Vertex {
                        pos: p.as_vec3().to_array(),
                        normal: normal.as_vec3().to_array(),
                        color,
                        wall: k as f32,
                    });
                }
            }
            for j in 0..n as u32 - 1 {
                for i in 0..n as u32 - 1 {
                    let a = base + j * n as u32 + i;
                    let (b, c, d) = (a + 1, a + n as u32, a + n as u32 + 1);
                    indices.extend([a, b, d, a, d, c]);
                }
            }
        }
        let wall_triangles = indices.len() / 3;
        // The facade: four quads around the window, far enough to fill any view.
        let [w, h, _] = room.size;
        let big = 1.0e3;
        for (x0, y0, x1, y1) in [(-big, -big, big, 0.0), (-big, h, big, big), (-big, 0.0, 0.0, h), (w, 0.0, big, h)] {
            let base = vertices.len() as u32;
            for (x, y) in [(x0, y0), (x1, y0), (x0, y1), (x1, y1)] {
                vertices.push(Vertex { pos: [x, y, 0.0], normal: [0.0, 0.0, 1.0], color: [0.0; 3], wall: -1.0 });
            }
            indices.extend([base, base + 1, base + 3, base, base + 3, base + 2]);
        }
        RoomMesh { vertices, indices, wall_triangles }
    }
}

const SHADER: &str = r#"
struct U { view_proj: mat4x4<f32>, light: vec4<f32>, kind: vec4<f32>, clear: vec4<f32> };
@group(0) @binding(0) var<uniform> u: U;
struct VOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec3<f32>,
    @location(3) @interpolate(flat) wall: f32,
};
@vertex fn vs_mesh(@location(0) p: vec3<f32>, @location(1) n: vec3<f32>, @location(2) c: vec3<f32>, @location(3) w: f32) -> VOut {
    return VOut(u.view_proj * vec4<f32>(p, 1.0), p, n, c, w);
}
@fragment fn fs_mesh(i: VOut) -> @location(0) vec4<f32> {
    if (i.wall < -0.5) {
        return u.clear;
    }
    let l = select(normalize(u.light.xyz), normalize(u.light.xyz - i.world), u.kind.x > 0.5);
    let d = max(dot(normalize(i.normal), l), 0.0);
    let c = i.color * (u.light.w + (1.0 - u.light.w) * d);
    return vec4<f32>(c, (i.wall + 1.0) / 8.0);
}
"#;

/// The baseline's uniform block.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct MeshParams {
    view_proj: [f32; 16],
    light: [f32; 4],
    kind: [f32; 4],
    clear: [f32; 4],
}

/// Renders the baseline: `frames` timed frames after `warmup`, `size²`, with a depth buffer.
pub fn render_geometry(
    gpu: &Gpu,
    room: &Room,
    mesh: &RoomMesh,
    size: u32,
    warmup: u32,
    frames: u32,
) -> Result<Frames, GpuError> {
    let module = gpu.checked(|| {
        gpu.device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("room mesh"),
            source: wgpu::ShaderSource::Wgsl(SHADER.into()),
        })
    })?;
    let attrs = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x3, 3 => Float32];
    let buffers = [Some(wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<Vertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &attrs,
    })];
    let pipeline = render_pipeline(
        gpu,
        &module,
        &Draw {
            label: "room mesh",
            entries: ("vs_mesh", "fs_mesh"),
            buffers: &buffers,
            topology: wgpu::PrimitiveTopology::TriangleList,
            depth: Some(wgpu::CompareFunction::Less),
            format: crate::gpu::FORMAT,
            cull: None,
        },
    )?;
    let (l, kind) = match room.light {
        RoomLight::Point(p) => (p, 1.0),
        RoomLight::Directional(d) => (d.normalize(), 0.0),
    };
    let c = super::CLEAR;
    let params = MeshParams {
        view_proj: room.camera.view_proj(1.0).to_cols_array(),
        light: [l.x, l.y, l.z, room.ambient],
        kind: [kind, 0.0, 0.0, 0.0],
        // The pass's clear colour (linear, as wgpu's clear values are), alpha 0: no wall.
        clear: [c.r as f32, c.g as f32, c.b as f32, 0.0],
    };
    let pb = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("mesh params"),
        contents: bytemuck::bytes_of(&params),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let vb = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("mesh vertices"),
        contents: bytemuck::cast_slice(&mesh.vertices),
        usage: wgpu::BufferUsages::VERTEX,
    });
    let ib = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("mesh indices"),
        contents: bytemuck::cast_slice(&mesh.indices),
        usage: wgpu::BufferUsages::INDEX,
    });
    let bg = gpu.checked(|| {
        gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("room mesh"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: pb.as_entire_binding() }],
        })
    })?;
    let count = mesh.indices.len() as u32;
    timed_frames(gpu, size, true, super::CLEAR, warmup, frames, |pass| {
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bg, &[]);
        pass.set_vertex_buffer(0, vb.slice(..));
        pass.set_index_buffer(ib.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..count, 0, 0..1);
    })
}
