//! `relief maps`: build one acceleration map from a height-map file and write it.
//!
//! ```text
//! relief maps INPUT --kind KIND [--encoding f32|f16|unorm8|unorm16] [--sqrt] [--max-value V]
//!             [--edge repeat|clamp] [--channel r|g|b|a] [--depth] [--min3x3]
//!             [--cones K] [--z-resolution D] --out FILE
//! relief maps --list
//! ```
//!
//! The output format follows the extension of `FILE`: `.png` (unorm8 → 8 bit, unorm16 → 16
//! bit), `.exr` (f32/f16, scanlines), `.npy` (float32, the decoded values). See [`relief_runtime::maps::encode`] and [`relief_runtime::maps::file`].
//!
//! `.ktx2` and `.dds` hold the texture exactly as the runtime uploads it
//! ([`relief_runtime::gpu::upload_of_map`]): R32F / RG32F / RGBA32F (or, with `--encoding
//! f16`, the 16-bit float forms), the max-mip chain as mip levels, the distance field as a
//! 3D texture; and for `--kind height`, `normal` or `albedo` the scene's own textures with
//! their mip chains (the levels `lod=auto` reads). Row 0 is v = 0 in every format.
//!
//! ```text
//! relief maps scene:rocks --kind max_mip --out rocks.max_mip.ktx2
//! relief maps scene:rocks --kind cell_cone --edge repeat --out rocks.cell_cone.dds
//! relief maps scene:rocks --kind height --out rocks.height.ktx2
//! ```

use anyhow::{bail, Context};
use relief_runtime::maps::{self, encode, MapKind, MapParams};
use relief_runtime::{Channel, EdgeMode, HeightMap, LoadOptions};
use std::path::PathBuf;

/// Arguments of `relief maps`.
#[derive(clap::Args, Debug, Clone)]
pub struct MapsArgs {
    /// Height map: .png (8/16 bit), .tga, .bmp, .exr or .npy (float32 [h, w]), a TOML scene
    /// file (.toml), or `scene:NAME` for a built-in scene (real or procedural).
    #[arg(required_unless_present_any = ["list", "scene"])]
    pub input: Option<PathBuf>,
    /// The same as INPUT, for a scene: `scene:NAME`, a bare NAME or a TOML scene file.
    #[arg(long, conflicts_with = "input")]
    pub scene: Option<String>,
    /// Map kind (see --list); with a .ktx2 or .dds output also `height`, `normal` or
    /// `albedo`, the scene's own textures.
    #[arg(long, required_unless_present = "list")]
    pub kind: Option<String>,
    /// Storage encoding: f32, f16, unorm8 or unorm16 (default: unorm16 for .png, f32 for
    /// .exr and .npy).
    #[arg(long)]
    pub encoding: Option<String>,
    /// Dummer's square-root encoding (store sqrt of the value).
    #[arg(long)]
    pub sqrt: bool,
    /// The value the largest unorm code stands for (default 1, as in GPU Gems 3).
    #[arg(long, default_value_t = 1.0)]
    pub max_value: f32,
    /// Edge mode: repeat (tiling) or clamp.
    #[arg(long, default_value = "repeat")]
    pub edge: String,
    /// Channel holding the heights: r, g, b or a (default: gray, or luma of colour images).
    #[arg(long)]
    pub channel: Option<String>,
    /// The input is a depth map (white = deep): height = 1 - value.
    #[arg(long)]
    pub depth: bool,
    /// Apply the conservative 3x3 pass (min for cones/normals/distances, max for max_mip)
    /// before encoding, so that bilinear filtering stays conservative.
    #[arg(long)]
    pub min3x3: bool,
    /// K for multi_cone and piecewise_cone.
    #[arg(long, default_value_t = 4)]
    pub cones: u32,
    /// Number of z slices for distance_field.
    #[arg(long, default_value_t = 64)]
    pub z_resolution: u32,
    /// Output file (.png, .exr, .npy, .ktx2 or .dds).
    #[arg(long, required_unless_present = "list")]
    pub out: Option<PathBuf>,
    /// List the map kinds and their parameters.
    #[arg(long)]
    pub list: bool,
}

/// The `--list` text.
fn list_text() -> String {
    let mut s = String::from("map kinds (relief maps INPUT --kind KIND ...):\n");
    for k in MapKind::ALL {
        s.push_str(&format!("  {:<20} {}\n", k.name(), k.describe()));
    }
    s.push_str("  height, normal, albedo  the scene's textures with their mip chains (.ktx2 and .dds only)\n");
    s.push_str("parameters: --cones K (default 4), --z-resolution D (default 64), --edge repeat|clamp,\n");
    s.push_str("            --encoding f32|f16|unorm8|unorm16, --sqrt, --max-value V, --min3x3\n");
    s
}

fn parse_edge(s: &str) -> anyhow::Result<EdgeMode> {
    match s.to_ascii_lowercase().as_str() {
        "repeat" | "wrap" => Ok(EdgeMode::Repeat),
        "clamp" => Ok(EdgeMode::Clamp),
        o => bail!("unknown edge mode `{o}` (expected repeat or clamp)"),
    }
}

/// Runs `relief maps`.
pub fn run(args: &MapsArgs) -> anyhow::Result<()> {
    if args.list {
        print!("{}", list_text());
        return Ok(());
    }
    let input = match (&args.input, &args.scene) {
        (Some(i), _) => i.clone(),
        (None, Some(s)) => PathBuf::from(relief_runtime::scene_spec(s)),
        (None, None) => bail!("relief maps needs INPUT (or --scene), --kind and --out (or --list)"),
    };
    let input = &input;
    let (Some(kind), Some(out)) = (&args.kind, &args.out) else {
        bail!("relief maps needs INPUT (or --scene), --kind and --out (or --list)");
    };
    let ext = out.extension().and_then(|e| e.to_str()).map(|e| e.to_ascii_lowercase()).unwrap_or_default();
    let container = matches!(ext.as_str(), "ktx2" | "dds");
    let scene_texture = ["height", "normal", "albedo"].contains(&kind.trim().to_ascii_lowercase().as_str());
    if scene_texture && !container {
        bail!("--kind {kind} is the scene's texture, written as .ktx2 or .dds only (a height map file is its own .png/.exr/.npy)");
    }
    let default_encoding = match ext.as_str() {
        "png" => "unorm16",
        _ => "f32",
    };
    let format: encode::Format =
        args.encoding.as_deref().unwrap_or(default_encoding).parse().map_err(anyhow::Error::msg)?;
    let edge = parse_edge(&args.edge)?;
    let channel = match &args.channel {
        Some(c) => Some(c.parse::<Channel>().map_err(anyhow::Error::msg)?),
        None => None,
    };
    if !(args.max_value.is_finite() && args.max_value > 0.0) {
        bail!("--max-value must be a positive number");
    }
    let is_scene_file = input.extension().is_some_and(|e| e.eq_ignore_ascii_case("toml"));
    let scene = match input.to_str().and_then(|s| s.strip_prefix("scene:")) {
        Some(name) => relief_runtime::Scene::by_name(name, None)?,
        None if is_scene_file => relief_runtime::load_scene_file(input)?,
        None => {
            let mut s = relief_runtime::Scene::from_height_map(
                "input",
                HeightMap::load(input, &LoadOptions { channel, depth: args.depth })?,
            );
            s.edge = edge;
            s
        }
    };
    if container {
        if !matches!(format, encode::Format::F32 | encode::Format::F16) {
            bail!("{kind} as {format:?} cannot be written as .{ext}: the runtime uploads 32-bit floats; use --encoding f32 or f16");
        }
        if args.sqrt || args.max_value != 1.0 || (args.min3x3 && scene_texture) {
            bail!("--sqrt, --max-value and --min3x3 (for a scene texture) do not apply to .{ext}: it holds the texture as the runtime uploads it");
        }
    }
    if scene_texture {
        let ups = relief_runtime::gpu::scene_uploads(&scene, true);
        let up = match kind.trim().to_ascii_lowercase().as_str() {
            "height" => ups.height,
            "normal" => ups.normal,
            _ => ups.albedo,
        };
        let up = if format == encode::Format::F16 { up.to_f16() } else { up };
        write_container(out, &up, kind)?;
        return Ok(());
    }
    let kind: MapKind = kind.parse()?;
    let hm = scene.height;
    let params = MapParams { cones: args.cones, z_resolution: args.z_resolution };
    if kind == MapKind::CellPatch && format != encode::Format::F32 {
        bail!("{kind} holds heights and their differences, which the safe marches must read exactly as the height map gives them: use --encoding f32");
    }
    if kind.per_cell() && args.min3x3 {
        bail!("--min3x3 does not apply to {kind}: a cell map is read at one cell, unfiltered, so no blend is formed (see the docs of relief_runtime::maps::cell)");
    }
    if kind.is_cell() && matches!(format, encode::Format::Unorm8 | encode::Format::Unorm16) && args.max_value < 1.0 {
        bail!("{kind} stores the apex height (up to 1) in its last channel: a unorm encoding needs --max-value >= 1");
    }
    let start = std::time::Instant::now();
    let mut map = maps::build(&hm, kind, &params, edge)?;
    if args.min3x3 {
        let mips = std::mem::take(&mut map.mips);
        map = match kind.rounding() {
            encode::Rounding::Down => maps::filter::min3x3(&map, edge),
            encode::Rounding::Up => maps::filter::max3x3(&map, edge),
        };
        map.mips = mips;
    }
    if container {
        let up = relief_runtime::gpu::upload_of_map(&map, kind)?;
        let up = if format == encode::Format::F16 { up.to_f16() } else { up };
        write_container(out, &up, &kind.to_string())?;
        eprintln!(
            "{}: {kind} as {:?}, {} level(s), from {} in {:.2} s",
            out.display(),
            up.format,
            up.levels.len(),
            input.display(),
            start.elapsed().as_secs_f64()
        );
        return Ok(());
    }
    let enc = encode::Encoding { format, sqrt: args.sqrt, max_value: args.max_value };
    let encoded = encode::encode_channels(&map, &enc, &maps::kind_rounding(&map, kind));
    maps::file::write_map(out, &encoded).with_context(|| format!("writing {}", out.display()))?;
    eprintln!(
        "{}: {} {}x{}x{} ({} ch) from {} in {:.2} s",
        out.display(),
        kind,
        map.width,
        map.height,
        map.depth,
        map.channels,
        input.display(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

/// Writes `up` as the container `out`'s extension names (`.ktx2` or `.dds`), atomically.
fn write_container(out: &std::path::Path, up: &relief_runtime::gpu::Upload, kind: &str) -> anyhow::Result<()> {
    let Some(bytes) = up.container_bytes(out) else {
        bail!("{}: not a .ktx2 or .dds file", out.display());
    };
    let bytes = bytes.map_err(|e| anyhow::anyhow!("{kind} cannot be written as {}: {e}", out.display()))?;
    relief_runtime::io::write_atomic(out, &bytes)?;
    Ok(())
}
