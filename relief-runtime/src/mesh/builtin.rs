//! The built-in meshes: a sphere, an open cylinder and a torus, all around the z axis at the
//! origin, with analytic normals, uvs and tangents (docs/meshes.md).
//!
//! Each is a grid over its two angles (or angle and height): u runs with the angle around z,
//! v along the other parameter, so that the tangent frame is right-handed (`w = +1`: tangent
//! × bitangent = normal, as on relief's flat quad, where u = x, v = y and the normal is +z).
//! The height map repeats `repeats = [ru, rv]` times along u and v: the scene's tiling t gives
//! `[2t, t]` (the sphere's equator is twice its meridian, the cylinder of height 2 has a
//! circumference of 2π ≈ 3·2 and takes `[3t, t]`, the torus's tube radius is half its
//! centre-line radius), so a texel is about square where it is largest. A whole t joins
//! the map seamlessly where u wraps.

use std::f32::consts::{PI, TAU};

use glam::{Vec2, Vec3, Vec4};

use super::Mesh;

/// Segments around z, and along the second parameter, of each built-in.
const SEGMENTS: (usize, usize) = (96, 48);

/// The built-in mesh `name` (one of `scene::file::BUILTIN_MESHES`) for a scene of tiling
/// `tiling`; `None` for another name.
pub fn builtin(name: &str, tiling: f32) -> Option<Mesh> {
    let t = tiling;
    Some(match name {
        "sphere" => sphere(SEGMENTS.0, SEGMENTS.1, [2.0 * t, t]),
        "cylinder" => cylinder(SEGMENTS.0, 8, [3.0 * t, t]),
        "torus" => torus(SEGMENTS.0, SEGMENTS.1, 1.0, 0.5, [2.0 * t, t]),
        _ => return None,
    })
}

/// The unit sphere: u = φ/2π (the longitude, from +x towards +y), v = 0 at the south pole
/// (z = −1) and 1 at the north pole. At a pole the triangles meet in one vertex per segment,
/// whose tangent is that of the segment's middle longitude.
pub fn sphere(nu: usize, nv: usize, repeats: [f32; 2]) -> Mesh {
    grid("sphere", nu, nv, repeats, true, |s, t| {
        let (phi, theta) = (TAU * s, PI * (1.0 - t)); // theta from +z
        let n = if t <= 0.0 {
            -Vec3::Z
        } else if t >= 1.0 {
            Vec3::Z
        } else {
            Vec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos())
        };
        (n, n, Vec3::new(-phi.sin(), phi.cos(), 0.0))
    })
}

/// The open cylinder of radius 1 from z = −1 to z = 1: u = φ/2π, v = (z + 1)/2.
pub fn cylinder(nu: usize, nv: usize, repeats: [f32; 2]) -> Mesh {
    grid("cylinder", nu, nv, repeats, false, |s, t| {
        let phi = TAU * s;
        let n = Vec3::new(phi.cos(), phi.sin(), 0.0);
        (n + Vec3::new(0.0, 0.0, 2.0 * t - 1.0), n, Vec3::new(-phi.sin(), phi.cos(), 0.0))
    })
}

/// The torus with centre-line radius `big` and tube radius `small`: u = φ/2π around z, v =
/// ψ/2π around the tube, ψ = 0 on the outer equator and rising towards +z.
pub fn torus(nu: usize, nv: usize, big: f32, small: f32, repeats: [f32; 2]) -> Mesh {
    grid("torus", nu, nv, repeats, false, |s, t| {
        let (phi, psi) = (TAU * s, TAU * t);
        let n = Vec3::new(psi.cos() * phi.cos(), psi.cos() * phi.sin(), psi.sin());
        let centre = Vec3::new(big * phi.cos(), big * phi.sin(), 0.0);
        (centre + small * n, n, Vec3::new(-phi.sin(), phi.cos(), 0.0))
    })
}

/// A `nu × nv` grid of quads over (s, t) ∈ [0, 1]², two triangles each, counter-clockwise
/// from outside; `f(s, t)` gives the position, the unit normal and the unit tangent along +u.
/// With `poles`, the rows t = 0 and t = 1 are single points: their vertices take the s of the
/// segment's middle and the triangle that would have no area there is left out.
fn grid(
    name: &str,
    nu: usize,
    nv: usize,
    repeats: [f32; 2],
    poles: bool,
    f: impl Fn(f32, f32) -> (Vec3, Vec3, Vec3),
) -> Mesh {
    let mut m = Mesh {
        name: name.to_string(),
        positions: vec![],
        normals: vec![],
        tangents: vec![],
        uvs: vec![],
        triangles: vec![],
    };
    let row = nu + 1;
    for j in 0..=nv {
        for i in 0..=nu {
            let t = j as f32 / nv as f32;
            let pole = poles && (j == 0 || j == nv);
            // A pole's vertex i serves segment i, so it sits at that segment's middle.
            let s = if pole { (i as f32 + 0.5).min(nu as f32) / nu as f32 } else { i as f32 / nu as f32 };
            let (p, n, tan) = f(s, t);
            m.positions.push(p);
            m.normals.push(n);
            m.tangents.push(Vec4::from((tan, 1.0)));
            m.uvs.push(Vec2::new(repeats[0] * s, repeats[1] * t));
        }
    }
    for j in 0..nv {
        for i in 0..nu {
            let (a, b) = ((j * row + i) as u32, (j * row + i + 1) as u32);
            let (c, d) = (((j + 1) * row + i + 1) as u32, ((j + 1) * row + i) as u32);
            if poles && j == 0 {
                m.triangles.push([a, c, d]); // a is the south pole's vertex of segment i
            } else if poles && j == nv - 1 {
                m.triangles.push([a, b, d]); // d is the north pole's vertex of segment i
            } else {
                m.triangles.push([a, b, c]);
                m.triangles.push([a, c, d]);
            }
        }
    }
    m
}
