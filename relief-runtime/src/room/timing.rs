//! Timed offscreen frames for the room's two renders, with render-pass timestamp queries
//! (as `relief render` times its frames; DESIGN.md: compute-pass timestamps are wrong on
//! lavapipe), and the read-back of the last frame.

use crate::gpu::{Gpu, GpuError};

/// The colour format of both renders.
pub(crate) const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// The depth format of the geometry baseline.
pub(crate) const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// The clear colour (outside the window).
pub(crate) const CLEAR: wgpu::Color = wgpu::Color { r: 0.02, g: 0.02, b: 0.03, a: 0.0 };

/// Frame times and the last frame.
pub struct Frames {
    /// GPU time of each timed frame's render pass, ms.
    pub frame_ms: Vec<f64>,
    /// The last frame, RGBA8, rows from the top.
    pub rgba: Vec<u8>,
    /// The last frame's depth buffer, when the render has one.
    pub depth: Option<Vec<f32>>,
}

fn attachment(gpu: &Gpu, size: u32, format: wgpu::TextureFormat) -> wgpu::Texture {
    gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("room frame"),
        size: wgpu::Extent3d { width: size, height: size, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

/// Copies a `size²` texture of 4-byte texels out, rows unpadded.
fn read_texture(gpu: &Gpu, texture: &wgpu::Texture, aspect: wgpu::TextureAspect, size: u32) -> Result<Vec<u8>, GpuError> {
    let row = (size * 4).div_ceil(256) * 256;
    let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: (row * size) as u64,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut enc = gpu.device.create_command_encoder(&Default::default());
    enc.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo { texture, mip_level: 0, origin: wgpu::Origin3d::ZERO, aspect },
        wgpu::TexelCopyBufferInfo { buffer: &buffer, layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(row), rows_per_image: Some(size) } },
        wgpu::Extent3d { width: size, height: size, depth_or_array_layers: 1 },
    );
    gpu.queue.submit([enc.finish()]);
    let padded = gpu.read_buffer(&buffer)?;
    let (row, width) = (row as usize, size as usize * 4);
    Ok((0..size as usize).flat_map(|y| padded[y * row..y * row + width].iter().copied()).collect())
}

/// Renders `warmup` untimed then `frames` timed frames of `size²`, each in its own
/// submission; `draw` records the pass's pipeline, bind group and draw calls.
pub(crate) fn timed(
    gpu: &Gpu,
    size: u32,
    with_depth: bool,
    warmup: u32,
    frames: u32,
    draw: impl Fn(&mut wgpu::RenderPass<'_>),
) -> Result<Frames, GpuError> {
    if !gpu.timestamps {
        return Err(GpuError::Device(format!("the adapter {} has no timestamp queries, so frames cannot be timed", gpu.adapter)));
    }
    let frames = frames.max(1);
    let target = attachment(gpu, size, FORMAT);
    let view = target.create_view(&Default::default());
    let depth = with_depth.then(|| attachment(gpu, size, DEPTH_FORMAT));
    let depth_view = depth.as_ref().map(|t| t.create_view(&Default::default()));
    let queries = gpu.device.create_query_set(&wgpu::QuerySetDescriptor { label: Some("room frame times"), ty: wgpu::QueryType::Timestamp, count: 2 * frames });
    let bytes = 16 * frames as u64;
    let resolve = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: bytes,
        usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let read = gpu.device.create_buffer(&wgpu::BufferDescriptor { label: None, size: bytes, usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST, mapped_at_creation: false });
    let frame = |enc: &mut wgpu::CommandEncoder, timed: Option<u32>| {
        let ts = timed.map(|i| wgpu::RenderPassTimestampWrites { query_set: &queries, beginning_of_pass_write_index: Some(2 * i), end_of_pass_write_index: Some(2 * i + 1) });
        let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: None,
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations { load: wgpu::LoadOp::Clear(CLEAR), store: wgpu::StoreOp::Store },
            })],
            depth_stencil_attachment: depth_view.as_ref().map(|view| wgpu::RenderPassDepthStencilAttachment {
                view,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            }),
            timestamp_writes: ts,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        draw(&mut pass);
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
    enc.copy_buffer_to_buffer(&resolve, 0, &read, 0, bytes);
    gpu.queue.submit([enc.finish()]);
    let stamps: Vec<u64> = bytemuck::cast_slice(&gpu.read_buffer(&read)?).to_vec();
    let period = gpu.queue.get_timestamp_period() as f64;
    let frame_ms = stamps.chunks(2).map(|p| p[1].saturating_sub(p[0]) as f64 * period / 1e6).collect();
    let rgba = read_texture(gpu, &target, wgpu::TextureAspect::All, size)?;
    let depth = match &depth {
        Some(t) => Some(bytemuck::pod_collect_to_vec::<u8, f32>(&read_texture(gpu, t, wgpu::TextureAspect::DepthOnly, size)?)),
        None => None,
    };
    Ok(Frames { frame_ms, rgba, depth })
}
