//! `relief export`: one pipeline's library for one engine target, with every texture it
//! reads as the runtime uploads it, and `relief.json` saying how to bind each.
//!
//! ```text
//! relief export PIPELINE --scene MAP --target T --out DIR [--container ktx2|dds] [--force]
//!               [--group N] [--import-path PATH]
//! relief export 'csm(64)' --scene scene:rock_bump --target glsl-es --out bundle/
//! ```
//!
//! `DIR` gets the library file(s) of `--target` (a `relief gen --library --target` form,
//! generated with the scene's edge mode), one container per texture the library reads
//! (`height.ktx2`, `cell_cone.ktx2`, …), the scene's `height`, `normal` and `albedo`
//! textures (shading needs the last two even where the library does not read them), and
//! `relief.json`: per binding its global, group and binding, the file, format, filter,
//! address mode, the levels in the file and the levels read (`--group`, and `--import-path`
//! for wgsl, as `relief gen --library` takes them; both recorded); the edge mode and its define;
//! the depth scale; the row order; the lines to paste; the shading of `relief render`. A
//! folder that holds other files is refused unless `--force`.
//!
//! A `curved=` pipeline takes a mesh scene (a scene file with `[mesh]`) and adds the mesh as
//! relief draws it for that mode (`mesh.glb` and `relief.json`'s `mesh`, [`crate::export_mesh`]);
//! a `curved=` pipeline on a flat scene, a flat pipeline on a mesh scene and a target with no
//! mesh form are refused in one line before anything is written.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context};
use relief_dsl::emit::{LibraryBinding, LibraryForm, LibraryOptions, ResourceKind};
use relief_dsl::ir::{Filter, Image, Resource};
use relief_dsl::spec::Curved;
use relief_runtime::gpu::{self, Upload};
use relief_runtime::{scene_from_arg, scene_spec, EdgeMode, MapKey};

/// Arguments of `relief export`.
#[derive(clap::Args, Debug, Clone)]
pub struct ExportArgs {
    /// The pipeline, in the text form (`csm(64)`, `maxmip(96)+shadow=soft(16)`).
    pub pipeline: String,
    /// The scene whose maps are exported: `scene:NAME`, a bare NAME or a TOML scene file.
    #[arg(long)]
    pub scene: String,
    /// The library form (one of `relief gen --library --target`'s: wgsl, wesl, glsl,
    /// glsl-es, tsl, hlsl, msl, unity, unreal).
    #[arg(long)]
    pub target: String,
    /// The texture container: ktx2 (three.js, Babylon.js, Bevy, Godot) or dds (Unity, Unreal).
    #[arg(long, default_value = "ktx2")]
    pub container: String,
    /// The bind group (descriptor set, register space) the library declares its resources in
    /// (default 0), for the targets whose resources carry one: wgsl, wesl, glsl, hlsl.
    #[arg(long)]
    pub group: Option<u32>,
    /// For --target wgsl: start the library with `#define_import_path PATH` (naga_oil, Bevy);
    /// `NAME` in PATH becomes the pipeline's file name (`-` → `_`), e.g. `relief::NAME`.
    #[arg(long)]
    pub import_path: Option<String>,
    /// Output folder.
    #[arg(long)]
    pub out: PathBuf,
    /// Write into a folder that already holds files.
    #[arg(long)]
    pub force: bool,
}

/// The file stem of an image's texture in the bundle.
fn stem(image: Image) -> anyhow::Result<String> {
    Ok(match image {
        Image::Height => "height".into(),
        Image::Normal => "normal".into(),
        Image::Albedo => "albedo".into(),
        Image::Map(req) => match MapKey::of(req) {
            Some(k) => k.kind.to_string(),
            None => bail!("the library reads {}, which relief builds no file for", image.texture_name()),
        },
        Image::Window => bail!("the library reads a room's window map, which a scene has not"),
    })
}

/// Whether `form` leaves the binding `b` out: the `tsl` form reads its nearest textures
/// with texel loads and takes no nearest sampler (three.js binds none for a texture whose
/// filters are both nearest).
fn takes_no_sampler(form: LibraryForm, b: &LibraryBinding) -> bool {
    form == LibraryForm::Tsl && b.resource == Resource::Sampler(Filter::Nearest)
}

fn filter_name(f: Filter) -> &'static str {
    if f == Filter::Nearest {
        "nearest"
    } else {
        "linear"
    }
}

/// The lines to paste into a shader of `form`, for this library.
fn paste_lines(form: LibraryForm, lib: &relief_dsl::emit::LibraryForms, depth: f32, edge: &str) -> Vec<String> {
    let d = format!("{depth:?}");
    let mut v = Vec::new();
    match form {
        LibraryForm::Wgsl | LibraryForm::Wesl | LibraryForm::Tsl => {
            v.push(format!("let hit = relief_trace(uv, normalize(view_ts), {d});"));
            if lib.has_shadow {
                v.push(format!("let shadow = relief_shadow(hit, normalize(light_ts), {d});"));
            }
        }
        LibraryForm::Unity | LibraryForm::Unreal => {
            v.push(format!("DepthScale = {d}"));
        }
        LibraryForm::Glsl | LibraryForm::GlslEs | LibraryForm::Hlsl | LibraryForm::Msl => {
            if form == LibraryForm::GlslEs {
                v.push(format!("#define RELIEF_EDGE_{}", edge.to_ascii_uppercase()));
            }
            v.push(format!("ReliefHit hit = relief_trace(uv, normalize(view_ts), {d});"));
            if lib.has_shadow {
                v.push(format!("float shadow = relief_shadow(hit, normalize(light_ts), {d});"));
            }
        }
    }
    if lib.has_ao {
        v.push("ao = relief_ao(hit)".into());
    }
    v
}

/// The lines to paste into a fragment shader of `form` for a mesh library (`curved`): the
/// varyings are the `MeshVertex` members the vertex stage passes on (docs/libraries.md).
fn mesh_paste_lines(
    form: LibraryForm,
    lib: &relief_dsl::emit::LibraryForms,
    curved: Curved,
    edge: &str,
) -> Vec<String> {
    let first = if curved == Curved::Prism { "vec3(uv, layer)" } else { "uv" };
    let extra = match curved {
        Curved::None => "",
        Curved::Quadric => ", curvature",
        Curved::Prism => ", prism_a, prism_b.xy, position, prism_p0, prism_p1, prism_p2, prism_n0, prism_n1, prism_n2",
    };
    let call =
        format!("relief_trace({first}, normalize(position - eye), normal, tangent, uv_scale{extra}, depth_scale)");
    let mut v = Vec::new();
    match form {
        LibraryForm::Wgsl | LibraryForm::Wesl => v.push(format!("let hit = {call};")),
        _ => {
            if form == LibraryForm::GlslEs {
                v.push(format!("#define RELIEF_EDGE_{}", edge.to_ascii_uppercase()));
            }
            v.push(format!("ReliefHit hit = {call};"));
        }
    }
    v.push("if hit.covered == 0: discard; depth at position + normalize(position - eye) * hit.depth_offset".into());
    if lib.has_shadow {
        v.push("shadow = relief_shadow(hit, light, normal, tangent, uv_scale, depth_scale)".into());
    }
    if lib.has_ao {
        v.push("ao = relief_ao(hit)".into());
    }
    v
}

/// Refuses a container other than ktx2 or dds.
pub(crate) fn check_container(container: &str) -> anyhow::Result<()> {
    if !matches!(container.to_ascii_lowercase().as_str(), "ktx2" | "dds") {
        bail!("--container {}: expected ktx2 or dds", relief_dsl::spec::echo(container));
    }
    Ok(())
}

/// Refuses a folder that holds files, unless `force`; creates it.
fn prepare_out(out: &Path, force: bool) -> anyhow::Result<()> {
    check_out(out, force)?;
    std::fs::create_dir_all(out).with_context(|| format!("cannot create output folder {}", out.display()))
}

/// Refuses an output that is not a folder, or a folder that holds files unless `force`
/// (before any work: `relief tune` checks its bundle's folder before it measures).
pub(crate) fn check_out(out: &Path, force: bool) -> anyhow::Result<()> {
    if out.exists() {
        if !out.is_dir() {
            bail!("--out {} is not a folder", out.display());
        }
        let n = std::fs::read_dir(out).with_context(|| format!("cannot read {}", out.display()))?.count();
        if n > 0 && !force {
            bail!("--out {} holds {n} other file(s); pass --force to write the bundle into it", out.display());
        }
    }
    Ok(())
}

/// Refuses `--group` for a target whose resources carry no group, and `--import-path` for a
/// target other than wgsl (the one form naga_oil imports by a `#define_import_path` line).
fn check_library_options(form: LibraryForm, a: &ExportArgs) -> anyhow::Result<()> {
    if let (Some(g), Some(why)) = (a.group, form.without_groups()) {
        bail!("--group {g}: --target {} has no groups ({why}); groups exist for wgsl, wesl, glsl, hlsl", form.name());
    }
    if a.import_path.is_some() && form != LibraryForm::Wgsl {
        bail!(
            "--import-path: only --target wgsl carries a `#define_import_path` line ({} names its module otherwise)",
            form.name()
        );
    }
    Ok(())
}

/// Runs `relief export`.
pub fn run(a: &ExportArgs) -> anyhow::Result<()> {
    let p: relief_dsl::Pipeline =
        a.pipeline.parse().map_err(|e| anyhow::anyhow!("pipeline `{}`: {e}", relief_dsl::spec::echo(&a.pipeline)))?;
    let form = LibraryForm::from_name(&a.target)?;
    check_container(&a.container)?;
    let container = a.container.to_ascii_lowercase();
    let scene = scene_from_arg(&scene_spec(&a.scene))?;
    let edge = if scene.edge == EdgeMode::Clamp { "clamp" } else { "repeat" };
    check_library_options(form, a)?;
    // A curved= pipeline draws the scene's mesh, which goes into the bundle too.
    let mesh_scene = match (p.curved, scene.mesh.is_some()) {
        (Some(c), false) => bail!(
            "pipeline `{p}` has curved={c}: its bundle holds a mesh, and the scene {} names none (a scene file with `[mesh]`, e.g. relief-runtime/scenes/meshes/sphere_rocks.toml)",
            scene.name
        ),
        (None, true) => bail!(
            "the scene {} names a mesh: the pipeline needs curved=none, quadric or prism (`{p}` has none)",
            scene.name
        ),
        (Some(_), true) => {
            let ms = relief_runtime::mesh::MeshScene::from_scene(scene.clone())?;
            if let Some(w) = ms.notes.warning() {
                eprintln!("{w}");
            }
            Some(ms)
        }
        (None, false) => None,
    };
    let opts = LibraryOptions {
        edge_clamp: scene.edge == EdgeMode::Clamp,
        group: a.group.unwrap_or(0),
        import_path: a.import_path.as_deref().map(|t| crate::gen::import_path_of(t, &p)),
        ..LibraryOptions::default()
    };
    let lib = relief_dsl::emit::library_forms(&p, &opts, &[form]).with_context(|| format!("pipeline {p}"))?;
    prepare_out(&a.out, a.force)?;
    for f in &lib.files {
        relief_runtime::io::write_atomic(&a.out.join(&f.name), f.text.as_bytes())?;
    }
    // Every texture as the runtime uploads it, one file per image.
    let ups = gpu::scene_uploads(&scene, true);
    let mut written: Vec<(Image, String, Upload)> = Vec::new();
    let mut file_of = |image: Image| -> anyhow::Result<(String, Upload)> {
        if let Some((_, f, u)) = written.iter().find(|(i, _, _)| *i == image) {
            return Ok((f.clone(), u.clone()));
        }
        let up = match image {
            Image::Height => ups.height.clone(),
            Image::Normal => ups.normal.clone(),
            Image::Albedo => ups.albedo.clone(),
            Image::Map(req) => {
                let key = MapKey::of(req).ok_or_else(|| anyhow::anyhow!("no map for {}", image.texture_name()))?;
                gpu::map_upload_of(&scene, key)?
            }
            Image::Window => bail!("the library reads a room's window map, which a scene has not"),
        };
        let name = format!("{}.{container}", stem(image)?);
        let path = a.out.join(&name);
        let bytes = up.container_bytes(&path).unwrap_or_else(|| Err("no container".into())).map_err(|e| {
            anyhow::anyhow!("{} cannot be written as .{container}: {e}", stem(image).unwrap_or_default())
        })?;
        relief_runtime::io::write_atomic(&path, &bytes)?;
        written.push((image, name.clone(), up.clone()));
        Ok((name, up))
    };
    let address = if scene.edge == EdgeMode::Clamp { "clamp_to_edge" } else { "repeat" };
    let mut bindings = Vec::new();
    for b in lib.bindings.iter().filter(|b| !takes_no_sampler(form, b)) {
        let mut e = serde_json::json!({
            "name": b.name,
            "group": b.group,
            "binding": b.binding,
            "what": b.what,
            "address_mode": address,
        });
        match (b.resource, b.kind) {
            (Resource::Texture { image, filter, .. }, kind) => {
                let (file, up) = file_of(image)?;
                e["kind"] = if kind == ResourceKind::Texture3d { "texture_3d" } else { "texture_2d" }.into();
                e["image"] = image.texture_name().into();
                e["file"] = file.into();
                e["format"] = format!("{:?}", up.format).into();
                e["filter"] = filter_name(filter).into();
                e["levels_in_file"] = up.levels.len().into();
                e["levels_read"] = if b.all_levels { "all" } else { "0" }.into();
                e["size"] = serde_json::json!([up.width, up.height, up.depth]);
            }
            (Resource::Sampler(filter), _) => {
                e["kind"] = "sampler".into();
                e["filter"] = filter_name(filter).into();
                e["mipmap_filter"] = "nearest".into();
            }
            (other, _) => bail!("the library binds {other:?}, which a bundle has no file for"),
        }
        bindings.push(e);
    }
    // The shading textures, bound or not.
    let mut shading_files = serde_json::Map::new();
    for image in [Image::Height, Image::Normal, Image::Albedo] {
        let (file, up) = file_of(image)?;
        shading_files.insert(
            stem(image)?,
            serde_json::json!({ "file": file, "format": format!("{:?}", up.format), "levels_in_file": up.levels.len() }),
        );
    }
    let c = gpu::CLEAR;
    let mut json = serde_json::json!({
        "pipeline": p.to_string(),
        "scene": scene.name,
        "target": form.name(),
        "library": lib.files.iter().map(|f| f.name.clone()).collect::<Vec<_>>(),
        "container": container,
        "depth_scale": scene.depth_scale,
        "tiling": scene.tiling,
        "edge": edge,
        "edge_define": format!("RELIEF_EDGE_{}", edge.to_ascii_uppercase()),
        "texture_space": "row 0 of every file is v = 0 (KTXorientation rd: first row stored first, not flipped); u grows along a row; height 1 at the polygon, 0 at the floor",
        "bindings": bindings,
        "textures": shading_files,
        "has_shadow": lib.has_shadow,
        "has_ao": lib.has_ao,
        "paste": paste_lines(form, &lib, scene.depth_scale, edge),
        "shading": {
            "formula": gpu::SHADING_FORMULA,
            "ambient": gpu::AMBIENT,
            "light_dir": [scene.light_dir.x, scene.light_dir.y, scene.light_dir.z],
            "clear_color_linear": [c.r, c.g, c.b, c.a],
        },
    });
    if let (Some(ms), Some(curved)) = (&mesh_scene, p.curved) {
        json["mesh"] = crate::export_mesh::write_mesh(&a.out, ms, curved)?;
        json["paste"] = mesh_paste_lines(form, &lib, curved, edge).into();
    }
    // Recorded only when asked for, so a bundle exported without them is unchanged.
    if let Some(g) = a.group {
        json["group"] = g.into();
    }
    if let Some(path) = &opts.import_path {
        json["import_path"] = path.as_str().into();
    }
    relief_runtime::io::write_atomic(&a.out.join("relief.json"), serde_json::to_string_pretty(&json)?.as_bytes())?;
    eprintln!(
        "{}: {} for {} on {}: {} file(s) and relief.json",
        a.out.display(),
        p,
        form.name(),
        scene.name,
        lib.files.len() + written.len() + usize::from(mesh_scene.is_some())
    );
    Ok(())
}
