//! Bevy draws relief's quad from a `relief export PIPELINE --scene MAP --target wgsl` bundle
//! and compares the frame with `relief render`'s.
//!
//! ```text
//! relief-bevy BUNDLE RENDER OUT.png
//! ```
//!
//! `BUNDLE` is the export folder (the WGSL library, the `.ktx2` maps, `relief.json`), `RENDER`
//! a `relief render PIPELINE --scene MAP --size N --out RENDER` folder (its `metrics.json`
//! gives the camera and the frame size, its `frame.png` the reference). Bevy does the rest:
//! its asset server loads every map with its own KTX2 loader (levels, format and sampler as
//! `relief.json` says), its `Camera3d` renders headless into an image, its mesh pipeline draws
//! the quad with an `ExtendedMaterial<StandardMaterial, ReliefExtension>` whose fragment
//! shader (`assets/relief_material.wgsl`) imports the library through naga_oil as
//! `relief::bundle`, and `Screenshot::image` reads the frame back. The program writes it to
//! `OUT.png`, prints the mean absolute difference (of 255) and the share of pixels off by more
//! than 8 against `frame.png`, and exits 1 when the bar (≤ 1 of 255, ≤ 1 %) is missed.
//!
//! The bundle is exported with `--group 3 --import-path relief::bundle`: its library declares
//! its globals in Bevy 0.19's material group (`MATERIAL_BIND_GROUP_INDEX`) and names itself
//! for naga_oil. The example checks both in `relief.json` and makes one edit a Bevy user makes
//! too (`library_for_bevy`): each global moves to the binding of its `AsBindGroup` slot.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use bevy::app::ScheduleRunnerPlugin;
use bevy::asset::{AssetMetaCheck, RenderAssetUsages, io::AssetSourceBuilder};
use bevy::camera::RenderTarget;
use bevy::core_pipeline::tonemapping::{DebandDither, Tonemapping};
use bevy::image::{ImageAddressMode, ImageFilterMode, ImageLoaderSettings, ImageSampler, ImageSamplerDescriptor};
use bevy::mesh::{Indices, PrimitiveTopology};
use bevy::pbr::{ExtendedMaterial, MATERIAL_BIND_GROUP_INDEX, MaterialExtension};
use bevy::prelude::*;
use bevy::render::RenderPlugin;
use bevy::render::error_handler::{RenderErrorHandler, RenderErrorPolicy};
use bevy::render::render_resource::{AsBindGroup, TextureDimension, TextureFormat, TextureUsages};
use bevy::render::view::Msaa;
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured};
use bevy::shader::ShaderRef;
use bevy::window::ExitCondition;
use serde_json::Value;

/// The material's fragment shader, under `assets/`.
const MATERIAL_SHADER: &str = "relief_material.wgsl";

/// The bindings (in the material's group) of the library's textures; each texture's sampler
/// is the next binding. A library sampler is bound as the sampler of a library texture with
/// the same filter and address mode (`slots`).
const TEXTURE_SLOTS: [u32; 4] = [100, 102, 104, 106];

/// The goal the three.js and Babylon.js tests hold engines to: mean absolute difference ≤ 1
/// of 255 and at most 1 % of pixels off by more than 8 in a channel.
const BAR_MAD: f64 = 1.0;
const BAR_SHARE: f64 = 0.01;

/// relief's resources at the material's bind group (the library's textures and samplers at
/// [`TEXTURE_SLOTS`]) and what the shading needs: the albedo and normal maps (sampled with
/// linear filtering at level 0, the bundle's edge mode) and the constants of `relief.json`'s
/// `shading`.
#[derive(Asset, AsBindGroup, Reflect, Debug, Clone, Default)]
struct ReliefExtension {
    #[texture(100)]
    #[sampler(101)]
    map0: Option<Handle<Image>>,
    #[texture(102)]
    #[sampler(103)]
    map1: Option<Handle<Image>>,
    #[texture(104)]
    #[sampler(105)]
    map2: Option<Handle<Image>>,
    #[texture(106)]
    #[sampler(107)]
    map3: Option<Handle<Image>>,
    #[texture(120)]
    #[sampler(121)]
    albedo: Handle<Image>,
    #[texture(122)]
    #[sampler(123)]
    normal: Handle<Image>,
    /// xyz: the direction toward the light (tangent space = world); w: the ambient share.
    #[uniform(130)]
    light: Vec4,
    /// x: the relief's depth scale.
    #[uniform(131)]
    relief: Vec4,
}

impl MaterialExtension for ReliefExtension {
    fn fragment_shader() -> ShaderRef {
        MATERIAL_SHADER.into()
    }
}

type ReliefMaterial = ExtendedMaterial<StandardMaterial, ReliefExtension>;

/// What the run needs besides the ECS: the reference frame, where to write Bevy's, what to
/// wait for before the screenshot.
#[derive(Resource)]
struct Run {
    pipeline: String,
    reference: Vec<u8>,
    size: u32,
    out: PathBuf,
    target: Handle<Image>,
    images: Vec<Handle<Image>>,
    material_shader: Handle<Shader>,
    _library: Handle<Shader>,
    ready_frames: u32,
    frames: u32,
}

fn main() -> ExitCode {
    match setup_app() {
        Ok(mut app) => match app.run() {
            AppExit::Success => ExitCode::SUCCESS,
            AppExit::Error(code) => ExitCode::from(code.get()),
        },
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

/// Reads the arguments and the two folders' json, and builds the app.
fn setup_app() -> Result<App, String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [bundle, render, out] = args.as_slice() else {
        return Err("usage: relief-bevy BUNDLE RENDER OUT.png (an export folder, a relief render folder)".into());
    };
    let bundle = std::fs::canonicalize(bundle).map_err(|e| format!("{bundle}: {e}"))?;
    let render = PathBuf::from(render);
    let json = read_json(&bundle.join("relief.json"))?;
    let metrics = read_json(&render.join("metrics.json"))?;
    let (reference, size) = read_png_rgba8(&render.join("frame.png"))?;
    if metrics["size"].as_u64() != Some(size as u64) {
        return Err(format!("{}: frame.png is {size}² but metrics.json says {}", render.display(), metrics["size"]));
    }
    if json["target"] != "wgsl" {
        return Err(format!("{}: a {} bundle; Bevy takes `--target wgsl`", bundle.display(), json["target"]));
    }
    let slots = slots(&json)?;
    let lib_file = json["library"][0].as_str().ok_or("relief.json names no library file")?;
    let lib_text = std::fs::read_to_string(bundle.join(lib_file)).map_err(|e| format!("{lib_file}: {e}"))?;
    let library = library_for_bevy(&lib_text, &json, &slots)?;

    let mut app = App::new();
    let bundle_str = bundle.to_str().ok_or("the bundle's path is not UTF-8")?.to_string();
    app.register_asset_source("bundle", AssetSourceBuilder::platform_default(&bundle_str, None));
    app.add_plugins((
        DefaultPlugins
            .set(WindowPlugin { primary_window: None, exit_condition: ExitCondition::DontExit, ..default() })
            .set(AssetPlugin {
                file_path: concat!(env!("CARGO_MANIFEST_DIR"), "/assets").into(),
                meta_check: AssetMetaCheck::Never,
                ..default()
            })
            .set(RenderPlugin { synchronous_pipeline_compilation: true, ..default() }),
        ScheduleRunnerPlugin::run_loop(std::time::Duration::from_millis(1)),
        MaterialPlugin::<ReliefMaterial>::default(),
    ));
    let library =
        app.world_mut().resource_mut::<Assets<Shader>>().add(Shader::from_wgsl(library, "relief_bundle.wgsl"));
    let setup = Setup { json, metrics, slots, size, library };
    let pipeline = setup.json["pipeline"].as_str().unwrap_or("?").to_string();
    app.insert_resource(PendingRun(Some((setup, reference, PathBuf::from(out), pipeline))));
    // Without Bevy's log plugin (not built here) a render error would end the app silently.
    app.insert_resource(RenderErrorHandler(|error, main_world, _| {
        eprintln!(
            "error: Bevy's renderer: {:?}: {}",
            error.ty,
            error.description.split_whitespace().collect::<Vec<_>>().join(" ")
        );
        main_world.write_message(AppExit::error());
        RenderErrorPolicy::StopRendering
    }));
    app.add_systems(Startup, spawn_scene);
    app.add_systems(Update, (keep_maps_2d, capture_when_ready).chain());
    Ok(app)
}

/// The parsed inputs, handed from `setup_app` to the startup system.
struct Setup {
    json: Value,
    metrics: Value,
    slots: Vec<Slot>,
    size: u32,
    library: Handle<Shader>,
}

#[derive(Resource)]
struct PendingRun(Option<(Setup, Vec<u8>, PathBuf, String)>);

/// Where one of `relief.json`'s bindings goes in the material's group.
#[derive(Clone, Debug)]
struct Slot {
    name: String,
    /// relief's binding number (in group 0, as exported).
    binding: u64,
    /// The binding in the material's group.
    slot: u32,
    /// For a texture, its file, filter and address mode.
    texture: Option<(String, String, String)>,
}

/// Assigns each library texture a slot of [`TEXTURE_SLOTS`] in binding order, and each
/// library sampler the sampler binding of the first texture with its filter and address mode.
fn slots(json: &Value) -> Result<Vec<Slot>, String> {
    let bindings = json["bindings"].as_array().ok_or("relief.json has no bindings")?;
    let mut out: Vec<Slot> = Vec::new();
    let field = |b: &Value, k: &str| b[k].as_str().map(str::to_string).ok_or(format!("a binding without `{k}`: {b}"));
    for b in bindings.iter().filter(|b| b["kind"] != "sampler") {
        if b["kind"] != "texture_2d" {
            return Err(format!("{}: a {} binding; this example binds 2D textures only", b["name"], b["kind"]));
        }
        let k = out.len();
        let slot = *TEXTURE_SLOTS.get(k).ok_or("more library textures than this example's four slots")?;
        out.push(Slot {
            name: field(b, "name")?,
            binding: b["binding"].as_u64().ok_or("a binding without a number")?,
            slot,
            texture: Some((field(b, "file")?, field(b, "filter")?, field(b, "address_mode")?)),
        });
    }
    for b in bindings.iter().filter(|b| b["kind"] == "sampler") {
        let (filter, address) = (field(b, "filter")?, field(b, "address_mode")?);
        let host = out
            .iter()
            .find(|s| matches!(&s.texture, Some((_, f, a)) if *f == filter && *a == address))
            .ok_or(format!("{}: no library texture has a {filter} {address} sampler to lend it", b["name"]))?;
        out.push(Slot {
            name: field(b, "name")?,
            binding: b["binding"].as_u64().ok_or("a binding without a number")?,
            slot: host.slot + 1,
            texture: None,
        });
    }
    Ok(out)
}

/// The import path the material shader imports the library by.
const IMPORT_PATH: &str = "relief::bundle";

/// The bundle's library (exported with `--group 3 --import-path relief::bundle`, which
/// `relief.json` must say) with each `@group(3) @binding(k)` at the binding of its slot
/// (Bevy's `AsBindGroup` pairs a texture with its sampler), and a library without a shadow or
/// ambient-occlusion stage given `relief_shadow` / `relief_ao` returning 1, the value `relief
/// render` shades with then.
fn library_for_bevy(text: &str, json: &Value, slots: &[Slot]) -> Result<String, String> {
    let group = MATERIAL_BIND_GROUP_INDEX as u64;
    if json["group"].as_u64() != Some(group) || json["import_path"] != IMPORT_PATH {
        return Err(format!(
            "the bundle was not exported for Bevy's material group: pass `relief export … --group {group} --import-path {IMPORT_PATH}`"
        ));
    }
    let mut out = String::new();
    let mut moved = 0;
    let lines: Vec<&str> = text.lines().collect();
    let at = format!("@group({group}) @binding(");
    for (i, line) in lines.iter().enumerate() {
        let Some(rest) = line.trim_start().strip_prefix(at.as_str()) else {
            out.push_str(line);
            out.push('\n');
            continue;
        };
        let k: u64 =
            rest.split(')').next().and_then(|n| n.parse().ok()).ok_or(format!("library line {}: {line}", i + 1))?;
        let slot = slots.iter().find(|s| s.binding == k).ok_or(format!("library binding {k} is not in relief.json"))?;
        // The declaration follows on the same or the next line; it must name the same global.
        let decl = format!("{} {}", line, lines.get(i + 1).unwrap_or(&""));
        if !decl.contains(&format!(" {}:", slot.name)) {
            return Err(format!("library binding {k} does not declare {}", slot.name));
        }
        out.push_str(&format!("@group({group}) @binding({})\n", slot.slot));
        moved += 1;
    }
    if moved != slots.len() {
        return Err(format!("the library declares {moved} globals, relief.json lists {}", slots.len()));
    }
    if json["has_shadow"] != true {
        out.push_str(
            "fn relief_shadow(hit: ReliefHit, light_ts: vec3<f32>, depth_scale: f32) -> f32 { return 1.0; }\n",
        );
    }
    if json["has_ao"] != true {
        out.push_str("fn relief_ao(hit: ReliefHit) -> f32 { return 1.0; }\n");
    }
    Ok(out)
}

fn spawn_scene(
    mut commands: Commands,
    mut pending: ResMut<PendingRun>,
    asset_server: Res<AssetServer>,
    mut images: ResMut<Assets<Image>>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<ReliefMaterial>>,
) {
    let (setup, reference, out, pipeline) = pending.0.take().expect("the run's inputs");
    let Setup { json, metrics, slots, size, library, .. } = setup;
    let edge = json["edge"].as_str().unwrap_or("repeat").to_string();
    let mut loaded = Vec::new();
    let mut load = |file: &str, filter: &str, address: &str, srgb: bool| -> Handle<Image> {
        let sampler = sampler(filter, address);
        let h: Handle<Image> = asset_server
            .load_builder()
            .with_settings(move |s: &mut ImageLoaderSettings| {
                s.is_srgb = srgb;
                s.sampler = ImageSampler::Descriptor(sampler.clone());
            })
            .load(format!("bundle://{file}"));
        loaded.push(h.clone());
        h
    };
    let mut maps: [Option<Handle<Image>>; 4] = Default::default();
    for s in &slots {
        if let Some((file, filter, address)) = &s.texture {
            let k = TEXTURE_SLOTS.iter().position(|&t| t == s.slot).expect("a texture slot");
            maps[k] = Some(load(file, filter, address, false));
        }
    }
    // Bevy's KTX2 loader takes sRGB or linear from the settings' `is_srgb` (default true),
    // not from the file's format: the normal map must say `false`.
    let tex = &json["textures"];
    let shading_map = |k: &str| {
        let srgb = tex[k]["format"].as_str().is_some_and(|f| f.ends_with("Srgb"));
        (tex[k]["file"].as_str().unwrap_or_default().to_string(), srgb)
    };
    let ((albedo_file, albedo_srgb), (normal_file, normal_srgb)) = (shading_map("albedo"), shading_map("normal"));
    let albedo = load(&albedo_file, "linear", &edge, albedo_srgb);
    let normal = load(&normal_file, "linear", &edge, normal_srgb);
    let shading = &json["shading"];
    let l = |k: usize| shading["light_dir"][k].as_f64().unwrap_or(0.0) as f32;
    let ambient = shading["ambient"].as_f64().unwrap_or(0.25) as f32;
    let depth = json["depth_scale"].as_f64().unwrap_or(0.1) as f32;
    let tiling = json["tiling"].as_f64().unwrap_or(1.0) as f32;
    let [m0, m1, m2, m3] = maps;
    let material = materials.add(ExtendedMaterial {
        base: StandardMaterial { cull_mode: None, unlit: true, ..default() },
        extension: ReliefExtension {
            map0: m0,
            map1: m1,
            map2: m2,
            map3: m3,
            albedo,
            normal,
            light: Vec4::new(l(0), l(1), l(2), ambient),
            relief: Vec4::new(depth, 0.0, 0.0, 0.0),
        },
    });
    commands.spawn((Mesh3d(meshes.add(quad(tiling))), MeshMaterial3d(material), Transform::IDENTITY));

    // relief's camera (`Camera::default_for` and `metrics.json`'s `camera`): it orbits the
    // quad's centre; the screen's up lies in the vertical plane through eye and target.
    let cam = &metrics["camera"];
    let f = |k: &str| cam[k].as_f64().unwrap_or(0.0) as f32;
    let (a, az) = (f("angle_deg").to_radians(), f("azimuth_deg").to_radians());
    let target = Vec3::new(0.5 * tiling, 0.5 * tiling, 0.0);
    let eye = target + f("distance") * Vec3::new(a.sin() * az.cos(), a.sin() * az.sin(), a.cos());
    let up = Vec3::new(-a.cos() * az.cos(), -a.cos() * az.sin(), a.sin());
    let clear = shading["clear_color_linear"]
        .as_array()
        .map(|c| c.iter().map(|x| x.as_f64().unwrap_or(0.0) as f32).collect::<Vec<_>>());
    let clear = clear.filter(|c| c.len() == 4).unwrap_or(vec![0.0, 0.0, 0.0, 1.0]);
    let mut target_image = Image::new_target_texture(size, size, TextureFormat::Rgba8UnormSrgb, None);
    // The screenshot copies from the target.
    target_image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
    let target_handle = images.add(target_image);
    commands.spawn((
        Camera3d::default(),
        Camera {
            clear_color: ClearColorConfig::Custom(Color::linear_rgba(clear[0], clear[1], clear[2], clear[3])),
            ..default()
        },
        RenderTarget::Image(target_handle.clone().into()),
        Projection::Perspective(PerspectiveProjection {
            fov: f("fov_deg").to_radians(),
            aspect_ratio: 1.0,
            near: f("distance") * 0.01,
            far: f("distance") * 100.0,
            ..default()
        }),
        Transform::from_translation(eye).looking_at(target, up),
        Tonemapping::None,
        DebandDither::Disabled,
        Msaa::Off,
    ));
    let material_shader = asset_server.load(MATERIAL_SHADER);
    commands.insert_resource(Run {
        pipeline,
        reference,
        size,
        out,
        target: target_handle,
        images: loaded,
        material_shader,
        _library: library,
        ready_frames: 0,
        frames: 0,
    });
}

/// An image sampler from a binding's filter and address mode (no mipmap blending: the
/// library reads given levels).
fn sampler(filter: &str, address: &str) -> ImageSamplerDescriptor {
    let filter = if filter == "nearest" { ImageFilterMode::Nearest } else { ImageFilterMode::Linear };
    let address = if address == "clamp" { ImageAddressMode::ClampToEdge } else { ImageAddressMode::Repeat };
    ImageSamplerDescriptor {
        address_mode_u: address,
        address_mode_v: address,
        address_mode_w: address,
        mag_filter: filter,
        min_filter: filter,
        mipmap_filter: ImageFilterMode::Nearest,
        ..default()
    }
}

/// relief's quad: [0, tiling]² on z = 0 with uv = position (u along x, v along y), facing +z.
fn quad(tiling: f32) -> Mesh {
    let c = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]].map(|[x, y]: [f32; 2]| [x * tiling, y * tiling]);
    Mesh::new(PrimitiveTopology::TriangleList, RenderAssetUsages::default())
        .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, c.iter().map(|&[x, y]| [x, y, 0.0]).collect::<Vec<_>>())
        .with_inserted_attribute(Mesh::ATTRIBUTE_NORMAL, vec![[0.0f32, 0.0, 1.0]; 4])
        .with_inserted_attribute(Mesh::ATTRIBUTE_UV_0, c.to_vec())
        .with_inserted_indices(Indices::U32(vec![0, 1, 2, 2, 1, 3]))
}

/// Bevy's KTX2 loader makes a file one texel high a 1D texture (`TextureDimension::D1`),
/// which a `texture_2d` binding refuses (the `rocks` scene's albedo is 1×1): such a map is
/// made 2D again in the frame it arrives, before the render world prepares it.
fn keep_maps_2d(run: Res<Run>, mut images: ResMut<Assets<Image>>) {
    for h in &run.images {
        if images.get(h.id()).is_some_and(|i| i.texture_descriptor.dimension == TextureDimension::D1)
            && let Some(mut image) = images.get_mut(h.id())
        {
            image.texture_descriptor.dimension = TextureDimension::D2;
        }
    }
}

/// Waits until every map and the material shader are loaded, lets a few frames pass (the
/// material's bind group and pipeline are prepared in the render world), then asks for a
/// screenshot of the target; gives up after a while with an error.
fn capture_when_ready(
    mut commands: Commands,
    mut run: ResMut<Run>,
    asset_server: Res<AssetServer>,
    mut exit: MessageWriter<AppExit>,
) {
    run.frames += 1;
    if run.frames > 2000 {
        eprintln!("error: nothing captured after 2000 frames (assets or pipeline never ready)");
        exit.write(AppExit::error());
        return;
    }
    for h in &run.images {
        if let Some(bevy::asset::LoadState::Failed(e)) = asset_server.get_load_state(h.id()) {
            eprintln!("error: Bevy could not load {:?}: {e}", h.path());
            exit.write(AppExit::error());
            return;
        }
    }
    let ready = run.images.iter().all(|h| asset_server.is_loaded_with_dependencies(h.id()))
        && asset_server.is_loaded_with_dependencies(run.material_shader.id());
    if !ready {
        return;
    }
    run.ready_frames += 1;
    if run.ready_frames == 5 {
        commands.spawn(Screenshot::image(run.target.clone())).observe(compare);
    }
}

/// The screenshot's observer: writes the frame, compares it with `relief render`'s, exits.
fn compare(captured: On<ScreenshotCaptured>, run: Res<Run>, mut exit: MessageWriter<AppExit>) {
    let img = &captured.image;
    let rgba = img.data.clone().unwrap_or_default();
    let n = (run.size * run.size * 4) as usize;
    if img.width() != run.size || img.height() != run.size || rgba.len() != n {
        eprintln!(
            "error: the screenshot is {}x{} ({} bytes), not {}²",
            img.width(),
            img.height(),
            rgba.len(),
            run.size
        );
        exit.write(AppExit::error());
        return;
    }
    if let Err(e) = write_png_rgba8(&run.out, run.size, &rgba) {
        eprintln!("error: {}: {e}", run.out.display());
    }
    let (mad, share) = frame_difference(&rgba, &run.reference);
    let met = mad <= BAR_MAD && share <= BAR_SHARE;
    let pairs = || rgba.chunks(4).zip(run.reference.chunks(4));
    let differ = pairs().filter(|(a, b)| a[..3] != b[..3]).count();
    let largest = pairs().flat_map(|(a, b)| (0..3).map(move |c| a[c].abs_diff(b[c]))).max().unwrap_or(0);
    println!(
        "{}: Bevy against relief render at {}²: mean |difference| {mad:.4} of 255, {:.3} % of pixels off by more than 8 (bar ≤ {BAR_MAD}, ≤ {} %: {}); {differ} pixels differ, by at most {largest}",
        run.pipeline,
        run.size,
        share * 100.0,
        BAR_SHARE * 100.0,
        if met { "met" } else { "missed" }
    );
    exit.write(if met { AppExit::Success } else { AppExit::error() });
}

/// Mean absolute difference over the RGB channels (of 255) and the share of pixels whose
/// largest channel difference exceeds 8: the measure of relief's engine tests
/// (`tests/common/frames.rs`).
fn frame_difference(a: &[u8], b: &[u8]) -> (f64, f64) {
    let (mut sum, mut big) = (0u64, 0u64);
    for (pa, pb) in a.chunks(4).zip(b.chunks(4)) {
        let d = (0..3).map(|c| (pa[c] as i32 - pb[c] as i32).unsigned_abs());
        let (s, worst) = d.fold((0u64, 0u32), |(s, w), x| (s + x as u64, w.max(x)));
        sum += s;
        big += (worst > 8) as u64;
    }
    let pixels = (a.len() / 4) as f64;
    (sum as f64 / (3.0 * pixels), big as f64 / pixels)
}

fn read_json(path: &Path) -> Result<Value, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))
}

/// A square RGBA8 PNG (relief render's frame.png), top row first.
fn read_png_rgba8(path: &Path) -> Result<(Vec<u8>, u32), String> {
    let err = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    let file = std::fs::File::open(path).map_err(|e| err(&e))?;
    let mut reader = png::Decoder::new(std::io::BufReader::new(file)).read_info().map_err(|e| err(&e))?;
    let mut buf = vec![0; reader.output_buffer_size().ok_or_else(|| err(&"too large"))?];
    let info = reader.next_frame(&mut buf).map_err(|e| err(&e))?;
    if info.color_type != png::ColorType::Rgba || info.bit_depth != png::BitDepth::Eight || info.width != info.height {
        return Err(err(&"not a square RGBA8 picture"));
    }
    buf.truncate(info.buffer_size());
    Ok((buf, info.width))
}

fn write_png_rgba8(path: &Path, size: u32, rgba: &[u8]) -> Result<(), String> {
    let file = std::fs::File::create(path).map_err(|e| e.to_string())?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), size, size);
    enc.set_color(png::ColorType::Rgba);
    enc.set_depth(png::BitDepth::Eight);
    enc.write_header().and_then(|mut w| w.write_image_data(rgba)).map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `csm(64)`'s bindings as `relief export` lists them (textures and samplers interleaved,
    /// the nearest sampler before the texture that can lend it).
    fn csm_json() -> Value {
        serde_json::json!({
            "has_shadow": false, "has_ao": false, "group": 3, "import_path": "relief::bundle",
            "bindings": [
                { "name": "relief_height", "binding": 0, "kind": "texture_2d", "file": "height.ktx2", "filter": "linear", "address_mode": "repeat" },
                { "name": "relief_sampler", "binding": 1, "kind": "sampler", "filter": "linear", "address_mode": "repeat" },
                { "name": "relief_sampler_nearest", "binding": 2, "kind": "sampler", "filter": "nearest", "address_mode": "repeat" },
                { "name": "relief_cell_cone_nearest", "binding": 3, "kind": "texture_2d", "file": "cell_cone.ktx2", "filter": "nearest", "address_mode": "repeat" }
            ]
        })
    }

    #[test]
    fn samplers_are_lent_by_textures_of_the_same_filter_and_address() {
        let s = slots(&csm_json()).unwrap();
        let at = |n: &str| s.iter().find(|x| x.name == n).unwrap().slot;
        assert_eq!(
            [at("relief_height"), at("relief_sampler"), at("relief_cell_cone_nearest"), at("relief_sampler_nearest")],
            [100, 101, 102, 103]
        );
    }

    #[test]
    fn a_sampler_no_texture_can_lend_is_refused() {
        let mut j = csm_json();
        j["bindings"][3]["filter"] = "linear".into();
        let e = slots(&j).unwrap_err();
        assert!(e.contains("relief_sampler_nearest") && e.contains("nearest repeat"), "{e}");
    }

    #[test]
    fn the_library_moves_to_its_slots_and_gets_shims() {
        let j = csm_json();
        let s = slots(&j).unwrap();
        let lib = "#define_import_path relief::bundle\n@group(3) @binding(0) \nvar relief_height: texture_2d<f32>;\n@group(3) @binding(3) \nvar relief_cell_cone_nearest: texture_2d<f32>;\n@group(3) @binding(2) \nvar relief_sampler_nearest: sampler;\n@group(3) @binding(1) \nvar relief_sampler: sampler;\n";
        let out = library_for_bevy(lib, &j, &s).unwrap();
        let expected = "#define_import_path relief::bundle\n\
            @group(3) @binding(100)\nvar relief_height: texture_2d<f32>;\n\
            @group(3) @binding(102)\nvar relief_cell_cone_nearest: texture_2d<f32>;\n\
            @group(3) @binding(103)\nvar relief_sampler_nearest: sampler;\n\
            @group(3) @binding(101)\nvar relief_sampler: sampler;\n\
            fn relief_shadow(hit: ReliefHit, light_ts: vec3<f32>, depth_scale: f32) -> f32 { return 1.0; }\n\
            fn relief_ao(hit: ReliefHit) -> f32 { return 1.0; }\n";
        assert_eq!(out, expected);
        // A global that relief.json does not name at that binding, or one left out, is refused.
        let swapped = lib.replace("binding(0)", "binding(9)");
        assert!(library_for_bevy(&swapped, &j, &s).unwrap_err().contains("binding 9"));
        let wrong = lib.replace("var relief_height", "var relief_other");
        assert!(library_for_bevy(&wrong, &j, &s).unwrap_err().contains("does not declare relief_height"));
        // A bundle exported without the options (group 0, no import path), or for group 2, is refused.
        for (k, v) in [("group", Value::Null), ("group", 2.into()), ("import_path", Value::Null)] {
            let mut other = j.clone();
            other[k] = v;
            let e = library_for_bevy(&lib.replace("@group(3)", "@group(0)"), &other, &s).unwrap_err();
            assert!(e.contains("--group 3 --import-path relief::bundle"), "{e}");
        }
    }

    /// Two 2-pixel frames worked by hand: pixel 0 differs by (3, 0, 9), pixel 1 by (0, 8, 0).
    #[test]
    fn frame_difference_of_two_hand_made_frames() {
        let (mad, share) = frame_difference(&[10, 20, 30, 255, 0, 100, 255, 0], &[13, 20, 21, 0, 0, 108, 255, 255]);
        assert!((mad - 20.0 / 6.0).abs() < 1e-12, "{mad}");
        assert_eq!(share, 0.5);
    }
}
