//! The CPU count of a mesh draw's fragments per pixel (`relief_runtime::mesh::fragments`),
//! against an independent count on a flat square.

use glam::DVec2;
use relief_dsl::spec::Curved;
use relief_runtime::mesh::fragments::{fragment_counts, fragments_per_pixel};
use relief_runtime::mesh::MeshScene;

/// With the normals along +z, each prism is its triangle extruded straight down by the depth,
/// a convex column, and a ray from above enters each column it passes through once, through
/// one face that faces the eye: so a pixel runs one prism fragment per triangle that the ray's
/// stretch between the planes z = 0 and z = −depth passes over (seen from above). Counted here
/// on that stretch (2000 points along it against the triangles, shrunk and grown by a margin:
/// pixels whose two counts differ pass near an edge and are left out). `none` draws the square
/// itself, both faces: one fragment where the ray meets it. The rasterizer's emulation must
/// give exactly these counts, pixel by pixel.
#[test]
fn a_flat_squares_prisms_run_one_fragment_per_column_the_ray_crosses() {
    let sc = crate::meshes::level_scene(0.3, 50.0, -60.0, 3.0);
    let depth = sc.depth_scale as f64;
    // The square [−1, 1]² in z = 0: triangle A below the diagonal y = x, B above it.
    let ms = MeshScene { scene: sc, mesh: crate::meshes::flat_square(), notes: Default::default() };
    let size = 40u32;
    let in_tri = |p: DVec2, k: usize, m: f64| {
        let inside = p.x.abs() < 1.0 + m && p.y.abs() < 1.0 + m;
        inside && if k == 0 { p.x - p.y > -m } else { p.y - p.x > -m }
    };
    let prism = fragments_per_pixel(&ms, Curved::Prism, size);
    let none = fragments_per_pixel(&ms, Curved::None, size);
    let (mut compared, mut twos) = (0, 0);
    for (i, ray) in ms.rays(size, size).iter().enumerate() {
        let o = glam::DVec3::from(ray.origin.map(|c| c as f64));
        let d = glam::DVec3::from(ray.dir.map(|c| c as f64));
        assert!(d.z < 0.0, "the camera looks down");
        // The stretch of the ray between z = 0 and z = −depth, seen from above.
        let at = |z: f64| {
            let p = o + d * ((z - o.z) / d.z);
            DVec2::new(p.x, p.y)
        };
        let (a, b) = (at(0.0), at(-depth));
        let count =
            |m: f64| (0..2).filter(|&k| (0..=2000).any(|s| in_tri(a + (b - a) * (s as f64 / 2000.0), k, m))).count();
        let (shrunk, grown) = (count(-1e-3), count(1e-3));
        if shrunk != grown {
            continue;
        }
        compared += 1;
        twos += usize::from(shrunk == 2);
        assert_eq!(prism[i].len(), shrunk, "pixel {i}: prism fragments {:?}", prism[i]);
        let on_square = in_tri(a, 0, 1e-3) || in_tri(a, 1, 1e-3);
        let near_edge = (in_tri(a, 0, -1e-3) || in_tri(a, 1, -1e-3)) != on_square;
        if !near_edge {
            assert_eq!(none[i].len(), usize::from(on_square), "pixel {i}: none fragments {:?}", none[i]);
        }
    }
    // Most pixels are compared, and the view makes rays cross the diagonal wall.
    assert!(compared > (size * size) as usize * 9 / 10, "{compared}");
    assert!(twos > 20, "{twos}");
    // The sums: every fragment of a covered pixel lies before or after its hit.
    let c = fragment_counts(&ms, Curved::Prism, size, &vec![None; (size * size) as usize]);
    assert_eq!(c.fragments, prism.iter().map(Vec::len).sum::<usize>());
    assert_eq!((c.covered, c.on_covered, c.before_hit), (0, 0, 0));
}
