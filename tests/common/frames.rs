//! What the picture tests share: comparing two RGBA8 frames, and the pipelines every library
//! test goes over (`use crate::common::frames;`).

use relief::runtime::gpu::{self, Gpu, Program, SceneTextures};
use relief::runtime::Scene;
use relief::Pipeline;

/// `relief render`'s frame of `p` on `scene` at `size`², RGBA8, top row first: the picture
/// every library test compares its engine's against.
pub fn relief_render(g: &Gpu, p: &Pipeline, scene: &Scene, size: u32) -> Vec<u8> {
    let program = Program::new(p).unwrap();
    let mut tex = SceneTextures::new(g, scene);
    tex.add_maps(g, scene, &p.required_maps()).unwrap();
    gpu::render(g, &program, scene, &tex, size, 0, 1).unwrap().rgba
}

/// A picture a browser page hands back as hex (RGBA8, top row first), as bytes.
pub fn from_hex(s: &str) -> Vec<u8> {
    assert!(s.len().is_multiple_of(2) && s.is_ascii(), "a picture's hex has an odd length or stray characters");
    (0..s.len()).step_by(2).map(|i| u8::from_str_radix(&s[i..i + 2], 16).expect("a picture's hex")).collect()
}

/// The mean absolute difference per channel over rgb, in units of 1/255 (so 1.0 is one step
/// of 255), and the share of pixels with any rgb channel off by more than 8. `a` and `b` are
/// RGBA8 frames of the same size.
pub fn frame_difference(a: &[u8], b: &[u8]) -> (f64, f64) {
    assert_eq!(a.len(), b.len(), "the two frames differ in size");
    assert!(!a.is_empty() && a.len().is_multiple_of(4), "a frame is RGBA8 and not empty");
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

/// The pipelines of `relief gen --all --library`: every default combination a library can
/// express (at least 300 of them).
pub fn library_pipelines() -> Vec<Pipeline> {
    let pipelines: Vec<Pipeline> = Pipeline::all_defaults()
        .into_iter()
        .filter(|p| relief::dsl::compose::library::inexpressible(p).is_none())
        .collect();
    assert!(pipelines.len() >= 300, "only {} pipelines have a library", pipelines.len());
    pipelines
}

/// Two 2-pixel frames, differences worked by hand: pixel 0 differs by (3, 0, 9) (9 > 8),
/// pixel 1 by (0, 8, 0) (not > 8); alpha is ignored. Sum 20 over 6 channels.
#[test]
fn frame_difference_of_two_hand_made_frames() {
    let a = [10, 20, 30, 255, 0, 100, 255, 0];
    let b = [13, 20, 21, 0, 0, 108, 255, 255];
    let (mad, share) = frame_difference(&a, &b);
    assert!((mad - 20.0 / 6.0).abs() < 1e-12, "{mad}");
    assert_eq!(share, 0.5);
}

/// The side of the engine tests' frames (`tests/babylon.rs`, `tests/threejs.rs`), pixels.
pub const ENGINE_SIZE: u32 = 128;

/// The pipelines and scenes the engine tests draw (as `relief export --scene` takes them): a
/// linear search with binary refinement and a soft shadow on a real height map, a safe cone
/// method (its cell cone map read with nearest filtering) on a rough procedural surface, the
/// max-mip traversal (its chain read at every level) on one-texel walls and pillars — all
/// three scenes repeat at their edges — and the safe cone method again on `rocks` with
/// clamped edges (a scene file), so that the bundle's `clamp_to_edge` and
/// `RELIEF_EDGE_CLAMP` are drawn too.
pub const ENGINE_CASES: [(&str, &str); 4] = [
    ("linear(32)+binary(5)+shadow=soft(16)", "scene:lion"),
    ("csm(64)", "scene:rock_bump"),
    ("maxmip(96)", "scene:shapes"),
    ("csm(64)", CLAMP_SCENE),
];

/// The clamp-edge case's scene file (`edge = "clamp"`), relative to the workspace root.
pub const CLAMP_SCENE: &str = "relief-runtime/scenes/rocks_clamp.toml";

/// The index in [`ENGINE_CASES`] of the clamp-edge case, which the engine tests draw once
/// more with every texture's address mode forced to repeat in the page: that picture must
/// miss the bar, or the case would not show that the engines take the bundle's address mode.
pub const CLAMP_CASE: usize = 3;

/// The `relief.json` of the clamp-edge case's bundle in `dir` says clamp everywhere an
/// engine reads it: `edge` and `edge_define`, and every binding's `address_mode` (the pages
/// set each texture's wrap from it; the forced-repeat picture shows the wrap matters).
pub fn assert_clamp_bundle(dir: &std::path::Path) {
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(dir.join("relief.json")).unwrap()).unwrap();
    assert_eq!(json["edge"], "clamp", "{}: edge", dir.display());
    assert_eq!(json["edge_define"], "RELIEF_EDGE_CLAMP", "{}: edge_define", dir.display());
    let bindings = json["bindings"].as_array().unwrap();
    assert!(!bindings.is_empty(), "{}: no bindings", dir.display());
    for b in bindings {
        assert_eq!(b["address_mode"], "clamp_to_edge", "{}: {b}", dir.display());
    }
}

/// An engine's `ENGINE_SIZE`² picture `rgba` of `what` against relief render's `reference`,
/// by the bar of `tests/integrate.rs`: the figures printed; a picture with a third of its
/// pixels or fewer lit fails at once; a mean absolute difference above 1 of 255 or more
/// than 1 % of pixels off by more than 8 is returned as a failure line. Both pictures are
/// kept in `dir` as `STEM_ENGINE.png` and `STEM_relief.png` when off, or when `keep`.
pub fn engine_picture(
    engine: &str,
    what: &str,
    rgba: &[u8],
    reference: &[u8],
    dir: &std::path::Path,
    stem: &str,
    keep: bool,
) -> Option<String> {
    let size = ENGINE_SIZE;
    assert_eq!(rgba.len(), (size * size * 4) as usize, "{what}: picture size");
    let (mad, share) = frame_difference(rgba, reference);
    println!("{what}: mean |difference| {mad:.4} of 255, {:.3} % of pixels off by more than 8", share * 100.0);
    let lit = rgba.chunks(4).filter(|px| px[0] > 20 || px[1] > 20 || px[2] > 20).count();
    let off = mad > 1.0 || share > 0.01;
    if off || lit <= (size * size / 3) as usize || keep {
        let short = engine.split_whitespace().next().unwrap_or(engine).to_lowercase().replace('.', "");
        for (who, px) in [(short.as_str(), rgba), ("relief", reference)] {
            let file = dir.join(format!("{stem}_{who}.png"));
            relief::runtime::io::png::write_rgba8(&file, size, size, px.to_vec()).unwrap();
        }
    }
    assert!(lit > (size * size / 3) as usize, "{what}: only {lit} lit pixels (pictures in {})", dir.display());
    off.then(|| {
        format!("{what}: mean |difference| {mad:.4}, {:.3} % off by > 8 (pictures in {})", share * 100.0, dir.display())
    })
}
