//! The mesh of a `relief export` bundle (a `curved=` pipeline on a mesh scene): the mesh as
//! relief draws it for that mode, written as one binary glTF 2.0 file (`mesh.glb`), and the
//! `mesh` entry of `relief.json` saying which attribute feeds which `MeshVertex` member and
//! what the mesh's `Params` are.
//!
//! The `.glb`'s vertex buffer view is the `MeshVertex` records byte for byte as the runtime
//! uploads them (thirteen `vec4<f32>`, 208 bytes each, from `mesh::vertices::mesh_vertices`),
//! and its accessors read them in place (byte stride 208): the standard attributes where one
//! fits (`POSITION`, `NORMAL`, `TANGENT`, `TEXCOORD_0`), glTF custom attributes (a leading
//! `_`) for the rest. The indices follow as `u32`. Written by hand (a GLB is a 12-byte header
//! and two chunks); `tests/threejs_mesh.rs` reads it back with the `gltf` crate.

use anyhow::{bail, Context};
use relief_dsl::compose::mesh::MeshVertex;
use relief_dsl::spec::Curved;
use relief_runtime::mesh::vertices::mesh_vertices;
use relief_runtime::mesh::MeshScene;
use serde_json::json;

/// The bundle's mesh file.
pub const MESH_FILE: &str = "mesh.glb";

/// One attribute of the `.glb`: its glTF name, the `MeshVertex` member (and components) it
/// carries, its byte offset in the record and its accessor type.
struct Attribute {
    gltf: &'static str,
    member: &'static str,
    offset: usize,
    ty: &'static str,
    components: usize,
}

/// The attributes `curved` reads, in `MeshVertex` order.
fn attributes(curved: Curved) -> Vec<Attribute> {
    let a = |gltf, member, offset, ty, components| Attribute { gltf, member, offset, ty, components };
    let mut v = vec![a("POSITION", "position.xyz", 0, "VEC3", 3)];
    if curved == Curved::Prism {
        v.push(a("_LAYER", "position.w", 12, "SCALAR", 1));
    }
    v.extend([
        a("NORMAL", "normal.xyz", 16, "VEC3", 3),
        a("TANGENT", "tangent", 32, "VEC4", 4),
        a("TEXCOORD_0", "uv.xy", 48, "VEC2", 2),
        a("_UV_SCALE", "uv.zw", 56, "VEC2", 2),
    ]);
    match curved {
        Curved::None => {}
        Curved::Quadric => v.push(a("_CURVATURE", "curvature.xy", 64, "VEC2", 2)),
        Curved::Prism => {
            v.push(a("_PRISM_A", "prism_a", 80, "VEC4", 4));
            v.push(a("_PRISM_B", "prism_b.xy", 96, "VEC2", 2));
            v.extend([
                a("_PRISM_P0", "prism_p0.xyz", 112, "VEC3", 3),
                a("_PRISM_P1", "prism_p1.xyz", 128, "VEC3", 3),
                a("_PRISM_P2", "prism_p2.xyz", 144, "VEC3", 3),
                a("_PRISM_N0", "prism_n0.xyz", 160, "VEC3", 3),
                a("_PRISM_N1", "prism_n1.xyz", 176, "VEC3", 3),
                a("_PRISM_N2", "prism_n2.xyz", 192, "VEC3", 3),
            ]);
        }
    }
    v
}

/// Pads `v` with `fill` to a multiple of 4 bytes (GLB chunks and glTF buffer views are
/// 4-byte aligned).
fn pad4(v: &mut Vec<u8>, fill: u8) {
    while !v.len().is_multiple_of(4) {
        v.push(fill);
    }
}

/// The `.glb` bytes of `vertices` and `indices` with `curved`'s attributes.
fn glb(vertices: &[MeshVertex], indices: &[u32], curved: Curved, name: &str) -> anyhow::Result<Vec<u8>> {
    const STRIDE: usize = std::mem::size_of::<MeshVertex>();
    let vertex_bytes: &[u8] = bytemuck::cast_slice(vertices);
    let index_bytes: &[u8] = bytemuck::cast_slice(indices);
    let mut bin = vertex_bytes.to_vec();
    pad4(&mut bin, 0);
    let index_offset = bin.len();
    bin.extend_from_slice(index_bytes);
    pad4(&mut bin, 0);
    let mut accessors = Vec::new();
    let mut attrs = serde_json::Map::new();
    for (i, at) in attributes(curved).iter().enumerate() {
        let mut acc = json!({
            "bufferView": 0,
            "byteOffset": at.offset,
            "componentType": 5126,
            "count": vertices.len(),
            "type": at.ty,
        });
        if at.gltf == "POSITION" {
            // glTF requires the bounds of POSITION.
            let bound = |c: usize, pick: fn(f32, f32) -> f32, start: f32| {
                vertices.iter().map(|v| v.position[c]).fold(start, pick)
            };
            let lo: [f32; 3] = std::array::from_fn(|c| bound(c, f32::min, f32::INFINITY));
            let hi: [f32; 3] = std::array::from_fn(|c| bound(c, f32::max, f32::NEG_INFINITY));
            acc["min"] = json!(lo);
            acc["max"] = json!(hi);
        }
        debug_assert!(at.offset + 4 * at.components <= STRIDE);
        accessors.push(acc);
        attrs.insert(at.gltf.into(), i.into());
    }
    let index_accessor = accessors.len();
    accessors.push(json!({
        "bufferView": 1,
        "componentType": 5125,
        "count": indices.len(),
        "type": "SCALAR",
    }));
    let doc = json!({
        "asset": { "version": "2.0", "generator": "relief export" },
        "scene": 0,
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "mesh": 0, "name": name }],
        "meshes": [{ "name": name, "primitives": [{ "attributes": attrs, "indices": index_accessor, "mode": 4 }] }],
        "buffers": [{ "byteLength": bin.len() }],
        "bufferViews": [
            { "buffer": 0, "byteOffset": 0, "byteLength": vertex_bytes.len(), "byteStride": STRIDE, "target": 34962 },
            { "buffer": 0, "byteOffset": index_offset, "byteLength": index_bytes.len(), "target": 34963 },
        ],
        "accessors": accessors,
    });
    let mut text = serde_json::to_vec(&doc)?;
    pad4(&mut text, b' ');
    let total = 12 + 8 + text.len() + 8 + bin.len();
    let len32 =
        |n: usize| u32::try_from(n).map(u32::to_le_bytes).context("the mesh is over 4 GiB: a .glb cannot hold it");
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&len32(total)?);
    out.extend_from_slice(&len32(text.len())?);
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&text);
    out.extend_from_slice(&len32(bin.len())?);
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    Ok(out)
}

/// Writes the mesh of `ms` as `curved` draws it into `dir/mesh.glb` and returns the `mesh`
/// entry of `relief.json`.
pub fn write_mesh(dir: &std::path::Path, ms: &MeshScene, curved: Curved) -> anyhow::Result<serde_json::Value> {
    let (vertices, indices) = mesh_vertices(&ms.mesh, curved);
    if vertices.is_empty() || indices.is_empty() {
        bail!("mesh {}: no triangle to export", ms.mesh.name);
    }
    let bytes = glb(&vertices, &indices, curved, &ms.mesh.name)?;
    relief_runtime::io::write_atomic(&dir.join(MESH_FILE), &bytes)?;
    let scene = &ms.scene;
    let cam = &scene.camera;
    let eye = cam.camera_position();
    let (_, _, up) = cam.basis();
    let l = scene.light_dir.normalize();
    let (near, far) = (cam.distance * 0.01, cam.distance * 100.0);
    let members: serde_json::Map<String, serde_json::Value> =
        attributes(curved).iter().map(|a| (a.member.to_string(), a.gltf.into())).collect();
    let vertex_stage = match curved {
        Curved::Prism => "position.xyz − normal·(1 − layer)·depth_scale, then view_proj (the floor vertices, layer 0, move the relief's depth along −N); pass position (w = layer), normal, tangent, uv, uv_scale, prism_a, prism_b and, flat, prism_p0..2 and prism_n0..2 (the triangle's corner points and normals) to the fragment",
        Curved::Quadric => "view_proj · position; pass position, normal, tangent, uv, uv_scale, curvature to the fragment",
        Curved::None => "view_proj · position; pass position, normal, tangent, uv, uv_scale to the fragment",
    };
    Ok(json!({
        "file": MESH_FILE,
        "container": "glTF 2.0 binary (.glb): one mesh, one primitive, triangles, u32 indices; the vertex buffer view is the MeshVertex records relief uploads (208 bytes each, member k at byte 16·k)",
        "name": ms.mesh.name,
        "curved": curved.name(),
        "vertices": vertices.len(),
        "indices": indices.len(),
        "vertex_stride": std::mem::size_of::<MeshVertex>(),
        "attributes": members,
        "vertex_stage": vertex_stage,
        "draw": "back faces culled (counter-clockwise front faces), depth test less, the fragment writes the hit's depth; discard where hit.covered is 0",
        "space": "object space is the scene's world space (the mesh has no transform)",
        "params": {
            "view_proj": "the engine's own: object → clip",
            "camera": [eye.x, eye.y, eye.z, scene.depth_scale],
            "camera_is": "xyz the eye in object space, w the relief's depth in object units (depth_scale)",
            "light": [l.x, l.y, l.z, relief_runtime::gpu::AMBIENT],
            "light_is": "xyz toward the light (unit, object space), w the ambient share",
            "edge": if scene.edge == relief_runtime::EdgeMode::Clamp { "clamp" } else { "repeat" },
        },
        "view": {
            "eye": [eye.x, eye.y, eye.z],
            "target": [cam.target.x, cam.target.y, cam.target.z],
            "up": [up.x, up.y, up.z],
            "fov_y_deg": cam.fov_deg,
            "near": near,
            "far": far,
            "projection": "right-handed, looking down −z, depth 0 at near and 1 at far (wgpu's, glam's perspective_rh); NDC y up",
            "view_proj_square": cam.view_proj(1.0).to_cols_array(),
        },
    }))
}
