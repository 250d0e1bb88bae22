//! `relief stability`: where each method fails. Every coarse × refine combination at
//! default parameters is probed on the stress scenes, a tiled map viewed across its seam,
//! the five dissertation-like procedural scenes and the seven real maps, at view angles from head-on to 89.9° from the normal,
//! and compared with the exact reference.
//!
//! Rays: `size²` entry points on a regular grid over the map, all with the same view
//! direction (azimuth 30°, the given angle from the normal, the scene's depth scale), so
//! that an angle means the same thing on every scene.
//!
//! **Mesh conditions** (issue 38): the built-in sphere and torus ([`MESH_SCENES`]), each with
//! the real maps [`MESH_MAPS`] at 64², at the grazing angles [`MESH_ANGLES`], each of [`mesh_methods`] under
//! `curved=none`, `quadric` and `prism` ([`run_meshes`]), against the exact mesh reference.
//! An angle means the same on each mesh: the ray through the frame's centre meets the smooth
//! surface (the analytic sphere or torus, not its facets) at the point on its outer equator
//! on +x, (1, 0, 0) or (1.5, 0, 0), where the normal is +x, at that angle from the normal;
//! the eye is 1.5 units from that point, in the x–z plane on the +z side ([`mesh_scene`]).
//! A frame is `size²` pixels, one pixel-centre ray each. A mesh cell is a [`Cell`] whose
//! `coverage_error`, `extra` and `missing` are set; its t figures are in units of the
//! relief's depth along the ray (`crate::mesh_measure`), not the flat tile's t.

use std::fmt::Write as _;
use std::path::Path;

use crate::error::{Error, Result};
use crate::io::FileError;
use relief_dsl::spec::{catalog, Slot};
use relief_dsl::Pipeline;

use crate::gpu::mesh::{MeshProber, MeshProgram};
use crate::gpu::{self, Gpu, GpuHit, Program, SceneTextures};
use crate::heightmap::{EdgeMode, HeightMap};
use crate::mesh::{MeshHit, MeshReference, MeshScene};
use crate::reference::{reference_hits, RefHit, Sampling};
use crate::scene::{ProbeRay, Scene};
use relief_dsl::spec::Curved;

/// View angles from the surface normal, in degrees.
pub const ANGLES: [f32; 7] = [0.0, 30.0, 60.0, 75.0, 85.0, 89.0, 89.9];

/// The scenes of the stability grid: the stress scenes, a seam, the five main procedural
/// scenes (stand-ins) and the seven real maps. Every scene is probed at 64² texels: the
/// procedural ones are generated at that size, the real ones box-filtered down from their
/// native 256² or 128² by a whole factor (4 or 2; see `crate::scene::builtin`).
pub const SCENES: [&str; 20] = [
    "spikes",
    "walls",
    "boxes",
    "flat0",
    "flat1",
    "step",
    "checker",
    "seam",
    "lion",
    "self_shadow",
    "collage",
    "shapes",
    "rock_bump",
    "rocks",
    "stones",
    "wall",
    "four",
    "saint",
    "bump",
    "dent",
];

/// One method on one condition.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Cell {
    /// The pipeline's text form.
    pub method: String,
    /// The scene's name.
    pub scene: String,
    /// The view angle from the surface normal, in degrees.
    pub angle: f32,
    /// Rays scored: the `size²` grid of entry points.
    pub rays: usize,
    /// Hits with NaN or Inf anywhere.
    pub nan_count: usize,
    /// Finite hits whose raw t lies outside the volume ([`GpuHit::outside`]).
    pub outside_count: usize,
    /// Share of rays that jumped over geometry: after the exact first hit the ray is back
    /// above the surface before its reported hit, or the hit is NaN
    /// (`crate::metrics::is_skipped`; the results' `skipped_rate`).
    pub skipped_rate: f64,
    /// Share of rays whose hit is more than one texel of travel past the exact first hit, or
    /// NaN (`crate::metrics::is_past`; the results' `past_rate`). On a fine map a coarse
    /// step spans several texels, so this counts rays that skipped nothing.
    pub past_rate: f64,
    /// The old name of `past_rate`, written beside it (the same value) for one release.
    pub missed_rate: f64,
    /// Share of rays whose coarse search ran out of steps before it found the surface.
    pub nonconverged_rate: f64,
    /// Share of rays whose hit ends above the surface (z above the height there by more than
    /// `crate::metrics::ABOVE_SURFACE`): what a one-shot method's non-convergence looks like.
    pub above_surface_rate: f64,
    /// Hits past the exact first hit by more than [`crate::metrics::PAST_SLACK`] in t (the
    /// `form=safe` conservative cone methods, sphere and maxmip must have none).
    pub past_count: usize,
    /// Largest |t − t_ref| over the rays the reference hits.
    pub ref_err_t_max: f64,
    /// RMS of t − t_ref over the rays the reference hits.
    pub ref_err_t_rms: f64,
    /// A mesh cell's share of pixels whose hit/miss disagrees with the reference's (`extra` +
    /// `missing` over `rays`); `None` (an empty CSV field) for a flat cell.
    pub coverage_error: Option<f64>,
    /// A mesh cell's pixels the pipeline draws and the reference does not hit.
    pub extra: Option<usize>,
    /// A mesh cell's pixels the reference hits and the pipeline does not draw.
    pub missing: Option<usize>,
}

impl Cell {
    /// Whether the cell is a mesh condition's ([`run_meshes`]).
    pub fn is_mesh(&self) -> bool {
        self.coverage_error.is_some()
    }
}

/// Boxes of random heights on a floor at 0.05, with one-texel walls (full height) and
/// single-texel pillars between them: the hard case for cone methods. `seed`
/// makes other layouts of the same kind.
pub fn boxes(n: usize, seed: u64) -> HeightMap {
    let mut state = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    let mut next = move || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((state >> 33) as f64 / (1u64 << 31) as f64) as f32
    };
    let mut h = vec![0.05f32; n * n];
    let at = |x: usize, y: usize| (y % n) * n + x % n;
    for _ in 0..n / 4 {
        let (x0, y0) = ((next() * n as f32) as usize, (next() * n as f32) as usize);
        let (w, d) = (1 + (next() * 12.0) as usize, 1 + (next() * 12.0) as usize);
        let top = 0.2 + 0.8 * next();
        for y in y0..(y0 + d).min(n) {
            for x in x0..(x0 + w).min(n) {
                h[at(x, y)] = top;
            }
        }
    }
    for _ in 0..n / 8 {
        // One-texel walls, horizontal or vertical.
        let (x0, y0) = ((next() * n as f32) as usize, (next() * n as f32) as usize);
        let len = 4 + (next() * 20.0) as usize;
        let vertical = next() < 0.5;
        for i in 0..len {
            let (x, y) = if vertical { (x0, y0 + i) } else { (x0 + i, y0) };
            h[at(x, y)] = 1.0;
        }
    }
    for _ in 0..n / 2 {
        // Single-texel pillars.
        let (x, y) = ((next() * n as f32) as usize, (next() * n as f32) as usize);
        h[at(x, y)] = 0.5 + 0.5 * next();
    }
    HeightMap::new(n, n, h)
}

/// A scene for the stability grid by name (`NAME` or `scene:NAME`, at `size²` texels; see
/// [`Scene::by_name`]); `seam` is a ramp that does not tile, with edge mode repeat, so rays
/// that cross its edge meet a cliff. A TOML scene file or an image file (see
/// [`crate::scene::scene_from_arg`]) is used at its own size.
pub fn scene(name: &str, size: usize) -> Result<Scene> {
    if name == "boxes" {
        let mut s = Scene::from_height_map("boxes", boxes(size, 1));
        s.depth_scale = 0.1;
        return Ok(s);
    }
    if name == "seam" {
        let hm = HeightMap::from_fn(size, size, |x, _| 0.1 + 0.8 * x as f32 / (size - 1) as f32);
        let mut s = Scene::from_height_map("seam", hm);
        s.edge = EdgeMode::Repeat;
        return Ok(s);
    }
    let spec = crate::scene::scene_spec(name);
    match spec.strip_prefix("scene:") {
        Some(n) => Ok(Scene::by_name(n, Some(size))?),
        None => Ok(crate::scene::scene_from_arg(&spec)?),
    }
}

/// Rays over the map at `angle` degrees from the normal.
pub fn rays(scene: &Scene, n: u32, angle: f32) -> Vec<ProbeRay> {
    let (az, th) = (30f32.to_radians(), angle.to_radians());
    // Horizontal travel per unit of depth, in texture units, scaled by the relief's depth.
    let reach = th.tan() * scene.depth_scale;
    let dir = [reach * az.cos(), reach * az.sin(), -1.0];
    let mut out = Vec::with_capacity((n * n) as usize);
    for y in 0..n {
        for x in 0..n {
            let origin = [(x as f32 + 0.5) / n as f32, (y as f32 + 0.5) / n as f32];
            out.push(ProbeRay { origin, dir, x, y, pixel_size: 0.0 });
        }
    }
    out
}

/// Scores one method's hits against the reference, with the metrics' own per-ray rules
/// ([`crate::metrics::Accuracy`]).
pub fn score(
    method: &str,
    scene: &Scene,
    angle: f32,
    rays: &[ProbeRay],
    hits: &[GpuHit],
    refs: &[Option<RefHit>],
) -> Cell {
    let a = crate::metrics::Accuracy::of(rays, hits, refs, &scene.height, scene.edge);
    Cell {
        method: method.to_string(),
        scene: scene.name.clone(),
        angle,
        rays: a.rays,
        nan_count: a.nan,
        outside_count: a.outside,
        skipped_rate: a.skipped_rate(),
        past_rate: a.missed_rate(),
        missed_rate: a.missed_rate(),
        nonconverged_rate: a.nonconverged_rate(),
        above_surface_rate: a.above_surface_rate(),
        past_count: a.past,
        ref_err_t_max: a.t_abs_max,
        ref_err_t_rms: a.t_rms(),
        coverage_error: None,
        extra: None,
        missing: None,
    }
}

/// Every coarse × refine combination at default parameters, and the cone
/// methods again in `form=textbook`.
pub fn methods() -> Vec<Pipeline> {
    let of = |slot| catalog().iter().filter(move |m| m.slot == slot).map(|m| m.default_spec());
    let textbook = of(Slot::Coarse).filter(|c| c.get("form").is_some()).map(|mut c| {
        for (n, v) in c.params.iter_mut() {
            if n == "form" {
                *v = relief_dsl::spec::Value::Word("textbook".into());
            }
        }
        c
    });
    let coarse: Vec<_> = of(Slot::Coarse).chain(textbook).collect();
    let mut out = vec![];
    for c in coarse {
        for r in of(Slot::Refine) {
            out.push(Pipeline::new(c.clone(), r, relief_dsl::StageSpec::none(), relief_dsl::StageSpec::none()));
        }
    }
    out
}

/// Runs the whole stability grid; `progress` is told each finished (scene, angle).
pub fn run(
    gpu: &Gpu,
    size: u32,
    methods: &[Pipeline],
    scenes: &[&str],
    angles: &[f32],
    mut progress: impl FnMut(&str, f32),
) -> Result<Vec<Cell>> {
    let programs: Vec<(String, Program, Vec<relief_dsl::spec::MapReq>)> = methods
        .iter()
        .map(|p| Ok((p.to_string(), Program::new(p)?, p.required_maps())))
        .collect::<Result<_, relief_dsl::CompileError>>()?;
    let mut cells = Vec::new();
    for &name in scenes {
        let scene = scene(name, 64)?;
        let mut tex = SceneTextures::new(gpu, &scene);
        let mut on_device = scene.clone();
        on_device.height.data = tex.heights_on_device.clone();
        for &angle in angles {
            let rays = rays(&scene, size, angle);
            let refs = reference_hits(&on_device, &rays, Sampling::Bilinear)
                .map_err(|e| Error::from(e).in_scene(format!("{name} at {angle}°")))?;
            for (text, program, maps) in &programs {
                tex.add_maps(gpu, &scene, maps)?;
                let hits = gpu::probe(gpu, program, &scene, &tex, &rays)
                    .map_err(|e| Error::from(e).in_scene(name).in_pipeline(text))?;
                cells.push(score(text, &on_device, angle, &rays, &hits, &refs));
            }
            progress(name, angle);
        }
    }
    Ok(cells)
}

/// The meshes of the mesh conditions, each with every map of [`MESH_MAPS`]: (built-in mesh,
/// depth in world units). The depths are the mesh grid's (`relief sweep --grid meshes`);
/// tiling 2, repeat edges.
pub const MESH_SCENES: [(&str, f32); 2] = [("sphere", 0.08), ("torus", 0.05)];

/// The height maps of the mesh conditions: two real maps of the flat matrix, at 64² as it
/// loads them, `rocks` (rounded rocks) and `four` (four shapes with flat tops, slopes and
/// sharp rims), so that a conclusion is checked on more than one real map.
pub const MESH_MAPS: [&str; 2] = ["rocks", "four"];

/// The grazing angles of the mesh conditions, degrees from the normal at the frame's centre.
pub const MESH_ANGLES: [f32; 3] = [75.0, 85.0, 89.0];

/// The mesh condition `mesh` (a built-in of [`MESH_SCENES`]) with the height map `map` (a
/// flat matrix's scene name, at 64²; the conditions' are [`MESH_MAPS`]), seen at `angle`
/// degrees from the normal at the frame's centre (the module doc). Its name is `MESH:MAP`,
/// e.g. `sphere:rocks`.
pub fn mesh_scene(mesh: &str, map: &str, angle: f32) -> Result<MeshScene> {
    let (_, depth) = MESH_SCENES
        .iter()
        .find(|(m, _)| *m == mesh)
        .ok_or_else(|| Error::Input(format!("no mesh condition `{}`", relief_dsl::spec::echo(mesh))))?;
    let mut s = scene(map, 64)?;
    s.name = format!("{mesh}:{map}");
    s.depth_scale = *depth;
    s.tiling = 2.0;
    s.edge = EdgeMode::Repeat;
    s.mesh = Some(crate::scene::MeshSource::Builtin(mesh.to_string()));
    // The outer equator's point on +x: the unit sphere's, the torus's (centre line 1, tube ½).
    let x = if mesh == "torus" { 1.5 } else { 1.0 };
    s.camera = crate::scene::Camera {
        angle_deg: 90.0 - angle,
        azimuth_deg: 0.0,
        distance: 1.5,
        fov_deg: 40.0,
        target: glam::Vec3::new(x, 0.0, 0.0),
    };
    Ok(MeshScene::from_scene(s)?)
}

/// The methods of the mesh conditions: every coarse method of [`methods`] at its default
/// parameters, each with `binary`'s default refinement (the refinement the mesh grid uses),
/// and `linear` with every refinement; three `curved=` modes each ([`run_meshes`]). Not the
/// whole product: it would take `relief stability --size 64` ~10× the flat matrix's time.
pub fn mesh_methods() -> Vec<Pipeline> {
    methods().into_iter().filter(|p| p.refine.name == "binary" || p.coarse.name == "linear").collect()
}

/// One mode's figures on a mesh condition as a [`Cell`]: `rays` the frame's pixels,
/// `nan_count` the pixels whose GPU output holds NaN or Inf, `past_count`, `ref_err_t_max`
/// and `ref_err_t_rms` from [`crate::mesh_measure::score`] (in units of the depth along the
/// ray); `outside_count` 0 and the flat rates NaN (a mesh has no volume of t ∈ [0, 1]).
pub fn mesh_cell(
    method: &str,
    ms: &MeshScene,
    angle: f32,
    probe: &crate::gpu::mesh::MeshProbe,
    refs: &[Option<crate::mesh::MeshHit>],
) -> Cell {
    let s = crate::mesh_measure::score(probe, refs, ms);
    Cell {
        method: method.to_string(),
        scene: ms.scene.name.clone(),
        angle,
        rays: s.pixels,
        nan_count: probe.hits.iter().filter(|h| h.iter().any(|v| !v.is_finite())).count(),
        outside_count: 0,
        skipped_rate: f64::NAN,
        past_rate: f64::NAN,
        missed_rate: f64::NAN,
        nonconverged_rate: f64::NAN,
        above_surface_rate: f64::NAN,
        past_count: s.past,
        ref_err_t_max: s.t_max,
        ref_err_t_rms: s.rms_t,
        coverage_error: Some(s.coverage_error),
        extra: Some(s.extra),
        missing: Some(s.missing),
    }
}

/// The mesh conditions: each of `methods` (with no `curved=` option) under each of `modes`
/// on each mesh of `meshes` ([`MESH_SCENES`] names) with each height map of `maps` at each
/// of `angles`, in a `size²` frame; `progress` is told each finished (`MESH:MAP`, angle).
/// The reference is traced once per condition on the heights as the device stores them. A
/// mesh with a map is one scene but for its camera, so its textures, maps and reference
/// (its BVH) are built once for all the angles.
#[allow(clippy::too_many_arguments)]
pub fn run_meshes(
    gpu: &Gpu,
    size: u32,
    methods: &[Pipeline],
    modes: &[Curved],
    meshes: &[&str],
    maps: &[&str],
    angles: &[f32],
    mut progress: impl FnMut(&str, f32),
) -> Result<Vec<Cell>> {
    let programs: Vec<(String, MeshProgram)> = methods
        .iter()
        .flat_map(|p| modes.iter().map(move |&m| p.clone().with_curved(Some(m))))
        .map(|p| Ok((p.to_string(), MeshProgram::new(&p)?)))
        .collect::<Result<_, relief_dsl::CompileError>>()?;
    // Each program's pipeline is compiled once, for every condition.
    let probers = probers(gpu, &programs)?;
    let mut cells = Vec::new();
    for &mesh in meshes {
        for &map in maps {
            let mut built: Option<(SceneTextures, MeshReference)> = None;
            for &angle in angles {
                let mut ms = mesh_scene(mesh, map, angle)?;
                let (tex, reference) = match &mut built {
                    Some(b) => b,
                    None => {
                        let tex = SceneTextures::new(gpu, &ms.scene);
                        ms.scene.height.data = tex.heights_on_device.clone();
                        built.insert((tex, ms.reference()?))
                    }
                };
                ms.scene.height.data = tex.heights_on_device.clone();
                let refs = reference.trace_all(&ms.rays(size, size));
                cells.extend(probe_condition(gpu, size, &probers, &ms, angle, tex, &refs)?);
                progress(&ms.scene.name, angle);
            }
        }
    }
    Ok(cells)
}

/// One mesh condition: each of `programs` (text form, compiled module) probed on `ms` in a
/// `size²` frame and scored ([`mesh_cell`]) against the exact reference, traced once on the
/// heights as the device stores them; `angle` labels the cells.
pub fn mesh_condition(
    gpu: &Gpu,
    size: u32,
    programs: &[(String, MeshProgram)],
    mut ms: MeshScene,
    angle: f32,
) -> Result<Vec<Cell>> {
    let mut tex = SceneTextures::new(gpu, &ms.scene);
    ms.scene.height.data = tex.heights_on_device.clone();
    let refs = ms.reference_hits(size, size)?;
    probe_condition(gpu, size, &probers(gpu, programs)?, &ms, angle, &mut tex, &refs)
}

/// Each of `programs` (text form, compiled module) with its measurement pipeline.
fn probers<'a>(gpu: &Gpu, programs: &'a [(String, MeshProgram)]) -> Result<Vec<(&'a str, MeshProber<'a>)>> {
    programs
        .iter()
        .map(|(text, prog)| {
            let prober = MeshProber::new(gpu, prog).map_err(|e| Error::from(e).in_pipeline(text))?;
            Ok((text.as_str(), prober))
        })
        .collect()
}

/// Each program of `probers` probed on `ms` (its heights as the device stores them, `tex` its
/// textures) and scored against the reference's hits `refs`.
fn probe_condition(
    gpu: &Gpu,
    size: u32,
    probers: &[(&str, MeshProber)],
    ms: &MeshScene,
    angle: f32,
    tex: &mut SceneTextures,
    refs: &[Option<MeshHit>],
) -> Result<Vec<Cell>> {
    let name = &ms.scene.name;
    let mut cells = Vec::new();
    for (text, prober) in probers {
        let prog = prober.program();
        tex.add_maps_lod(gpu, &ms.scene, &prog.program.maps, prog.lod)?;
        let probe = prober
            .probe(gpu, ms, tex, size)
            .map_err(|e| Error::from(e).in_scene(format!("{name} at {angle}°")).in_pipeline(*text))?;
        cells.push(mesh_cell(text, ms, angle, &probe, refs));
    }
    Ok(cells)
}

/// A named column of a [`Cell`], as a number.
type CellMetric = fn(&Cell) -> f64;

/// Writes `stability.csv` (every cell, flat and mesh), one heat map per metric of the flat
/// cells (`stability_METRIC.svg`), one per metric of the mesh cells when there are any
/// (`stability_meshes_METRIC.svg`: coverage error, RMS t, past count) and `worst.md` (the
/// worst condition of each method; the mesh cells' in a second table, only when there are
/// any).
pub fn write(out: &Path, cells: &[Cell]) -> Result<()> {
    crate::io::create_dir_all(out)?;
    let path = out.join("stability.csv");
    let encode = |e: &dyn std::fmt::Display| FileError::Encode { path: path.clone(), message: e.to_string() };
    let mut w = csv::Writer::from_writer(Vec::new());
    for c in cells {
        w.serialize(c).map_err(|e| encode(&e))?;
    }
    crate::io::write_atomic(&path, &w.into_inner().map_err(|e| encode(&e))?)?;
    let (mesh, flat): (Vec<Cell>, Vec<Cell>) = cells.iter().cloned().partition(Cell::is_mesh);
    let metrics: [(&str, CellMetric); 8] = [
        ("nan_count", |c| c.nan_count as f64),
        ("outside_count", |c| c.outside_count as f64),
        ("skipped_rate", |c| c.skipped_rate),
        ("past_rate", |c| c.past_rate),
        ("nonconverged_rate", |c| c.nonconverged_rate),
        ("above_surface_rate", |c| c.above_surface_rate),
        ("ref_err_t_max", |c| c.ref_err_t_max),
        ("ref_err_t_rms", |c| c.ref_err_t_rms),
    ];
    for (name, f) in metrics {
        crate::io::write_atomic(&out.join(format!("stability_{name}.svg")), heat_map(name, &flat, f).as_bytes())?;
    }
    if !mesh.is_empty() {
        let metrics: [(&str, CellMetric); 3] = [
            ("coverage_error", |c| c.coverage_error.unwrap_or(f64::NAN)),
            ("ref_err_t_rms", |c| c.ref_err_t_rms),
            ("past_count", |c| c.past_count as f64),
        ];
        for (name, f) in metrics {
            let title = format!("meshes {name}");
            let svg = heat_map(&title, &mesh, f);
            crate::io::write_atomic(&out.join(format!("stability_meshes_{name}.svg")), svg.as_bytes())?;
        }
    }
    let mut md = worst_table(&flat);
    if !mesh.is_empty() {
        md.push('\n');
        md.push_str(&worst_mesh_table(&mesh));
    }
    crate::io::write_atomic(&out.join("worst.md"), md.as_bytes())?;
    Ok(())
}

/// The worst mesh condition of each method (with its `curved=` mode), by coverage error,
/// then RMS t: a heading, a line saying what the figures are, and the table.
pub fn worst_mesh_table(cells: &[Cell]) -> String {
    let mut s = format!(
        "### Mesh conditions (grazing views)\n\nThe sphere and the torus, each with {}, at 75°, 85° and 89° from the normal at the frame's centre, against the exact mesh reference; coverage error: pixels whose hit/miss disagrees (extra + missing); t in units of the relief's depth along the ray, on pixels both hit; past: pixels both hit whose hit lies after the exact first hit.\n\n| method | worst condition | coverage error | extra | missing | RMS t | max t | past | NaN |\n|---|---|---|---|---|---|---|---|---|\n",
        mesh_maps_named("`", "`"),
    );
    let mut seen = std::collections::HashSet::new();
    for m in cells.iter().map(|c| c.method.as_str()) {
        if !seen.insert(m) {
            continue;
        }
        let key = |c: &Cell| (c.coverage_error.unwrap_or(f64::NAN), c.ref_err_t_rms);
        let of_m = || cells.iter().filter(move |c| c.method == m);
        let Some(c) = of_m().max_by(|a, b| key(a).partial_cmp(&key(b)).unwrap_or(std::cmp::Ordering::Equal)) else {
            continue;
        };
        let nan: usize = of_m().map(|x| x.nan_count).sum();
        let _ = writeln!(
            s,
            "| `{m}` | {} at {}° | {:.2}% | {} | {} | {:.3} | {:.3} | {} | {nan} |",
            c.scene,
            c.angle,
            100.0 * c.coverage_error.unwrap_or(f64::NAN),
            c.extra.unwrap_or(0),
            c.missing.unwrap_or(0),
            c.ref_err_t_rms,
            c.ref_err_t_max,
            c.past_count
        );
    }
    s
}

/// The maps of [`MESH_MAPS`] in words, each between `open` and `close`: "`rocks` and `four`".
pub fn mesh_maps_named(open: &str, close: &str) -> String {
    let names: Vec<String> = MESH_MAPS.iter().map(|m| format!("{open}{m}{close}")).collect();
    match names.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => names.concat(),
    }
}

/// The worst condition of each method, by skipped rate, then past rate, then RMS error.
pub fn worst_table(cells: &[Cell]) -> String {
    let mut s = String::from(
        "| method | worst condition | skipped rate | past rate | non-converged | ends above surface | max t error | NaN | outside |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    let mut methods: Vec<&str> = cells.iter().map(|c| c.method.as_str()).collect();
    methods.dedup();
    let mut seen = std::collections::HashSet::new();
    for m in methods {
        if !seen.insert(m) {
            continue;
        }
        let worst = cells.iter().filter(|c| c.method == m).max_by(|a, b| {
            (a.skipped_rate, a.past_rate, a.ref_err_t_rms)
                .partial_cmp(&(b.skipped_rate, b.past_rate, b.ref_err_t_rms))
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        if let Some(c) = worst {
            let nan: usize = cells.iter().filter(|x| x.method == m).map(|x| x.nan_count).sum();
            let outside: usize = cells.iter().filter(|x| x.method == m).map(|x| x.outside_count).sum();
            let _ = writeln!(
                s,
                "| `{m}` | {} at {}° | {:.2}% | {:.1}% | {:.1}% | {:.1}% | {:.3} | {nan} | {outside} |",
                c.scene.trim_start_matches("scene:"),
                c.angle,
                100.0 * c.skipped_rate,
                100.0 * c.past_rate,
                100.0 * c.nonconverged_rate,
                100.0 * c.above_surface_rate,
                c.ref_err_t_max
            );
        }
    }
    s
}

/// A method × condition heat map as SVG, darker = worse (log scale over the metric's range).
/// Every cell is a 14 × 14 `<rect>` with its value as a `<title>`; the cells sit in one group
/// that gives them their grey stroke and a white fill, so a cell states its fill only when it
/// is not white, as `#rrggbb`.
fn heat_map(metric: &str, cells: &[Cell], f: fn(&Cell) -> f64) -> String {
    let mut methods: Vec<String> = vec![];
    let mut conditions: Vec<(String, f32)> = vec![];
    for c in cells {
        if !methods.contains(&c.method) {
            methods.push(c.method.clone());
        }
        let cond = (c.scene.clone(), c.angle);
        if !conditions.contains(&cond) {
            conditions.push(cond);
        }
    }
    let by_key: std::collections::HashMap<(&str, &str, u32), &Cell> =
        cells.iter().rev().map(|c| ((c.method.as_str(), c.scene.as_str(), c.angle.to_bits()), c)).collect();
    let (cw, ch, left, top) = (14.0, 14.0, 230.0, 120.0);
    let width = left + cw * conditions.len() as f64 + 20.0;
    let height = top + ch * methods.len() as f64 + 40.0;
    let max = cells.iter().map(f).fold(0.0, f64::max);
    let floor = cells.iter().map(f).filter(|v| *v > 0.0).fold(f64::INFINITY, f64::min).min(max);
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\" font-family=\"sans-serif\" font-size=\"10\">\n<text x=\"4\" y=\"14\" font-size=\"13\">{metric}: method × condition (white = 0, dark red = {max:.3e})</text>\n"
    );
    for (j, (scene, angle)) in conditions.iter().enumerate() {
        let x = left + cw * j as f64 + cw / 2.0;
        let _ = writeln!(
            s,
            "<text transform=\"translate({x},{}) rotate(-60)\">{} {angle}°</text>",
            top - 4.0,
            scene.trim_start_matches("scene:")
        );
    }
    for (i, m) in methods.iter().enumerate() {
        let y = top + ch * i as f64;
        let _ = writeln!(s, "<text x=\"{}\" y=\"{}\" text-anchor=\"end\">{m}</text>", left - 4.0, y + ch - 3.0);
    }
    s.push_str("<g fill=\"#fff\" stroke=\"#ddd\">\n");
    for (i, m) in methods.iter().enumerate() {
        let y = top + ch * i as f64;
        for (j, cond) in conditions.iter().enumerate() {
            let Some(c) = by_key.get(&(m.as_str(), cond.0.as_str(), cond.1.to_bits())) else {
                continue;
            };
            let v = f(c);
            if v.is_nan() {
                // Not measured (a mesh cell with no pixel both hit has no t error): grey.
                let _ = writeln!(
                    s,
                    "<rect x=\"{}\" y=\"{y}\" width=\"{cw}\" height=\"{ch}\" fill=\"#bbbbbb\"><title>{m} on {} at {}°: none</title></rect>",
                    left + cw * j as f64,
                    cond.0,
                    cond.1
                );
                continue;
            }
            let k = if v <= 0.0 || max <= 0.0 {
                0.0
            } else if max <= floor {
                1.0
            } else {
                0.15 + 0.85 * ((v / floor).ln() / (max / floor).ln()).clamp(0.0, 1.0)
            };
            let (r, g, b) = ((255.0 - 100.0 * k) as u8, (255.0 * (1.0 - k)) as u8, (255.0 * (1.0 - k)) as u8);
            let fill =
                if (r, g, b) == (255, 255, 255) { String::new() } else { format!(" fill=\"#{r:02x}{g:02x}{b:02x}\"") };
            let _ = writeln!(
                s,
                "<rect x=\"{}\" y=\"{y}\" width=\"{cw}\" height=\"{ch}\"{fill}><title>{m} on {} at {}°: {v:.4e}</title></rect>",
                left + cw * j as f64,
                cond.0,
                cond.1
            );
        }
    }
    s.push_str("</g>\n</svg>\n");
    s
}
