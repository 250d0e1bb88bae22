//! Every default combination compiles, validates in naga, and its outputs pass the Khronos
//! validators: `spirv-val --target-env vulkan1.1` and `glslangValidator` (real processes).

use std::path::Path;
use std::process::Command;

use crate::common::{run, tool};

use relief::dsl::emit;
use relief::dsl::spec::catalog;
use relief::{Pipeline, Slot};

#[test]
fn every_default_combination_passes_spirv_val_and_glslang() {
    let spirv_val = tool("spirv-val");
    let glslang = tool("glslangValidator");
    let dir = std::env::temp_dir().join(format!("relief-khronos-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut all = Pipeline::all_defaults();
    let methods = |slot| catalog().iter().filter(|m| m.slot == slot).count();
    assert_eq!(all.len(), methods(Slot::Coarse) * methods(Slot::Refine) * methods(Slot::Shadow));
    assert!(all.len() >= 7 * 4 * 3, "at least the 7 coarse × 4 refine × 3 shadow of the first stages");
    // Every ao stage and every kind of nested shadow search, too.
    for extra in [
        "rcs(15)+binary(5)+ao=cone_normal",
        "csm(15)+binary(4)+ao=cone_ratio",
        "linear(16)+shadow=hard(csm(15, form=textbook, sample=min4))",
        // The textbook form of every cone method (the defaults above are the safe forms).
        "csm(15, form=textbook)+binary(5)",
        "csm(15, form=textbook, sample=nearest)",
        "qcsm(15, form=textbook)+interval(3)",
        "rcs(15, form=textbook)+binary(5)",
        "cns(15, form=textbook)+secant(3)",
        "rcns(15, form=textbook)+binary(5)",
        "mcns(15, 3, form=textbook)",
        "pcns(15, 2, form=textbook)+binary(4)",
        "cns(10)+shadow=hard(rcs(8, start=bracket))+ao=cone_ratio",
        "mcns(10, 2)+interval(2)+shadow=hard(pcns(6, 3))",
        "sphere(20)+secant(3)+shadow=hard(sphere(10))",
        // Sampling at a level: the stage-wide level, gathers as nearest samples, the cell
        // map atlas of the safe cone methods, and the silhouette's discard.
        "linear(32)+binary(5)+shadow=soft(16)+lod=auto",
        "csm(15, form=textbook, sample=min4)+binary(5)+lod=level(1)",
        "csm(15)+binary(5)+lod=auto",
        "rcs(15)+interval(3)+shadow=hard(qcsm(8))+lod=auto",
        "maxmip(32)+silhouette=clip",
        "maxmip(32)+interval(2)+lod=auto",
        "qcsm(12)+shadow=hard(qcsm(12))",
    ] {
        all.push(extra.parse().unwrap_or_else(|e| panic!("{extra}: {e}")));
    }
    let chunks: Vec<&[Pipeline]> = all.chunks(all.len().div_ceil(2)).collect();
    std::thread::scope(|scope| {
        for chunk in chunks {
            let dir = &dir;
            scope.spawn(move || validate_all(chunk, dir, spirv_val, glslang));
        }
    });
    std::fs::remove_dir_all(&dir).ok();
}

fn validate_all(all: &[Pipeline], dir: &Path, spirv_val: &str, glslang: &str) {
    for p in all {
        let out = emit::emit(p).unwrap_or_else(|e| panic!("{p}: {e}"));
        let stem = p.file_stem();
        let spv = dir.join(format!("{stem}.spv"));
        std::fs::write(&spv, bytes(&out.spirv)).unwrap();
        run(Command::new(spirv_val).args(["--target-env", "vulkan1.1"]).arg(&spv), &format!("spirv-val on {p}"));
        assert_eq!(out.glsl.len(), 3, "{p}: one GLSL file per entry point");
        for (stage, src) in &out.glsl {
            let file = dir.join(format!("{stem}.{stage}.glsl"));
            std::fs::write(&file, src).unwrap();
            validate_glsl(glslang, &file, stage, &format!("glslangValidator on {p} ({stage})"));
        }
    }
}

fn validate_glsl(glslang: &str, file: &Path, stage: &str, what: &str) {
    // `-G`: compile for OpenGL SPIR-V, which checks the explicit bindings naga's binding map
    // gave every resource (a binding left out fails here).
    let spv = file.with_extension("glsl.spv");
    run(Command::new(glslang).args(["-G", "-S", stage, "-o"]).arg(&spv).arg(file), what);
}

fn bytes(words: &[u32]) -> Vec<u8> {
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}

#[test]
fn the_validators_reject_a_broken_file() {
    // The harness above would be worthless if the tools accepted anything.
    let glslang = tool("glslangValidator");
    let file = std::env::temp_dir().join(format!("relief-broken-{}.frag.glsl", std::process::id()));
    std::fs::write(&file, "#version 450\nvoid main() { undefined_thing = 1; }\n").unwrap();
    let out = Command::new(glslang).args(["-G", "-S", "frag"]).arg(&file).output().unwrap();
    assert!(!out.status.success());
    let spirv_val = tool("spirv-val");
    let spv = std::env::temp_dir().join(format!("relief-broken-{}.spv", std::process::id()));
    std::fs::write(&spv, [0x07u8, 0x23, 0x02, 0x03, 0, 0, 0, 0]).unwrap();
    let out = Command::new(spirv_val).arg(&spv).output().unwrap();
    assert!(!out.status.success());
}
