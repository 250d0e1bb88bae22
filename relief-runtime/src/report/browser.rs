//! What a browser needs to draw and measure the sweep's pipelines with WebGPU, written beside
//! `index.html` under `browser/` as script files, so that the page works from `file://`
//! with no server:
//!
//! - `browser/manifest.js`: the `Params` layout (from the ABI's member list), the binding
//!   numbers, every measured pipeline (its files, the source of each binding its render and
//!   probe entries read), every scene (camera, depth scale, tiling, edge mode, light, the
//!   `Params` of the measured view, its textures and maps, its probe rays' counts and the
//!   terms they are computed from) and every ok row;
//! - `browser/wgsl/STEM.js`: a pipeline's module as `relief gen` writes it (render pair and
//!   probe entry);
//! - `browser/scenes/SCENE/NAME.js`: the height, normal and albedo textures and the
//!   acceleration maps, in the layouts the runtime uploads ([`crate::gpu::scene_uploads`],
//!   [`crate::gpu::map_upload`]); a scene seen from another view (`rocks@angle=70`) has the
//!   same height map, and its manifest entry names the first view's files ([`data_file`]);
//! - no distance field: the manifest names it as computed in the page, with its z resolution,
//!   edge mode and size ([`computed_in_page`]), and the page builds it from the height file's
//!   level 0 (`distanceField` in `web/live.js`, the generator's f64 operations in its order,
//!   rounded down to f32: the runtime's values bit for bit), when a pipeline that reads it is
//!   first drawn or probed;
//! - no patch map (`cell_patch`, read by the safe `csm`, `cns`, `csm_relax`, `qcsm`): computed in the
//!   page the same way (`cellPatch`: per cell the f32 differences of the corners, in the
//!   generator's order, bit for bit), 4 floats a cell that would be a scene's largest file;
//! - no probe rays: the manifest gives what [`Scene::rays`] computes them from ([`rays_from`])
//!   and the page computes them bit for bit (`probeRays`, every `stride`-th ray). Their exact
//!   hits are not shipped: the page reads none, and `--add` traces them again ([`probe_set`]).
//!
//! A data file sets `window.RELIEF_DATA[NAME] = { meta, gz, shuffle, bytes }`: its bytes split
//! into `shuffle`-byte planes ([`shuffle`]), gzip-compressed and base64-encoded ([`pack`]),
//! which the page inflates with the browser's `DecompressionStream`; the manifest sets
//! `window.RELIEF_MANIFEST`. The page's script (`web/live.js`) loads files on demand.
//!
//! Pipelines under a `lod` other than zero read per-level maps, which are not shipped; they
//! are listed as set aside. Heights ship as `R32Float`: the page needs WebGPU's
//! `float32-filterable`.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use relief_dsl::abi::{binding, Member, Params};
use relief_dsl::ir::{Filter, Image, Resource};
use relief_dsl::spec::Lod;
use serde_json::{json, Value};

use crate::error::{Error, Result};
use crate::gpu::{self, GpuError, Program, Upload};
use crate::heightmap::EdgeMode;
use crate::maps::{MapKey, MapKind};
use crate::reference::{reference_hits, RefHit, Sampling};
use crate::scene::{scene_from_arg, ProbeRay, Scene};

use super::data::Data;

/// The exact pipeline the page draws its |t − t_exact| view against (a max-mip traversal
/// with enough steps to finish every ray, Tevs, Ihrke & Seidel 2008).
pub(crate) const EXACT: &str = "maxmip(96)";

/// The most probe rays the page probes per scene and size: above it every `stride`-th ray.
pub(crate) const MAX_PROBE_RAYS: usize = 65536;

/// The stride of the probed rays for `n` rays ([`MAX_PROBE_RAYS`]).
pub(crate) fn probe_stride(n: usize) -> usize {
    n.div_ceil(MAX_PROBE_RAYS).max(1)
}

/// What [`write`] wrote.
#[derive(Debug, Default)]
pub(crate) struct Written {
    /// Every file, the manifest first.
    pub files: Vec<PathBuf>,
    /// Pipelines and scenes not shipped, with why.
    pub set_aside: Vec<String>,
    /// Pipelines shipped (the exact one included).
    pub pipelines: usize,
}

/// The `Params` members with their WGSL uniform-buffer offsets and sizes: `(name, type,
/// offset, size)`, and the block's size.
pub(crate) fn params_layout() -> (Vec<(&'static str, &'static str, usize, usize)>, usize) {
    let mut off = 0usize;
    let mut out = Vec::new();
    let mut align_max = 1;
    for &(name, m) in Params::MEMBERS {
        let (ty, size, align) = match m {
            Member::F32 => ("f32", 4, 4),
            Member::U32 => ("u32", 4, 4),
            Member::Vec2 => ("vec2<f32>", 8, 8),
            Member::Vec3 => ("vec3<f32>", 12, 16),
            Member::Vec4 => ("vec4<f32>", 16, 16),
            Member::Mat4 => ("mat4x4<f32>", 64, 16),
        };
        off = off.next_multiple_of(align);
        align_max = align_max.max(align);
        out.push((name, ty, off, size));
        off += size;
    }
    (out, off.next_multiple_of(align_max))
}

/// A map's name in the browser data (kind and the parameters that matter to it).
fn map_slug(k: MapKey) -> String {
    format!("{}_{}_{}", k.kind.name(), k.params.cones, k.params.z_resolution)
}

/// A scene label as a folder name.
fn scene_slug(label: &str) -> String {
    super::text::file_safe(label.strip_prefix("scene:").unwrap_or(label))
}

fn format_name(f: wgpu::TextureFormat) -> &'static str {
    match f {
        wgpu::TextureFormat::R32Float => "r32float",
        wgpu::TextureFormat::R16Float => "r16float",
        wgpu::TextureFormat::Rgba8Unorm => "rgba8unorm",
        wgpu::TextureFormat::Rgba8UnormSrgb => "rgba8unorm-srgb",
        wgpu::TextureFormat::Rg32Float => "rg32float",
        wgpu::TextureFormat::Rgba32Float => "rgba32float",
        other => unreachable!("no upload has format {other:?}"),
    }
}

/// What the page binds for `resource` (`live.js` reads these names); a room's resources
/// have no place in the page.
fn resource_json(resource: Resource) -> Option<Value> {
    Some(match resource {
        Resource::Params => json!("params"),
        Resource::Texture { image, wall: None, .. } => match image {
            Image::Height => json!("height"),
            Image::Normal => json!("normal"),
            Image::Albedo => json!("albedo"),
            Image::Map(req) => json!(format!("map:{}", MapKey::of(req).map(map_slug).unwrap_or_default())),
            Image::Window => return None,
        },
        Resource::Sampler(Filter::Linear) => json!("linear"),
        Resource::Sampler(Filter::Nearest) => json!("nearest"),
        Resource::Rays => json!("rays"),
        Resource::Hits => json!("hits"),
        // The page draws flat tiles; the prism walk's buffer belongs to the runtime's mesh draw.
        Resource::Texture { wall: Some(_), .. } | Resource::RoomParams | Resource::PrismCells => return None,
    })
}

/// The byte planes of `bytes` taken `elem` bytes at a time: every element's first byte, then
/// every element's second, and so on (a trailing part shorter than `elem` kept as it is).
/// The high bytes of neighbouring floats are alike, so the planes deflate far better than the
/// interleaved floats; the page puts the bytes back (`unshuffle` in `web/live.js`).
pub(crate) fn shuffle(bytes: &[u8], elem: usize) -> Vec<u8> {
    if elem <= 1 {
        return bytes.to_vec();
    }
    let n = bytes.len() / elem;
    let mut out = Vec::with_capacity(bytes.len());
    for b in 0..elem {
        out.extend((0..n).map(|i| bytes[i * elem + b]));
    }
    out.extend_from_slice(&bytes[n * elem..]);
    out
}

/// `bytes` shuffled by `elem` ([`shuffle`]) and gzip-compressed: what a data file's `gz`
/// holds, which the page inflates with the browser's `DecompressionStream("gzip")`.
pub(crate) fn pack(bytes: &[u8], elem: usize) -> Result<Vec<u8>> {
    use std::io::Write as _;
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    gz.write_all(&shuffle(bytes, elem))
        .and_then(|()| gz.finish())
        .map_err(|e| Error::Input(format!("cannot compress the browser data: {e}")))
}

/// The data files written so far, and which holds what: a scene seen from two views (`rocks`
/// and `rocks@angle=70`) has the same height map and so the same textures and maps, which
/// are written once and named by both scenes' manifest entries.
#[derive(Default)]
struct Files {
    /// Every file written, in order.
    written: Vec<PathBuf>,
    /// The name of the file holding each content ([`content_key`]).
    by_content: std::collections::HashMap<u64, String>,
}

/// A data file's content as a 64-bit hash of its meta, element size and bytes: two files
/// with equal keys are taken to be equal (a chance collision among the few hundred files
/// of a sweep is about 1e-15).
fn content_key(meta: &Value, bytes: &[u8], elem: usize) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    (meta.to_string(), elem, bytes).hash(&mut h);
    h.finish()
}

/// One data file: `window.RELIEF_DATA[name] = { meta, gz, shuffle, bytes }`, `gz` the
/// base64 of `bytes` packed by [`pack`] with element size `shuffle`, `bytes` their length.
/// Returns the name to load it by: `name`, or that of a file already written with the same
/// content ([`Files`]).
fn data_file(dir: &Path, name: &str, meta: Value, bytes: &[u8], elem: usize, files: &mut Files) -> Result<String> {
    let key = content_key(&meta, bytes, elem);
    if let Some(same) = files.by_content.get(&key) {
        return Ok(same.clone());
    }
    let path = dir.join(format!("{name}.js"));
    if let Some(parent) = path.parent() {
        crate::io::create_dir_all(parent)?;
    }
    let gz = pack(bytes, elem)?;
    let body = json!({ "meta": meta, "gz": crate::io::base64::encode(&gz), "shuffle": elem, "bytes": bytes.len() });
    let text = format!("(window.RELIEF_DATA = window.RELIEF_DATA || {{}})[{}] = {};\n", json!(name), body);
    crate::io::write_atomic(&path, text.as_bytes())?;
    files.written.push(path);
    files.by_content.insert(key, name.to_string());
    Ok(name.to_string())
}

fn texture_file(dir: &Path, name: &str, u: &Upload, files: &mut Files) -> Result<String> {
    let dimension = if u.dimension == wgpu::TextureDimension::D3 { "3d" } else { "2d" };
    let view = match u.view {
        wgpu::TextureViewDimension::D3 => "3d",
        wgpu::TextureViewDimension::D2Array => "2d-array",
        _ => "2d",
    };
    let meta = json!({
        "width": u.width, "height": u.height, "depth": u.depth, "format": format_name(u.format),
        "dimension": dimension, "view": view, "levels": u.levels.iter().map(Vec::len).collect::<Vec<_>>(),
    });
    // Shuffled by 4: the bytes of a 32-bit float, or the channels of an RGBA8 texel; 2 for
    // the bytes of a 16-bit float.
    let elem = if u.format == wgpu::TextureFormat::R16Float { 2 } else { 4 };
    data_file(dir, name, meta, &u.levels.concat(), elem, files)
}

/// A pipeline the page can draw: its module and bindings.
struct Shipped {
    pipeline: relief_dsl::Pipeline,
    text: String,
    stem: String,
    program: Program,
}

fn ship(p: &relief_dsl::Pipeline) -> Result<Shipped, String> {
    let text = p.to_string();
    if p.lod != Lod::Zero {
        return Err(format!("`{text}`: lod={} reads per-level maps, which the browser data does not ship", p.lod));
    }
    let program = Program::new(p).map_err(|e| format!("`{text}`: {e}"))?;
    Ok(Shipped { pipeline: p.clone(), text, stem: p.file_stem(), program })
}

fn bindings_json(b: &[u32], program: &Program) -> Result<Value, GpuError> {
    b.iter()
        .map(|&n| {
            let resource = gpu::resource_at(&program.bindings, n)?;
            let json = resource_json(resource).ok_or_else(|| {
                GpuError::Pipeline(format!("binding {n} holds {resource:?}, which the page cannot bind"))
            })?;
            Ok(json!([n, json]))
        })
        .collect::<Result<Vec<_>, _>>()
        .map(Value::Array)
}

/// Writes the browser data of the rows of `datas` (every adapter's) into `dir/browser/`.
pub(crate) fn write(datas: &[&Data], dir: &Path) -> Result<Written> {
    let out = dir.join("browser");
    if out.is_dir() {
        std::fs::remove_dir_all(&out).map_err(|source| crate::io::FileError::Clear { path: out.clone(), source })?;
    }
    crate::io::create_dir_all(&out)?;
    let mut w = Written::default();
    let mut files = Files::default();

    // The pipelines: every ok row's, and the exact one.
    let mut pipelines: BTreeMap<String, Shipped> = BTreeMap::new();
    let mut scenes: BTreeMap<String, Vec<u32>> = BTreeMap::new();
    let mut rows = Vec::new();
    for d in datas {
        for r in d.rows.iter().filter(|r| r.status.is_ok() && d.is_indexed(r)) {
            let m = &r.metrics;
            let text = m.pipeline.to_string();
            if !pipelines.contains_key(&text) {
                match ship(&m.pipeline) {
                    Ok(s) => {
                        pipelines.insert(text.clone(), s);
                    }
                    Err(e) => {
                        if !w.set_aside.contains(&e) {
                            w.set_aside.push(e);
                        }
                        continue;
                    }
                }
            }
            let sizes = scenes.entry(m.scene.clone()).or_default();
            if !sizes.contains(&m.size) {
                sizes.push(m.size);
            }
            rows.push(json!({
                "pipeline": text, "scene": m.scene, "size": m.size, "adapter": m.adapter,
                "frame_ms_median": finite(m.frame_ms_median), "frame_ratio_to_baseline": m.frame_ratio_to_baseline,
                "ref_err_t_rms": finite(m.ref_err_t_rms), "avg_fetches": finite(m.avg_fetches), "cell_dir": r.cell_dir,
            }));
        }
    }
    let exact = EXACT
        .parse::<relief_dsl::Pipeline>()
        .map_err(|e| e.to_string())
        .and_then(|p| ship(&p))
        .map_err(Error::Input)?;
    pipelines.entry(exact.text.clone()).or_insert(exact);

    let mut pjson = Vec::new();
    for s in pipelines.values() {
        let wgsl = relief_dsl::emit::emit(&s.pipeline)?.wgsl;
        let wgsl = data_file(
            &out,
            &format!("wgsl/{}", s.stem),
            json!({ "pipeline": s.text }),
            wgsl.as_bytes(),
            1,
            &mut files,
        )?;
        let render = bindings_json(&s.program.render_bindings, &s.program)?;
        let probe = bindings_json(&s.program.probe_bindings, &s.program)?;
        let maps: Vec<String> = s.program.maps.iter().filter_map(|r| MapKey::of(*r)).map(map_slug).collect();
        pjson.push(json!({
            "pipeline": s.text, "wgsl": wgsl, "render_bindings": render, "probe_bindings": probe,
            "maps": maps, "writes_depth": s.program.writes_depth,
        }));
    }

    let mut sjson = Vec::new();
    for (label, sizes) in &scenes {
        let scene = match scene_from_arg(label) {
            Ok(s) => s,
            Err(e) => {
                w.set_aside.push(format!("scene {label}: {e}"));
                continue;
            }
        };
        sjson.push(write_scene(&out, label, &scene, sizes, pipelines.values(), &mut files)?);
    }
    let (members, size) = params_layout();
    let manifest = json!({
        "params": { "size": size, "members": members.iter().map(|(n, t, o, s)| json!({ "name": n, "type": t, "offset": o, "size": s })).collect::<Vec<_>>() },
        "bindings": { "params": binding::PARAMS, "height": binding::HEIGHT, "linear": binding::LINEAR_SAMPLER, "nearest": binding::NEAREST_SAMPLER,
                      "normal": binding::NORMAL, "albedo": binding::ALBEDO, "nearest_offset": binding::NEAREST_OFFSET, "rays": binding::RAYS, "hits": binding::HITS },
        "probe_workgroup": relief_dsl::abi::PROBE_WORKGROUP,
        "ray_bytes": std::mem::size_of::<relief_dsl::abi::ProbeRay>(),
        "max_probe_rays": MAX_PROBE_RAYS,
        "hit_bytes": std::mem::size_of::<relief_dsl::abi::ProbeHit>(),
        "ambient": gpu::AMBIENT,
        "clear": [0.02, 0.02, 0.03, 1.0],
        "frame_format": "rgba8unorm-srgb",
        "min_block_ms": gpu::MIN_BLOCK_MS,
        "max_frames_per_block": gpu::MAX_FRAMES_PER_BLOCK,
        "exact": EXACT,
        "pipelines": pjson,
        "scenes": sjson,
        "rows": rows,
        "set_aside": w.set_aside,
        "relief_version": env!("CARGO_PKG_VERSION"),
    });
    let path = out.join("manifest.js");
    crate::io::write_atomic(&path, format!("window.RELIEF_MANIFEST = {manifest};\n").as_bytes())?;
    w.files.push(path);
    w.files.extend(files.written);
    w.pipelines = pipelines.len();
    Ok(w)
}

fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

/// `scene` with its heights as the device stores them (level 0 of `uploads`, the surface
/// the probe hits are scored on).
pub(crate) fn on_device(scene: &Scene, uploads: &gpu::SceneUploads) -> Scene {
    let mut s = scene.clone();
    s.height.data = uploads.height_levels[0].data.clone();
    s
}

/// The probe rays the page probes for one scene and size, with their exact hits.
pub(crate) struct ProbeSet {
    /// Every `stride`-th ray of [`Scene::rays`].
    pub rays: Vec<ProbeRay>,
    /// [`probe_stride`] of `all`.
    pub stride: usize,
    /// The exact first hit of each of `rays` on the heights as stored ([`on_device`]).
    pub refs: Vec<Option<RefHit>>,
}

/// The probed rays of `on_device` (a scene from [`on_device`], labelled `label`) at
/// `size²` and their exact hits: what the page probes and what `--add` scores it against.
pub(crate) fn probe_set(label: &str, on_device: &Scene, size: u32) -> Result<ProbeSet> {
    let (rays, _, stride) = shipped_rays(on_device, size);
    let refs = reference_hits(on_device, &rays, Sampling::Bilinear).map_err(|e| Error::from(e).in_scene(label))?;
    Ok(ProbeSet { rays, stride, refs })
}

/// The probe rays the page probes for `scene` at `size²`: every `stride`-th ray of [`Scene::rays`],
/// with the frame's ray count and the stride.
fn shipped_rays(scene: &Scene, size: u32) -> (Vec<ProbeRay>, usize, usize) {
    let all = scene.rays(size);
    let stride = probe_stride(all.len());
    (all.iter().step_by(stride).copied().collect(), all.len(), stride)
}

/// The f32 values [`Scene::rays`] computes a frame's rays from, as bit patterns (`u32`, so
/// that no decimal round trip can change them): the eye, the camera's basis and
/// `tan(fov_y / 2)` ([`crate::scene::Camera::ray_terms`]), the depth scale and the tiling.
/// The page's `probeRays` (`web/live.js`) repeats `Scene::rays` on them with every operation
/// rounded to f32 (`Math.fround`), which gives the same bits: `+ − × ÷ √` computed in f64 and
/// rounded to f32 are the f32 operations' correctly rounded results.
pub(crate) fn rays_from(scene: &Scene) -> Value {
    let c = &scene.camera;
    let (f, r, u, ty) = c.ray_terms();
    let bits = |v: glam::Vec3| [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()];
    json!({
        "eye": bits(c.camera_position()), "forward": bits(f), "right": bits(r), "up": bits(u),
        "tan_half_fov": ty.to_bits(), "depth_scale": scene.depth_scale.to_bits(), "tiling": scene.tiling.to_bits(),
    })
}

/// The manifest entry of a map the page computes itself from the scene's height file instead
/// of loading it, or `None` for a map shipped as a data file. The patch map is computed too
/// (`cellPatch` in `web/live.js`; its entry gives the cell grid's size and the height map's).
/// The distance field is computed
/// (`distanceField` in `web/live.js`, a port of [`crate::maps::distance_field`] that gives its
/// f32 values bit for bit): at 256² × 64 it was a third of `browser/` in the main job (21.2 of
/// 67.9 MB), and headless Chromium rebuilds it from the heights in 0.3 to 2 s (on a loaded
/// two-core machine), once per scene, when a pipeline that reads it is first drawn or probed.
/// The entry names its kind, z resolution,
/// edge mode and size (width, height, slices); the heights are level 0 of the scene's height
/// file, which is the map the runtime builds from ([`gpu::scene_uploads`]).
fn computed_in_page(scene: &Scene, k: MapKey) -> Option<Value> {
    match k.kind {
        MapKind::DistanceField => {
            let z = k.params.z_resolution;
            Some(json!({
                "computed_in_page": k.kind.name(), "z_resolution": z, "edge": edge_name(scene.edge),
                "size": [scene.height.width, scene.height.height, z],
            }))
        }
        MapKind::CellPatch => {
            // One pass over the cells of level 0 (`cellPatch` in `web/live.js`, the f32
            // differences of `maps::cell::patch` in the same order, bit for bit): the
            // largest of a scene's maps as a data file (4 floats a cell), a loop in the page.
            let grid = crate::maps::cell::CellGrid::new(scene.height.width, scene.height.height, scene.edge);
            Some(json!({
                "computed_in_page": k.kind.name(), "edge": edge_name(scene.edge),
                "size": [grid.cw, grid.ch], "height_size": [scene.height.width, scene.height.height],
            }))
        }
        MapKind::Cone
        | MapKind::QuadCone
        | MapKind::RelaxedCone
        | MapKind::ConeNormal
        | MapKind::RelaxedConeNormal
        | MapKind::MultiCone
        | MapKind::PiecewiseCone
        | MapKind::MaxMip
        | MapKind::CellCone
        | MapKind::CellQuadCone
        | MapKind::CellRelaxedCone
        | MapKind::CellConeNormal
        | MapKind::CellMultiCone
        | MapKind::CellPiecewiseCone => None,
    }
}

/// The edge mode as the manifest and the page name it.
fn edge_name(edge: EdgeMode) -> &'static str {
    match edge {
        EdgeMode::Clamp => "clamp",
        EdgeMode::Repeat => "repeat",
    }
}

/// One scene's textures and maps, and its manifest entry (with what the page needs to compute
/// the probe rays).
fn write_scene<'a>(
    out: &Path,
    label: &str,
    scene: &Scene,
    sizes: &[u32],
    pipelines: impl Iterator<Item = &'a Shipped>,
    files: &mut Files,
) -> Result<Value> {
    let slug = scene_slug(label);
    let base = format!("scenes/{slug}");
    let u = gpu::scene_uploads(scene, true);
    let height = texture_file(out, &format!("{base}/height"), &u.height, files)?;
    let normal = texture_file(out, &format!("{base}/normal"), &u.normal, files)?;
    let albedo = texture_file(out, &format!("{base}/albedo"), &u.albedo, files)?;
    let mut keys: Vec<MapKey> = Vec::new();
    for p in pipelines {
        for k in p.program.maps.iter().filter_map(|r| MapKey::of(*r)) {
            if !keys.contains(&k) {
                keys.push(k);
            }
        }
    }
    let mut maps = serde_json::Map::new();
    for k in keys {
        let entry = match computed_in_page(scene, k) {
            Some(entry) => entry,
            None => {
                let name = format!("{base}/map_{}", map_slug(k));
                json!(texture_file(out, &name, &gpu::map_upload_of(scene, k)?, files)?)
            }
        };
        maps.insert(map_slug(k), entry);
    }
    let mut probes = serde_json::Map::new();
    let mut measured = serde_json::Map::new();
    for &size in sizes {
        // The rays are not shipped: the page computes them from `rays_from` (`probeRays` in
        // `web/live.js`), and `--add` traces their exact hits again.
        let (rays, all, stride) = shipped_rays(scene, size);
        probes.insert(size.to_string(), json!({ "rays": rays.len(), "all_rays": all, "stride": stride }));
        let p = gpu::params_for(scene, 1.0, scene.camera.pixel_size(size));
        measured.insert(size.to_string(), json!(bytemuck::cast_slice::<Params, f32>(&[p])));
    }
    let c = &scene.camera;
    Ok(json!({
        "label": label, "slug": slug,
        "camera": { "angle_deg": c.angle_deg, "azimuth_deg": c.azimuth_deg, "distance": c.distance, "fov_deg": c.fov_deg, "target": [c.target.x, c.target.y, c.target.z] },
        "depth_scale": scene.depth_scale, "tiling": scene.tiling, "edge": edge_name(scene.edge),
        "light_dir": [scene.light_dir.x, scene.light_dir.y, scene.light_dir.z],
        "height_size": [scene.height.width, scene.height.height],
        "textures": { "height": height, "normal": normal, "albedo": albedo },
        "maps": maps, "probe": probes, "rays_from": rays_from(scene), "params_measured": measured, "sizes": sizes,
    }))
}

/// The page's live section: two pipelines side by side and the measure button (their
/// script is `web/live.js`), or why there is no browser data.
pub(crate) fn section(w: &Result<Written>) -> super::html::PageSection {
    use super::html::esc;
    let mut h = String::from("<h2>Live: the pipelines on your GPU</h2>\n");
    match w {
        Err(e) => {
            let _ = writeln!(h, "<p>No browser data was written: {}</p>", esc(&e.to_string()));
        }
        Ok(w) => {
            h.push_str(LIVE_HTML);
            if !w.set_aside.is_empty() {
                let _ = writeln!(h, "<p>Not in the browser data: {}.</p>", esc(&w.set_aside.join("; ")));
            }
            let _ = writeln!(h, "<script src=\"browser/manifest.js\"></script>\n<script>{LIVE_SCRIPT}</script>");
        }
    }
    super::html::PageSection { id: "live".into(), nav: "Live".into(), html: h }
}

/// The live section's script.
const LIVE_SCRIPT: &str = include_str!("../../web/live.js");
/// The live section's controls.
const LIVE_HTML: &str = include_str!("../../web/live.html");

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_params_layout_is_the_abi_struct() {
        let (members, size) = params_layout();
        assert_eq!(size, std::mem::size_of::<Params>());
        // Every member at its field's offset in the #[repr(C)] struct.
        let p = Params::default();
        let base = &p as *const Params as usize;
        let fields = [
            &p.view_proj as *const _ as usize,
            &p.camera as *const _ as usize,
            &p.light as *const _ as usize,
            &p.quad as *const _ as usize,
            &p.pixel_right as *const _ as usize,
            &p.pixel_up as *const _ as usize,
        ];
        assert_eq!(members.len(), fields.len());
        for ((name, _, off, _), f) in members.iter().zip(fields) {
            assert_eq!(*off, f - base, "{name}");
        }
    }

    /// The same content under a second name is not written again: the second name loads the
    /// first file; other bytes or another meta make a file of their own.
    #[test]
    fn a_content_written_twice_is_one_file() {
        let dir = std::env::temp_dir().join(format!("relief-browser-files-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut files = Files::default();
        let bytes: Vec<u8> = (0..64u8).collect();
        let a = data_file(&dir, "a/height", json!({ "width": 4 }), &bytes, 4, &mut files).unwrap();
        let b = data_file(&dir, "b/height", json!({ "width": 4 }), &bytes, 4, &mut files).unwrap();
        let c = data_file(&dir, "c/height", json!({ "width": 8 }), &bytes, 4, &mut files).unwrap();
        let d = data_file(&dir, "d/height", json!({ "width": 4 }), &bytes[1..], 4, &mut files).unwrap();
        assert_eq!((a.as_str(), b.as_str(), c.as_str(), d.as_str()), ("a/height", "a/height", "c/height", "d/height"));
        assert_eq!(files.written.len(), 3);
        assert!(!dir.join("b/height.js").exists());
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn probe_strides_keep_at_most_the_cap() {
        for n in [0, 1, 4096, MAX_PROBE_RAYS, MAX_PROBE_RAYS + 1, 262_144] {
            let s = probe_stride(n);
            assert!(n.div_ceil(s) <= MAX_PROBE_RAYS, "{n}");
            assert!(s == 1 || n.div_ceil(s - 1) > MAX_PROBE_RAYS, "{n}: stride {s} is larger than needed");
        }
    }

    #[test]
    fn packed_bytes_inflate_and_unshuffle_to_the_input() {
        use std::io::Read as _;
        // 4-byte elements with a 3-byte tail, and 1-byte elements (no shuffle).
        let bytes: Vec<u8> = (0..4099u32).map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8).collect();
        for elem in [1, 2, 4] {
            let planes = shuffle(&bytes, elem);
            assert_eq!(planes.len(), bytes.len());
            let n = bytes.len() / elem;
            // Byte b of element i at b * n + i, the tail last (what `unshuffle` in live.js reads).
            for i in [0, 1, n / 2, n - 1] {
                for b in 0..elem {
                    assert_eq!(planes[b * n + i], bytes[i * elem + b], "elem {elem}, element {i}, byte {b}");
                }
            }
            assert_eq!(planes[n * elem..], bytes[n * elem..]);
            let mut inflated = Vec::new();
            flate2::read::GzDecoder::new(&pack(&bytes, elem).unwrap()[..]).read_to_end(&mut inflated).unwrap();
            assert_eq!(inflated, planes, "elem {elem}");
        }
    }
}
