//! What the picture tests share: comparing two RGBA8 frames, and the pipelines every library
//! test goes over (`use crate::common::frames;`).

use relief::Pipeline;

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
