//! Relief on curved meshes, the CPU side: meshes (built-in and from files), the scenes that
//! name them, and the exact first hit of a pixel's ray with the displaced surface.
//!
//! The surface is `S = P − depth·(1 − h)·N` over each triangle, P and N interpolated
//! barycentrically (N *not* renormalized), h bilinear between texel centres with the scene's
//! edge mode; docs/meshes.md states the conventions and how the reference is exact.
//!
//! # Modules
//!
//! [`builtin`] the sphere, cylinder and torus; [`mod@file`] glTF 2.0 and OBJ files;
//! [`tangent`] MikkTSpace tangents; [`surface`] the displaced surface and its proven boxes;
//! [`mod@reference`] the exact trace over a BVH of patches; [`scene`] a scene with its mesh and
//! its per-pixel rays; [`vertices`] the mesh as the mesh module's vertices for each `curved=`
//! mode.

use glam::{Vec2, Vec3, Vec4};

pub mod builtin;
pub mod file;
pub mod fragments;
pub mod reference;
pub mod scene;
pub mod surface;
pub mod tangent;
pub mod vertices;

pub use reference::{MeshHit, MeshReference};
pub use scene::{MeshRay, MeshScene};

/// The most triangles a mesh may have (files and built-ins alike): far above any mesh relief
/// measures, low enough that a hostile count is refused before memory is taken.
pub const MAX_TRIANGLES: usize = 1 << 24;

/// The most vertices a mesh may have (see [`MAX_TRIANGLES`]).
pub const MAX_VERTICES: usize = 1 << 24;

/// A triangle mesh with what relief mapping needs at each vertex.
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    /// The mesh's name (a glTF mesh's name, an OBJ object's, the built-in's).
    pub name: String,
    /// Vertex positions, world units.
    pub positions: Vec<Vec3>,
    /// Unit vertex normals, pointing out of the surface (away from the relief).
    pub normals: Vec<Vec3>,
    /// Unit tangents along +u in `xyz`; `w` = ±1, the handedness: the bitangent (along +v)
    /// is `w · cross(normal, tangent)` (glTF's convention).
    pub tangents: Vec<Vec4>,
    /// Texture coordinates as the shader samples the height map (tiling already applied).
    pub uvs: Vec<Vec2>,
    /// Triangles, counter-clockwise seen from outside; degenerate ones removed (see
    /// [`Mesh::checked`]).
    pub triangles: Vec<[u32; 3]>,
}

/// What loading a mesh found that the caller should say once: generated tangents and
/// skipped triangles.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct MeshNotes {
    /// Meshes (by name) whose file had no tangents: they were generated with MikkTSpace.
    pub generated_tangents: Vec<String>,
    /// Degenerate triangles skipped: zero area in position or in uv, or a non-finite value.
    pub degenerate_triangles: usize,
}

impl MeshNotes {
    /// One warning line for stderr, or `None` if there is nothing to say.
    pub fn warning(&self) -> Option<String> {
        let mut parts = Vec::new();
        if !self.generated_tangents.is_empty() {
            parts.push(format!("tangents generated (MikkTSpace) for {}", self.generated_tangents.join(", ")));
        }
        if self.degenerate_triangles > 0 {
            parts.push(format!("{} degenerate triangles skipped", self.degenerate_triangles));
        }
        (!parts.is_empty()).then(|| format!("warning: {}", parts.join("; ")))
    }
}

/// Why a mesh could not be made. Displays as one line naming the file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}: {message}", path.display())]
pub struct MeshError {
    /// The mesh file (or `builtin:NAME`).
    pub path: std::path::PathBuf,
    /// What is wrong, one line.
    pub message: String,
}

impl MeshError {
    pub(crate) fn new(path: impl Into<std::path::PathBuf>, message: impl Into<String>) -> MeshError {
        let message: String = message.into();
        MeshError { path: path.into(), message: message.replace(['\n', '\r'], " ") }
    }
}

impl Mesh {
    /// The mesh with every triangle checked: an index out of range is an error; a triangle
    /// with a non-finite position, normal or uv, or with zero area in position or in uv, is
    /// removed and counted (returned). A triangle with zero uv area cannot carry a height
    /// map (its texture space is singular), one with zero area covers nothing.
    pub fn checked(mut self) -> Result<(Mesh, usize), String> {
        let n = self.positions.len();
        if self.normals.len() != n || self.uvs.len() != n || self.tangents.len() != n {
            return Err(format!(
                "mesh `{}`: {} positions, {} normals, {} uvs, {} tangents (one each per vertex)",
                self.name,
                n,
                self.normals.len(),
                self.uvs.len(),
                self.tangents.len()
            ));
        }
        if let Some(t) = self.triangles.iter().find(|t| t.iter().any(|&i| i as usize >= n)) {
            return Err(format!("mesh `{}`: triangle {t:?} indexes past its {n} vertices", self.name));
        }
        let before = self.triangles.len();
        let (p, u, nn) = (&self.positions, &self.uvs, &self.normals);
        self.triangles
            .retain(|t| !degenerate(t.map(|i| p[i as usize]), t.map(|i| u[i as usize]), t.map(|i| nn[i as usize])));
        let skipped = before - self.triangles.len();
        Ok((self, skipped))
    }

    /// The centre and radius of a sphere holding every vertex (the bounding box's).
    pub fn bounds(&self) -> (Vec3, f32) {
        let lo = self.positions.iter().fold(Vec3::splat(f32::INFINITY), |a, &p| a.min(p));
        let hi = self.positions.iter().fold(Vec3::splat(f32::NEG_INFINITY), |a, &p| a.max(p));
        ((lo + hi) * 0.5, (hi - lo).length() * 0.5)
    }

    /// The meshes joined into one (indices shifted), named `a+b+…`.
    pub fn join(meshes: Vec<Mesh>) -> Mesh {
        let mut out = Mesh {
            name: meshes.iter().map(|m| m.name.as_str()).collect::<Vec<_>>().join("+"),
            positions: vec![],
            normals: vec![],
            tangents: vec![],
            uvs: vec![],
            triangles: vec![],
        };
        for m in meshes {
            let base = out.positions.len() as u32;
            out.triangles.extend(m.triangles.iter().map(|t| t.map(|i| i + base)));
            out.positions.extend(m.positions);
            out.normals.extend(m.normals);
            out.tangents.extend(m.tangents);
            out.uvs.extend(m.uvs);
        }
        out
    }
}

/// The largest coordinate (position or uv) relief takes as finite: products of two stay far
/// inside f32 (MikkTSpace works in f32).
pub const MAX_COORDINATE: f32 = 1e12;

/// Whether a triangle cannot carry relief: a non-finite value (or one beyond
/// [`MAX_COORDINATE`]), or an area that is zero (to rounding: below 1e-12 of its squared
/// longest side) in position or in uv.
fn degenerate(p: [Vec3; 3], uv: [Vec2; 3], n: [Vec3; 3]) -> bool {
    let ok3 = |v: &Vec3| v.is_finite() && v.abs().max_element() <= MAX_COORDINATE;
    let ok2 = |v: &Vec2| v.is_finite() && v.abs().max_element() <= MAX_COORDINATE;
    let finite = p.iter().all(ok3) && uv.iter().all(ok2) && n.iter().all(ok3);
    if !finite {
        return true;
    }
    let (p, uv) = (p.map(|v| v.as_dvec3()), uv.map(|v| v.as_dvec2()));
    let area3 = (p[1] - p[0]).cross(p[2] - p[0]).length();
    let side3 = (p[1] - p[0]).length().max((p[2] - p[0]).length()).max((p[2] - p[1]).length());
    let area2 = (uv[1] - uv[0]).perp_dot(uv[2] - uv[0]).abs();
    let side2 = (uv[1] - uv[0]).length().max((uv[2] - uv[0]).length()).max((uv[2] - uv[1]).length());
    area3 <= 1e-12 * side3 * side3 || area2 <= 1e-12 * side2 * side2
}
