//! The render entry on a quad, offscreen, timed with render-pass timestamp queries.

use super::{Gpu, GpuError, Program, SceneTextures};
use crate::scene::Scene;

/// Frame times and the last frame.
pub struct RenderResult {
    /// Mean GPU time per frame of each timed block of frames, in milliseconds (one value per
    /// frame where a frame lasts at least `MIN_BLOCK_MS`).
    pub frame_ms: Vec<f64>,
    /// The last frame, RGBA8 (sRGB), row-major, `size × size`.
    pub rgba: Vec<u8>,
    /// Side of the square frame, in pixels.
    pub size: u32,
    /// The last frame's depth buffer (NDC depth, row-major, cleared to 1), when the program
    /// writes depth.
    pub depth: Option<Vec<f32>>,
    /// Frames per timed block (`Clock::calibrate`).
    pub frames_per_block: u32,
    /// The timer's tick in nanoseconds (`wgpu::Queue::get_timestamp_period`).
    pub timestamp_period_ns: f64,
}

/// The depth format of the timed renders.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The colour format of the timed renders.
pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// A timed block lasts at least this long on the device: a 256² frame can take 20 µs on a
/// desktop GPU, near the timer's resolution, so fast frames are timed many to a block.
pub(crate) const MIN_BLOCK_MS: f64 = 2.0;

/// The most frames one block holds (a frame below the timer's resolution still ends).
pub const MAX_FRAMES_PER_BLOCK: u32 = 1 << 14;

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

/// What frames are drawn into: a `size²` RGBA8 colour attachment cleared to `clear` and,
/// `with_depth`, a `Depth32Float` depth cleared to 1.
pub(crate) struct Target {
    color: wgpu::Texture,
    /// Bytes per colour texel (4 for [`FORMAT`], 16 for the mesh probe's `Rgba32Float`).
    texel_bytes: u32,
    view: wgpu::TextureView,
    depth: Option<(wgpu::Texture, wgpu::TextureView)>,
    size: u32,
    clear: wgpu::Color,
}

impl Target {
    /// A new target (see the type's doc).
    pub(crate) fn new(gpu: &Gpu, size: u32, with_depth: bool, clear: wgpu::Color) -> Target {
        Target::with_format(gpu, size, with_depth, clear, FORMAT)
    }

    /// A new target whose colour has `format` (one of 4 or 16 bytes a texel).
    pub(crate) fn with_format(
        gpu: &Gpu,
        size: u32,
        with_depth: bool,
        clear: wgpu::Color,
        format: wgpu::TextureFormat,
    ) -> Target {
        let color = attachment(gpu, "frame", size, format);
        let texel_bytes = format.block_copy_size(None).unwrap_or(4);
        let view = color.create_view(&Default::default());
        let depth = with_depth.then(|| {
            let t = attachment(gpu, "depth", size, DEPTH_FORMAT);
            let v = t.create_view(&Default::default());
            (t, v)
        });
        Target { color, texel_bytes, view, depth, size, clear }
    }

    /// A render pass into the target, cleared, with `ts`.
    fn pass<'e>(
        &self,
        enc: &'e mut wgpu::CommandEncoder,
        ts: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) -> wgpu::RenderPass<'e> {
        enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: None,
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &self.view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations { load: wgpu::LoadOp::Clear(self.clear), store: wgpu::StoreOp::Store },
            })],
            depth_stencil_attachment: self.depth.as_ref().map(|(_, view)| wgpu::RenderPassDepthStencilAttachment {
                view,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            }),
            timestamp_writes: ts,
            occlusion_query_set: None,
            multiview_mask: None,
        })
    }

    /// `frames` untimed frames in one submission, waited for.
    pub(crate) fn untimed(
        &self,
        gpu: &Gpu,
        frames: u32,
        draw: &dyn Fn(&mut wgpu::RenderPass<'_>),
    ) -> Result<(), GpuError> {
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        for _ in 0..frames {
            draw(&mut self.pass(&mut enc, None));
        }
        gpu.queue.submit([enc.finish()]);
        gpu.wait()
    }

    /// The last frame drawn (and its depth), read back, with `frame_ms` as the frame times.
    pub(crate) fn read(&self, gpu: &Gpu, frame_ms: Vec<f64>) -> Result<Frames, GpuError> {
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        let pixels = Readback::new(gpu, &mut enc, &self.color, wgpu::TextureAspect::All, self.size, self.texel_bytes);
        let depth_pixels = self
            .depth
            .as_ref()
            .map(|(t, _)| Readback::new(gpu, &mut enc, t, wgpu::TextureAspect::DepthOnly, self.size, 4));
        gpu.queue.submit([enc.finish()]);
        let rgba = pixels.read(gpu)?;
        let depth = match depth_pixels {
            Some(d) => Some(bytemuck::pod_collect_to_vec::<u8, f32>(&d.read(gpu)?)),
            None => None,
        };
        Ok(Frames { frame_ms, rgba, depth, frames_per_block: 0, timestamp_period_ns: f64::NAN })
    }
}

/// The device's clock: render-pass timestamps around a block of frames (compute-pass
/// timestamps are wrong on lavapipe).
pub(crate) struct Clock {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    read: wgpu::Buffer,
    /// The timer's tick, ns (`wgpu::Queue::get_timestamp_period`).
    pub period_ns: f64,
}

impl Clock {
    /// A clock on `gpu`; an adapter without timestamp queries is an error.
    pub(crate) fn new(gpu: &Gpu) -> Result<Clock, GpuError> {
        if !gpu.timestamps {
            return Err(GpuError::Device(format!(
                "the adapter {} has no timestamp queries, so frames cannot be timed",
                gpu.adapter
            )));
        }
        let queries = gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("block time"),
            ty: wgpu::QueryType::Timestamp,
            count: 2,
        });
        let buffer = |usage| {
            gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: None,
                size: 16,
                usage,
                mapped_at_creation: false,
            })
        };
        Ok(Clock {
            queries,
            resolve: buffer(wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC),
            read: buffer(wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST),
            period_ns: gpu.queue.get_timestamp_period() as f64,
        })
    }

    /// One timed block: `frames` (at least 1) frames drawn into `target` in one submission,
    /// a timestamp at the beginning of the first pass and one at the end of the last; waits
    /// for it and returns the block's device time in milliseconds.
    pub(crate) fn block(
        &self,
        gpu: &Gpu,
        target: &Target,
        frames: u32,
        draw: &dyn Fn(&mut wgpu::RenderPass<'_>),
    ) -> Result<f64, GpuError> {
        let frames = frames.max(1);
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        for i in 0..frames {
            let (first, last) = (i == 0, i + 1 == frames);
            let ts = (first || last).then(|| wgpu::RenderPassTimestampWrites {
                query_set: &self.queries,
                beginning_of_pass_write_index: first.then_some(0),
                end_of_pass_write_index: last.then_some(1),
            });
            draw(&mut target.pass(&mut enc, ts));
        }
        enc.resolve_query_set(&self.queries, 0..2, &self.resolve, 0);
        enc.copy_buffer_to_buffer(&self.resolve, 0, &self.read, 0, 16);
        gpu.queue.submit([enc.finish()]);
        let stamps: Vec<u64> = bytemuck::pod_collect_to_vec(&gpu.read_buffer(&self.read)?);
        Ok(stamps[1].saturating_sub(stamps[0]) as f64 * self.period_ns / 1e6)
    }

    /// Frames per block such that a block lasts at least [`MIN_BLOCK_MS`] of device time:
    /// one-frame blocks are timed, then blocks growing by the shortfall (×2 at least, with a
    /// quarter to spare) until one lasts long enough, up to [`MAX_FRAMES_PER_BLOCK`]. The
    /// blocks timed here are warm-up: their times are dropped.
    pub(crate) fn calibrate(
        &self,
        gpu: &Gpu,
        target: &Target,
        draw: &dyn Fn(&mut wgpu::RenderPass<'_>),
    ) -> Result<u32, GpuError> {
        let mut k = 1u32;
        loop {
            let ms = self.block(gpu, target, k, draw)?;
            if ms >= MIN_BLOCK_MS || k >= MAX_FRAMES_PER_BLOCK {
                return Ok(k);
            }
            let grow = if ms > 0.0 { (1.25 * MIN_BLOCK_MS / ms * k as f64).ceil() as u32 } else { 16 * k };
            k = grow.max(2 * k).min(MAX_FRAMES_PER_BLOCK);
        }
    }
}

/// A pipeline ready to draw: its render pipeline and bind group on a scene, and its target.
pub(crate) struct Renderer {
    pub(crate) pipeline: wgpu::RenderPipeline,
    pub(crate) bind_group: wgpu::BindGroup,
    /// Where its frames go.
    pub target: Target,
    /// The vertex and index buffers of a mesh (`gpu::mesh`); `None` for relief's quad.
    pub(crate) mesh: Option<MeshBuffers>,
}

/// A mesh's vertex and index buffers on the device, and its index count.
pub(crate) struct MeshBuffers {
    pub(crate) vertices: wgpu::Buffer,
    pub(crate) indices: wgpu::Buffer,
    pub(crate) count: u32,
}

/// The background of the renders: linear RGBA, written to the sRGB target as
/// `(0.02, 0.02, 0.03)` encoded to sRGB bytes (`relief render`'s `metrics.json`, `shading`).
pub const CLEAR: wgpu::Color = wgpu::Color { r: 0.02, g: 0.02, b: 0.03, a: 1.0 };

/// How the render entry shades a pixel, as `relief render` writes it into `metrics.json`
/// (`shading.formula`), so that an engine can reproduce the frame: `n` the normal map's
/// texel at the hit (linear filtering) times 2 minus 1, normalized; `l` the scene's unit
/// direction toward the light (tangent space = world: the quad lies in z = 0, u along x,
/// v along y); `albedo` the albedo at the hit (an sRGB texture, linear filtering);
/// `shadow` the shadow stage's visibility (1 without one), `ao` the ao stage's factor (1
/// without one); the result goes to an `Rgba8UnormSrgb` target (linear → sRGB on write,
/// no tone mapping), alpha 1, over [`CLEAR`].
pub const SHADING_FORMULA: &str =
    "rgb = albedo * (ambient * ao + (1 - ambient) * max(dot(n, l), 0) * shadow); n = normalize(normal_texel * 2 - 1)";

/// What a render pipeline draws: relief's quad, the room's window quad, or a vertex-buffered
/// mesh. Every render pipeline of the runtime is made from one of these by [`render_pipeline`],
/// into [`FORMAT`] (and [`DEPTH_FORMAT`] when `depth` is set), culling what `cull` says.
pub(crate) struct Draw<'a> {
    /// The pipeline's label.
    pub label: &'a str,
    /// The vertex and fragment entry points.
    pub entries: (&'a str, &'a str),
    /// The vertex buffers (none for the generated quads, which make their corners from the
    /// vertex index).
    pub buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
    /// Strip for the quads, list for meshes.
    pub topology: wgpu::PrimitiveTopology,
    /// The depth test, when the pass has a depth buffer (depth is then written).
    pub depth: Option<wgpu::CompareFunction>,
    /// The colour target's format: [`FORMAT`] for pictures, `Rgba32Float` for the mesh probe.
    pub format: wgpu::TextureFormat,
    /// The faces culled (counter-clockwise front faces): `None` but for a `curved=prism` mesh,
    /// whose prisms are wound outward and whose every face traces the same exact entry and
    /// exit, so that only the faces toward the eye need run.
    pub cull: Option<wgpu::Face>,
}

/// The render pipeline of `draw` over `module`, its bind group layout derived from the module.
pub(crate) fn render_pipeline(
    gpu: &Gpu,
    module: &wgpu::ShaderModule,
    draw: &Draw<'_>,
) -> Result<wgpu::RenderPipeline, GpuError> {
    gpu.checked(|| {
        gpu.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(draw.label),
            layout: None,
            vertex: wgpu::VertexState {
                module,
                entry_point: Some(draw.entries.0),
                compilation_options: Default::default(),
                buffers: draw.buffers,
            },
            primitive: wgpu::PrimitiveState {
                topology: draw.topology,
                front_face: wgpu::FrontFace::Ccw,
                cull_mode: draw.cull,
                ..Default::default()
            },
            depth_stencil: draw.depth.map(|compare| wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(compare),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module,
                entry_point: Some(draw.entries.1),
                compilation_options: Default::default(),
                targets: &[Some(draw.format.into())],
            }),
            multiview_mask: None,
            cache: None,
        })
    })
}

impl Renderer {
    /// `program`'s render entry on `scene` (its textures and maps already in `tex`) at
    /// `size × size` pixels.
    pub(crate) fn new(
        gpu: &Gpu,
        program: &Program,
        scene: &Scene,
        tex: &SceneTextures,
        size: u32,
    ) -> Result<Renderer, GpuError> {
        let module = program.shader_module(gpu)?;
        let pipeline = render_pipeline(
            gpu,
            &module,
            &Draw {
                label: "render",
                entries: ("vs_main", "fs_main"),
                buffers: &[],
                topology: wgpu::PrimitiveTopology::TriangleStrip,
                // The render entry writes the hit's depth itself: every fragment is kept.
                depth: program.writes_depth.then_some(wgpu::CompareFunction::Always),
                format: FORMAT,
                cull: None,
            },
        )?;
        let params = SceneTextures::params(gpu, scene, 1.0, scene.camera.pixel_size(size));
        let bind_group =
            tex.bind_group(gpu, &pipeline.get_bind_group_layout(0), &program.render_bindings, program, &params, &[])?;
        Ok(Renderer { pipeline, bind_group, target: Target::new(gpu, size, program.writes_depth, CLEAR), mesh: None })
    }

    /// Records one frame's draw into `pass`: the quad, or the mesh's indexed triangles.
    pub(crate) fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.bind_group, &[]);
        match &self.mesh {
            None => pass.draw(0..4, 0..1),
            Some(m) => {
                pass.set_vertex_buffer(0, m.vertices.slice(..));
                pass.set_index_buffer(m.indices.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..m.count, 0, 0..1);
            }
        }
    }
}

/// Renders `frames` timed frames (after `warmup` untimed ones) of `program` on `scene` at
/// `size × size` pixels, in blocks of at least `MIN_BLOCK_MS` (`timed_frames`).
pub fn render(
    gpu: &Gpu,
    program: &Program,
    scene: &Scene,
    tex: &SceneTextures,
    size: u32,
    warmup: u32,
    frames: u32,
) -> Result<RenderResult, GpuError> {
    let clock = Clock::new(gpu)?;
    let r = Renderer::new(gpu, program, scene, tex, size)?;
    let f = time_frames(gpu, &clock, &r.target, warmup, frames, &|pass| r.draw(pass))?;
    Ok(RenderResult {
        frame_ms: f.frame_ms,
        rgba: f.rgba,
        size,
        depth: f.depth,
        frames_per_block: f.frames_per_block,
        timestamp_period_ns: f.timestamp_period_ns,
    })
}

/// One untimed headless frame into a `size²` RGBA8 target cleared to `clear` (and a `Depth32Float`
/// depth cleared to 1 `with_depth`), read back: for headless programs that draw with their
/// own pipelines (`examples/integrate.rs`). `draw` records the pass's pipeline, bind groups
/// and draw calls; [`Frames::frame_ms`] is empty.
pub fn draw_frame(
    gpu: &Gpu,
    size: u32,
    with_depth: bool,
    clear: wgpu::Color,
    draw: impl Fn(&mut wgpu::RenderPass<'_>),
) -> Result<Frames, GpuError> {
    let target = Target::new(gpu, size, with_depth, clear);
    target.untimed(gpu, 1, &draw)?;
    target.read(gpu, Vec::new())
}

/// Timed frames and the last one.
pub struct Frames {
    /// Mean GPU time per frame of each timed block, ms (render-pass timestamps): one value
    /// per frame when a frame lasts at least `MIN_BLOCK_MS`.
    pub frame_ms: Vec<f64>,
    /// The last frame, RGBA8 (sRGB), rows from the top.
    pub rgba: Vec<u8>,
    /// The last frame's depth buffer (NDC depth, cleared to 1), with `with_depth`.
    pub depth: Option<Vec<f32>>,
    /// Frames per timed block (0 for an untimed frame).
    pub frames_per_block: u32,
    /// The timer's tick in nanoseconds (NaN for an untimed frame).
    pub timestamp_period_ns: f64,
}

/// Renders `warmup` untimed frames, then times about `frames` (at least 1) frames into a
/// `size²` RGBA8 target cleared to `clear` (and a `Depth32Float` depth cleared to 1
/// `with_depth`): in blocks of as many frames as make a block last at least
/// [`MIN_BLOCK_MS`] ([`Clock::calibrate`], whose blocks are dropped as warm-up), each block
/// in its own submission so that blocks do not overlap, timed by render-pass timestamps
/// (compute-pass timestamps are wrong on lavapipe). `frames / k` blocks (at least one) are
/// timed, one frame time per block. `draw` records the pass's pipeline, bind groups and draw
/// calls. `relief render` and the room's two renders use it.
pub(crate) fn timed_frames(
    gpu: &Gpu,
    size: u32,
    with_depth: bool,
    clear: wgpu::Color,
    warmup: u32,
    frames: u32,
    draw: impl Fn(&mut wgpu::RenderPass<'_>),
) -> Result<Frames, GpuError> {
    let clock = Clock::new(gpu)?;
    let target = Target::new(gpu, size, with_depth, clear);
    time_frames(gpu, &clock, &target, warmup, frames, &draw)
}

fn time_frames(
    gpu: &Gpu,
    clock: &Clock,
    target: &Target,
    warmup: u32,
    frames: u32,
    draw: &dyn Fn(&mut wgpu::RenderPass<'_>),
) -> Result<Frames, GpuError> {
    target.untimed(gpu, warmup, draw)?;
    let k = clock.calibrate(gpu, target, draw)?;
    let blocks = (frames.max(1) / k).max(1);
    let mut frame_ms = Vec::with_capacity(blocks as usize);
    for _ in 0..blocks {
        frame_ms.push(clock.block(gpu, target, k, draw)? / k as f64);
    }
    let mut f = target.read(gpu, frame_ms)?;
    f.frames_per_block = k;
    f.timestamp_period_ns = clock.period_ns;
    Ok(f)
}

/// Block times of two pipelines timed alternately (`paired_blocks`).
#[derive(Clone, Debug, Default)]
pub struct PairedBlocks {
    /// Mean frame time (ms) of each of A's timed blocks, pair order.
    pub a_ms: Vec<f64>,
    /// Mean frame time (ms) of each of B's timed blocks, pair order.
    pub b_ms: Vec<f64>,
    /// Frames per block of A and of B.
    pub frames_per_block: [u32; 2],
    /// The timer's tick, ns.
    pub timestamp_period_ns: f64,
}

impl PairedBlocks {
    /// The ratio of A's to B's mean frame time with its 95 % interval
    /// (`crate::timing::paired_ratio`).
    pub fn ratio(&self) -> crate::timing::Ratio {
        crate::timing::paired_ratio(&self.a_ms, &self.b_ms)
    }
}

/// Times renderers A and B in alternating blocks: `pairs` pairs, A B in even pairs and B A
/// in odd ones, so that a steady drift falls on both alike (`crate::timing`). Each block
/// holds `frames_per_block` frames of its pipeline (calibrate them with [`Clock::calibrate`]:
/// those blocks are the warm-up, dropped); one more untimed block of each is drawn first.
pub(crate) fn paired_blocks(
    gpu: &Gpu,
    clock: &Clock,
    a: &Renderer,
    b: &Renderer,
    frames_per_block: [u32; 2],
    pairs: u32,
) -> Result<PairedBlocks, GpuError> {
    let side = [a, b];
    let draws: [&dyn Fn(&mut wgpu::RenderPass<'_>); 2] = [&|p| a.draw(p), &|p| b.draw(p)];
    for i in 0..2 {
        side[i].target.untimed(gpu, frames_per_block[i], draws[i])?;
    }
    let mut out = PairedBlocks { frames_per_block, timestamp_period_ns: clock.period_ns, ..Default::default() };
    for pair in 0..pairs {
        let order = if pair % 2 == 0 { [0, 1] } else { [1, 0] };
        for i in order {
            let k = frames_per_block[i].max(1);
            let ms = clock.block(gpu, &side[i].target, k, draws[i])? / k as f64;
            if i == 0 {
                out.a_ms.push(ms)
            } else {
                out.b_ms.push(ms)
            }
        }
    }
    Ok(out)
}

/// A copy of a `size²` attachment (RGBA8, `Rgba32Float`, or one aspect such as a
/// `Depth32Float` depth) into a mappable buffer, rows padded to wgpu's 256-byte alignment.
struct Readback {
    buffer: wgpu::Buffer,
    row: u32,
    size: u32,
    texel_bytes: u32,
}

impl Readback {
    /// Records the copy of `texture`'s `aspect` into `enc`; submit `enc` before [`Readback::read`].
    fn new(
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        texture: &wgpu::Texture,
        aspect: wgpu::TextureAspect,
        size: u32,
        texel_bytes: u32,
    ) -> Readback {
        let row = (size * texel_bytes).div_ceil(256) * 256;
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
        Readback { buffer, row, size, texel_bytes }
    }

    /// The texels' bytes, rows unpadded, top row first.
    fn read(&self, gpu: &Gpu) -> Result<Vec<u8>, GpuError> {
        let padded = gpu.read_buffer(&self.buffer)?;
        let (row, width) = (self.row as usize, (self.size * self.texel_bytes) as usize);
        Ok((0..self.size as usize).flat_map(|y| padded[y * row..y * row + width].iter().copied()).collect())
    }
}
