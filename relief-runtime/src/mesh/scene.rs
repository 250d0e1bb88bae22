//! A scene with its mesh (a scene file's `[mesh]`, docs/meshes.md), and one ray per pixel.

use glam::Vec3;

use super::reference::{MeshHit, MeshReference};
use super::{builtin, file, Mesh, MeshError, MeshNotes};
use crate::scene::{MeshSource, Scene};

/// One ray per pixel, from the eye through the pixel's centre: every pixel has one (a miss is
/// the silhouette).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshRay {
    /// Pixel column.
    pub x: u32,
    /// Pixel row (0 at the top).
    pub y: u32,
    /// The eye, world space.
    pub origin: [f32; 3],
    /// Unit direction, world space.
    pub dir: [f32; 3],
}

/// A scene whose relief covers a mesh.
#[derive(Clone, Debug)]
pub struct MeshScene {
    /// The scene: height map, edge mode, depth scale (world units), camera, light.
    pub scene: Scene,
    /// The mesh, its uvs scaled by the scene's tiling (built-ins take it as their repeats).
    pub mesh: Mesh,
    /// What loading found that the caller should say once (generated tangents, skipped
    /// triangles).
    pub notes: MeshNotes,
}

impl MeshScene {
    /// The mesh `scene` names; an error if it names none or the mesh cannot be made.
    pub fn from_scene(scene: Scene) -> Result<MeshScene, MeshError> {
        let (mesh, notes) = match &scene.mesh {
            None => return Err(MeshError::new(scene.name.clone(), "the scene names no mesh (`[mesh]` in its file)")),
            Some(MeshSource::Builtin(b)) => {
                let path = format!("builtin:{b}");
                let m =
                    builtin::builtin(b, scene.tiling).ok_or_else(|| MeshError::new(&path, "no such built-in mesh"))?;
                let (m, skipped) = m.checked().map_err(|e| MeshError::new(&path, e))?;
                (m, MeshNotes { generated_tangents: vec![], degenerate_triangles: skipped })
            }
            Some(MeshSource::File { path, name }) => {
                let (mut m, notes) = file::load_mesh_file(path, name.as_deref())?;
                for uv in &mut m.uvs {
                    *uv *= scene.tiling;
                }
                (m, notes)
            }
        };
        Ok(MeshScene { scene, mesh, notes })
    }

    /// One ray per pixel of a `width × height` frame, row-major (pixel centres, NDC as
    /// `Scene::rays_wh`).
    pub fn rays(&self, width: u32, height: u32) -> Vec<MeshRay> {
        let cam = &self.scene.camera;
        let aspect = width as f32 / height as f32;
        let eye: Vec3 = cam.camera_position();
        let mut out = Vec::with_capacity((width * height) as usize);
        for y in 0..height {
            for x in 0..width {
                let nx = 2.0 * (x as f32 + 0.5) / width as f32 - 1.0;
                let ny = 1.0 - 2.0 * (y as f32 + 0.5) / height as f32;
                let d = cam.ray_dir(nx, ny, aspect);
                out.push(MeshRay { x, y, origin: eye.to_array(), dir: d.to_array() });
            }
        }
        out
    }

    /// The exact reference over this scene's mesh and height map.
    pub fn reference(&self) -> Result<MeshReference, MeshError> {
        MeshReference::new(&self.mesh, &self.scene.height, self.scene.edge, self.scene.depth_scale as f64)
            .map_err(|e| MeshError::new(self.scene.name.clone(), e))
    }

    /// The exact first hit of every pixel's ray of a `width × height` frame, row-major.
    pub fn reference_hits(&self, width: u32, height: u32) -> Result<Vec<Option<MeshHit>>, MeshError> {
        Ok(self.reference()?.trace_all(&self.rays(width, height)))
    }
}
