//! The real height maps shipped with relief: the textures of the Parallax Occlusion Mapping
//! sample of the legacy DirectX SDK (Tatarchuk's POM sample, MIT licence, © Microsoft; see
//! `relief-runtime/scenes/tatarchuk/README.md` and its `LICENSE`), embedded in the binary so
//! that `scene:rocks` works from any folder.
//!
//! Each file is a 32-bit TGA: RGB a tangent-space normal map, **alpha the height** (255 = the
//! top of the relief = relief's height 1, the polygon; 0 = the deepest point = height 0), the
//! same orientation as relief's height maps (ARCHITECTURE.md "Conventions": z in [0, 1], polygon at
//! z = 1), so heights are `alpha / 255` with no inversion.
//!
//! # Depth scale
//!
//! The sample's height scale is the relief depth as a fraction of the texture's width; in
//! relief a texture spans one world unit (world units = texture units, see [`crate::scene`]),
//! so that fraction *is* [`Scene::depth_scale`] for tiling 1: a depth scale of 0.1 on a
//! 256-texel map is 25.6 texels deep.
//!
//! # Normals
//!
//! `rocks`, `stones`, `wall`, `four` and `saint` read their normals from the RGB: c = 2·rgb/255
//! − 1, renormalised, with red along +u, **green towards the top of the image (−v)** and blue
//! up, so n = (c.r, −c.g, c.b) in relief's tangent space (x along +u, y along +v = image rows
//! downward). The test `rgb_normals_agree_with_the_height` found that orientation: with the
//! green read as +v, the y signs disagreed with the alpha's slopes at 99.5% of `rocks`' sloped
//! texels; read as −v they agree at 99.5%. `bump` and `dent` share
//! one RGB that disagrees with their own alphas on one axis, so their normals are derived from
//! the height (the scene's normal map is `None`).
//!
//! # Sizes
//!
//! A real map has one native size (256² or 128²). [`real_scene`] with a smaller size `s`
//! box-filters it down by the whole factor `native / s` (each output texel is the mean of a
//! `k × k` block of heights; normals are averaged and renormalised); a size that does not
//! divide the native one, or a larger size, is an error (no resampling is silently invented).
//!
//! # Edges
//!
//! The sample's sampler wraps, so the edge mode is repeat. `rocks`, `wall`, `four`, `bump` and
//! `dent` tile seamlessly; `saint` does not tile (rays that leave the square meet a cliff at
//! the border) and `stones` has a vertical seam.

use glam::Vec3;

use crate::heightmap::{EdgeMode, HeightMap};
use crate::scene::{NormalMap, Scene, SceneError};

/// One built-in real scene.
#[derive(Clone, Copy, Debug)]
pub struct RealScene {
    /// The name, `scene:NAME` on the command line.
    pub name: &'static str,
    /// The TGA file's name under `relief-runtime/scenes/tatarchuk/`.
    pub file: &'static str,
    /// The TGA file's bytes.
    pub bytes: &'static [u8],
    /// Native side in texels.
    pub size: usize,
    /// The sample's height scale = relief's depth scale (see the module docs).
    pub depth_scale: f32,
    /// Normals from the RGB (`true`) or derived from the height (`false`).
    pub rgb_normals: bool,
    /// Whether the map tiles seamlessly.
    pub tiles: bool,
    /// What it shows.
    pub doc: &'static str,
}

macro_rules! tga {
    ($f:literal) => {
        ($f, include_bytes!(concat!("../../scenes/tatarchuk/", $f)) as &[u8])
    };
}

const fn real(
    (file, bytes): (&'static str, &'static [u8]),
    name: &'static str,
    size: usize,
    depth_scale: f32,
    rgb_normals: bool,
    tiles: bool,
    doc: &'static str,
) -> RealScene {
    RealScene { name, file, bytes, size, depth_scale, rgb_normals, tiles, doc }
}

/// The built-in real scenes, in the order the README lists them.
pub const REAL_SCENES: &[RealScene] = &[
    real(
        tga!("rocks_NM_height.tga"),
        "rocks",
        256,
        0.1,
        true,
        true,
        "real (POM sample): rounded rocks; the dissertation's Rock Bump (the relaxed-cone chapter's rockbump)",
    ),
    real(
        tga!("stones_NM_height.tga"),
        "stones",
        256,
        0.02,
        true,
        false,
        "real (POM sample): flat paving stones, shallow; a vertical seam at the edge",
    ),
    real(
        tga!("wall_NM_height.tga"),
        "wall",
        256,
        0.06,
        true,
        true,
        "real (POM sample): a brick wall, flat bricks and mortar grooves",
    ),
    real(
        tga!("four_NM_height.tga"),
        "four",
        256,
        0.2,
        true,
        true,
        "real (POM sample): four simple shapes, flat tops and slopes; close to the dissertation's Shapes",
    ),
    real(
        tga!("saint_NM_height.tga"),
        "saint",
        256,
        0.08,
        true,
        false,
        "real (POM sample): a carved saint's relief; does not tile",
    ),
    real(
        tga!("bump_NM_height.tga"),
        "bump",
        128,
        0.2,
        false,
        true,
        "real (POM sample): raised bumps; normals derived from the height",
    ),
    real(
        tga!("dent_NM_height.tga"),
        "dent",
        128,
        0.2,
        false,
        true,
        "real (POM sample): dents; normals derived from the height",
    ),
];

/// The built-in real scene called `name` (without `scene:`), if there is one.
pub(crate) fn find(name: &str) -> Option<&'static RealScene> {
    REAL_SCENES.iter().find(|r| r.name == name)
}

/// The map decoded at its native size: heights from the alpha, normals from the RGB.
pub(crate) fn decode(r: &RealScene) -> (HeightMap, NormalMap) {
    let img = image::load_from_memory_with_format(r.bytes, image::ImageFormat::Tga)
        .unwrap_or_else(|e| panic!("embedded {} does not decode: {e}", r.file))
        .to_rgba8();
    let (w, h) = (img.width() as usize, img.height() as usize);
    assert_eq!((w, h), (r.size, r.size), "embedded {} has the wrong size", r.file);
    let px = img.as_raw();
    let heights = px.chunks_exact(4).map(|p| p[3] as f32 / 255.0).collect();
    let normals = crate::scene::file::rgb_to_normals(px, true);
    (HeightMap::new(w, h, heights), NormalMap { width: w, height: h, data: normals })
}

/// The built-in real scene `r` with `size × size` texels (default: native), box-filtered
/// down by a whole factor (see the module docs).
pub(crate) fn real_scene(r: &RealScene, size: Option<usize>) -> Result<Scene, SceneError> {
    let size = size.unwrap_or(r.size);
    if size == 0 {
        return Err(SceneError::ZeroSize);
    }
    if size > r.size || !r.size.is_multiple_of(size) {
        return Err(SceneError::BadRealSize { name: r.name, native: r.size, size });
    }
    let (hm, nm) = decode(r);
    let k = r.size / size;
    let (hm, nm) = if k == 1 { (hm, nm) } else { (box_down(&hm, k), box_down_normals(&nm, k)) };
    let mut s = Scene::from_height_map(format!("scene:{}", r.name), hm);
    s.depth_scale = r.depth_scale;
    s.edge = EdgeMode::Repeat;
    s.normal = r.rgb_normals.then_some(nm);
    Ok(s)
}

/// Mean of each `k × k` block (the map's side must be a multiple of `k`).
pub(crate) fn box_down(m: &HeightMap, k: usize) -> HeightMap {
    let (w, h) = (m.width / k, m.height / k);
    HeightMap::from_fn(w, h, |x, y| {
        let mut sum = 0.0f64;
        for j in 0..k {
            for i in 0..k {
                sum += m.data[(y * k + j) * m.width + x * k + i] as f64;
            }
        }
        (sum / (k * k) as f64) as f32
    })
}

fn box_down_normals(m: &NormalMap, k: usize) -> NormalMap {
    let (w, h) = (m.width / k, m.height / k);
    let mut data = Vec::with_capacity(w * h);
    for y in 0..h {
        for x in 0..w {
            let mut sum = Vec3::ZERO;
            for j in 0..k {
                for i in 0..k {
                    sum += Vec3::from(m.data[(y * k + j) * m.width + x * k + i]);
                }
            }
            data.push(sum.normalize_or(Vec3::Z).to_array());
        }
    }
    NormalMap { width: w, height: h, data }
}

/// What a scene is: one of the real maps, a procedural stand-in for one of the dissertation's
/// scenes, or a stress scene (or a user's file).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum SceneKind {
    /// A real height map (a built-in one or a user's file or scene file).
    Real,
    /// A procedural stand-in for one of the dissertation's scenes.
    StandIn,
    /// A procedural stress scene.
    Stress,
}

impl SceneKind {
    /// `real`, `stand-in` or `stress`.
    pub(crate) fn label(self) -> &'static str {
        match self {
            SceneKind::Real => "real",
            SceneKind::StandIn => "stand-in",
            SceneKind::Stress => "stress",
        }
    }
}

/// The kind of the scene named `name` (`scene:NAME`, a bare built-in NAME, or anything else,
/// which is a user's file and counts as real). Any `@…` override suffix is ignored.
pub(crate) fn scene_kind(name: &str) -> SceneKind {
    let base = name.split('@').next().unwrap_or(name);
    let bare = base.strip_prefix("scene:").unwrap_or(base);
    if find(bare).is_some() {
        return SceneKind::Real;
    }
    match bare {
        "lion" | "self_shadow" | "collage" | "shapes" | "rock_bump" => SceneKind::StandIn,
        "spikes" | "walls" | "flat0" | "flat1" | "step" | "checker" | "seam" => SceneKind::Stress,
        _ if base.starts_with("scene:") => SceneKind::Stress,
        _ => SceneKind::Real,
    }
}
