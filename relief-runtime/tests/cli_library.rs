//! `relief gen --library`: four files per pipeline, the options reach them, `--target`
//! picks the forms, `--all --library` skips what a library cannot express, and bad input
//! (library options without `--library`, an unknown target, an inexpressible named
//! pipeline) is a one-line error.

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

#[test]
fn target_picks_the_forms_and_all_library_skips_what_it_cannot_express() {
    let out = std::env::temp_dir().join(format!("relief-cli-targets-{}", std::process::id()));
    std::fs::remove_dir_all(&out).ok();
    let o = relief()
        .args([
            "gen",
            "linear(20)+binary(5)+shadow=soft(8)",
            "--library",
            "--target",
            "wesl,glsl-es",
            "--target",
            "unity,unreal",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut files: Vec<String> =
        std::fs::read_dir(&out).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    files.sort();
    let stem = "linear_20__binary_5__shadow-soft_8";
    let mut expect = vec![
        "linear_20__binary_5__shadow_soft_8.wesl".to_string(),
        format!("{stem}.lib.es.glsl"),
        format!("{stem}.unity.hlsl"),
        format!("{stem}.ush"),
        format!("{stem}.custom.hlsl"),
    ];
    expect.sort();
    assert_eq!(files, expect);
    let unity = std::fs::read_to_string(out.join(format!("{stem}.unity.hlsl"))).unwrap();
    assert!(
        unity.contains("void Relief_float(")
            && unity.contains("void Relief_half(")
            && unity.contains("UnityTexture2D Height"),
        "{unity}"
    );
    std::fs::remove_dir_all(&out).ok();

    // --all --library: every expressible default pipeline written, the others listed, exit 0.
    let o = relief().args(["gen", "--all", "--library", "--target", "wgsl", "--out"]).arg(&out).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    let written = std::fs::read_dir(&out).unwrap().count();
    let skipped: Vec<&str> = text.lines().filter(|l| l.starts_with("  ")).collect();
    assert!(written >= 300 && !skipped.is_empty(), "{written} written: {text}");
    assert!(skipped.iter().all(|l| l.contains("linear_distance")), "{text}");
    assert!(text.contains(&format!("skipped {} pipeline(s) or form(s)", skipped.len())), "{text}");
    assert!(!out.join("linear_distance_16_180_4.lib.wgsl").exists());
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn an_unknown_target_or_an_inexpressible_pipeline_is_one_line() {
    for (args, says) in [
        (
            vec!["gen", "linear(10)", "--library", "--target", "unreel", "--out", "/tmp/relief-x"],
            "unknown target `unreel`",
        ),
        (vec!["gen", "linear_distance+binary(5)", "--library", "--out", "/tmp/relief-x"], "linear_distance"),
        (
            vec![
                "gen",
                "linear(10)",
                "--library",
                "--target",
                "glsl-es",
                "--prefix",
                "webgl",
                "--out",
                "/tmp/relief-x",
            ],
            "prefix `webgl`",
        ),
    ] {
        let o = relief().args(&args).output().unwrap();
        assert!(!o.status.success(), "{args:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(says) && err.trim().lines().count() == 1, "{args:?}: {err}");
    }
}
