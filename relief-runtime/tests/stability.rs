//! No method produces NaN, Inf or a hit outside the volume, at any angle, on the stress
//! scenes (the clamp in `Hit::at` exists because this failed: linear + binary and the cone
//! searches ended below the floor at 89.9°).

use relief_runtime::gpu::Gpu;
use relief_runtime::stability;

#[test]
fn every_method_stays_finite_and_inside_the_volume_at_every_angle() {
    let gpu = Gpu::new().unwrap();
    let methods = stability::methods();
    assert_eq!(methods.len(), 16 * 4, "every implemented coarse × refine at default parameters");
    let cells = stability::run(&gpu, 16, &methods, &["spikes", "flat1", "seam", "walls"], &stability::ANGLES, |_, _| {}).unwrap();
    assert_eq!(cells.len(), methods.len() * 4 * stability::ANGLES.len());
    let bad: Vec<_> = cells.iter().filter(|c| c.nan_count > 0 || c.outside_count > 0).collect();
    assert!(bad.is_empty(), "{} bad cells, e.g. {:?}", bad.len(), &bad[..bad.len().min(3)]);
}

#[test]
fn the_scores_see_what_they_measure() {
    // On a flat surface at height 1 every ray hits at its entry; a method that answers t = 0
    // is exact there, and the same answer on flat 0 has not converged.
    use relief_runtime::gpu::GpuHit;
    let flat1 = stability::scene("flat1", 16).unwrap();
    let rays = stability::rays(&flat1, 4, 60.0);
    let refs = relief_runtime::reference::reference_hits(&flat1, &rays, relief_runtime::reference::Sampling::Bilinear);
    let at_entry: Vec<GpuHit> =
        rays.iter().map(|r| GpuHit { t: 0.0, u: r.origin[0], v: r.origin[1], z: 1.0, iterations: 1, fetches: 1 }).collect();
    let c = stability::score("entry", &flat1, 60.0, &rays, &at_entry, &refs);
    assert_eq!((c.nan_count, c.outside_count, c.missed_rate, c.nonconverged_rate), (0, 0, 0.0, 0.0));
    let flat0 = stability::scene("flat0", 16).unwrap();
    let refs0 = relief_runtime::reference::reference_hits(&flat0, &rays, relief_runtime::reference::Sampling::Bilinear);
    let c = stability::score("entry", &flat0, 60.0, &rays, &at_entry, &refs0);
    assert_eq!(c.nonconverged_rate, 1.0);
    assert!((c.ref_err_t_max - 1.0).abs() < 1e-6);
    let mut broken = at_entry.clone();
    broken[0].t = f32::NAN;
    broken[1].t = -0.5;
    let c = stability::score("broken", &flat1, 60.0, &rays, &broken, &refs);
    assert_eq!((c.nan_count, c.outside_count), (1, 1));
}
