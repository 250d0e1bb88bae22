//! `relief render`: one pipeline on one scene: timed frames, probe against the exact
//! reference, and the files that show both.

use std::io::Write;
use std::path::PathBuf;

use anyhow::Context;

use relief_runtime::camera_json;
use relief_runtime::gpu::Gpu;
use relief_runtime::io::write_atomic;
use relief_runtime::measure::{measure_with, write_images, Prepared};
use relief_runtime::{scene_from_arg, scene_spec};

/// Arguments of `relief render`.
#[derive(clap::Args, Debug)]
pub struct RenderArgs {
    /// The pipeline in the text form, e.g. `linear(10)+binary(5)`.
    pub pipeline: String,
    /// `scene:NAME` (a built-in scene, real or procedural; a bare NAME works too), a TOML
    /// scene file (`.toml`) or a height-map file.
    #[arg(long)]
    pub scene: String,
    /// Frame size in pixels (square).
    #[arg(long, default_value_t = 512)]
    pub size: u32,
    #[command(flatten)]
    pub overrides: crate::OverrideArgs,
    /// Number of timed frames (after 5 warm-up frames).
    #[arg(long, default_value_t = 50)]
    pub frames: u32,
    /// Also write hits.csv, one row per ray.
    #[arg(long)]
    pub dump_hits: bool,
    /// Render with a depth buffer holding the hit's depth (pixel depth offset): writes
    /// depth.png and depth.npy, and `depth_err_max` (against the reference hits' depth) in
    /// metrics.json.
    #[arg(long)]
    pub write_depth: bool,
    /// Output folder.
    #[arg(long)]
    pub out: PathBuf,
}

/// Writes `depth.npy` (the depth buffer, f32, rows from the top) and `depth.png` (near =
/// white, far = black, stretched over the depths the relief covers).
fn write_depth(out: &std::path::Path, size: u32, depth: &[f32]) -> anyhow::Result<()> {
    let n = size as usize;
    write_atomic(&out.join("depth.npy"), &relief_runtime::io::npy::npy_bytes(&[n, n], depth))?;
    let covered: Vec<f32> = depth.iter().copied().filter(|d| *d < 1.0).collect();
    let (lo, hi) = covered.iter().fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), &d| (a.min(d), b.max(d)));
    let span = (hi - lo).max(1e-12);
    let rgba: Vec<u8> = depth
        .iter()
        .flat_map(|&d| {
            let g = if d < 1.0 { (255.0 * (1.0 - (d - lo) / span)).round() as u8 } else { 0 };
            [g, g, g, 255]
        })
        .collect();
    Ok(relief_runtime::io::png::write_rgba8(&out.join("depth.png"), size, size, rgba)?)
}

/// Runs `relief render`.
pub fn run(a: &RenderArgs) -> anyhow::Result<()> {
    let pipeline: relief_dsl::Pipeline =
        a.pipeline.parse().map_err(|e| anyhow::anyhow!("pipeline `{}`: {e}", relief_dsl::spec::echo(&a.pipeline)))?;
    if a.size == 0 || a.size > 8192 {
        anyhow::bail!("--size {} is out of range: allowed 1..=8192", a.size);
    }
    if a.frames == 0 || a.frames > 100_000 {
        anyhow::bail!("--frames {} is out of range: allowed 1..=100000 (a frame time needs a timed frame)", a.frames);
    }
    let overrides = a.overrides.checked()?;
    let scene = overrides.apply(scene_from_arg(&scene_spec(&a.scene))?);
    std::fs::create_dir_all(&a.out).with_context(|| format!("cannot create output folder {}", a.out.display()))?;
    let g = Gpu::new()?;
    if scene.mesh.is_some() {
        return render_mesh_scene(&g, a, &pipeline, scene);
    }
    let mut prep = Prepared::new(&g, scene, a.size)?;
    let options = relief_dsl::compose::Options { frag_depth: a.write_depth, ..Default::default() };
    let measured = measure_with(&g, &mut prep, &pipeline, &options, 5, a.frames)?;
    write_images(&a.out, &prep, &measured)?;
    if let Some(depth) = &measured.frame.depth {
        write_depth(&a.out, a.size, depth)?;
    }
    // The level each ray sampled (none under lod=zero), for hits.csv.
    let levels = prep.refs_for(measured.lod)?.0.to_vec();
    let (m, rays, hits, refs) = (&measured.metrics, &prep.rays, &measured.hits, &measured.refs);
    // The metrics, then the scene's parameters as measured (with the overrides applied).
    let mut json = serde_json::to_value(m)?;
    let s = &prep.scene;
    json["depth_scale"] = s.depth_scale.into();
    json["tiling"] = s.tiling.into();
    json["edge"] = format!("{:?}", s.edge).to_lowercase().into();
    json["camera"] = camera_json(&s.camera);
    // What the render entry shades with, so that an engine can reproduce the frame
    // (docs/libraries.md, "Reproducing relief render's frame").
    let c = relief_runtime::gpu::CLEAR;
    json["shading"] = serde_json::json!({
        "formula": relief_runtime::gpu::SHADING_FORMULA,
        "ambient": relief_runtime::gpu::AMBIENT,
        "light_dir": [s.light_dir.x, s.light_dir.y, s.light_dir.z],
        "clear_color_linear": [c.r, c.g, c.b, c.a],
        "output": "Rgba8UnormSrgb: linear colour encoded to sRGB on write, no tone mapping, alpha 1",
        "albedo": "sRGB texture (decoded to linear on read), linear filtering, at hit.uv",
        "normal": "normal map (unorm8 RGB), linear filtering, at hit.uv: n = normalize(texel * 2 - 1)",
        "texture_space": "u along x, v along y, texel row 0 at v = 0; the quad lies in z = 0, tangent space = world",
    });
    write_atomic(&a.out.join("metrics.json"), serde_json::to_string_pretty(&json)?.as_bytes())?;
    if a.dump_hits {
        let chain: &[relief_runtime::HeightMap] = if measured.lod == relief_dsl::spec::Lod::Zero {
            std::slice::from_ref(&prep.on_device.height)
        } else {
            &prep.textures.height_levels
        };
        let texels = chain[0].width.max(chain[0].height) as f64;
        let mut csv = Vec::new();
        writeln!(
            csv,
            "x,y,origin_u,origin_v,dir_x,dir_y,dir_z,t,u,v,z,t_ref,u_ref,v_ref,coarse_steps,refine_steps,fetches,converged,clipped,height_at_hit,level,coarse_step_texels"
        )?;
        for (i, ((r, h), rf)) in rays.iter().zip(hits).zip(refs).enumerate() {
            let (tr, ur, vr) = rf.map(|x| (x.t.to_string(), x.u.to_string(), x.v.to_string())).unwrap_or_default();
            let level = levels.get(i).copied().unwrap_or(0);
            let height = chain[level].bilinear(h.u as f64, h.v as f64, prep.scene.edge);
            let height = if height.is_finite() { height.to_string() } else { String::new() };
            let step = relief_runtime::metrics::coarse_step_texels(&m.pipeline, r, prep.scene.depth_scale, texels)
                .map(|s| s.to_string())
                .unwrap_or_default();
            writeln!(
                csv,
                "{},{},{},{},{},{},{},{},{},{},{},{tr},{ur},{vr},{},{},{},{},{},{height},{level},{step}",
                r.x,
                r.y,
                r.origin[0],
                r.origin[1],
                r.dir[0],
                r.dir[1],
                r.dir[2],
                h.t,
                h.u,
                h.v,
                h.z,
                h.coarse_steps,
                h.refine_steps,
                h.fetches,
                h.converged,
                h.clipped
            )?;
        }
        write_atomic(&a.out.join("hits.csv"), &csv)?;
    }
    println!(
        "{} on {} at {}²: frame {:.3} ms (p10 {:.3}, p90 {:.3}), mse {:.3e}, t err rms {:.2e}, skipped {:.2}%, past {:.2}%, NaN {}, {:.1} iterations, {:.1} fetches → {}",
        m.pipeline,
        m.scene,
        m.size,
        m.frame_ms_median,
        m.frame_ms_p10,
        m.frame_ms_p90,
        m.mse_dissertation,
        m.ref_err_t_rms,
        100.0 * m.skipped_rate,
        100.0 * m.past_rate,
        m.nan_count,
        m.avg_iterations,
        m.avg_fetches,
        a.out.display()
    );
    Ok(())
}

/// `relief render` on a scene that names a mesh: one frame of the `curved=` pipeline on the
/// mesh, written as `frame.png` (docs/meshes.md; `relief scene measure` measures it).
fn render_mesh_scene(
    g: &Gpu,
    a: &RenderArgs,
    pipeline: &relief_dsl::Pipeline,
    scene: relief_runtime::Scene,
) -> anyhow::Result<()> {
    use relief_runtime::gpu::mesh::{mesh_textures, render_mesh, MeshProgram};
    anyhow::ensure!(
        pipeline.curved.is_some(),
        "the scene names a mesh: the pipeline needs curved=none, quadric or prism (`{pipeline}` has none)"
    );
    let ms = relief_runtime::mesh::MeshScene::from_scene(scene)?;
    if let Some(w) = ms.notes.warning() {
        eprintln!("{w}");
    }
    let prog = MeshProgram::new(pipeline)?;
    let tex = mesh_textures(g, &ms, &prog)?;
    let f = render_mesh(g, &prog, &ms, &tex, a.size)?;
    relief_runtime::io::png::write_rgba8(&a.out.join("frame.png"), a.size, a.size, f.rgba)?;
    println!("{}: {} on mesh {} -> {}", ms.scene.name, pipeline, ms.mesh.name, a.out.join("frame.png").display());
    Ok(())
}
