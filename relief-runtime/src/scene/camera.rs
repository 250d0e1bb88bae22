//! The camera.
//!
//! [`Camera`] orbits the centre of the quad: `angle_deg` is measured from the surface normal
//! (0 = straight down, 90 = grazing), `azimuth_deg` is the direction, around +z and from +x
//! towards +y, in which the eye sits as seen from the target. Projection follows wgpu: a
//! right-handed view, depth in [0, 1] ([`glam::Mat4::perspective_rh`]), NDC x to the right
//! and y up, pixel row 0 at the top of the image. The screen's up vector is the direction in
//! the vertical plane through the eye and the target that is perpendicular to the view, so it
//! stays defined at angle 0 (where it points away from the eye's azimuth).

use glam::{Mat4, Vec3};

/// A perspective camera that looks at a target point (the centre of the quad).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Angle between the view axis and the surface normal, degrees (0 = looking straight down).
    pub angle_deg: f32,
    /// Direction of the eye around the target, degrees from +x towards +y.
    pub azimuth_deg: f32,
    /// Distance from the eye to the target, world (= texture) units.
    pub distance: f32,
    /// Vertical field of view, degrees.
    pub fov_deg: f32,
    /// The point looked at (the centre of the quad, on z = 0).
    pub target: Vec3,
}

impl Camera {
    /// The default camera for a quad of side `tiling`: 45° from the normal, azimuth -90° (the
    /// eye on the -v side, so +u runs right and +v runs up the screen), 40° vertical field of
    /// view, at a distance where the quad fills most of a square frame.
    pub(crate) fn default_for(tiling: f32) -> Camera {
        Camera {
            angle_deg: 45.0,
            azimuth_deg: -90.0,
            distance: 1.3 * tiling,
            fov_deg: 40.0,
            target: Vec3::new(0.5 * tiling, 0.5 * tiling, 0.0),
        }
    }

    /// The eye's world position.
    pub fn camera_position(&self) -> Vec3 {
        let (a, az) = (self.angle_deg.to_radians(), self.azimuth_deg.to_radians());
        self.target + self.distance * Vec3::new(a.sin() * az.cos(), a.sin() * az.sin(), a.cos())
    }

    /// Unit vectors (forward, right, up) of the view.
    pub fn basis(&self) -> (Vec3, Vec3, Vec3) {
        let (a, az) = (self.angle_deg.to_radians(), self.azimuth_deg.to_radians());
        let forward = -Vec3::new(a.sin() * az.cos(), a.sin() * az.sin(), a.cos());
        let up = Vec3::new(-a.cos() * az.cos(), -a.cos() * az.sin(), a.sin());
        let right = forward.cross(up);
        (forward, right, up)
    }

    /// Near and far clip distances: `distance / 100` and `distance * 100`.
    pub(crate) fn near_far(&self) -> (f32, f32) {
        (self.distance * 0.01, self.distance * 100.0)
    }

    /// The view matrix (world → view, right-handed, looking down -z).
    pub fn view(&self) -> Mat4 {
        let (_, _, up) = self.basis();
        Mat4::look_at_rh(self.camera_position(), self.target, up)
    }

    /// Projection × view, wgpu clip conventions (depth 0..1). `aspect` = width / height.
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        let (near, far) = self.near_far();
        Mat4::perspective_rh(self.fov_deg.to_radians(), aspect, near, far) * self.view()
    }

    /// The world direction (unit) of the ray through NDC point `(ndc_x, ndc_y)`. Built from
    /// the camera basis directly (equal, up to rounding, to unprojecting with
    /// [`Camera::view_proj`], without its loss of precision).
    pub(crate) fn ray_dir(&self, ndc_x: f32, ndc_y: f32, aspect: f32) -> Vec3 {
        let (f, r, u, ty) = self.ray_terms();
        (f + ndc_x * ty * aspect * r + ndc_y * ty * u).normalize()
    }

    /// What [`Camera::ray_dir`] builds a direction from: the basis (forward, right, up) and
    /// `tan(fov_y / 2)`. The report's browser data ships these (with the eye) as f32 bit
    /// patterns, and the page computes the probe rays from them with the same f32 operations.
    pub(crate) fn ray_terms(&self) -> (Vec3, Vec3, Vec3, f32) {
        let (f, r, u) = self.basis();
        (f, r, u, (0.5 * self.fov_deg.to_radians()).tan())
    }

    /// The size δ of one pixel of a frame `height` pixels tall on the image plane at unit
    /// distance: `2·tan(fov_y / 2) / height` (pixels are square: the frame's width follows
    /// from the aspect).
    pub fn pixel_size(&self, height: u32) -> f32 {
        2.0 * (0.5 * self.fov_deg.to_radians()).tan() / height as f32
    }

    /// λ, the log2 of the footprint in texels of a pixel of size `pixel_size`
    /// ([`Camera::pixel_size`]) whose ray enters the relief at `entry` on the plane z = 0,
    /// for a map of `size` texels per texture unit: `log2 max(|δ·∂P/∂a|, |δ·∂P/∂b|)` in
    /// texels, with `∂P/∂a = (D·f)·(r − D·r.z/D.z)` and `∂P/∂b` likewise with the up vector
    /// (D = entry − eye; f, r, u the basis). The derivation is in relief-dsl's
    /// `compose::lod_level_fn`, the shader twin of this function; the operations are the
    /// same, in f32, so that both round to the same level away from ties. `-inf` for
    /// `pixel_size` 0.
    pub(crate) fn footprint_lambda(&self, entry: glam::Vec2, pixel_size: f32, size: [usize; 2]) -> f32 {
        let (_, right, up) = self.basis();
        let d = entry.extend(0.0) - self.camera_position();
        let dist = d.dot(up.cross(right));
        let dx = (right - d * (right.z / d.z)) * (dist * pixel_size);
        let dy = (up - d * (up.z / d.z)) * (dist * pixel_size);
        let n = glam::Vec2::new(size[0] as f32, size[1] as f32);
        let extent = (dx.truncate() * n).length().max((dy.truncate() * n).length());
        extent.log2()
    }
}

/// The whole mip level of footprint `lambda` ([`Camera::footprint_lambda`]) in a chain of
/// `levels` levels: `clamp(round(λ), 0, levels − 1)`, halves rounded to even as WGSL's
/// `round` does.
pub(crate) fn footprint_level(lambda: f32, levels: usize) -> usize {
    let last = levels.saturating_sub(1) as f32;
    lambda.round_ties_even().clamp(0.0, last) as usize
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2;

    /// Where the ray through NDC `(x, y)` meets the plane z = 0: the pinhole ray of
    /// [`Camera::ray_dir`] built in f64 (independent of the footprint formula).
    fn on_plane(c: &Camera, x: f64, y: f64) -> [f64; 2] {
        let e = c.camera_position().as_dvec3();
        let (f, r, u) = c.basis();
        let ty = (0.5 * (c.fov_deg as f64).to_radians()).tan();
        let d = f.as_dvec3() + x * ty * r.as_dvec3() + y * ty * u.as_dvec3();
        let s = -e.z / d.z;
        [e.x + s * d.x, e.y + s * d.y]
    }

    #[test]
    fn the_footprint_level_matches_projected_pixel_edges() {
        let frame = 64u32;
        let mut checked = 0;
        for (angle, azimuth) in [(0.0, -90.0), (30.0, -90.0), (55.0, 20.0), (75.0, 135.0)] {
            let c = Camera { angle_deg: angle, azimuth_deg: azimuth, ..Camera::default_for(1.0) };
            let delta = c.pixel_size(frame);
            for size in [[256usize, 256usize], [512, 128]] {
                for py in (0..frame).step_by(5) {
                    for px in (0..frame).step_by(5) {
                        // The pixel's centre, and points 1/64 pixel either side in NDC (one
                        // pixel is 2/frame), projected onto the plane: the pixel's extent
                        // is 32 times their distance.
                        let p = 1.0 / frame as f64;
                        let h = p / 32.0;
                        let (x, y) = (2.0 * (px as f64 + 0.5) * p - 1.0, 1.0 - 2.0 * (py as f64 + 0.5) * p);
                        let centre = on_plane(&c, x, y);
                        if !(0.0..=1.0).contains(&centre[0]) || !(0.0..=1.0).contains(&centre[1]) {
                            continue;
                        }
                        let texels = |a: [f64; 2], b: [f64; 2]| {
                            (((b[0] - a[0]) * size[0] as f64).powi(2) + ((b[1] - a[1]) * size[1] as f64).powi(2)).sqrt()
                        };
                        let ex = 32.0 * texels(on_plane(&c, x - h, y), on_plane(&c, x + h, y));
                        let ey = 32.0 * texels(on_plane(&c, x, y - h), on_plane(&c, x, y + h));
                        let brute = ex.max(ey).log2();
                        let entry = Vec2::new(centre[0] as f32, centre[1] as f32);
                        let lambda = c.footprint_lambda(entry, delta, size) as f64;
                        // Central differences are exact to second order: over 1/32 pixel the
                        // truncation is ~1000 times below the 1e-3 a whole pixel shows at 75°,
                        // and the f32 formula leaves ~1e-5; 1e-3 in log2 (0.07 %) is a margin
                        // that a wrong axis, factor 2 or missing term (≥ 1e-2) exceeds.
                        assert!(
                            (lambda - brute).abs() < 1e-3,
                            "angle {angle} az {azimuth} size {size:?} pixel ({px}, {py}): {lambda} vs {brute}"
                        );
                        let tie = (brute - brute.floor() - 0.5).abs() < 1e-2;
                        if !tie {
                            let want = (brute.round().max(0.0) as usize).min(7);
                            assert_eq!(footprint_level(lambda as f32, 8), want);
                            checked += 1;
                        }
                    }
                }
            }
        }
        assert!(checked > 500, "{checked}");
        assert_eq!(footprint_level(f32::NEG_INFINITY, 9), 0);
        assert_eq!(footprint_level(2.5, 9), 2, "halves round to even, as WGSL's round");
        assert_eq!(footprint_level(12.0, 9), 8);
    }
}
