//! The room module ([`relief_dsl::compose::interior`]) on the device: every wall's
//! textures, the timed interior frames (`vs_room` + `fs_room` on the window quad) and the
//! room probe (`probe_room`).

use relief_dsl::abi::Params;
use relief_dsl::compose::interior::{compile_room, RoomOptions, RoomParams, ROOM_HITS, ROOM_RAYS};
use relief_dsl::ir::{Bindings, Filter, Image, Resource};
use relief_dsl::spec::MapReq;
use relief_dsl::{CompileError, Pipeline};
use wgpu::util::DeviceExt;

use super::{Room, RoomHit, RoomLight, RoomRay, WALLS};
use crate::gpu::{render_pipeline, timed_frames, Draw, Frames};
use crate::gpu::{Gpu, GpuError, MapKey, SceneTextures};

/// A pipeline compiled as a room module, with the bindings each entry reads.
pub struct RoomProgram {
    /// The pipeline.
    pub pipeline: Pipeline,
    /// The WGSL the device loads.
    pub wgsl: String,
    /// Bindings `vs_room` + `fs_room` read.
    pub render_bindings: Vec<u32>,
    /// Bindings `probe_room` reads.
    pub probe_bindings: Vec<u32>,
    /// What each binding of the module holds (each wall's textures name their wall).
    pub bindings: Bindings,
    /// The maps the pipeline reads (built per wall).
    pub maps: Vec<MapReq>,
}

impl RoomProgram {
    /// Compiles `p` as a room module (no light scattering).
    pub fn new(p: &Pipeline) -> Result<RoomProgram, CompileError> {
        Self::new_with(p, &RoomOptions::default())
    }

    /// Compiles `p` as a room module with `options` (e.g. light scattering).
    pub(crate) fn new_with(p: &Pipeline, options: &RoomOptions) -> Result<RoomProgram, CompileError> {
        let c = &compile_room(p, options)?;
        let wgsl = relief_dsl::emit::wgsl(c)?;
        // The fragment entry's bind group also serves its vertex entry.
        let used = |name: &str| match name {
            "fs_room" => crate::gpu::used_bindings(c, &["vs_room", "fs_room"]),
            other => crate::gpu::used_bindings(c, &[other]),
        };
        Ok(RoomProgram {
            pipeline: p.clone(),
            wgsl,
            render_bindings: used("fs_room"),
            probe_bindings: used("probe_room"),
            bindings: c.bindings.clone(),
            maps: p.required_maps(),
        })
    }

    fn shader(&self, gpu: &Gpu) -> Result<wgpu::ShaderModule, GpuError> {
        gpu.checked(|| {
            gpu.device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("room"),
                source: wgpu::ShaderSource::Wgsl(self.wgsl.as_str().into()),
            })
        })
    }
}

/// Every wall's textures on the device (each wall as a scene with edge mode clamp,
/// `Room::wall_scene`), and the window's opacity.
pub struct RoomTextures {
    /// Per wall, in [`super::WALL_NAMES`] order.
    pub walls: Vec<SceneTextures>,
    /// The window's opacity map (1×1 clear when the room has none).
    pub window: wgpu::TextureView,
}

impl RoomTextures {
    /// Uploads every wall's maps and the acceleration maps in `maps`.
    pub fn new(gpu: &Gpu, room: &Room, maps: &[MapReq]) -> Result<RoomTextures, crate::maps::MapError> {
        let mut walls = Vec::new();
        for k in 0..WALLS {
            let scene = room.wall_scene(k);
            let mut t = SceneTextures::new(gpu, &scene);
            t.add_maps(gpu, &scene, maps)?;
            walls.push(t);
        }
        let (w, h, data) = match &room.window {
            Some(m) => (m.width, m.height, m.data.clone()),
            None => (1, 1, vec![0.0]),
        };
        let tex = gpu.device.create_texture_with_data(
            &gpu.queue,
            &wgpu::TextureDescriptor {
                label: Some("window"),
                size: wgpu::Extent3d { width: w as u32, height: h as u32, depth_or_array_layers: 1 },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::R8Unorm,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            &data.iter().map(|x| (x.clamp(0.0, 1.0) * 255.0).round() as u8).collect::<Vec<u8>>(),
        );
        Ok(RoomTextures { walls, window: tex.create_view(&Default::default()) })
    }
}

/// The `Params` and [`RoomParams`] blocks of a room seen at `aspect`.
pub(crate) fn room_params(room: &Room, aspect: f32) -> (Params, RoomParams) {
    let c = room.camera.position;
    let (l, kind) = match room.light {
        RoomLight::Point(p) => (p, 1.0),
        RoomLight::Directional(d) => (d.normalize(), 0.0),
    };
    let d: Vec<f32> = room.walls.iter().map(|w| w.depth_scale).collect();
    let params = Params {
        view_proj: room.camera.view_proj(aspect).to_cols_array(),
        camera: [c.x, c.y, c.z, 0.0],
        light: [l.x, l.y, l.z, room.ambient],
        quad: [1.0, 1.0, 0.0, 0.0],
        // The room entries sample level 0 (a room refuses lod other than zero).
        pixel_right: [0.0; 4],
        pixel_up: [0.0; 4],
    };
    let window = if room.window.is_some() { 1.0 } else { 0.0 };
    let rp = RoomParams {
        size: [room.size[0], room.size[1], room.size[2], window],
        depth_a: [d[0], d[1], d[2], d[3]],
        depth_b: [d[4], kind, 0.0, 0.0],
        sun: [room.sun.x, room.sun.y, room.sun.z, room.sun_intensity],
    };
    (params, rp)
}

fn uniform(gpu: &Gpu, label: &str, bytes: &[u8]) -> wgpu::Buffer {
    gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytes,
        usage: wgpu::BufferUsages::UNIFORM,
    })
}

fn map_view(t: &SceneTextures, req: MapReq, b: u32) -> Result<&wgpu::TextureView, GpuError> {
    MapKey::of(req)
        .and_then(|k| t.maps.get(&k))
        .ok_or_else(|| GpuError::Pipeline(format!("the map at binding {b} was not built")))
}

/// The view of a room module's texture at binding `b`: the window's, or wall `wall`'s image.
fn room_texture(tex: &RoomTextures, image: Image, wall: Option<u32>, b: u32) -> Result<&wgpu::TextureView, GpuError> {
    if image == Image::Window {
        return Ok(&tex.window);
    }
    let Some(k) = wall else {
        return Err(GpuError::Pipeline(format!(
            "the room shader reads a texture at binding {b} that belongs to no wall"
        )));
    };
    let t = tex.walls.get(k as usize).ok_or_else(|| {
        GpuError::Pipeline(format!("the room shader reads wall {k}'s texture; a room has {WALLS} walls"))
    })?;
    Ok(match image {
        Image::Height => &t.height,
        Image::Normal => &t.normal,
        Image::Albedo => &t.albedo,
        Image::Map(req) => map_view(t, req, b)?,
        Image::Window => &tex.window,
    })
}

/// A bind group with exactly `bindings` of `prog`, each bound by what the module's binding
/// table says it holds: a wall's texture from that wall's textures, the shared samplers and
/// blocks, the window, the buffers given.
#[allow(clippy::too_many_arguments)]
fn bind_group(
    gpu: &Gpu,
    layout: &wgpu::BindGroupLayout,
    bindings: &[u32],
    prog: &RoomProgram,
    tex: &RoomTextures,
    params: &wgpu::Buffer,
    room: &wgpu::Buffer,
    storage: &[(u32, &wgpu::Buffer)],
) -> Result<wgpu::BindGroup, GpuError> {
    let mut entries = Vec::new();
    let shared = &tex.walls[0];
    for &b in bindings {
        let resource = match crate::gpu::resource_at(&prog.bindings, b)? {
            Resource::Texture { image, wall, .. } => {
                wgpu::BindingResource::TextureView(room_texture(tex, image, wall, b)?)
            }
            Resource::Params => params.as_entire_binding(),
            Resource::RoomParams => room.as_entire_binding(),
            Resource::Sampler(Filter::Linear) => wgpu::BindingResource::Sampler(&shared.linear),
            Resource::Sampler(Filter::Nearest) => wgpu::BindingResource::Sampler(&shared.nearest),
            Resource::Rays | Resource::Hits | Resource::PrismCells => match storage.iter().find(|(n, _)| *n == b) {
                Some((_, buf)) => buf.as_entire_binding(),
                None => {
                    return Err(GpuError::Pipeline(format!(
                        "the room shader reads binding {b}, a buffer this call does not provide"
                    )))
                }
            },
        };
        entries.push(wgpu::BindGroupEntry { binding: b, resource });
    }
    gpu.checked(|| {
        gpu.device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("room"), layout, entries: &entries })
    })
}

/// Renders the room with interior mapping: `frames` timed frames after `warmup`, `size²`.
pub(crate) fn render_interior(
    gpu: &Gpu,
    prog: &RoomProgram,
    room: &Room,
    tex: &RoomTextures,
    size: u32,
    warmup: u32,
    frames: u32,
) -> Result<Frames, GpuError> {
    let module = prog.shader(gpu)?;
    let pipeline = render_pipeline(
        gpu,
        &module,
        &Draw {
            label: "room interior",
            entries: ("vs_room", "fs_room"),
            buffers: &[],
            topology: wgpu::PrimitiveTopology::TriangleStrip,
            depth: None,
            format: crate::gpu::FORMAT,
            cull: None,
        },
    )?;
    let (p, r) = room_params(room, 1.0);
    let pb = uniform(gpu, "params", bytemuck::bytes_of(&p));
    let rb = uniform(gpu, "room", bytemuck::bytes_of(&r));
    let bg = bind_group(gpu, &pipeline.get_bind_group_layout(0), &prog.render_bindings, prog, tex, &pb, &rb, &[])?;
    timed_frames(gpu, size, false, super::CLEAR, warmup, frames, |pass| {
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bg, &[]);
        pass.draw(0..4, 0..1);
    })
}

/// Runs `probe_room` on `rays`: per ray the wall met and the hit in its tangent space.
pub fn probe_room(
    gpu: &Gpu,
    prog: &RoomProgram,
    room: &Room,
    tex: &RoomTextures,
    rays: &[RoomRay],
) -> Result<Vec<RoomHit>, GpuError> {
    if rays.is_empty() {
        return Ok(vec![]);
    }
    let module = prog.shader(gpu)?;
    let (p, r) = room_params(room, 1.0);
    let pb = uniform(gpu, "params", bytemuck::bytes_of(&p));
    let rb = uniform(gpu, "room", bytemuck::bytes_of(&r));
    crate::gpu::dispatch(gpu, &module, "probe_room", rays, |layout, ray_buf, hit_buf| {
        bind_group(
            gpu,
            layout,
            &prog.probe_bindings,
            prog,
            tex,
            &pb,
            &rb,
            &[(ROOM_RAYS, ray_buf), (ROOM_HITS, hit_buf)],
        )
    })
}
