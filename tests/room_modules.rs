//! The room modules (interior mapping, `relief_dsl::compose::interior`) validate in naga and
//! pass the Khronos validators: `spirv-val --target-env vulkan1.1` and `glslangValidator`.

use std::process::Command;

use crate::common::{run, tool};

use relief::dsl::compose::interior::{compile_room, RoomOptions, WALL_BASE, WINDOW_MAP};
use relief::dsl::emit;
use relief::dsl::ir::{Image, Resource};
use relief::Pipeline;

#[test]
fn room_modules_pass_naga_spirv_val_and_glslang() {
    let spirv_val = tool("spirv-val");
    let glslang = tool("glslangValidator");
    let dir = std::env::temp_dir().join(format!("relief-room-khronos-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for text in [
        "none",
        "linear(32)+binary(5)+shadow=soft(16)",
        "linear_dynamic(8, 32)+interval(8)",
        "linear_distance+binary(5)+shadow=hard(16)",
        "linear(400)+interval(8)",
        "csm(15)+binary(5)+ao=cone_ratio",
    ] {
        let p: Pipeline = text.parse().unwrap();
        // Light scattering (Amaro & Gustafsson 2022, §2.3) on the shadowed pipeline.
        let options = RoomOptions { scatter: text.contains("soft").then_some(42) };
        let c = &compile_room(&p, &options).unwrap_or_else(|e| panic!("{p}: {e}"));
        // The binding table: every wall texture at a wall binding below the probe's buffers,
        // named for its wall; every other texture the window's.
        for e in &c.bindings {
            if let Resource::Texture { image, wall, .. } = e.resource {
                match wall {
                    Some(k) => {
                        assert!(e.binding >= WALL_BASE && e.binding < 64, "{p}: {e:?}");
                        assert!(e.name.ends_with(&format!("_wall{k}")), "{p}: {e:?}");
                    }
                    None => assert_eq!((image, e.binding), (Image::Window, WINDOW_MAP), "{p}"),
                }
            }
        }
        let bound = c.module.global_variables.iter().filter(|(_, g)| g.binding.is_some()).count();
        assert_eq!(bound, c.bindings.len(), "{p}: one table entry per bound global");
        let names: Vec<&str> = c.module.entry_points.iter().map(|e| e.name.as_str()).collect();
        assert_eq!(names, ["vs_room", "fs_room", "probe_room"], "{p}");
        // Every wall has its own height map (five textures at the walls' bindings).
        let walls = c
            .module
            .global_variables
            .iter()
            .filter(|(_, g)| g.name.as_deref().is_some_and(|n| n.starts_with("height_map_wall")))
            .filter(|(_, g)| g.binding.is_some_and(|b| b.binding >= WALL_BASE))
            .count();
        if text != "none" {
            assert_eq!(walls, 5, "{p}: one height map per wall");
        }
        let out = emit::all(c).unwrap_or_else(|e| panic!("{p}: {e}"));
        let stem = p.file_stem();
        let spv = dir.join(format!("room-{stem}.spv"));
        std::fs::write(&spv, out.spirv.iter().flat_map(|w| w.to_le_bytes()).collect::<Vec<u8>>()).unwrap();
        run(Command::new(spirv_val).args(["--target-env", "vulkan1.1"]).arg(&spv), &format!("spirv-val on room {p}"));
        assert_eq!(out.glsl.len(), 3);
        for (stage, src) in &out.glsl {
            let file = dir.join(format!("room-{stem}.{stage}.glsl"));
            std::fs::write(&file, src).unwrap();
            let o = file.with_extension("glsl.spv");
            run(
                Command::new(glslang).args(["-G", "-S", stage, "-o"]).arg(&o).arg(&file),
                &format!("glslangValidator on room {p} ({stage})"),
            );
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn light_scattering_is_off_by_default() {
    let p: Pipeline = "linear(8)+shadow=soft(8)".parse().unwrap();
    let wgsl = |o: &RoomOptions| emit::wgsl(&compile_room(&p, o).unwrap()).unwrap();
    assert_eq!(RoomOptions::default().scatter, None);
    assert!(!wgsl(&RoomOptions::default()).contains("scatter"));
    assert!(wgsl(&RoomOptions { scatter: Some(42) }).contains("scatter"));
    assert!(compile_room(&p, &RoomOptions { scatter: Some(0) }).is_err(), "0 samples is refused, not defaulted");
}

/// The room's entries set no sample level and have no quad square: pipeline options they
/// do not implement are errors that name them.
#[test]
fn rooms_refuse_the_pipeline_options_they_do_not_implement() {
    for (text, says) in
        [("linear(8)+binary(3)+lod=auto", "lod=auto"), ("linear(8)+binary(3)+silhouette=clip", "silhouette=clip")]
    {
        let p: relief::Pipeline = text.parse().unwrap();
        let e = compile_room(&p, &RoomOptions::default()).err().unwrap_or_else(|| panic!("{text} compiled for a room"));
        assert!(e.to_string().contains(says) && e.to_string().contains("not implemented for rooms"), "{text}: {e}");
    }
}

/// The room's records are laid out by naga as the Rust structs the runtime uploads and reads
/// (one field list declares both): same size, and member k at the struct's offset of field k.
#[test]
fn room_records_match_their_rust_structs() {
    use relief::dsl::compose::interior::{RoomHit, RoomParams, RoomRay};
    let p: relief::Pipeline = "linear(4)".parse().unwrap();
    let rc = compile_room(&p, &RoomOptions::default()).unwrap();
    let module = &rc.module;
    let span_of = |name: &str| -> (u32, Vec<u32>) {
        let ty = module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("no type {name}"))
            .1;
        match &ty.inner {
            naga::TypeInner::Struct { members, span } => (*span, members.iter().map(|m| m.offset).collect()),
            other => panic!("{name} is {other:?}"),
        }
    };
    assert_eq!(span_of("RoomParams"), (std::mem::size_of::<RoomParams>() as u32, vec![0, 16, 32, 48]));
    assert_eq!(span_of("RoomRay"), (std::mem::size_of::<RoomRay>() as u32, vec![0, 16]));
    assert_eq!(span_of("RoomHit"), (std::mem::size_of::<RoomHit>() as u32, (0..8).map(|i| 4 * i).collect()));
    assert_eq!(std::mem::offset_of!(RoomHit, converged), 28);
}
