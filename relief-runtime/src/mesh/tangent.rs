//! Tangents by MikkTSpace (Mikkelsen 2008), through the `mikktspace` crate, for meshes whose
//! file has none: the tangent frame that normal-map bakers and engines agree on.

use glam::Vec4;

use super::Mesh;

/// The mesh seen corner by corner, as `mikktspace` reads it.
struct Corners<'a> {
    mesh: &'a mut Mesh,
}

impl mikktspace::Geometry for Corners<'_> {
    fn num_faces(&self) -> usize {
        self.mesh.triangles.len()
    }
    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }
    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.mesh.positions[self.mesh.triangles[face][vert] as usize].to_array()
    }
    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.mesh.normals[self.mesh.triangles[face][vert] as usize].to_array()
    }
    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        self.mesh.uvs[self.mesh.triangles[face][vert] as usize].to_array()
    }
    fn set_tangent_encoded(&mut self, tangent: [f32; 4], face: usize, vert: usize) {
        let i = self.mesh.triangles[face][vert] as usize;
        self.mesh.tangents[i] = Vec4::from_array(tangent);
    }
}

/// Fills `mesh.tangents` by MikkTSpace. A vertex takes the tangent of its corners (MikkTSpace
/// gives corners that share position, normal and uv the same tangent; a vertex shared by
/// corners it would split takes the last). `w` is the handedness, ±1. An error if MikkTSpace
/// gives up (it does on meshes without a triangle).
pub fn generate(mesh: &mut Mesh) -> Result<(), String> {
    mesh.tangents = vec![Vec4::new(1.0, 0.0, 0.0, 1.0); mesh.positions.len()];
    if mesh.triangles.is_empty() {
        return Ok(());
    }
    if !mikktspace::generate_tangents(&mut Corners { mesh }) {
        return Err("MikkTSpace could not generate tangents".into());
    }
    for t in &mut mesh.tangents {
        let w = if t.w < 0.0 { -1.0 } else { 1.0 };
        *t = Vec4::from((t.truncate().normalize_or_zero(), w));
    }
    Ok(())
}
