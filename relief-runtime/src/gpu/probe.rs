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
    let pipeline = gpu.checked(|| {
        gpu.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("probe"),
            layout: None,
            module: &module,
            entry_point: Some("probe"),
            compilation_options: Default::default(),
            cache: None,
        })
    })?;
    let ray_buf = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("rays"),
        contents: bytemuck::cast_slice(rays),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let size = rays.len() as u64 * std::mem::size_of::<GpuHit>() as u64;
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
    let params = SceneTextures::params(gpu, scene, 1.0, 0.0);
    let bg = tex.bind_group(
        gpu,
        &pipeline.get_bind_group_layout(0),
        &program.probe_bindings,
        program,
        &params,
        &[(binding::RAYS, &ray_buf), (binding::HITS, &hit_buf)],
    )?;
    let mut enc = gpu.device.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bg, &[]);
        let groups = (rays.len() as u32).div_ceil(PROBE_WORKGROUP);
        // Stay within the 65535 workgroups per dimension limit.
        let (gx, gy) = (groups.min(65535), groups.div_ceil(65535));
        if gy > 1 {
            return Err(GpuError::Device(format!("{} rays are more than one probe dispatch takes", rays.len())));
        }
        pass.dispatch_workgroups(gx, 1, 1);
    }
    enc.copy_buffer_to_buffer(&hit_buf, 0, &readback, 0, size);
    gpu.queue.submit([enc.finish()]);
    let bytes = gpu.read_buffer(&readback)?;
    Ok(bytemuck::cast_slice(&bytes).to_vec())
}
