//! `relief render`: one pipeline on one scene: timed frames, probe against the exact
//! reference, and the files that show both.

use std::io::Write;
use std::path::PathBuf;

use anyhow::Context;

use crate::cli_gen::write_atomic;
use crate::gpu::Gpu;
use crate::measure::{measure, write_images, Prepared};
use crate::scene::file::camera_json;
use crate::scene::{scene_from_arg, scene_spec, Overrides};

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
    /// View angle from the surface normal, in degrees (overrides the scene's camera).
    #[arg(long)]
    pub angle: Option<f32>,
    /// The eye's azimuth around the normal, degrees from +u towards +v (overrides the scene's camera).
    #[arg(long)]
    pub azimuth: Option<f32>,
    /// Relief depth in texture units (overrides the scene's depth scale).
    #[arg(long)]
    pub depth_scale: Option<f32>,
    /// Repeats of the texture across the quad (overrides the scene's tiling).
    #[arg(long)]
    pub tiling: Option<f32>,
    /// Number of timed frames (after 5 warm-up frames).
    #[arg(long, default_value_t = 50)]
    pub frames: u32,
    /// Also write hits.csv, one row per ray.
    #[arg(long)]
    pub dump_hits: bool,
    /// Output folder.
    #[arg(long)]
    pub out: PathBuf,
}

/// Runs `relief render`.
pub fn run(a: &RenderArgs) -> anyhow::Result<()> {
    let pipeline: relief_dsl::Pipeline = a.pipeline.parse().map_err(|e| anyhow::anyhow!("pipeline `{}`: {e}", a.pipeline))?;
    if a.size == 0 || a.size > 8192 {
        anyhow::bail!("--size {} is out of range: allowed 1..=8192", a.size);
    }
    let overrides = Overrides { depth_scale: a.depth_scale, tiling: a.tiling, angle: a.angle, azimuth: a.azimuth };
    overrides.check().map_err(anyhow::Error::msg)?;
    let scene = overrides.apply(scene_from_arg(&scene_spec(&a.scene))?);
    std::fs::create_dir_all(&a.out).with_context(|| format!("cannot create output folder {}", a.out.display()))?;
    let g = Gpu::new()?;
    let mut prep = Prepared::new(&g, scene, a.size)?;
    let measured = measure(&g, &mut prep, &pipeline, 5, a.frames)?;
    write_images(&a.out, &prep, &measured)?;
    let (m, rays, hits, refs) = (&measured.metrics, &prep.rays, &measured.hits, &prep.refs);
    // The metrics, then the scene's parameters as measured (with the overrides applied).
    let mut json = serde_json::to_value(m)?;
    let s = &prep.scene;
    json["depth_scale"] = s.depth_scale.into();
    json["tiling"] = s.tiling.into();
    json["edge"] = format!("{:?}", s.edge).to_lowercase().into();
    json["camera"] = camera_json(&s.camera);
    write_atomic(&a.out.join("metrics.json"), serde_json::to_string_pretty(&json)?.as_bytes())?;
    if a.dump_hits {
        let mut csv = Vec::new();
        writeln!(csv, "x,y,origin_u,origin_v,dir_x,dir_y,dir_z,t,u,v,z,t_ref,u_ref,v_ref,coarse_steps,refine_steps,fetches,converged")?;
        for ((r, h), rf) in rays.iter().zip(hits).zip(refs) {
            let (tr, ur, vr) = rf.map(|x| (x.t.to_string(), x.u.to_string(), x.v.to_string())).unwrap_or_default();
            writeln!(
                csv,
                "{},{},{},{},{},{},{},{},{},{},{},{tr},{ur},{vr},{},{},{},{}",
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
                h.converged
            )?;
        }
        write_atomic(&a.out.join("hits.csv"), &csv)?;
    }
    println!(
        "{} on {} at {}²: frame {:.3} ms (p10 {:.3}, p90 {:.3}), mse {:.3e}, t err rms {:.2e}, missed {:.2}%, NaN {}, {:.1} iterations, {:.1} fetches → {}",
        m.pipeline,
        m.scene,
        m.size,
        m.frame_ms_median,
        m.frame_ms_p10,
        m.frame_ms_p90,
        m.mse_dissertation,
        m.ref_err_t_rms,
        100.0 * m.missed_rate,
        m.nan_count,
        m.avg_iterations,
        m.avg_fetches,
        a.out.display()
    );
    Ok(())
}

/// Per-pixel |t − t_ref| as a heat map (log scale, black = exact, yellow = the largest
/// error, magenta = no finite hit), with a legend bar and its range below the image.
pub fn error_map(size: u32, errors: &[(u32, u32, f64)]) -> (u32, u32, Vec<u8>) {
    let legend_h = 24u32;
    let (w, h) = (size.max(96), size + legend_h);
    let mut img = vec![0u8; (w * h * 4) as usize];
    for px in img.chunks_mut(4) {
        px.copy_from_slice(&[40, 40, 48, 255]);
    }
    let max = errors.iter().map(|e| e.2).filter(|e| e.is_finite()).fold(1e-9, f64::max);
    let lo = (max * 1e-4).max(1e-9);
    let scale = |e: f64| ((e.max(lo) / lo).ln() / (max / lo).ln()).clamp(0.0, 1.0);
    let mut put = |x: u32, y: u32, c: [u8; 3]| {
        if x < w && y < h {
            let i = ((y * w + x) * 4) as usize;
            img[i..i + 3].copy_from_slice(&c);
        }
    };
    for &(x, y, e) in errors {
        let c = if e.is_finite() { heat(if e <= lo { 0.0 } else { scale(e) }) } else { [255, 0, 255] };
        put(x, y, c);
    }
    // Legend: the colour bar from `lo` (left) to `max` (right), labelled with both.
    for x in 0..w {
        for y in size + 2..size + 8 {
            put(x, y, heat(x as f64 / (w - 1).max(1) as f64));
        }
    }
    draw_text(&mut put, 2, size + 11, &format!("{lo:.0e}"));
    let label = format!("{max:.1e}");
    draw_text(&mut put, w.saturating_sub(4 * label.len() as u32 + 2), size + 11, &label);
    (w, h, img)
}

fn heat(f: f64) -> [u8; 3] {
    // black → red → yellow
    let r = (f * 2.0).min(1.0);
    let g = (f * 2.0 - 1.0).clamp(0.0, 1.0);
    [(r * 255.0) as u8, (g * 255.0) as u8, (g * 80.0) as u8]
}

/// 3×5 pixel glyphs for the legend's numbers.
fn glyph(c: char) -> [u8; 5] {
    match c {
        '0' => [7, 5, 5, 5, 7],
        '1' => [2, 6, 2, 2, 7],
        '2' => [7, 1, 7, 4, 7],
        '3' => [7, 1, 7, 1, 7],
        '4' => [5, 5, 7, 1, 1],
        '5' => [7, 4, 7, 1, 7],
        '6' => [7, 4, 7, 5, 7],
        '7' => [7, 1, 1, 1, 1],
        '8' => [7, 5, 7, 5, 7],
        '9' => [7, 5, 7, 1, 7],
        '.' => [0, 0, 0, 0, 2],
        'e' => [0, 7, 7, 4, 7],
        '-' => [0, 0, 7, 0, 0],
        '+' => [0, 2, 7, 2, 0],
        _ => [0; 5],
    }
}

fn draw_text(put: &mut impl FnMut(u32, u32, [u8; 3]), x0: u32, y0: u32, s: &str) {
    for (i, c) in s.chars().enumerate() {
        for (row, bits) in glyph(c).iter().enumerate() {
            for col in 0..3 {
                if bits & (4 >> col) != 0 {
                    put(x0 + 4 * i as u32 + col, y0 + row as u32, [230, 230, 230]);
                }
            }
        }
    }
}
