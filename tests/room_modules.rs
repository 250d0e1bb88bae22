//! The room modules (interior mapping, `relief_dsl::compose::interior`) validate in naga and
//! pass the Khronos validators: `spirv-val --target-env vulkan1.1` and `glslangValidator`.

use std::process::Command;

mod common;
use common::{run, tool};

use relief::dsl::compose::interior::{compile_room, RoomOptions, WALL_BASE};
use relief::dsl::emit;
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
        // Light scattering (seed 003 §2.3) on the shadowed pipeline.
        let options = RoomOptions { scatter: text.contains("soft").then_some(42) };
        let rc = compile_room(&p, &options).unwrap_or_else(|e| panic!("{p}: {e}"));
        let c = &rc.compiled;
        assert!(rc.wall_bindings.iter().all(|w| w.binding >= WALL_BASE && w.binding < 64));
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
            run(Command::new(glslang).args(["-G", "-S", stage, "-o"]).arg(&o).arg(&file), &format!("glslangValidator on room {p} ({stage})"));
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn light_scattering_is_off_by_default() {
    let p: Pipeline = "linear(8)+shadow=soft(8)".parse().unwrap();
    let wgsl = |o: &RoomOptions| emit::wgsl(&compile_room(&p, o).unwrap().compiled).unwrap();
    assert_eq!(RoomOptions::default().scatter, None);
    assert!(!wgsl(&RoomOptions::default()).contains("scatter"));
    assert!(wgsl(&RoomOptions { scatter: Some(42) }).contains("scatter"));
    assert!(compile_room(&p, &RoomOptions { scatter: Some(0) }).is_err(), "0 samples is refused, not defaulted");
}

/// The room's entries set no sample level and have no quad square: pipeline options they
/// do not implement are errors that name them.
#[test]
fn rooms_refuse_the_pipeline_options_they_do_not_implement() {
    for (text, says) in [("linear(8)+binary(3)+lod=auto", "lod=auto"), ("linear(8)+binary(3)+silhouette=clip", "silhouette=clip")] {
        let p: relief::Pipeline = text.parse().unwrap();
        let e = compile_room(&p, &RoomOptions::default()).err().unwrap_or_else(|| panic!("{text} compiled for a room"));
        assert!(e.to_string().contains(says) && e.to_string().contains("not implemented for rooms"), "{text}: {e}");
    }
}
