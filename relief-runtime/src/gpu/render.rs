//! The render entry on a quad, offscreen, timed with render-pass timestamp queries.

use super::{Gpu, GpuError, Program, SceneTextures};
use crate::scene::Scene;

/// Frame times and the last frame.
pub struct RenderResult {
    /// GPU time of each timed frame's render pass, in milliseconds.
    pub frame_ms: Vec<f64>,
    /// The last frame, RGBA8 (sRGB), row-major, `size × size`.
    pub rgba: Vec<u8>,
    /// Side of the square frame, in pixels.
    pub size: u32,
    /// The last frame's depth buffer (NDC depth, row-major, cleared to 1), when the program
    /// writes depth.
    pub depth: Option<Vec<f32>>,
}

/// The depth format of the timed renders.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// A `size²` render attachment that can be copied out (with [`Readback`]).
fn attachment(gpu: &Gpu, label: &str, size: u32, format: wgpu::TextureFormat) -> wgpu::Texture {
    gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d { width: size, height: size, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

/// The colour format of the timed renders.
pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// Renders `frames` timed frames (after `warmup` untimed ones) of `program` on `scene` at
/// `size × size` pixels.
pub fn render(
    gpu: &Gpu,
    program: &Program,
    scene: &Scene,
    tex: &SceneTextures,
    size: u32,
    warmup: u32,
    frames: u32,
) -> Result<RenderResult, GpuError> {
    if !gpu.timestamps {
        return Err(GpuError::Device(format!(
            "the adapter {} has no timestamp queries, so frames cannot be timed",
            gpu.adapter
        )));
    }
    let frames = frames.max(1);
    let module = program.shader_module(gpu)?;
    let pipeline = gpu.checked(|| {
        gpu.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("render"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState { topology: wgpu::PrimitiveTopology::TriangleStrip, ..Default::default() },
            depth_stencil: program.writes_depth.then(|| wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Always),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &[Some(FORMAT.into())],
            }),
            multiview_mask: None,
            cache: None,
        })
    })?;
    let params = SceneTextures::params(gpu, scene, 1.0, scene.camera.pixel_size(size));
    let bg = tex.bind_group(gpu, &pipeline.get_bind_group_layout(0), &program.render_bindings, &program.maps, program.map_levels, &params, &[])?;
    let clear = wgpu::Color { r: 0.02, g: 0.02, b: 0.03, a: 1.0 };
    let f = timed_frames(gpu, size, program.writes_depth, clear, warmup, frames, |pass| {
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bg, &[]);
        pass.draw(0..4, 0..1);
    })?;
    Ok(RenderResult { frame_ms: f.frame_ms, rgba: f.rgba, size, depth: f.depth })
}

/// A render pass into `view` cleared to `clear` (and `depth` cleared to 1), with `ts`.
fn begin_pass<'e>(
    enc: &'e mut wgpu::CommandEncoder,
    view: &wgpu::TextureView,
    depth: Option<&wgpu::TextureView>,
    clear: wgpu::Color,
    ts: Option<wgpu::RenderPassTimestampWrites<'_>>,
) -> wgpu::RenderPass<'e> {
    enc.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: None,
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations { load: wgpu::LoadOp::Clear(clear), store: wgpu::StoreOp::Store },
        })],
        depth_stencil_attachment: depth.map(|view| wgpu::RenderPassDepthStencilAttachment {
            view,
            depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
            stencil_ops: None,
        }),
        timestamp_writes: ts,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

/// One untimed frame into a `size²` RGBA8 target cleared to `clear` (and a `Depth32Float`
/// depth cleared to 1 `with_depth`), read back: for headless programs that draw with their
/// own pipelines (`examples/integrate.rs`). `draw` records the pass's pipeline, bind groups
/// and draw calls; [`Frames::frame_ms`] is empty.
pub fn draw_frame(gpu: &Gpu, size: u32, with_depth: bool, clear: wgpu::Color, draw: impl Fn(&mut wgpu::RenderPass<'_>)) -> Result<Frames, GpuError> {
    let target = attachment(gpu, "frame", size, FORMAT);
    let view = target.create_view(&Default::default());
    let depth_target = with_depth.then(|| attachment(gpu, "depth", size, DEPTH_FORMAT));
    let depth_view = depth_target.as_ref().map(|t| t.create_view(&Default::default()));
    let mut enc = gpu.device.create_command_encoder(&Default::default());
    draw(&mut begin_pass(&mut enc, &view, depth_view.as_ref(), clear, None));
    read_frame(gpu, enc, &target, depth_target.as_ref(), size, Vec::new())
}

/// Copies the frame (and its depth) out after the work recorded in `enc`.
fn read_frame(
    gpu: &Gpu,
    mut enc: wgpu::CommandEncoder,
    target: &wgpu::Texture,
    depth: Option<&wgpu::Texture>,
    size: u32,
    frame_ms: Vec<f64>,
) -> Result<Frames, GpuError> {
    let pixels = Readback::new(gpu, &mut enc, target, wgpu::TextureAspect::All, size);
    let depth_pixels = depth.map(|t| Readback::new(gpu, &mut enc, t, wgpu::TextureAspect::DepthOnly, size));
    gpu.queue.submit([enc.finish()]);
    let rgba = pixels.read(gpu)?;
    let depth = match depth_pixels {
        Some(d) => Some(bytemuck::pod_collect_to_vec::<u8, f32>(&d.read(gpu)?)),
        None => None,
    };
    Ok(Frames { frame_ms, rgba, depth })
}

/// Timed frames and the last one.
pub struct Frames {
    /// GPU time of each timed frame's render pass, ms (render-pass timestamps).
    pub frame_ms: Vec<f64>,
    /// The last frame, RGBA8 (sRGB), rows from the top.
    pub rgba: Vec<u8>,
    /// The last frame's depth buffer (NDC depth, cleared to 1), with `with_depth`.
    pub depth: Option<Vec<f32>>,
}

/// Renders `warmup` untimed then `frames` (at least 1) timed frames into a `size²` RGBA8
/// target cleared to `clear` (and a `Depth32Float` depth cleared to 1 `with_depth`), each
/// in its own submission so that frames do not overlap, timed by render-pass timestamps
/// (compute-pass timestamps are wrong on lavapipe); `draw` records the pass's pipeline,
/// bind groups and draw calls. `relief render` and the room's two renders use it.
pub fn timed_frames(
    gpu: &Gpu,
    size: u32,
    with_depth: bool,
    clear: wgpu::Color,
    warmup: u32,
    frames: u32,
    draw: impl Fn(&mut wgpu::RenderPass<'_>),
) -> Result<Frames, GpuError> {
    if !gpu.timestamps {
        return Err(GpuError::Device(format!("the adapter {} has no timestamp queries, so frames cannot be timed", gpu.adapter)));
    }
    let frames = frames.max(1);
    let target = attachment(gpu, "frame", size, FORMAT);
    let view = target.create_view(&Default::default());
    let depth_target = with_depth.then(|| attachment(gpu, "depth", size, DEPTH_FORMAT));
    let depth_view = depth_target.as_ref().map(|t| t.create_view(&Default::default()));
    let queries = gpu.device.create_query_set(&wgpu::QuerySetDescriptor { label: Some("frame times"), ty: wgpu::QueryType::Timestamp, count: 2 * frames });
    let buffer = |usage| gpu.device.create_buffer(&wgpu::BufferDescriptor { label: None, size: 16 * frames as u64, usage, mapped_at_creation: false });
    let resolve = buffer(wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC);
    let ts_read = buffer(wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST);
    let frame = |enc: &mut wgpu::CommandEncoder, timed: Option<u32>| {
        let ts = timed.map(|i| wgpu::RenderPassTimestampWrites {
            query_set: &queries,
            beginning_of_pass_write_index: Some(2 * i),
            end_of_pass_write_index: Some(2 * i + 1),
        });
        draw(&mut begin_pass(enc, &view, depth_view.as_ref(), clear, ts));
    };
    let mut enc = gpu.device.create_command_encoder(&Default::default());
    for _ in 0..warmup {
        frame(&mut enc, None);
    }
    gpu.queue.submit([enc.finish()]);
    gpu.wait()?;
    for i in 0..frames {
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        frame(&mut enc, Some(i));
        gpu.queue.submit([enc.finish()]);
        gpu.wait()?;
    }
    let mut enc = gpu.device.create_command_encoder(&Default::default());
    enc.resolve_query_set(&queries, 0..2 * frames, &resolve, 0);
    enc.copy_buffer_to_buffer(&resolve, 0, &ts_read, 0, 16 * frames as u64);
    gpu.queue.submit([enc.finish()]);
    let stamps: Vec<u64> = bytemuck::cast_slice(&gpu.read_buffer(&ts_read)?).to_vec();
    let period = gpu.queue.get_timestamp_period() as f64;
    let frame_ms = stamps.chunks(2).map(|p| p[1].saturating_sub(p[0]) as f64 * period / 1e6).collect();
    read_frame(gpu, gpu.device.create_command_encoder(&Default::default()), &target, depth_target.as_ref(), size, frame_ms)
}

/// A copy of a `size²` attachment of 4-byte texels (RGBA8, or one aspect such as a
/// `Depth32Float` depth) into a mappable buffer, rows padded to wgpu's 256-byte alignment.
struct Readback {
    buffer: wgpu::Buffer,
    row: u32,
    size: u32,
}

impl Readback {
    /// Records the copy of `texture`'s `aspect` into `enc`; submit `enc` before [`Readback::read`].
    fn new(gpu: &Gpu, enc: &mut wgpu::CommandEncoder, texture: &wgpu::Texture, aspect: wgpu::TextureAspect, size: u32) -> Readback {
        let row = (size * 4).div_ceil(256) * 256;
        let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size: (row * size) as u64,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        enc.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo { texture, mip_level: 0, origin: wgpu::Origin3d::ZERO, aspect },
            wgpu::TexelCopyBufferInfo {
                buffer: &buffer,
                layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(row), rows_per_image: Some(size) },
            },
            wgpu::Extent3d { width: size, height: size, depth_or_array_layers: 1 },
        );
        Readback { buffer, row, size }
    }

    /// The texels' bytes, rows unpadded, top row first.
    fn read(&self, gpu: &Gpu) -> Result<Vec<u8>, GpuError> {
        let padded = gpu.read_buffer(&self.buffer)?;
        let (row, width) = (self.row as usize, self.size as usize * 4);
        Ok((0..self.size as usize).flat_map(|y| padded[y * row..y * row + width].iter().copied()).collect())
    }
}
