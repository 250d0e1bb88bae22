//! `relief gen --library`: four files per pipeline, the options reach them, and library
//! options without `--library` are an error.

use std::process::Command;

fn relief() -> Command {
    Command::new(env!("CARGO_BIN_EXE_relief"))
}

#[test]
fn gen_library_writes_four_files_with_the_options() {
    let out = std::env::temp_dir().join(format!("relief-cli-library-{}", std::process::id()));
    std::fs::remove_dir_all(&out).ok();
    let o = relief()
        .args([
            "gen",
            "linear(10)+binary(5)+shadow=soft(30)",
            "maxmip(20)",
            "--library",
            "--group",
            "3",
            "--binding",
            "7",
        ])
        .args(["--prefix", "rock", "--import-path", "relief::NAME", "--edge", "clamp", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut files: Vec<String> =
        std::fs::read_dir(&out).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    files.sort();
    let stem = "linear_10__binary_5__shadow-soft_30";
    let mut expect: Vec<String> = ["glsl", "hlsl", "metal", "wgsl"]
        .iter()
        .flat_map(|e| [format!("{stem}.lib.{e}"), format!("maxmip_20.lib.{e}")])
        .collect();
    expect.sort();
    assert_eq!(files, expect);
    let wgsl = std::fs::read_to_string(out.join(format!("{stem}.lib.wgsl"))).unwrap();
    assert!(wgsl.starts_with("#define_import_path relief::linear_10__binary_5__shadow_soft_30\n"), "{wgsl}");
    assert!(wgsl.contains("@group(3) @binding(7)") && wgsl.contains("var rock_height: texture_2d<f32>;"), "{wgsl}");
    assert!(wgsl.contains("fn rock_trace(") && wgsl.contains("fn rock_shadow("), "{wgsl}");
    let mm = std::fs::read_to_string(out.join("maxmip_20.lib.wgsl")).unwrap();
    assert!(mm.contains("const rock_edge_clamp: bool = true;"), "{mm}");
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn library_options_without_library_are_an_error() {
    let o = relief().args(["gen", "linear(10)", "--prefix", "rock", "--out", "/tmp/relief-x"]).output().unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("--library"), "{err}");
}
