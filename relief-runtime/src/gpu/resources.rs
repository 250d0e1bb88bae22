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
    /// The height map with its mip chain: `R32Float`, or `R16Float` where 32-bit float
    /// textures cannot be filtered.
    pub height: wgpu::TextureView,
    /// The normal map (the scene's, or derived from the heights) with its mip chain:
    /// `Rgba8Unorm`, `n * 0.5 + 0.5` in rgb.
    pub normal: wgpu::TextureView,
    /// The albedo with its mip chain, `Rgba8UnormSrgb`; one grey texel when the scene has none.
    pub albedo: wgpu::TextureView,
    /// Linear filtering; address mode repeat or clamp-to-edge after the scene's edge mode.
    pub linear: wgpu::Sampler,
    /// Nearest filtering, same address mode.
    pub nearest: wgpu::Sampler,
    /// Acceleration maps by the full request: kind and every parameter that changes the map
    /// (see [`SceneTextures::add_maps`]). Two maps of one kind with different parameters are
    /// two entries, though a shader binds either at the same binding.
    pub maps: HashMap<MapKey, wgpu::TextureView>,
    /// The same maps with a mip chain of their own: level k built from level k of the height
    /// map's chain, for stages that read them at a level ([`SceneTextures::add_maps_lod`]).
    pub level_maps: HashMap<MapKey, wgpu::TextureView>,
    /// The heights as the device stores them (f32, or rounded to f16 where 32-bit float
    /// textures cannot be filtered): the surface the shaders sample, for the reference.
    pub heights_on_device: Vec<f32>,
    /// The height map's mip chain as the device stores it (level 0 first, the same values as
    /// `heights_on_device`): the surfaces `lod=level(k)` and `lod=auto` sample, for the
    /// reference.
    pub height_levels: Vec<crate::heightmap::HeightMap>,
}

/// A 2D texture with the given mip levels (level 0 first), each `(width, height, bytes)`.
fn texture(
    gpu: &Gpu,
    label: &str,
    levels: &[(usize, usize, Vec<u8>)],
    format: wgpu::TextureFormat,
) -> wgpu::TextureView {
    let (w, h, _) = levels[0];
    let bytes: Vec<u8> = levels.iter().flat_map(|(_, _, b)| b.iter().copied()).collect();
    let t = gpu.device.create_texture_with_data(
        &gpu.queue,
        &wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d { width: w as u32, height: h as u32, depth_or_array_layers: 1 },
            mip_level_count: levels.len() as u32,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        &bytes,
    );
    t.create_view(&Default::default())
}

impl SceneTextures {
    /// Uploads the scene's height map, normal map (derived when the scene has none) and
    /// albedo (neutral grey when it has none), each with its mip chain built by the one
    /// filter of [`crate::maps::mips`] (level 0 is what every pipeline under `lod=zero`
    /// samples; the other levels are what `lod=level(k)` and `lod=auto` sample).
    pub fn new(gpu: &Gpu, scene: &Scene) -> SceneTextures {
        let chain = crate::maps::mips::height_chain(&scene.height);
        let (height, height_levels) = if gpu.float32_filterable {
            let levels: Vec<(usize, usize, Vec<u8>)> =
                chain.iter().map(|l| (l.width, l.height, bytemuck::cast_slice(&l.data).to_vec())).collect();
            (texture(gpu, "height", &levels, wgpu::TextureFormat::R32Float), chain)
        } else {
            let rounded: Vec<crate::heightmap::HeightMap> = chain
                .iter()
                .map(|l| {
                    let data = l.data.iter().map(|&x| half::f16::from_f32(x).to_f32()).collect();
                    crate::heightmap::HeightMap::new(l.width, l.height, data)
                })
                .collect();
            let levels: Vec<(usize, usize, Vec<u8>)> = rounded
                .iter()
                .map(|l| {
                    (l.width, l.height, l.data.iter().flat_map(|&x| half::f16::from_f32(x).to_le_bytes()).collect())
                })
                .collect();
            (texture(gpu, "height", &levels, wgpu::TextureFormat::R16Float), rounded)
        };
        let heights_on_device = height_levels[0].data.clone();
        let normals: Vec<[f32; 3]> = match &scene.normal {
            Some(n) => n.data.clone(),
            None => normal::derived_normals(&scene.height, scene.depth_scale, scene.edge),
        };
        let (nw, nh) = match &scene.normal {
            Some(n) => (n.width, n.height),
            None => (scene.height.width, scene.height.height),
        };
        let flat: Vec<f32> = normals.iter().flat_map(|n| *n).collect();
        let nlevels: Vec<(usize, usize, Vec<u8>)> = crate::maps::mips::box_chain(nw, nh, 3, &flat)
            .into_iter()
            .map(|l| {
                let bytes = l
                    .data
                    .chunks(3)
                    .flat_map(|n| {
                        [n[0], n[1], n[2]]
                            .map(|c| ((c * 0.5 + 0.5).clamp(0.0, 1.0) * 255.0).round() as u8)
                            .into_iter()
                            .chain([255])
                    })
                    .collect();
                (l.width, l.height, bytes)
            })
            .collect();
        let normal = texture(gpu, "normal", &nlevels, wgpu::TextureFormat::Rgba8Unorm);
        let albedo = match &scene.albedo {
            Some(a) => {
                let f: Vec<f32> = a.rgba.iter().map(|&b| b as f32).collect();
                let levels: Vec<(usize, usize, Vec<u8>)> = crate::maps::mips::box_chain(a.width, a.height, 4, &f)
                    .into_iter()
                    .map(|l| (l.width, l.height, l.data.iter().map(|&x| x.round().clamp(0.0, 255.0) as u8).collect()))
                    .collect();
                texture(gpu, "albedo", &levels, wgpu::TextureFormat::Rgba8UnormSrgb)
            }
            None => texture(gpu, "albedo", &[(1, 1, vec![180, 170, 160, 255])], wgpu::TextureFormat::Rgba8UnormSrgb),
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
            level_maps: HashMap::new(),
            heights_on_device,
            height_levels,
        }
    }

    /// Builds and uploads the acceleration maps in `reqs` that are not there yet (the normal
    /// map is always there). Ratios are uploaded clamped to [`MAX_RATIO`]: a narrower cone
    /// than the exact one, which stays conservative and keeps `+inf` out of the shaders.
    pub fn add_maps(&mut self, gpu: &Gpu, scene: &Scene, reqs: &[MapReq]) -> Result<(), crate::maps::MapError> {
        self.add_maps_lod(gpu, scene, reqs, relief_dsl::spec::Lod::Zero)
    }

    /// [`SceneTextures::add_maps`] for a pipeline whose stages sample at `lod`: under a `lod`
    /// other than zero every map is built once per level of the height map's mip chain (the
    /// chain of [`crate::maps::mips`], in f32 as the scene holds it), level k from level k,
    /// and uploaded as the map's mip chain, so that a cone read at level k is the cone of
    /// level k's surface. Only maps with levels ([`MapReq::has_levels`]) are asked for here:
    /// the composer refuses the others under such a `lod`.
    pub fn add_maps_lod(
        &mut self,
        gpu: &Gpu,
        scene: &Scene,
        reqs: &[MapReq],
        lod: relief_dsl::spec::Lod,
    ) -> Result<(), crate::maps::MapError> {
        if lod != relief_dsl::spec::Lod::Zero {
            let chain = crate::maps::mips::height_chain(&scene.height);
            for &req in reqs {
                let Some((kind, params)) = MapKind::of(req) else { continue };
                let key = MapKey { kind, params: params.relevant(kind) };
                if self.level_maps.contains_key(&key) {
                    continue;
                }
                let view = if kind == MapKind::MaxMip {
                    // The pyramid of every level's cells, one layer each (see `upload_layers`).
                    let pyramids = chain
                        .iter()
                        .map(|h| crate::maps::build(h, kind, &params, scene.edge))
                        .collect::<Result<Vec<_>, _>>()?;
                    upload_layers(gpu, &pyramids)
                } else if kind.is_cell() {
                    // Cell maps: every level's cells in one atlas (see `maps::cell::level_atlas`).
                    let atlas = crate::maps::cell::level_atlas(&chain, kind, &params, scene.edge)?;
                    upload_map(gpu, &atlas, cell_channels_uploaded(atlas.channels), kind.is_ratio())
                } else {
                    if !req.has_levels() {
                        return Err(crate::maps::MapError::Params {
                            kind,
                            message: format!("the {} map has no per-level form (lod={lod})", req.name()),
                        });
                    }
                    let mut map = crate::maps::build(&chain[0], kind, &params, scene.edge)?;
                    for level in &chain[1..] {
                        map.mips.push(crate::maps::build(level, kind, &params, scene.edge)?);
                    }
                    upload_map(gpu, &map, map.channels, kind.is_ratio())
                };
                self.level_maps.insert(key, view);
            }
            return Ok(());
        }
        for &req in reqs {
            // The normal map (no key) is uploaded with the scene.
            let Some((kind, params)) = MapKind::of(req) else { continue };
            let key = MapKey { kind, params: params.relevant(kind) };
            if self.maps.contains_key(&key) {
                continue;
            }
            let map = crate::maps::build(&scene.height, kind, &params, scene.edge)?;
            let used = if kind.is_cell() { cell_channels_uploaded(map.channels) } else { map.channels };
            let view = upload_map(gpu, &map, used, kind.is_ratio());
            self.maps.insert(key, view);
        }
        Ok(())
    }

    /// The uploaded map a shader binding `b` of a program reading `reqs` takes.
    fn map_view(&self, b: u32, reqs: &[MapReq], levels: bool) -> Result<&wgpu::TextureView, super::GpuError> {
        let req = reqs.iter().find(|r| **r != MapReq::Normal && r.binding() == b).ok_or_else(|| {
            super::GpuError::Pipeline(format!(
                "the shader reads a map at binding {b}, which the pipeline's required maps do not name"
            ))
        })?;
        let maps = if levels { &self.level_maps } else { &self.maps };
        MapKey::of(*req).and_then(|k| maps.get(&k)).ok_or_else(|| missing_map(b))
    }

    /// The params uniform buffer for a scene seen at `aspect`, in a frame whose pixels have
    /// size `pixel_size` on the image plane at unit distance ([`Camera::pixel_size`]; the
    /// probe passes 0, its rays carry their own).
    ///
    /// [`Camera::pixel_size`]: crate::scene::Camera::pixel_size
    pub fn params(gpu: &Gpu, scene: &Scene, aspect: f32, pixel_size: f32) -> wgpu::Buffer {
        let (_, right, up) = scene.camera.basis();
        let cam = scene.camera.camera_position();
        let l = scene.light_dir.normalize();
        let clamp = if scene.edge == EdgeMode::Clamp { 1.0 } else { 0.0 };
        let params = Params {
            view_proj: scene.camera.view_proj(aspect).to_cols_array(),
            camera: [cam.x, cam.y, cam.z, scene.depth_scale],
            light: [l.x, l.y, l.z, AMBIENT],
            quad: [scene.tiling, clamp, 0.0, 0.0],
            pixel_right: [right.x, right.y, right.z, pixel_size],
            pixel_up: [up.x, up.y, up.z, 0.0],
        };
        gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("params"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM,
        })
    }

    /// A bind group with exactly `bindings`, from this scene's resources (the maps of
    /// `program`'s requests, with their per-level chains when `map_levels`) and the buffers
    /// given.
    #[allow(clippy::too_many_arguments)]
    pub fn bind_group(
        &self,
        gpu: &Gpu,
        layout: &wgpu::BindGroupLayout,
        bindings: &[u32],
        reqs: &[MapReq],
        map_levels: bool,
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
                        _ => wgpu::BindingResource::TextureView(self.map_view(base, reqs, map_levels)?),
                    }
                }
                binding::NEAREST_SAMPLER => wgpu::BindingResource::Sampler(&self.nearest),
                b if b > binding::ALBEDO && b < binding::NEAREST_OFFSET => {
                    wgpu::BindingResource::TextureView(self.map_view(b, reqs, map_levels)?)
                }
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
        gpu.checked(|| {
            gpu.device.create_bind_group(&wgpu::BindGroupDescriptor { label: None, layout, entries: &entries })
        })
    }
}

fn missing_map(b: u32) -> super::GpuError {
    super::GpuError::Pipeline(format!("the shader reads the map at binding {b}, which was not built (call add_maps_lod with the pipeline's required_maps and lod)"))
}

/// The channels of a cell map that go to the device: all of them (the cones, then the apex)
/// where the apex fits in the texel ([`relief_dsl::abi::cell_apex_on_device`]), else the
/// cones only (the shader then takes the apex from the cell's gathered corners).
fn cell_channels_uploaded(channels: usize) -> usize {
    if relief_dsl::abi::cell_apex_on_device(channels) {
        channels
    } else {
        channels - 1
    }
}

/// The largest cone ratio uploaded (a cone 89.99° wide).
pub const MAX_RATIO: f32 = 1.0e4;

/// Uploads the first `used` channels of a map as R32Float (one channel), Rg32Float (two: a
/// cell map's cone and apex, half the bytes of a padded texel) or Rgba32Float (3 or 4
/// channels, padded), 2D or 3D, with its pyramid levels (max-mip) as mip levels.
fn upload_map(gpu: &Gpu, map: &crate::maps::Map, used: usize, ratio: bool) -> wgpu::TextureView {
    assert!((1..=4).contains(&used) && used <= map.channels, "a map uploads 1 to 4 of its channels");
    let fix = |x: f32| if ratio { x.min(MAX_RATIO) } else { x };
    // Channels per stored texel: no format holds three 32-bit floats.
    let stored = if used == 3 { 4 } else { used };
    let texels = |m: &crate::maps::Map| -> Vec<f32> {
        let mut out = Vec::with_capacity(m.data.len() / m.channels * stored);
        for texel in m.data.chunks(m.channels) {
            if stored < 4 {
                out.extend(texel[..stored].iter().map(|&x| fix(x)));
            } else {
                out.extend((0..4).map(|c| if c < used { fix(texel[c]) } else { 0.0 }));
            }
        }
        out
    };
    let format = match stored {
        1 => wgpu::TextureFormat::R32Float,
        2 => wgpu::TextureFormat::Rg32Float,
        _ => wgpu::TextureFormat::Rgba32Float,
    };
    let mut data = texels(map);
    for level in &map.mips {
        data.extend(texels(level));
    }
    let dimension = if map.depth > 1 { wgpu::TextureDimension::D3 } else { wgpu::TextureDimension::D2 };
    let t = gpu.device.create_texture_with_data(
        &gpu.queue,
        &wgpu::TextureDescriptor {
            label: Some("map"),
            size: wgpu::Extent3d {
                width: map.width as u32,
                height: map.height as u32,
                depth_or_array_layers: map.depth as u32,
            },
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

/// One-channel pyramids (`layers[k]`: a [`crate::maps::Map`] whose `mips` are its coarser
/// levels) as the layers of one `R32Float` 2D array texture with a mip chain: layer k's level
/// j sits in the top-left corner of mip j, the rest is 0. The max-mip pyramids of the levels
/// of the height map's chain fit that way (level k's pyramid level j has `w_0 >> (k + j)`
/// texels a side, at most mip j's `w_0 >> j`); a stage sampling at level k reads layer k
/// (relief-dsl's `Stage::map_texel`). Mips past the texture's chain are dropped: the
/// traversal starts at `floor(log2 n)`, the chain's last mip.
fn upload_layers(gpu: &Gpu, layers: &[crate::maps::Map]) -> wgpu::TextureView {
    let (w0, h0) = (layers[0].width, layers[0].height);
    let mip_count = (usize::BITS - w0.max(h0).leading_zeros()) as usize;
    let mut data = Vec::new();
    for p in layers {
        let levels: Vec<&crate::maps::Map> = std::iter::once(p).chain(&p.mips).collect();
        for j in 0..mip_count {
            let (mw, mh) = ((w0 >> j).max(1), (h0 >> j).max(1));
            let mut mip = vec![0.0f32; mw * mh];
            if let Some(l) = levels.get(j) {
                for y in 0..l.height.min(mh) {
                    for x in 0..l.width.min(mw) {
                        mip[y * mw + x] = l.data[(y * l.width + x) * l.channels];
                    }
                }
            }
            data.extend(mip);
        }
    }
    let t = gpu.device.create_texture_with_data(
        &gpu.queue,
        &wgpu::TextureDescriptor {
            label: Some("map layers"),
            size: wgpu::Extent3d { width: w0 as u32, height: h0 as u32, depth_or_array_layers: layers.len() as u32 },
            mip_level_count: mip_count as u32,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R32Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(&data),
    );
    t.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    })
}

/// Ambient light share in the render.
pub const AMBIENT: f32 = 0.25;
