//! The scene's textures and samplers on the device, and bind groups built from the bindings
//! an entry point reads.

use std::collections::HashMap;

use relief_dsl::abi::Params;
use relief_dsl::ir::{Bindings, Filter, Image, Resource};
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

/// A texture's contents in the layout the runtime uploads them: its size, format and
/// dimension, and the bytes of each mip level (all slices or layers of a level together),
/// level 0 first. The device upload and the report's browser data ([`crate::report`]) both
/// take their bytes from here, so the two cannot differ.
#[derive(Clone, Debug, PartialEq)]
pub struct Upload {
    /// Width of level 0, texels.
    pub width: u32,
    /// Height of level 0, texels.
    pub height: u32,
    /// Slices (3D) or layers (2D array) of level 0; 1 for a plain 2D texture.
    pub depth: u32,
    /// The texel format.
    pub format: wgpu::TextureFormat,
    /// 2D or 3D.
    pub dimension: wgpu::TextureDimension,
    /// The view: 2D, 2D array or 3D.
    pub view: wgpu::TextureViewDimension,
    /// The bytes of each mip level, level 0 first, rows tightly packed.
    pub levels: Vec<Vec<u8>>,
}

impl Upload {
    /// A 2D texture from `(width, height, bytes)` levels, level 0 first.
    fn d2(levels: Vec<(usize, usize, Vec<u8>)>, format: wgpu::TextureFormat) -> Upload {
        let (w, h, _) = levels[0];
        Upload {
            width: w as u32,
            height: h as u32,
            depth: 1,
            format,
            dimension: wgpu::TextureDimension::D2,
            view: wgpu::TextureViewDimension::D2,
            levels: levels.into_iter().map(|(_, _, b)| b).collect(),
        }
    }
}

/// Uploads `u` as a texture and returns its view.
fn texture(gpu: &Gpu, label: &str, u: &Upload) -> wgpu::TextureView {
    let bytes: Vec<u8> = u.levels.concat();
    let t = gpu.device.create_texture_with_data(
        &gpu.queue,
        &wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d { width: u.width, height: u.height, depth_or_array_layers: u.depth },
            mip_level_count: u.levels.len() as u32,
            sample_count: 1,
            dimension: u.dimension,
            format: u.format,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        &bytes,
    );
    t.create_view(&wgpu::TextureViewDescriptor { dimension: Some(u.view), ..Default::default() })
}

/// The scene's own textures in their upload layouts ([`scene_uploads`]).
pub struct SceneUploads {
    /// The height map with its mip chain (`R32Float`, or `R16Float` without `float32`).
    pub height: Upload,
    /// The normal map with its mip chain, `Rgba8Unorm`.
    pub normal: Upload,
    /// The albedo with its mip chain, `Rgba8UnormSrgb`.
    pub albedo: Upload,
    /// The height chain as stored (level 0 first): f32, or rounded to f16.
    pub height_levels: Vec<crate::heightmap::HeightMap>,
}

/// The scene's height, normal and albedo textures as [`SceneTextures::new`] uploads them:
/// heights in `R32Float` when `float32` (32-bit float textures can be filtered), else
/// rounded to `R16Float`.
pub fn scene_uploads(scene: &Scene, float32: bool) -> SceneUploads {
    let chain = crate::maps::mips::height_chain(&scene.height);
    let (height, height_levels) = if float32 {
        let levels: Vec<(usize, usize, Vec<u8>)> =
            chain.iter().map(|l| (l.width, l.height, bytemuck::cast_slice(&l.data).to_vec())).collect();
        (Upload::d2(levels, wgpu::TextureFormat::R32Float), chain)
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
            .map(|l| (l.width, l.height, l.data.iter().flat_map(|&x| half::f16::from_f32(x).to_le_bytes()).collect()))
            .collect();
        (Upload::d2(levels, wgpu::TextureFormat::R16Float), rounded)
    };
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
    let normal = Upload::d2(nlevels, wgpu::TextureFormat::Rgba8Unorm);
    let albedo = match &scene.albedo {
        Some(a) => {
            let f: Vec<f32> = a.rgba.iter().map(|&b| b as f32).collect();
            let levels: Vec<(usize, usize, Vec<u8>)> = crate::maps::mips::box_chain(a.width, a.height, 4, &f)
                .into_iter()
                .map(|l| (l.width, l.height, l.data.iter().map(|&x| x.round().clamp(0.0, 255.0) as u8).collect()))
                .collect();
            Upload::d2(levels, wgpu::TextureFormat::Rgba8UnormSrgb)
        }
        None => Upload::d2(vec![(1, 1, vec![180, 170, 160, 255])], wgpu::TextureFormat::Rgba8UnormSrgb),
    };
    SceneUploads { height, normal, albedo, height_levels }
}

/// What binding `b` holds in a module whose binding table is `table`
/// ([`relief_dsl::compose::Compiled::bindings`]: the composer records each resource as a
/// stage declares it, so nothing here works it out again from the number). A binding the
/// table does not name is an error.
pub(crate) fn resource_at(table: &Bindings, b: u32) -> Result<Resource, super::GpuError> {
    table.resource(b).ok_or_else(|| {
        super::GpuError::Pipeline(format!(
            "the shader reads binding {b}, which its module's binding table does not name"
        ))
    })
}

/// The `Params` block for a scene seen at `aspect`, in a frame whose pixels have size
/// `pixel_size` on the image plane at unit distance ([`Camera::pixel_size`]; the probe
/// passes 0, its rays carry their own).
///
/// [`Camera::pixel_size`]: crate::scene::Camera::pixel_size
pub(crate) fn params_for(scene: &Scene, aspect: f32, pixel_size: f32) -> Params {
    let (_, right, up) = scene.camera.basis();
    let cam = scene.camera.camera_position();
    let l = scene.light_dir.normalize();
    let clamp = if scene.edge == EdgeMode::Clamp { 1.0 } else { 0.0 };
    Params {
        view_proj: scene.camera.view_proj(aspect).to_cols_array(),
        camera: [cam.x, cam.y, cam.z, scene.depth_scale],
        light: [l.x, l.y, l.z, AMBIENT],
        quad: [scene.tiling, clamp, 0.0, 0.0],
        pixel_right: [right.x, right.y, right.z, pixel_size],
        pixel_up: [up.x, up.y, up.z, 0.0],
    }
}

impl SceneTextures {
    /// Uploads the scene's height map, normal map (derived when the scene has none) and
    /// albedo (neutral grey when it has none), each with its mip chain built by the one
    /// filter of [`crate::maps::mips`] (level 0 is what every pipeline under `lod=zero`
    /// samples; the other levels are what `lod=level(k)` and `lod=auto` sample).
    pub fn new(gpu: &Gpu, scene: &Scene) -> SceneTextures {
        let u = scene_uploads(scene, gpu.float32_filterable);
        let (height, normal, albedo) =
            (texture(gpu, "height", &u.height), texture(gpu, "normal", &u.normal), texture(gpu, "albedo", &u.albedo));
        let height_levels = u.height_levels;
        let heights_on_device = height_levels[0].data.clone();
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
    /// map is always there). Ratios are uploaded clamped to `MAX_RATIO`: a narrower cone
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
                } else if kind.per_cell() {
                    // Cell maps and the patch map: every level's cells in one atlas (see
                    // `maps::cell::level_atlas`); the patch map from the chain as the device
                    // stores it ([`SceneTextures::patch_heights`]).
                    let chain = if kind == MapKind::CellPatch { &self.height_levels } else { &chain };
                    let atlas = crate::maps::cell::level_atlas(chain, kind, &params, scene.edge)?;
                    let used = if kind.is_cell() { cell_channels_uploaded(atlas.channels) } else { atlas.channels };
                    upload_map(gpu, &atlas, used, kind.is_ratio())
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
            let upload = if kind == MapKind::CellPatch {
                let map = crate::maps::build(self.patch_heights(), kind, &params, scene.edge)?;
                upload_of_map(&map, kind)?
            } else {
                map_upload_of(scene, key)?
            };
            self.maps.insert(key, texture(gpu, "map", &upload));
        }
        Ok(())
    }

    /// The heights the patch map (`cell_patch`) is built from: level 0 as the device stores it
    /// (f32, or rounded to f16 where 32-bit float textures cannot be filtered), the heights a
    /// gather would read, so that a patch read from the map is the gathered one bit for bit in
    /// either case. (The cone maps are built from the scene's f32 heights.)
    fn patch_heights(&self) -> &crate::heightmap::HeightMap {
        &self.height_levels[0]
    }

    /// The uploaded map of `req` (with its per-level chain when `levels`).
    fn map_view(&self, req: MapReq, levels: bool) -> Result<&wgpu::TextureView, super::GpuError> {
        let maps = if levels { &self.level_maps } else { &self.maps };
        MapKey::of(req).and_then(|k| maps.get(&k)).ok_or_else(|| missing_map(req.binding()))
    }

    /// The params uniform buffer for a scene seen at `aspect`, in a frame whose pixels have
    /// size `pixel_size` on the image plane at unit distance ([`Camera::pixel_size`]; the
    /// probe passes 0, its rays carry their own).
    ///
    /// [`Camera::pixel_size`]: crate::scene::Camera::pixel_size
    pub fn params(gpu: &Gpu, scene: &Scene, aspect: f32, pixel_size: f32) -> wgpu::Buffer {
        let params = params_for(scene, aspect, pixel_size);
        gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("params"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM,
        })
    }

    /// A bind group with exactly `bindings` of `program`, from this scene's resources (the
    /// maps its table names, with their per-level chains when `program.map_levels`) and the
    /// buffers given.
    pub(crate) fn bind_group(
        &self,
        gpu: &Gpu,
        layout: &wgpu::BindGroupLayout,
        bindings: &[u32],
        program: &super::Program,
        params: &wgpu::Buffer,
        storage: &[(u32, &wgpu::Buffer)],
    ) -> Result<wgpu::BindGroup, super::GpuError> {
        let mut entries = Vec::new();
        for &b in bindings {
            let resource = match resource_at(&program.bindings, b)? {
                Resource::Params => params.as_entire_binding(),
                Resource::Texture { image, wall: None, .. } => wgpu::BindingResource::TextureView(match image {
                    Image::Height => &self.height,
                    Image::Normal => &self.normal,
                    Image::Albedo => &self.albedo,
                    Image::Map(req) => self.map_view(req, program.map_levels)?,
                    Image::Window => return Err(only_rooms(b)),
                }),
                Resource::Sampler(Filter::Linear) => wgpu::BindingResource::Sampler(&self.linear),
                Resource::Sampler(Filter::Nearest) => wgpu::BindingResource::Sampler(&self.nearest),
                Resource::Rays | Resource::Hits | Resource::PrismCells => match storage.iter().find(|(n, _)| *n == b) {
                    Some((_, buf)) => buf.as_entire_binding(),
                    None => {
                        return Err(super::GpuError::Pipeline(format!(
                            "the shader reads binding {b}, a buffer this call does not provide"
                        )))
                    }
                },
                Resource::Texture { wall: Some(_), .. } | Resource::RoomParams => return Err(only_rooms(b)),
            };
            entries.push(wgpu::BindGroupEntry { binding: b, resource });
        }
        gpu.checked(|| {
            gpu.device.create_bind_group(&wgpu::BindGroupDescriptor { label: None, layout, entries: &entries })
        })
    }
}

/// A room's resource in a scene's bind group.
fn only_rooms(b: u32) -> super::GpuError {
    super::GpuError::Pipeline(format!(
        "the shader reads a room's resource at binding {b}; bind it with the room runtime"
    ))
}

fn missing_map(b: u32) -> super::GpuError {
    super::GpuError::Pipeline(format!("the shader reads the map at binding {b}, which was not built (call add_maps_lod with the pipeline's required_maps and lod)"))
}

/// The largest cone ratio uploaded (a cone 89.99° wide).
pub(crate) const MAX_RATIO: f32 = 1.0e4;

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

/// The first `used` channels of a map as R32Float (one channel), Rg32Float (two: a cell
/// map's cone and apex, half the bytes of a padded texel) or Rgba32Float (3 or 4 channels,
/// padded), 2D or 3D, with its pyramid levels (max-mip) as mip levels; cone ratios (`ratio`)
/// clamped to [`MAX_RATIO`]: the layout [`SceneTextures::add_maps`] uploads.
pub(crate) fn map_upload(map: &crate::maps::Map, used: usize, ratio: bool) -> Upload {
    assert!((1..=4).contains(&used) && used <= map.channels, "a map uploads 1 to 4 of its channels");
    let fix = |x: f32| if ratio { x.min(MAX_RATIO) } else { x };
    // Channels per stored texel: no format holds three 32-bit floats.
    let stored = if used == 3 { 4 } else { used };
    let texels = |m: &crate::maps::Map| -> Vec<u8> {
        let mut out: Vec<f32> = Vec::with_capacity(m.data.len() / m.channels * stored);
        for texel in m.data.chunks(m.channels) {
            if stored < 4 {
                out.extend(texel[..stored].iter().map(|&x| fix(x)));
            } else {
                out.extend((0..4).map(|c| if c < used { fix(texel[c]) } else { 0.0 }));
            }
        }
        bytemuck::cast_slice(&out).to_vec()
    };
    let format = match stored {
        1 => wgpu::TextureFormat::R32Float,
        2 => wgpu::TextureFormat::Rg32Float,
        _ => wgpu::TextureFormat::Rgba32Float,
    };
    let (dimension, view) = if map.depth > 1 {
        (wgpu::TextureDimension::D3, wgpu::TextureViewDimension::D3)
    } else {
        (wgpu::TextureDimension::D2, wgpu::TextureViewDimension::D2)
    };
    let levels = std::iter::once(map).chain(&map.mips).map(texels).collect();
    Upload {
        width: map.width as u32,
        height: map.height as u32,
        depth: map.depth as u32,
        format,
        dimension,
        view,
        levels,
    }
}

/// The layout of a map kind as [`SceneTextures::add_maps`] uploads it at level 0: the map
/// of `key` built on `scene`'s heights.
pub fn map_upload_of(scene: &Scene, key: MapKey) -> Result<Upload, crate::maps::MapError> {
    let map = crate::maps::build(&scene.height, key.kind, &key.params, scene.edge)?;
    upload_of_map(&map, key.kind)
}

/// The layout [`SceneTextures::add_maps`] uploads for `map`, a map of kind `kind` (the
/// channels the device gets, cone ratios clamped, the max-mip chain as mip levels, the
/// distance field as a 3D texture). A map with more than four channels on the device (K > 4
/// stacked or piecewise cones) fits no texel: an error naming the kind.
///
/// ```
/// use relief_runtime::{gpu, maps, EdgeMode, HeightMap, MapKind, MapParams};
/// let hm = HeightMap::new(8, 8, (0..64).map(|i| (i % 7) as f32 / 7.0).collect());
/// let map = maps::build(&hm, MapKind::MaxMip, &MapParams::default(), EdgeMode::Repeat).unwrap();
/// let up = gpu::upload_of_map(&map, MapKind::MaxMip).unwrap();
/// assert_eq!((up.format, up.levels.len()), (wgpu::TextureFormat::R32Float, 4)); // 8², 4², 2², 1²
/// ```
pub fn upload_of_map(map: &crate::maps::Map, kind: crate::maps::MapKind) -> Result<Upload, crate::maps::MapError> {
    let used = if kind.is_cell() { cell_channels_uploaded(map.channels) } else { map.channels };
    if !(1..=4).contains(&used) {
        return Err(crate::maps::MapError::Params {
            kind,
            message: format!("{used} channels on the device, and a texel holds 1 to 4"),
        });
    }
    Ok(map_upload(map, used, kind.is_ratio()))
}

impl Upload {
    /// The same texture with each 32-bit float texel channel rounded to a 16-bit float
    /// (`R32Float` → `R16Float`, `Rg32Float` → `Rg16Float`, `Rgba32Float` → `Rgba16Float`);
    /// other formats are returned as they are.
    pub fn to_f16(&self) -> Upload {
        let format = match self.format {
            wgpu::TextureFormat::R32Float => wgpu::TextureFormat::R16Float,
            wgpu::TextureFormat::Rg32Float => wgpu::TextureFormat::Rg16Float,
            wgpu::TextureFormat::Rgba32Float => wgpu::TextureFormat::Rgba16Float,
            _ => return self.clone(),
        };
        let levels = self
            .levels
            .iter()
            .map(|l| {
                l.chunks_exact(4)
                    .flat_map(|b| half::f16::from_f32(f32::from_le_bytes([b[0], b[1], b[2], b[3]])).to_le_bytes())
                    .collect()
            })
            .collect();
        Upload { format, levels, ..self.clone() }
    }

    /// The texture as the container its extension names: `.ktx2` or `.dds`
    /// ([`crate::io::container`]); `None` for any other extension.
    pub fn container_bytes(&self, path: &std::path::Path) -> Option<Result<Vec<u8>, String>> {
        let ext = path.extension().and_then(|e| e.to_str()).map(|e| e.to_ascii_lowercase())?;
        let t = crate::io::container::Texture {
            width: self.width,
            height: self.height,
            depth: self.depth,
            format: self.format,
            levels: &self.levels,
        };
        if self.view == wgpu::TextureViewDimension::D2Array {
            return Some(Err("a 2D array texture is not written to a container".into()));
        }
        match ext.as_str() {
            "ktx2" => Some(crate::io::container::ktx2_bytes(&t)),
            "dds" => Some(crate::io::container::dds_bytes(&t)),
            _ => None,
        }
    }
}

fn upload_map(gpu: &Gpu, map: &crate::maps::Map, used: usize, ratio: bool) -> wgpu::TextureView {
    texture(gpu, "map", &map_upload(map, used, ratio))
}

/// One-channel pyramids (`layers[k]`: a [`crate::maps::Map`] whose `mips` are its coarser
/// levels) as the layers of one `R32Float` 2D array texture with a mip chain: layer k's level
/// j sits in the top-left corner of mip j, the rest is 0. The max-mip pyramids of the levels
/// of the height map's chain fit that way (level k's pyramid level j has `w_0 >> (k + j)`
/// texels a side, at most mip j's `w_0 >> j`); a stage sampling at level k reads layer k
/// (relief-dsl's `FnBuilder::map_texel`). Mips past the texture's chain are dropped: the
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
