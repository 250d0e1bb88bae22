//! The scene's textures and samplers on the device, and bind groups built from the bindings
//! an entry point reads.

use std::collections::HashMap;

use relief_dsl::abi::{binding, Params};
use relief_dsl::spec::MapReq;
use wgpu::util::DeviceExt;

use crate::maps::{normal, MapKey, MapKind};

use super::Gpu;
use crate::heightmap::EdgeMode;
use crate::scene::Scene;

/// The textures a scene needs on the device.
pub struct SceneTextures {
    pub height: wgpu::TextureView,
    pub normal: wgpu::TextureView,
    pub albedo: wgpu::TextureView,
    pub linear: wgpu::Sampler,
    pub nearest: wgpu::Sampler,
    /// Acceleration maps by the full request: kind and every parameter that changes the map
    /// (see [`SceneTextures::add_maps`]). Two maps of one kind with different parameters are
    /// two entries, though a shader binds either at the same binding.
    pub maps: HashMap<MapKey, wgpu::TextureView>,
    /// The heights as the device stores them (f32, or rounded to f16 where 32-bit float
    /// textures cannot be filtered): the surface the shaders sample, for the reference.
    pub heights_on_device: Vec<f32>,
}

fn texture(gpu: &Gpu, label: &str, w: usize, h: usize, format: wgpu::TextureFormat, bytes: &[u8]) -> wgpu::TextureView {
    let t = gpu.device.create_texture_with_data(
        &gpu.queue,
        &wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d { width: w as u32, height: h as u32, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytes,
    );
    t.create_view(&Default::default())
}

impl SceneTextures {
    /// Uploads the scene's height map, normal map (derived when the scene has none) and
    /// albedo (neutral grey when it has none).
    pub fn new(gpu: &Gpu, scene: &Scene) -> SceneTextures {
        let m = &scene.height;
        let (w, h) = (m.width, m.height);
        let (height, heights_on_device) = if gpu.float32_filterable {
            let bytes: &[u8] = bytemuck::cast_slice(&m.data);
            (texture(gpu, "height", w, h, wgpu::TextureFormat::R32Float, bytes), m.data.clone())
        } else {
            let halves: Vec<half::f16> = m.data.iter().map(|&x| half::f16::from_f32(x)).collect();
            let bytes: Vec<u8> = halves.iter().flat_map(|x| x.to_le_bytes()).collect();
            (
                texture(gpu, "height", w, h, wgpu::TextureFormat::R16Float, &bytes),
                halves.iter().map(|x| x.to_f32()).collect(),
            )
        };
        let normals: Vec<[f32; 3]> = match &scene.normal {
            Some(n) => n.data.clone(),
            None => normal::derived_normals(&scene.height, scene.depth_scale, scene.edge),
        };
        let (nw, nh) = match &scene.normal {
            Some(n) => (n.width, n.height),
            None => (w, h),
        };
        let nbytes: Vec<u8> = normals
            .iter()
            .flat_map(|n| [n[0], n[1], n[2]].map(|c| ((c * 0.5 + 0.5).clamp(0.0, 1.0) * 255.0).round() as u8).into_iter().chain([255]))
            .collect();
        let normal = texture(gpu, "normal", nw, nh, wgpu::TextureFormat::Rgba8Unorm, &nbytes);
        let albedo = match &scene.albedo {
            Some(a) => texture(gpu, "albedo", a.width, a.height, wgpu::TextureFormat::Rgba8UnormSrgb, &a.rgba),
            None => texture(gpu, "albedo", 1, 1, wgpu::TextureFormat::Rgba8UnormSrgb, &[180, 170, 160, 255]),
        };
        let address = match scene.edge {
            EdgeMode::Repeat => wgpu::AddressMode::Repeat,
            EdgeMode::Clamp => wgpu::AddressMode::ClampToEdge,
        };
        let sampler = |filter| {
            gpu.device.create_sampler(&wgpu::SamplerDescriptor {
                address_mode_u: address,
                address_mode_v: address,
                mag_filter: filter,
                min_filter: filter,
                ..Default::default()
            })
        };
        SceneTextures {
            height,
            normal,
            albedo,
            linear: sampler(wgpu::FilterMode::Linear),
            nearest: sampler(wgpu::FilterMode::Nearest),
            maps: HashMap::new(),
            heights_on_device,
        }
    }

    /// Builds and uploads the acceleration maps in `reqs` that are not there yet (the normal
    /// map is always there). Ratios are uploaded clamped to [`MAX_RATIO`]: a narrower cone
    /// than the exact one, which stays conservative and keeps `+inf` out of the shaders.
    pub fn add_maps(&mut self, gpu: &Gpu, scene: &Scene, reqs: &[MapReq]) -> Result<(), crate::maps::MapError> {
        for &req in reqs {
            // The normal map (no key) is uploaded with the scene.
            let Some((kind, params)) = MapKind::of(req) else { continue };
            let key = MapKey { kind, params: params.relevant(kind) };
            if self.maps.contains_key(&key) {
                continue;
            }
            let map = crate::maps::build(&scene.height, kind, &params, scene.edge)?;
            let used = if kind.is_cell() { map.channels - 1 } else { map.channels };
            let view = upload_map(gpu, &map, used, kind.is_ratio());
            self.maps.insert(key, view);
        }
        Ok(())
    }

    /// The uploaded map a shader binding `b` of a program reading `reqs` takes.
    fn map_view(&self, b: u32, reqs: &[MapReq]) -> Result<&wgpu::TextureView, super::GpuError> {
        let req = reqs.iter().find(|r| **r != MapReq::Normal && r.binding() == b).ok_or_else(|| {
            super::GpuError::Pipeline(format!("the shader reads a map at binding {b}, which the pipeline's required maps do not name"))
        })?;
        MapKey::of(*req).and_then(|k| self.maps.get(&k)).ok_or_else(|| missing_map(b))
    }

    /// The params uniform buffer for a scene seen at `aspect`.
    pub fn params(gpu: &Gpu, scene: &Scene, aspect: f32) -> wgpu::Buffer {
        let cam = scene.camera.camera_position();
        let l = scene.light_dir.normalize();
        let clamp = if scene.edge == EdgeMode::Clamp { 1.0 } else { 0.0 };
        let params = Params {
            view_proj: scene.camera.view_proj(aspect).to_cols_array(),
            camera: [cam.x, cam.y, cam.z, scene.depth_scale],
            light: [l.x, l.y, l.z, AMBIENT],
            quad: [scene.tiling, clamp, 0.0, 0.0],
        };
        gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("params"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM,
        })
    }

    /// A bind group with exactly `bindings`, from this scene's resources (the maps of
    /// `program`'s requests) and the buffers given.
    pub fn bind_group(
        &self,
        gpu: &Gpu,
        layout: &wgpu::BindGroupLayout,
        bindings: &[u32],
        reqs: &[MapReq],
        params: &wgpu::Buffer,
        storage: &[(u32, &wgpu::Buffer)],
    ) -> Result<wgpu::BindGroup, super::GpuError> {
        let mut entries = Vec::new();
        for &b in bindings {
            let resource = match b {
                binding::PARAMS => params.as_entire_binding(),
                binding::HEIGHT => wgpu::BindingResource::TextureView(&self.height),
                binding::NORMAL => wgpu::BindingResource::TextureView(&self.normal),
                binding::ALBEDO => wgpu::BindingResource::TextureView(&self.albedo),
                binding::LINEAR_SAMPLER => wgpu::BindingResource::Sampler(&self.linear),
                b if (binding::NEAREST_OFFSET..binding::RAYS).contains(&b) => {
                    let base = b - binding::NEAREST_OFFSET;
                    match base {
                        binding::HEIGHT => wgpu::BindingResource::TextureView(&self.height),
                        binding::NORMAL => wgpu::BindingResource::TextureView(&self.normal),
                        binding::ALBEDO => wgpu::BindingResource::TextureView(&self.albedo),
                        _ => wgpu::BindingResource::TextureView(self.map_view(base, reqs)?),
                    }
                }
                binding::NEAREST_SAMPLER => wgpu::BindingResource::Sampler(&self.nearest),
                b if b > binding::ALBEDO && b < binding::NEAREST_OFFSET => wgpu::BindingResource::TextureView(self.map_view(b, reqs)?),
                other => match storage.iter().find(|(n, _)| *n == other) {
                    Some((_, buf)) => buf.as_entire_binding(),
                    None => {
                        return Err(super::GpuError::Pipeline(format!(
                            "the shader reads binding {other}, which this runtime does not provide yet"
                        )))
                    }
                },
            };
            entries.push(wgpu::BindGroupEntry { binding: b, resource });
        }
        gpu.checked(|| gpu.device.create_bind_group(&wgpu::BindGroupDescriptor { label: None, layout, entries: &entries }))
    }
}

fn missing_map(b: u32) -> super::GpuError {
    super::GpuError::Pipeline(format!("the shader reads the map at binding {b}, which was not built (call add_maps with the pipeline's required_maps)"))
}

/// The largest cone ratio uploaded (a cone 89.99° wide).
pub const MAX_RATIO: f32 = 1.0e4;

/// Uploads the first `used` channels of a map as R32Float (one channel) or Rgba32Float (2 to
/// 4 channels, padded), 2D or 3D, with its pyramid levels (max-mip) as mip levels.
fn upload_map(gpu: &Gpu, map: &crate::maps::Map, used: usize, ratio: bool) -> wgpu::TextureView {
    assert!((1..=4).contains(&used) && used <= map.channels, "a map uploads 1 to 4 of its channels");
    let fix = |x: f32| if ratio { x.min(MAX_RATIO) } else { x };
    let texels = |m: &crate::maps::Map| -> Vec<f32> {
        let mut out = Vec::with_capacity(m.data.len() / m.channels * if used == 1 { 1 } else { 4 });
        for texel in m.data.chunks(m.channels) {
            if used == 1 {
                out.push(fix(texel[0]));
            } else {
                out.extend((0..4).map(|c| if c < used { fix(texel[c]) } else { 0.0 }));
            }
        }
        out
    };
    let format = if used == 1 { wgpu::TextureFormat::R32Float } else { wgpu::TextureFormat::Rgba32Float };
    let mut data = texels(map);
    for level in &map.mips {
        data.extend(texels(level));
    }
    let dimension = if map.depth > 1 { wgpu::TextureDimension::D3 } else { wgpu::TextureDimension::D2 };
    let t = gpu.device.create_texture_with_data(
        &gpu.queue,
        &wgpu::TextureDescriptor {
            label: Some("map"),
            size: wgpu::Extent3d { width: map.width as u32, height: map.height as u32, depth_or_array_layers: map.depth as u32 },
            mip_level_count: 1 + map.mips.len() as u32,
            sample_count: 1,
            dimension,
            format,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(&data),
    );
    t.create_view(&Default::default())
}

/// Ambient light share in the render.
pub const AMBIENT: f32 = 0.25;
