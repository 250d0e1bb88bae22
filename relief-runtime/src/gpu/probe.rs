//! The probe: the generated compute entry over rays made on the CPU.

use relief_dsl::abi::{binding, PROBE_WORKGROUP};
use wgpu::util::DeviceExt;

use super::{Gpu, GpuError, Program, SceneTextures};
use crate::scene::{ProbeRay, Scene};

/// One hit as the probe reports it: the shader ABI's record ([`relief_dsl::abi::ProbeHit`]).
pub type GpuHit = relief_dsl::abi::ProbeHit;

/// Runs the probe entry of `program` on `rays`; one hit per ray, in order.
pub fn probe(
    gpu: &Gpu,
    program: &Program,
    scene: &Scene,
    tex: &SceneTextures,
    rays: &[ProbeRay],
) -> Result<Vec<GpuHit>, GpuError> {
    if rays.is_empty() {
        return Ok(vec![]);
    }
    let module = program.shader_module(gpu)?;
    let params = SceneTextures::params(gpu, scene, 1.0, 0.0);
    dispatch(gpu, &module, "probe", rays, |layout, ray_buf, hit_buf| {
        tex.bind_group(
            gpu,
            layout,
            &program.probe_bindings,
            program,
            &params,
            &[(binding::RAYS, ray_buf), (binding::HITS, hit_buf)],
        )
    })
}

/// Runs the compute entry `entry` of `module` once per ray of `rays` (one thread each, in
/// workgroups of [`PROBE_WORKGROUP`]) and reads back one `H` per ray, in order: the probe of
/// the plain module and the room's. `bind` makes the entry's bind group from its layout, the
/// rays' storage buffer and the hits' storage buffer.
pub(crate) fn dispatch<R: bytemuck::Pod, H: bytemuck::Pod>(
    gpu: &Gpu,
    module: &wgpu::ShaderModule,
    entry: &str,
    rays: &[R],
    bind: impl FnOnce(&wgpu::BindGroupLayout, &wgpu::Buffer, &wgpu::Buffer) -> Result<wgpu::BindGroup, GpuError>,
) -> Result<Vec<H>, GpuError> {
    if rays.is_empty() {
        return Ok(vec![]);
    }
    let groups = (rays.len() as u32).div_ceil(PROBE_WORKGROUP);
    // One dispatch stays within the 65535 workgroups a dimension allows.
    if groups > 65535 {
        return Err(GpuError::Device(format!("{} rays are more than one probe dispatch takes", rays.len())));
    }
    let pipeline = gpu.checked(|| {
        gpu.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry),
            layout: None,
            module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        })
    })?;
    let ray_buf = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("rays"),
        contents: bytemuck::cast_slice(rays),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let size = rays.len() as u64 * std::mem::size_of::<H>() as u64;
    let hit_buf = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("hits"),
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let readback = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("hits readback"),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let bg = bind(&pipeline.get_bind_group_layout(0), &ray_buf, &hit_buf)?;
    let mut enc = gpu.device.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bg, &[]);
        pass.dispatch_workgroups(groups, 1, 1);
    }
    enc.copy_buffer_to_buffer(&hit_buf, 0, &readback, 0, size);
    gpu.queue.submit([enc.finish()]);
    let bytes = gpu.read_buffer(&readback)?;
    Ok(bytemuck::cast_slice(&bytes).to_vec())
}
