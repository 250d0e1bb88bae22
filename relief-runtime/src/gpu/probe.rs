//! The probe: the generated compute entry over rays made on the CPU.

use relief_dsl::compose::{binding, PROBE_HIT_SIZE, PROBE_WORKGROUP};
use wgpu::util::DeviceExt;

use super::{Gpu, GpuError, Program, SceneTextures};
use crate::scene::{ProbeRay, Scene};

/// One hit as the probe reports it (the layout of the shader's `ProbeHit`): the search's raw
/// result, never clamped.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GpuHit {
    pub t: f32,
    pub u: f32,
    pub v: f32,
    pub z: f32,
    /// Loop passes of the coarse stage.
    pub coarse_steps: u32,
    /// Loop passes of the refine stage.
    pub refine_steps: u32,
    /// Texture samples over both stages.
    pub fetches: u32,
    /// 1 when the coarse search found the surface; 0 when it ran out of steps (the hit is
    /// then the last point it knew to be above the surface).
    pub converged: u32,
}

impl GpuHit {
    /// Loop passes over both stages.
    pub fn iterations(&self) -> u32 {
        self.coarse_steps + self.refine_steps
    }
    /// Whether every field of the position is finite.
    pub fn is_finite(&self) -> bool {
        [self.t, self.u, self.v, self.z].iter().all(|x| x.is_finite())
    }
    /// Whether the raw hit lies outside the volume: the ray's height at the hit's t,
    /// `1 + t·dir.z`, above the polygon (t < 0) or below the floor, by more than
    /// [`OUTSIDE_TOLERANCE`]. A NaN t is not outside (it is counted as NaN).
    pub fn outside(&self, ray: &crate::scene::ProbeRay) -> bool {
        let z = 1.0 + self.t as f64 * ray.dir[2] as f64;
        z > 1.0 + OUTSIDE_TOLERANCE || z < -OUTSIDE_TOLERANCE
    }
}

/// How far (in height) a hit may lie outside the volume and still count as inside: the
/// rounding of a t summed in f32 over up to 128 steps of at most the volume's depth is below
/// 128 · 2⁻²⁴ ≈ 7.6e-6, so 1e-5 separates rounding from a search that left the volume.
pub const OUTSIDE_TOLERANCE: f64 = 1e-5;

const _: () = assert!(std::mem::size_of::<GpuHit>() as u64 == PROBE_HIT_SIZE);

/// Runs the probe entry of `program` on `rays`; one hit per ray, in order.
pub fn probe(gpu: &Gpu, program: &Program, scene: &Scene, tex: &SceneTextures, rays: &[ProbeRay]) -> Result<Vec<GpuHit>, GpuError> {
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
    let size = rays.len() as u64 * PROBE_HIT_SIZE;
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
    let params = SceneTextures::params(gpu, scene, 1.0);
    let bg = tex.bind_group(
        gpu,
        &pipeline.get_bind_group_layout(0),
        &program.probe_bindings,
        &program.maps,
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
